#include "softflow/simulation/drop_run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <limits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <numbers>
#include <optional>
#include <deque>
#include <set>
#include <sstream>
#include <string>

#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>
#include <mpi.h>

#include "softflow/analysis/steady_state.hpp"
#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"
#include "softflow/simulation/stop_requests.hpp"
#include "softflow/time/step_controller.hpp"

namespace softflow::simulation {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

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

/// True on every rank if true on any: all ranks must take the same branch.
bool on_any_rank(bool local) {
  int l = local ? 1 : 0, any = 0;
  MPI_Allreduce(&l, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return any != 0;
}

// ---------------------------------------------------------------------------
// What a run accumulates across restarts (saved in the checkpoint's run_json).

/// The state of adaptive stepping between steps.
struct AdaptiveSteps {
  double next_step = 0.0;  ///< the size the next step tries first
  int rejected = 0;        ///< steps taken again smaller: estimate above the tolerance
  int failed = 0;          ///< steps taken again smaller: solver or mesh failure
  double smallest = std::numeric_limits<double>::infinity();  ///< accepted steps' extremes
  double largest = 0.0;
};

std::optional<AdaptiveSteps> adaptive_steps(const io::CaseConfig& config) {
  if (!(config.time.adaptive_tolerance > 0.0)) return std::nullopt;
  AdaptiveSteps a;
  a.next_step = config.time.step;
  return a;
}

/// The largest adaptive step: time.max_step, and the stability bound of the
/// tangential redistribution. Its velocity u_t = k grad_s c is evaluated on
/// the extrapolated surface, and to first order it relaxes the node
/// distribution at the rate k whatever the wavelength (-lap_s c = 1 - 1/g ~
/// div_s of the tangential displacement); BDF2 with a linearly extrapolated
/// term is stable for k dt <= 4/3 and at the bound oscillates from step to
/// step, which is what adaptive runs of the main example showed above
/// dt ~ 0.13 at k = 10. 1/k keeps a margin for changing steps.
double adaptive_step_bound(const io::CaseConfig& config) {
  double bound = config.time.max_step;
  const double k = redistribution_rate(config);
  if (k > 0.0) bound = bound > 0.0 ? std::min(bound, 1.0 / k) : 1.0 / k;
  return std::max(bound, config.time.step);  // never below the first step
}

time::StepController step_controller(const io::CaseConfig& config) {
  time::StepControllerSettings s;
  s.tolerance = config.time.adaptive_tolerance;
  s.max_growth = config.time.max_growth;
  s.max_step = adaptive_step_bound(config);
  s.min_step = config.time.step / 1000.0;
  return time::StepController(s);
}

nlohmann::json adaptive_json(const AdaptiveSteps& a) {
  return {{"next_step", a.next_step},
          {"rejected", a.rejected},
          {"failed", a.failed},
          {"smallest", std::isfinite(a.smallest) ? nlohmann::json(a.smallest) : nlohmann::json()},
          {"largest", a.largest}};
}

AdaptiveSteps adaptive_from_json(const nlohmann::json& j) {
  AdaptiveSteps a;
  a.next_step = j.at("next_step");
  a.rejected = j.at("rejected");
  a.failed = j.at("failed");
  a.smallest = j.at("smallest").is_null() ? std::numeric_limits<double>::infinity()
                                          : j.at("smallest").get<double>();
  a.largest = j.at("largest");
  return a;
}

struct RunLedger {
  StageSeconds total;
  long stokes_iterations = 0;
  int timed_steps = 0;        ///< steps whose timings are in `total`
  double wall_seconds = 0.0;  ///< up to the last checkpoint of earlier sessions
  int sessions = 1;
  nlohmann::json mesh_report;
  /// Watches for the steady state when time.steady_tolerance > 0; its window
  /// is saved with the checkpoint, so a restarted run stops at the same step.
  std::optional<analysis::SteadyStateMonitor> steady;
  /// Adaptive steps (time.adaptive_tolerance > 0): saved with the
  /// checkpoint, so a restarted run takes the same steps.
  std::optional<AdaptiveSteps> adaptive;
  /// What a reader of the results must know (e.g. rows of the time series
  /// lost before a restart); in summary.json, kept across restarts.
  std::vector<std::string> warnings;
};

/// The monitor of time.steady_tolerance, or none. Centre velocities are
/// compared in units of gamma_dot R, R the smallest object's radius
/// (gamma_dot = 1 for a static case, e.g. a drop relaxing at rest).
std::optional<analysis::SteadyStateMonitor> steady_monitor(const io::CaseConfig& config) {
  if (!(config.time.steady_tolerance > 0.0)) return std::nullopt;
  double radius = std::numeric_limits<double>::infinity();
  for (const auto& o : config.objects) radius = std::min(radius, io::mean_radius(o.geometry));
  const double rate = config.shear_rate > 0.0 ? config.shear_rate : 1.0;
  return analysis::SteadyStateMonitor(
      {config.time.steady_tolerance, config.time.steady_window, rate * radius});
}

/// The objects' state for the monitor. The centre velocity is taken
/// relative to the undisturbed shear flow at the centre, gamma_dot(t) y_c e_x:
/// an object that drifts across the streamlines at a steady rate (migration,
/// or the slow spurious drift of an unsymmetric mesh) then has a steady
/// velocity, where its absolute x-velocity would grow with its y.
std::vector<analysis::ObjectSample> steady_sample(const StepReport& r,
                                                  const physics::WallMotion& walls) {
  std::vector<analysis::ObjectSample> out;
  for (const auto& o : r.objects) {
    Eigen::Vector3d relative = o.centre_velocity;
    relative.x() -= walls.shear_rate(r.time) * o.centre.y();
    // An undefined orientation (a sphere) adds nothing to the shape vector.
    const double theta = std::isnan(o.theta_deg) ? 0.0 : o.theta_deg * std::numbers::pi / 180.0;
    out.push_back({o.deformation, theta, relative});
  }
  return out;
}

nlohmann::json steady_samples_json(const analysis::SteadyStateMonitor& m) {
  nlohmann::json samples = nlohmann::json::array();
  for (const auto& s : m.samples()) {
    nlohmann::json objects = nlohmann::json::array();
    for (const auto& o : s.objects)
      objects.push_back({o.deformation, o.theta_rad, o.centre_velocity(0), o.centre_velocity(1),
                         o.centre_velocity(2)});
    samples.push_back({s.time, objects});
  }
  return {{"samples", samples},
          {"reached_at", m.reached_at() ? nlohmann::json(*m.reached_at()) : nlohmann::json()}};
}

void restore_steady_samples(analysis::SteadyStateMonitor& m, const nlohmann::json& j) {
  std::deque<analysis::SteadyStateMonitor::Sample> samples;
  for (const auto& s : j.at("samples")) {
    analysis::SteadyStateMonitor::Sample sample{s.at(0).get<double>(), {}};
    for (const auto& o : s.at(1))
      sample.objects.push_back({o.at(0).get<double>(), o.at(1).get<double>(),
                                {o.at(2).get<double>(), o.at(3).get<double>(),
                                 o.at(4).get<double>()}});
    samples.push_back(std::move(sample));
  }
  const auto& reached = j.at("reached_at");
  m.restore(std::move(samples),
            reached.is_null() ? std::nullopt : std::optional<double>(reached.get<double>()));
}

/// What summary.json says about the steady state (runs that watch for it).
nlohmann::json steady_json(const analysis::SteadyStateMonitor& m) {
  const auto c = m.changes();
  return {{"tolerance", m.criterion().tolerance},
          {"window", m.criterion().window},
          {"reached", m.reached_at().has_value()},
          {"time", m.reached_at() ? nlohmann::json(*m.reached_at()) : nlohmann::json()},
          {"changes_over_window",
           {{"D", c.deformation},
            {"shape", c.shape},
            {"theta_deg", c.theta_rad * 180.0 / std::numbers::pi},
            {"centre_velocity", c.velocity}}}};
}

nlohmann::json to_json(const RunLedger& l) {
  return {{"stage_seconds",
           {l.total.predict_and_translate, l.total.ale, l.total.stokes_assembly,
            l.total.stokes_solve, l.total.correct, l.total.analysis, l.total.conformation}},
          {"stokes_iterations", l.stokes_iterations},
          {"timed_steps", l.timed_steps},
          {"wall_seconds", l.wall_seconds},
          {"sessions", l.sessions},
          {"mesh", l.mesh_report},
          {"steady", l.steady ? steady_samples_json(*l.steady) : nlohmann::json()},
          {"adaptive", l.adaptive ? adaptive_json(*l.adaptive) : nlohmann::json()},
          {"warnings", l.warnings}};
}

RunLedger ledger_from_json(const std::string& text, const io::CaseConfig& config) {
  RunLedger l;
  l.steady = steady_monitor(config);
  l.adaptive = adaptive_steps(config);
  try {
    const auto j = nlohmann::json::parse(text);
    const auto& s = j.at("stage_seconds");
    l.total.predict_and_translate = s.at(0);
    l.total.ale = s.at(1);
    l.total.stokes_assembly = s.at(2);
    l.total.stokes_solve = s.at(3);
    l.total.correct = s.at(4);
    l.total.analysis = s.at(5);
    l.total.conformation = s.size() > 6 ? static_cast<double>(s.at(6)) : 0.0;  // absent before the viscoelastic phases
    l.stokes_iterations = j.at("stokes_iterations");
    l.timed_steps = j.at("timed_steps");
    l.wall_seconds = j.at("wall_seconds");
    l.sessions = j.at("sessions");
    l.mesh_report = j.at("mesh");
    if (l.steady) restore_steady_samples(*l.steady, j.at("steady"));
    if (l.adaptive) l.adaptive = adaptive_from_json(j.at("adaptive"));
    l.warnings = j.value("warnings", std::vector<std::string>{});  // absent before 2026-12-03
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("the checkpoint's run record is damaged: {}", e.what()));
  }
  return l;
}

void add(StageSeconds& total, const StageSeconds& s) {
  total.predict_and_translate += s.predict_and_translate;
  total.ale += s.ale;
  total.stokes_assembly += s.stokes_assembly;
  total.stokes_solve += s.stokes_solve;
  total.correct += s.correct;
  total.analysis += s.analysis;
  total.conformation += s.conformation;
}

/// The files a run keeps open (rank 0 only).
struct RunFiles {
  std::ofstream series;
  std::ofstream stress;  ///< stress.csv, for runs with viscoelastic phases
  std::ofstream slip;    ///< slip.csv, for runs with interface slip
  std::unique_ptr<io::FieldSeries> fields;
};

/// A failure of the same type with a longer message.
[[noreturn]] void rethrow_with_message(const std::exception_ptr& failure,
                                       const std::string& message) {
  try {
    std::rethrow_exception(failure);
  } catch (const MeshError&) {
    throw MeshError(message);
  } catch (const SolverError&) {
    throw SolverError(message);
  } catch (const AccuracyError&) {
    throw AccuracyError(message);
  } catch (const InputError&) {
    throw InputError(message);
  } catch (const Error&) {
    throw Error(message);
  }
}

struct CheckpointMark {
  int step = -1;  ///< -1: none written
  double time = 0.0;
};

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
  summary["stokes_factorizations"] = sim.stokes().n_factorizations();
  summary["ale_rebuilds"] = sim.ale_rebuilds();
  summary["relocation_steps"] = sim.relocation_steps();
  summary["relocated_nodes"] = sim.relocated_nodes();
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& o : last.objects) {
    const double v0 = sim.initial_volumes().at(o.object - 1);
    objects.push_back({{"object", o.object},
                       {"D", o.deformation},
                       {"theta_deg", o.theta_deg},
                       {"L", o.L},
                       {"B", o.B},
                       {"W", o.W},
                       {"ellipsoid_deviation", o.ellipsoid_deviation},
                       {"volume", o.volume},
                       {"volume_drift", v0 > 0 ? o.volume / v0 - 1.0 : 0.0}});
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
  if (!last.stresses.empty()) {
    nlohmann::json stresses = nlohmann::json::array();
    for (const auto& r : last.stresses)
      stresses.push_back({{"region", r.region},
                          {"tau_mean", {r.mean(0, 0), r.mean(1, 1), r.mean(2, 2), r.mean(0, 1),
                                        r.mean(1, 2), r.mean(0, 2)}},
                          {"N1", r.first_normal_stress_difference()},
                          {"principal", {r.principal(0), r.principal(1), r.principal(2)}},
                          {"spread", r.spread}});
    summary["final_stress"] = stresses;
  }
  if (!last.slips.empty()) {
    nlohmann::json slips = nlohmann::json::array();
    for (std::size_t k = 0; k < last.slips.size(); ++k)
      slips.push_back({{"object", k + 1},
                       {"mean_slip_speed", last.slips[k].mean_slip_speed},
                       {"max_slip_speed", last.slips[k].max_slip_speed},
                       {"slip_dissipation", last.slips[k].dissipation}});
    summary["final_slip"] = slips;
  }
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

/// The size of the next adaptive step from t: the controller's, shortened
/// to land on the end of the run and on a jump of the wall speed (where
/// the BDF histories restart); a last step within 1 % of the end is
/// stretched to it rather than leaving a sliver.
double adaptive_step_size(double proposed, double t, double end, const physics::WallMotion& walls) {
  double dt = proposed;
  if (t + 1.01 * dt >= end) dt = end - t;
  if (const auto jump = walls.jump_time(); jump && *jump > t + 1e-12 * std::max(1.0, std::abs(t)) &&
                                           t + dt > *jump)
    dt = *jump - t;
  return dt;
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

/// The loop from the simulation's current step to time.end, shared by a
/// fresh run and a restart: steps, output, checkpoints, stop requests and
/// failures, then the summary.
nlohmann::json continue_run(const io::CaseConfig& config, const RunOptions& options,
                            const fs::path& directory, DropSimulation& sim, RunLedger ledger,
                            StepReport last, RunFiles& files, CheckpointMark checkpoint) {
  const bool root = is_root();
  const auto session_start = Clock::now();
  const nlohmann::json n_steps = planned_steps(config);
  const bool adaptive = ledger.adaptive.has_value();
  const auto controller = adaptive ? std::optional(step_controller(config)) : std::nullopt;
  const int first_step = sim.steps();
  leave_startup();  // from here a stop request checkpoints after the step
  const physics::WallMotion walls = wall_motion(config);
  auto last_checkpoint_clock = Clock::now();
  double longest_step = 0.0, checkpoint_seconds = 0.0, checkpoint_bytes = 0.0;
  const double earlier_wall_seconds = ledger.wall_seconds;

  auto write_checkpoint = [&] {
    const auto begin = Clock::now();
    RunLedger saved = ledger;
    saved.wall_seconds = earlier_wall_seconds + seconds_since(session_start);
    // Saving is collective (distributed fields gather their values), so every
    // rank saves; only rank 0 writes.
    io::Checkpoint c;
    sim.save(c);
    on_root_sharing_failure([&] {
      c.softflow_version = SOFTFLOW_VERSION;
      c.case_toml = io::to_toml(config);
      c.run_json = to_json(saved).dump();
      io::write_checkpoint(directory / kCheckpointFile, c);
      checkpoint_bytes = static_cast<double>(fs::file_size(directory / kCheckpointFile));
    });
    checkpoint = {sim.steps(), sim.time()};
    last_checkpoint_clock = Clock::now();
    checkpoint_seconds = seconds_since(begin);
  };

  std::string status = "running", stop_reason;
  std::exception_ptr failure;
  double first_step_seconds = 0.0, first_step_time = 0.0;
  try {
    // One accepted step. Adaptive: a step whose estimate exceeds the
    // tolerance, or that fails (solver, mesh quality, an interface that no
    // longer fits), is taken back and tried again smaller.
    auto take_step = [&]() -> StepReport {
      if (!adaptive) return sim.step();
      auto& a = *ledger.adaptive;
      while (true) {
        const double dt = adaptive_step_size(a.next_step, sim.time(), config.time.end, walls);
        const StateRecord before = sim.save_step_state();
        StepReport r;
        time::StepDecision decision;
        std::string why;
        bool failed = false;
        try {
          r = sim.step(dt);
          // A BDF1 step (the first, or the one after a jump) predicts x_n:
          // no estimate (NaN); keep its size.
          decision = std::isnan(r.interface_change) ? time::StepDecision{true, dt}
                                                    : controller->judge(dt, r.interface_change);
          if (!decision.accepted)
            why = fmt::format("estimate {:.3g} > time.adaptive_tolerance = {:g}",
                              r.interface_change, config.time.adaptive_tolerance);
        } catch (const Error& e) {
          if (dynamic_cast<const InputError*>(&e)) throw;
          decision = controller->after_failure(dt);
          if (decision.next_step == 0.0) throw;  // the smallest step failed too
          why = e.what();
          failed = true;
        }
        if (decision.accepted) {
          a.next_step = time::next_planned_step(a.next_step, dt, decision.next_step);
          a.smallest = std::min(a.smallest, dt);
          a.largest = std::max(a.largest, dt);
          return r;
        }
        if (decision.next_step == 0.0)
          throw AccuracyError(fmt::format(
              "step {} (t = {:.4f}): no step down to time.step / 1000 = {:g} meets "
              "time.adaptive_tolerance = {:g} ({}): raise the tolerance or refine the mesh",
              sim.steps() + 1, sim.time(), config.time.step / 1000.0,
              config.time.adaptive_tolerance, why));
        ++(failed ? a.failed : a.rejected);
        sim.restore_step_state(before);
        a.next_step = decision.next_step;
        if (!options.quiet && root) {
          fmt::print("step {} (t = {:.4f}) taken again with dt = {:.4g} instead of {:.4g}: {}\n",
                     sim.steps() + 1, sim.time(), decision.next_step, dt, why);
          std::fflush(stdout);
        }
      }
    };

    while (!at_end(config, sim.steps(), sim.time())) {
      last = take_step();
      add(ledger.total, last.stages);
      ledger.stokes_iterations += last.stokes_iterations;
      ++ledger.timed_steps;
      longest_step = std::max(longest_step, last.step_seconds);
      const double elapsed = seconds_since(session_start);
      // The session's first step carries one-off costs (the first LU
      // factorisation, a restart's refactorisation): the estimate comes from
      // the steps after it, and is unknown ("--", null) until there is one.
      if (last.step == first_step + 1) {
        first_step_seconds = elapsed;
        first_step_time = last.time;
      }
      const int later_steps = last.step - first_step - 1;
      // Constant steps: the steps still to go at the pace of the later ones;
      // adaptive steps: the time still to go at the pace simulated time advanced.
      const double eta =
          later_steps == 0 ? std::numeric_limits<double>::quiet_NaN()
          : adaptive ? (elapsed - first_step_seconds) / (last.time - first_step_time) *
                           (config.time.end - last.time)
                     : (elapsed - first_step_seconds) / later_steps *
                           static_cast<double>(n_steps.get<long>() - last.step);
      // Gathering a field is collective: every rank takes part, rank 0 writes.
      const bool fields_due = config.write_fields && config.time.fields_interval > 0 &&
                              last.step % config.time.fields_interval == 0;
      const auto fields = fields_due ? sim.output_fields() : std::vector<io::FieldData>{};
      on_root_sharing_failure([&] {
        files.series << timeseries_rows(last) << std::flush;
        if (files.stress.is_open()) files.stress << stress_rows(last) << std::flush;
        if (files.slip.is_open()) files.slip << slip_rows(last) << std::flush;
        if (files.fields && fields_due) files.fields->write(sim.mesh(), fields, sim.time(), last.step);
        io::write_text_file_atomically(
            directory / "progress.json",
            progress_json(last, n_steps, config, "running", earlier_wall_seconds + elapsed, eta,
                          checkpoint)
                    .dump(2) +
                "\n");
      });
      if (!options.quiet && root) {
        // The first object's shape, or (no objects) the matrix's mean stress.
        std::string state;
        if (!last.objects.empty())
          state = fmt::format("D = {:.5f}  theta = {:6.2f} deg", last.objects.front().deformation,
                              last.objects.front().theta_deg);
        else if (!last.stresses.empty())
          state = fmt::format("tau_xy = {:.5g}  N1 = {:.5g}", last.stresses.front().mean(0, 1),
                              last.stresses.front().first_normal_stress_difference());
        fmt::print("step {:>6}{}  t = {:8.4f}  {}  dt = {:g}  quality {:.3f}  ETA {}\n",
                   last.step, adaptive ? std::string() : fmt::format("/{}", n_steps.get<long>()),
                   last.time, state, last.dt, last.min_quality, format_duration(eta));
        std::fflush(stdout);
      }
      sim.check_volumes();
      if (ledger.steady) {
        ledger.steady->add(last.time, steady_sample(last, walls));
        if (ledger.steady->reached_at()) {  // set by add() at the first steady sample
          if (!options.quiet && root) {
            const auto c = ledger.steady->changes();
            fmt::print("steady state at t = {:.4f}: over the last {:g} time units D changed by "
                       "{:.2g}, theta by {:.2g} deg, the centre velocity by {:.2g} gamma_dot R "
                       "(time.steady_tolerance = {:g})\n",
                       last.time, config.time.steady_window, c.deformation,
                       c.theta_rad * 180.0 / std::numbers::pi, c.velocity,
                       config.time.steady_tolerance);
            std::fflush(stdout);
          }
          break;  // the final checkpoint follows the loop
        }
      }
      if (at_end(config, sim.steps(), sim.time())) break;  // the final checkpoint follows the loop

      // Stop before the wall-time limit with room for the longest step seen
      // and two checkpoint writes (the next may be slower than the last).
      const bool limit_near =
          options.wall_time_limit &&
          seconds_since(options.started) + 1.5 * longest_step + 2.0 * checkpoint_seconds + 1.0 >
              *options.wall_time_limit;
      const int signal = stop_requested();
      const bool stop = signal != 0 || on_any_rank(limit_near);
      const bool due =
          (config.checkpoint.interval_steps > 0 &&
           sim.steps() % config.checkpoint.interval_steps == 0) ||
          (config.checkpoint.interval_minutes > 0 &&
           seconds_since(last_checkpoint_clock) >= 60.0 * config.checkpoint.interval_minutes);
      if (stop || due) write_checkpoint();
      if (stop) {
        status = "interrupted";
        stop_reason = signal != 0 ? fmt::format("interrupted by {} at step {} (t = {:.4f})",
                                                signal_name(signal), sim.steps(), sim.time())
                                  : fmt::format(
                                        "stopped at step {} (t = {:.4f}) before the wall-time "
                                        "limit of {:g} s",
                                        sim.steps(), sim.time(), *options.wall_time_limit);
        break;
      }
    }
    if (status == "running") {
      write_checkpoint();  // lets a later, longer run continue from the end
      status = "completed";
    }
  } catch (const Error& e) {
    failure = std::current_exception();
    status = "stopped";
    stop_reason = e.what();
    stop_reason += checkpoint.step >= 0
                       ? fmt::format(
                             ". The last checkpoint (step {}, t = {:.4f}) and the output "
                             "so far are in {}",
                             checkpoint.step, checkpoint.time, directory.string())
                       : fmt::format(
                             ". The output so far is in {} (no checkpoint was written{})",
                             directory.string(), no_checkpoint_advice(config, stop_reason));
  }

  ledger.wall_seconds = earlier_wall_seconds + seconds_since(session_start);
  auto summary = make_summary(config, sim, ledger, last, status, stop_reason, checkpoint);
  summary["peak_memory_mb"] = peak_memory_summary();  // collective
  if (checkpoint_bytes > 0)  // what a checkpoint costs: the last one written in this session
    summary["checkpoint_cost"] = {{"bytes", checkpoint_bytes}, {"seconds", checkpoint_seconds}};
  const bool written =
      config.time.fields_interval > 0 && sim.steps() % config.time.fields_interval == 0;
  const bool final_fields = config.write_fields && sim.steps() > first_step && !written && !failure;
  const auto fields = final_fields ? sim.output_fields() : std::vector<io::FieldData>{};  // collective
  on_root_sharing_failure([&] {
    if (files.fields && final_fields) files.fields->write(sim.mesh(), fields, sim.time(), sim.steps());
    io::write_text_file_atomically(directory / "summary.json", summary.dump(2) + "\n");
    io::write_text_file_atomically(
        directory / "progress.json",
        progress_json(last, n_steps, config, status, ledger.wall_seconds, 0.0, checkpoint).dump(2) +
            "\n");
    files.series.close();
    draw_plot("plot_timeseries.py", directory, "deformation.png", false);
  });
  // A failure says where the output is in its own message, after which "wrote" would mislead.
  if (!options.quiet && root && !failure) fmt::print("wrote {}\n", directory.string());
  if (failure) rethrow_with_message(failure, stop_reason);
  if (status == "interrupted")
    throw RunInterrupted(fmt::format("{}; checkpoint written: continue with `softflow restart {}`",
                                     stop_reason, directory.string()));
  return summary;
}

/// Keeps the header and the rows of steps <= `step`; a row cut short by a
/// crash (no final newline) goes too. Rows past the checkpoint are computed
/// again. Returns how many of the steps 0..step have no row (a file deleted
/// or edited since: those rows cannot be computed again).
int truncate_timeseries(const fs::path& path, int step, const std::string& header) {
  std::ifstream in(path, std::ios::binary);
  std::set<int> steps_kept;
  std::ostringstream text;
  text << in.rdbuf();
  std::string all = text.str();
  if (!all.empty() && all.back() != '\n') all.erase(all.rfind('\n') + 1);
  std::istringstream lines(all);
  std::string line, kept;
  bool first_line = true;
  while (std::getline(lines, line)) {
    if (first_line) {
      kept += line + "\n";
      first_line = false;
      continue;
    }
    const auto comma = line.find(',');
    if (comma == std::string::npos) continue;
    try {
      const int row_step = std::stoi(line.substr(0, comma));
      if (row_step <= step) {
        kept += line + "\n";
        if (row_step >= 0) steps_kept.insert(row_step);
      }
    } catch (const std::exception&) {
      // not a row of ours: dropped
    }
  }
  if (kept.empty()) kept = header;
  io::write_text_file_atomically(path, kept);
  return step + 1 - static_cast<int>(steps_kept.size());
}

/// Opens timeseries.csv (and stress.csv for viscoelastic runs, slip.csv
/// for runs with slip) for appending.
void open_series(const fs::path& directory, const DropSimulation& sim, RunFiles& files) {
  auto open = [&](std::ofstream& file, const char* name) {
    file.open(directory / name, std::ios::app);
    if (!file) throw Error(fmt::format("cannot append to {}/{}", directory.string(), name));
  };
  open(files.series, "timeseries.csv");
  if (sim.viscoelastic()) open(files.stress, "stress.csv");
  if (sim.interface_slip()) open(files.slip, "slip.csv");
}

/// The case of `directory`/case.toml must be the one the checkpoint was
/// written with; only [checkpoint] may change between sessions.
void check_same_case(const io::CaseConfig& config, const io::Checkpoint& checkpoint,
                     const fs::path& directory) {
  if (checkpoint.softflow_version != SOFTFLOW_VERSION)
    throw InputError(fmt::format(
        "{}: the checkpoint was written by softflow {}, this is softflow {}: continue the run "
        "with softflow {} (results of two versions would not form one run)",
        (directory / kCheckpointFile).string(), checkpoint.softflow_version, SOFTFLOW_VERSION,
        checkpoint.softflow_version));
  io::CaseConfig saved = io::parse_case(checkpoint.case_toml, "checkpoint");
  saved.checkpoint = config.checkpoint;
  const std::string expected = io::to_toml(saved), given = io::to_toml(config);
  if (expected == given) return;
  std::istringstream a(expected), b(given);
  std::string line_a, line_b;
  int line = 0;
  while (true) {
    ++line;
    const bool more_a = static_cast<bool>(std::getline(a, line_a));
    const bool more_b = static_cast<bool>(std::getline(b, line_b));
    if (!more_a && !more_b) break;
    if (!more_a) line_a.clear();
    if (!more_b) line_b.clear();
    if (line_a != line_b) break;
  }
  throw InputError(fmt::format(
      "{}: not the case the checkpoint was written with (resolved line {}: '{}' here, '{}' in "
      "the checkpoint). A restart continues the same case; only [checkpoint] may change. To "
      "run a changed case, start it with softflow run",
      (directory / "case.toml").string(), line, line_b, line_a));
}

}  // namespace

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

namespace {

nlohmann::json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

}  // namespace

std::string run_status(const fs::path& directory) {
  const auto summary = read_json_file(directory / "summary.json");
  if (summary.is_object() && summary.contains("status") && summary["status"].is_string())
    return summary["status"];
  const auto progress = read_json_file(directory / "progress.json");
  if (!progress.is_object() || !progress.contains("status") || !progress["status"].is_string())
    return "";
  const std::string status = progress["status"];
  if (status != "running") return status;
  // A process killed outright (SIGKILL, the machine's OOM killer, a node
  // lost) writes nothing more: its last word is "running". Its pid tells,
  // on the host that ran it.
  if (!progress.contains("pid") || !progress["pid"].is_number_integer()) return status;
  const long pid = progress["pid"];
  if (progress.value("host", std::string()) != host_name() || pid <= 0) return status;
  if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return "killed";
  return status;
}

void refuse_to_replace_unfinished_run(const fs::path& directory) {
  std::error_code ec;
  const bool checkpoint = fs::exists(directory / kCheckpointFile, ec);
  const auto progress = read_json_file(directory / "progress.json");
  std::string status = run_status(directory);
  // The caller holds the directory's io::RunLock, so no process of this
  // host writes it; a "running" here is a run on another host (or a pid
  // reused since the run was killed): it may be live, and two writers lose
  // results (issue 33).
  if (status == "running") {
    const long pid = progress.is_object() ? progress.value("pid", 0L) : 0L;
    const std::string host = progress.is_object() ? progress.value("host", std::string()) : "";
    throw io::DirectoryBusy(fmt::format(
        "{}/progress.json says a run is still running there (pid {} on {}{}): two runs in one "
        "directory would mix and lose results. If that run has really ended (its machine "
        "rebooted, or the pid belongs to another process now), start afresh with "
        "`softflow run ... --overwrite`{}",
        directory.string(), pid, host == host_name() ? "this host" : fmt::format("host '{}'", host),
        host == host_name() ? ", a process that is not softflow" : "",
        checkpoint ? fmt::format(" or continue it with `softflow restart {}`", directory.string())
                   : std::string()));
  }
  if (status == "killed") {
    const long step = progress.is_object() ? progress.value("step", 0L) : 0L;
    throw InputError(fmt::format(
        "{} holds a run that was killed at step {} (stopped without a final checkpoint; pid {} "
        "is gone): {}, or start afresh with `softflow run ... --overwrite`",
        directory.string(), step, progress.value("pid", 0L),
        checkpoint ? fmt::format("continue it from its last checkpoint with `softflow restart {}`",
                                 directory.string())
                   : std::string("it has no checkpoint to continue from, but its results so far "
                                 "would be replaced")));
  }
  if (!checkpoint) return;
  if (status.empty()) status = "interrupted";
  if (status == "completed" || status == "stopped") return;
  throw InputError(
      fmt::format("{} holds an unfinished run (status \"{}\"), with a checkpoint: continue it "
                  "with `softflow restart {}`, or start afresh with `softflow run ... --overwrite`",
                  directory.string(), status, directory.string()));
}

/// A mesh that starts below time.min_quality would stop the run at its first
/// step with advice about the time step; say before the run what it is and
/// which mesh keys change it (issue 11). Nothing is written.
void check_initial_mesh_quality(const io::CaseConfig& config, const mesh::Mesh& mesh) {
  const double quality = mesh::min_quality(mesh);
  if (quality >= config.time.min_quality) return;
  throw MeshError(fmt::format(
      "the initial mesh has minimum element quality {:.3g} at {}, below time.min_quality = {:.3g}, "
      "so the run would stop at its first step. "
      "Mesh finer or smoother: a larger mesh.equator_nodes (now {}), a smaller mesh.far_size (now "
      "{:g}) or mesh.growth (now {:g}){}; or lower time.min_quality",
      quality, mesh::describe_element(mesh, mesh::worst_tet(mesh)), config.time.min_quality,
      config.sizing.equator_nodes, config.sizing.far_size, config.sizing.growth,
      config.sizing.optimize_high_order ? "" : ", mesh.optimize_high_order = true"));
}

nlohmann::json run_drop_case(const io::CaseConfig& config, const RunOptions& options,
                             MeshedCase meshed) {
  const fs::path directory = options.output_directory.value_or(fs::path(config.output_directory));
  if (!options.overwrite)
    on_root_sharing_failure([&] { refuse_to_replace_unfinished_run(directory); });
  check_initial_mesh_quality(config, meshed.mesh);
  // Staged, then committed at once: an older directory is replaced in one
  // step, and from then on the run writes in place, so that its progress,
  // time series and checkpoints are readable while it runs.
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });
  RunLedger ledger;
  ledger.mesh_report = meshed.report;
  ledger.steady = steady_monitor(config);
  ledger.adaptive = adaptive_steps(config);
  leave_startup();  // the staging directory exists: a stop request now removes it cleanly
  DropSimulation sim(config, std::move(meshed.mesh));
  const StepReport first = sim.initial_report();
  if (const int signal = stop_requested())
    throw RunInterrupted(fmt::format(
        "stopped by {} during set-up, before the first step: nothing to continue from and no "
        "results written; run the case again to start it",
        signal_name(signal)));
  if (ledger.steady) ledger.steady->add(first.time, steady_sample(first, wall_motion(config)));
  RunFiles files;
  on_root_sharing_failure([&] {
    output->write_text("case.toml", io::to_toml(config));
    output->write_text("timeseries.csv", timeseries_header() + timeseries_rows(first));
    if (sim.viscoelastic()) output->write_text("stress.csv", stress_header() + stress_rows(first));
    if (sim.interface_slip()) output->write_text("slip.csv", slip_header() + slip_rows(first));
    output->commit();
    open_series(directory, sim, files);
    if (config.write_fields)
      files.fields =
          std::make_unique<io::FieldSeries>(directory / "fields", directory / "fields.pvd");
  });
  return continue_run(config, options, directory, sim, std::move(ledger), first, files, {});
}

