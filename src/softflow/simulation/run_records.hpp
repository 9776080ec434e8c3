// What a run in time tells: summary.json, progress.json, the theory beside the results,
// the planned steps, and advice on failures.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_ledger.hpp"

namespace softflow::simulation {

/// The last checkpoint written (for records and messages).
struct CheckpointMark {
  int step = -1;  ///< -1: none written
  double time = 0.0;
};

std::string format_duration(double seconds);

nlohmann::json theory_json(const io::CaseConfig& config);

/// summary.json: final values, theory, wall time, unknowns, status and why.
nlohmann::json make_summary(const io::CaseConfig& config, const DropSimulation& sim,
                            const RunLedger& ledger, const StepReport& last,
                            const std::string& status, const std::string& stop_reason,
                            const CheckpointMark& checkpoint);

/// Whether a run in time has reached its end: n = round(end / step) steps,
/// or with adaptive steps t = end (to round-off: the last step lands on it).
bool at_end(const io::CaseConfig& config, int steps, double time);

/// The step count for messages: known in advance for constant steps only.
nlohmann::json planned_steps(const io::CaseConfig& config);

/// progress.json: rewritten each step (step, t, D, theta, status, ETA, pid, host).
nlohmann::json progress_json(const StepReport& r, const nlohmann::json& n_steps,
                             const io::CaseConfig& config,
                             const std::string& status, double wall_seconds, double eta_seconds,
                             const CheckpointMark& checkpoint);

/// Why a failed run has no checkpoint, and which key changes that: advice
/// only where the key is not already set so.
std::string no_checkpoint_advice(const io::CaseConfig& config, const std::string& failure);

}  // namespace softflow::simulation
