#include "softflow/analysis/ellipsoid_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::analysis {

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

constexpr int kQuadricParameters = 9;  // a..i of eq. 2.57
// Smallest over largest eigenvalue of the quadric's matrix below which the
// fit is called degenerate: an aspect ratio of 10^6, far past any drop.
constexpr double kMinEigenvalueRatio = 1e-12;

/// The quadric q^T A q + b^T q = rhs in the centred, scaled coordinates q.
struct Quadric {
  Matrix3d A;
  Vector3d b;
  double rhs = 1.0;
};

/// Mean of the points, the origin of the fit's coordinates.
Vector3d mean_of(std::span<const Vector3d> points) {
  Vector3d sum = Vector3d::Zero();
  for (const auto& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

/// RMS distance from `origin`: scaling by it keeps the columns of the design
/// matrix (x^2 ... z) of order one, whatever the length unit.
double rms_distance(std::span<const Vector3d> points, const Vector3d& origin) {
  double sum = 0.0;
  for (const auto& p : points) sum += (p - origin).squaredNorm();
  return std::sqrt(sum / static_cast<double>(points.size()));
}

/// Linear least squares for the nine coefficients of eq. 2.57 with
/// column-pivoted QR of the N x 9 design matrix (never the normal equations,
/// whose condition number is the square of this one).
Quadric fit_quadric(std::span<const Vector3d> points, const Vector3d& origin, double scale) {
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd design(n, kQuadricParameters);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Vector3d q = (points[k] - origin) / scale;
    design.row(k) << q.x() * q.x(), q.y() * q.y(), q.z() * q.z(), q.x() * q.y(), q.x() * q.z(),
        q.y() * q.z(), q.x(), q.y(), q.z();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(design);
  if (qr.rank() < kQuadricParameters) {
    throw Error(fmt::format(
        "fit_ellipsoid: the {} points do not determine a quadric (design matrix rank {} < 9); "
        "they lie on a plane, a circle or another degenerate set",
        points.size(), qr.rank()));
  }
  const Eigen::VectorXd c = qr.solve(Eigen::VectorXd::Ones(n));
  Quadric quadric;
  // Off-diagonal terms carry half the cross coefficients: d xy = 2 A_xy x y.
  quadric.A << c(0), 0.5 * c(3), 0.5 * c(4),  //
      0.5 * c(3), c(1), 0.5 * c(5),           //
      0.5 * c(4), 0.5 * c(5), c(2);
  quadric.b << c(6), c(7), c(8);
  return quadric;
}

std::string eigenvalue_text(const Vector3d& values) {
  return fmt::format("({:.3g}, {:.3g}, {:.3g})", values(0), values(1), values(2));
}

/// Right-handed unit axes with a reproducible sign: the largest component of
/// the first two directions positive, the third their cross product.
Matrix3d normalised_axes(Matrix3d axes) {
  for (int j = 0; j < 2; ++j) {
    Eigen::Index i_max = 0;
    axes.col(j).cwiseAbs().maxCoeff(&i_max);
    if (axes(i_max, j) < 0.0) axes.col(j) *= -1.0;
  }
  axes.col(2) = axes.col(0).cross(axes.col(1));
  return axes;
}

/// Reduces the quadric to centre, axes and semi-axes (still in the scaled
/// coordinates): centre = -A^{-1} b / 2, then (q - centre)^T A (q - centre)
/// = rhs + b^T A^{-1} b / 4 = k, semi-axes sqrt(k / eigenvalue).
EllipsoidFit reduce_quadric(Quadric quadric) {
  Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(quadric.A);
  Vector3d values = eigen.eigenvalues();  // ascending
  if (values(2) <= 0.0) {
    // All negative: the same surface written with the opposite sign.
    quadric = {-quadric.A, -quadric.b, -quadric.rhs};
    eigen.compute(quadric.A);
    values = eigen.eigenvalues();
  }
  if (!(values(0) > kMinEigenvalueRatio * values(2))) {
    throw Error(
        "fit_ellipsoid: the fitted quadric (eq. 2.57) is not an ellipsoid, its matrix "
        "has eigenvalues " +
        eigenvalue_text(values) +
        " (a hyperboloid, paraboloid or cylinder); the points are far from an "
        "ellipsoidal shape");
  }
  const Matrix3d& vectors = eigen.eigenvectors();
  const Vector3d a_inv_b = vectors * (vectors.transpose() * quadric.b).cwiseQuotient(values);
  const double k = quadric.rhs + 0.25 * quadric.b.dot(a_inv_b);
  if (!(k > 0.0)) {
    throw Error(fmt::format(
        "fit_ellipsoid: the fitted quadric (eq. 2.57) is an imaginary ellipsoid (level {:.3g})",
        k));
  }
  EllipsoidFit fit;
  fit.centre = -0.5 * a_inv_b;
  // Ascending eigenvalues give descending semi-axes, columns already in order.
  fit.semi_axes = (k / values.array()).sqrt().matrix();
  fit.axes = normalised_axes(vectors);
  return fit;
}

/// theta of the fit: the direction of L projected on x-y, as a line (sign
/// free), folded into (-90, 90] degrees, positive towards +y.
double in_plane_angle_deg(const Vector3d& direction) {
  double theta = std::atan2(direction.y(), direction.x()) * 180.0 / std::numbers::pi;
  if (theta > 90.0) theta -= 180.0;
  if (theta <= -90.0) theta += 180.0;
  return theta;
}

/// L, B, W, D and theta from the sorted axes: W is the axis with the largest
/// z component (vorticity direction), L >= B the remaining two.
void assign_shear_plane_measures(EllipsoidFit& fit) {
  Eigen::Index w = 0;
  fit.axes.row(2).cwiseAbs().maxCoeff(&w);
  std::array<Eigen::Index, 2> in_plane{};
  int n = 0;
  for (Eigen::Index j = 0; j < 3; ++j) {
    if (j != w) in_plane[n++] = j;
  }
  // Columns are sorted by semi-axis, so the first of the two is the longer.
  fit.L = fit.semi_axes(in_plane[0]);
  fit.B = fit.semi_axes(in_plane[1]);
  fit.W = fit.semi_axes(w);
  fit.deformation = (fit.L - fit.B) / (fit.L + fit.B);
  fit.theta_deg = in_plane_angle_deg(fit.axes.col(in_plane[0]));
}

/// Closest-point distance to the ellipsoid sum (x_i / e_i)^2 = 1 for a point
/// y with y_i >= 0, e descending and positive. The closest point is
/// x_i = e_i^2 y_i / (t + e_i^2) with the Lagrange multiplier t >= -e_2^2
/// (the smallest semi-axis; smaller t is not a minimum); in s = t + e_2^2 >= 0
/// it is the root of F(s) = sum (e_i y_i / (s + d_i))^2 - 1, d_i = e_i^2 - e_2^2,
/// which decreases monotonically, so bisection in s cannot fail. If F(0) <= 0
/// (only possible with y_2 = 0, a point inside on the plane of the two long
/// axes) the closest point leaves that plane: x_2 = e_2 sqrt(1 - sum (x_i/e_i)^2).
double principal_frame_distance(const Vector3d& y, const Vector3d& e) {
  const Vector3d d = (e.array().square() - e(2) * e(2)).matrix();
  const auto f = [&](double s) {
    double sum = -1.0;
    for (int i = 0; i < 3; ++i) {
      if (y(i) == 0.0) continue;
      const double denominator = s + d(i);
      if (denominator <= 0.0) return std::numeric_limits<double>::infinity();
      const double ratio = e(i) * y(i) / denominator;
      sum += ratio * ratio;
    }
    return sum;
  };
  if (f(0.0) <= 0.0) {
    Vector3d x = Vector3d::Zero();
    double used = 0.0;
    for (int i = 0; i < 2; ++i) {
      if (y(i) == 0.0) continue;
      x(i) = e(i) * e(i) * y(i) / d(i);
      used += (x(i) / e(i)) * (x(i) / e(i));
    }
    x(2) = e(2) * std::sqrt(std::max(0.0, 1.0 - used));
    return (x - y).norm();
  }
  // F(lo) > 0 >= F(hi): at s = |e o y| every term is at most (e_i y_i / s)^2.
  double lo = 0.0, hi = e.cwiseProduct(y).norm();
  for (int iteration = 0; iteration < 400; ++iteration) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;  // converged to round-off in s
    if (f(mid) > 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const double s = 0.5 * (lo + hi);
  // x_i - y_i = y_i (e_2^2 - s) / (s + d_i), free of the cancellation in x_i - y_i.
  Vector3d difference;
  for (int i = 0; i < 3; ++i) difference(i) = y(i) * (e(2) * e(2) - s) / (s + d(i));
  return difference.norm();
}

double max_relative_deviation(std::span<const Vector3d> points, const EllipsoidFit& fit) {
  const double mean_radius = std::cbrt(fit.semi_axes.prod());
  double worst = 0.0;
  for (const auto& p : points) {
    worst = std::max(worst, distance_to_ellipsoid(p, fit.centre, fit.axes, fit.semi_axes));
  }
  return worst / mean_radius;
}

}  // namespace

double distance_to_ellipsoid(const Vector3d& point, const Vector3d& centre, const Matrix3d& axes,
                             const Vector3d& semi_axes) {
  if (!(semi_axes.minCoeff() > 0.0)) {
    throw Error("distance_to_ellipsoid: semi-axes must be positive");
  }
  // Principal frame, first octant (the ellipsoid is symmetric in each axis),
  // semi-axes sorted descending.
  const Vector3d local = (axes.transpose() * (point - centre)).cwiseAbs();
  std::array<int, 3> order{0, 1, 2};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return semi_axes(i) > semi_axes(j); });
  Vector3d y, e;
  for (int i = 0; i < 3; ++i) {
    y(i) = local(order[i]);
    e(i) = semi_axes(order[i]);
  }
  return principal_frame_distance(y, e);
}

EllipsoidFit fit_ellipsoid(std::span<const Vector3d> points) {
  if (points.size() < static_cast<std::size_t>(kQuadricParameters)) {
    throw Error(fmt::format(
        "fit_ellipsoid: {} points given; the 9-parameter fit (eq. 2.57) needs at least 9",
        points.size()));
  }
  // Centring and scaling the points first keeps the design matrix well
  // conditioned (a drop far from the origin would otherwise make x^2 and x
  // nearly collinear); the result is shifted and scaled back below.
  const Vector3d origin = mean_of(points);
  const double scale = rms_distance(points, origin);
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    throw Error("fit_ellipsoid: the points coincide or are not finite");
  }
  EllipsoidFit fit = reduce_quadric(fit_quadric(points, origin, scale));
  fit.centre = origin + scale * fit.centre;
  fit.semi_axes *= scale;
  assign_shear_plane_measures(fit);
  fit.max_relative_deviation = max_relative_deviation(points, fit);
  return fit;
}

}  // namespace softflow::analysis
