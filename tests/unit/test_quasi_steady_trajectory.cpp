// The quasi-steady migration trajectory of `softflow migration --trajectory-from`:
// dy/dt = v(y) along a master curve linear between its stretches, against the
// closed forms of a linear curve (exponential approach to the centre plane or
// to a neutral height) and a quadrature of dy / v on a curve of unequal pieces.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/migration_curves.hpp"

using namespace softflow;

namespace {

/// A master curve with stretches at `heights` (y_p / y_p,max) whose v_p is
/// `velocity(y)` (in y_p per unit time), y_p,max = 1.5.
template <class Velocity>
simulation::MigrationCurves curve(const std::vector<double>& heights, Velocity velocity) {
  simulation::MigrationCurves c;
  c.y_max = 1.5;
  for (const double y : heights) c.segments.push_back({0, 0.0, 1.0, y, c.y_max * velocity(y)});
  return c;
}

}  // namespace

TEST(QuasiSteadyTrajectory, FollowsTheExponentialOfALinearCurveToItsLowestHeight) {
  const double a = 0.02;  // d(y_rel)/dt = -a y_rel: eq. 3.7's linear law
  const auto c = curve({0.1, 0.2, 0.35, 0.5, 0.7, 0.9}, [&](double y) { return -a * y; });
  const auto path = simulation::quasi_steady_trajectory(c, 0.85);
  EXPECT_NEAR(path.duration, std::log(0.85 / 0.1) / a, 1e-10);
  EXPECT_DOUBLE_EQ(path.y_end, 0.1);
  EXPECT_TRUE(std::isnan(path.neutral_height));
  EXPECT_NE(path.ends_at.find("lowest measured height"), std::string::npos) << path.ends_at;
  ASSERT_EQ(path.t.size(), 1u + 8u * 5u);  // five pieces from 0.85 down, eight samples each
  for (std::size_t i = 0; i < path.t.size(); ++i)
    EXPECT_NEAR(path.y_rel[i], 0.85 * std::exp(-a * path.t[i]), 1e-12) << i;
}

TEST(QuasiSteadyTrajectory, StopsWithinTheToleranceOfAStableNeutralHeightFromEitherSide) {
  const double a = 0.05, y_n = 0.3;  // v = -a (y - y_n): particles gather at y_n
  const auto c = curve({0.05, 0.2, 0.4, 0.6, 0.8}, [&](double y) { return -a * (y - y_n); });
  const auto above = simulation::quasi_steady_trajectory(c, 0.75);
  EXPECT_NEAR(above.neutral_height, y_n, 1e-14);
  EXPECT_NEAR(above.y_end, 1.01 * y_n, 1e-14);
  EXPECT_NEAR(above.duration, std::log((0.75 - y_n) / (0.01 * y_n)) / a, 1e-9);
  EXPECT_NE(above.ends_at.find("within 1 % of the stable neutral height"), std::string::npos);
  const auto below = simulation::quasi_steady_trajectory(c, 0.1, 0.02);
  EXPECT_NEAR(below.y_end, 0.98 * y_n, 1e-14);
  EXPECT_NEAR(below.duration, std::log((y_n - 0.1) / (0.02 * y_n)) / a, 1e-9);
  // Already within the tolerance: no time at all.
  EXPECT_EQ(simulation::quasi_steady_trajectory(c, 0.301).duration, 0.0);
}

TEST(QuasiSteadyTrajectory, StopsWhereTheToleranceBandBeginsEvenPiecesBeforeTheZero) {
  // A node inside the 1 % band above y_n: the path stops at 1.01 y_n, in the
  // piece above that node, not at the node.
  const double a = 0.05, y_n = 0.3;
  const auto c = curve({0.2, 0.301, 0.4}, [&](double y) { return -a * (y - y_n); });
  const auto path = simulation::quasi_steady_trajectory(c, 0.35);
  EXPECT_NEAR(path.y_end, 1.01 * y_n, 1e-14);
  EXPECT_NEAR(path.duration, std::log(0.05 / 0.003) / a, 1e-9);
  // Started inside the band, a piece away from the zero: no time.
  EXPECT_EQ(simulation::quasi_steady_trajectory(c, 0.3025).duration, 0.0);
}

