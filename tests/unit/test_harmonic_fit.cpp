// The first-harmonic fit and the complex modulus of eqs. 4.6-4.7.
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/analysis/harmonic_fit.hpp"

using namespace softflow::analysis;

namespace {
constexpr double kPi = std::numbers::pi;

std::vector<double> uneven_times(double omega, double periods, int n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  const double dt = periods * 2 * kPi / omega / n;
  std::vector<double> t;
  for (int k = 0; k < n; ++k) t.push_back(3.0 + dt * (k + jitter(random)));
  return t;
}
}  // namespace

TEST(HarmonicFit, RecoversMeanAmplitudeAndPhaseOfASinusoidOnUnevenSamples) {
  const double omega = 0.7;
  // Less than one period too: the QR separates the terms where the normal equations would not.
  for (double periods : {0.6, 2.0, 3.5}) {
    const auto t = uneven_times(omega, periods, 40, 7);
    std::vector<double> y;
    for (double s : t) y.push_back(0.25 + 1.5 * std::cos(omega * s + 0.4));
    const HarmonicFit fit = fit_harmonic(t, y, omega);
    EXPECT_NEAR(fit.mean, 0.25, 1e-12) << periods;
    EXPECT_NEAR(std::abs(fit.amplitude), 1.5, 1e-12);
    EXPECT_NEAR(std::arg(fit.amplitude), 0.4, 1e-12);
    EXPECT_LT(fit.residual, 1e-12);
    EXPECT_EQ(fit.samples, 40u);
  }
}

TEST(HarmonicFit, ResidualMeasuresWhatTheFirstHarmonicLeavesOut) {
  // A second harmonic of a tenth of the first: over whole periods it is orthogonal to the
  // fit, and its rms over the first harmonic's amplitude is 0.1 / sqrt(2).
  const double omega = 2.0;
  std::vector<double> t, y;
  for (int k = 0; k < 400; ++k) {
    t.push_back(k * 2 * 2 * kPi / omega / 400);
    y.push_back(std::sin(omega * t.back()) + 0.1 * std::sin(2 * omega * t.back()));
  }
  const HarmonicFit fit = fit_harmonic(t, y, omega);
  EXPECT_NEAR(std::abs(fit.amplitude), 1.0, 1e-12);
  EXPECT_NEAR(fit.residual, 0.1 / std::sqrt(2.0), 1e-12);
}

TEST(HarmonicFit, RefusesWhatCannotBeFitted) {
  const std::vector<double> t{0, 1, 2}, y{0, 1, 0};
  EXPECT_THROW((void)fit_harmonic(t, y, 1.0), std::invalid_argument);
  const std::vector<double> t4{0, 1, 2, 3}, y3{0, 1, 0};
  EXPECT_THROW((void)fit_harmonic(t4, y3, 1.0), std::invalid_argument);
  const std::vector<double> y4{0, 1, 0, 1};
  EXPECT_THROW((void)fit_harmonic(t4, y4, 0.0), std::invalid_argument);
  // Samples 1e-12 of a period apart cannot tell a cosine from the mean.
  const std::vector<double> close{1.0, 1.0 + 1e-12, 1.0 + 2e-12, 1.0 + 3e-12};
  EXPECT_THROW((void)fit_harmonic(close, y4, 1.0), std::invalid_argument);
}

TEST(HarmonicFit, LastPeriodsStartAtTheFirstSampleOfTheWindow) {
  const double omega = 2 * kPi;  // period 1
  std::vector<double> t;
  for (int k = 0; k <= 50; ++k) t.push_back(0.1 * k);  // t = 0 ... 5
  // t in (3, 5]: t = 3 has the phase of t = 5 (0.1 * 30 is 3 only to rounding).
  EXPECT_EQ(last_periods_start(t, omega, 2.0), 31u);
  EXPECT_EQ(last_periods_start(t, omega, 5.0), 1u);  // the whole record but t = 0
  // A record starting at t = 0.1 (a run's first solve) still covers (0, 5].
  const std::vector<double> from_first_step(t.begin() + 1, t.end());
  EXPECT_EQ(last_periods_start(from_first_step, omega, 5.0), 0u);
  EXPECT_EQ(last_periods_start(t, omega, 5.5), t.size());  // not enough yet
}

TEST(HarmonicFit, ComplexModulusOfANewtonianLiquidIsPurelyViscous) {
  // stress = eta * shear rate, whatever the phase of the forcing: G' = 0, G'' = eta omega.
  const double eta = 1.7, omega = 0.4;
  const std::complex<double> rate = std::polar(0.3, -1.1);
  const std::complex<double> g = complex_modulus(eta * rate, rate, omega);
  EXPECT_NEAR(g.real(), 0.0, 1e-15);
  EXPECT_NEAR(g.imag(), eta * omega, 1e-15);
  // An elastic solid, stress = G strain with strain = rate / (i omega): G' = G, G'' = 0.
  const std::complex<double> solid = complex_modulus(2.5 * rate / std::complex<double>(0, omega), rate, omega);
  EXPECT_NEAR(solid.real(), 2.5, 1e-15);
  EXPECT_NEAR(solid.imag(), 0.0, 1e-15);
}
