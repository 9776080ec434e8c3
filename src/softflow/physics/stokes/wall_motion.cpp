#include "softflow/physics/stokes/wall_motion.hpp"

#include <cmath>

namespace softflow::physics {

WallMotion::WallMotion(double height, std::function<double(double)> wall_speed)
    : height_(height), wall_speed_(std::move(wall_speed)) {}

WallMotion WallMotion::steady(double height, double shear_rate) {
  return WallMotion(height, [u = 0.5 * shear_rate * height](double) { return u; });
}

WallMotion WallMotion::start_up(double height, double shear_rate) {
  return WallMotion(height, [u = 0.5 * shear_rate * height](double t) { return t < 0.0 ? 0.0 : u; });
}

WallMotion WallMotion::cessation(double height, double shear_rate, double stop_time) {
  return WallMotion(height, [u = 0.5 * shear_rate * height, stop_time](double t) {
    return t < stop_time ? u : 0.0;
  });
}

WallMotion WallMotion::oscillatory(double height, double strain_amplitude, double frequency) {
  return WallMotion(height, [=](double t) {
    return 0.5 * height * strain_amplitude * frequency * std::sin(frequency * t);
  });
}

}  // namespace softflow::physics
