#include "softflow/simulation/drop_simulation.hpp"

#include <chrono>
#include <utility>

#include <fmt/format.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/common/error.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/physics/ale/mesh_velocity.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace {

using physics::Vec3;
using Clock = std::chrono::steady_clock;

}  // namespace

DropSimulation::DropSimulation(const io::CaseConfig& config, mesh::Mesh mesh)
    : config_(config), mesh_(std::move(mesh)), reference_nodes_(mesh_.nodes) {
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
  const int iterations = solve_stokes(x_hat, dt, r.stages);  // Step 4
  lap();
  correct_interfaces(x_hat, centre_velocity, dt);            // Step 5
  r.stages.correct = lap();
  ++steps_;

  r.step = steps_;
  r.time = time_;
  r.min_quality = quality;
  r.stokes_iterations = iterations;
  for (int k = 0; k < static_cast<int>(trackers_.size()); ++k)
    r.objects.push_back(measure(k, centre_velocity[k]));
  r.stages.analysis = lap();
  r.step_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
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

double DropSimulation::move_mesh_ale(const std::vector<std::vector<Vec3>>& x_hat, double dt) {
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
  if (quality < config_.time.min_quality) {
    const int worst = mesh::worst_tet(mesh_);
    const auto& x = mesh_.nodes[mesh_.tets[worst][0]];
    throw MeshError(fmt::format(
        "step {} (t = {:.4f}): the moving mesh degraded: element {} (region {}, near ({:.3f}, "
        "{:.3f}, {:.3f})) has quality {:.3g} < time.min_quality = {:.3g}. The deformation is "
        "too large for a mesh that is never remeshed; try a smaller time.step, a larger "
        "interface.redistribution_factor, or a finer mesh",
        steps_ + 1, time_ + config_.time.step, worst, mesh_.tet_region[worst], x.x(), x.y(), x.z(),
        quality, config_.time.min_quality));
  }
  return quality;
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
  const auto& dofs = stokes_->dofs();
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& tracker = trackers_[k];
    const auto normals = physics::node_normals(tracker.surface(), x_hat[k]);
    const auto& nodes = tracker.surface().volume_node;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      tension.node_normal[nodes[i]] = normals[i];
      if (!first_step) {
        const int v = dofs.velocity_dof(nodes[i], 0);
        tension.predicted_normal_velocity[nodes[i]] =
            normals[i].dot(Vec3(solution_[v], solution_[v + 1], solution_[v + 2]));
      }
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
  const auto walls = physics::WallMotion::steady(config_.box.height, config_.shear_rate);
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
  const auto& dofs = stokes_->dofs();
  for (std::size_t k = 0; k < trackers_.size(); ++k) {
    const auto& nodes = trackers_[k].surface().volume_node;
    std::vector<Vec3> u(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const int v = dofs.velocity_dof(nodes[i], 0);  // no slip: the shared interface velocity
      u[i] = Vec3(solution_[v], solution_[v + 1], solution_[v + 2]);
    }
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