TEST(QuasiSteadyTrajectory, TheCentrePlaneGetsABandOfATenthOfItsHeightScale) {
  // v_rel = -0.05 y (a master curve through the centre plane): the band is
  // 1 % of 0.1 y_p,max there, and a y_n off zero by round-off changes nothing.
  const auto c = curve({-0.2, 0.2}, [](double y) { return -0.05 * y; });
  const auto path = simulation::quasi_steady_trajectory(c, -0.1);
  EXPECT_NEAR(path.y_end, -0.001, 1e-15);
  EXPECT_NEAR(path.duration, std::log(100.0) / 0.05, 1e-9);
  auto nudged = c;
  nudged.segments[1].v_p += 1e-9;
  EXPECT_NEAR(simulation::quasi_steady_trajectory(nudged, -0.1).duration, path.duration, 1e-4);
}

TEST(QuasiSteadyTrajectory, AZeroOnANodeIsAnExactNeutralHeight) {
  // v_rel = 0.007 / 0 / -0.007 at -0.35 / 0 / 0.35: stable at the node 0.
  simulation::MigrationCurves c;
  c.y_max = 1.0;
  c.segments = {{0, 0, 1, -0.35, 0.007}, {0, 1, 2, 0.0, 0.0}, {0, 2, 3, 0.35, -0.007}};
  const auto path = simulation::quasi_steady_trajectory(c, -0.3);
  EXPECT_EQ(path.neutral_height, 0.0);
  EXPECT_NEAR(path.y_end, -0.001, 1e-15);
  EXPECT_NEAR(path.duration, std::log(0.3 / 0.001) / 0.02, 1e-9);
  EXPECT_NE(path.ends_at.find("stable neutral height"), std::string::npos) << path.ends_at;
  // Touched, not crossed (v_p > 0 again above it): it still stops there, saying so.
  c.segments[2].v_p = 0.004;
  const auto touched = simulation::quasi_steady_trajectory(c, -0.3);
  EXPECT_NEAR(touched.y_end, -0.001, 1e-15);
  EXPECT_TRUE(std::isfinite(touched.duration));
  EXPECT_NE(touched.ends_at.find("points onwards again"), std::string::npos) << touched.ends_at;
  // Started on it: there already.
  const auto on = simulation::quasi_steady_trajectory(c, 0.0);
  EXPECT_EQ(on.duration, 0.0);
  EXPECT_NE(on.ends_at.find("v_p = 0 where it starts"), std::string::npos) << on.ends_at;
}

TEST(QuasiSteadyTrajectory, StartsOnANodeOrAnEndGoingEitherWay) {
  const auto c = curve({0.1, 0.3, 0.5, 0.7, 0.9}, [](double y) { return 0.01 * (y - 0.5); });
  const auto up = simulation::quasi_steady_trajectory(c, 0.7);  // on a node, moving up
  EXPECT_NEAR(up.duration, std::log(0.4 / 0.2) / 0.01, 1e-9);
  EXPECT_EQ(up.t.size(), 9u);                                     // one piece
  const auto down = simulation::quasi_steady_trajectory(c, 0.3);  // on a node, moving down
  EXPECT_NEAR(down.duration, std::log(0.4 / 0.2) / 0.01, 1e-9);
  EXPECT_EQ(down.t.size(), 9u);
  EXPECT_EQ(simulation::quasi_steady_trajectory(c, 0.9).duration, 0.0);  // at the top, moving up
  EXPECT_EQ(simulation::quasi_steady_trajectory(c, 0.1).duration,
            0.0);  // at the bottom, moving down
}

TEST(QuasiSteadyTrajectory, LeavesAnUnstableNeutralHeightToTheEndOfTheCurve) {
  const auto c = curve({0.1, 0.3, 0.5, 0.7, 0.9}, [](double y) { return 0.01 * (y - 0.5); });
  const auto up = simulation::quasi_steady_trajectory(c, 0.6);
  EXPECT_DOUBLE_EQ(up.y_end, 0.9);
  EXPECT_NE(up.ends_at.find("highest measured height"), std::string::npos) << up.ends_at;
  EXPECT_NEAR(up.duration, std::log(0.4 / 0.1) / 0.01, 1e-9);
}

