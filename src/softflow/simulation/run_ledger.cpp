#include "softflow/simulation/run_ledger.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/case_flow.hpp"

namespace softflow::simulation {

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

std::optional<std::string> redistribution_step_warning(const io::CaseConfig& config) {
  const double k = redistribution_rate(config);
  const double dt = config.time.step;
  if (config.objects.empty() || config.time.end <= 0.0 || config.time.adaptive_tolerance > 0.0 ||
      k <= 0.0 || k * dt <= 4.0 / 3.0)
    return std::nullopt;
  return fmt::format(
      "time.step = {:g} is above the tangential redistribution's stability bound 4 / (3 k) = "
      "{:.4g} "
      "(k = interface.redistribution_factor {:g} x the shear rate): the interface nodes will "
      "oscillate from step to step and the objects' volume drift; a time.step below {:.4g}, or "
      "interface.redistribution_factor at most {:.4g}, keeps it stable",
      dt, 4.0 / (3.0 * k), config.interface.redistribution_factor, 4.0 / (3.0 * k),
      config.interface.redistribution_factor * 4.0 / (3.0 * k * dt));
}

time::StepController step_controller(const io::CaseConfig& config) {
  time::StepControllerSettings s;
  s.tolerance = config.time.adaptive_tolerance;
  s.max_growth = config.time.max_growth;
  s.max_step = adaptive_step_bound(config);
  s.min_step = config.time.step / 1000.0;
  return time::StepController(s);
}

nlohmann::json steps_json(const io::CaseConfig& config) {
  if (config.time.adaptive_tolerance > 0.0)
    return {{"kind", "adaptive"},
            {"tolerance", config.time.adaptive_tolerance},
            {"first_step", config.time.step},
            {"largest_step", adaptive_step_bound(config)},
            {"chosen_by", config.time.steps_chosen_by}};
  return {{"kind", "constant"}, {"step", config.time.step}, {"chosen_by", config.time.steps_chosen_by}};
}

std::string describe_steps(const io::CaseConfig& config) {
  const std::string& by = config.time.steps_chosen_by;
  const std::string why =
      by != "default" ? by
      : config.time.adaptive_tolerance > 0.0
          ? "the default: neither time.step nor time.adaptive_tolerance given"
          : "the default: adaptive steps need objects, a flow without a period and no "
            "remeshing; time.step sets the step";
  if (config.time.adaptive_tolerance > 0.0)
    return fmt::format("adaptive, tolerance {:g}, first step {:g}, at most {:g} ({})",
                       config.time.adaptive_tolerance, config.time.step,
                       adaptive_step_bound(config), why);
  return fmt::format("constant, dt = {:g} ({})", config.time.step, why);
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
          {"warnings", l.warnings},
          {"finished", l.finished},
          {"last_remesh_time", l.last_remesh_time}};
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
    l.finished = j.value("finished", std::string());                 // absent before 2026-12-04
    l.last_remesh_time = j.value("last_remesh_time", 0.0);            // absent before 2026-12-05
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

}  // namespace softflow::simulation
