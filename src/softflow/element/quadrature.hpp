// Quadrature rules with positive weights on the reference tetrahedron and triangle.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace softflow::element {

/// Points and weights on a reference cell. The reference tetrahedron is
/// {x, y, z >= 0, x + y + z <= 1} (volume 1/6); the reference triangle is
/// {x, y >= 0, x + y <= 1} (area 1/2), with points stored as (x, y, 0).
struct QuadratureRule {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> weights;
  int degree = 0;  ///< polynomials up to this degree are integrated exactly

  [[nodiscard]] int size() const { return static_cast<int>(weights.size()); }
};

/// A rule exact for polynomials of the given degree on the tetrahedron.
/// Degree <= 5 uses the 14-point symmetric rule; higher degrees a collapsed
/// (Duffy) Gauss-Legendre product rule. All weights are positive (gmsh's
/// "Gauss4" has a negative one, see PLATFORM.md).
QuadratureRule tetrahedron_rule(int degree);

/// A rule exact for polynomials of the given degree on the triangle.
/// Degree <= 5 uses the 7-point Radon rule; higher degrees a collapsed
/// Gauss-Legendre product rule.
QuadratureRule triangle_rule(int degree);

/// n-point Gauss-Legendre rule on [0, 1].
void gauss_legendre_01(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace softflow::element
