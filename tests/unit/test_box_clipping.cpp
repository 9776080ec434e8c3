// The part of a tetrahedron inside a box (analysis/box_clipping): volumes
// and first moments of the pieces against exact values.
#include <random>

#include <gtest/gtest.h>

#include "softflow/analysis/box_clipping.hpp"

namespace {

using softflow::analysis::Box;
using softflow::analysis::clip_to_box;
using softflow::analysis::clip_to_half_space;
using softflow::analysis::Tetrahedron;
using softflow::analysis::tetrahedron_volume;
using Eigen::Vector3d;

/// The unit cube [0, 1]^3 as the six tetrahedra of the Kuhn split
/// (each along a path of unit steps from (0,0,0) to (1,1,1)).
std::vector<Tetrahedron> kuhn_cube(const Vector3d& origin, double h) {
  std::vector<Tetrahedron> tets;
  int order[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (auto& o : order) {
    Vector3d p = origin;
    Tetrahedron t;
    t[0] = p;
    for (int k = 0; k < 3; ++k) {
      p(o[k]) += h;
      t[k + 1] = p;
    }
    tets.push_back(t);
  }
  return tets;
}

/// Integral over the pieces of x_axis (degree-1 exact: the centroid rule).
double first_moment(const std::vector<Tetrahedron>& pieces, int axis) {
  double m = 0.0;
  for (const auto& t : pieces)
    m += tetrahedron_volume(t) * (t[0] + t[1] + t[2] + t[3])(axis) / 4.0;
  return m;
}

TEST(BoxClipping, TetInsideIsKeptAndTetOutsideVanishes) {
  const Tetrahedron t{Vector3d(0.1, 0.1, 0.1), Vector3d(0.4, 0.1, 0.1), Vector3d(0.1, 0.4, 0.1),
                      Vector3d(0.1, 0.1, 0.4)};
  const Box unit{Vector3d::Zero(), Vector3d::Ones()};
  const auto inside = clip_to_box(t, unit);
  ASSERT_EQ(inside.size(), 1u);
  EXPECT_DOUBLE_EQ(tetrahedron_volume(inside[0]), tetrahedron_volume(t));
  const Box away{Vector3d::Constant(2.0), Vector3d::Constant(3.0)};
  EXPECT_TRUE(clip_to_box(t, away).empty());
}

TEST(BoxClipping, EachCaseOfAPlaneCutsTheVolumeExactly) {
  // The reference tetrahedron cut by x <= c, and by -x <= -c (its complement):
  // the two parts tile it, and x <= c keeps (1 - (1 - c)^3) of it (1, 2 or 3
  // vertices inside as c passes 0 ... 1 with other normals below).
  const Tetrahedron t{Vector3d::Zero(), Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
  for (const Vector3d& n : {Vector3d(1, 0, 0), Vector3d(1, 1, 0), Vector3d(1, 1, 1)}) {
    for (double c : {0.2, 0.5, 0.9}) {
      double below = 0.0, above = 0.0;
      for (const auto& p : clip_to_half_space(t, n, c)) below += tetrahedron_volume(p);
      for (const auto& p : clip_to_half_space(t, -n, -c)) above += tetrahedron_volume(p);
      EXPECT_NEAR(below + above, 1.0 / 6.0, 1e-15) << n.transpose() << " c " << c;
    }
  }
  // x + y + z <= c: one vertex inside, the corner tetrahedron c^3 / 6.
  double corner = 0.0;
  for (const auto& p : clip_to_half_space(t, Vector3d(1, 1, 1), 0.3)) corner += tetrahedron_volume(p);
  EXPECT_NEAR(corner, 0.027 / 6.0, 1e-16);
  // x <= c: three vertices inside, 1/6 - (1 - c)^3 / 6.
  double most = 0.0;
  for (const auto& p : clip_to_half_space(t, Vector3d::UnitX(), 0.4)) most += tetrahedron_volume(p);
  EXPECT_NEAR(most, (1.0 - 0.216) / 6.0, 1e-16);
}

TEST(BoxClipping, AMeshOfACubeClippedByABoxGivesItsVolumeAndCentroid) {
  // 4^3 cubes of side 1/4, 384 tetrahedra, and a box that cuts them all ways.
  std::vector<Tetrahedron> mesh;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) {
        auto cube = kuhn_cube(Vector3d(i, j, k) * 0.25, 0.25);
        mesh.insert(mesh.end(), cube.begin(), cube.end());
      }
  const Box box{Vector3d(0.13, 0.31, 0.07), Vector3d(0.71, 0.52, 0.999)};
  std::vector<Tetrahedron> pieces;
  for (const auto& t : mesh) {
    auto p = clip_to_box(t, box);
    pieces.insert(pieces.end(), p.begin(), p.end());
  }
  double volume = 0.0;
  for (const auto& p : pieces) volume += tetrahedron_volume(p);
  EXPECT_NEAR(volume, box.volume(), 1e-14);
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_NEAR(first_moment(pieces, axis), box.volume() * 0.5 * (box.lo(axis) + box.hi(axis)),
                1e-14);
}

TEST(BoxClipping, RandomTetrahedraSplitBetweenABoxAndItsOutsideByEachFace) {
  // For a random tetrahedron and the slab lo_x <= x <= hi_x (the box with the
  // other faces far away), the inside and the two outside parts tile it.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Tetrahedron t;
    for (auto& v : t) v = Vector3d(u(rng), u(rng), u(rng));
    const double lo = -0.3, hi = 0.4;
    const Box slab{Vector3d(lo, -10, -10), Vector3d(hi, 10, 10)};
    double parts = 0.0;
    for (const auto& p : clip_to_box(t, slab)) parts += tetrahedron_volume(p);
    for (const auto& p : clip_to_half_space(t, -Vector3d::UnitX(), -hi)) parts += tetrahedron_volume(p);
    for (const auto& p : clip_to_half_space(t, Vector3d::UnitX(), lo)) parts += tetrahedron_volume(p);
    EXPECT_NEAR(parts, tetrahedron_volume(t), 1e-14 * (1 + tetrahedron_volume(t))) << trial;
  }
}

}  // namespace

