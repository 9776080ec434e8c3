#include "softflow/simulation/drop_simulation.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <limits>
#include <chrono>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "softflow/fem/mesh_transfer.hpp"
#include "softflow/geometry/remesh.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/parallel/mesh_broadcast.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/moving_mesh.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/modules/viscoelastic_module.hpp"
#include "softflow/simulation/report_tables.hpp"
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
      initial_nodes_(mesh_.nodes) {
  build_parts();
  last_centre_velocity_.assign(trackers_.size(), Vec3::Zero());
  for (const auto& tracker : trackers_)
    initial_volumes_.push_back(physics::surface_integrals(tracker.surface(), tracker.positions()).volume);
  register_state();
}

void DropSimulation::build_parts() {
  stokes_ = std::make_unique<physics::StokesSystem>(mesh_, solver_settings(config_),
                                                    has_interface_slip(config_));
  moving_mesh_ = std::make_unique<physics::MovingMesh>(
      mesh_, physics::MovingMeshSettings{config_.time.ale_rebuild_quality,
                                         config_.time.relocation_quality});
  physics::InterfaceTrackerSettings tracking;
  tracking.redistribution_factor = redistribution_rate(config_);
  tracking.supg_beta = config_.interface.supg_beta;
  trackers_.clear();
  for (int k = 1; k <= mesh_.n_objects; ++k) {
    auto surface = physics::extract_interface(mesh_, k);
    auto x0 = physics::interface_positions(surface, mesh_);
    trackers_.emplace_back(std::move(surface), std::move(x0), tracking);
  }
  modules_ = make_modules({config_, mesh_, *stokes_, models_});
}

RemeshEvent DropSimulation::remesh(const std::string& reason) {
  const auto start = Clock::now();
  RemeshEvent event;
  event.step = steps_;
  event.time = time_;
  event.reason = reason;
  // What is carried: gathered while the old parts still exist. Dof maps
  // and spaces hold no reference to the mesh, so copies of them outlive it.
  const mesh::Mesh old_mesh = mesh_;
  const fem::DofMap old_dofs = stokes_->dofs();
  const std::vector<double> old_solution = solution();
  std::size_t module_fields = 0;
  for (auto& module : modules_) module_fields += module->fields().size();
  if (module_fields != added_fields_.size())
    throw Error("remesh: fields added to the run from outside a module cannot be carried to a new mesh");
  std::vector<physics::InterfaceTracker::History> histories;
  std::vector<std::vector<double>> reference_areas;
  std::vector<std::vector<std::array<int, 6>>> old_triangles;
  std::vector<std::vector<int>> old_volume_nodes;
  std::vector<double> volume_before;
  for (const auto& tracker : trackers_) {
    histories.push_back(tracker.history());
    reference_areas.push_back(tracker.reference_areas());
    old_triangles.push_back(tracker.surface().triangles);
    old_volume_nodes.push_back(tracker.surface().volume_node);
    volume_before.push_back(physics::surface_integrals(tracker.surface(), tracker.positions()).volume);
  }

  // The new mesh: gmsh on rank 0 (its meshes differ run to run), sent to all.
  geometry::Remeshed r;
  std::string failure;
  if (la::mpi_rank() == 0) try {
      r = geometry::remesh(config_.shear_cell_spec(), mesh_);
    } catch (const MeshError& e) {
      failure = e.what();
    }
  int failed = failure.empty() ? 0 : 1;
  MPI_Bcast(&failed, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  // Nothing has changed yet: the run can go on with the mesh it has.
  if (failed) throw MeshError(failure.empty() ? std::string("remeshing failed on rank 0") : failure);
  if (la::mpi_size() > 1) {
    parallel::broadcast_mesh(r.mesh, PETSC_COMM_WORLD);
    r.new_node_of_old.resize(old_mesh.n_nodes());
    MPI_Bcast(r.new_node_of_old.data(), old_mesh.n_nodes(), MPI_INT, 0, PETSC_COMM_WORLD);
    MPI_Bcast(&r.report.quality_after, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
  }
  event.nodes_before = old_mesh.n_nodes();
  event.quality_before = moving_mesh_->quality();
  event.nodes_after = r.mesh.n_nodes();
  event.quality_after = r.report.quality_after;

  // The parts on the new mesh, from scratch; then the state carried over.
  registry_ = StateRegistry{};
  added_fields_.clear();
  // The old modules stay until they have handed their fields over (reading
  // only their fields' values: the mesh they were built on is replaced).
  auto old_modules = std::move(modules_);
  modules_.clear();
  moving_mesh_.reset();
  stokes_.reset();
  solution_.reset();
  interface_values_ = la::SelectedEntries{};
  mesh_ = std::move(r.mesh);
  initial_nodes_ = mesh_.nodes;
  build_parts();

  const fem::MeshTransfer transfer(old_mesh, mesh_, r.new_node_of_old);
  if (!old_solution.empty()) {
    const auto values = transfer.transfer(old_dofs, stokes_->dofs(), old_solution);
    la::Vector v = la::make_vector(stokes_->ownership().size(), stokes_->dofs().n_dofs());
    la::scatter_from_all(v.get(), values);
    set_solution(std::move(v));
  }
  // Each module takes over its predecessor's state (make_modules builds the
  // same kinds in the same order from the same case).
  if (old_modules.size() != modules_.size()) throw Error("remesh: the run's modules changed");
  for (std::size_t i = 0; i < modules_.size(); ++i) modules_[i]->carry_over(*old_modules[i], transfer);
  old_modules.clear();
  // The interface nodes are the old ones: the trackers' histories (x_n,
  // x_{n-1}, the centres) carry over in the new surfaces' node order.
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& surface = trackers_[k].surface();
    std::vector<int> local(mesh_.n_nodes(), -1);
    for (int i = 0; i < surface.n_nodes(); ++i) local[surface.volume_node[i]] = i;
    auto h = histories[k];
    auto remap = [&](const std::vector<Vec3>& x) {
      std::vector<Vec3> out(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) out.at(local.at(r.new_node_of_old.at(old_volume_nodes[k][i]))) = x[i];
      return out;
    };
    h.x = remap(h.x);
    if (!h.x_previous.empty()) h.x_previous = remap(h.x_previous);
    trackers_[k].restore(std::move(h));
    // The redistribution keeps the run's initial element areas (eq. 2.32's
    // reference), triangle by triangle: the triangles are the old ones.
    auto key = [](std::array<int, 3> t) {
      std::sort(t.begin(), t.end());
      return t;
    };
    std::map<std::array<int, 3>, int> new_triangle;
    for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
      const auto& tri = surface.triangles[t];
      new_triangle[key({tri[0], tri[1], tri[2]})] = static_cast<int>(t);
    }
    std::vector<double> areas(surface.triangles.size(), 0.0);
    for (std::size_t t = 0; t < old_triangles[k].size(); ++t) {
      std::array<int, 3> corners{};
      for (int c = 0; c < 3; ++c)
        corners[c] = local.at(r.new_node_of_old.at(old_volume_nodes[k][old_triangles[k][t][c]]));
      areas.at(new_triangle.at(key(corners))) = reference_areas[k][t];
    }
    trackers_[k].set_reference_areas(std::move(areas));
    const double after = physics::surface_integrals(surface, trackers_[k].positions()).volume;
    event.volume_change = std::max(event.volume_change, std::abs(after / volume_before[k] - 1.0));
  }
  register_state();
  event.extrapolation = transfer.largest_extrapolation();
  event.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return event;
}

