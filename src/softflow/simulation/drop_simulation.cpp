#include "softflow/simulation/drop_simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/common/error.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/physics/ale/mesh_velocity.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace {

using physics::Vec3;
using Clock = std::chrono::steady_clock;

}  // namespace

DropSimulation::DropSimulation(const io::CaseConfig& config, mesh::Mesh mesh)
    : config_(config),
      mesh_(std::move(mesh)),
      initial_nodes_(mesh_.nodes),
      reference_nodes_(mesh_.nodes) {
  stokes_ = std::make_unique<physics::StokesSystem>(mesh_, solver_settings(config_));
  ale_ = std::make_unique<physics::AleMeshMotion>(mesh_);
  physics::InterfaceTrackerSettings tracking;
  // k = (k / gamma_dot) gamma_dot; at rest the factor is taken as k itself.
  tracking.redistribution_factor =
      config_.interface.redistribution_factor * (config_.shear_rate > 0 ? config_.shear_rate : 1.0);
  tracking.supg_beta = config_.interface.supg_beta;
  for (int k = 1; k <= mesh_.n_objects; ++k) {
    auto surface = physics::extract_interface(mesh_, k);
    auto x0 = physics::interface_positions(surface, mesh_);
    trackers_.emplace_back(std::move(surface), std::move(x0), tracking);
  }
  last_centre_velocity_.assign(trackers_.size(), Vec3::Zero());
  mesh_velocity_.assign(mesh_.n_nodes(), mesh::Point::Zero());
  last_quality_ = mesh::min_quality(mesh_);
  for (const auto& tracker : trackers_)
    initial_volumes_.push_back(physics::surface_integrals(tracker.surface(), tracker.positions()).volume);
}

DropSimulation::~DropSimulation() = default;

StepReport DropSimulation::initial_report() const {
  StepReport r;
  r.min_quality = mesh::min_quality(mesh_);
  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k) r.objects.push_back(measure(k, Vec3::Zero()));
  return r;
}

StepReport DropSimulation::step() {
  const auto start = Clock::now();
  auto lap = [last = start]() mutable {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - last).count();
    last = now;
    return s;
  };
  StepReport r;
  const double dt = config_.time.step;
  const auto x_hat = predict_interfaces();                   // Step 1
  const auto centre_velocity = translate_mesh(x_hat, dt);    // Step 2
  r.stages.predict_and_translate = lap();
  const double quality = move_mesh_ale(x_hat, dt);           // Step 3
  r.stages.ale = lap();
  time_ += dt;
  const int factorizations = stokes_->n_factorizations();
  int iterations = 0;
  try {
    iterations = solve_stokes(x_hat, dt, r.stages);          // Step 4
  } catch (const SolverError& e) {
    throw SolverError(fmt::format("step {} (t = {:.4f}): {}", steps_ + 1, time_, e.what()));
  }
  if (config_.solver == io::SolverType::direct && stokes_->n_factorizations() > factorizations) {
    if (analysis_nodes_.empty()) {
      analysis_nodes_ = mesh_.nodes;
      analysis_step_ = steps_ + 1;
    }
    factorization_nodes_ = mesh_.nodes;
    factorization_step_ = steps_ + 1;
  }
  check_solution_finite();
  lap();
  correct_interfaces(x_hat, centre_velocity, dt);            // Step 5
  r.stages.correct = lap();

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

StepReport DropSimulation::current_report() const {
  StepReport r;
  r.step = steps_;
  r.time = time_;
  r.min_quality = mesh::min_quality(mesh_);
  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k)
    r.objects.push_back(measure(k, last_centre_velocity_[k]));
  return r;
}

