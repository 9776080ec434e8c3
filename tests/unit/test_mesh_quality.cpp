// Tetrahedron quality: mean-ratio shape of the vertices times the P2 curving distortion.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/mesh/quality.hpp"
#include "support/verification/structured_box.hpp"

using namespace softflow;
using mesh::Point;

namespace {

// One P2 tetrahedron with straight edges on the given vertices.
mesh::Mesh single_tet(const std::array<Point, 4>& v) {
  mesh::Mesh m;
  for (const auto& x : v) {
    m.nodes.push_back(x);
    m.is_vertex.push_back(1);
  }
  for (const auto& [a, b] : mesh::kTetEdges) {
    m.nodes.push_back(0.5 * (v[a] + v[b]));
    m.is_vertex.push_back(0);
  }
  m.tets.push_back({0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
  m.tet_region.push_back(0);
  return m;
}

const std::array<Point, 4> kRegular{Point(1, 1, 1), Point(-1, 1, -1), Point(1, -1, -1), Point(-1, -1, 1)};

}  // namespace

TEST(MeshQuality, RegularTetrahedronHasQualityOne) {
  const auto m = single_tet(kRegular);
  ASSERT_GT((m.nodes[1] - m.nodes[0]).dot((m.nodes[2] - m.nodes[0]).cross(m.nodes[3] - m.nodes[0])), 0.0);
  EXPECT_NEAR(mesh::tet_quality(m, 0), 1.0, 1e-12);
}

TEST(MeshQuality, InvariantUnderScalingRotationAndTranslation) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Point(1, 2, 3).normalized()).toRotationMatrix();
  std::array<Point, 4> v;
  for (int k = 0; k < 4; ++k) v[k] = 3.5 * (r * kRegular[k]) + Point(10, -2, 5);
  EXPECT_NEAR(mesh::tet_quality(single_tet(v), 0), 1.0, 1e-12);
}

TEST(MeshQuality, KuhnTetrahedronOfAStructuredBox) {
  // Kuhn tetrahedra of a unit cube: V = 1/6, sum of squared edges 1+1+1+2+2+3.
  const double expected = 12.0 * std::cbrt(0.25) / 10.0;
  const auto m = mesh::structured_box({2.0, 2.0, 2.0, true, true}, 2, 2, 2);
  EXPECT_NEAR(mesh::min_quality(m), expected, 1e-12);
  for (int t = 0; t < m.n_tets(); ++t) EXPECT_NEAR(mesh::tet_quality(m, t), expected, 1e-12);
}

TEST(MeshQuality, FlatTetrahedronTendsToZero) {
  auto v = kRegular;
  double previous = 1.0;
  for (double squash : {0.5, 0.1, 0.01, 0.0001}) {
    for (int k = 0; k < 4; ++k) v[k] = Point(kRegular[k].x(), kRegular[k].y(), squash * kRegular[k].z());
    const double q = mesh::tet_quality(single_tet(v), 0);
    EXPECT_GT(q, 0.0);
    EXPECT_LT(q, previous);
    previous = q;
  }
  EXPECT_LT(previous, 0.01);
}

TEST(MeshQuality, CurvingLowersQualityAndFoldingMakesItNonPositive) {
  auto m = single_tet(kRegular);
  const Point mid = m.nodes[4];  // edge (0,1)
  const Point outward = (mid - Point::Zero()).normalized();
  const double edge = (m.nodes[1] - m.nodes[0]).norm();

  m.nodes[4] = mid + 0.05 * edge * outward;
  const double gently = mesh::tet_quality(m, 0);
  EXPECT_GT(gently, 0.0);
  EXPECT_LT(gently, 1.0);

  m.nodes[4] = mid + 0.15 * edge * outward;
  const double strongly = mesh::tet_quality(m, 0);
  EXPECT_LT(strongly, gently);

  // Past a quarter of the edge along it, the edge map x(s) folds back at a vertex.
  m.nodes[4] = mid + 0.4 * (m.nodes[1] - m.nodes[0]);
  EXPECT_LE(mesh::tet_quality(m, 0), 0.0);
}

TEST(MeshQuality, InvertedTetrahedronIsNonPositive) {
  auto v = kRegular;
  std::swap(v[1], v[2]);
  EXPECT_NEAR(mesh::tet_quality(single_tet(v), 0), -1.0, 1e-12);
}

TEST(MeshQuality, WorstTetAndMinQualityOfAMixedMesh) {
  auto m = single_tet(kRegular);
  // A second, squashed tetrahedron sharing nothing with the first.
  auto v = kRegular;
  for (auto& x : v) x = Point(x.x() + 5, x.y(), 0.1 * x.z());
  const auto other = single_tet(v);
  const int offset = m.n_nodes();
  m.nodes.insert(m.nodes.end(), other.nodes.begin(), other.nodes.end());
  m.is_vertex.insert(m.is_vertex.end(), other.is_vertex.begin(), other.is_vertex.end());
  mesh::Tet10 t = other.tets[0];
  for (int& n : t) n += offset;
  m.tets.push_back(t);
  m.tet_region.push_back(0);

  EXPECT_EQ(mesh::worst_tet(m), 1);
  EXPECT_DOUBLE_EQ(mesh::min_quality(m), mesh::tet_quality(m, 1));
  EXPECT_LT(mesh::min_quality(m), 0.5);

  EXPECT_EQ(mesh::worst_tet(mesh::Mesh{}), -1);
  EXPECT_EQ(mesh::min_quality(mesh::Mesh{}), 1.0);
}

TEST(MeshQuality, PositiveQualityMeansPositiveJacobianAtEveryQuadraturePoint) {
  // Randomly curved tetrahedra, up to folding: wherever the quality says
  // "valid", the P2 map's det J is positive at every point of the rule the
  // assemblies integrate with. (Sampling only vertices, edge nodes and the
  // centroid lets some through, the first at trial 340.)
  const auto rule = element::tetrahedron_rule(5);
  std::mt19937 random(12345);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int valid = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    auto m = single_tet(kRegular);
    const double amplitude = 0.5 * (trial % 100) / 100.0;  // of the edge length ~2.8
    for (int k = 4; k < 10; ++k) m.nodes[k] += amplitude * 2.8 * Point(unit(random), unit(random), unit(random));
    if (mesh::tet_quality(m, 0) <= 0.0) continue;
    ++valid;
    element::TetNodes x;
    for (int k = 0; k < 10; ++k) x.col(k) = m.nodes[k];
    for (const auto& p : rule.points)
      ASSERT_GT(element::tet_map(x, element::p2_tet_gradients(p)).det_jacobian, 0.0) << "trial " << trial;
  }
  EXPECT_GT(valid, 5000);
}
