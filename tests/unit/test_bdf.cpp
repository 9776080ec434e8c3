// BDF coefficients and the predictor's extrapolation: each formula is exact
// for polynomials in t of its order, at constant and variable steps.
#include <gtest/gtest.h>

#include <cmath>

#include "softflow/common/error.hpp"
#include "softflow/time/bdf.hpp"

using softflow::time::bdf;
using softflow::time::bdf_order;
using softflow::time::extrapolation;

namespace {

// u(t) = a + b t + c t^2 + d t^3 and its derivative.
struct Polynomial {
  double a, b, c, d;
  [[nodiscard]] double operator()(double t) const { return a + t * (b + t * (c + t * d)); }
  [[nodiscard]] double derivative(double t) const { return b + t * (2.0 * c + 3.0 * t * d); }
};

// The BDF approximation of u'(t + dt), the previous level at t - dt_previous.
double bdf_derivative(const Polynomial& u, int order, double t, double dt, double dt_previous) {
  const auto c = bdf(order, dt, dt_previous);
  return (c.a0 * u(t + dt) + c.a1 * u(t) + c.a2 * u(t - dt_previous)) / dt;
}

// Constant step, then w = dt / dt_previous below, at and above 1.
const double kT = 1.3, kDt = 0.05;
const double kPreviousSteps[] = {kDt, 2.0 * kDt, 0.4 * kDt, 0.037};

}  // namespace

TEST(Bdf, FirstStepIsBdf1ThenBdf2) {
  EXPECT_EQ(bdf_order(0), 1);
  EXPECT_EQ(bdf_order(1), 2);
  EXPECT_EQ(bdf_order(1000), 2);
}

TEST(Bdf, ConstantStepCoefficientsAreTheThesisGearScheme) {
  // Exact in binary, so callers reproduce the hand-written formulas bit for bit.
  const auto c1 = bdf(1);
  EXPECT_EQ(c1.a0, 1.0);
  EXPECT_EQ(c1.a1, -1.0);
  EXPECT_EQ(c1.a2, 0.0);
  EXPECT_EQ(c1.theta(), 1.0);
  const auto c2 = bdf(2);
  EXPECT_EQ(c2.a0, 1.5);
  EXPECT_EQ(c2.a1, -2.0);
  EXPECT_EQ(c2.a2, 0.5);
  EXPECT_DOUBLE_EQ(c2.theta(), 2.0 / 3.0);
  for (double dt : {0.05, 0.0075, 0.002, 0.1, 1.0 / 3.0}) {
    EXPECT_EQ(c2.theta_dt(dt), 2.0 * dt / 3.0) << dt;
    EXPECT_EQ(c1.theta_dt(dt), dt);
    const auto v = bdf(2, dt, dt);  // the variable-step form at w = 1
    EXPECT_EQ(v.a0, c2.a0);
    EXPECT_EQ(v.a1, c2.a1);
    EXPECT_EQ(v.a2, c2.a2);
  }
}

TEST(Bdf, Bdf1IsExactForLinearFunctions) {
  const Polynomial linear{0.3, -1.7, 0.0, 0.0};
  for (double dt_previous : kPreviousSteps)
    EXPECT_NEAR(bdf_derivative(linear, 1, kT, kDt, dt_previous), linear.derivative(kT + kDt), 1e-12);
  // ... and first order only: on a quadratic its error is c dt.
  const Polynomial quadratic{0.3, -1.7, 0.9, 0.0};
  EXPECT_NEAR(bdf_derivative(quadratic, 1, kT, kDt, kDt) - quadratic.derivative(kT + kDt),
              -quadratic.c * kDt, 1e-12);
}

TEST(Bdf, Bdf2IsExactForQuadraticFunctionsAtConstantAndVariableSteps) {
  const Polynomial quadratic{0.3, -1.7, 0.9, 0.0};
  for (double dt_previous : kPreviousSteps)
    EXPECT_NEAR(bdf_derivative(quadratic, 2, kT, kDt, dt_previous),
                quadratic.derivative(kT + kDt), 1e-11)
        << "dt_previous = " << dt_previous;
  // The constant-step formula applied to unequal steps is not: the variable
  // coefficients are needed as soon as the step changes.
  const auto c = bdf(2);
  const double dt_previous = 2.0 * kDt;
  const double wrong =
      (c.a0 * quadratic(kT + kDt) + c.a1 * quadratic(kT) + c.a2 * quadratic(kT - dt_previous)) / kDt;
  EXPECT_GT(std::abs(wrong - quadratic.derivative(kT + kDt)), 1e-3);
}

TEST(Bdf, Bdf2IsSecondOrderOnACubic) {
  // Halving both steps (their ratio fixed) divides the error by 4.
  const Polynomial cubic{0.3, -1.7, 0.9, 2.1};
  for (double ratio : {1.0, 2.0, 0.5}) {
    double error[2];
    for (int k = 0; k < 2; ++k) {
      const double dt = kDt / (1 << k);
      error[k] = std::abs(bdf_derivative(cubic, 2, kT, dt, dt / ratio) - cubic.derivative(kT + dt));
    }
    EXPECT_NEAR(std::log2(error[0] / error[1]), 2.0, 0.1) << "w = " << ratio;
  }
}

TEST(Bdf, ExtrapolationIsExactForLinearFunctions) {
  const Polynomial linear{0.3, -1.7, 0.0, 0.0};
  for (double dt_previous : kPreviousSteps) {
    const auto e = extrapolation(2, kDt, dt_previous);
    EXPECT_NEAR(e.current * linear(kT) + e.previous * linear(kT - dt_previous), linear(kT + kDt), 1e-12)
        << "dt_previous = " << dt_previous;
  }
  const auto e2 = extrapolation(2);  // eq. 2.49: 2 x_n - x_{n-1}
  EXPECT_EQ(e2.current, 2.0);
  EXPECT_EQ(e2.previous, -1.0);
  const auto e1 = extrapolation(1);  // eq. 2.47: x_n
  EXPECT_EQ(e1.current, 1.0);
  EXPECT_EQ(e1.previous, 0.0);
}

TEST(Bdf, RejectsOtherOrdersAndNonPositiveSteps) {
  EXPECT_THROW((void)bdf(3), softflow::Error);
  EXPECT_THROW((void)bdf(0), softflow::Error);
  EXPECT_THROW((void)bdf(2, 0.1, 0.0), softflow::Error);
  EXPECT_THROW((void)bdf(1, -0.1, 0.1), softflow::Error);
  EXPECT_THROW((void)extrapolation(2, 0.1, -1.0), softflow::Error);
  EXPECT_NO_THROW((void)bdf(1, 0.1, 0.0));  // BDF1 has no previous step
}
