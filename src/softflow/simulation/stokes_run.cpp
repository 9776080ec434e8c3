#include "softflow/simulation/stokes_run.hpp"

#include <chrono>
#include <fstream>
#include <memory>

#include <fmt/format.h>
#include <mpi.h>

#include "softflow/analysis/interface_measures.hpp"
#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/parallel/mesh_broadcast.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"

namespace softflow::simulation {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

bool is_root() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank == 0;
}

struct MeshedCase {
  mesh::Mesh mesh;
  nlohmann::json report;
};

// Runs `work` on rank 0 only; a failure there is rethrown on every rank with
// the same type (input / mesh / other) and message, so no rank waits forever.
template <class Work>
void on_root_sharing_failure(Work&& work) {
  std::string error;
  int failed = 0;  // 1 input, 2 mesh, 3 other
  if (is_root()) {
    try {
      work();
    } catch (const InputError& e) {
      error = e.what();
      failed = 1;
    } catch (const MeshError& e) {
      error = e.what();
      failed = 2;
    } catch (const std::exception& e) {
      error = e.what();
      failed = 3;
    }
  }
  MPI_Bcast(&failed, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (!failed) return;
  int n = static_cast<int>(error.size());
  MPI_Bcast(&n, 1, MPI_INT, 0, MPI_COMM_WORLD);
  error.resize(n);
  MPI_Bcast(error.data(), n, MPI_CHAR, 0, MPI_COMM_WORLD);
  if (failed == 1) throw InputError(error);
  if (failed == 2) throw MeshError(error);
  throw Error(error);
}

// Step 1: rank 0 meshes (gmsh is serial), every rank receives the mesh.
MeshedCase build_mesh(const io::CaseConfig& config) {
  MeshedCase out;
  on_root_sharing_failure([&] {
    geometry::MeshReport r;
    out.mesh = geometry::build_shear_cell(config.shear_cell_spec(), &r);
    out.report = {{"nodes", r.n_nodes},
                  {"tetrahedra", r.n_tets},
                  {"interface_nodes", r.n_interface_nodes},
                  {"equator_nodes", r.n_equator_nodes},
                  {"min_quality", r.min_quality},
                  {"seconds", r.seconds}};
  });
  parallel::broadcast_mesh(out.mesh, MPI_COMM_WORLD);
  return out;
}

// The walls move with u = (+-gamma_dot H/2, 0, 0); box faces that are not
// periodic carry the undisturbed shear u = (gamma_dot y, 0, 0).
physics::StokesProblem stokes_problem(const io::CaseConfig& config, const mesh::Mesh& mesh) {
  physics::StokesProblem p;
  p.viscosity.push_back(config.matrix_viscosity);
  for (const auto& o : config.objects) {
    p.viscosity.push_back(o.viscosity_ratio * config.matrix_viscosity);
    p.interfacial_tension.push_back(o.interfacial_tension);
  }
  const auto walls = physics::WallMotion::steady(config.box.height, config.shear_rate);
  const double t = 0.0;  // the instantaneous solve of the initial state
  p.boundary_velocity = [walls, t](const Eigen::Vector3d& x) { return walls.velocity(x, t); };
  p.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
  p.pressure_gauge_value = 0.0;
  return p;
}

la::SaddlePointSettings solver_settings(const io::CaseConfig& config) {
  la::SaddlePointSettings s;
  s.method = config.solver == io::SolverType::direct ? la::SaddlePointMethod::direct
                                                     : la::SaddlePointMethod::iterative;
  s.rtol = config.rtol;
  s.max_iterations = config.max_iterations;
  return s;
}

nlohmann::json object_summary(const io::CaseConfig& config,
                              const std::vector<analysis::ObjectMeasures>& measures) {
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& m : measures) {
    const auto& o = config.objects[m.object - 1];
    const auto& a = o.geometry.semi_axes;
    const double r = io::mean_radius(o.geometry);
    nlohmann::json j = {{"object", m.object},
                        {"volume", m.volume},
                        {"volume_exact", 4.0 / 3.0 * M_PI * a.x() * a.y() * a.z()},
                        {"area", m.area},
                        {"centre", {m.centre.x(), m.centre.y(), m.centre.z()}},
                        {"mean_interface_velocity",
                         {m.mean_interface_velocity.x(), m.mean_interface_velocity.y(),
                          m.mean_interface_velocity.z()}},
                        {"pressure_jump", m.pressure_jump}};
    if (o.geometry.shape == geometry::ObjectShape::sphere)
      j["laplace_pressure_jump"] = 2.0 * o.interfacial_tension / r;  // 2 Gamma / R
    objects.push_back(j);
  }
  return objects;
}

}  // namespace

