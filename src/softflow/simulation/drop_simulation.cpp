#include "softflow/simulation/drop_simulation.hpp"

#include <algorithm>
#include <limits>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/physics/ale/mesh_velocity.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/time/bdf.hpp"

namespace softflow::simulation {

namespace {

using physics::Vec3;
using Clock = std::chrono::steady_clock;

}  // namespace

DropSimulation::DropSimulation(const io::CaseConfig& config, mesh::Mesh mesh)
    : config_(config),
      models_(phase_models(config_)),
      mesh_(std::move(mesh)),
      initial_nodes_(mesh_.nodes),
      reference_nodes_(mesh_.nodes),
      relocation_(mesh_.n_nodes(), mesh::Point::Zero()),
      relocator_(std::make_unique<mesh::NodeRelocation>(mesh_)) {
  stokes_ = std::make_unique<physics::StokesSystem>(mesh_, solver_settings(config_),
                                                    has_interface_slip(config_));
  ale_ = std::make_unique<physics::AleMeshMotion>(mesh_);
  physics::InterfaceTrackerSettings tracking;
  tracking.redistribution_factor = redistribution_rate(config_);
  tracking.supg_beta = config_.interface.supg_beta;
  for (int k = 1; k <= mesh_.n_objects; ++k) {
    auto surface = physics::extract_interface(mesh_, k);
    auto x0 = physics::interface_positions(surface, mesh_);
    trackers_.emplace_back(std::move(surface), std::move(x0), tracking);
  }
  last_centre_velocity_.assign(trackers_.size(), Vec3::Zero());
  mesh_velocity_.assign(mesh_.n_nodes(), mesh::Point::Zero());
  last_quality_ = mesh::min_quality(mesh_);
  if (ViscoelasticPhases::needed(models_))
    viscoelastic_ = std::make_unique<ViscoelasticPhases>(mesh_, models_, stokes_->interface_slip());
  for (const auto& tracker : trackers_)
    initial_volumes_.push_back(physics::surface_integrals(tracker.surface(), tracker.positions()).volume);
  register_state();
}

DropSimulation::~DropSimulation() = default;

StepReport DropSimulation::initial_report() const {
  StepReport r;
  r.min_quality = mesh::min_quality(mesh_);
  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k) r.objects.push_back(measure(k, Vec3::Zero()));
  r.stresses = measure_stresses();
  r.slips = measure_slips();
  return r;
}

StepReport DropSimulation::step(double dt) {
  const auto start = Clock::now();
  auto lap = [last = start]() mutable {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - last).count();
    last = now;
    return s;
  };
  StepReport r;
  r.dt = dt;
  if (steps_ > 0 && wall_motion(config_).jumps_at(time_)) restart_time_histories();
  const auto x_hat = predict_interfaces(dt);                 // Step 1
  const auto centre_velocity = translate_mesh(x_hat, dt);    // Step 2
  r.stages.predict_and_translate = lap();
  const double quality = move_mesh_ale(x_hat, dt);           // Step 3
  r.stages.ale = lap();
  time_ += dt;
  int iterations = 0;
  try {
    iterations = solve_stokes(x_hat, dt, r.stages);          // Step 4
  } catch (const SolverError& e) {
    throw SolverError(fmt::format("step {} (t = {:.4f}): {}", steps_ + 1, time_, e.what()));
  }
  check_solution_finite();
  lap();
  if (viscoelastic_) {
    viscoelastic_->advance(stokes_->dofs(), solution_.get(), dt, time_, steps_ + 1);
    r.stages.conformation = lap();
  }
  // BDF1's predictor x_hat = x_n (the first step, a step after a jump) estimates nothing.
  const bool extrapolated = !trackers_.empty() && trackers_.front().steps() > 0;
  correct_interfaces(x_hat, centre_velocity, dt);            // Step 5
  r.stages.correct = lap();
  if (extrapolated) r.interface_change = interface_change(x_hat);

  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k) {
    try {
      r.objects.push_back(measure(k, centre_velocity[k]));
    } catch (const Error& e) {
      // An interface that no longer fits an ellipsoid after one step has
      // almost always blown up numerically rather than deformed. The step
      // is not counted: it has no row in the time series.
      throw AccuracyError(fmt::format(
          "step {} (t = {:.4f}): object {}: {}. The interface left the range the method resolves; "
          "try a smaller time.step or check the case's capillary number and viscosity ratio",
          steps_ + 1, time_, k + 1, e.what()));
    }
  }
  r.stresses = measure_stresses();
  r.slips = measure_slips();
  check_slip_dissipation(r.slips);
  ++steps_;
  last_centre_velocity_ = centre_velocity;
  r.step = steps_;
  r.time = time_;
  r.min_quality = quality;
  r.stokes_iterations = iterations;
  r.stages.analysis = lap();
  r.step_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

