#include "softflow/analysis/theory/drop_in_linear_flow.hpp"

#include <cmath>

namespace softflow::analysis::theory {

DropInLinearFlow::DropInLinearFlow(Kind kind, double lambda,
                                   const Eigen::Matrix3d& velocity_gradient, double tension)
    : kind_(kind),
      lambda_(lambda),
      e_(0.5 * (velocity_gradient + velocity_gradient.transpose())),
      w_(0.5 * (velocity_gradient - velocity_gradient.transpose())),
      tension_(tension) {}

DropInLinearFlow DropInLinearFlow::simple_shear(Kind kind, double lambda, double shear_rate,
                                                double tension) {
  Eigen::Matrix3d grad = Eigen::Matrix3d::Zero();
  grad(0, 1) = shear_rate;  // du_x/dy
  return DropInLinearFlow(kind, lambda, grad, tension);
}

Eigen::Vector3d DropInLinearFlow::velocity(const Eigen::Vector3d& x, bool inside) const {
  const double r2 = x.squaredNorm();
  const Eigen::Vector3d ex = e_ * x;
  const double h = x.dot(ex);
  if (kind_ == Kind::instantaneous) {
    const double d = 2.0 * lambda_ + 3.0;
    if (inside) return 5.0 / d * ex + w_ * x;
    const double r5 = std::pow(r2, 2.5), r7 = r5 * r2;
    const Eigen::Vector3d grad_h_over_r5 = 2.0 * ex / r5 - 5.0 * h * x / r7;
    return ex + 5.0 * (1.0 - lambda_) / d * h * x / r5 + (1.0 - lambda_) / d * grad_h_over_r5 +
           w_ * x;
  }
  const double big_l = lambda_ + 1.0;
  if (inside) return (5.0 * r2 * ex - 2.0 * h * x - 3.0 * ex) / (2.0 * big_l) + w_ * x;
  const double r5 = std::pow(r2, 2.5), r7 = r5 * r2;
  const Eigen::Vector3d grad_h_over_r5 = 2.0 * ex / r5 - 5.0 * h * x / r7;
  return ex - (5.0 * lambda_ + 2.0) / (2.0 * big_l) * h * x / r5 -
         lambda_ / (2.0 * big_l) * grad_h_over_r5 + w_ * x;
}

double DropInLinearFlow::pressure(const Eigen::Vector3d& x, bool inside) const {
  const double h = x.dot(e_ * x);
  const double r5 = std::pow(x.squaredNorm(), 2.5);
  if (kind_ == Kind::instantaneous) {
    if (inside) return 2.0 * tension_;
    return 10.0 * (1.0 - lambda_) / (2.0 * lambda_ + 3.0) * h / r5;
  }
  const double big_l = lambda_ + 1.0;
  if (inside) return 21.0 * lambda_ * h / (2.0 * big_l) + 2.0 * tension_;
  return -(5.0 * lambda_ + 2.0) / big_l * h / r5;
}

}  // namespace softflow::analysis::theory
