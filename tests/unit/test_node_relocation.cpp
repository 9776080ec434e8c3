// Node relocation of a moving mesh (mesh::NodeRelocation): restores
// elements spoiled by a moved vertex or a bent edge, never moves a fixed
// node, leaves good meshes alone.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/mesh/mesh.hpp"
#include "softflow/mesh/node_relocation.hpp"
#include "softflow/mesh/quality.hpp"
#include "support/verification/structured_box.hpp"

using namespace softflow;
using mesh::Point;

namespace {

// 4 x 4 x 4 cubes of edge 1, periodic in x and z: walls at y = +-2, the
// nodes at x = +-2 and z = +-2 are periodic copies.
mesh::Mesh box() { return mesh::structured_box({4.0, 4.0, 4.0, true, true}, 4, 4, 4); }

int node_at(const mesh::Mesh& m, const Point& x) {
  for (int i = 0; i < m.n_nodes(); ++i)
    if ((m.nodes[i] - x).norm() < 1e-12) return i;
  return -1;
}

double min_quality(const mesh::Mesh& m, const std::vector<Point>& nodes) {
  double q = 1.0;
  for (const auto& t : m.tets) q = std::min(q, mesh::tet_quality(nodes, t));
  return q;
}

// Moves vertex `v` by `d` and the edge nodes of its edges by d / 2 (edges stay straight).
void push_vertex(const mesh::Mesh& m, std::vector<Point>& nodes, int v, const Point& d) {
  nodes[v] += d;
  std::vector<int> done;
  for (const auto& t : m.tets)
    for (int e = 0; e < 6; ++e)
      for (int end : mesh::kTetEdges[e])
        if (t[end] == v && std::find(done.begin(), done.end(), t[4 + e]) == done.end()) {
          nodes[t[4 + e]] += 0.5 * d;
          done.push_back(t[4 + e]);
        }
}

// Kuhn tetrahedra of a cube: the quality of every element of box().
const double kKuhn = 12.0 * std::cbrt(0.25) / 10.0;

}  // namespace

TEST(NodeRelocation, FixedNodesAreTheWallsAndThePeriodicFaces) {
  const auto m = box();
  const mesh::NodeRelocation relocation(m);
  for (int i = 0; i < m.n_nodes(); ++i) {
    const auto& x = m.nodes[i];
    const bool on_box = std::abs(std::abs(x.x()) - 2.0) < 1e-12 || std::abs(std::abs(x.y()) - 2.0) < 1e-12 ||
                        std::abs(std::abs(x.z()) - 2.0) < 1e-12;
    EXPECT_EQ(relocation.is_free(i), !on_box) << "node " << i << " at " << x.transpose();
  }
}

TEST(NodeRelocation, LeavesAGoodMeshAlone) {
  const auto m = box();
  auto nodes = m.nodes;
  const auto report = mesh::NodeRelocation(m).improve(nodes, 0.9 * kKuhn);
  EXPECT_EQ(report.nodes_moved, 0);
  EXPECT_EQ(nodes, m.nodes);
  EXPECT_EQ(report.smallest_quality, min_quality(m, nodes));  // from the same scan
}

TEST(NodeRelocation, RestoresElementsAroundAPushedVertex) {
  const auto m = box();
  const int v = node_at(m, Point(0, 0, 0));
  ASSERT_GE(v, 0);
  auto nodes = m.nodes;
  push_vertex(m, nodes, v, Point(0.52, -0.47, 0.05));  // almost onto a face of its star
  const double spoiled = min_quality(m, nodes);
  ASSERT_GT(spoiled, 0.0);
  ASSERT_LT(spoiled, 0.1);

  const auto report = mesh::NodeRelocation(m).improve(nodes, 0.5);
  EXPECT_GT(report.nodes_moved, 0);
  EXPECT_NEAR(report.quality_before, spoiled, 1e-12);
  // Back to within 10 % of the cube's own elements, near where it came from.
  EXPECT_GT(report.quality_after, 0.9 * kKuhn);
  EXPECT_GT(min_quality(m, nodes), 0.9 * kKuhn);
  EXPECT_LT(nodes[v].norm(), 0.1);
  // Kept up to date through the moves (only the moved nodes' elements rescanned).
  EXPECT_EQ(report.smallest_quality, min_quality(m, nodes));
}

