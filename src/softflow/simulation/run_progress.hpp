// A session of a run in time as the user follows it: the pace and the time still
// to go, the console's step and steady-state lines, when a checkpoint is due.
#pragma once

#include <chrono>
#include <optional>

#include <nlohmann/json.hpp>

#include "softflow/analysis/steady_state.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/stokes_run.hpp"

namespace softflow::simulation {

/// The time still to go, from the pace of this session's steps after its
/// first: the first carries one-off costs (the first LU factorisation, a
/// restart's refactorisation), so the estimate is unknown (NaN) until a
/// second step. Constant steps: the steps to go at the later steps' pace;
/// adaptive steps: the time to go at the pace simulated time advanced.
class SessionPace {
 public:
  SessionPace(const io::CaseConfig& config, int first_step, bool adaptive);
  /// After each step, `elapsed` seconds into the session: seconds to go.
  double eta(const StepReport& last, double elapsed);

 private:
  const io::CaseConfig& config_;
  nlohmann::json n_steps_;
  int first_step_;
  bool adaptive_;
  double first_step_seconds_ = 0.0, first_step_time_ = 0.0;
};

/// The console's line for a step: step (of n), t, the first object's D and
/// theta (no objects: the matrix's mean tau_xy and N1), dt, quality, ETA.
void print_step(const StepReport& last, const nlohmann::json& n_steps, double eta);
/// The console's line when the steady state is reached.
void print_steady(const StepReport& last, const analysis::SteadyStateMonitor& steady,
                  const io::CaseConfig& config);

/// When a session writes checkpoints: every [checkpoint] interval_steps
/// steps and interval_minutes apart; and when it must stop before the
/// wall-time limit, with room for the longest step seen and two checkpoint
/// writes (the next may be slower than the last).
class CheckpointSchedule {
 public:
  CheckpointSchedule(const io::CaseConfig& config, const RunOptions& options);
  /// After a step of `step_seconds`: whether a checkpoint is due at `steps`.
  [[nodiscard]] bool due(int steps) const;
  /// Whether the wall-time limit is near (this rank's view).
  [[nodiscard]] bool limit_near() const;
  void record_step(double step_seconds);
  void record_checkpoint(double seconds);
  [[nodiscard]] double last_checkpoint_seconds() const { return checkpoint_seconds_; }

 private:
  using Clock = std::chrono::steady_clock;
  const io::CaseConfig& config_;
  const RunOptions& options_;
  Clock::time_point last_checkpoint_ = Clock::now();
  double longest_step_ = 0.0, checkpoint_seconds_ = 0.0;
};

}  // namespace softflow::simulation
