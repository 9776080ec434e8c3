// Element kernels of the Taylor-Hood Stokes weak form, each named after its term.
#pragma once

#include <Eigen/Core>

#include "softflow/fem/tabulation.hpp"

namespace softflow::physics {

/// Element matrix in the local order of fem::StokesDofMap (30 velocity + 4 pressure).
/// The Stokes assembly's rule. Degree 5 (14 points): exact for the
/// affine-element integrands (degree <= 4) and accurate to well below
/// discretisation error on curved P2 elements.
inline constexpr int kStokesQuadratureDegree = 5;
inline constexpr int kTetVelocityDofs = 30;
inline constexpr int kTetPressureDofs = 4;
using TetMatrix = Eigen::Matrix<double, kTetVelocityDofs + kTetPressureDofs,
                                kTetVelocityDofs + kTetPressureDofs>;
using TetVector = Eigen::Matrix<double, kTetVelocityDofs + kTetPressureDofs, 1>;
using TriangleVelocityVector = Eigen::Matrix<double, 18, 1>;

using PressureMass = Eigen::Matrix<double, 4, 4>;
using TriangleStiffness = Eigen::Matrix<double, 6, 6>;

/// Adds on one tetrahedron, with eta the region's viscosity:
///   (1) a(v, u) = (2 eta D(v), D(u))        velocity-velocity,
///   (2) b(q, u) = -(q, div u) and its transpose  pressure-velocity,
/// and, if `scaled_pressure_mass` is given,
///   (3) -(1/eta)(q, p)  into it: the Schur-complement approximation that
///       the preconditioning matrix carries in its pressure block, with
///       `pressure_mass_viscosity` in place of eta if it is positive (a
///       viscoelastic phase's step viscosity: eta may be 0 there).
/// Returns the element volume.
double add_stokes_tet_matrix(const element::TetNodes& x, const fem::TetTabulation& tab,
                             double eta, TetMatrix& out,
                             PressureMass* scaled_pressure_mass = nullptr,
                             double pressure_mass_viscosity = 0.0);

/// (v, f) on one tetrahedron: body force loading of the velocity rows.
template <class Force>
void add_body_force(const element::TetNodes& x, const fem::TetTabulation& tab, const Force& f,
                    TetVector& out) {
  for (int q = 0; q < tab.rule.size(); ++q) {
    const auto map = element::tet_map(x, tab.p2_grad[q]);
    Eigen::Vector3d xq = Eigen::Vector3d::Zero();
    for (int k = 0; k < 10; ++k) xq += tab.p2[q][k] * x.col(k);
    const Eigen::Vector3d fq = f(xq) * (tab.rule.weights[q] * map.det_jacobian);
    for (int k = 0; k < 10; ++k)
      for (int d = 0; d < 3; ++d) out(3 * k + d) += tab.p2[q][k] * fq(d);
  }
}

/// Surface tension, thesis eq. 2.34's interface term moved to the right side:
///   -Gamma * integral_S (grad_s v)^T : (I - n n) ds = -Gamma * integral_S div_s v ds
/// on one curved P2 interface triangle (velocity of its 6 nodes, 3k + d).
/// No curvature is computed: the identity integral_S div_s v = integral_S
/// (div n) v.n ds for closed S makes this the weak form of the traction jump.
void add_surface_tension(const element::TriangleNodes& x, double gamma,
                         TriangleVelocityVector& out);

/// The Laplace-Beltrami stiffness of one curved P2 triangle,
///   S_ab = integral_T grad_s N_a . grad_s N_b ds,
/// the operator of the semi-implicit tension (SemiImplicitTension). Since
/// grad_s x = I - n n on the isoparametric surface, sum_b S_ab x_b equals
/// integral_T grad_s N_a ds: the explicit tension's load per unit Gamma.
TriangleStiffness surface_stiffness(const element::TriangleNodes& x);

/// The mass matrix of one curved P2 triangle, M_ab = integral_T N_a N_b ds:
/// how the slip multipliers (tractions, P2 on the interface) load the two
/// velocity copies (physics/stokes/interface_slip.hpp).
TriangleStiffness surface_mass(const element::TriangleNodes& x);

}  // namespace softflow::physics
