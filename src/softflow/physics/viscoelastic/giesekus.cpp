// The Giesekus liquid and its special cases Oldroyd-B (alpha = 0) and UCM
// (alpha = 0, mu = 0), thesis eqs. 2.5-2.9:
//
//   T = 2 mu D + tau,   tau = G (c - I),                                   eq. 2.6
//   lambda c_UC + (c - I) + alpha (c - I)^2 = 0,                           eq. 2.7
//
// so r(c) = -(1/lambda) ((c - I) + alpha (c - I)^2), and with c = R diag(Lambda) R^T
// the log form c^{-1} r(c) has the eigenvalues
//
//   g_i / lambda = ((1 - Lambda_i) - alpha (Lambda_i - 1)^2) / (lambda Lambda_i)
//               = (expm1(-sigma_i) - alpha expm1(sigma_i)^2 e^{-sigma_i}) / lambda,
//
// written with expm1 so that nothing cancels as c -> I. The zero-shear
// viscosity is eta = mu + G lambda (eq. 2.9).
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

class GiesekusLaw final : public ConstitutiveLaw {
 public:
  GiesekusLaw(ConstitutiveModel model, double mu, double g, double lambda, double alpha)
      : model_(model), mu_(mu), g_(g), lambda_(lambda), alpha_(alpha) {}

  ConstitutiveModel model() const override { return model_; }
  ConstitutiveValues values() const override {
    ConstitutiveValues v{.modulus = g_, .relaxation_time = lambda_};
    if (model_ != ConstitutiveModel::ucm) v.solvent_viscosity = mu_;
    if (model_ == ConstitutiveModel::giesekus) v.mobility = alpha_;
    return v;
  }
  double solvent_viscosity() const override { return mu_; }
  double modulus() const override { return g_; }
  double relaxation_time() const override { return lambda_; }
  bool relaxes() const override { return true; }

  Mat3 polymer_stress(const Mat3& c) const override {
    return g_ * (c - Mat3::Identity());  // eq. 2.6
  }
  Mat3 relaxation(const Mat3& c) const override {
    const Mat3 a = c - Mat3::Identity();
    return -(a + alpha_ * a * a) / lambda_;  // eq. 2.7
  }
  Vec3 log_relaxation(const Vec3& sigma) const override {
    Vec3 g;
    for (int i = 0; i < 3; ++i) {
      // (1 - Lambda)/Lambda = e^{-sigma} - 1 and (Lambda - 1)^2/Lambda =
      // expm1(sigma)^2 e^{-sigma}: no cancellation as Lambda -> 1.
      const double stretch = std::expm1(sigma(i));
      g(i) = std::expm1(-sigma(i)) - alpha_ * stretch * stretch * std::exp(-sigma(i));
    }
    return g / lambda_;
  }

 private:
  ConstitutiveModel model_;
  double mu_, g_, lambda_, alpha_;
};

}  // namespace

ConstitutiveLawPtr make_giesekus_law(ConstitutiveModel model, const ConstitutiveValues& v) {
  const ParameterCheck check(model);
  const Parameter mu{v.solvent_viscosity, "solvent viscosity mu"};
  double solvent = 0.0;
  if (model == ConstitutiveModel::ucm)
    check.absent(mu, "UCM is the liquid without solvent, mu = 0; use oldroyd_b", true);
  else
    solvent = check.non_negative(mu);
  // lambda = 0 would make the relaxation term 1/lambda infinite: the
  // liquid is then Newtonian and should be declared so.
  const double time = check.positive({v.relaxation_time, "relaxation time lambda"});
  const double modulus = check.modulus({v.modulus, "modulus G"},
                                       {v.polymer_viscosity, "polymer viscosity eta_p"}, time);
  double mobility = 0.0;
  if (model == ConstitutiveModel::giesekus) {
    mobility = check.required({v.mobility, "mobility alpha"});
    if (!(mobility >= 0.0 && mobility <= 1.0))
      check.fail(fmt::format("the mobility alpha = {} must lie in [0, 1]", mobility));
  }
  return std::make_shared<GiesekusLaw>(model, solvent, modulus, time, mobility);
}

}  // namespace softflow::physics::viscoelastic
