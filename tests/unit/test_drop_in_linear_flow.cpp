// The exact drop solution itself: Stokes equations, continuity and traction balance at r = 1.
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "softflow/analysis/theory/drop_in_linear_flow.hpp"

using softflow::analysis::theory::DropInLinearFlow;
using Eigen::Matrix3d;
using Eigen::Vector3d;

namespace {

constexpr double kStep = 1e-4;

Matrix3d velocity_gradient(const DropInLinearFlow& s, const Vector3d& x, bool inside) {
  Matrix3d g;  // g(i, j) = du_i / dx_j
  for (int j = 0; j < 3; ++j) {
    Vector3d dx = Vector3d::Zero();
    dx[j] = kStep;
    g.col(j) = (s.velocity(x + dx, inside) - s.velocity(x - dx, inside)) / (2 * kStep);
  }
  return g;
}

Vector3d laplacian(const DropInLinearFlow& s, const Vector3d& x, bool inside) {
  Vector3d lap = Vector3d::Zero();
  const double h = 1e-3;
  for (int j = 0; j < 3; ++j) {
    Vector3d dx = Vector3d::Zero();
    dx[j] = h;
    lap += (s.velocity(x + dx, inside) - 2 * s.velocity(x, inside) + s.velocity(x - dx, inside)) / (h * h);
  }
  return lap;
}

Vector3d pressure_gradient(const DropInLinearFlow& s, const Vector3d& x, bool inside) {
  Vector3d g;
  for (int j = 0; j < 3; ++j) {
    Vector3d dx = Vector3d::Zero();
    dx[j] = kStep;
    g[j] = (s.pressure(x + dx, inside) - s.pressure(x - dx, inside)) / (2 * kStep);
  }
  return g;
}

Matrix3d stress(const DropInLinearFlow& s, const Vector3d& x, bool inside, double viscosity) {
  const Matrix3d g = velocity_gradient(s, x, inside);
  return -s.pressure(x, inside) * Matrix3d::Identity() + viscosity * (g + g.transpose());
}

}  // namespace

using Kind = DropInLinearFlow::Kind;

class DropExactSolution : public ::testing::TestWithParam<double> {};

TEST_P(DropExactSolution, BothFieldsSatisfyStokesAndVelocityContinuity) {
  const double lambda = GetParam();
  for (Kind kind : {Kind::instantaneous, Kind::taylor_quasi_steady}) {
    const auto s = DropInLinearFlow::simple_shear(kind, lambda, 1.0, 0.3);
    for (const Vector3d& x : {Vector3d(0.3, -0.2, 0.4), Vector3d(1.5, 0.7, -0.9), Vector3d(-0.1, 0.5, 0.2)}) {
      const bool inside = x.norm() < 1.0;
      const double eta = inside ? lambda : 1.0;
      EXPECT_NEAR(velocity_gradient(s, x, inside).trace(), 0.0, 1e-8);
      EXPECT_LT((eta * laplacian(s, x, inside) - pressure_gradient(s, x, inside)).norm(), 1e-4);
    }
    const Vector3d n = Vector3d(0.2, -0.6, 0.77).normalized();
    EXPECT_LT((s.velocity(n, true) - s.velocity(n, false)).norm(), 1e-12);
    EXPECT_LT((s.velocity(100 * n, false) - Vector3d(100 * n.y(), 0, 0)).norm(), 1e-3);
  }
}

TEST_P(DropExactSolution, InstantaneousFieldBalancesTractionWithLaplacePressure) {
  const double lambda = GetParam(), tension = 0.3;
  const auto s = DropInLinearFlow::simple_shear(Kind::instantaneous, lambda, 1.0, tension);
  for (const Vector3d& n : {Vector3d(1, 1, 0).normalized(), Vector3d(0.2, -0.6, 0.77).normalized()}) {
    // (sigma_m - sigma_d) n = Gamma (div n) n = 2 Gamma n on the unit sphere.
    const Vector3d jump = (stress(s, n, false, 1.0) - stress(s, n, true, lambda)) * n;
    EXPECT_LT((jump - 2 * tension * n).norm(), 1e-7);
  }
}

TEST_P(DropExactSolution, TaylorFieldHasNoNormalVelocityAndBalancesTangentialTraction) {
  const double lambda = GetParam();
  const auto s = DropInLinearFlow::simple_shear(Kind::taylor_quasi_steady, lambda, 1.0, 0.0);
  const Vector3d w(0, 0, -0.5);  // vorticity of (y, 0, 0): u_rot = w x x
  for (const Vector3d& n : {Vector3d(1, 1, 0).normalized(), Vector3d(0.2, -0.6, 0.77).normalized()}) {
    EXPECT_NEAR((s.velocity(n, true) - w.cross(n)).dot(n), 0.0, 1e-12);
    const Vector3d jump = (stress(s, n, false, 1.0) - stress(s, n, true, lambda)) * n;
    EXPECT_LT((jump - jump.dot(n) * n).norm(), 1e-7);
  }
}

INSTANTIATE_TEST_SUITE_P(ViscosityRatios, DropExactSolution, ::testing::Values(0.5, 1.0, 5.0));
