// Oldroyd's emulsion moduli (thesis appendices A-B, SPEC §9) against values computed by
// hand from eqs. A.1-A.5, their limits, and the dilute coefficient against the derivative.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/analysis/theory/oldroyd_emulsion.hpp"
#include "softflow/common/error.hpp"

using namespace softflow::analysis::theory;

TEST(OldroydEmulsion, ConstantsAndModuliByHand) {
  // lambda = 1, phi = 0.1: denominator 20 - 1.4 = 18.6, eta = 22.1 / 18.6,
  // tau = xi = 35 * 5 / (4 * 18.6) (lambda = 1 drops the phi terms).
  const OldroydConstants c = oldroyd_constants(1.0, 0.1);
  EXPECT_NEAR(c.viscosity, 22.1 / 18.6, 1e-15);
  EXPECT_NEAR(c.relaxation_time, 175.0 / 74.4, 1e-14);
  EXPECT_NEAR(c.retardation, 175.0 / 74.4, 1e-14);
  // eqs. A.1-A.2 at omega* = 1: G' = (eta tau - xi) / (1 + tau^2), G'' / omega = (eta + xi tau) / (1 + tau^2).
  const ScaledModuli m = oldroyd_moduli(1.0, 0.1, 1.0);
  EXPECT_NEAR(m.storage, 0.06775375023921223, 1e-14);
  EXPECT_NEAR(m.loss, 1.0288050229588424, 1e-14);
  // lambda = 5, phi = 0.2, omega* = 0.4 (Fig. 4.14's frequency), from the same formulas by hand.
  const ScaledModuli m5 = oldroyd_moduli(5.0, 0.2, 0.4);
  EXPECT_NEAR(m5.storage, 0.02673681385845816, 1e-14);
  EXPECT_NEAR(m5.loss, 1.3768660352820483, 1e-14);
}

TEST(OldroydEmulsion, TheMatrixAloneIsNewtonian) {
  for (double lambda : {0.1, 1.0, 5.0, 100.0})
    for (double alpha : {0.0, 0.1, 1.0})
      for (double omega : {0.02, 0.4, 10.0}) {
        const ScaledModuli m = oldroyd_moduli(lambda, 0.0, omega, alpha);
        EXPECT_NEAR(m.storage, 0.0, 1e-14) << lambda << " " << alpha << " " << omega;
        EXPECT_NEAR(m.loss, 1.0, 1e-14);
      }
}

TEST(OldroydEmulsion, SlipFormsReduceToTheNoSlipOnesAndStayPhysical) {
  for (double lambda : {0.1, 1.0, 5.0})
    for (double phi : {0.05, 0.28}) {
      const OldroydConstants a = oldroyd_constants(lambda, phi);
      const OldroydConstants b = oldroyd_constants(lambda, phi, 0.0);
      EXPECT_EQ(a.viscosity, b.viscosity);
      for (double alpha : {0.1, 1.0, 10.0}) {
        // SPEC §9: as printed, B.2-B.3 give negative times; corrected, times stay
        // positive, G' >= 0, and slip lowers the viscosity towards the free-slip drop's.
        const OldroydConstants s = oldroyd_constants(lambda, phi, alpha);
        EXPECT_GT(s.relaxation_time, 0.0);
        EXPECT_GT(s.retardation, 0.0);
        EXPECT_LT(s.viscosity, a.viscosity);
        EXPECT_GT(oldroyd_moduli(lambda, phi, 1.0, alpha).storage, 0.0);
      }
    }
}

TEST(OldroydEmulsion, DiluteCoefficientIsTheDerivativeAtZeroVolumeFraction) {
  const double h = 1e-6;
  for (double lambda : {0.1, 1.0, 5.0})
    for (double alpha : {0.0, 1.0})
      for (double omega : {0.1, 1.0, 5.0}) {
        const std::complex<double> i_omega(0.0, omega);
        // eta* / eta_m = G* / (i omega) in these units; a central difference about phi = h.
        const auto eta_star = [&](double phi) {
          return oldroyd_complex_modulus(lambda, phi, omega, alpha) / i_omega;
        };
        const std::complex<double> slope = (eta_star(2 * h) - eta_star(0.0)) / (2 * h);
        const std::complex<double> c = oldroyd_dilute_coefficient(lambda, omega, alpha);
        EXPECT_NEAR(c.real(), slope.real(), 1e-5 * std::abs(c));
        EXPECT_NEAR(c.imag(), slope.imag(), 1e-5 * std::abs(c));
      }
}

TEST(OldroydEmulsion, DiluteLimitsAreTaylorAndTheTensionFreeSphere) {
  for (double lambda : {0.1, 1.0, 3.0, 100.0}) {
    // omega -> 0: Taylor's intrinsic viscosity; omega -> oo: a viscous sphere without tension.
    EXPECT_NEAR(oldroyd_dilute_coefficient(lambda, 0.0).real(),
                (5 * lambda + 2) / (2 * (lambda + 1)), 1e-14);
    EXPECT_NEAR(oldroyd_dilute_coefficient(lambda, 1e9).real(),
                5 * (lambda - 1) / (2 * lambda + 3), 1e-6);
  }
  // With slip the steady value is (5 lambda + 2 + 10 alpha lambda) / (2 (lambda + 1) + 10 alpha lambda):
  // a rigid sphere (lambda -> oo) slipping freely (alpha -> oo) has intrinsic viscosity 1.
  EXPECT_NEAR(oldroyd_dilute_coefficient(1e8, 0.0, 1e4).real(), 1.0, 1e-4);
  // The tension stores energy: eta* = eta' - i eta'', G' = omega eta'' > 0.
  EXPECT_LT(oldroyd_dilute_coefficient(1.0, 1.0).imag(), 0.0);
}

TEST(OldroydEmulsion, RefusesArgumentsOutOfRangeNamingThem) {
  const auto message = [](auto&& call) {
    try {
      call();
    } catch (const softflow::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message([] { (void)oldroyd_moduli(1.0, 1.0, 1.0); }).find("phi = 1"), std::string::npos);
  EXPECT_NE(message([] { (void)oldroyd_moduli(-1.0, 0.1, 1.0); }).find("lambda = -1"), std::string::npos);
  EXPECT_NE(message([] { (void)oldroyd_moduli(1.0, 0.1, 0.0); }).find("omega_star = 0"), std::string::npos);
  EXPECT_NE(message([] { (void)oldroyd_moduli(1.0, 0.1, 1.0, -0.5); }).find("alpha = -0.5"),
            std::string::npos);
}
