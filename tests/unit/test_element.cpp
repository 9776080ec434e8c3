// Reference-element pieces: quadrature exactness, shape functions, isoparametric maps.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/mesh/mesh.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {
double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }
// Exact integral of x^a y^b z^c over the reference tetrahedron: a! b! c! / (a+b+c+3)!.
double tet_monomial(int a, int b, int c) {
  return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
}
double triangle_monomial(int a, int b) { return factorial(a) * factorial(b) / factorial(a + b + 2); }

const Vector3d kTetNodes[10] = {{0, 0, 0},     {1, 0, 0},   {0, 1, 0},     {0, 0, 1},
                                {0.5, 0, 0},   {0.5, 0.5, 0}, {0, 0.5, 0}, {0, 0, 0.5},
                                {0.5, 0, 0.5}, {0, 0.5, 0.5}};
}  // namespace

class TetRule : public ::testing::TestWithParam<int> {};

TEST_P(TetRule, IntegratesMonomialsExactlyUpToItsDegree) {
  const int degree = GetParam();
  const auto rule = element::tetrahedron_rule(degree);
  EXPECT_GE(rule.degree, degree);
  for (double w : rule.weights) EXPECT_GT(w, 0.0);
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; a + b <= degree; ++b)
      for (int c = 0; a + b + c <= degree; ++c) {
        double sum = 0;
        for (int q = 0; q < rule.size(); ++q) {
          const auto& p = rule.points[q];
          sum += rule.weights[q] * std::pow(p[0], a) * std::pow(p[1], b) * std::pow(p[2], c);
        }
        EXPECT_NEAR(sum, tet_monomial(a, b, c), 1e-14) << a << " " << b << " " << c;
      }
}
INSTANTIATE_TEST_SUITE_P(Degrees, TetRule, ::testing::Values(2, 4, 5, 6, 8));

class TriangleRule : public ::testing::TestWithParam<int> {};

TEST_P(TriangleRule, IntegratesMonomialsExactlyUpToItsDegree) {
  const int degree = GetParam();
  const auto rule = element::triangle_rule(degree);
  for (double w : rule.weights) EXPECT_GT(w, 0.0);
  for (int a = 0; a <= degree; ++a)
    for (int b = 0; a + b <= degree; ++b) {
      double sum = 0;
      for (int q = 0; q < rule.size(); ++q)
        sum += rule.weights[q] * std::pow(rule.points[q][0], a) * std::pow(rule.points[q][1], b);
      EXPECT_NEAR(sum, triangle_monomial(a, b), 1e-14) << a << " " << b;
    }
}
INSTANTIATE_TEST_SUITE_P(Degrees, TriangleRule, ::testing::Values(2, 5, 7, 9));

TEST(ShapeFunctions, P2TetIsNodalAndMatchesMeshEdgeOrder) {
  for (int i = 0; i < 10; ++i) {
    const auto n = element::p2_tet_values(kTetNodes[i]);
    for (int j = 0; j < 10; ++j) EXPECT_NEAR(n[j], i == j ? 1.0 : 0.0, 1e-15);
  }
  // The edge nodes above are the midpoints of mesh::kTetEdges.
  for (int e = 0; e < 6; ++e) {
    const Vector3d mid =
        0.5 * (kTetNodes[mesh::kTetEdges[e][0]] + kTetNodes[mesh::kTetEdges[e][1]]);
    EXPECT_LT((mid - kTetNodes[4 + e]).norm(), 1e-15);
  }
}

TEST(ShapeFunctions, P2TetGradientsMatchFiniteDifferences) {
  const Vector3d xi(0.2, 0.3, 0.15);
  const auto g = element::p2_tet_gradients(xi);
  const double h = 1e-6;
  for (int d = 0; d < 3; ++d) {
    Vector3d xp = xi, xm = xi;
    xp[d] += h;
    xm[d] -= h;
    const auto np = element::p2_tet_values(xp), nm = element::p2_tet_values(xm);
    for (int k = 0; k < 10; ++k) EXPECT_NEAR(g(k, d), (np[k] - nm[k]) / (2 * h), 1e-8);
  }
  // Partition of unity: gradients sum to zero.
  EXPECT_LT(g.colwise().sum().norm(), 1e-13);
}

TEST(ShapeFunctions, P2TriangleIsNodal) {
  const Vector3d nodes[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}, {0, 0.5, 0}};
  for (int i = 0; i < 6; ++i) {
    const auto n = element::p2_triangle_values(nodes[i]);
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(n[j], i == j ? 1.0 : 0.0, 1e-15);
  }
}