DropSimulation::~DropSimulation() = default;

StepReport DropSimulation::initial_report() {
  StepReport r;
  r.min_quality = mesh::min_quality(mesh_);
  measure_all(r, std::vector<Vec3>(trackers_.size(), Vec3::Zero()), 0.0, 0);
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
  // The stages of step_module.hpp's Stage, in order; each module's hook after the driver's part.
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
  if (!modules_.empty()) {                                   // fields carried by the new flow
    const StepContext now = context(dt, steps_ + 1);
    for (auto& module : modules_) module->advance(now);
    r.stages.conformation = lap();
  }
  // BDF1's predictor x_hat = x_n (the first step, a step after a jump) estimates nothing.
  const bool extrapolated = !trackers_.empty() && trackers_.front().steps() > 0;
  correct_interfaces(x_hat, centre_velocity, dt);            // Step 5
  r.stages.correct = lap();
  if (extrapolated) r.interface_change = interface_change(x_hat);
  measure_all(r, centre_velocity, dt, steps_ + 1);
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
  moving_mesh_->restart_history();  // the mesh velocity by BDF1
  for (auto& module : modules_) module->restart_time_history();
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

StepReport DropSimulation::current_report() {
  StepReport r;
  r.step = steps_;
  r.time = time_;
  r.min_quality = mesh::min_quality(mesh_);
  measure_all(r, last_centre_velocity_, moving_mesh_->last_step(), steps_);
  return r;
}

StepContext DropSimulation::context(double dt, int step) const {
  StepContext c{config_, mesh_, *stokes_};
  c.solution = solution_ ? solution_.get() : nullptr;
  c.interface_values = solution_ && !interface_values_.empty() ? &interface_values_ : nullptr;
  c.mesh_velocity = moving_mesh_->velocity();
  c.interfaces = trackers_;
  c.time = time_;
  c.dt = dt;
  c.step = step;
  return c;
}

void DropSimulation::measure_all(StepReport& r, const std::vector<Vec3>& centre_velocity,
                                 double dt, int step) {
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
          step, time_, k + 1, e.what()));
    }
  }
  const StepContext now = context(dt, step);
  for (auto& module : modules_) module->measure(now, r);
}