nlohmann::json mesh_case(const io::CaseConfig& config, bool quiet) {
  const auto meshed = build_mesh(config);
  if (!quiet && is_root())
    fmt::print("mesh: {} nodes, {} tetrahedra, {} interface nodes, {} equator nodes, "
               "min quality {:.3f}, {:.2f} s\n",
               meshed.report["nodes"].get<int>(), meshed.report["tetrahedra"].get<int>(),
               meshed.report["interface_nodes"].get<int>(),
               meshed.report["equator_nodes"].get<int>(),
               meshed.report["min_quality"].get<double>(), meshed.report["seconds"].get<double>());
  return meshed.report;
}

nlohmann::json run_case(const io::CaseConfig& config, const RunOptions& options) {
  const auto start = Clock::now();
  const bool root = is_root();
  const std::filesystem::path directory =
      options.output_directory.value_or(std::filesystem::path(config.output_directory));
  const auto meshed = build_mesh(config);  // step 1 (rejects bad geometry before any file is made)
  // Staged output: nothing appears under `directory` until the run succeeds.
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });
  const mesh::Mesh& mesh = meshed.mesh;
  if (!options.quiet && root)
    fmt::print("mesh: {} nodes, {} tetrahedra, {} interface nodes, min quality {:.3f}\n",
               mesh.n_nodes(), mesh.n_tets(), meshed.report["interface_nodes"].get<int>(),
               meshed.report["min_quality"].get<double>());

  physics::StokesSystem stokes(mesh, solver_settings(config));  // step 2
  const auto result = stokes.solve(stokes_problem(config, mesh));
  const auto& dofs = stokes.dofs();
  if (!options.quiet && root)
    fmt::print("stokes: {} unknowns ({} velocity, {} pressure), assembly {:.2f} s, solve {:.2f} s, "
               "{} iterations ({})\n",
               dofs.n_dofs(), dofs.n_velocity_dofs(), dofs.n_pressure_dofs(),
               result.assembly_seconds, result.solve.seconds, result.solve.iterations,
               result.solve.reason);

  const auto measures = analysis::object_measures(mesh, dofs, result.solution);  // step 3

  nlohmann::json summary = {
      {"softflow_version", SOFTFLOW_VERSION},
      {"case", config.name},
      {"mpi_ranks", la::mpi_size()},
      {"mesh", meshed.report},
      {"dimensionless_groups", io::to_json(io::dimensionless_groups(config))},
      {"unknowns",
       {{"total", dofs.n_dofs()},
        {"velocity", dofs.n_velocity_dofs()},
        {"pressure", dofs.n_pressure_dofs()}}},
      {"solver",
       {{"method", config.solver == io::SolverType::direct ? "direct" : "iterative"},
        {"iterations", result.solve.iterations},
        {"converged_reason", result.solve.reason},
        {"residual_norm", result.solve.residual_norm},
        {"assembly_seconds", result.assembly_seconds},
        {"solve_seconds", result.solve.seconds}}},
      {"max_velocity", analysis::max_velocity(dofs, result.solution)},
      {"objects", object_summary(config, measures)},
  };
  summary["wall_seconds"] = seconds_since(start);

  on_root_sharing_failure([&] {  // step 4
    output->write_text("case.toml", io::to_toml(config));
    if (config.write_fields)
      io::write_stokes_fields(output->staging_path(), mesh, dofs, result.solution);
    output->write_text("summary.json", summary.dump(2) + "\n");
    output->commit();
  });
  if (!options.quiet && root) fmt::print("wrote {}\n", directory.string());
  return summary;
}

}  // namespace softflow::simulation
