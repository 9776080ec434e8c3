#include "softflow/physics/viscoelastic/conformation_prediction.hpp"

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::physics::viscoelastic {

Mat3 convective_derivative(const Vec3& w, const std::array<Mat3, 3>& grad_c) {
  return w(0) * grad_c[0] + w(1) * grad_c[1] + w(2) * grad_c[2];
}

ConformationPrediction::ConformationPrediction(const Constitutive& model, const Mat3& c_n,
                                               const Mat3& convection, double dt)
    : ConformationPrediction(model, c_n, c_n, convection, dt) {}

ConformationPrediction::ConformationPrediction(const Constitutive& model, const Mat3& history,
                                               const Mat3& extrapolated, const Mat3& convection,
                                               double theta_dt)
    : extrapolated_(extrapolated), theta_dt_(theta_dt) {
  if (!model.has_conformation())
    throw Error("ConformationPrediction: a Newtonian phase has no conformation tensor");
  if (!(theta_dt > 0.0))
    throw Error(
        fmt::format("ConformationPrediction: the time step dt = {} must be positive", theta_dt));
  // conformation_relaxation carries the corrected sign and 1/lambda (SPEC §9).
  constant_ = history + theta_dt * (-convection + conformation_relaxation(model, extrapolated));
}

Mat3 ConformationPrediction::linear(const Mat3& velocity_gradient) const {
  return theta_dt_ * upper_convected_terms(velocity_gradient, extrapolated_);
}

Mat3 ConformationPrediction::operator()(const Mat3& velocity_gradient) const {
  return constant_ + linear(velocity_gradient);
}

}  // namespace softflow::physics::viscoelastic