nlohmann::json restart_drop_case(const io::CaseConfig& config, const fs::path& directory,
                                 const RunOptions& options) {
  const bool root = is_root();
  if (root) io::remove_stale_temporaries(directory / kCheckpointFile);
  const std::string previous = root ? run_status(directory) : std::string();
  // The caller holds the directory's io::RunLock: "running" is a run on
  // another host (or a reused pid), perhaps live.
  if (!options.overwrite)
    on_root_sharing_failure([&] {
      if (previous != "running") return;
      const auto progress = read_json_file(directory / "progress.json");
      throw io::DirectoryBusy(fmt::format(
          "{}/progress.json says the run is still running (pid {} on host '{}'): two writers "
          "would mix and lose results. If that run has really ended, continue it with "
          "`softflow restart {} --force`",
          directory.string(), progress.value("pid", 0L), progress.value("host", std::string()),
          directory.string()));
    });
  // Every rank reads the checkpoint: each holds the full replicated state.
  const io::Checkpoint checkpoint = io::read_checkpoint(directory / kCheckpointFile);
  check_same_case(config, checkpoint, directory);
  RunLedger ledger = ledger_from_json(checkpoint.run_json, config);
  const bool steady = ledger.steady && ledger.steady->reached_at();
  if (at_end(config, checkpoint.step, checkpoint.time) || steady) {
    if (!options.quiet && root)
      fmt::print("{}: the run is complete ({}step {}, t = {:.4f}); nothing to do\n",
                 directory.string(), steady ? "steady state at " : "", checkpoint.step,
                 checkpoint.time);
    std::ifstream in(directory / "summary.json");
    try {
      return in ? nlohmann::json::parse(in) : nlohmann::json::object();
    } catch (const nlohmann::json::exception&) {
      return nlohmann::json::object();
    }
  }
  ++ledger.sessions;
  DropSimulation sim(config, checkpoint.reference_mesh);
  sim.restore(checkpoint);
  leave_startup();
  if (const int signal = stop_requested())
    throw RunInterrupted(fmt::format(
        "stopped by {} during the restart's set-up: {} is as it was; `softflow restart {}` "
        "continues it",
        signal_name(signal), directory.string(), directory.string()));
  RunFiles files;
  on_root_sharing_failure([&] {
    std::vector<std::pair<std::string, int>> missing;
    missing.emplace_back("timeseries.csv", truncate_timeseries(directory / "timeseries.csv",
                                                               checkpoint.step, timeseries_header()));
    if (sim.viscoelastic())
      missing.emplace_back("stress.csv", truncate_timeseries(directory / "stress.csv",
                                                             checkpoint.step, stress_header()));
    if (sim.interface_slip())
      missing.emplace_back("slip.csv", truncate_timeseries(directory / "slip.csv",
                                                           checkpoint.step, slip_header()));
    for (const auto& [file, steps] : missing) {
      if (steps <= 0) continue;
      const std::string warning = fmt::format(
          "{}/{} has no rows for {} of the steps 0..{} the checkpoint covers (deleted or edited "
          "since): the run continues from the checkpoint, but those rows are lost for good",
          directory.string(), file, steps, checkpoint.step);
      fmt::print(stderr, "softflow: warning: {}\n", warning);
      ledger.warnings.push_back(warning);
    }
    open_series(directory, sim, files);
    if (config.write_fields) {
      files.fields =
          std::make_unique<io::FieldSeries>(directory / "fields", directory / "fields.pvd");
      files.fields->resume(checkpoint.step);
    }
  });
  if (!options.quiet && root)
    fmt::print("restarting {} ({}) from its checkpoint: step {}{}, t = {:.4f}\n",
               directory.string(),
               previous == "killed" ? "killed: stopped without a final checkpoint"
                                    : fmt::format("status \"{}\"", previous),
               checkpoint.step,
               ledger.adaptive ? std::string()
                               : fmt::format("/{}", planned_steps(config).get<long>()),
               checkpoint.time);
  return continue_run(config, options, directory, sim, std::move(ledger), sim.current_report(),
                      files, {checkpoint.step, checkpoint.time});
}

}  // namespace softflow::simulation
