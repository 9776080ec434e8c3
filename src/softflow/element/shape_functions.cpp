#include "softflow/element/shape_functions.hpp"

namespace softflow::element {

namespace {
// Edge vertex pairs, in the order of the edge nodes (see mesh/mesh.hpp).
constexpr int kTetEdge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};
constexpr int kTriEdge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

// Gradients of the barycentric coordinates l0 = 1 - x - y - z, l1 = x, l2 = y, l3 = z.
constexpr double kDl[4][3] = {{-1, -1, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
}  // namespace

std::array<double, 4> p1_tet_values(const Vec3& xi) {
  return {1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]};
}

Eigen::Matrix<double, 4, 3> p1_tet_gradients() {
  Eigen::Matrix<double, 4, 3> g;
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) g(i, d) = kDl[i][d];
  return g;
}

std::array<double, 10> p2_tet_values(const Vec3& xi) {
  const auto l = p1_tet_values(xi);
  std::array<double, 10> n{};
  for (int i = 0; i < 4; ++i) n[i] = l[i] * (2.0 * l[i] - 1.0);
  for (int e = 0; e < 6; ++e) n[4 + e] = 4.0 * l[kTetEdge[e][0]] * l[kTetEdge[e][1]];
  return n;
}

Eigen::Matrix<double, 10, 3> p2_tet_gradients(const Vec3& xi) {
  const auto l = p1_tet_values(xi);
  Eigen::Matrix<double, 10, 3> g;
  for (int i = 0; i < 4; ++i)
    for (int d = 0; d < 3; ++d) g(i, d) = (4.0 * l[i] - 1.0) * kDl[i][d];
  for (int e = 0; e < 6; ++e) {
    const int a = kTetEdge[e][0], b = kTetEdge[e][1];
    for (int d = 0; d < 3; ++d) g(4 + e, d) = 4.0 * (kDl[a][d] * l[b] + l[a] * kDl[b][d]);
  }
  return g;
}

std::array<double, 3> p1_triangle_values(const Vec3& xi) {
  return {1.0 - xi[0] - xi[1], xi[0], xi[1]};
}

std::array<double, 6> p2_triangle_values(const Vec3& xi) {
  const auto l = p1_triangle_values(xi);
  std::array<double, 6> n{};
  for (int i = 0; i < 3; ++i) n[i] = l[i] * (2.0 * l[i] - 1.0);
  for (int e = 0; e < 3; ++e) n[3 + e] = 4.0 * l[kTriEdge[e][0]] * l[kTriEdge[e][1]];
  return n;
}

Eigen::Matrix<double, 6, 2> p2_triangle_gradients(const Vec3& xi) {
  const auto l = p1_triangle_values(xi);
  constexpr double dl[3][2] = {{-1, -1}, {1, 0}, {0, 1}};
  Eigen::Matrix<double, 6, 2> g;
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 2; ++d) g(i, d) = (4.0 * l[i] - 1.0) * dl[i][d];
  for (int e = 0; e < 3; ++e) {
    const int a = kTriEdge[e][0], b = kTriEdge[e][1];
    for (int d = 0; d < 2; ++d) g(3 + e, d) = 4.0 * (dl[a][d] * l[b] + l[a] * dl[b][d]);
  }
  return g;
}

}  // namespace softflow::element
