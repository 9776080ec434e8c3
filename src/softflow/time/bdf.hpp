// Backward differentiation formulas (Gear) of order 1 and 2, and the
// predictor's extrapolation: the one place that knows their coefficients.
//
// With steps dt = t_{n+1} - t_n and dt_previous = t_n - t_{n-1}, and
// w = dt / dt_previous,
//   BDF1:  u'(t_{n+1}) ~ (u_{n+1} - u_n) / dt
//   BDF2:  u'(t_{n+1}) ~ ( (1+2w)/(1+w) u_{n+1} - (1+w) u_n + w^2/(1+w) u_{n-1} ) / dt
// which for a constant step (w = 1) is (3/2 u_{n+1} - 2 u_n + 1/2 u_{n-1}) / dt,
// the thesis's Gear scheme (eqs. 2.48, 2.50). Solving u' = f(u_{n+1}) then
// reads u_{n+1} = -(a1 u_n + a2 u_{n-1}) / a0 + theta dt f with theta = 1/a0:
// 1 for BDF1, 2/3 for constant-step BDF2.
//
// The predictor extrapolates the last two levels linearly to t_{n+1}:
//   x_hat = x_n (order 1, eq. 2.47), x_hat = (1+w) x_n - w x_{n-1} (order 2;
//   2 x_n - x_{n-1} at a constant step, eq. 2.49).
#pragma once

namespace softflow::time {

/// The order of the step that follows `steps_done` completed steps: 1 at
/// the first (only u_0 is known), 2 after. Every BDF user in softflow
/// starts this way, so that a restart from a checkpoint continues alike.
[[nodiscard]] int bdf_order(int steps_done);

/// u'(t_{n+1}) ~ (a0 u_{n+1} + a1 u_n + a2 u_{n-1}) / dt, dt = t_{n+1} - t_n.
struct BdfCoefficients {
  double a0 = 1.0;
  double a1 = -1.0;
  double a2 = 0.0;  ///< 0 for BDF1: u_{n-1} is not needed

  /// theta = 1 / a0: u_{n+1} = history + theta dt f.
  [[nodiscard]] double theta() const { return 1.0 / a0; }
  /// theta dt, formed as dt / a0 rather than theta() * dt: one rounding, so
  /// that constant-step BDF2 gives 2 dt / 3 to the last bit.
  [[nodiscard]] double theta_dt(double dt) const { return dt / a0; }
  friend bool operator==(const BdfCoefficients&, const BdfCoefficients&) = default;
};

/// BDF coefficients of order 1 or 2 for a constant step.
[[nodiscard]] BdfCoefficients bdf(int order);
/// BDF coefficients of order 1 or 2 for a step dt after a step dt_previous
/// (dt_previous is not used by order 1). Throws softflow::Error for another
/// order or a step that is not positive.
[[nodiscard]] BdfCoefficients bdf(int order, double dt, double dt_previous);

/// x_hat_{n+1} = current x_n + previous x_{n-1}.
struct Extrapolation {
  double current = 1.0;
  double previous = 0.0;

  friend bool operator==(const Extrapolation&, const Extrapolation&) = default;
};

/// The predictor of a step of the given BDF order, constant step.
[[nodiscard]] Extrapolation extrapolation(int order);
/// The predictor of a step dt after a step dt_previous (variable step).
[[nodiscard]] Extrapolation extrapolation(int order, double dt, double dt_previous);

}  // namespace softflow::time
