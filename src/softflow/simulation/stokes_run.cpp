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
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/stop_requests.hpp"

namespace softflow::simulation {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
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

/// A mesh preview may replace only an empty directory or an earlier preview
/// (mesh.json, no run's summary.json or checkpoint): never a run's results.
void refuse_to_replace_all_but_a_mesh(const std::filesystem::path& directory) {
  namespace fs = std::filesystem;
  if (!fs::exists(directory) || (fs::is_directory(directory) && fs::is_empty(directory))) return;
  const bool earlier_mesh = fs::exists(directory / "mesh.json") &&
                            !fs::exists(directory / "summary.json") &&
                            !fs::exists(directory / "checkpoint.h5");
  if (!earlier_mesh)
    throw InputError(fmt::format(
        "--output {}: the directory exists and is not a mesh written by `softflow mesh` (a run's "
        "results are never replaced by a mesh); give a new directory",
        directory.string()));
}

}  // namespace

nlohmann::json mesh_case(const io::CaseConfig& config, bool quiet,
                         const std::optional<std::filesystem::path>& output) {
  if (output) on_root_sharing_failure([&] { refuse_to_replace_all_but_a_mesh(*output); });
  const auto meshed = build_mesh(config);
  if (!quiet && is_root())
    fmt::print("mesh: {} nodes, {} tetrahedra, {} interface nodes, {} equator nodes ({} asked), "
               "{} vertices inside objects, min quality {:.3f}, {:.2f} s, fingerprint {}\n",
               meshed.report["nodes"].get<int>(), meshed.report["tetrahedra"].get<int>(),
               meshed.report["interface_nodes"].get<int>(),
               meshed.report["equator_nodes"].get<int>(),
               meshed.report["equator_nodes_requested"].get<int>(),
               meshed.report["object_interior_vertices"].get<int>(),
               meshed.report["min_quality"].get<double>(), meshed.report["seconds"].get<double>(),
               meshed.report["fingerprint"].get<std::string>());
  if (!quiet && is_root() && meshed.report.contains("cap_vertices"))
    fmt::print(
        "folded caps: tetrahedra lying flat on an interface folded once curved; meshed again with "
        "{} "
        "vertices embedded below them\n",
        meshed.report["cap_vertices"].get<int>());
  if (!quiet && is_root() && meshed.report.contains("wall_gap")) {
    const auto& g = meshed.report["wall_gap"];
    fmt::print("wall gap: objects[{}] to the wall y = {:g}: {:.4g} wide, {:.2f} elements across "
               "({} asked, mesh.gap_elements), {} tetrahedra crossed\n",
               g["object"].get<int>(), g["wall_y"].get<double>(), g["gap"].get<double>(),
               g["elements_across"].get<double>(), g["gap_elements_requested"].get<int>(),
               g["tetrahedra_crossed"].get<int>());
  }
  if (!quiet && is_root() && meshed.report.contains("point_symmetric_start")) {
    const auto& c = meshed.report["point_symmetric_start"];
    fmt::print(
        "point-symmetric start: meshed with the object on the z axis (fingerprint {}, min "
        "quality {:.3f}; {} nodes relocated symmetrically: {:.3f}), carried by ({:g}, {:g}, "
        "{:g}) to its centre{}\n",
        c["fingerprint_gmsh"].get<std::string>(), c["min_quality_gmsh"].get<double>(),
        c["relocated_nodes"].get<int>(), c["min_quality_before"].get<double>(),
        c["offset"][0].get<double>(), c["offset"][1].get<double>(), c["offset"][2].get<double>(),
        c.value("carry_steps", 1) > 1
            ? fmt::format(" in {} steps (in one, an element inverts)", c["carry_steps"].get<int>())
            : "");
  }
  if (output) {
    on_root_sharing_failure([&] {  // rank 0 writes
      io::OutputDirectory directory(*output, true);
      directory.write_text("case.toml", io::to_toml(config));
      directory.write_text("mesh.json", meshed.report.dump(2) + "\n");
      io::write_mesh(directory.staging_path(), meshed.mesh);
      directory.commit();
    });
    if (!quiet && is_root()) fmt::print("wrote {}/mesh.pvd\n", output->string());
  }
  return meshed.report;
}

