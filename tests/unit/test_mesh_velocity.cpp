// BDF mesh velocity: exact for trajectories of the formula's order.
#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/ale/mesh_velocity.hpp"

using softflow::mesh::Point;
using softflow::physics::bdf_mesh_velocity;

namespace {
// A node trajectory x(t) = a + b t + c t^2 and its velocity.
Point position(const Point& a, const Point& b, const Point& c, double t) { return a + b * t + c * t * t; }
Point velocity(const Point& b, const Point& c, double t) { return b + 2.0 * t * c; }
}  // namespace

TEST(MeshVelocity, Bdf2IsExactForQuadraticMotionAndBdf1ForLinear) {
  const Point a(0.3, -1.0, 2.0), b(1.0, 0.5, -0.25), c(-0.7, 0.2, 0.9);
  const double t = 1.3, dt = 0.05;
  const std::vector<Point> x_new{position(a, b, c, t + dt)}, x{position(a, b, c, t)},
      x_old{position(a, b, c, t - dt)};
  const auto bdf2 = bdf_mesh_velocity(x_new, x, x_old, dt, dt);
  EXPECT_LT((bdf2[0] - velocity(b, c, t + dt)).norm(), 1e-12);
  // BDF1 is exact for linear motion only; for the quadratic one its error is c dt.
  const std::vector<Point> lin_new{a + b * (t + dt)}, lin{a + b * t};
  EXPECT_LT((bdf_mesh_velocity(lin_new, lin, {}, dt, 0.0)[0] - b).norm(), 1e-12);
  const auto bdf1 = bdf_mesh_velocity(x_new, x, {}, dt, 0.0);
  EXPECT_NEAR((bdf1[0] - velocity(b, c, t + dt)).norm(), (c * dt).norm(), 1e-12);
}

TEST(MeshVelocity, Bdf2IsExactForQuadraticMotionAtVariableSteps) {
  // Adaptive runs change dt: the previous level lies dt_previous back.
  const Point a(0.3, -1.0, 2.0), b(1.0, 0.5, -0.25), c(-0.7, 0.2, 0.9);
  const double t = 1.3, dt = 0.05;
  for (double dt_previous : {0.02, 0.05, 0.11}) {
    const std::vector<Point> x_new{position(a, b, c, t + dt)}, x{position(a, b, c, t)},
        x_old{position(a, b, c, t - dt_previous)};
    const auto u = bdf_mesh_velocity(x_new, x, x_old, dt, dt_previous);
    EXPECT_LT((u[0] - velocity(b, c, t + dt)).norm(), 1e-11) << dt_previous;
    if (dt_previous != dt) {  // the constant-step formula is not exact there
      EXPECT_GT((bdf_mesh_velocity(x_new, x, x_old, dt, dt)[0] - velocity(b, c, t + dt)).norm(), 1e-3);
    }
  }
}

TEST(MeshVelocity, RejectsLevelsOfDifferentSizes) {
  EXPECT_THROW(bdf_mesh_velocity({Point::Zero()}, {}, {}, 0.1, 0.1), softflow::Error);
}
