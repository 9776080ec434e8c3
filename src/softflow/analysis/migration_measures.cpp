#include "softflow/analysis/migration_measures.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/element/shape_functions.hpp"

namespace softflow::analysis {

namespace {

element::TriangleNodes triangle_at(const std::array<int, 6>& tri, const std::vector<Vec3>& x) {
  element::TriangleNodes nodes;
  for (int k = 0; k < 6; ++k) nodes.col(k) = x[tri[k]];
  return nodes;
}

/// f(xi) = (dx/dxi_1 x dx/dxi_2)_y: the y component of the (unnormalised) outward normal,
/// with the sign of n_y. Quadratic on a P2 triangle (its tangents are linear in xi), kept as
/// f = c00 + c10 u + c01 v + c20 u^2 + c11 u v + c02 v^2 with (u, v) = (xi_1, xi_2).
struct Quadratic {
  double c00 = 0, c10 = 0, c01 = 0, c20 = 0, c11 = 0, c02 = 0;
  [[nodiscard]] double operator()(double u, double v) const {
    return c00 + c10 * u + c01 * v + c20 * u * u + c11 * u * v + c02 * v * v;
  }
  [[nodiscard]] double scale() const {
    return std::max({std::abs(c00), std::abs(c10), std::abs(c01), std::abs(c20), std::abs(c11),
                     std::abs(c02)});
  }
};

double normal_y(const element::TriangleNodes& x, double u, double v) {
  const Eigen::Matrix<double, 6, 2> dn = element::p2_triangle_gradients(Vec3(u, v, 0.0));
  const Eigen::Matrix<double, 3, 2> t = x * dn;
  return t(2, 0) * t(0, 1) - t(0, 0) * t(2, 1);  // (a1 x a2)_y
}

// The six coefficients from f at the vertices and edge midpoints (f is exactly quadratic).
Quadratic normal_y_polynomial(const element::TriangleNodes& x) {
  const double f00 = normal_y(x, 0, 0), f10 = normal_y(x, 1, 0), f01 = normal_y(x, 0, 1);
  const double fh0 = normal_y(x, 0.5, 0), f0h = normal_y(x, 0, 0.5), fhh = normal_y(x, 0.5, 0.5);
  Quadratic q;
  q.c00 = f00;
  q.c20 = 2.0 * (f10 - 2.0 * fh0 + f00);
  q.c10 = f10 - f00 - q.c20;
  q.c02 = 2.0 * (f01 - 2.0 * f0h + f00);
  q.c01 = f01 - f00 - q.c02;
  q.c11 = 4.0 * (fhh - f00 - 0.5 * q.c10 - 0.5 * q.c01 - 0.25 * q.c20 - 0.25 * q.c02);
  return q;
}

/// Roots of a t^2 + b t + c strictly inside (lo, hi), appended to `out`; `scale` sets what
/// counts as a vanishing leading coefficient. Cancellation-free formula.
void roots_in(double a, double b, double c, double lo, double hi, double scale,
              std::vector<double>& out) {
  const double tiny = 1e-14 * scale;
  auto keep = [&](double r) {
    if (std::isfinite(r) && r > lo && r < hi) out.push_back(r);
  };
  if (std::abs(a) <= tiny) {
    if (std::abs(b) > tiny) keep(-c / b);
    return;
  }
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return;
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  keep(q / a);
  if (q != 0.0) keep(c / q);
}

/// Whether f keeps one strict sign on the closed reference triangle: its extrema lie at the
/// vertices, at stationary points of the edges, or at the interior stationary point.
/// Returns +1 or -1 for a strict sign, 0 when f vanishes somewhere (a cut triangle).
int strict_sign(const Quadratic& f) {
  std::vector<double> values{f(0, 0), f(1, 0), f(0, 1)};
  // Edge v = 0: c20 u^2 + c10 u + c00.
  if (f.c20 != 0.0) {
    const double u = -f.c10 / (2.0 * f.c20);
    if (u > 0.0 && u < 1.0) values.push_back(f(u, 0));
  }
  if (f.c02 != 0.0) {  // edge u = 0
    const double v = -f.c01 / (2.0 * f.c02);
    if (v > 0.0 && v < 1.0) values.push_back(f(0, v));
  }
  {  // edge u + v = 1, u = s, v = 1 - s: a s^2 + b s + c
    const double a = f.c20 - f.c11 + f.c02;
    const double b = f.c10 - f.c01 + f.c11 - 2.0 * f.c02;
    if (a != 0.0) {
      const double s = -b / (2.0 * a);
      if (s > 0.0 && s < 1.0) values.push_back(f(s, 1.0 - s));
    }
  }
  {  // interior: grad f = 0
    const double det = 4.0 * f.c20 * f.c02 - f.c11 * f.c11;
    if (det != 0.0) {
      const double u = (-2.0 * f.c02 * f.c10 + f.c11 * f.c01) / det;
      const double v = (-2.0 * f.c20 * f.c01 + f.c11 * f.c10) / det;
      if (u > 0.0 && v > 0.0 && u + v < 1.0) values.push_back(f(u, v));
    }
  }
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  if (*lo > 0.0) return 1;
  if (*hi < 0.0) return -1;
  return 0;
}

struct GaussRule {
  std::vector<double> x, w;
};
const GaussRule& gauss(int n) {
  static const GaussRule outer = [] {
    GaussRule r;
    element::gauss_legendre_01(12, r.x, r.w);
    return r;
  }();
  static const GaussRule inner = [] {
    GaussRule r;
    element::gauss_legendre_01(10, r.x, r.w);
    return r;
  }();
  return n == 12 ? outer : inner;
}

/// The areas of the parts of a cut triangle where f > 0 and f < 0.
///
/// Line by line in u: on each line u = const the zero set of f is the roots of the
/// quadratic A v^2 + B(u) v + C(u) (A = c02, B = c01 + c11 u, C = c00 + c10 u + c20 u^2),
/// in closed form; between them each piece of [0, 1 - u] has one sign, and its area
/// density (the P2 map's area scale) is integrated by Gauss-Legendre. Along u the lines'
/// integrals are smooth except where the root pattern changes: where a root meets an edge
/// (C(u) = 0, f(u, 1 - u) = 0) or two roots meet (the discriminant B^2 - 4AC = 0, with a
/// square-root behaviour). [0, 1] is split there, and each part is integrated with the
/// substitution u = a + (b - a)(3t^2 - 2t^3), whose vanishing derivative at both ends absorbs
/// the square roots, then Gauss-Legendre in t.
std::array<double, 2> signed_areas(const element::TriangleNodes& x, const Quadratic& f) {
  const double scale = f.scale();
  std::vector<double> breaks{0.0, 1.0};
  roots_in(f.c20, f.c10, f.c00, 0.0, 1.0, scale, breaks);  // f(u, 0)
  // f(u, 1 - u) = (c20 - c11 + c02) u^2 + (c10 - c01 + c11 - 2 c02) u + (c00 + c01 + c02)
  roots_in(f.c20 - f.c11 + f.c02, f.c10 - f.c01 + f.c11 - 2.0 * f.c02, f.c00 + f.c01 + f.c02,
           0.0, 1.0, scale, breaks);
  // Discriminant (c01 + c11 u)^2 - 4 c02 (c00 + c10 u + c20 u^2), or B(u) = 0 when A = 0.
  const double a = f.c02;
  if (std::abs(a) > 1e-14 * scale)
    roots_in(f.c11 * f.c11 - 4.0 * a * f.c20, 2.0 * f.c01 * f.c11 - 4.0 * a * f.c10,
             f.c01 * f.c01 - 4.0 * a * f.c00, 0.0, 1.0, scale * scale, breaks);
  else
    roots_in(0.0, f.c11, f.c01, 0.0, 1.0, scale, breaks);
  std::sort(breaks.begin(), breaks.end());

  const GaussRule& outer = gauss(12);
  const GaussRule& inner = gauss(10);
  std::array<double, 2> area{0.0, 0.0};  // [f > 0, f < 0]
  std::vector<double> cuts;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double u0 = breaks[i], u1 = breaks[i + 1];
    if (!(u1 - u0 > 1e-15)) continue;
    for (std::size_t p = 0; p < outer.x.size(); ++p) {
      const double t = outer.x[p];
      const double u = u0 + (u1 - u0) * t * t * (3.0 - 2.0 * t);
      const double du = (u1 - u0) * 6.0 * t * (1.0 - t) * outer.w[p];
      const double length = 1.0 - u;
      cuts.assign({0.0, length});
      roots_in(f.c02, f.c01 + f.c11 * u, f.c00 + f.c10 * u + f.c20 * u * u, 0.0, length, scale,
               cuts);
      std::sort(cuts.begin(), cuts.end());
      for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
        const double v0 = cuts[j], v1 = cuts[j + 1];
        if (!(v1 > v0)) continue;
        const int side = f(u, 0.5 * (v0 + v1)) > 0.0 ? 0 : 1;
        double piece = 0.0;
        for (std::size_t k = 0; k < inner.x.size(); ++k) {
          const double v = v0 + (v1 - v0) * inner.x[k];
          piece += inner.w[k] * element::surface_point(x, Vec3(u, v, 0.0)).area_scale;
        }
        area[side] += du * (v1 - v0) * piece;
      }
    }
  }
  return area;
}

}  // namespace

