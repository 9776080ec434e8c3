// Per-object measures of cross-stream migration (thesis §3.2.2): centre of volume, its velocity,
// and the surface imbalance Delta S (eq. 3.6), on the curved P2 interface.
//
// The thesis calls y_p the y of the centre of volume and v_p = dy_p/dt the migration velocity;
// Delta S = (S(n_y > 0) - S(n_y < 0)) / (S / 2) is the share by which the part of the surface
// facing the upper wall (n the outward normal) exceeds the part facing the lower one. A
// particle above the centre plane has Delta S > 0 and migrates down (Figs. 3.6-3.8).
//
// The sign of n_y changes inside triangles, along a curve. Quadrature of the indicator
// (sign n_y at the quadrature points) converges only like the area of the cut triangles'
// misclassified parts: first order in h, erratically (measured in
// tests/unit/test_migration_measures.cpp). Here each cut triangle is integrated over its
// two parts exactly up to quadrature: on a P2 triangle the tangents are linear in the
// reference coordinates, so f = (dx/dxi_1 x dx/dxi_2)_y, which has the sign of n_y, is a
// quadratic polynomial; its zero set is a conic found in closed form line by line (see
// signed_area in the .cpp). What remains is the geometric error of the P2 surface itself.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "softflow/physics/interface/interface_mesh.hpp"

namespace softflow::analysis {

using Vec3 = Eigen::Vector3d;

/// Areas of the parts of a closed surface by the sign of the outward normal's y component.
struct SurfaceImbalance {
  double area = 0.0;           ///< S, the whole surface
  double area_positive = 0.0;  ///< S(n_y > 0): facing the upper wall y = +H/2
  double area_negative = 0.0;  ///< S(n_y < 0)
  /// Delta S = (S(n_y > 0) - S(n_y < 0)) / (S / 2), thesis eq. 3.6; in [-2, 2].
  [[nodiscard]] double delta_s() const {
    return area > 0.0 ? (area_positive - area_negative) / (0.5 * area) : 0.0;
  }
};

/// S(n_y > 0), S(n_y < 0) and S of the curved P2 surface `s` at node positions `x` (its
/// triangles oriented with the normal out of the object, as extract_interface makes them).
/// Triangles where n_y keeps its sign take the 7-point rule; cut ones are split along the
/// conic n_y = 0 (see the file comment).
SurfaceImbalance surface_imbalance(const physics::InterfaceMesh& s, const std::vector<Vec3>& x);

/// The same by quadrature of the indicator: each point of a `degree` triangle rule counts
/// for the side its n_y falls on. Kept as the reference of the tests' convergence study
/// (first order at best); use surface_imbalance.
SurfaceImbalance surface_imbalance_by_indicator(const physics::InterfaceMesh& s,
                                                const std::vector<Vec3>& x, int degree);

/// What the time step records per object for migration: the centre of volume (x_p, y_p,
/// z_p) from physics::surface_integrals (eqs. 2.53-2.54: Q / V on the curved surface, the
/// same centre the mesh translation follows), and Delta S.
struct MigrationMeasures {
  Vec3 centre = Vec3::Zero();  ///< (x_p, y_p, z_p)
  double volume = 0.0;
  SurfaceImbalance imbalance;
};

MigrationMeasures migration_measures(const physics::InterfaceMesh& s, const std::vector<Vec3>& x);

/// The velocity of the centre of volume from consecutive centres: (X_{n+1} - X_n) / dt
/// (first order), or, given the centre before that and its step dt_previous, the
/// three-point (variable-step BDF2) difference
///   U = [(1 + 2 w) X_{n+1} - (1 + w)^2 X_n + w^2 X_{n-1}] / ((1 + w) dt),  w = dt / dt_prev,
/// exact for centres moving quadratically in time. Its y component is the thesis's
/// migration velocity v_p.
Vec3 centre_velocity(const Vec3& centre, const Vec3& previous, double dt);
Vec3 centre_velocity(const Vec3& centre, const Vec3& previous, const Vec3& before_previous,
                     double dt, double dt_previous);

}  // namespace softflow::analysis