void DropSimulation::restart_time_histories() {
  // Every multistep history restarts at first order after a jump of the
  // walls: a BDF2 stencil across it is O(1) wrong in the derivative, an
  // O(dt) error in what follows (measured before: a drop relaxing after
  // cessation converged at order 1.0 in dt).
  for (auto& tracker : trackers_) tracker.restart_history();
  previous_nodes_.clear();  // the mesh velocity by BDF1
  if (viscoelastic_) viscoelastic_->restart_time_history();
}

double DropSimulation::interface_change(const std::vector<std::vector<Vec3>>& x_hat) const {
  // The predictor's error, dt^2 x'' (1 + w) / 2 to leading order: the
  // scheme's geometric error, since Stokes was solved on x_hat. The whole
  // distance, tangential part included: measured on the main example, the
  // normal part alone let a step of 1.8 / gamma_dot through, after which D
  // kept a two-step oscillation of +-1e-4 that never settled; the
  // tangential motion of the redistribution (eq. 2.30) is where such a step
  // shows first.
  double change = 0.0;
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const double radius = std::cbrt(3.0 * initial_volumes_[k] / (4.0 * std::numbers::pi));
    const auto& x = trackers_[k].positions();
    for (std::size_t i = 0; i < x.size(); ++i)
      change = std::max(change, (x[i] - x_hat[k][i]).norm() / radius);
  }
  return change;
}

StateRecord DropSimulation::save_step_state() const {
  StateRecord state(StateRecord::Scope::this_rank);  // in memory: nothing gathered
  registry_.save(state, {"stokes"});
  return state;
}

void DropSimulation::restore_step_state(const StateRecord& state) {
  registry_.restore(state, {"stokes"});
}

StepReport DropSimulation::current_report() const {
  StepReport r;
  r.step = steps_;
  r.time = time_;
  r.min_quality = mesh::min_quality(mesh_);
  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k)
    r.objects.push_back(measure(k, last_centre_velocity_[k]));
  r.stresses = measure_stresses();
  r.slips = measure_slips();
  return r;
}

void DropSimulation::check_solution_finite() const {
  const auto bad = la::first_non_finite(solution_.get());
  if (!bad) return;
  const int dof = static_cast<int>(bad->first);
  const auto& dofs = stokes_->dofs();
  const int node = dofs.node_of(dof);
  const int region = dofs.region_of(dof);
  const std::string& field = dofs.field(dofs.field_of(dof)).name;
  const auto& x = mesh_.nodes[node];
  throw SolverError(fmt::format(
      "step {} (t = {:.4f}): the Stokes solution is not finite ({} {} at node {}, {}, near "
      "({:.3f}, {:.3f}, {:.3f})). Usually solver options that do not converge (check "
      "[solver] and the PETSc options), a time step too large for the surface tension (with "
      "interface.semi_implicit_tension = false) or a tangled mesh: try the default solver, a "
      "smaller time.step or a finer mesh",
      steps_ + 1, time_, bad->second, field, node,
      region == 0 ? std::string("in the matrix") : fmt::format("in object {}", region), x.x(),
      x.y(), x.z()));
}

