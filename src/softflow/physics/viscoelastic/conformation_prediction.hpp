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
#pragma once

#include <array>

#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::physics::viscoelastic {

/// (w . grad) c = sum_k w_k dc/dx_k, with grad_c[k] = dc/dx_k (each symmetric).
[[nodiscard]] Mat3 convective_derivative(const Vec3& w, const std::array<Mat3, 3>& grad_c);

/// c_{n+1} ~ constant() + linear(L): the D'Avino-Hulsen prediction at one
/// point, its L-independent part computed once at construction.
class ConformationPrediction {
 public:
  /// `convection` = (u - u_m).grad c_n (or the part of it kept explicit);
  /// c_n symmetric. Throws softflow::Error for a Newtonian phase or dt <= 0.
  ConformationPrediction(const Constitutive& model, const Mat3& c_n, const Mat3& convection,
                         double dt);

  /// c_n + dt [ -convection + r(c_n) ], r the model's relaxation.
  [[nodiscard]] const Mat3& constant() const { return constant_; }
  /// dt (L c_n + c_n L^T): linear in L, the part that goes to the left-hand side.
  [[nodiscard]] Mat3 linear(const Mat3& velocity_gradient) const;
  /// constant() + linear(L): the whole prediction.
  [[nodiscard]] Mat3 operator()(const Mat3& velocity_gradient) const;

 private:
  Mat3 c_n_;
  double dt_;
  Mat3 constant_;
};

}  // namespace softflow::physics::viscoelastic
