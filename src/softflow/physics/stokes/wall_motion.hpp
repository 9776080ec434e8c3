// Velocity of the shear cell's walls as a function of time.
#pragma once

#include <functional>
#include <optional>

#include <Eigen/Core>

namespace softflow::physics {

/// The walls y = +-H/2 move with u = (+-u_w(t), 0, 0) (thesis eqs. 2.11-2.12);
/// box faces that are not periodic carry the undisturbed flow (u_w(t) 2y/H, 0, 0).
class WallMotion {
 public:
  /// Any wall speed history u_w(t).
  /// `jump_time`: where u_w jumps, if it does (see jumps_at).
  explicit WallMotion(double height, std::function<double(double)> wall_speed,
                      std::optional<double> jump_time = std::nullopt);

  /// Steady shear: u_w = shear_rate H / 2.
  static WallMotion steady(double height, double shear_rate);
  /// Start-up at t = 0 (u_w = 0 before), then steady.
  static WallMotion start_up(double height, double shear_rate);
  /// Cessation: steady up to and including t = stop_time, at rest after (the
  /// relaxation of a deformed drop). The walls stop at once: inertialess
  /// flow follows them without delay.
  static WallMotion cessation(double height, double shear_rate, double stop_time);
  /// Oscillatory shear (SPEC §1): u_w = (H/2) gamma0 omega sin(omega t), i.e.
  /// shear rate gamma0 omega sin(omega t) and strain gamma0 (1 - cos(omega t)).
  static WallMotion oscillatory(double height, double strain_amplitude, double frequency);

  [[nodiscard]] double wall_speed(double t) const { return wall_speed_(t); }
  [[nodiscard]] double shear_rate(double t) const { return 2.0 * wall_speed_(t) / height_; }
  /// Velocity imposed at boundary point x at time t.
  [[nodiscard]] Eigen::Vector3d velocity(const Eigen::Vector3d& x, double t) const {
    return Eigen::Vector3d(shear_rate(t) * x.y(), 0.0, 0.0);
  }

  /// True if the wall speed jumps at t (to round-off): the cessation's stop.
  /// Multistep schemes (BDF2) must restart at first order after such a time:
  /// their three-level stencil across a jump in the forcing is O(1) wrong
  /// in the derivative and would leave an O(dt) error.
  [[nodiscard]] bool jumps_at(double t) const;
  /// Where the wall speed jumps, if it does: adaptive steps end there exactly.
  [[nodiscard]] std::optional<double> jump_time() const { return jump_time_; }

 private:
  double height_;
  std::function<double(double)> wall_speed_;
  std::optional<double> jump_time_;
};

}  // namespace softflow::physics
