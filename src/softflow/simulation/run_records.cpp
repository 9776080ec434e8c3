#include "softflow/simulation/run_records.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <unistd.h>

#include <fmt/format.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/report_tables.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds)) return "--";  // not known yet
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}h{:02d}m", s / 3600, (s % 3600) / 60);
  if (s >= 60) return fmt::format("{}m{:02d}s", s / 60, s % 60);
  return fmt::format("{}s", s);
}

nlohmann::json theory_json(const io::CaseConfig& config) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < config.objects.size(); ++k) {
    const auto& o = config.objects[k];
    const double ca = io::capillary_number(config, o);
    if (!std::isfinite(ca)) continue;  // no tension: no small-deformation theory
    out.push_back({{"object", k + 1},
                   {"capillary_number", ca},
                   {"viscosity_ratio", o.viscosity_ratio},
                   {"slip", o.slip},
                   // Taylor's D, generalised to a slipping interface (SPEC §10).
                   {"taylor_D", analysis::theory::slip_taylor_deformation(o.viscosity_ratio, ca, o.slip)},
                   {"chaffey_brenner_theta_deg",
                    analysis::theory::chaffey_brenner_angle_deg(o.viscosity_ratio, ca)}});
  }
  return out;
}

nlohmann::json make_summary(const io::CaseConfig& config, const DropSimulation& sim,
                            const RunLedger& ledger, const StepReport& last,
                            const std::string& status, const std::string& stop_reason,
                            const CheckpointMark& checkpoint) {
  nlohmann::json summary = {
      {"softflow_version", SOFTFLOW_VERSION},
      {"case", config.name},
      {"status", status},
      {"mpi_ranks", la::mpi_size()},
      {"mesh", ledger.mesh_report},
      {"dimensionless_groups", io::to_json(io::dimensionless_groups(config))},
      {"unknowns", sim.stokes().dofs().n_dofs()},
      {"steps", sim.steps()},
      {"time", sim.time()},
      {"dt", config.time.step},
      {"theory", theory_json(config)},
      {"wall_seconds", ledger.wall_seconds},
      {"sessions", ledger.sessions},
  };
  if (!stop_reason.empty()) summary["stop_reason"] = stop_reason;
  if (!ledger.warnings.empty()) summary["warnings"] = ledger.warnings;
  summary["last_checkpoint"] =
      checkpoint.step >= 0 ? nlohmann::json{{"step", checkpoint.step}, {"time", checkpoint.time}}
                           : nlohmann::json(nullptr);
  const double per_step = ledger.timed_steps > 0 ? 1.0 / ledger.timed_steps : 0.0;
  const auto& total = ledger.total;
  summary["seconds_per_step"] = {{"predict_and_translate", total.predict_and_translate * per_step},
                                 {"ale", total.ale * per_step},
                                 {"stokes_assembly", total.stokes_assembly * per_step},
                                 {"stokes_solve", total.stokes_solve * per_step},
                                 {"conformation", total.conformation * per_step},
                                 {"correct_interface", total.correct * per_step},
                                 {"analysis", total.analysis * per_step}};
  summary["stokes_iterations_per_step"] = static_cast<double>(ledger.stokes_iterations) * per_step;
  summary["stokes_solver"] =
      sim.stokes().settings().method == la::SaddlePointMethod::direct ? "direct" : "iterative";
  summary["stokes_solver_reason"] = sim.stokes().method_reason();
  if (config.time.end > 0.0) summary["time_steps"] = steps_json(config);
  summary["stokes_factorizations"] = sim.stokes().n_factorizations();
  summary["ale_rebuilds"] = sim.ale_rebuilds();
  summary["relocation_steps"] = sim.relocation_steps();
  summary["relocated_nodes"] = sim.relocated_nodes();
  // Every object's last timeseries.csv row, from the column declarations
  // (the step's solver and timing columns left out: they describe the step,
  // not the object), and its volume drift.
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& o : last.objects) {
    nlohmann::json entry = timeseries_table().json_row(
        {last, o}, {"step", "t", "min_quality", "stokes_iterations", "step_seconds", "dt",
                    "interface_change"});
    const double v0 = sim.initial_volumes().at(o.object - 1);
    entry["volume_drift"] = v0 > 0 ? o.volume / v0 - 1.0 : 0.0;
    objects.push_back(std::move(entry));
  }
  summary["final"] = objects;
  if (ledger.steady) summary["steady"] = steady_json(*ledger.steady);
  if (ledger.adaptive) {
    const auto& a = *ledger.adaptive;
    summary["adaptive"] = {{"tolerance", config.time.adaptive_tolerance},
                           {"accepted", sim.steps()},
                           {"rejected", a.rejected},
                           {"failed", a.failed},
                           {"smallest_step", std::isfinite(a.smallest) ? nlohmann::json(a.smallest)
                                                                       : nlohmann::json()},
                           {"largest_step", a.largest},
                           {"step_bound", adaptive_step_bound(config)},
                           {"next_step", a.next_step}};
  }
  sim.summarise(summary);  // each module its own final values
  return summary;
}