SurfaceImbalance surface_imbalance(const physics::InterfaceMesh& s, const std::vector<Vec3>& x) {
  // Degree 7 as physics::surface_integrals, whose area this matches on uncut triangles.
  static const element::QuadratureRule rule = element::triangle_rule(7);
  SurfaceImbalance r;
  for (const auto& tri : s.triangles) {
    const auto nodes = triangle_at(tri, x);
    const Quadratic f = normal_y_polynomial(nodes);
    const int sign = strict_sign(f);
    if (sign == 0) {
      const auto parts = signed_areas(nodes, f);
      r.area_positive += parts[0];
      r.area_negative += parts[1];
      continue;
    }
    double area = 0.0;
    for (int q = 0; q < rule.size(); ++q)
      area += rule.weights[q] * element::surface_point(nodes, rule.points[q]).area_scale;
    (sign > 0 ? r.area_positive : r.area_negative) += area;
  }
  r.area = r.area_positive + r.area_negative;
  return r;
}

SurfaceImbalance surface_imbalance_by_indicator(const physics::InterfaceMesh& s,
                                                const std::vector<Vec3>& x, int degree) {
  const element::QuadratureRule rule = element::triangle_rule(degree);
  SurfaceImbalance r;
  for (const auto& tri : s.triangles) {
    const auto nodes = triangle_at(tri, x);
    for (int q = 0; q < rule.size(); ++q) {
      const auto p = element::surface_point(nodes, rule.points[q]);
      const double w = rule.weights[q] * p.area_scale;
      (p.normal.y() > 0.0 ? r.area_positive : r.area_negative) += w;
    }
  }
  r.area = r.area_positive + r.area_negative;
  return r;
}

MigrationMeasures migration_measures(const physics::InterfaceMesh& s, const std::vector<Vec3>& x) {
  const physics::SurfaceIntegrals integrals = physics::surface_integrals(s, x);
  MigrationMeasures m;
  m.volume = integrals.volume;
  m.centre = integrals.centre_of_volume();
  m.imbalance = surface_imbalance(s, x);
  return m;
}

Vec3 centre_velocity(const Vec3& centre, const Vec3& previous, double dt) {
  if (!(dt > 0.0)) throw std::invalid_argument("centre_velocity: dt must be > 0");
  return (centre - previous) / dt;
}

Vec3 centre_velocity(const Vec3& centre, const Vec3& previous, const Vec3& before_previous,
                     double dt, double dt_previous) {
  if (!(dt > 0.0) || !(dt_previous > 0.0))
    throw std::invalid_argument("centre_velocity: steps must be > 0");
  const double w = dt / dt_previous;
  return ((1.0 + 2.0 * w) * centre - (1.0 + w) * (1.0 + w) * previous + w * w * before_previous) /
         ((1.0 + w) * dt);
}

}  // namespace softflow::analysis
