// The FENE-P liquid: finitely extensible dumbbells with Peterlin's closure
// (Bird, Dotson & Johnson, J. Non-Newt. Fluid Mech. 7, 1980), in the
// conformation form of thesis eqs. 2.5-2.8 with the Peterlin function f:
//
//   T = 2 mu D + tau,        tau = G (f c - I),
//   lambda c_UC + (f c - I) = 0,
//   f(tr c) = (L^2 - 3) / (L^2 - tr c),     L^2 > 3 the extensibility,
//
// so r(c) = -(1/lambda)(f c - I) in dc/dt = L c + c L^T + r(c).
//
// Convention. Two normalisations are common. This one (used e.g. by
// Vaithianathan & Collins, J. Comput. Phys. 187, 2003) has f = 1 at tr c = 3,
// so the rest state is c = I (eq. 2.20), tau = 0 there, and the linear
// response is Oldroyd-B's: zero-shear viscosity eta = mu + G lambda (eq. 2.9)
// and first normal-stress coefficient 2 G lambda^2. The other,
// f = L^2 / (L^2 - tr c) (Bird et al. with b = L^2), rests at
// c = L^2 / (L^2 + 3) I. L^2 is the bound of tr c: as tr c -> L^2, f -> infinity.
// As L^2 -> infinity, f -> 1 and the model is Oldroyd-B.
//
// Log form (eqs. 2.10, 2.38-2.41): r commutes with c, so in the eigenbasis of
// s = log c (c = R diag(Lambda) R^T, Lambda_i = e^{sigma_i})
//
//   c^{-1} r(c) has the eigenvalues (e^{-sigma_i} - f) / lambda
//              = (expm1(-sigma_i) - (f - 1)) / lambda,
//   f - 1 = (tr c - 3) / (L^2 - tr c),   tr c - 3 = sum_i expm1(sigma_i),
//
// exact to round-off near c = I. The log-conformation keeps c positive
// definite but not tr c < L^2: a state with tr c >= L^2 is refused
// (inadmissible(); a SolverError if met in a kernel).
//
// The Stokes step needs tau at the D'Avino-Hulsen prediction, which is affine
// in the unknown velocity; tau is not, so it is linearised at c_n (an
// O(dt^2) error, as the prediction's own):
//
//   tau'(c_n)[dc] = G (f dc + f' tr(dc) c_n),   f' = df/dtr c = f / (L^2 - tr c_n).
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

class FenePLaw final : public ConstitutiveLaw {
 public:
  FenePLaw(double mu, double g, double lambda, double l2)
      : mu_(mu), g_(g), lambda_(lambda), l2_(l2) {}

  ConstitutiveModel model() const override { return ConstitutiveModel::fene_p; }
  ConstitutiveValues values() const override {
    return {.solvent_viscosity = mu_, .modulus = g_, .relaxation_time = lambda_,
            .extensibility = l2_};
  }
  double solvent_viscosity() const override { return mu_; }
  double modulus() const override { return g_; }
  double relaxation_time() const override { return lambda_; }
  bool relaxes() const override { return true; }

  // tau = G (f c - I) = G ((c - I) + (f - 1) c): no cancellation near c = I.
  Mat3 polymer_stress(const Mat3& c) const override {
    const double excess = peterlin_excess(c.trace() - 3.0);
    return g_ * ((c - Mat3::Identity()) + excess * c);
  }
  Mat3 linearized_stress(const Mat3& c_n, const Mat3& c) const override {
    const double stretch = c_n.trace() - 3.0;
    const double excess = peterlin_excess(stretch);
    const double slope = (1.0 + excess) / (l2_ - 3.0 - stretch);  // f'
    const Mat3 dc = c - c_n;
    return polymer_stress(c_n) + g_ * ((1.0 + excess) * dc + slope * dc.trace() * c_n);
  }
  StressDerivative stress_derivative(const Mat3& c_n) const override {
    const double stretch = c_n.trace() - 3.0;
    const double f = 1.0 + peterlin_excess(stretch);
    return {g_ * f, g_ * (f / (l2_ - 3.0 - stretch)) * c_n, true};
  }

  Mat3 relaxation(const Mat3& c) const override {
    // -(1/lambda)(f c - I) = -tau / (G lambda).
    const double excess = peterlin_excess(c.trace() - 3.0);
    return -((c - Mat3::Identity()) + excess * c) / lambda_;
  }
  Vec3 log_relaxation(const Vec3& sigma) const override {
    const double stretch = std::expm1(sigma(0)) + std::expm1(sigma(1)) + std::expm1(sigma(2));
    const double excess = peterlin_excess(stretch);
    Vec3 g;
    for (int i = 0; i < 3; ++i) g(i) = (std::expm1(-sigma(i)) - excess) / lambda_;
    return g;
  }
  std::string inadmissible(const Mat3& c) const override {
    const double trace = c.trace();
    if (trace < l2_) return {};
    return fmt::format(
        "tr c = {:.6g} has reached the FENE-P extensibility L^2 = {:.6g} (the Peterlin function "
        "f = (L^2 - 3) / (L^2 - tr c) is infinite there)",
        trace, l2_);
  }

 private:
  // f - 1 = (tr c - 3) / (L^2 - tr c), from tr c - 3 = `stretch`.
  double peterlin_excess(double stretch) const {
    const double room = l2_ - 3.0 - stretch;  // L^2 - tr c
    if (!(room > 0.0))
      throw SolverError(fmt::format(
          "FENE-P: tr c = {:.6g} is not below the extensibility L^2 = {:.6g}; the conformation "
          "left the model's domain (try a smaller time.step or a finer mesh)",
          3.0 + stretch, l2_));
    return stretch / room;
  }

  double mu_, g_, lambda_, l2_;
};

}  // namespace

ConstitutiveLawPtr make_fene_p_law(ConstitutiveModel model, const ConstitutiveValues& v) {
  const ParameterCheck check(model);
  const double solvent = check.non_negative({v.solvent_viscosity, "solvent viscosity mu"});
  const double time = check.positive({v.relaxation_time, "relaxation time lambda"});
  const double modulus = check.modulus({v.modulus, "modulus G"},
                                       {v.polymer_viscosity, "polymer viscosity eta_p"}, time);
  const double l2 = check.required({v.extensibility, "extensibility L^2"});
  if (!(l2 > 3.0))
    check.fail(fmt::format("the extensibility L^2 = {} must exceed 3 (tr c = 3 at rest)", l2));
  return std::make_shared<FenePLaw>(solvent, modulus, time, l2);
}

}  // namespace softflow::physics::viscoelastic