TEST(QuasiSteadyTrajectory, IntegratesUnequalPiecesAsAQuadratureOfOneOverV) {
  // v = -0.03 y^2 sampled at uneven heights; the trajectory integrates the
  // curve linear between them, so compare with Simpson's rule on that curve.
  const std::vector<double> heights{0.12, 0.15, 0.27, 0.31, 0.6, 0.64, 0.95};
  const auto c = curve(heights, [](double y) { return -0.03 * y * y; });
  const auto path = simulation::quasi_steady_trajectory(c, 0.9);
  double expected = 0.0;
  for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
    const double lo = heights[k], hi = std::min(heights[k + 1], 0.9);
    if (hi <= lo) continue;
    const double vl = -0.03 * heights[k] * heights[k], vh = -0.03 * heights[k + 1] * heights[k + 1];
    const auto v = [&](double y) {
      return vl + (vh - vl) * (y - heights[k]) / (heights[k + 1] - heights[k]);
    };
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double y = lo + (hi - lo) * i / n;
      sum += (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0)) / v(y);
    }
    expected += -sum * (hi - lo) / (3.0 * n);  // time to go down from hi to lo
  }
  EXPECT_NEAR(path.duration, expected, 1e-8 * expected);
  EXPECT_DOUBLE_EQ(path.y_end, 0.12);
}

TEST(QuasiSteadyTrajectory, StretchesAtOneHeightAreMerged) {
  simulation::MigrationCurves c;
  c.y_max = 2.0;
  c.segments = {{0, 0, 1, 0.2, -0.002},
                {1, 0, 1, 0.5, -0.004},
                {2, 0, 1, 0.5, -0.008},
                {1, 1, 2, 0.8, -0.01}};
  auto path = simulation::quasi_steady_trajectory(c, 0.5);
  // Down from 0.5 along v_rel linear from -0.003 (the two stretches' mean) to -0.001.
  const double slope = (-0.003 + 0.001) / 0.3;
  EXPECT_NEAR(path.duration, std::log(-0.001 / -0.003) / slope, 1e-10);
  EXPECT_EQ(path.t.size(), 9u);  // one piece: the start on a node adds nothing from the piece above
  // Three at one height: their mean, each with its weight.
  c.segments = {
      {0, 0, 1, 0.2, -0.002}, {1, 0, 1, 0.5, 0.0}, {2, 0, 1, 0.5, 0.0}, {3, 0, 1, 0.5, -0.018}};
  path = simulation::quasi_steady_trajectory(c, 0.5);
  EXPECT_NEAR(path.duration, std::log(-0.001 / -0.003) / slope, 1e-10);
}

TEST(QuasiSteadyTrajectory, RefusesAStartOutsideTheMeasuredHeightsAndAOnePointCurve) {
  const auto c = curve({0.2, 0.4}, [](double y) { return -y; });
  try {
    simulation::quasi_steady_trajectory(c, 0.45);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("--trajectory-from = 0.45"), std::string::npos) << m;
    EXPECT_NE(m.find("0.2000 ... 0.4000"), std::string::npos) << m;
  }
  EXPECT_THROW(simulation::quasi_steady_trajectory(curve({0.3}, [](double y) { return -y; }), 0.3),
               InputError);
  EXPECT_THROW(simulation::quasi_steady_trajectory(c, 0.3, 0.0), InputError);
  // A round-off beyond an end is that end.
  EXPECT_EQ(simulation::quasi_steady_trajectory(c, 0.4 + 1e-13).y_start, 0.4);
}

namespace {

simulation::MasterCurve master(const std::vector<simulation::MigrationSegment>& segments) {
  return simulation::master_curve(segments);
}

using Kind = simulation::NeutralHeight::Kind;

}  // namespace

TEST(NeutralHeights, CrossingsBetweenNodesByLinearInterpolation) {
  // + / - / + at 0.1 / 0.3 / 0.7: stable between the first two, unstable above.
  const auto zeros = simulation::neutral_heights(
      master({{0, 0, 1, 0.1, 0.002}, {0, 1, 2, 0.3, -0.002}, {1, 0, 1, 0.7, 0.006}}));
  ASSERT_EQ(zeros.size(), 2u);
  EXPECT_NEAR(zeros[0].y_rel, 0.2, 1e-15);
  EXPECT_NEAR(zeros[0].error, 0.1, 1e-15);
  EXPECT_EQ(zeros[0].kind, Kind::stable);
  EXPECT_NEAR(zeros[1].y_rel, 0.4, 1e-15);  // a quarter of the way from -0.002 to 0.006
  EXPECT_NEAR(zeros[1].error, 0.2, 1e-15);
  EXPECT_EQ(zeros[1].kind, Kind::unstable);
  // One sign throughout: none.
  EXPECT_TRUE(
      simulation::neutral_heights(master({{0, 0, 1, 0.1, -1.0}, {0, 1, 2, 0.3, -2.0}})).empty());
}