void DropSimulation::check_solution_finite() const {
  const auto bad = std::find_if(solution_.begin(), solution_.end(),
                                [](double v) { return !std::isfinite(v); });
  if (bad == solution_.end()) return;
  const int dof = static_cast<int>(bad - solution_.begin());
  const auto& dofs = stokes_->dofs();
  const int node = dofs.node_of(dof);
  const int region = dofs.region_of(dof);
  const auto& x = mesh_.nodes[node];
  throw SolverError(fmt::format(
      "step {} (t = {:.4f}): the Stokes solution is not finite ({} {} at node {}, {}, near "
      "({:.3f}, {:.3f}, {:.3f})). Usually solver options that do not converge (check "
      "[solver] and the PETSc options), a time step too large for the surface tension (with "
      "interface.semi_implicit_tension = false) or a tangled mesh: try the default solver, a "
      "smaller time.step or a finer mesh",
      steps_ + 1, time_, *bad, dofs.is_velocity(dof) ? "velocity" : "pressure", node,
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

void DropSimulation::save(io::Checkpoint& c) const {
  c.step = steps_;
  c.time = time_;
  c.dt = config_.time.step;
  c.translation_x = translation_x_;
  c.reference_mesh = mesh_;
  c.reference_mesh.nodes = initial_nodes_;
  c.ale_reference_nodes = reference_nodes_;
  c.ale_rebuilt_at_quality = ale_rebuilt_at_quality_;
  c.ale_rebuilds = ale_rebuilds_;
  c.nodes = mesh_.nodes;
  c.previous_nodes = previous_nodes_;
  c.mesh_velocity = mesh_velocity_;
  c.solution = solution_;
  c.analysis_nodes = analysis_nodes_;
  c.analysis_step = analysis_step_;
  c.factorization_nodes = factorization_nodes_;
  c.factorization_step = factorization_step_;
  c.refactor_next = stokes_->solver().refactor_next();
  c.n_factorizations = stokes_->n_factorizations();
  c.objects.clear();
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto h = trackers_[k].history();
    c.objects.push_back({h.x, h.x_previous, h.centre, h.centre_previous, h.steps, h.centre_steps,
                         last_centre_velocity_[k]});
  }
}

void DropSimulation::restore(const io::Checkpoint& c) {
  const auto n = mesh_.nodes.size();
  if (c.nodes.size() != n || c.objects.size() != trackers_.size() ||
      (!c.previous_nodes.empty() && c.previous_nodes.size() != n) ||
      (!c.mesh_velocity.empty() && c.mesh_velocity.size() != n) ||
      (!c.solution.empty() && static_cast<int>(c.solution.size()) != stokes_->dofs().n_dofs()))
    throw InputError("the checkpoint does not fit the mesh it carries");
  time_ = c.time;
  translation_x_ = c.translation_x;
  solution_ = c.solution;
  // The trackers are still at t = 0 here: what the first step's Stokes
  // matrix depended on (see rebuild_preconditioner).
  if (c.analysis_step == 1) rebuild_factorization(c.analysis_nodes);
  steps_ = c.step;
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& o = c.objects[k];
    trackers_[k].restore({o.x, o.x_previous, o.centre, o.centre_previous, o.steps, o.centre_steps});
    last_centre_velocity_[k] = o.last_centre_velocity;
  }
  rebuild_preconditioner(c);
  mesh_.nodes = c.nodes;
  previous_nodes_ = c.previous_nodes;
  mesh_velocity_ = c.mesh_velocity.empty() ? std::vector<mesh::Point>(n, mesh::Point::Zero())
                                           : c.mesh_velocity;
  solution_ = c.solution;
  last_quality_ = mesh::min_quality(mesh_);
  ale_rebuilt_at_quality_ = c.ale_rebuilt_at_quality;
  ale_rebuilds_ = c.ale_rebuilds;
  if (!c.ale_reference_nodes.empty() && c.ale_reference_nodes != initial_nodes_) {
    // The mesh-motion operator was rebuilt on a later mesh: build it there again.
    reference_nodes_ = c.ale_reference_nodes;
    mesh::Mesh reference = mesh_;
    reference.nodes = reference_nodes_;
    ale_ = std::make_unique<physics::AleMeshMotion>(reference);
  }
}

void DropSimulation::rebuild_preconditioner(const io::Checkpoint& c) {
  // Round-off agreement with an uninterrupted run. With the direct method
  // the solver keeps the LU factors of an earlier matrix and preconditions
  // GMRES with them until a solve needs more than 25 iterations. Fresh
  // factors at restart would change every later solve at the level of the
  // solver tolerance (1e-8), and the iteration counts with it. So the
  // checkpoint records the mesh nodes at which the factors in use were
  // built, and the reuse policy's state; here the matrix is assembled on
  // those nodes and factored again, which gives the same factors: the
  // matrix depends only on the nodes, the case and (through the
  // semi-implicit tension's theta dt) on whether it was the first step,
  // never on the time or the right-hand side.
  // MUMPS's symbolic analysis (ordering, and a scaling that looks at the
  // values) is done once, at the first factorisation, and kept for later
  // numeric ones of the same pattern; so the matrix of the first
  // factorisation is factored first, as the uninterrupted run did. A
  // first-step matrix is rebuilt by restore() while the trackers are still
  // at t = 0. The iterative method builds its preconditioner at every
  // solve: nothing to do.
  if (config_.solver != io::SolverType::direct || c.factorization_nodes.empty()) return;
  if (c.analysis_step != 1) rebuild_factorization(c.analysis_nodes);
  if (c.factorization_step != c.analysis_step) rebuild_factorization(c.factorization_nodes);
  analysis_nodes_ = c.analysis_nodes;
  analysis_step_ = c.analysis_step;
  factorization_nodes_ = c.factorization_nodes;
  factorization_step_ = c.factorization_step;
  stokes_->solver().restore_reuse_state(c.refactor_next, c.n_factorizations);
}

void DropSimulation::rebuild_factorization(const std::vector<mesh::Point>& nodes) {
  if (config_.solver != io::SolverType::direct || nodes.empty()) return;
  // The mesh as it was at that solve: the interfaces on their predicted
  // positions x_hat, which the moved mesh carries exactly (move_mesh_ale).
  mesh_.nodes = nodes;
  std::vector<std::vector<Vec3>> x_hat(trackers_.size());
  for (std::size_t k = 0; k < trackers_.size(); ++k)
    for (int node : trackers_[k].surface().volume_node) x_hat[k].push_back(nodes[node]);
  StageSeconds ignored;
  stokes_->solver().request_fresh_preconditioner();
  solve_stokes(x_hat, config_.time.step, ignored);
}

std::vector<std::vector<Vec3>> DropSimulation::predict_interfaces() const {
  std::vector<std::vector<Vec3>> x_hat;
  for (const auto& tracker : trackers_) x_hat.push_back(tracker.predict());
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
  translation_x_ = 0.0;
  ale_ = std::make_unique<physics::AleMeshMotion>(mesh_);
  ale_rebuilt_at_quality_ = last_quality_;
  ++ale_rebuilds_;
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
  for (int i = 0; i < mesh_.n_nodes(); ++i) moved[i] = reference_nodes_[i] + d1 + d2[i];
  for (std::size_t k = 0; k < trackers_.size(); ++k) {  // exactly on the predicted interface
    const auto& nodes = trackers_[k].surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) moved[nodes[i]] = x_hat[k][i];
  }
  mesh_velocity_ = physics::bdf_mesh_velocity(moved, mesh_.nodes, previous_nodes_, dt);
  previous_nodes_ = std::exchange(mesh_.nodes, std::move(moved));
  const double quality = mesh::min_quality(mesh_);
  last_quality_ = quality;
  if (quality < config_.time.min_quality) {
    const int worst = mesh::worst_tet(mesh_);
    const auto& x = mesh_.nodes[mesh_.tets[worst][0]];
    throw MeshError(fmt::format(
        "step {} (t = {:.4f}): the moving mesh degraded: element {} (region {}, near ({:.3f}, "
        "{:.3f}, {:.3f})) has quality {:.3g} < time.min_quality = {:.3g}. The deformation is "
        "too large for a mesh that is never remeshed; try a smaller time.step, a larger "
        "interface.redistribution_factor, or a finer mesh{}",
        steps_ + 1, time_ + config_.time.step, worst, mesh_.tet_region[worst], x.x(), x.y(), x.z(),
        quality, config_.time.min_quality,
        // Explicit tension collapses the interface mesh above the capillary step limit.
        config_.interface.semi_implicit_tension
            ? ""
            : "; with explicit tension, a step above the capillary limit (about eta h / Gamma) "
              "does this: interface.semi_implicit_tension = true lifts it"));
  }
  return quality;
}