nlohmann::json run_case(const io::CaseConfig& config, const RunOptions& options) {
  const auto start = Clock::now();
  const bool root = is_root();
  const std::filesystem::path directory =
      options.output_directory.value_or(std::filesystem::path(config.output_directory));
  // An interrupted run in the directory is refused before minutes of meshing.
  if (config.time.end > 0.0 && !options.overwrite)
    on_root_sharing_failure([&] { refuse_to_replace_unfinished_run(directory); });
  auto meshed = build_mesh(config);  // step 1 (rejects bad geometry before any file is made)
  if (config.time.end > 0.0) return run_drop_case(config, options, std::move(meshed));
  // Staged output: nothing appears under `directory` until the run succeeds.
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });
  leave_startup();  // the staging directory exists: a stop request now removes it cleanly
  const mesh::Mesh& mesh = meshed.mesh;
  if (!options.quiet && root)
    fmt::print("mesh: {} nodes, {} tetrahedra, {} interface nodes, min quality {:.3f}\n",
               mesh.n_nodes(), mesh.n_tets(), meshed.report["interface_nodes"].get<int>(),
               meshed.report["min_quality"].get<double>());

  const auto setup_start = Clock::now();
  physics::StokesSystem stokes(mesh, solver_settings(config),
                               io::has_interface_slip(config));  // step 2
  const double setup_seconds = seconds_since(setup_start);  // dof map, matrix patterns
  const auto result = stokes.solve(stokes_problem(config, mesh, 0.0));  // the initial state
  if (const int signal = stop_requested())
    throw RunInterrupted(fmt::format("stopped by {} before the results were written; run the case "
                                     "again", signal_name(signal)));
  const auto& dofs = stokes.dofs();
  if (!options.quiet && root)
    fmt::print("stokes: {} unknowns ({} velocity, {} pressure), assembly {:.2f} s, solve {:.2f} s, "
               "{} iterations ({})\n",
               dofs.n_dofs(), dofs.n_field_dofs(physics::kVelocityField),
               dofs.n_field_dofs(physics::kPressureField),
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
        {"velocity", dofs.n_field_dofs(physics::kVelocityField)},
        {"pressure", dofs.n_field_dofs(physics::kPressureField)}}},
      {"solver",
       {{"method", stokes.settings().method == la::SaddlePointMethod::direct ? "direct" : "iterative"},
        {"iterations", result.solve.iterations},
        {"converged_reason", result.solve.reason},
        {"residual_norm", result.solve.residual_norm},
        {"setup_seconds", setup_seconds},
        {"assembly_seconds", result.assembly_seconds},
        {"solve_seconds", result.solve.seconds}}},
      {"max_velocity", analysis::max_velocity(dofs, result.solution)},
      {"objects", object_summary(config, measures)},
  };
  summary["wall_seconds"] = seconds_since(start);
  summary["peak_memory_mb"] = peak_memory_summary();  // collective
  if (!options.quiet && root)
    for (const auto& o : summary["objects"]) {
      // What the README promises for end = 0: the jump across each interface.
      std::string laplace;
      if (o.contains("laplace_pressure_jump"))
        laplace = fmt::format(" (Laplace 2 Gamma / R = {:.6g})", o["laplace_pressure_jump"].get<double>());
      fmt::print("object {}: pressure jump {:.6g}{}, volume {:.6g}, area {:.6g}\n",
                 o["object"].get<int>(), o["pressure_jump"].get<double>(), laplace,
                 o["volume"].get<double>(), o["area"].get<double>());
    }

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
