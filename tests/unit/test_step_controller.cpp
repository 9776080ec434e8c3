// The adaptive step controller: acceptance, the size law, its limits.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "softflow/common/error.hpp"
#include "softflow/time/step_controller.hpp"

using softflow::time::StepController;
using softflow::time::StepControllerSettings;

namespace {
StepControllerSettings settings(double tolerance = 1e-3) {
  StepControllerSettings s;
  s.tolerance = tolerance;
  s.min_step = 1e-4;
  return s;
}
}  // namespace

TEST(StepController, AcceptsBelowTheToleranceAndScalesByTheEstimatesOrder) {
  const StepController c(settings());
  // The estimate scales as dt^2: a step with a quarter of the tolerance may
  // double, times the safety factor.
  const auto d = c.judge(0.1, 0.25e-3);
  EXPECT_TRUE(d.accepted);
  EXPECT_NEAR(d.next_step, 0.1 * 0.9 * 2.0, 1e-15);
  // At the tolerance: accepted, next a little smaller (the safety factor).
  const auto at = c.judge(0.1, 1e-3);
  EXPECT_TRUE(at.accepted);
  EXPECT_NEAR(at.next_step, 0.09, 1e-15);
}

TEST(StepController, TheNextStepMeetsTheToleranceForAnEstimateOfItsOrder) {
  // For an estimate C dt^2 the proposed step gives safety^2 x tolerance.
  const StepController c(settings());
  const double constant = 0.37;
  double dt = 0.01;
  for (int i = 0; i < 5; ++i) dt = c.judge(dt, constant * dt * dt).next_step;
  EXPECT_NEAR(constant * dt * dt, 0.81e-3, 1e-9);
}

TEST(StepController, RejectsAboveTheToleranceAndRetriesSmaller) {
  const StepController c(settings());
  const auto d = c.judge(0.1, 4e-3);
  EXPECT_FALSE(d.accepted);
  EXPECT_NEAR(d.next_step, 0.1 * 0.9 * 0.5, 1e-15);
  // A very large estimate shrinks by min_shrink at most.
  EXPECT_NEAR(c.judge(0.1, 1.0).next_step, 0.1 * 0.2, 1e-15);
}

TEST(StepController, GrowthIsBounded) {
  auto s = settings();
  s.max_growth = 1.5;
  s.max_step = 0.12;
  const StepController c(s);
  EXPECT_NEAR(c.judge(0.05, 1e-9).next_step, 0.075, 1e-15);
  EXPECT_NEAR(c.judge(0.05, 0.0).next_step, 0.075, 1e-15);  // nothing moved
  EXPECT_NEAR(c.judge(0.1, 0.0).next_step, 0.12, 1e-15);    // max_step
}

TEST(StepController, AFailureHalvesTheStepAndGivesUpBelowTheSmallest) {
  const StepController c(settings());
  const auto d = c.after_failure(0.1);
  EXPECT_FALSE(d.accepted);
  EXPECT_DOUBLE_EQ(d.next_step, 0.05);
  EXPECT_EQ(c.after_failure(1.5e-4).next_step, 0.0);
  // A non-finite estimate is a failure.
  EXPECT_DOUBLE_EQ(c.judge(0.1, std::numeric_limits<double>::quiet_NaN()).next_step, 0.05);
  EXPECT_DOUBLE_EQ(c.judge(0.1, std::numeric_limits<double>::infinity()).next_step, 0.05);
  // A rejection at the smallest step gives up.
  EXPECT_EQ(c.judge(1e-4, 1.0).next_step, 0.0);
}

TEST(StepController, RefusesSettingsOutOfRange) {
  auto bad = settings(0.0);
  EXPECT_THROW(StepController{bad}, softflow::Error);
  bad = settings();
  bad.max_growth = 1.0;
  EXPECT_THROW(StepController{bad}, softflow::Error);
  bad = settings();
  bad.max_step = 1e-5;  // below min_step
  EXPECT_THROW(StepController{bad}, softflow::Error);
}

TEST(StepController, TheNextPlannedStepShrinksAfterAnAcceptedStepAndIgnoresCutShortSteps) {
  using softflow::time::next_planned_step;
  // A full step: the proposal, smaller or larger.
  EXPECT_DOUBLE_EQ(next_planned_step(0.1, 0.1, 0.08), 0.08);
  EXPECT_DOUBLE_EQ(next_planned_step(0.1, 0.1, 0.15), 0.15);
  // Cut short to 0.02 to land on the end: its estimate lets it grow, the plan stays.
  EXPECT_DOUBLE_EQ(next_planned_step(0.1, 0.02, 0.04), 0.1);
  EXPECT_DOUBLE_EQ(next_planned_step(0.1, 0.02, 0.2), 0.2);
  // ... unless even the short step asks to shrink.
  EXPECT_DOUBLE_EQ(next_planned_step(0.1, 0.02, 0.015), 0.015);
}