Vec3 DropSimulation::interface_velocity(int node) const {
  // No slip: the matrix-side copy is the shared interface velocity.
  const int v = stokes_->dofs().velocity_dof(node, 0);
  return Vec3(solution_[v], solution_[v + 1], solution_[v + 2]);
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
  const bool first_step = trackers_.front().steps() == 0;
  tension.theta_dt = first_step ? dt : 2.0 * dt / 3.0;
  tension.node_normal.assign(mesh_.n_nodes(), Vec3::Zero());
  tension.predicted_normal_velocity.assign(mesh_.n_nodes(), 0.0);
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& tracker = trackers_[k];
    const auto normals = physics::node_normals(tracker.surface(), x_hat[k]);
    const auto& nodes = tracker.surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      tension.node_normal[nodes[i]] = normals[i];
      if (!first_step)
        tension.predicted_normal_velocity[nodes[i]] = normals[i].dot(interface_velocity(nodes[i]));
    }
  }
  return tension;
}

int DropSimulation::solve_stokes(const std::vector<std::vector<Vec3>>& x_hat, double dt,
                                 StageSeconds& stages) {
  physics::StokesProblem problem;
  problem.semi_implicit_tension = semi_implicit_tension(x_hat, dt);
  problem.viscosity.push_back(config_.matrix_viscosity);
  for (const auto& o : config_.objects) {
    problem.viscosity.push_back(o.viscosity_ratio * config_.matrix_viscosity);
    problem.interfacial_tension.push_back(o.interfacial_tension);
  }
  const auto walls = wall_motion(config_);
  const double t = time_;
  problem.boundary_velocity = [walls, t](const Vec3& x) { return walls.velocity(x, t); };
  problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh_);
  auto result = stokes_->solve(problem);
  solution_ = std::move(result.solution);
  stages.stokes_assembly = result.assembly_seconds;
  stages.stokes_solve = result.solve.seconds;
  return result.solve.iterations;
}