TEST(BoxClipping, ReferencePiecesOfAStraightP2TetMapBackOntoItsClippedPart) {
  // A straight P2 tetrahedron (edge nodes at the midpoints) across the
  // faces x, y, z = 0.5 of the box [-1, 0.5]^3: the pieces in reference coordinates,
  // mapped by the element's affine map, have the clipped volume; a tet wholly
  // inside gives the reference tetrahedron, one outside nothing.
  const Tetrahedron v{Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1)};
  auto p2_nodes = [](const Tetrahedron& t) {
    Eigen::Matrix<double, 3, 10> x;
    for (int k = 0; k < 4; ++k) x.col(k) = t[k];
    const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
    for (int e = 0; e < 6; ++e) x.col(4 + e) = (t[edges[e][0]] + t[edges[e][1]]) / 2;
    return x;
  };
  const Box box{Vector3d::Constant(-1.0), Vector3d::Constant(0.5)};
  double reference_volume = 0.0;
  for (const auto& piece : softflow::analysis::reference_pieces_in_box(p2_nodes(v), box))
    reference_volume += tetrahedron_volume(piece);
  double clipped = 0.0;
  for (const auto& piece : clip_to_box(v, box)) clipped += tetrahedron_volume(piece);
  // The reference tetrahedron has volume 1/6, as v: the affine map keeps volumes here.
  EXPECT_NEAR(reference_volume, clipped, 1e-15);
  // The corners beyond x, y, z = 0.5 cut off, each (1/2)^3 / 6.
  EXPECT_NEAR(clipped, 1.0 / 6.0 - 3.0 / 48.0, 1e-15);

  const Box around{Vector3d::Constant(-1.0), Vector3d::Constant(2.0)};
  const auto whole = softflow::analysis::reference_pieces_in_box(p2_nodes(v), around);
  ASSERT_EQ(whole.size(), 1u);
  EXPECT_NEAR(tetrahedron_volume(whole[0]), 1.0 / 6.0, 1e-15);
  const Box away{Vector3d::Constant(5.0), Vector3d::Constant(6.0)};
  EXPECT_TRUE(softflow::analysis::reference_pieces_in_box(p2_nodes(v), away).empty());
}
