#include "softflow/analysis/box_clipping.hpp"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace softflow::analysis {

using Eigen::Vector3d;

Box centred_cube(double side) {
  const Vector3d h = Vector3d::Constant(side / 2.0);
  return {-h, h};
}

double tetrahedron_volume(const Tetrahedron& t) {
  return std::abs((t[1] - t[0]).dot((t[2] - t[0]).cross(t[3] - t[0]))) / 6.0;
}

namespace {

/// The three tetrahedra of the prism with triangles (a, b, c) and (a2, b2, c2),
/// a-a2, b-b2, c-c2 its lateral edges: a valid split of any such prism,
/// whichever way its quadrilateral faces are cut.
void add_prism(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& a2,
               const Vector3d& b2, const Vector3d& c2, std::vector<Tetrahedron>& out) {
  out.push_back({a, b, c, a2});
  out.push_back({b, c, a2, b2});
  out.push_back({c, a2, b2, c2});
}

}  // namespace

std::vector<Tetrahedron> clip_to_half_space(const Tetrahedron& tet, const Vector3d& n, double c) {
  std::array<double, 4> s{};  // signed distance, <= 0 inside
  std::array<int, 4> in{}, out{};
  int n_in = 0, n_out = 0;
  for (int k = 0; k < 4; ++k) {
    s[k] = n.dot(tet[k]) - c;
    if (s[k] <= 0.0) in[n_in++] = k;
    else out[n_out++] = k;
  }
  if (n_out == 0) return {tet};
  if (n_in == 0) return {};
  // The point where edge (i, o) crosses the plane, i inside, o outside: s[o] > 0 >= s[i],
  // so the denominator is positive and the point lies on the edge.
  const auto cross = [&](int i, int o) {
    const double t = s[i] / (s[i] - s[o]);
    return Vector3d(tet[i] + t * (tet[o] - tet[i]));
  };
  std::vector<Tetrahedron> pieces;
  if (n_in == 1) {
    const int i = in[0];
    pieces.push_back({tet[i], cross(i, out[0]), cross(i, out[1]), cross(i, out[2])});
  } else if (n_in == 3) {
    // The tet less the corner at o: the prism between the inside face and the cut.
    const int o = out[0];
    add_prism(tet[in[0]], tet[in[1]], tet[in[2]], cross(in[0], o), cross(in[1], o),
              cross(in[2], o), pieces);
  } else {
    // Two inside (i, j), two outside (k, l): the wedge with triangles
    // (i, x_ik, x_il) and (j, x_jk, x_jl).
    const int i = in[0], j = in[1], k = out[0], l = out[1];
    add_prism(tet[i], cross(i, k), cross(i, l), tet[j], cross(j, k), cross(j, l), pieces);
  }
  return pieces;
}

std::vector<Tetrahedron> clip_to_box(const Tetrahedron& tet, const Box& box) {
  std::vector<Tetrahedron> pieces{tet};
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      // x_axis <= hi  and  -x_axis <= -lo
      const Vector3d n = sign * Vector3d::Unit(axis);
      const double c = sign > 0 ? box.hi(axis) : -box.lo(axis);
      std::vector<Tetrahedron> next;
      for (const auto& p : pieces) {
        auto clipped = clip_to_half_space(p, n, c);
        next.insert(next.end(), clipped.begin(), clipped.end());
      }
      pieces = std::move(next);
      if (pieces.empty()) return pieces;
    }
  }
  return pieces;
}

Tetrahedron reference_tetrahedron() {
  return {Vector3d::Zero(), Vector3d::UnitX(), Vector3d::UnitY(), Vector3d::UnitZ()};
}

std::vector<Tetrahedron> reference_pieces_in_box(const Eigen::Matrix<double, 3, 10>& x, const Box& box) {
  bool all_in = true;
  for (int k = 0; k < 10; ++k) all_in = all_in && box.contains(x.col(k));
  if (all_in) return {reference_tetrahedron()};
  const Vector3d lo = x.rowwise().minCoeff(), hi = x.rowwise().maxCoeff();
  if (!((hi.array() >= box.lo.array()).all() && (lo.array() <= box.hi.array()).all())) return {};
  const Tetrahedron vertices{x.col(0), x.col(1), x.col(2), x.col(3)};
  // xi = A^{-1} (x - v_0), A's columns the edges from v_0: factored once per element.
  Eigen::Matrix3d a;
  a << vertices[1] - vertices[0], vertices[2] - vertices[0], vertices[3] - vertices[0];
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu = a.partialPivLu();
  std::vector<Tetrahedron> pieces;
  for (const auto& piece : clip_to_box(vertices, box)) {
    Tetrahedron reference;
    for (int k = 0; k < 4; ++k) reference[k] = lu.solve(piece[k] - vertices[0]);
    pieces.push_back(reference);
  }
  return pieces;
}

}  // namespace softflow::analysis
