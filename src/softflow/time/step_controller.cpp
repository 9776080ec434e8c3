#include "softflow/time/step_controller.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::time {

StepController::StepController(const StepControllerSettings& s) : settings_(s) {
  if (!(s.tolerance > 0.0) || !std::isfinite(s.tolerance))
    throw Error(fmt::format("step controller: tolerance {} must be a positive number", s.tolerance));
  if (!(s.estimate_order > 0.0))
    throw Error(fmt::format("step controller: estimate order {} must be positive", s.estimate_order));
  if (!(s.max_growth > 1.0) || !(s.min_shrink > 0.0 && s.min_shrink < 1.0) ||
      !(s.safety > 0.0 && s.safety <= 1.0))
    throw Error(fmt::format("step controller: need max_growth > 1 (got {}), 0 < min_shrink < 1 "
                            "(got {}), 0 < safety <= 1 (got {})",
                            s.max_growth, s.min_shrink, s.safety));
  if (s.min_step < 0.0 || s.max_step < 0.0 || (s.max_step > 0.0 && s.min_step > s.max_step))
    throw Error(fmt::format("step controller: need 0 <= min_step <= max_step (got {}, {})",
                            s.min_step, s.max_step));
}

double StepController::bounded(double dt) const {
  if (settings_.max_step > 0.0) dt = std::min(dt, settings_.max_step);
  return std::max(dt, settings_.min_step);
}

StepDecision StepController::judge(double dt, double estimate) const {
  if (!std::isfinite(estimate) || estimate < 0.0) return after_failure(dt);
  const auto& s = settings_;
  // An estimate of zero (nothing moves) allows the largest growth.
  const double ratio =
      estimate == 0.0 ? s.max_growth
                      : std::clamp(s.safety * std::pow(s.tolerance / estimate, 1.0 / s.estimate_order),
                                   s.min_shrink, s.max_growth);
  if (estimate <= s.tolerance) return {true, bounded(ratio * dt)};
  // Rejected: retry smaller, but never below min_step (then give up).
  const double retry = ratio * dt;
  if (retry < s.min_step || dt <= s.min_step) return {false, 0.0};
  return {false, bounded(retry)};
}

StepDecision StepController::after_failure(double dt) const {
  const double retry = 0.5 * dt;
  if (retry < settings_.min_step) return {false, 0.0};
  return {false, bounded(retry)};
}

double next_planned_step(double planned, double taken, double proposed) {
  const bool cut_short = taken < planned;
  return cut_short && proposed >= taken ? std::max(planned, proposed) : proposed;
}

}  // namespace softflow::time
