// Operators on the curved P2 interface: the Laplace-Beltrami stiffness of the
// semi-implicit tension and the nodal normals it projects on.
#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {
// The unit-sphere octant x, y, z >= 0 as n^2 curved P2 triangles, nodes on the sphere.
physics::InterfaceMesh octant(int n, std::vector<Vector3d>& x) {
  physics::InterfaceMesh s;
  // Nodes on the half lattice (i, j), i + j <= 2n, numbered row by row.
  std::vector<std::vector<int>> index(2 * n + 1, std::vector<int>(2 * n + 1, -1));
  x.clear();
  for (int i = 0; i <= 2 * n; ++i)
    for (int j = 0; i + j <= 2 * n; ++j) {
      index[i][j] = static_cast<int>(x.size());
      x.push_back(Vector3d(i, j, 2 * n - i - j).normalized());
    }
  s.volume_node.resize(x.size());
  auto add = [&](int ai, int aj, int bi, int bj, int ci, int cj) {  // corners, lattice units
    const int c[3][2] = {{2 * ai, 2 * aj}, {2 * bi, 2 * bj}, {2 * ci, 2 * cj}};
    std::array<int, 6> t;
    for (int v = 0; v < 3; ++v) t[v] = index[c[v][0]][c[v][1]];
    for (int e = 0; e < 3; ++e) {
      const auto& p = c[mesh::kTriangleEdges[e][0]];
      const auto& q = c[mesh::kTriangleEdges[e][1]];
      t[3 + e] = index[(p[0] + q[0]) / 2][(p[1] + q[1]) / 2];
    }
    s.triangles.push_back(t);
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      add(i, j, i + 1, j, i, j + 1);
      if (i + j + 1 < n) add(i + 1, j, i + 1, j + 1, i, j + 1);
    }
  return s;
}

element::TriangleNodes sphere_triangle() {
  const Vector3d v[3] = {Vector3d(1, 0.2, 0.1).normalized(), Vector3d(0.3, 1, 0).normalized(),
                         Vector3d(0.1, 0.2, 1).normalized()};
  element::TriangleNodes x;
  for (int i = 0; i < 3; ++i) x.col(i) = v[i];
  for (int e = 0; e < 3; ++e)
    x.col(3 + e) = (v[mesh::kTriangleEdges[e][0]] + v[mesh::kTriangleEdges[e][1]]).normalized();
  return x;
}
}  // namespace

TEST(SurfaceStiffness, IsSymmetricPositiveSemidefiniteWithConstantsInItsKernel) {
  const auto s = physics::surface_stiffness(sphere_triangle());
  EXPECT_LT((s - s.transpose()).norm(), 1e-14 * s.norm());
  EXPECT_LT((s * Eigen::Matrix<double, 6, 1>::Ones()).norm(), 1e-12 * s.norm());
  Eigen::SelfAdjointEigenSolver<physics::TriangleStiffness> eig(s);
  EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * s.norm());
  EXPECT_GT(eig.eigenvalues()(1), 1e-3 * s.norm());  // only the constants are in the kernel
}

TEST(SurfaceStiffness, AppliedToThePositionGivesTheTensionLoad) {
  // grad_s x = I - n n on the isoparametric surface, so sum_b S_ab x_b =
  // int grad_s N_a ds = -(tension load of node a) / Gamma, to round-off.
  const auto x = sphere_triangle();
  const auto s = physics::surface_stiffness(x);
  physics::TriangleVelocityVector load = physics::TriangleVelocityVector::Zero();
  const double gamma = 2.5;
  physics::add_surface_tension(x, gamma, load);
  for (int a = 0; a < 6; ++a) {
    Vector3d sx = Vector3d::Zero();
    for (int b = 0; b < 6; ++b) sx += s(a, b) * x.col(b);
    EXPECT_LT((sx + load.segment<3>(3 * a) / gamma).norm(), 1e-13) << "node " << a;
  }
}

TEST(NodeNormals, ConvergeToTheSphereNormalAtSecondOrder) {
  auto error = [](int n) {
    std::vector<Vector3d> x;
    const auto s = octant(n, x);
    const auto normals = physics::node_normals(s, x);
    double worst = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      EXPECT_NEAR(normals[i].norm(), 1.0, 1e-14);
      worst = std::max(worst, (normals[i] - x[i]).norm());
    }
    return worst;
  };
  const double e4 = error(4), e8 = error(8);
  std::printf("max nodal normal error: %.3e (n = 4), %.3e (n = 8)\n", e4, e8);
  EXPECT_GT(e4 / e8, 3.0);
}