void DropSimulation::correct_interfaces(const std::vector<std::vector<Vec3>>& x_hat,
                                        const std::vector<Vec3>& centre_velocity, double dt) {
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& nodes = trackers_[k].surface().volume_node;
    std::vector<Vec3> u(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) u[i] = interface_velocity(nodes[i]);
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
  s.theta_deg = fit.theta_deg;
  s.L = fit.L;
  s.B = fit.B;
  s.W = fit.W;
  s.ellipsoid_deviation = fit.max_relative_deviation;
  return s;
}

std::string timeseries_header() {
  return "step,t,object,D,theta_deg,L,B,W,xc,yc,zc,uc,vc,wc,volume,area,ellipsoid_dev,"
         "min_quality,stokes_iterations,step_seconds\n";
}

std::string timeseries_rows(const StepReport& r) {
  std::string out;
  for (const auto& o : r.objects)
    out += fmt::format(
        "{},{:.10g},{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},"
        "{:.10g},{:.10g},{:.10g},{:.10g},{:.6g},{:.6g},{},{:.4g}\n",
        r.step, r.time, o.object, o.deformation, o.theta_deg, o.L, o.B, o.W, o.centre.x(),
        o.centre.y(), o.centre.z(), o.centre_velocity.x(), o.centre_velocity.y(),
        o.centre_velocity.z(), o.volume, o.area, o.ellipsoid_deviation, r.min_quality,
        r.stokes_iterations, r.step_seconds);
  return out;
}

}  // namespace softflow::simulation
