#include "softflow/element/isoparametric.hpp"

namespace softflow::element {

SurfacePoint surface_point(const TriangleNodes& x, const Vec3& xi) {
  const auto n = p2_triangle_values(xi);
  const Eigen::Matrix<double, 6, 2> dn = p2_triangle_gradients(xi);
  SurfacePoint s;
  s.position = x * Eigen::Map<const Eigen::Matrix<double, 6, 1>>(n.data());
  const Eigen::Matrix<double, 3, 2> tangents = x * dn;  // covariant a_1, a_2
  const Vec3 cross = tangents.col(0).cross(tangents.col(1));
  s.area_scale = cross.norm();
  s.normal = cross / s.area_scale;
  // Dual basis a^a = g^{ab} a_b with the metric g_ab = a_a . a_b.
  const Eigen::Matrix2d metric = tangents.transpose() * tangents;
  const Eigen::Matrix<double, 3, 2> dual = tangents * metric.inverse();
  s.surface_gradients = dn * dual.transpose();
  return s;
}

}  // namespace softflow::element