std::vector<ReportFile> DropSimulation::report_files() const {
  std::vector<ReportFile> files{{"timeseries.csv", timeseries_header(), timeseries_rows}};
  for (const auto& module : modules_)
    for (auto& file : module->report_files()) files.push_back(std::move(file));
  return files;
}

void DropSimulation::summarise(nlohmann::json& summary) const {
  for (const auto& module : modules_) module->summarise(summary);
}

std::string DropSimulation::finish_reason() const {
  for (const auto& module : modules_)
    if (auto why = module->finished(); !why.empty()) return why;
  return {};
}

const ViscoelasticPhases* DropSimulation::viscoelastic() const {
  for (const auto& module : modules_)
    if (const auto* v = dynamic_cast<const ViscoelasticModule*>(module.get())) return &v->phases();
  return nullptr;
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
                     // After a remesh the reference mesh's interface is not the initial one.
                     r.set(p + "reference_areas", trackers_[k].reference_areas());
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
                     if (r.contains(p + "reference_areas"))  // records from before remeshing: the initial ones
                       trackers_[k].set_reference_areas(r.get_array(p + "reference_areas"));
                   }});
  // Each module's state saves and restores itself: the driver only lists it.
  for (auto& module : modules_) {
    for (fem::Field* f : module->fields()) add_field(*f);
    for (auto& part : module->state_parts()) registry_.add(std::move(part));
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
  moving_mesh_->save(r, p);
  // Each object's volume at t = 0: after a remesh the reference mesh a
  // restart builds on is the new one, whose volumes are not the initial ones.
  r.set(p + "initial_volumes", initial_volumes_);
  if (solution_) la::save_vector(r, p + "solution", solution_.get());
  else r.set(p + "solution", std::vector<double>{});
}

void DropSimulation::restore_time_loop(const StateRecord& r, const std::string& p) {
  steps_ = r.get_int(p + "step");
  time_ = r.get_double(p + "time");
  moving_mesh_->restore(r, p, config_.time.step);
  if (r.contains(p + "initial_volumes")) {  // records from before remeshing: the reference mesh's
    const auto& volumes = r.get_array(p + "initial_volumes");
    if (volumes.size() != initial_volumes_.size())
      throw InputError("the checkpoint's initial volumes do not fit the mesh it carries");
    initial_volumes_ = volumes;
  }
  const auto& solution = r.get_array(p + "solution");
  if (solution.empty()) {
    solution_.reset();
  } else {
    la::Vector restored = la::make_vector(stokes_->ownership().size(), stokes_->dofs().n_dofs());
    la::restore_vector(r, p + "solution", restored.get(), "Stokes solution");
    set_solution(std::move(restored));
  }
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
    if (trackers_.size() == 1) moving_mesh_->translate_x(trackers_[k].centre().x() - before.x());
  }
  return u;
}

double DropSimulation::move_mesh_ale(const std::vector<std::vector<Vec3>>& x_hat, double dt) {
  std::vector<physics::InterfacePlacement> placed;
  for (std::size_t k = 0; k < trackers_.size(); ++k)
    placed.push_back({trackers_[k].surface().volume_node, x_hat[k]});
  const double quality = moving_mesh_->move(placed, dt);
  if (quality < config_.time.min_quality) {
    throw MeshError(fmt::format(
        "step {} (t = {:.4f}): the moving mesh degraded: {} has quality {:.3g} < "
        "time.min_quality = {:.3g}. The deformation is too large for {}; try a smaller "
        "time.step, a larger interface.redistribution_factor, or a finer mesh{}{}",
        steps_ + 1, time_ + dt, mesh::describe_element(mesh_, mesh::worst_tet(mesh_)),
        quality, config_.time.min_quality,
        config_.remesh.quality > 0.0
            ? "the mesh, and remeshing (remesh.quality) could not replace it (see the notes "
              "above: docs/remeshing.md says which deformations it cannot mesh yet)"
            : "a mesh that is never remeshed ([remesh] quality > 0 remeshes it)",
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

const std::vector<mesh::Point>& DropSimulation::mesh_velocity() const { return moving_mesh_->velocity(); }
double DropSimulation::mesh_quality() const { return moving_mesh_->quality(); }
int DropSimulation::ale_rebuilds() const { return moving_mesh_->rebuilds(); }
int DropSimulation::relocation_steps() const { return moving_mesh_->relocation_steps(); }
int DropSimulation::relocated_nodes() const { return moving_mesh_->relocated_nodes(); }

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
  // Built once per mesh: the dofs change only with a remesh, which clears it.
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
  const StepContext now = context(dt, steps_ + 1);
  for (auto& module : modules_) module->contribute(problem, now);
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

bool DropSimulation::interface_slip() const { return stokes_->interface_slip(); }

}  // namespace softflow::simulation