TEST(Isoparametric, AffineMapHasConstantJacobianAndExactGradients) {
  Eigen::Matrix3d a;
  a << 2, 0.3, 0.1, 0.2, 1.5, -0.4, 0.0, 0.5, 1.2;
  const Vector3d shift(1, -2, 0.5);
  element::TetNodes x;
  for (int k = 0; k < 10; ++k) x.col(k) = a * kTetNodes[k] + shift;
  const Vector3d xi(0.1, 0.2, 0.3);
  const auto m = element::tet_map(x, element::p2_tet_gradients(xi));
  EXPECT_LT((m.jacobian - a).norm(), 1e-13);
  EXPECT_NEAR(m.det_jacobian, a.determinant(), 1e-13);
  // The gradient of the interpolant of a linear function is exact.
  const Vector3d c(0.7, -1.1, 2.3);
  Eigen::Matrix<double, 10, 1> values;
  for (int k = 0; k < 10; ++k) values(k) = c.dot(x.col(k));
  const auto g = element::physical_gradients<10>(element::p2_tet_gradients(xi), m);
  EXPECT_LT((g.transpose() * values - c).norm(), 1e-12);
}

TEST(Isoparametric, SurfaceGeometryOfACurvedTriangleOnTheUnitSphere) {
  // A P2 triangle whose 6 nodes lie on the unit sphere: normal ~ position,
  // surface gradient of the interpolated position is ~ I - n n.
  const Vector3d v[3] = {Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1)};
  element::TriangleNodes x;
  for (int i = 0; i < 3; ++i) x.col(i) = v[i];
  for (int e = 0; e < 3; ++e)
    x.col(3 + e) = (v[mesh::kTriangleEdges[e][0]] + v[mesh::kTriangleEdges[e][1]]).normalized();
  const auto s = element::surface_point(x, Vector3d(1.0 / 3, 1.0 / 3, 0));
  EXPECT_GT(s.normal.dot(s.position.normalized()), 0.999);
  const Eigen::Matrix3d grad_s_x = x * s.surface_gradients;  // sum_k x_k (grad_s N_k)^T
  const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - s.normal * s.normal.transpose();
  EXPECT_LT((grad_s_x - projector).norm(), 1e-12);
  // Surface gradients are tangential.
  EXPECT_LT((s.surface_gradients * s.normal).norm(), 1e-12);
}

namespace {
// Area of the unit-sphere octant meshed by n^2 curved P2 triangles (nodes projected onto the sphere).
double octant_area(int n) {
  auto node = [&](double i, double j) {
    const double k = n - i - j;
    return Vector3d(i / n, j / n, k / n).normalized();
  };
  const auto rule = element::triangle_rule(8);
  double area = 0;
  auto add = [&](Vector3d a, Vector3d b, Vector3d c) {  // corners in (i, j) lattice units
    element::TriangleNodes x;
    const Vector3d corners[3] = {a, b, c};
    for (int v = 0; v < 3; ++v) x.col(v) = node(corners[v][0], corners[v][1]);
    for (int e = 0; e < 3; ++e) {
      const Vector3d m = 0.5 * (corners[mesh::kTriangleEdges[e][0]] + corners[mesh::kTriangleEdges[e][1]]);
      x.col(3 + e) = node(m[0], m[1]);
    }
    for (int q = 0; q < rule.size(); ++q)
      area += rule.weights[q] * element::surface_point(x, rule.points[q]).area_scale;
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      add(Vector3d(i, j, 0), Vector3d(i + 1, j, 0), Vector3d(i, j + 1, 0));
      if (i + j + 1 < n) add(Vector3d(i + 1, j, 0), Vector3d(i + 1, j + 1, 0), Vector3d(i, j + 1, 0));
    }
  return area;
}
}  // namespace

TEST(Isoparametric, CurvedSurfaceAreaConvergesAtLeastCubically) {
  // P2 isoparametric surfaces approximate the sphere to O(h^3) in position;
  // the area error must fall by at least 2^3 per halving of h.
  const double e1 = std::abs(octant_area(4) - M_PI / 2);
  const double e2 = std::abs(octant_area(8) - M_PI / 2);
  const double e3 = std::abs(octant_area(16) - M_PI / 2);
  EXPECT_GT(e1 / e2, 8.0);
  EXPECT_GT(e2 / e3, 8.0);
  EXPECT_LT(e3, 1e-4);
}
