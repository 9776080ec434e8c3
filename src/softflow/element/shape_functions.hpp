// Lagrange P1/P2 shape functions on the reference tetrahedron and triangle.
//
// Node order follows mesh/mesh.hpp (VTK): vertices first, then edge nodes
// on (0,1) (1,2) (0,2) (0,3) (1,3) (2,3) for the tetrahedron and (0,1)
// (1,2) (2,0) for the triangle. In barycentric coordinates l_i,
// vertex functions are l_i (2 l_i - 1) and edge functions 4 l_a l_b.
#pragma once

#include <array>

#include <Eigen/Core>

namespace softflow::element {

using Vec3 = Eigen::Vector3d;

/// Values of the 4 P1 tetrahedron functions at xi.
std::array<double, 4> p1_tet_values(const Vec3& xi);
/// Reference gradients of the 4 P1 tetrahedron functions (constant), one per row.
Eigen::Matrix<double, 4, 3> p1_tet_gradients();

/// Values of the 10 P2 tetrahedron functions at xi.
std::array<double, 10> p2_tet_values(const Vec3& xi);
/// Reference gradients of the 10 P2 tetrahedron functions at xi, one per row.
Eigen::Matrix<double, 10, 3> p2_tet_gradients(const Vec3& xi);

/// Values of the 3 P1 / 6 P2 triangle functions at (xi[0], xi[1]).
std::array<double, 3> p1_triangle_values(const Vec3& xi);
std::array<double, 6> p2_triangle_values(const Vec3& xi);
/// Reference gradients (d/dxi0, d/dxi1) of the 6 P2 triangle functions, one per row.
Eigen::Matrix<double, 6, 2> p2_triangle_gradients(const Vec3& xi);

}  // namespace softflow::element
