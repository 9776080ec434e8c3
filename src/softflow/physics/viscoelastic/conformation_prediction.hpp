// The D'Avino-Hulsen predicted conformation (SPEC §2 part 4; thesis eq. 2.37
// as corrected in SPEC §9): the pointwise part of the decoupling that turns
// the momentum balance at t_{n+1} into a Stokes-like system in u_{n+1}.
//
// One explicit Euler step of the conformation equation (constitutive.hpp),
// with the velocity taken at the new time:
//
//   c_{n+1} ~ c_n + dt [ -(u - u_m).grad c_n + L c_n + c_n L^T
//                        - (1/lambda) ((c_n - I) + alpha (c_n - I)^2) ],
//
// L_ij = du_i/dx_j of u = u_{n+1}, u_m the mesh velocity; for another model
// the relaxation is its own r(c_n) (ConstitutiveLaw::relaxation, e.g.
// -(1/lambda)(f c_n - I) for FENE-P). Eq. 2.7 with the
// upper-convected derivative of eq. 2.8 gives the relaxation term with a
// minus sign and a factor 1/lambda; the printed eq. 2.37 has "+ c_n - I +
// alpha (c_n - I)^2" without either (SPEC §9). The prediction is affine in
// the unknown velocity:
//
//   c_{n+1} = constant + dt (L c_n + c_n L^T),
//   constant = c_n + dt [ -convection - (1/lambda) ((c_n - I) + alpha (c_n - I)^2) ],
//
// so the Stokes assembly keeps G * constant - G I on the right-hand side and
// puts G dt (L c_n + c_n L^T) (the `linear` part, for the trial function's
// L) in the matrix, beside 2 mu D(u). The convection term is linear in u
// too: pass -(u_m).grad c_n here if the assembly puts u.grad c_n in the
// matrix (convective_derivative serves both), or the whole
// (u - u_m).grad c_n with a lagged u.
//
// After the first step the prediction takes the step the transport will take
// (BDF2, time::bdf), with c extrapolated to t_{n+1} where the Euler step has
// c_n:
//
//   c_{n+1} ~ h + theta dt [ -(u - u_m).grad c* + L c* + c* L^T + r(c*) ],
//   h = -(a1 c_n + a2 c_{n-1}) / a0,   c* = 2 c_n - c_{n-1} (constant step).
//
// Why: the momentum balance holds at the predicted c, the run keeps the
// transported one, which the transport computes by BDF2. The Euler step
// differs from that in time by O(dt^2) at every step, the BDF2 one by
// O(dt^3); what is left between them is spatial (the transport's
// projection), which physics/stokes/prediction_defect.hpp carries to the
// next step (docs/viscoelastic.md, "The predicted stress and the
// transported one"). The BDF2 step alone made the drop-in-Giesekus
// study's changes of D about a third smaller; the defect does the rest.
#pragma once

#include <array>

#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::physics::viscoelastic {

/// The conformation the Stokes step's polymer stress is taken at
/// (physics/stokes/viscoelastic_terms.hpp, physics/stokes/prediction_defect.hpp):
///   euler       one explicit Euler step from c_n (eq. 2.37, D'Avino-Hulsen):
///               first order in dt where the flow is not homogeneous;
///   consistent  the transport's own BDF step, plus the previous step's
///               defect against the transported c: second order.
enum class StressPrediction { euler, consistent };

/// (w . grad) c = sum_k w_k dc/dx_k, with grad_c[k] = dc/dx_k (each symmetric).
[[nodiscard]] Mat3 convective_derivative(const Vec3& w, const std::array<Mat3, 3>& grad_c);

/// c_{n+1} ~ constant() + linear(L): the D'Avino-Hulsen prediction at one
/// point, its L-independent part computed once at construction.
class ConformationPrediction {
 public:
  /// The Euler (BDF1) step: `convection` = (u - u_m).grad c_n (or the part
  /// of it kept explicit); c_n symmetric. Throws softflow::Error for a
  /// Newtonian phase or dt <= 0.
  ConformationPrediction(const Constitutive& model, const Mat3& c_n, const Mat3& convection,
                         double dt);
  /// Any BDF step: `history` = -(a1 c_n + a2 c_{n-1}) / a0, `extrapolated`
  /// = c* (c_n at a BDF1 step), `convection` = (u - u_m).grad c* (or its
  /// explicit part), `theta_dt` = dt / a0. Throws as above for theta_dt <= 0.
  ConformationPrediction(const Constitutive& model, const Mat3& history, const Mat3& extrapolated,
                         const Mat3& convection, double theta_dt);

  /// history + theta dt [ -convection + r(c*) ], r the model's relaxation.
  [[nodiscard]] const Mat3& constant() const { return constant_; }
  /// theta dt (L c* + c* L^T): linear in L, the part that goes to the left-hand side.
  [[nodiscard]] Mat3 linear(const Mat3& velocity_gradient) const;
  /// constant() + linear(L): the whole prediction.
  [[nodiscard]] Mat3 operator()(const Mat3& velocity_gradient) const;

 private:
  Mat3 extrapolated_;
  double theta_dt_;
  Mat3 constant_;
};

}  // namespace softflow::physics::viscoelastic
