// steady_simple_shear (physics/viscoelastic/steady_shear): the viscometric
// functions against Oldroyd-B's exact ones, Giesekus's closed form (Giesekus
// 1982; Bird, Armstrong and Hassager vol. 1), its zero-shear limit
// Psi_2 / Psi_1 = -alpha / 2, and a time integration of the same conformation
// equation to its steady state (independent of the closed form); refusals.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/steady_shear.hpp"

using namespace softflow;
namespace ve = physics::viscoelastic;
using ve::Constitutive;
using ve::Mat3;

namespace {

/// Giesekus's polymer viscosity and N_1 in steady shear (closed form).
struct GiesekusShear {
  double shear_stress, first_normal;
};

GiesekusShear giesekus_closed_form(double eta_p, double lambda, double alpha, double rate) {
  const double wi = lambda * rate;
  const double s = 8.0 * alpha * (1.0 - alpha) * wi * wi;
  const double chi = std::sqrt((std::sqrt(1.0 + 2.0 * s) - 1.0) / s);
  const double f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi);
  const double viscosity = eta_p * (1.0 - f) * (1.0 - f) / (1.0 + (1.0 - 2.0 * alpha) * f);
  const double psi1 = 2.0 * eta_p * lambda * f * (1.0 - alpha * f) / (alpha * wi * wi * (1.0 - f));
  return {viscosity * rate, psi1 * rate * rate};
}

}  // namespace

TEST(SteadyShear, OldroydBAndUcmHaveTheirExactViscometricFunctions) {
  // tau_xy = eta_p gamma_dot, N_1 = 2 eta_p lambda gamma_dot^2, N_2 = 0 at every rate.
  for (const double rate : {0.0, 0.3, 1.0, 7.0}) {
    const auto ob = ve::steady_simple_shear(Constitutive::oldroyd_b(0.1, 1.8, 0.5), rate);
    const double eta_p = 1.8 * 0.5;
    EXPECT_NEAR(ob.shear_stress(), eta_p * rate, 1e-12 * (1.0 + eta_p * rate));
    EXPECT_NEAR(ob.first_normal_stress_difference(), 2.0 * eta_p * 0.5 * rate * rate,
                1e-11 * (1.0 + rate * rate));
    EXPECT_NEAR(ob.second_normal_stress_difference(), 0.0, 1e-11);
    const auto ucm = ve::steady_simple_shear(Constitutive::ucm(2.0, 1.5), rate);
    EXPECT_NEAR(ucm.first_normal_stress_difference(), 2.0 * 3.0 * 1.5 * rate * rate,
                1e-11 * (1.0 + rate * rate));
  }
}

TEST(SteadyShear, GiesekusMatchesTheClosedFormFromSmallToLargeWeissenberg) {
  const double eta_p = 0.9, alpha = 0.2;
  for (const double lambda : {0.05, 0.5, 0.6514, 2.0, 10.0, 100.0}) {
    const auto model = Constitutive::giesekus(0.1, eta_p / lambda, lambda, alpha);
    const auto steady = ve::steady_simple_shear(model, 1.0);
    const auto exact = giesekus_closed_form(eta_p, lambda, alpha, 1.0);
    EXPECT_NEAR(steady.shear_stress() / exact.shear_stress, 1.0, 1e-9) << "lambda " << lambda;
    EXPECT_NEAR(steady.first_normal_stress_difference() / exact.first_normal, 1.0, 1e-9)
        << "lambda " << lambda;
  }
}

TEST(SteadyShear, GiesekusSecondNormalStressRatioTendsToMinusHalfAlphaAtSmallRates) {
  for (const double alpha : {0.1, 0.2, 0.5}) {
    const auto steady =
        ve::steady_simple_shear(Constitutive::giesekus(0.0, 1.0, 1.0, alpha), 1e-3);
    EXPECT_NEAR(steady.second_normal_stress_difference() / steady.first_normal_stress_difference(),
                -alpha / 2.0, 1e-5);
  }
}

TEST(SteadyShear, AgreesWithTheStartUpIntegratedToSteadyState) {
  // RK4 of dc/dt = L c + c L^T + r(c) from c = I over 60 relaxation times.
  for (const auto& model : {Constitutive::giesekus(0.1, 0.9 / 0.6514, 0.6514, 0.2),
                            Constitutive::create(ve::ConstitutiveModel::fene_p,
                                                 {.solvent_viscosity = 0.1,
                                                  .polymer_viscosity = 0.9,
                                                  .relaxation_time = 1.5,
                                                  .extensibility = 20.0})}) {
    Mat3 gradient = Mat3::Zero();
    gradient(0, 1) = 1.0;
    Mat3 c = Mat3::Identity();
    const double h = 1e-3 * model.relaxation_time();
    for (int k = 0; k < 60000; ++k) {
      const Mat3 k1 = ve::conformation_rate(model, gradient, c);
      const Mat3 k2 = ve::conformation_rate(model, gradient, c + 0.5 * h * k1);
      const Mat3 k3 = ve::conformation_rate(model, gradient, c + 0.5 * h * k2);
      const Mat3 k4 = ve::conformation_rate(model, gradient, c + h * k3);
      c += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    const auto steady = ve::steady_simple_shear(model, 1.0);
    EXPECT_LT((steady.conformation - c).norm(), 1e-9 * c.norm()) << ve::to_string(model.model());
  }
}

TEST(SteadyShear, RefusesModelsWithoutASteadyState) {
  EXPECT_THROW((void)ve::steady_simple_shear(Constitutive::neo_hookean(1.0), 1.0), Error);
  EXPECT_THROW((void)ve::steady_simple_shear(Constitutive::newtonian(1.0), 1.0), Error);
  EXPECT_THROW((void)ve::steady_simple_shear(Constitutive::oldroyd_b(0.1, 1.0, 1.0), -1.0), Error);
}
