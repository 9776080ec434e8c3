// Wall velocity histories: steady, start-up, cessation, oscillatory.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/physics/stokes/wall_motion.hpp"

using softflow::physics::WallMotion;

TEST(WallMotion, SteadyShearMovesWallsAtHalfHeightTimesRate) {
  const auto w = WallMotion::steady(30.0, 2.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(7.0), 30.0);
  EXPECT_DOUBLE_EQ(w.velocity(Eigen::Vector3d(1, 15, 2), 0.0).x(), 30.0);
  EXPECT_DOUBLE_EQ(w.velocity(Eigen::Vector3d(1, -15, 2), 0.0).x(), -30.0);
  EXPECT_DOUBLE_EQ(w.velocity(Eigen::Vector3d(1, 15, 2), 0.0).y(), 0.0);
}

TEST(WallMotion, StartUpIsAtRestBeforeTimeZero) {
  const auto w = WallMotion::start_up(10.0, 1.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(-0.1), 0.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(0.5), 5.0);
}

TEST(WallMotion, CessationMovesUntilTheStopTimeThenRests) {
  const auto w = WallMotion::cessation(10.0, 2.0, 3.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(0.0), 10.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(2.999), 10.0);
  EXPECT_DOUBLE_EQ(w.shear_rate(1.0), 2.0);
  // The step that ends at the stop time still sees the walls move (time
  // loops sample them at the end of a step); any later time sees them at rest.
  EXPECT_DOUBLE_EQ(w.wall_speed(3.0), 10.0);
  EXPECT_DOUBLE_EQ(w.wall_speed(3.0 + 1e-12), 10.0);  // round-off of an accumulated time
  EXPECT_DOUBLE_EQ(w.wall_speed(3.001), 0.0);
  EXPECT_TRUE(w.jumps_at(3.0));
  EXPECT_FALSE(w.jumps_at(2.9));
  EXPECT_FALSE(WallMotion::steady(10.0, 2.0).jumps_at(0.0));
  EXPECT_DOUBLE_EQ(w.wall_speed(7.5), 0.0);
  EXPECT_DOUBLE_EQ(w.velocity(Eigen::Vector3d(1, 5, 2), 4.0).x(), 0.0);
  EXPECT_DOUBLE_EQ(w.velocity(Eigen::Vector3d(1, -5, 2), 1.0).x(), -10.0);
}

TEST(WallMotion, OscillatoryFollowsSpecAndIntegratesToTheStrainAmplitude) {
  const double h = 8.0, gamma0 = 0.2, omega = 3.0;
  const auto w = WallMotion::oscillatory(h, gamma0, omega);
  EXPECT_NEAR(w.wall_speed(0.3), 0.5 * h * gamma0 * omega * std::sin(omega * 0.3), 1e-15);
  // Strain over half a period: integral of the shear rate = 2 gamma0.
  const int n = 20000;
  const double period = 2 * M_PI / omega;
  double strain = 0.0;
  for (int i = 0; i < n; ++i) strain += w.shear_rate((i + 0.5) * 0.5 * period / n) * 0.5 * period / n;
  EXPECT_NEAR(strain, 2 * gamma0, 1e-8);
}