/// Whether a run in time has reached its end: n = round(end / step) steps,
/// or with adaptive steps t = end (to round-off: the last step lands on it).
bool at_end(const io::CaseConfig& config, int steps, double time) {
  if (config.time.adaptive_tolerance > 0.0) return time >= config.time.end * (1.0 - 1e-12);
  return steps >= static_cast<int>(std::lround(config.time.end / config.time.step));
}

/// The step count for messages: known in advance for constant steps only.
nlohmann::json planned_steps(const io::CaseConfig& config) {
  if (config.time.adaptive_tolerance > 0.0) return nullptr;
  return std::lround(config.time.end / config.time.step);
}

nlohmann::json progress_json(const StepReport& r, const nlohmann::json& n_steps,
                             const io::CaseConfig& config,
                             const std::string& status, double wall_seconds, double eta_seconds,
                             const CheckpointMark& checkpoint) {
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& o : r.objects)
    objects.push_back({{"object", o.object}, {"D", o.deformation}, {"theta_deg", o.theta_deg}});
  nlohmann::json j = {{"status", status},          {"step", r.step},
                      {"steps", n_steps},          {"t", r.time},
                      {"t_end", config.time.end},  {"dt", r.dt > 0.0 ? r.dt : config.time.step},
                      {"objects", objects},        {"wall_seconds", wall_seconds},
                      {"eta_seconds", std::isfinite(eta_seconds) ? nlohmann::json(eta_seconds)
                                                                 : nlohmann::json(nullptr)},
                      {"pid", static_cast<long>(::getpid())},
                      {"host", host_name()}};
  // The first object's D and theta at the top level: what a batch script greps for.
  if (!r.objects.empty()) {
    j["D"] = r.objects.front().deformation;
    j["theta_deg"] = r.objects.front().theta_deg;
  }
  j["last_checkpoint"] = checkpoint.step >= 0
                             ? nlohmann::json{{"step", checkpoint.step}, {"time", checkpoint.time}}
                             : nlohmann::json(nullptr);
  return j;
}

/// Why a failed run has no checkpoint, and which key changes that: advice
/// only where the key is not already set so.
std::string no_checkpoint_advice(const io::CaseConfig& config, const std::string& failure) {
  if (failure.find("cannot write the checkpoint") != std::string::npos) return "";
  if (config.checkpoint.interval_steps > 0)
    return fmt::format(": it failed before step {}, the first checkpoint [checkpoint] "
                       "interval_steps = {} asks for",
                       config.checkpoint.interval_steps, config.checkpoint.interval_steps);
  if (config.checkpoint.interval_minutes > 0)
    return fmt::format(": checkpoints come every {:g} minutes ([checkpoint] interval_minutes); "
                       "[checkpoint] interval_steps adds one every so many steps",
                       config.checkpoint.interval_minutes);
  return ": [checkpoint] interval_steps or interval_minutes sets how often";
}

}  // namespace softflow::simulation