void DropSimulation::check_volumes() const {
  // The discrete scheme conserves volume only approximately (thesis §2.4);
  // past a few per cent the drop is no longer the one asked for, and D and
  // theta of a drop of another size compare with the wrong theory.
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const double volume =
        physics::surface_integrals(trackers_[k].surface(), trackers_[k].positions()).volume;
    const double drift = volume / initial_volumes_[k] - 1.0;
    if (std::abs(drift) <= config_.time.max_volume_drift) continue;
    const Vec3 c = trackers_[k].centre();
    throw AccuracyError(fmt::format(
        "step {} (t = {:.4f}): object {} (centre ({:.3f}, {:.3f}, {:.3f})) changed its volume by "
        "{:+.3g} % (from {:.6g} to {:.6g}), more than time.max_volume_drift = {:g} %. Try a "
        "smaller time.step, more mesh.equator_nodes, or a larger time.max_volume_drift if this "
        "accuracy is enough",
        steps_, time_, k + 1, c.x(), c.y(), c.z(), 100.0 * drift, initial_volumes_[k], volume,
        100.0 * config_.time.max_volume_drift));
  }
}

void DropSimulation::register_state() {
  // Restored in this order: the Stokes factors are rebuilt from their own
  // saved matrices, independent of the time loop's state.
  registry_.add({"time_loop",
                 [this](StateRecord& r, const std::string& p) { save_time_loop(r, p); },
                 [this](const StateRecord& r, const std::string& p) { restore_time_loop(r, p); }});
  registry_.add(stokes_->state_part());
  for (std::size_t k = 0; k < trackers_.size(); ++k)
    registry_.add({fmt::format("objects/{}", k + 1),
                   [this, k](StateRecord& r, const std::string& p) {
                     const auto h = trackers_[k].history();
                     r.set(p + "x", h.x);
                     r.set(p + "x_previous", h.x_previous);
                     r.set(p + "centre", std::vector<Vec3>{h.centre, h.centre_previous});
                     r.set(p + "steps", h.steps);
                     r.set(p + "centre_steps", h.centre_steps);
                     r.set(p + "last_step", h.last_step);
                     r.set(p + "last_centre_velocity", std::vector<Vec3>{last_centre_velocity_[k]});
                   },
                   [this, k](const StateRecord& r, const std::string& p) {
                     const auto centre = r.get_points(p + "centre");
                     const auto velocity = r.get_points(p + "last_centre_velocity");
                     auto x = r.get_points(p + "x");
                     auto x_previous = r.get_points(p + "x_previous");
                     if (centre.size() != 2 || velocity.size() != 1 ||
                         x.size() != trackers_[k].positions().size() ||
                         x_previous.size() != x.size())
                       throw InputError(fmt::format("the saved state of object {} does not fit "
                                                    "its interface mesh", k + 1));
                     const int steps = r.get_int(p + "steps");
                     // Checkpoints from before variable steps: every step was time.step.
                     const double last_step =
                         r.contains(p + "last_step") ? r.get_double(p + "last_step")
                                                     : (steps > 0 ? config_.time.step : 0.0);
                     trackers_[k].restore({std::move(x), std::move(x_previous), centre[0],
                                           centre[1], steps, r.get_int(p + "centre_steps"),
                                           last_step});
                     last_centre_velocity_[k] = velocity[0];
                   }});
  if (viscoelastic_) {
    for (fem::Field* f : viscoelastic_->output_fields()) add_field(*f);
    registry_.add(viscoelastic_->state_part());
  }
}

void DropSimulation::add_field(fem::Field& field) {
  if (&field.mesh() != &mesh_)
    throw Error(fmt::format("field '{}' lives on another mesh than the simulation's", field.name()));
  registry_.add(fem::state_part(field));
  added_fields_.push_back(&field);
}

std::vector<io::FieldData> DropSimulation::output_fields() const {
  std::vector<io::FieldData> out{{&stokes_->dofs(), solution()}};
  for (const fem::Field* f : added_fields_) out.push_back({&f->dofs(), f->gather()});
  return out;
}

void DropSimulation::save_time_loop(StateRecord& r, const std::string& p) const {
  r.set(p + "step", steps_);
  r.set(p + "time", time_);
  r.set(p + "dt", config_.time.step);
  r.set(p + "last_step", last_dt_);
  r.set(p + "translation_x", translation_x_);
  r.set(p + "nodes", mesh_.nodes);
  r.set(p + "previous_nodes", previous_nodes_);
  r.set(p + "mesh_velocity", mesh_velocity_);
  if (solution_) la::save_vector(r, p + "solution", solution_.get());
  else r.set(p + "solution", std::vector<double>{});
  ale_->save_warm_start(r, p + "ale_");
  r.set(p + "ale_reference_nodes", reference_nodes_);
  r.set(p + "ale_rebuilt_at_quality", ale_rebuilt_at_quality_);
  r.set(p + "ale_rebuilds", ale_rebuilds_);
  r.set(p + "ale_relocation", relocation_);
  r.set(p + "relocation_steps", relocation_steps_);
  r.set(p + "relocated_nodes", relocated_nodes_);
}

