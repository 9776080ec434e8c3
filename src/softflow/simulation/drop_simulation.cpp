#include "softflow/simulation/drop_simulation.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include <fmt/format.h>

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

namespace softflow::simulation {

namespace {

using physics::Vec3;
using Clock = std::chrono::steady_clock;

// A step's saved state: where the Stokes guess history stood (no part of
// the registry has this name).
constexpr const char* kGuessMarkKey = "step/stokes_guess_mark";

}  // namespace

DropSimulation::DropSimulation(const io::CaseConfig& config, mesh::Mesh mesh)
    : config_(config),
      models_(phase_models(config_)),
      mesh_(std::move(mesh)),
      initial_nodes_(mesh_.nodes) {
  build_parts();
  register_state();
}

void DropSimulation::build_parts() {
  stokes_ = std::make_unique<physics::StokesSystem>(mesh_, solver_settings(config_),
                                                    io::has_interface_slip(config_));
  moving_mesh_ = std::make_unique<physics::MovingMesh>(
      mesh_, physics::MovingMeshSettings{config_.time.ale_rebuild_quality,
                                         config_.time.relocation_quality});
  interfaces_ = std::make_unique<ObjectInterfaces>(config_, mesh_);
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
  // The new mesh: gmsh on rank 0 (gmsh is serial), sent to all.
  // The interfaces where the trackers have them (x_n): the mesh's interface
  // nodes are still at the step's prediction (Step 3 moved them there), an
  // O(dt^2) difference (1.8e-4 in volume, measured) a resampled interface
  // would inherit. A kept interface stays the mesh's: its tracker history
  // carries over as it is.
  mesh::Mesh tracked = mesh_;
  for (const auto& tracker : interfaces_->trackers())
    for (int i = 0; i < tracker.surface().n_nodes(); ++i)
      tracked.nodes[tracker.surface().volume_node[i]] = tracker.positions()[i];
  geometry::Remeshed r;
  std::string failure;
  if (la::mpi_rank() == 0) try {
      // Slip's multipliers live on the interface nodes: carried node for node only.
      const auto interfaces = io::has_interface_slip(config_) ? geometry::InterfaceRemeshing::keep
                                                              : config_.remesh.interfaces;
      r = geometry::remesh(config_.shear_cell_spec(), mesh_, interfaces, &tracked);
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
    MPI_Bcast(&r.report.algorithm, 1, MPI_INT, 0, PETSC_COMM_WORLD);
    MPI_Bcast(&r.report.interface_shape, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    MPI_Bcast(&r.report.volume_change, 1, MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    MPI_Bcast(&r.report.interface_triangles_before, 1, MPI_INT, 0, PETSC_COMM_WORLD);
    MPI_Bcast(&r.report.interface_triangles_after, 1, MPI_INT, 0, PETSC_COMM_WORLD);
    r.report.resampled.resize(old_mesh.n_objects);
    MPI_Bcast(r.report.resampled.data(), old_mesh.n_objects, MPI_CHAR, 0, PETSC_COMM_WORLD);
    r.old_surface_point.resize(r.mesh.n_nodes());
    MPI_Bcast(r.old_surface_point.data(),
              static_cast<int>(r.old_surface_point.size() * sizeof(r.old_surface_point[0])),
              MPI_BYTE, 0, PETSC_COMM_WORLD);
  }
  event.nodes_before = old_mesh.n_nodes();
  event.quality_before = moving_mesh_->quality();
  event.nodes_after = r.mesh.n_nodes();
  event.quality_after = r.report.quality_after;
  event.interface_shape = r.report.interface_shape;
  event.algorithm = r.report.algorithm == 10 ? "hxt" : "delaunay";
  event.interface_triangles_before = r.report.interface_triangles_before;
  event.interface_triangles_after = r.report.interface_triangles_after;
  event.resampled =
      static_cast<int>(std::count(r.report.resampled.begin(), r.report.resampled.end(), 1));

  // The parts on the new mesh, from scratch; then the state carried over.
  registry_ = StateRegistry{};
  added_fields_.clear();
  // The old modules stay until they have handed their fields over (reading
  // only their fields' values: the mesh they were built on is replaced).
  auto old_modules = std::move(modules_);
  modules_.clear();
  const auto old_interfaces = std::move(interfaces_);
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
  // A kept interface's nodes are the old ones: histories and reference areas
  // node for node; a resampled one's history is interpolated on the old
  // surface, its reference areas its own.
  event.volume_change = interfaces_->carry_over(*old_interfaces, r.new_node_of_old,
                                                r.report.resampled, r.old_surface_point);
  register_state();
  event.extrapolation = transfer.largest_extrapolation();
  event.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return event;
}

DropSimulation::~DropSimulation() = default;

StepReport DropSimulation::initial_report() {
  StepReport r;
  r.min_quality = mesh::min_quality(mesh_);
  measure_all(r, std::vector<Vec3>(interfaces_->size(), Vec3::Zero()), 0.0, 0);
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
  const auto x_hat = interfaces_->predict(dt);               // Step 1
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
  const bool extrapolated = interfaces_->extrapolating();
  interfaces_->correct(x_hat, centre_velocity, dt, fluid_at_interface());  // Step 5
  r.stages.correct = lap();
  if (extrapolated) r.interface_change = interfaces_->interface_change(x_hat);
  measure_all(r, centre_velocity, dt, steps_ + 1);
  ++steps_;
  interfaces_->set_last_centre_velocity(centre_velocity);
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
  interfaces_->restart_histories();
  moving_mesh_->restart_history();  // the mesh velocity by BDF1
  stokes_->restart_guess_history();
  for (auto& module : modules_) module->restart_time_history();
}

StateRecord DropSimulation::save_step_state() const {
  StateRecord state(StateRecord::Scope::this_rank);  // in memory: nothing gathered
  registry_.save(state, {"stokes"});
  // The Stokes system is not saved (its matrices and preconditioner stay),
  // only where its guess history stood.
  state.set(kGuessMarkKey, static_cast<double>(stokes_->guess_history_mark()));
  return state;
}

void DropSimulation::restore_step_state(const StateRecord& state) {
  registry_.restore(state, {"stokes"});
  // The rejected step's solve leaves the guess history: the retried step
  // extrapolates from x_n along x_{n-1}, x_n with its own step.
  stokes_->rewind_guess_history(static_cast<long>(state.get_double(kGuessMarkKey)));
}

StepReport DropSimulation::current_report() {
  StepReport r;
  r.step = steps_;
  r.time = time_;
  r.min_quality = mesh::min_quality(mesh_);
  measure_all(r, interfaces_->last_centre_velocity(), moving_mesh_->last_step(), steps_);
  return r;
}

StepContext DropSimulation::context(double dt, int step) const {
  StepContext c{config_, mesh_, *stokes_};
  c.solution = solution_ ? solution_.get() : nullptr;
  c.interface_values = solution_ && !interface_values_.empty() ? &interface_values_ : nullptr;
  c.mesh_velocity = moving_mesh_->velocity();
  c.interfaces = interfaces_->trackers();
  c.time = time_;
  c.dt = dt;
  c.step = step;
  return c;
}

void DropSimulation::measure_all(StepReport& r, const std::vector<Vec3>& centre_velocity,
                                 double dt, int step) {
  for (int k = 0; k < static_cast<int>(interfaces_->size()); ++k) {
    try {
      r.objects.push_back(interfaces_->measure(k, centre_velocity[k]));
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

void DropSimulation::check_volumes() const { interfaces_->check_volumes(steps_, time_); }

void DropSimulation::register_state() {
  // Restored in this order: the Stokes factors are rebuilt from their own
  // saved matrices, independent of the time loop's state.
  registry_.add({"time_loop",
                 [this](StateRecord& r, const std::string& p) { save_time_loop(r, p); },
                 [this](const StateRecord& r, const std::string& p) { restore_time_loop(r, p); }});
  registry_.add(stokes_->state_part());
  for (auto& part : interfaces_->state_parts()) registry_.add(std::move(part));
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
  r.set(p + "initial_volumes", interfaces_->initial_volumes());
  if (solution_) la::save_vector(r, p + "solution", solution_.get());
  else r.set(p + "solution", std::vector<double>{});
}

void DropSimulation::restore_time_loop(const StateRecord& r, const std::string& p) {
  steps_ = r.get_int(p + "step");
  time_ = r.get_double(p + "time");
  moving_mesh_->restore(r, p, config_.time.step);
  if (r.contains(p + "initial_volumes"))  // records from before remeshing: the reference mesh's
    interfaces_->set_initial_volumes(r.get_array(p + "initial_volumes"));
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

std::vector<Vec3> DropSimulation::translate_mesh(const InterfacePositions& x_hat, double dt) {
  double x_shift = 0.0;
  auto u = interfaces_->advance_centres(x_hat, dt, x_shift);
  if (interfaces_->size() == 1) moving_mesh_->translate_x(x_shift);
  return u;
}

double DropSimulation::move_mesh_ale(const InterfacePositions& x_hat, double dt) {
  const double quality = moving_mesh_->move(interfaces_->placements(x_hat), dt);
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

InterfaceVelocity DropSimulation::fluid_at_interface() const {
  return [this](int node, int object) { return interface_velocity(node, object); };
}

int DropSimulation::solve_stokes(const InterfacePositions& x_hat, double dt,
                                 StageSeconds& stages) {
  // time_ is already t_{n+1}: the walls of the end of the step.
  physics::StokesProblem problem = stokes_problem(config_, models_, mesh_, time_);
  problem.semi_implicit_tension =
      interfaces_->semi_implicit_tension(x_hat, dt, mesh_.n_nodes(), fluid_at_interface());
  const StepContext now = context(dt, steps_ + 1);
  for (auto& module : modules_) module->contribute(problem, now);
  auto result = stokes_->solve(problem, physics::SolutionLayout::distributed, dt);
  set_solution(std::move(result.distributed));
  stages.stokes_assembly = result.assembly_seconds;
  stages.stokes_solve = result.solve.seconds;
  return result.solve.iterations;
}

bool DropSimulation::interface_slip() const { return stokes_->interface_slip(); }

}  // namespace softflow::simulation
