// SteadyStateMonitor: when D, the shape vector and the centre velocity have
// stopped changing over a window; against the closed form for an
// exponential approach, independent of the time step, not fooled by
// oscillations or a near-sphere's undefined angle, exact after restore.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/analysis/steady_state.hpp"
#include "softflow/common/error.hpp"

using namespace softflow;
using analysis::ObjectSample;
using analysis::SteadyCriterion;
using analysis::SteadyStateMonitor;

namespace {

constexpr double kDInf = 0.1;
constexpr double kTheta = 0.66;  // rad

/// D(t) = D_inf (1 - e^{-t}) at fixed theta, sampled every dt up to t_end;
/// returns the monitor's reached_at (or -1).
double exponential_reached_at(const SteadyCriterion& criterion, double dt, double t_end) {
  SteadyStateMonitor m(criterion);
  const int n = static_cast<int>(std::lround(t_end / dt));
  for (int i = 0; i <= n; ++i) {
    const double t = i * dt;
    m.add(t, {{kDInf * (1.0 - std::exp(-t)), kTheta, {}}});
  }
  return m.reached_at() ? *m.reached_at() : -1.0;
}

}  // namespace

TEST(SteadyState, ExponentialApproachStopsWhereTheClosedFormSays) {
  // Over [t - W, t] D changes by D_inf e^{-t} (e^W - 1): steady from
  // t* = ln(D_inf (e^W - 1) / tol), the first sample at or after it. The
  // shape vector changes by D's change times |cos 2 theta| or |sin 2 theta|
  // (both < 1), so D decides.
  const double tol = 1e-4, window = 1.0;
  const double t_star = std::log(kDInf * (std::exp(window) - 1.0) / tol);
  for (double dt : {0.1, 0.02, 0.005}) {
    const double reached = exponential_reached_at({tol, window, 1.0}, dt, 20.0);
    EXPECT_GE(reached, t_star - 1e-9) << "dt = " << dt;
    EXPECT_LT(reached, t_star + dt + 1e-9) << "dt = " << dt;
  }
}

TEST(SteadyState, NeedsAWholeWindowOfSamples) {
  SteadyStateMonitor m({1e-3, 2.0, 1.0});
  for (int i = 0; i <= 19; ++i) m.add(0.1 * i, {{0.05, kTheta, {}}});
  EXPECT_FALSE(m.steady()) << "constant over 1.9 < window 2";
  m.add(2.0, {{0.05, kTheta, {}}});
  EXPECT_TRUE(m.steady());
  ASSERT_TRUE(m.reached_at());
  EXPECT_DOUBLE_EQ(*m.reached_at(), 2.0);
}

TEST(SteadyState, AnOscillationLargerThanTheToleranceIsNotSteady) {
  // D = 0.1 + a sin(t): over a window of 2 pi the spread is 2a.
  for (double a : {4e-4, 6e-4}) {
    SteadyStateMonitor m({1e-3, 2.0 * std::numbers::pi, 1.0});
    for (int i = 0; i <= 2000; ++i) {
      const double t = 0.02 * i;
      m.add(t, {{0.1 + a * std::sin(t), kTheta, {}}});
    }
    EXPECT_EQ(m.reached_at().has_value(), 2 * a <= 1e-3) << "a = " << a;
    EXPECT_NEAR(m.changes().deformation, 2 * a, 1e-3 * a);
  }
}

TEST(SteadyState, ANearSpheresAngleDoesNotHoldTheRunButARotatingShapeDoes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.5, 1.5);
  // D = 1e-6 with theta jumping at random (a sphere's fit): shape changes ~2e-6.
  SteadyStateMonitor sphere({1e-4, 1.0, 1.0});
  for (int i = 0; i <= 20; ++i) sphere.add(0.1 * i, {{1e-6, angle(rng), {}}});
  EXPECT_TRUE(sphere.steady());
  EXPECT_GT(sphere.changes().theta_rad, 0.5);
  // D = 0.1 fixed while theta turns by 0.01 rad per time unit: the shape
  // vector moves by ~2 D dtheta = 2e-3 per window.
  SteadyStateMonitor turning({1e-4, 1.0, 1.0});
  for (int i = 0; i <= 100; ++i) turning.add(0.1 * i, {{0.1, 0.7 + 0.001 * i, {}}});
  EXPECT_FALSE(turning.reached_at().has_value());
  EXPECT_NEAR(turning.changes().shape, 2 * 0.1 * 0.01 * std::sin(2 * 0.7), 1e-4);
  EXPECT_NEAR(turning.changes().deformation, 0.0, 1e-15);
}

TEST(SteadyState, CentreVelocityInUnitsOfTheScaleAndEveryObjectCounts) {
  // Object 1 steady; object 2 accelerates by 1e-3 per time unit, which is
  // 5e-4 in units of velocity_scale = 2: steady at tol 6e-4, not at 4e-4.
  for (double tol : {6e-4, 4e-4}) {
    SteadyStateMonitor m({tol, 1.0, 2.0});
    for (int i = 0; i <= 30; ++i) {
      const double t = 0.1 * i;
      m.add(t, {{0.1, kTheta, {}}, {0.1, kTheta, {1e-3 * t, 0.0, 0.0}}});
    }
    EXPECT_NEAR(m.changes().velocity, 5e-4, 1e-12);
    EXPECT_EQ(m.steady(), tol > 5e-4) << "tol = " << tol;
  }
}

TEST(SteadyState, ARestoredMonitorDecidesAsTheOriginal) {
  const SteadyCriterion criterion{1e-4, 1.0, 1.0};
  SteadyStateMonitor whole(criterion), first(criterion);
  const auto sample = [](double t) {
    return std::vector<ObjectSample>{{kDInf * (1.0 - std::exp(-t)), kTheta, {0.0, 1e-5 * t, 0.0}}};
  };
  for (int i = 0; i <= 50; ++i) first.add(0.1 * i, sample(0.1 * i));
  SteadyStateMonitor second(criterion);
  second.restore(first.samples(), first.reached_at());
  for (int i = 0; i <= 200; ++i) whole.add(0.1 * i, sample(0.1 * i));
  for (int i = 51; i <= 200; ++i) second.add(0.1 * i, sample(0.1 * i));
  ASSERT_TRUE(whole.reached_at());
  ASSERT_TRUE(second.reached_at());
  EXPECT_EQ(*whole.reached_at(), *second.reached_at());
  EXPECT_EQ(whole.samples().size(), second.samples().size());
}

TEST(SteadyState, RefusesBadCriteriaAndSamplesOutOfOrder) {
  EXPECT_THROW(SteadyStateMonitor({0.0, 1.0, 1.0}), Error);
  EXPECT_THROW(SteadyStateMonitor({1e-3, -1.0, 1.0}), Error);
  EXPECT_THROW(SteadyStateMonitor({1e-3, 1.0, NAN}), Error);
  SteadyStateMonitor m({1e-3, 1.0, 1.0});
  m.add(1.0, {{0.1, kTheta, {}}});
  EXPECT_THROW(m.add(1.0, {{0.1, kTheta, {}}}), Error);
  EXPECT_THROW(m.add(2.0, {{0.1, kTheta, {}}, {0.1, kTheta, {}}}), Error);
}