TEST(NodeRelocation, UnbendsAFoldedEdge) {
  // The P2 map folds near a vertex when an edge node is pushed along its
  // edge towards it: the vertex shape stays perfect, det J does not.
  const auto m = box();
  const int a = node_at(m, Point(0, 0, 0)), b = node_at(m, Point(1, 0, 0));
  const int mid = node_at(m, Point(0.5, 0, 0));
  ASSERT_GE(a, 0);
  ASSERT_GE(b, 0);
  ASSERT_GE(mid, 0);
  auto nodes = m.nodes;
  nodes[mid] = Point(0.27, 0.08, 0.0);
  const double spoiled = min_quality(m, nodes);
  ASSERT_LT(spoiled, 0.1);

  const auto report = mesh::NodeRelocation(m).improve(nodes, 0.5);
  EXPECT_GT(report.nodes_moved, 0);
  // Quality is flat near its optimum: the node need not return to the
  // midpoint exactly for the elements to be within 10 % of the cube's.
  EXPECT_GT(min_quality(m, nodes), 0.9 * kKuhn);
  EXPECT_LT((nodes[mid] - Point(0.5, 0, 0)).norm(), 0.2);
  EXPECT_EQ(report.smallest_quality, min_quality(m, nodes));
}

TEST(NodeRelocation, NeverMovesInterfaceNodes) {
  // The pushed vertex and its whole neighbourhood's faces declared an
  // interface: nothing there may move, the elements stay as bad as they
  // are unless other free nodes can help, and no fixed node moves.
  auto m = box();
  const int v = node_at(m, Point(0, 0, 0));
  for (const auto& t : m.tets)
    if (std::find(t.begin(), t.begin() + 4, v) != t.begin() + 4)
      for (int f = 0; f < 4; ++f) {
        // Face opposite vertex f, as a 6-node triangle.
        std::array<int, 3> corner;
        int c = 0;
        for (int k = 0; k < 4; ++k)
          if (k != f) corner[c++] = k;
        mesh::Triangle6 tri{t[corner[0]], t[corner[1]], t[corner[2]], 0, 0, 0};
        for (int e = 0; e < 3; ++e) {
          const int p = corner[mesh::kTriangleEdges[e][0]], q = corner[mesh::kTriangleEdges[e][1]];
          for (int k = 0; k < 6; ++k)
            if ((mesh::kTetEdges[k][0] == p && mesh::kTetEdges[k][1] == q) ||
                (mesh::kTetEdges[k][0] == q && mesh::kTetEdges[k][1] == p))
              tri[3 + e] = t[4 + k];
        }
        m.interface_faces.push_back(tri);
        m.interface_object.push_back(1);
      }
  const mesh::NodeRelocation relocation(m);
  EXPECT_FALSE(relocation.is_free(v));
  auto nodes = m.nodes;
  push_vertex(m, nodes, v, Point(0.52, -0.47, 0.05));
  const auto before = nodes;
  relocation.improve(nodes, 0.5);
  for (int i = 0; i < m.n_nodes(); ++i)
    if (!relocation.is_free(i)) EXPECT_EQ(nodes[i], before[i]) << "fixed node " << i << " moved";
  EXPECT_EQ(nodes[v], before[v]);
}

TEST(NodeRelocation, IsDeterministic) {
  const auto m = box();
  const int v = node_at(m, Point(0, 0, 0));
  auto first = m.nodes;
  push_vertex(m, first, v, Point(0.52, -0.47, 0.05));
  auto second = first;
  const mesh::NodeRelocation relocation(m);
  relocation.improve(first, 0.5);
  relocation.improve(second, 0.5);
  EXPECT_EQ(first, second);
}
