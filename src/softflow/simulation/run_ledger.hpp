// What a run in time accumulates across its sessions (saved in the checkpoint's run
// record): stage timings, the adaptive steps, the steady-state watch, warnings.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/analysis/steady_state.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/time/step_controller.hpp"

namespace softflow::simulation {

/// The state of adaptive stepping between steps.
struct AdaptiveSteps {
  double next_step = 0.0;  ///< the size the next step tries first
  int rejected = 0;        ///< steps taken again smaller: estimate above the tolerance
  int failed = 0;          ///< steps taken again smaller: solver or mesh failure
  double smallest = std::numeric_limits<double>::infinity();  ///< accepted steps' extremes
  double largest = 0.0;
};

std::optional<AdaptiveSteps> adaptive_steps(const io::CaseConfig& config);

/// The largest adaptive step: time.max_step, and the stability bound of the
/// tangential redistribution. Its velocity u_t = k grad_s c is evaluated on
/// the extrapolated surface, and to first order it relaxes the node
/// distribution at the rate k whatever the wavelength (-lap_s c = 1 - 1/g ~
/// div_s of the tangential displacement); BDF2 with a linearly extrapolated
/// term is stable for k dt <= 4/3 and at the bound oscillates from step to
/// step, which is what adaptive runs of the main example showed above
/// dt ~ 0.13 at k = 10. 1/k keeps a margin for changing steps.
double adaptive_step_bound(const io::CaseConfig& config);

/// A warning when constant steps exceed the tangential redistribution's
/// stability bound, k dt <= 4/3 (see adaptive_step_bound): the interface
/// nodes then oscillate from step to step and the object's volume drifts
/// (a particle at k dt = 1.6 lost 1.26 % in five steps:
/// docs/validation/giesekus_trajectory_time_step.md). Empty otherwise.
std::optional<std::string> redistribution_step_warning(const io::CaseConfig& config);

time::StepController step_controller(const io::CaseConfig& config);

/// The run's time steps and what chose them, for the progress output and
/// summary.json: kind "adaptive" or "constant", the step(s) and the key (or
/// the default) that decided.
nlohmann::json steps_json(const io::CaseConfig& config);

/// One line: "adaptive, tolerance 0.001, first step 0.005, at most 0.1
/// (default: ...)" or "constant, dt = 0.05 (time.step)".
std::string describe_steps(const io::CaseConfig& config);

nlohmann::json adaptive_json(const AdaptiveSteps& a);

AdaptiveSteps adaptive_from_json(const nlohmann::json& j);

/// The run record of the checkpoint (`run_json`).
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
  /// Why a module ended the run before time.end (StepModule::finished), or
  /// "": a restart of such a run has nothing to do.
  std::string finished;
  /// The time of the last remesh (0 before the first): remesh.interval
  /// counts from it, and a restart from the checkpoint a remesh writes does
  /// not remesh again.
  double last_remesh_time = 0.0;
};

/// The monitor of time.steady_tolerance, or none. Centre velocities are
/// compared in units of gamma_dot R, R the smallest object's radius
/// (gamma_dot = 1 for a static case, e.g. a drop relaxing at rest).
std::optional<analysis::SteadyStateMonitor> steady_monitor(const io::CaseConfig& config);

/// The objects' state for the monitor. The centre velocity is taken
/// relative to the undisturbed shear flow at the centre, gamma_dot(t) y_c e_x:
/// an object that drifts across the streamlines at a steady rate (migration,
/// or the slow spurious drift of an unsymmetric mesh) then has a steady
/// velocity, where its absolute x-velocity would grow with its y.
std::vector<analysis::ObjectSample> steady_sample(const StepReport& r,
                                                  const physics::WallMotion& walls);

nlohmann::json steady_samples_json(const analysis::SteadyStateMonitor& m);

void restore_steady_samples(analysis::SteadyStateMonitor& m, const nlohmann::json& j);

/// What summary.json says about the steady state (runs that watch for it).
nlohmann::json steady_json(const analysis::SteadyStateMonitor& m);

/// The ledger as the checkpoint stores it, and back (InputError if damaged).
nlohmann::json to_json(const RunLedger& l);
RunLedger ledger_from_json(const std::string& text, const io::CaseConfig& config);

/// Adds one step's stage timings to `total`.
void add(StageSeconds& total, const StageSeconds& s);

}  // namespace softflow::simulation
