#include "softflow/time/bdf.hpp"

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::time {

namespace {

void check(int order, double dt, double dt_previous) {
  if (order != 1 && order != 2)
    throw Error(fmt::format("BDF of order {}: only orders 1 and 2 are implemented", order));
  if (!(dt > 0.0) || (order == 2 && !(dt_previous > 0.0)))
    throw Error(fmt::format("BDF{}: time steps must be positive (dt = {}, previous dt = {})", order,
                            dt, dt_previous));
}

}  // namespace

int bdf_order(int steps_done) { return steps_done == 0 ? 1 : 2; }

BdfCoefficients bdf(int order) { return bdf(order, 1.0, 1.0); }

BdfCoefficients bdf(int order, double dt, double dt_previous) {
  check(order, dt, dt_previous);
  if (order == 1) return {1.0, -1.0, 0.0};  // eq. 2.48
  // Differentiate the quadratic through (t_{n-1}, u_{n-1}), (t_n, u_n),
  // (t_{n+1}, u_{n+1}) at t_{n+1}. At w = 1 every coefficient is exact in
  // binary (3/2, -2, 1/2), so constant steps reproduce eq. 2.50 bit for bit.
  const double w = dt / dt_previous;
  return {(1.0 + 2.0 * w) / (1.0 + w), -(1.0 + w), w * w / (1.0 + w)};
}

Extrapolation extrapolation(int order) { return extrapolation(order, 1.0, 1.0); }

Extrapolation extrapolation(int order, double dt, double dt_previous) {
  check(order, dt, dt_previous);
  if (order == 1) return {1.0, 0.0};  // eq. 2.47: x_hat = x_n
  // The line through (t_{n-1}, x_{n-1}), (t_n, x_n) at t_{n+1}; eq. 2.49 at w = 1.
  const double w = dt / dt_previous;
  return {1.0 + w, -w};
}

}  // namespace softflow::time
