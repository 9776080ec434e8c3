#include "softflow/mesh/quality.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <fmt/format.h>

namespace softflow::mesh {

namespace {

using RefGradients = Eigen::Matrix<double, 10, 3>;

// Gradients of the barycentric coordinates l0 = 1 - x - y - z, l1 = x,
// l2 = y, l3 = z on the reference tetrahedron (0,0,0) (1,0,0) (0,1,0) (0,0,1).
constexpr double kDl[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// Reference gradients of the 10 P2 functions (vertex l_i (2 l_i - 1), edge
// 4 l_a l_b, edges in kTetEdges order) at barycentric point l. Kept local so
// that mesh/ does not depend on element/.
RefGradients p2_gradients(const std::array<double, 4>& l) {
  RefGradients g;
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) g(i, d) = (4.0 * l[i] - 1.0) * kDl[i][d];
  for (int e = 0; e < 6; ++e) {
    const auto [a, b] = kTetEdges[e];
    for (int d = 0; d < 3; ++d) g(4 + e, d) = 4.0 * (kDl[a][d] * l[b] + l[a] * kDl[b][d]);
  }
  return g;
}

// The 25 sample points, tabulated once: the vertices, edge midpoints and
// centroid (where a P2 map folds first in practice) and the 14 points of the
// degree-5 rule every assembly integrates with (element/quadrature.cpp's
// symmetric orbits; mesh/ sits below element/, so they are repeated here).
// A positive quality then guarantees det J > 0 where the assemblies look:
// with the first 11 alone, a relocated particle mesh at quality 0.04 had
// det J < 0 at a quadrature point, and the mesh-motion operator refused it.
constexpr int kSamples = 25;
const std::array<RefGradients, kSamples>& sample_gradients() {
  static const std::array<RefGradients, kSamples> table = [] {
    std::array<RefGradients, kSamples> t;
    for (int v = 0; v < 4; ++v) {
      std::array<double, 4> l{};
      l[v] = 1.0;
      t[v] = p2_gradients(l);
    }
    for (int e = 0; e < 6; ++e) {
      std::array<double, 4> l{};
      l[kTetEdges[e][0]] = l[kTetEdges[e][1]] = 0.5;
      t[4 + e] = p2_gradients(l);
    }
    t[10] = p2_gradients({0.25, 0.25, 0.25, 0.25});
    int k = 11;
    for (const double a : {0.0927352503108912264, 0.3108859192633006097}) {
      const double b = 1.0 - 3.0 * a;
      for (int v = 0; v < 4; ++v) {
        std::array<double, 4> l{a, a, a, a};
        l[v] = b;
        t[k++] = p2_gradients(l);
      }
    }
    const double a = 0.0455037041256496494, b = 0.5 - a;
    for (const auto& [i, j] : kTetEdges) {  // the 6 ways to put b on two coordinates
      std::array<double, 4> l{a, a, a, a};
      l[i] = l[j] = b;
      t[k++] = p2_gradients(l);
    }
    return t;
  }();
  return table;
}

double straight_shape(std::span<const Point> nodes, const Tet10& t) {
  const Point& x0 = nodes[t[0]];
  const Point e1 = nodes[t[1]] - x0, e2 = nodes[t[2]] - x0, e3 = nodes[t[3]] - x0;
  const double volume = std::abs(e1.dot(e2.cross(e3))) / 6.0;
  double edges2 = 0.0;
  for (const auto& [a, b] : kTetEdges) edges2 += (nodes[t[a]] - nodes[t[b]]).squaredNorm();
  if (edges2 <= 0.0) return 0.0;
  return 12.0 * std::cbrt(3.0 * volume * 3.0 * volume) / edges2;
}

}  // namespace

double tet_quality(const Mesh& mesh, int tet) { return tet_quality(mesh.nodes, mesh.tets[tet]); }

double tet_quality(std::span<const Point> nodes, const Tet10& t) {
  Eigen::Matrix<double, 3, 10> x;
  for (int k = 0; k < 10; ++k) x.col(k) = nodes[t[k]];
  double det_min = INFINITY, det_max = -INFINITY, abs_max = 0.0;
  for (const auto& g : sample_gradients()) {
    const double det = (x * g).determinant();
    det_min = std::min(det_min, det);
    det_max = std::max(det_max, det);
    abs_max = std::max(abs_max, std::abs(det));
  }
  if (det_min <= 0.0) return abs_max > 0.0 ? det_min / abs_max : 0.0;
  return straight_shape(nodes, t) * det_min / det_max;
}

int worst_tet(const Mesh& mesh) {
  int worst = -1;
  double q_worst = INFINITY;
  for (int k = 0; k < mesh.n_tets(); ++k) {
    const double q = tet_quality(mesh, k);
    if (q < q_worst) {
      q_worst = q;
      worst = k;
    }
  }
  return worst;
}

double min_quality(const Mesh& mesh) {
  const int k = worst_tet(mesh);
  return k < 0 ? 1.0 : tet_quality(mesh, k);
}

std::string describe_element(const Mesh& mesh, int tet) {
  const auto& x = mesh.nodes[mesh.tets[tet][0]];
  return fmt::format("element {} (region {}, near ({:.3f}, {:.3f}, {:.3f}))", tet,
                     mesh.tet_region[tet], x.x(), x.y(), x.z());
}

double triangle_shape(const Point& a, const Point& b, const Point& c) {
  const double edges2 = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  if (!(edges2 > 0.0)) return 0.0;
  return 2.0 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / edges2;
}

double min_interface_shape(const Mesh& mesh) {
  double worst = 1.0;
  for (const auto& f : mesh.interface_faces)
    worst = std::min(worst, triangle_shape(mesh.nodes[f[0]], mesh.nodes[f[1]], mesh.nodes[f[2]]));
  return worst;
}

}  // namespace softflow::mesh
