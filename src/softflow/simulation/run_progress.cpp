#include "softflow/simulation/run_progress.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "softflow/simulation/run_records.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

SessionPace::SessionPace(const io::CaseConfig& config, int first_step, bool adaptive)
    : config_(config), n_steps_(planned_steps(config)), first_step_(first_step), adaptive_(adaptive) {}

double SessionPace::eta(const StepReport& last, double elapsed) {
  if (last.step == first_step_ + 1) {
    first_step_seconds_ = elapsed;
    first_step_time_ = last.time;
  }
  const int later_steps = last.step - first_step_ - 1;
  if (later_steps == 0) return std::numeric_limits<double>::quiet_NaN();
  if (adaptive_)
    return (elapsed - first_step_seconds_) / (last.time - first_step_time_) *
           (config_.time.end - last.time);
  return (elapsed - first_step_seconds_) / later_steps *
         static_cast<double>(n_steps_.get<long>() - last.step);
}

void print_step(const StepReport& last, const nlohmann::json& n_steps, double eta) {
  std::string state;
  if (!last.objects.empty())
    state = fmt::format("D = {:.5f}  theta = {:6.2f} deg", last.objects.front().deformation,
                        last.objects.front().theta_deg);
  else if (!last.stresses.empty())
    state = fmt::format("tau_xy = {:.5g}  N1 = {:.5g}", last.stresses.front().mean(0, 1),
                        last.stresses.front().first_normal_stress_difference());
  fmt::print("step {:>6}{}  t = {:8.4f}  {}  dt = {:g}  quality {:.3f}  ETA {}\n", last.step,
             n_steps.is_null() ? std::string() : fmt::format("/{}", n_steps.get<long>()), last.time,
             state, last.dt, last.min_quality, format_duration(eta));
  std::fflush(stdout);
}

void print_steady(const StepReport& last, const analysis::SteadyStateMonitor& steady,
                  const io::CaseConfig& config) {
  const auto c = steady.changes();
  fmt::print("steady state at t = {:.4f}: over the last {:g} time units D changed by {:.2g}, theta "
             "by {:.2g} deg, the centre velocity by {:.2g} gamma_dot R (time.steady_tolerance = "
             "{:g})\n",
             last.time, config.time.steady_window, c.deformation,
             c.theta_rad * 180.0 / std::numbers::pi, c.velocity, config.time.steady_tolerance);
  std::fflush(stdout);
}

CheckpointSchedule::CheckpointSchedule(const io::CaseConfig& config, const RunOptions& options)
    : config_(config), options_(options) {}

bool CheckpointSchedule::due(int steps) const {
  const auto& c = config_.checkpoint;
  return (c.interval_steps > 0 && steps % c.interval_steps == 0) ||
         (c.interval_minutes > 0 && seconds_since(last_checkpoint_) >= 60.0 * c.interval_minutes);
}

bool CheckpointSchedule::limit_near() const {
  return options_.wall_time_limit &&
         seconds_since(options_.started) + 1.5 * longest_step_ + 2.0 * checkpoint_seconds_ + 1.0 >
             *options_.wall_time_limit;
}

void CheckpointSchedule::record_step(double step_seconds) {
  longest_step_ = std::max(longest_step_, step_seconds);
}

void CheckpointSchedule::record_checkpoint(double seconds) {
  checkpoint_seconds_ = seconds;
  last_checkpoint_ = std::chrono::steady_clock::now();
}

}  // namespace softflow::simulation
