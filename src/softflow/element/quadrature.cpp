#include "softflow/element/quadrature.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>

namespace softflow::element {

void gauss_legendre_01(int n, std::vector<double>& x, std::vector<double>& w) {
  // Golub-Welsch: nodes are the eigenvalues of the Jacobi matrix of the
  // Legendre recurrence, weights the squared first eigenvector components.
  Eigen::MatrixXd jacobi = Eigen::MatrixXd::Zero(n, n);
  for (int k = 1; k < n; ++k) {
    const double beta = k / std::sqrt(4.0 * k * k - 1.0);
    jacobi(k, k - 1) = jacobi(k - 1, k) = beta;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(jacobi);
  x.resize(n);
  w.resize(n);
  for (int k = 0; k < n; ++k) {
    x[k] = 0.5 * (eig.eigenvalues()(k) + 1.0);
    const double v0 = eig.eigenvectors()(0, k);
    w[k] = v0 * v0;  // 2 v0^2 on [-1, 1], halved for [0, 1]
  }
}

namespace {

QuadratureRule collapsed_tetrahedron_rule(int degree) {
  // x = u, y = v (1 - u), z = w (1 - u)(1 - v); dV = (1-u)^2 (1-v) du dv dw.
  // The Jacobian raises the degree in u by 2 and in v by 1.
  std::vector<double> xu, wu, xv, wv, xw, ww;
  gauss_legendre_01((degree + 4) / 2, xu, wu);
  gauss_legendre_01((degree + 3) / 2, xv, wv);
  gauss_legendre_01((degree + 2) / 2, xw, ww);
  QuadratureRule rule;
  rule.degree = degree;
  for (std::size_t i = 0; i < xu.size(); ++i)
    for (std::size_t j = 0; j < xv.size(); ++j)
      for (std::size_t k = 0; k < xw.size(); ++k) {
        const double u = xu[i], v = xv[j], s = xw[k];
        rule.points.emplace_back(u, v * (1 - u), s * (1 - u) * (1 - v));
        rule.weights.push_back(wu[i] * wv[j] * ww[k] * (1 - u) * (1 - u) * (1 - v));
      }
  return rule;
}

QuadratureRule collapsed_triangle_rule(int degree) {
  std::vector<double> xu, wu, xv, wv;
  gauss_legendre_01((degree + 3) / 2, xu, wu);
  gauss_legendre_01((degree + 2) / 2, xv, wv);
  QuadratureRule rule;
  rule.degree = degree;
  for (std::size_t i = 0; i < xu.size(); ++i)
    for (std::size_t j = 0; j < xv.size(); ++j) {
      rule.points.emplace_back(xu[i], xv[j] * (1 - xu[i]), 0.0);
      rule.weights.push_back(wu[i] * wv[j] * (1 - xu[i]));
    }
  return rule;
}

// Symmetric orbits in barycentric coordinates (l0, l1, l2, l3); the point is (l1, l2, l3).
void add_orbit_4(QuadratureRule& r, double a, double w) {
  const double b = 1.0 - 3.0 * a;
  const double l[4][4] = {{b, a, a, a}, {a, b, a, a}, {a, a, b, a}, {a, a, a, b}};
  for (const auto& p : l) {
    r.points.emplace_back(p[1], p[2], p[3]);
    r.weights.push_back(w);
  }
}

void add_orbit_6(QuadratureRule& r, double a, double w) {
  const double b = 0.5 - a;
  const double l[6][4] = {{a, a, b, b}, {a, b, a, b}, {a, b, b, a},
                          {b, a, a, b}, {b, a, b, a}, {b, b, a, a}};
  for (const auto& p : l) {
    r.points.emplace_back(p[1], p[2], p[3]);
    r.weights.push_back(w);
  }
}

QuadratureRule tetrahedron_14_point() {
  // Degree-5 symmetric rule with positive weights (Walkington 2000; Keast's
  // family); weights sum to 1/6.
  QuadratureRule r;
  r.degree = 5;
  add_orbit_4(r, 0.0927352503108912264, 0.0122488405193936583);
  add_orbit_4(r, 0.3108859192633006097, 0.0187813209530026417);
  add_orbit_6(r, 0.0455037041256496494, 0.00709100346284691107);
  return r;
}

QuadratureRule triangle_7_point() {
  // Radon's degree-5 rule; weights sum to 1/2.
  QuadratureRule r;
  r.degree = 5;
  const double s15 = std::sqrt(15.0);
  r.points.emplace_back(1.0 / 3.0, 1.0 / 3.0, 0.0);
  r.weights.push_back(9.0 / 80.0);
  const double a[2] = {(6.0 - s15) / 21.0, (6.0 + s15) / 21.0};
  const double w[2] = {(155.0 - s15) / 2400.0, (155.0 + s15) / 2400.0};
  for (int k = 0; k < 2; ++k) {
    const double b = 1.0 - 2.0 * a[k];
    r.points.emplace_back(a[k], a[k], 0.0);
    r.points.emplace_back(b, a[k], 0.0);
    r.points.emplace_back(a[k], b, 0.0);
    for (int m = 0; m < 3; ++m) r.weights.push_back(w[k]);
  }
  return r;
}

}  // namespace

QuadratureRule tetrahedron_rule(int degree) {
  if (degree < 0) throw std::invalid_argument("tetrahedron_rule: negative degree");
  return degree <= 5 ? tetrahedron_14_point() : collapsed_tetrahedron_rule(degree);
}

QuadratureRule triangle_rule(int degree) {
  if (degree < 0) throw std::invalid_argument("triangle_rule: negative degree");
  return degree <= 5 ? triangle_7_point() : collapsed_triangle_rule(degree);
}

}  // namespace softflow::element
