// Data of one two-phase Stokes solve: viscosities, tensions, forcing, boundary values.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "softflow/physics/viscoelastic/constitutive.hpp"
#include "softflow/physics/stokes/point_tensors.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::fem {
class Field;
}  // namespace softflow::fem

namespace softflow::physics {

using Vec3 = Eigen::Vector3d;

/// Surface tension taken (to leading order) on the interface where it will
/// be at the end of the step rather than where the predictor put it. With
/// explicit tension a step above about eta h / Gamma lets short surface
/// waves grow: the capillary time-step limit. The corrector moves the
/// interface from the predicted position by theta dt (u.n - w) n, with w the
/// normal velocity the predictor already accounted for, so
///
///   -Gamma int_S grad_s x_new : grad_s v
///     ~ -Gamma int_S grad_s x_hat : grad_s v
///       - Gamma theta dt int_S grad_s(u.n - w) . grad_s(v.n)
///
/// (the normal's own surface gradient dropped). The last term, moved to the
/// left side, is a symmetric positive surface Laplacian of the normal
/// velocity that damps the short waves (the idea of Baensch 2001 and Hysing
/// 2006). w is the previous step's fluid velocity along n: the term then
/// acts on the velocity increment u_{n+1} - u_n and vanishes exactly at any
/// steady state. (Taking w from the predictor's node motion instead is not
/// exact at steady state: nodes slide tangentially, and the tank-treading
/// velocity has an O(h^2) component along a nodal normal; that version was
/// measured first order in dt.) On the scalar model x' = -sigma x the
/// increment form is stable for every sigma dt (BDF1).
struct SemiImplicitTension {
  /// theta dt: dt for a BDF1 step, 2 dt / 3 for BDF2 (eqs. 2.48, 2.50); 0 = explicit.
  double theta_dt = 0.0;
  /// Unit outward normal at every interface node (indexed by mesh node; others unused).
  std::vector<Vec3> node_normal;
  /// w at every interface node (indexed by mesh node; others unused).
  std::vector<double> predicted_normal_velocity;

  [[nodiscard]] bool active() const { return theta_dt > 0.0; }
};

/// Components of the projected velocity gradient field: G_ij = du_i/dx_j
/// at component 3 i + j.
inline constexpr int kVelocityGradientComponents = 9;

/// What the Stokes step needs from the viscoelastic phases (DEVSS-G and
/// the D'Avino-Hulsen terms, physics/stokes/viscoelastic_terms.hpp). The fields are
/// referenced, not owned, and live on the Stokes mesh (its current nodes).
struct ViscoelasticCoupling {
  /// Constitutive model of every region (0 = matrix, k = object k).
  std::vector<viscoelastic::Constitutive> models;
  /// c_n: 6 components (xx, yy, zz, xy, yz, xz), P1 per region.
  const fem::Field* conformation = nullptr;
  /// c_{n-1}, alike; nullptr at a BDF1 step (bdf.a2 = 0 and extrapolation
  /// c_n alone), which makes the prediction the Euler step of eq. 2.37.
  const fem::Field* previous_conformation = nullptr;
  /// The step the conformation transport will take (AleTransport::next_bdf,
  /// next_extrapolation): the prediction takes the same (viscoelastic_terms.hpp).
  time::BdfCoefficients bdf;
  time::Extrapolation extrapolation;
  /// The previous step's defect (PredictionDefect): per tetrahedron and
  /// point of the Stokes rule, defect_scale times it is added to the
  /// prediction; nullptr: none (the Euler prediction of eq. 2.37).
  const PointTensors* defect = nullptr;
  double defect_scale = 1.0;
  /// u_m over the step: 3 x P2; nullptr for a mesh at rest.
  const fem::Field* mesh_velocity = nullptr;
  /// G_n: the projected velocity gradient of the previous step
  /// (kVelocityGradientComponents, P1 per region); nullptr: no DEVSS term.
  const fem::Field* velocity_gradient = nullptr;
  double dt = 0.0;

  [[nodiscard]] bool active() const { return conformation != nullptr; }
  /// theta of region r's DEVSS-G term (0 without G_n or without a conformation).
  [[nodiscard]] double devss_theta(int region) const;
  /// A viscosity that measures region r's resistance to a velocity change
  /// over one step: mu + theta + G dt (the Newtonian viscosity of a
  /// Newtonian phase). The iterative solver's pressure mass is scaled by its
  /// inverse; it is positive even for a UCM phase (mu = 0).
  [[nodiscard]] double step_viscosity(int region) const;
};

/// Navier slip on the objects' interfaces (thesis eqs. 2.17-2.18, the sign
/// of eq. 2.18 as corrected in SPEC §9): with n the object's outward normal,
///   n.(u_m - u_d) = 0,   (I - n n)(u_m - u_d) = alpha_k (I - n n)(sigma_m n).
/// It needs a StokesSystem built with separate velocity copies at the
/// interfaces (interface_slip = true, physics/stokes/interface_slip.hpp).
struct InterfaceSlip {
  /// alpha_k of object k at index k - 1, dimensional (velocity per stress:
  /// the case's dimensionless slip times R / eta_m); missing entries are 0,
  /// i.e. no slip, which such a system imposes through the same multipliers.
  std::vector<double> coefficient;

  [[nodiscard]] double of(int object) const {
    return object - 1 < static_cast<int>(coefficient.size()) ? coefficient[object - 1] : 0.0;
  }
  [[nodiscard]] bool any() const {
    for (double a : coefficient)
      if (a > 0.0) return true;
    return false;
  }
};

/// Everything that defines one instantaneous Stokes problem on a given mesh:
///
///   -div(2 eta_r D(u)) + grad p = f,  div u = 0   in every region r,
///   (sigma_m - sigma_d) n = Gamma_k n div(n)       on the interface of object k,
///   u = g on the Dirichlet boundary (walls; box faces that are not periodic).
struct StokesProblem {
  /// Viscosity of region r (0 = matrix, k = object k).
  std::vector<double> viscosity;
  /// Interfacial tension Gamma of object k at index k - 1 (0: none).
  std::vector<double> interfacial_tension;
  /// Body force f(x, region); empty means none (the physical problems have none).
  std::function<Vec3(const Vec3&, int)> body_force;
  /// Velocity g(x) on every outer boundary face.
  std::function<Vec3(const Vec3&)> boundary_velocity;
  /// Semi-implicit surface tension (see SemiImplicitTension); off by default.
  SemiImplicitTension semi_implicit_tension;
  /// The viscoelastic phases' stress (inactive: all Newtonian). `viscosity`
  /// then holds each such phase's solvent viscosity mu (0 for UCM).
  ViscoelasticCoupling viscoelastic;
  /// Navier slip per object (none by default).
  InterfaceSlip slip;
  /// The pressure level is fixed at one matrix vertex (the gauge) to this value.
  int pressure_gauge_node = -1;
  double pressure_gauge_value = 0.0;
};

}  // namespace softflow::physics