void DropSimulation::restore_time_loop(const StateRecord& r, const std::string& p) {
  const auto n = mesh_.nodes.size();
  auto nodes = r.get_points(p + "nodes");
  auto previous = r.get_points(p + "previous_nodes");
  auto velocity = r.get_points(p + "mesh_velocity");
  auto reference = r.get_points(p + "ale_reference_nodes");
  const auto& solution = r.get_array(p + "solution");
  if (nodes.size() != n || (!previous.empty() && previous.size() != n) ||
      (!velocity.empty() && velocity.size() != n) || reference.size() != n)
    throw InputError("the checkpoint does not fit the mesh it carries");
  steps_ = r.get_int(p + "step");
  time_ = r.get_double(p + "time");
  // Checkpoints from before variable steps: every step was time.step.
  last_dt_ = r.contains(p + "last_step") ? r.get_double(p + "last_step")
                                         : (steps_ > 0 ? config_.time.step : 0.0);
  translation_x_ = r.get_double(p + "translation_x");
  mesh_.nodes = std::move(nodes);
  previous_nodes_ = std::move(previous);
  mesh_velocity_ = velocity.empty() ? std::vector<mesh::Point>(n, mesh::Point::Zero())
                                    : std::move(velocity);
  if (solution.empty()) {
    solution_.reset();
  } else {
    la::Vector restored = la::make_vector(stokes_->ownership().size(), stokes_->dofs().n_dofs());
    la::restore_vector(r, p + "solution", restored.get(), "Stokes solution");
    set_solution(std::move(restored));
  }
  last_quality_ = mesh::min_quality(mesh_);
  ale_rebuilt_at_quality_ = r.get_double(p + "ale_rebuilt_at_quality");
  ale_rebuilds_ = r.get_int(p + "ale_rebuilds");
  // Checkpoints from before vertex relocation: none.
  if (r.contains(p + "ale_relocation")) {
    auto relocation = r.get_points(p + "ale_relocation");
    if (relocation.size() != n) throw InputError("the checkpoint does not fit the mesh it carries");
    relocation_ = std::move(relocation);
    relocation_steps_ = r.get_int(p + "relocation_steps");
    relocated_nodes_ = r.get_int(p + "relocated_nodes");
  } else {
    std::fill(relocation_.begin(), relocation_.end(), mesh::Point::Zero());
    relocation_steps_ = relocated_nodes_ = 0;
  }
  // The mesh-motion operator must be the one of the saved reference: the
  // current one if they agree (always after a fresh start; usually after a
  // step taken back), else built there again: a checkpoint of a run that
  // rebuilt it, or a step taken back that had rebuilt it (the translation
  // restored above counts from the saved reference).
  if (reference != reference_nodes_) {
    reference_nodes_ = std::move(reference);
    mesh::Mesh rebuilt = mesh_;
    rebuilt.nodes = reference_nodes_;
    ale_ = std::make_unique<physics::AleMeshMotion>(rebuilt);
  }
  ale_->restore_warm_start(r, p + "ale_");
}

void DropSimulation::save(io::Checkpoint& c) const {
  c.step = steps_;
  c.time = time_;
  c.reference_mesh = mesh_;
  c.reference_mesh.nodes = initial_nodes_;
  c.state = StateRecord{};
  registry_.save(c.state);
}

void DropSimulation::restore(const io::Checkpoint& c) { registry_.restore(c.state); }

std::vector<std::vector<Vec3>> DropSimulation::predict_interfaces(double dt) const {
  std::vector<std::vector<Vec3>> x_hat;
  for (const auto& tracker : trackers_) x_hat.push_back(tracker.predict(dt));
  return x_hat;
}

