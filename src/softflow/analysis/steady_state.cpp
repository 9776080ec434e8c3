#include "softflow/analysis/steady_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::analysis {

namespace {

/// max - min of f(sample, object) over the samples, for one object.
template <class F>
double spread(const std::deque<SteadyStateMonitor::Sample>& samples, std::size_t object, F f) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : samples) {
    const double v = f(s.objects[object]);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  return hi - lo;
}

}  // namespace

SteadyStateMonitor::SteadyStateMonitor(const SteadyCriterion& criterion) : criterion_(criterion) {
  const auto positive = [](double x, const char* what) {
    if (!(x > 0.0) || !std::isfinite(x))
      throw Error(fmt::format("SteadyStateMonitor: the {} must be finite and > 0, not {}", what, x));
  };
  positive(criterion.tolerance, "tolerance");
  positive(criterion.window, "window");
  positive(criterion.velocity_scale, "velocity scale");
}

void SteadyStateMonitor::add(double time, std::vector<ObjectSample> objects) {
  if (!samples_.empty()) {
    if (!(time > samples_.back().time))
      throw Error(fmt::format("SteadyStateMonitor: sample at t = {} after one at t = {}", time,
                              samples_.back().time));
    if (objects.size() != samples_.back().objects.size())
      throw Error(fmt::format("SteadyStateMonitor: {} objects after {}", objects.size(),
                              samples_.back().objects.size()));
  }
  samples_.push_back({time, std::move(objects)});
  // Keep the last sample at or before time - window: it is where the window starts.
  const double start = time - criterion_.window;
  while (samples_.size() > 2 && samples_[1].time <= start) samples_.pop_front();
  if (!reached_at_ && steady()) reached_at_ = time;
}

bool SteadyStateMonitor::window_covered() const {
  // Sample times are sums of steps: allow their round-off.
  return samples_.size() >= 2 && samples_.back().time - samples_.front().time >=
                                     criterion_.window * (1.0 - 1e-9);
}

SteadyChanges SteadyStateMonitor::changes() const {
  SteadyChanges c;
  if (samples_.size() < 2) return c;
  for (std::size_t k = 0; k < samples_.front().objects.size(); ++k) {
    c.deformation = std::max(c.deformation,
                             spread(samples_, k, [](const ObjectSample& o) { return o.deformation; }));
    c.shape = std::max({c.shape, spread(samples_, k, [](const ObjectSample& o) {
                          return o.deformation * std::cos(2.0 * o.theta_rad);
                        }),
                        spread(samples_, k, [](const ObjectSample& o) {
                          return o.deformation * std::sin(2.0 * o.theta_rad);
                        })});
    c.theta_rad =
        std::max(c.theta_rad, spread(samples_, k, [](const ObjectSample& o) { return o.theta_rad; }));
    for (int d = 0; d < 3; ++d)
      c.velocity = std::max(c.velocity, spread(samples_, k, [d](const ObjectSample& o) {
                              return o.centre_velocity(d);
                            }) / criterion_.velocity_scale);
  }
  return c;
}

bool SteadyStateMonitor::steady() const {
  if (!window_covered()) return false;
  const SteadyChanges c = changes();
  const double tol = criterion_.tolerance;
  return c.deformation <= tol && c.shape <= tol && c.velocity <= tol;
}

void SteadyStateMonitor::restore(std::deque<Sample> samples, std::optional<double> reached_at) {
  samples_ = std::move(samples);
  reached_at_ = reached_at;
}

}  // namespace softflow::analysis
