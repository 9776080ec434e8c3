// Isoparametric P2 maps: volume Jacobians and curved-surface geometry.
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "softflow/element/shape_functions.hpp"

namespace softflow::element {

using Mat3 = Eigen::Matrix3d;

/// The 10 geometry nodes of a tetrahedron, one per column.
using TetNodes = Eigen::Matrix<double, 3, 10>;
/// The 6 geometry nodes of a triangle, one per column.
using TriangleNodes = Eigen::Matrix<double, 3, 6>;

/// The P2 map x(xi) = sum_k x_k N_k(xi) evaluated at one reference point.
struct TetMapPoint {
  Mat3 jacobian;            ///< J_ij = dx_i / dxi_j
  double det_jacobian = 0;  ///< volume scale; negative means an inverted element
  Mat3 inverse_jacobian;
};

/// Jacobian of the P2 map from reference gradients (10 x 3) at one point.
inline TetMapPoint tet_map(const TetNodes& x, const Eigen::Matrix<double, 10, 3>& ref_grad) {
  TetMapPoint m;
  m.jacobian = x * ref_grad;
  m.det_jacobian = m.jacobian.determinant();
  m.inverse_jacobian = m.jacobian.inverse();
  return m;
}

/// Physical gradients (one row per function) from reference gradients:
/// grad N = J^{-T} grad_xi N, i.e. rows multiplied by J^{-1}.
template <int n>
Eigen::Matrix<double, n, 3> physical_gradients(const Eigen::Matrix<double, n, 3>& ref_grad,
                                               const TetMapPoint& m) {
  return ref_grad * m.inverse_jacobian;
}

/// Geometry of a curved P2 triangle at one reference point.
struct SurfacePoint {
  Vec3 position;
  Vec3 normal;          ///< unit, along (dx/dxi0) x (dx/dxi1)
  double area_scale = 0;  ///< |dx/dxi0 x dx/dxi1|
  /// Surface gradients of the 6 P2 triangle functions, one per row:
  /// grad_s N = sum_a a^a dN/dxi_a with a^a the dual (contravariant) tangents.
  Eigen::Matrix<double, 6, 3> surface_gradients;
};

SurfacePoint surface_point(const TriangleNodes& x, const Vec3& xi);

}  // namespace softflow::element