TEST(NeutralHeights, AZeroOnANodeIsListedOnceWithItsKind) {
  // Before the master curve was shared, a zero on a stretch was skipped.
  auto zeros = simulation::neutral_heights(
      master({{0, 0, 1, 0.1, 0.002}, {0, 1, 2, 0.3, 0.0}, {0, 2, 3, 0.4, -0.002}}));
  ASSERT_EQ(zeros.size(), 1u);
  EXPECT_EQ(zeros[0].y_rel, 0.3);
  EXPECT_NEAR(zeros[0].error, 0.1, 1e-15);  // half the larger gap to a neighbour
  EXPECT_EQ(zeros[0].kind, Kind::stable);
  // Touched: + on both sides.
  zeros = simulation::neutral_heights(
      master({{0, 0, 1, 0.1, 0.002}, {0, 1, 2, 0.3, 0.0}, {0, 2, 3, 0.4, 0.001}}));
  ASSERT_EQ(zeros.size(), 1u);
  EXPECT_EQ(zeros[0].kind, Kind::touching);
  // On the last node: the side beyond is not measured.
  zeros = simulation::neutral_heights(master({{0, 0, 1, 0.1, 0.002}, {0, 1, 2, 0.3, 0.0}}));
  ASSERT_EQ(zeros.size(), 1u);
  EXPECT_EQ(zeros[0].kind, Kind::at_end);
  // Zero from a node on to the last: both at an end, and a trajectory stops at the first.
  simulation::MigrationCurves c;
  c.y_max = 1.0;
  c.segments = {{0, 0, 1, 0.1, 0.002}, {0, 1, 2, 0.3, 0.0}, {0, 2, 3, 0.5, 0.0}};
  zeros = simulation::neutral_heights(simulation::master_curve(c.segments));
  ASSERT_EQ(zeros.size(), 2u);
  EXPECT_EQ(zeros[0].kind, Kind::at_end);
  EXPECT_EQ(zeros[1].kind, Kind::at_end);
  const auto path = simulation::quasi_steady_trajectory(c, 0.15);
  EXPECT_EQ(path.neutral_height, 0.3);
  EXPECT_NE(path.ends_at.find("v_p = 0 from there to the last measured height"), std::string::npos)
      << path.ends_at;
  EXPECT_EQ(path.ends_at.find("stable"), std::string::npos) << path.ends_at;
  // Two zero nodes in a row take their kind from the nearest non-zero sides.
  zeros = simulation::neutral_heights(master(
      {{0, 0, 1, 0.1, -0.002}, {0, 1, 2, 0.2, 0.0}, {0, 2, 3, 0.3, 0.0}, {0, 3, 4, 0.4, 0.003}}));
  ASSERT_EQ(zeros.size(), 2u);
  EXPECT_EQ(zeros[0].kind, Kind::unstable);
  EXPECT_EQ(zeros[1].kind, Kind::unstable);
}

TEST(NeutralHeights, ReadTheCurveTheTrajectoryIntegrates) {
  // Two runs at one height average to +0.001 there: the same stable height
  // for the list and for the trajectory, where a list of unmerged stretches
  // would have found a crossing between the two (0.006 and -0.004 of the pair).
  simulation::MigrationCurves c;
  c.y_max = 1.0;
  c.segments = {
      {0, 0, 1, 0.1, 0.003}, {1, 0, 1, 0.3, 0.006}, {2, 0, 1, 0.3, -0.004}, {0, 1, 2, 0.5, -0.003}};
  const auto zeros = simulation::neutral_heights(simulation::master_curve(c.segments));
  ASSERT_EQ(zeros.size(), 1u);
  EXPECT_NEAR(zeros[0].y_rel, 0.3 + 0.2 * 0.001 / 0.004, 1e-15);
  EXPECT_EQ(zeros[0].kind, Kind::stable);
  const auto path = simulation::quasi_steady_trajectory(c, 0.45);
  EXPECT_DOUBLE_EQ(path.neutral_height, zeros[0].y_rel);
  EXPECT_NE(path.ends_at.find("stable neutral height"), std::string::npos) << path.ends_at;
}
