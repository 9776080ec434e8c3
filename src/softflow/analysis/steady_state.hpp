// When a run has reached its steady state: the objects' shapes, orientations
// and centre velocities have stopped changing (issue 13, "run to steady").
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace softflow::analysis {

/// What "steady" means for a run ([time] steady_tolerance, steady_window).
struct SteadyCriterion {
  /// The largest change over the window that still counts as steady; > 0.
  double tolerance = 1e-4;
  /// The time span the changes are measured over (> 0): at least one period
  /// of the slowest oscillation that should not count as steady (an elastic
  /// particle's material rotation takes ~2 pi / gamma_dot).
  double window = 5.0;
  /// gamma_dot R: the centre velocities are compared in these units.
  double velocity_scale = 1.0;
};

/// One object at one time.
struct ObjectSample {
  double deformation = 0.0;  ///< Taylor D
  double theta_rad = 0.0;    ///< orientation in the shear plane
  /// In the frame the caller chooses: softflow's runs take it relative to
  /// the undisturbed shear flow at the centre.
  Eigen::Vector3d centre_velocity = Eigen::Vector3d::Zero();
};

/// The largest change over the window of each quantity, over the objects:
/// max - min over the window's samples.
struct SteadyChanges {
  double deformation = 0.0;  ///< of D
  /// Of the in-plane shape vector D (cos 2 theta, sin 2 theta), the larger
  /// component's: the orientation weighted by how deformed the object is, so
  /// that a near-sphere, whose theta is not defined, does not hold a run.
  /// At D = 0.1 a change of 1e-4 is a rotation of 5e-4 rad (0.03 deg).
  double shape = 0.0;
  double theta_rad = 0.0;  ///< of theta itself (reported, not tested)
  double velocity = 0.0;   ///< of any centre-velocity component, over velocity_scale
};

/// Watches the objects' samples step by step and says when every object's
/// D, shape vector and centre velocity have each changed by at most the
/// tolerance over a whole window (the samples from the last one at or before
/// t - window to t). Time-step independent: a smaller dt only adds samples.
class SteadyStateMonitor {
 public:
  struct Sample {
    double time = 0.0;
    std::vector<ObjectSample> objects;
  };

  /// Throws softflow::Error for a tolerance, window or scale that is not > 0.
  explicit SteadyStateMonitor(const SteadyCriterion& criterion);

  /// Adds the state at `time` (later than every earlier sample, the same
  /// number of objects) and drops the samples the window no longer needs.
  void add(double time, std::vector<ObjectSample> objects);

  /// True once the samples span a whole window and every change is within
  /// the tolerance.
  [[nodiscard]] bool steady() const;
  /// The time of the first sample at which steady() held; stays set.
  [[nodiscard]] std::optional<double> reached_at() const { return reached_at_; }
  /// The changes over the current window (zero with fewer than two samples).
  [[nodiscard]] SteadyChanges changes() const;
  [[nodiscard]] const SteadyCriterion& criterion() const { return criterion_; }

  /// The samples the window holds, oldest first, for checkpoints: a monitor
  /// restored from them (restore) decides exactly as the original would.
  [[nodiscard]] const std::deque<Sample>& samples() const { return samples_; }
  void restore(std::deque<Sample> samples, std::optional<double> reached_at);

 private:
  [[nodiscard]] bool window_covered() const;

  SteadyCriterion criterion_;
  std::deque<Sample> samples_;
  std::optional<double> reached_at_;
};

}  // namespace softflow::analysis