std::vector<Vec3> DropSimulation::translate_mesh(const std::vector<std::vector<Vec3>>& x_hat,
                                                 double dt) {
  // U from the centre of volume of the predicted surface (eqs. 2.51-2.54);
  // with one object, the mesh follows its centre in x so the drop never
  // drifts towards the periodic faces (d1 of Step 2).
  std::vector<Vec3> u(trackers_.size());
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const Vec3 before = trackers_[k].centre();
    u[k] = trackers_[k].centre_velocity(x_hat[k], dt);
    if (trackers_.size() == 1) translation_x_ += trackers_[k].centre().x() - before.x();
  }
  return u;
}

void DropSimulation::rebuild_ale_if_degraded() {
  // The thesis solves the mesh motion on the current mesh every step, so
  // that k_e = 1/V_e stiffens the elements that have shrunk. softflow keeps
  // the initial mesh's operator, factored once, while the mesh is good, and
  // rebuilds it on the current mesh when the quality falls below
  // time.ale_rebuild_quality, then after each further 5 % drop: the same
  // effect at a few factorisations per run. The displacement is then taken
  // from the current mesh (the new reference) and the translation restarts.
  const double threshold = config_.time.ale_rebuild_quality;
  if (threshold <= 0.0 || steps_ == 0 || last_quality_ >= threshold ||
      last_quality_ >= 0.95 * ale_rebuilt_at_quality_)
    return;
  reference_nodes_ = mesh_.nodes;
  std::fill(relocation_.begin(), relocation_.end(), mesh::Point::Zero());
  translation_x_ = 0.0;
  ale_ = std::make_unique<physics::AleMeshMotion>(mesh_);
  ale_rebuilt_at_quality_ = last_quality_;
  ++ale_rebuilds_;
}

std::optional<double> DropSimulation::relocate_vertices(std::vector<mesh::Point>& moved) {
  // Part of this step's mesh motion, so the mesh velocity (and with it the
  // ALE transport) sees the relocation; kept in relocation_ so that later
  // steps, which extend the interface displacement from the reference
  // again, keep it too.
  const double target = config_.time.relocation_quality;
  if (target <= 0.0) return std::nullopt;
  const std::vector<mesh::Point> before = moved;
  const auto report = relocator_->improve(moved, target);
  if (report.nodes_moved == 0) return report.smallest_quality;
  for (int i = 0; i < mesh_.n_nodes(); ++i) relocation_[i] += moved[i] - before[i];
  ++relocation_steps_;
  relocated_nodes_ += report.nodes_moved;
  return report.smallest_quality;
}

double DropSimulation::move_mesh_ale(const std::vector<std::vector<Vec3>>& x_hat, double dt) {
  rebuild_ale_if_degraded();
  // Total displacement from the reference mesh: d1 (translation) + d2, with
  // d2 = x_hat - x_ref - d1 on the interfaces and 0 on the outer boundary.
  const Vec3 d1(translation_x_, 0.0, 0.0);
  std::vector<Vec3> interface_displacement(mesh_.n_nodes(), Vec3::Zero());
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& nodes = trackers_[k].surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      interface_displacement[nodes[i]] = x_hat[k][i] - reference_nodes_[nodes[i]] - d1;
  }
  const auto d2 = ale_->solve(interface_displacement);
  std::vector<mesh::Point> moved(mesh_.n_nodes());
  for (int i = 0; i < mesh_.n_nodes(); ++i) moved[i] = reference_nodes_[i] + relocation_[i] + d1 + d2[i];
  for (std::size_t k = 0; k < trackers_.size(); ++k) {  // exactly on the predicted interface
    const auto& nodes = trackers_[k].surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) moved[nodes[i]] = x_hat[k][i];
  }
  const auto measured = relocate_vertices(moved);
  mesh_velocity_ = physics::bdf_mesh_velocity(moved, mesh_.nodes, previous_nodes_, dt, last_dt_);
  last_dt_ = dt;
  previous_nodes_ = std::exchange(mesh_.nodes, std::move(moved));
  const double quality = measured ? *measured : mesh::min_quality(mesh_);
  last_quality_ = quality;
  if (quality < config_.time.min_quality) {
    throw MeshError(fmt::format(
        "step {} (t = {:.4f}): the moving mesh degraded: {} has quality {:.3g} < "
        "time.min_quality = {:.3g}. The deformation is too large for a mesh that is never "
        "remeshed; try a smaller time.step, a larger interface.redistribution_factor, or a finer "
        "mesh{}{}",
        steps_ + 1, time_ + dt, mesh::describe_element(mesh_, mesh::worst_tet(mesh_)),
        quality, config_.time.min_quality,
        config_.time.relocation_quality > 0.0
            ? " (node relocation, time.relocation_quality, could not keep it valid: a finer "
              "mesh gives it nodes to move)"
            : "; time.relocation_quality > 0 moves free nodes to keep elements valid",
        // Explicit tension collapses the interface mesh above the capillary step limit.
        config_.interface.semi_implicit_tension
            ? ""
            : "; with explicit tension, a step above the capillary limit (about eta h / Gamma) "
              "does this: interface.semi_implicit_tension = true lifts it"));
  }
  return quality;
}

