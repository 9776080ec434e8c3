// Adaptive time steps: accept or reject a step from its error estimate and
// choose the next step size.
#pragma once

namespace softflow::time {

struct StepControllerSettings {
  /// The error estimate each step should stay below (> 0).
  double tolerance = 1e-3;
  /// The estimate's order in dt: it scales as dt^order. 2 for the
  /// distance between the linear predictor (eq. 2.49) and the corrected
  /// interface (eq. 2.50), whose leading term is dt^2 x''/2 (1 + dt_n/dt_{n-1}).
  double estimate_order = 2.0;
  /// Largest ratio of one step to the one before. Variable-step BDF2 is
  /// zero-stable for ratios below 1 + sqrt(2); 2 leaves a margin.
  double max_growth = 2.0;
  /// Smallest ratio after a rejection or a failure (a failed step halves).
  double min_shrink = 0.2;
  /// Aim below the tolerance, so that the next step is rarely rejected.
  double safety = 0.9;
  /// Bounds on the step (max_step = 0: no upper bound but max_growth).
  double min_step = 0.0;
  double max_step = 0.0;
};

/// The decision on one step and the size of the next attempt.
struct StepDecision {
  bool accepted = true;
  double next_step = 0.0;
};

/// The elementary controller dt_new = dt * safety * (tol / err)^(1/order),
/// limited to [min_shrink, max_growth] times dt and to [min_step, max_step]:
/// a step whose estimate exceeds the tolerance is rejected and retried at
/// the smaller size. A step that failed outright (a solver failure, a
/// degraded mesh) is retried at half the size. Stateless beyond its
/// settings, so that a restarted run decides exactly as the original.
class StepController {
 public:
  /// Throws softflow::Error if a setting is out of range (tolerance <= 0,
  /// max_growth <= 1, a min_step above max_step...).
  explicit StepController(const StepControllerSettings& settings);

  /// The decision for a step of size dt whose error estimate is `estimate`
  /// (>= 0; NaN or infinity count as a failure).
  [[nodiscard]] StepDecision judge(double dt, double estimate) const;
  /// The retry after a step of size dt failed: dt / 2, or nothing below
  /// min_step (next_step = 0: give up).
  [[nodiscard]] StepDecision after_failure(double dt) const;

  [[nodiscard]] const StepControllerSettings& settings() const { return settings_; }

 private:
  [[nodiscard]] double bounded(double dt) const;
  StepControllerSettings settings_;
};

/// The size planned for the step after an accepted one. `taken` may be
/// shorter than `planned` (cut to land on the end or a jump of the flow):
/// then a proposal that would let it grow keeps the planned size (a short
/// step's small estimate says nothing against it); otherwise the proposal.
[[nodiscard]] double next_planned_step(double planned, double taken, double proposed);

}  // namespace softflow::time
