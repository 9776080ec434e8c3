#include "softflow/analysis/theory/drop_in_linear_flow.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::analysis::theory {

namespace {

using Coefficients = DropInLinearFlow::Coefficients;

void require_non_negative(const char* name, double value) {
  if (!std::isfinite(value) || value < 0.0)
    throw InputError(
        fmt::format("DropInLinearFlow: {} = {} must be a finite number >= 0", name, value));
}

/// The instantaneous field: the no-slip field plus S times the field of a
/// unit tangential slip velocity (I - nn) E n (each with n.u continuous,
/// tangential traction continuous and a uniform normal-traction jump), S
/// from the Navier law S = alpha (T0 + S T1). scripts/theory/derive_slip_drop.py.
Coefficients instantaneous(double lambda, double alpha) {
  const double d = 2.0 * lambda + 3.0;
  const double e = 19.0 * lambda + 16.0;
  // No slip (the interior a uniform straining flow).
  const double a0 = 5.0 * (1.0 - lambda) / d, b0 = (1.0 - lambda) / d, k0 = 5.0 / d;
  const double t0 = 10.0 * lambda / d;
  // Per unit slip velocity.
  const double a1 = 3.0 * lambda / d, b1 = lambda * (19.0 * lambda + 21.0) / (d * e);
  const double k1 = 3.0 * (11.0 * lambda + 24.0) / (d * e), m1 = -8.0 / e;
  const double t1 = -10.0 * lambda * (19.0 * lambda + 24.0) / (d * e);
  // S = alpha T0 / (1 - alpha T1) = 10 alpha lambda e / Den: exactly 0 at alpha = 0,
  // so the no-slip coefficients come out unchanged; free slip (alpha = inf)
  // is its limit -T0 / T1, where the tangential traction T0 + S T1 vanishes.
  const double s = std::isinf(alpha) ? (t1 != 0.0 ? -t0 / t1 : 0.0)
                                     : alpha * t0 / (1.0 - alpha * t1);
  Coefficients c;
  c.a = a0 + s * a1;
  c.b = b0 + s * b1;
  c.k = k0 + s * k1;
  c.m = s * m1;
  c.t = std::isinf(alpha) ? 0.0 : t0 + s * t1;
  c.s = s;
  return c;
}

/// Taylor's quasi-steady field with slip (SPEC §10, the outer h x / r^5
/// coefficient with its factor 1/2).
Coefficients taylor_quasi_steady(double lambda, double alpha) {
  const double big_l = lambda + 1.0 + 5.0 * alpha * lambda;
  Coefficients c;
  c.a = -(5.0 * lambda + 2.0 + 10.0 * alpha * lambda) / (2.0 * big_l);
  c.b = -lambda / (2.0 * big_l);
  c.k = -3.0 / (2.0 * big_l);
  c.m = 1.0 / (2.0 * big_l);
  c.t = 5.0 * lambda / big_l;
  c.s = alpha * c.t;
  return c;
}

}  // namespace

DropInLinearFlow::DropInLinearFlow(Kind kind, double lambda,
                                   const Eigen::Matrix3d& velocity_gradient, double tension,
                                   double slip)
    : kind_(kind),
      lambda_(lambda),
      alpha_(slip),
      e_(0.5 * (velocity_gradient + velocity_gradient.transpose())),
      w_(0.5 * (velocity_gradient - velocity_gradient.transpose())),
      tension_(tension) {
  require_non_negative("lambda", lambda);
  if (!(slip >= 0.0))  // inf: free slip
    throw InputError(fmt::format("DropInLinearFlow: slip = {} must be >= 0 (inf: free slip)", slip));
  if (std::isinf(slip) && kind == Kind::taylor_quasi_steady)
    throw InputError("DropInLinearFlow: free slip (slip = inf) has no quasi-steady Taylor shape");
  c_ = kind_ == Kind::instantaneous ? instantaneous(lambda, slip)
                                    : taylor_quasi_steady(lambda, slip);
}

DropInLinearFlow DropInLinearFlow::simple_shear(Kind kind, double lambda, double shear_rate,
                                                double tension, double slip) {
  Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
  grad(0, 1) = shear_rate;  // du_x/dy
  return DropInLinearFlow(kind, lambda, grad, tension, slip);
}

Eigen::Vector3d DropInLinearFlow::velocity(const Eigen::Vector3d& x, bool inside) const {
  const double r2 = x.squaredNorm();
  const Eigen::Vector3d ex = e_ * x;
  const double h = x.dot(ex);
  if (inside) {
    Eigen::Vector3d u = c_.k * ex;
    // Skipped when M = 0 (no-slip instantaneous): the numbers stay the no-slip ones exactly.
    if (c_.m != 0.0) u += c_.m * (5.0 * r2 * ex - 2.0 * h * x);
    return u + w_ * x;
  }
  const double r5 = std::pow(r2, 2.5), r7 = r5 * r2;
  const Eigen::Vector3d grad_h_over_r5 = 2.0 * ex / r5 - 5.0 * h * x / r7;
  return ex + c_.a * h * x / r5 + c_.b * grad_h_over_r5 + w_ * x;
}

double DropInLinearFlow::pressure(const Eigen::Vector3d& x, bool inside) const {
  const double h = x.dot(e_ * x);
  if (inside) return 21.0 * lambda_ * c_.m * h + 2.0 * tension_;
  return 2.0 * c_.a * h / std::pow(x.squaredNorm(), 2.5);
}

namespace {

/// (I - nn) E n at n = x / |x|.
Eigen::Vector3d tangential_strain(const Eigen::Matrix3d& e, const Eigen::Vector3d& x) {
  const Eigen::Vector3d n = x.normalized();
  const Eigen::Vector3d en = e * n;
  return en - n.dot(en) * n;
}

}  // namespace

Eigen::Vector3d DropInLinearFlow::slip_velocity(const Eigen::Vector3d& x) const {
  return c_.s * tangential_strain(e_, x);
}

Eigen::Vector3d DropInLinearFlow::tangential_traction(const Eigen::Vector3d& x) const {
  return c_.t * tangential_strain(e_, x);
}

double DropInLinearFlow::slip_dissipation() const {
  if (std::isinf(alpha_)) return 0.0;  // alpha t^2 with t ~ 1 / alpha
  return 0.8 * std::numbers::pi * alpha_ * c_.t * c_.t * e_.squaredNorm();
}

double DropInLinearFlow::interior_dissipation() const {
  const double k = c_.k, m = c_.m;
  return 8.0 * std::numbers::pi / 15.0 * lambda_ *
         (5.0 * k * k + 42.0 * k * m + 111.0 * m * m) * e_.squaredNorm();
}

}  // namespace softflow::analysis::theory