Vec3 DropSimulation::interface_velocity(int node, int object) const {
  // No slip: the shared copy. With slip the copies agree along the normal
  // (collocated constraint) and the tracker moves nodes with the normal
  // part only (eq. 2.29): their mean, which favours neither side.
  const auto& dofs = stokes_->dofs();
  const int m = dofs.dof(physics::kVelocityField, node, 0);
  const int d = dofs.dof(physics::kVelocityField, node, object);
  const auto& u = interface_values_;
  return 0.5 * (Vec3(u[m], u[m + 1], u[m + 2]) + Vec3(u[d], u[d + 1], u[d + 2]));
}

std::vector<PetscInt> DropSimulation::interface_dofs() const {
  const auto& dofs = stokes_->dofs();
  std::vector<PetscInt> out;
  for (std::size_t f = 0; f < mesh_.interface_faces.size(); ++f) {
    const int object = mesh_.interface_object[f];
    for (int node : mesh_.interface_faces[f])
      for (int c = 0; c < 3; ++c) {
        out.push_back(dofs.dof(physics::kVelocityField, node, 0, c));
        out.push_back(dofs.dof(physics::kVelocityField, node, object, c));
        if (stokes_->interface_slip())
          out.push_back(dofs.dof(physics::kMultiplierField, node, object, c));
      }
  }
  return out;
}

void DropSimulation::set_solution(la::Vector solution) {
  solution_ = std::move(solution);
  if (mesh_.interface_faces.empty()) return;  // no objects: nothing reads it
  // Built once: the dofs never change (the mesh moves, it is not remeshed).
  if (interface_values_.empty())
    interface_values_ = la::SelectedEntries(solution_.get(), interface_dofs());
  interface_values_.read(solution_.get());
}

std::vector<double> DropSimulation::solution() const {
  return solution_ ? la::gather_to_all(solution_.get()) : std::vector<double>{};
}

physics::SemiImplicitTension DropSimulation::semi_implicit_tension(
    const std::vector<std::vector<Vec3>>& x_hat, double dt) const {
  physics::SemiImplicitTension tension;
  if (!config_.interface.semi_implicit_tension || trackers_.empty()) return tension;
  // theta = 1 for the BDF1 first step, 2/3 after (eqs. 2.48, 2.50). w = the
  // previous step's fluid velocity along the normal: the implicit part then
  // acts on the velocity increment only (see physics::SemiImplicitTension).
  // At the first step there is no previous velocity; w = 0 is exact there,
  // since the BDF1 predictor does not move the interface.
  const int order = time::bdf_order(trackers_.front().steps());
  const bool first_step = order == 1;
  tension.theta_dt = time::bdf(order, dt, trackers_.front().last_step()).theta_dt(dt);
  tension.node_normal.assign(mesh_.n_nodes(), Vec3::Zero());
  tension.predicted_normal_velocity.assign(mesh_.n_nodes(), 0.0);
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& tracker = trackers_[k];
    const auto normals = physics::node_normals(tracker.surface(), x_hat[k]);
    const auto& nodes = tracker.surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      tension.node_normal[nodes[i]] = normals[i];
      if (!first_step)
        tension.predicted_normal_velocity[nodes[i]] =
            normals[i].dot(interface_velocity(nodes[i], static_cast<int>(k) + 1));
    }
  }
  return tension;
}

