// The viscoelastic phases' part of the Stokes step (thesis §2.3.1, eqs.
// 2.34-2.37; SPEC §2 part 4): DEVSS-G and the D'Avino-Hulsen decoupling.
//
// In a phase with a conformation tensor the momentum balance at t_{n+1} reads
//
//   (D(v), 2 (mu + theta) D(u)) + (D(v), tau_{n+1}) - (div v, p)
//       = (D(v), theta (G_n + G_n^T)) + tension,
//
// with tau_{n+1} = tau(c_{n+1}) (G (c_{n+1} - I) for Oldroyd-B, Giesekus and
// the solids, eq. 2.6) and c_{n+1} the D'Avino-Hulsen prediction
// (physics/viscoelastic/conformation_prediction.hpp), affine in u; below its
// Euler form (StressPrediction::euler); the consistent one takes the
// transport's BDF step with c* = 2 c_n - c_{n-1} in place of c_n and adds the
// last step's defect (prediction_defect.hpp):
//
//   c_{n+1} = c_n + dt [ -(u - u_m).grad c_n + L c_n + c_n L^T + r(c_n) ],   L = grad u^T,
//
// r the model's relaxation (eq. 2.37 corrected: -(1/lambda)((c_n - I) + alpha (c_n - I)^2)
// for Giesekus). The kernel asks the model's law (physics/viscoelastic/
// constitutive_law.hpp) for tau at c_{n+1}, linearised at c_n where tau is not
// affine in c (FENE-P): tau(c_n) + A dc + tr(dc) B, an O(dt^2) error.
//
// The parts linear in u = u_{n+1} (L c_n + c_n L^T and u.grad c_n, as in
// eq. 2.37, where the convection is implicit) go to the matrix; c_n, the
// mesh-velocity convection u_m.grad c_n and the relaxation to the load.
//
// DEVSS-G (eqs. 2.34, 2.36) adds theta (grad u - G^T) to the stress, G the
// P1 projection of the velocity gradient. softflow does not solve for G with
// u and p: it takes G_n, the projection of the previous step's velocity
// gradient, so that one Stokes-like system per step remains. The residual
// theta (grad u_{n+1} - G_n) vanishes at a steady state (up to the O(h^2)
// projection error) and for homogeneous flows, and is O(dt) in a transient;
// it adds the elliptic part theta (D(v), 2 D(u)) a UCM phase (mu = 0)
// otherwise lacks. The second-order extrapolation G* = 2 G_n - G_{n-1} is
// unstable: in the scalar model of a velocity-gradient perturbation g and
// its stress T (in units of theta), (1 + a) g_{n+1} = 2 g_n - g_{n-1} - T_n,
// T_{n+1} = T_n + a g_{n+1}, a = G dt / theta, the amplification factors
// solve (1 - 1/z)^3 = 1 + a, one of them z ~ -3/a; with G_n instead,
// (1 + a) z^2 - 2 z + 1 = 0 and |z|^2 = 1/(1 + a) < 1. (Measured: the UCM
// start-up of shear with the extrapolation lets a round-off perturbation of
// the linear profile grow ~12 % per step at dt = lambda/40.) theta is the
// polymer viscosity eta_p = G lambda of a liquid (the thesis: the phase's
// viscosity, eta_p for its UCM drop) and G dt for an elastic solid (thesis
// §2.3.1); there is no DEVSS term at the first step (no G yet) nor in
// Newtonian phases, which keeps Newtonian runs unchanged.
#pragma once

#include <vector>

#include "softflow/physics/stokes/stokes_problem.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"

namespace softflow::physics {

/// Adds on tetrahedron `tet` of a region with a conformation the
/// D'Avino-Hulsen stress terms and the DEVSS-G load (header comment): into
/// the velocity block of `matrix`,
///   G dt (D(v), L c_n + c_n L^T) - G dt (D(v), u.grad c_n),
/// and into the velocity rows of `load`
///   -G (D(v), c* - I) + theta (D(v), G_n + G_n^T),
/// c* the prediction's part without u. The theta (D(v), 2 D(u)) term is the
/// caller's (add_stokes_tet_matrix with mu + theta). `points` are the
/// tetrahedron's quadrature points on the current mesh.
/// The prediction at one quadrature point, before the velocity is known:
/// c* and its gradient, and the affine prediction (its constant part holds
/// the history, the explicit terms and the coupling's defect).
struct PointPrediction {
  viscoelastic::Mat3 extrapolated;
  std::array<viscoelastic::Mat3, 3> gradient;
  viscoelastic::ConformationPrediction prediction;
};
[[nodiscard]] PointPrediction predict_at(const ViscoelasticCoupling& coupling,
                                         const fem::QuadraturePoint& p);

/// The whole prediction at p for the velocity u and its gradient L there
/// (the velocity's convection included): what the Stokes step's stress was
/// evaluated at, once the step is solved.
[[nodiscard]] viscoelastic::Mat3 predicted_conformation(
    const ViscoelasticCoupling& coupling, const fem::QuadraturePoint& p, const Eigen::Vector3d& u,
    const viscoelastic::Mat3& velocity_gradient);

void add_viscoelastic_tet_terms(const ViscoelasticCoupling& coupling,
                                const std::vector<fem::QuadraturePoint>& points, TetMatrix& matrix,
                                TetVector& load);

}  // namespace softflow::physics
