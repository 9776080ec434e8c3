#include "softflow/physics/stokes/wall_motion.hpp"

#include <algorithm>
#include <cmath>

namespace softflow::physics {

WallMotion::WallMotion(double height, std::function<double(double)> wall_speed,
                       std::optional<double> jump_time)
    : height_(height), wall_speed_(std::move(wall_speed)), jump_time_(jump_time) {}

bool WallMotion::jumps_at(double t) const {
  return jump_time_ && std::abs(t - *jump_time_) <= 1e-9 * std::max(1.0, std::abs(*jump_time_));
}

WallMotion WallMotion::steady(double height, double shear_rate) {
  return WallMotion(height, [u = 0.5 * shear_rate * height](double) { return u; });
}

WallMotion WallMotion::start_up(double height, double shear_rate) {
  return WallMotion(height, [u = 0.5 * shear_rate * height](double t) { return t < 0.0 ? 0.0 : u; });
}

WallMotion WallMotion::cessation(double height, double shear_rate, double stop_time) {
  // Moving up to and including t = stop_time: time loops sample the walls at
  // the end of each step (t_{n+1}), so the step that ends at stop_time must
  // still see them move, or one step of shear is lost (an O(dt) error in
  // every history-dependent quantity, e.g. a polymer stress). The tolerance
  // absorbs the round-off of a time accumulated step by step.
  return WallMotion(height, [u = 0.5 * shear_rate * height, stop_time](double t) {
    return t - stop_time <= 1e-9 * std::max(1.0, std::abs(stop_time)) ? u : 0.0;
  }, stop_time);
}

WallMotion WallMotion::oscillatory(double height, double strain_amplitude, double frequency) {
  return WallMotion(height, [=](double t) {
    return 0.5 * height * strain_amplitude * frequency * std::sin(frequency * t);
  });
}

}  // namespace softflow::physics