int DropSimulation::solve_stokes(const std::vector<std::vector<Vec3>>& x_hat, double dt,
                                 StageSeconds& stages) {
  // time_ is already t_{n+1}: the walls of the end of the step.
  physics::StokesProblem problem = stokes_problem(config_, models_, mesh_, time_);
  problem.semi_implicit_tension = semi_implicit_tension(x_hat, dt);
  if (viscoelastic_) problem.viscoelastic = viscoelastic_->coupling(mesh_velocity_, dt);
  auto result = stokes_->solve(problem, physics::SolutionLayout::distributed);
  set_solution(std::move(result.distributed));
  stages.stokes_assembly = result.assembly_seconds;
  stages.stokes_solve = result.solve.seconds;
  return result.solve.iterations;
}

void DropSimulation::correct_interfaces(const std::vector<std::vector<Vec3>>& x_hat,
                                        const std::vector<Vec3>& centre_velocity, double dt) {
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& nodes = trackers_[k].surface().volume_node;
    std::vector<Vec3> u(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i)
      u[i] = interface_velocity(nodes[i], static_cast<int>(k) + 1);
    trackers_[k].correct(x_hat[k], u, centre_velocity[k], dt);
  }
}

ObjectState DropSimulation::measure(int k, const Vec3& centre_velocity) const {
  const auto& tracker = trackers_[k];
  const auto& x = tracker.positions();
  const auto integrals = physics::surface_integrals(tracker.surface(), x);
  ObjectState s;
  s.object = k + 1;
  s.volume = integrals.volume;
  s.area = integrals.area;
  s.centre = integrals.centre_of_volume();
  s.centre_velocity = centre_velocity;
  const auto fit = analysis::fit_ellipsoid(x);
  s.deformation = fit.deformation;
  // An undeformed sphere has no long axis: its fitted angle is whatever the
  // round-off picks (0 or 90 deg at t = 0), which would distort averages
  // and plots. NaN says "undefined" ("nan" in CSV, null in JSON).
  s.theta_deg = fit.deformation < kOrientationUndefinedBelow ? std::numeric_limits<double>::quiet_NaN()
                                                             : fit.theta_deg;
  s.L = fit.L;
  s.B = fit.B;
  s.W = fit.W;
  s.ellipsoid_deviation = fit.max_relative_deviation;
  return s;
}

std::vector<physics::SlipMeasures> DropSimulation::measure_slips() const {
  if (!stokes_->interface_slip()) return {};
  if (!solution_)  // t = 0: the interface is there, nothing moves across it yet
    return physics::slip_measures(mesh_, stokes_->dofs(), stokes_->slip_node_normals(mesh_),
                                  [](int) { return 0.0; });
  return physics::slip_measures(mesh_, stokes_->dofs(), stokes_->slip_node_normals(mesh_),
                                [this](int dof) { return interface_values_[dof]; });
}

void DropSimulation::check_slip_dissipation(const std::vector<physics::SlipMeasures>& slips) const {
  // Measured on the geometry the system was assembled on (mesh_ before
  // Step 5 moves only the trackers' copies), so the identity holds.
  for (std::size_t k = 0; k < slips.size(); ++k) {
    const auto& s = slips[k];
    if (!physics::dissipation_is_negative(s)) continue;
    throw AccuracyError(fmt::format(
        "step {} (t = {:.4f}): object {}: the slip dissipates {:.3e} < 0 (of |power| {:.3e}): "
        "energy would be made at the interface, so the solution is wrong. Check the solver "
        "(solver.type = \"direct\") and that objects[{}].slip is within what the mesh resolves",
        steps_ + 1, time_, k + 1, s.dissipation, s.absolute_power, k + 1));
  }
}

std::vector<RegionStress> DropSimulation::measure_stresses() const {
  std::vector<RegionStress> out;
  if (!viscoelastic_) return out;
  for (int r = 0; r <= mesh_.n_objects; ++r)
    if (viscoelastic_->models()[r].has_conformation()) out.push_back(viscoelastic_->region_stress(r));
  return out;
}

bool DropSimulation::interface_slip() const { return stokes_->interface_slip(); }

}  // namespace softflow::simulation
