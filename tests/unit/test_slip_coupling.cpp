// The pieces of the symmetric slip coupling (physics/stokes/interface_slip.hpp):
// the discrete traction, the coupling matrix of one triangle, the checks.
#include <array>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"

namespace softflow::physics {
namespace {

using Eigen::Vector3d;

/// A curved P2 triangle on the unit sphere and its radial nodal normals.
element::TriangleNodes sphere_triangle() {
  const Vector3d v[3] = {Vector3d(1, 0.2, 0.1).normalized(), Vector3d(0.3, 1, 0).normalized(),
                         Vector3d(0.1, 0.2, 1).normalized()};
  element::TriangleNodes x;
  for (int i = 0; i < 3; ++i) x.col(i) = v[i];
  for (int e = 0; e < 3; ++e)
    x.col(3 + e) = (v[mesh::kTriangleEdges[e][0]] + v[mesh::kTriangleEdges[e][1]]).normalized();
  return x;
}

TriangleNormals radial(const element::TriangleNodes& x) {
  TriangleNormals n;
  for (int a = 0; a < 6; ++a) n[a] = x.col(a).normalized();
  return n;
}

TEST(SlipTraction, NormalPartFollowsTheSurfaceTangentialPartTheNodes) {
  const auto x = sphere_triangle();
  const auto nodal = radial(x);
  const Vector3d xi(0.2, 0.3, 0.0);
  const auto p = element::surface_point(x, xi);
  const auto shape = element::p2_triangle_values(xi);
  // Purely normal multipliers mu n_a: the traction is mu n at the point,
  // exactly (the shape functions sum to one), whatever n_a.
  Eigen::Matrix<double, 3, 6> lambda;
  for (int a = 0; a < 6; ++a) lambda.col(a) = 2.5 * nodal[a];
  EXPECT_LT((slip_traction(shape, p.normal, nodal, lambda) - 2.5 * p.normal).norm(), 1e-14);
  // Tangential multipliers: the P2 interpolant of their tangential parts.
  Vector3d expected = Vector3d::Zero();
  for (int a = 0; a < 6; ++a) {
    const Vector3d t = Vector3d(1, -2, 0.5).cross(nodal[a]);  // tangent at node a
    lambda.col(a) = t;
    expected += shape[a] * t;
  }
  EXPECT_LT((slip_traction(shape, p.normal, nodal, lambda) - expected).norm(), 1e-14);
}

TEST(SlipCouplingMatrix, OnAFlatTriangleItIsTheSurfaceMassPerComponent) {
  element::TriangleNodes x;
  x << 0, 2, 0, 1, 1, 0,  //
      0, 0, 1, 0, 0.5, 0.5,  //
      0, 0, 0, 0, 0, 0;
  TriangleNormals nodal;
  nodal.fill(Vector3d(0, 0, 1));
  const auto c = slip_coupling_matrix(x, nodal);
  const auto m = surface_mass(x);
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b)
      EXPECT_LT((c.block<3, 3>(3 * b, 3 * a) - m(b, a) * Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

TEST(SlipCouplingMatrix, GivesTheIntegralOfTheTractionAgainstAVelocity) {
  // v^T C lambda = integral lambda_h . v_h, computed here point by point.
  const auto x = sphere_triangle();
  const auto nodal = radial(x);
  Eigen::Matrix<double, 18, 1> v, lambda;
  for (int k = 0; k < 18; ++k) {
    v(k) = 0.3 + 0.1 * k - 0.01 * k * k;
    lambda(k) = 1.0 - 0.07 * k;
  }
  const Eigen::Map<const Eigen::Matrix<double, 3, 6>> l(lambda.data()), vv(v.data());
  const auto rule = element::triangle_rule(5);
  double integral = 0.0;
  for (int q = 0; q < rule.size(); ++q) {
    const auto p = element::surface_point(x, rule.points[q]);
    const auto shape = element::p2_triangle_values(rule.points[q]);
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> n(shape.data());
    integral += rule.weights[q] * p.area_scale *
                slip_traction(shape, p.normal, nodal, l).dot(vv * n);
  }
  EXPECT_NEAR(v.dot(slip_coupling_matrix(x, nodal) * lambda), integral, 1e-13);
}

TEST(SlipChecks, NegativeDissipationBeyondRoundOffOnly) {
  SlipMeasures m;
  m.absolute_power = 2.0;
  m.dissipation = 1e-3;
  EXPECT_FALSE(dissipation_is_negative(m));
  m.dissipation = -1e-12;  // round-off of a free-slip interface
  EXPECT_FALSE(dissipation_is_negative(m));
  m.dissipation = -1e-6;
  EXPECT_TRUE(dissipation_is_negative(m));
}

TEST(SlipChecks, LargestResolvedSlipGrowsAsTheFourthPowerOfTheEquatorNodes) {
  EXPECT_DOUBLE_EQ(largest_resolved_slip(16), 100.0);
  EXPECT_DOUBLE_EQ(largest_resolved_slip(32), 1600.0);
  EXPECT_DOUBLE_EQ(largest_resolved_slip(8), 6.25);
}

}  // namespace
}  // namespace softflow::physics
