#include "softflow/simulation/run_support.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <mpi.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/mesh/fingerprint.hpp"
#include "softflow/mesh/node_relocation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/parallel/memory.hpp"
#include "softflow/parallel/mesh_broadcast.hpp"
#include "softflow/physics/ale/mesh_motion.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/run_ledger.hpp"

namespace softflow::simulation {

bool is_root() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank == 0;
}

// Runs `work` on rank 0 only; a failure there is rethrown on every rank with
// the same type (input / mesh / other) and message, so no rank waits forever.
void on_root_sharing_failure(const std::function<void()>& work) {
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
  la::broadcast_text(error, 0, MPI_COMM_WORLD);
  if (failed == 1) throw InputError(error);
  if (failed == 2) throw MeshError(error);
  throw Error(error);
}

namespace {

/// The report's "wall_gap": how an object's gap to its nearest wall was meshed.
nlohmann::json wall_gap_report(const geometry::WallGapResolution& g, const io::CaseConfig& config) {
  return {{"object", g.object},
          {"wall_y", g.side * config.box.height / 2},
          {"gap", g.gap},
          {"elements_across", g.elements_across()},
          {"tetrahedra_crossed", g.tets_crossed},
          {"gap_elements_requested", config.sizing.elements_across_gaps()}};
}

/// After the mesh was moved (carried to the start, objects deformed): the
/// report describes the mesh the run starts from: its quality, fingerprint
/// and, when gmsh refined a wall gap, that gap as it now is (`objects`: each
/// object's surface, as moved). Root only.
void describe_moved_mesh(const io::CaseConfig& config, const std::vector<geometry::Ellipsoid>& objects,
                         MeshedCase& meshed) {
  auto& r = meshed.report;
  r["min_quality"] = mesh::min_quality(meshed.mesh);
  r["fingerprint"] = fmt::format("{:016x}", mesh::fingerprint(meshed.mesh));
  if (!r.contains("wall_gap")) return;
  const int object = r["wall_gap"]["object"];
  geometry::WallGapResolution g = geometry::measure_wall_gap(meshed.mesh, objects.at(object - 1));
  g.object = object;
  r["wall_gap"] = wall_gap_report(g, config);
}

/// The objects' surfaces as the case places them.
std::vector<geometry::Ellipsoid> case_objects(const io::CaseConfig& config) {
  std::vector<geometry::Ellipsoid> out;
  for (const auto& o : config.shear_cell_spec().objects) out.push_back(geometry::ellipsoid_of(o));
  return out;
}

/// Meshes `config` in this process (gmsh), with the report.
MeshedCase mesh_here(const io::CaseConfig& config) {
  MeshedCase out;
  geometry::MeshReport r;
  out.mesh = geometry::build_shear_cell(config.shear_cell_spec(), &r);
  out.report = {{"nodes", r.n_nodes},
                {"tetrahedra", r.n_tets},
                {"interface_nodes", r.n_interface_nodes},
                // What the case asked for and what the mesher made of it
                // (2 x 2 pi r / mean edge on the first object's equator).
                {"equator_nodes", r.n_equator_nodes},
                {"equator_nodes_requested", config.sizing.equator_nodes},
                {"object_interior_vertices", r.n_object_interior_vertices},
                {"min_quality", r.min_quality},
                {"seconds", r.seconds},
                {"fingerprint", fmt::format("{:016x}", r.fingerprint)}};
  if (r.cap_vertices > 0) out.report["cap_vertices"] = r.cap_vertices;
  if (r.wall_gap)  // an object close to a wall: how its gap was meshed
    out.report["wall_gap"] = wall_gap_report(*r.wall_gap, config);
  return out;
}

/// The mesh made by mesh_before_mpi, with the case it was made for, or why
/// it could not be made (then build_mesh reports that on every rank rather
/// than meshing again: a failing mesh took twice its time, e.g. an
/// ellipsoid gmsh meshes for 76 s before producing an inverted element).
struct EarlyMesh {
  std::string case_toml;
  MeshedCase meshed;
  std::exception_ptr failure;
};
std::optional<EarlyMesh>& early_mesh() {
  static std::optional<EarlyMesh> mesh;
  return mesh;
}

/// Node relocation's target on the symmetric mesh before the carry: the
/// default time.relocation_quality of a run.
constexpr double kStartRelocationQuality = 0.2;

/// mesh.point_symmetric_start: the symmetric mesh of the object on the z
/// axis, relocated and carried to the object's centre; the report then describes the
/// carried mesh (its quality, wall gap and fingerprint) and the offset.
/// Collective.
void carry_to_start(const io::CaseConfig& config, MeshedCase& meshed) {
  const geometry::ShearCellSpec spec = config.shear_cell_spec();
  const geometry::ShearCellSpec start = geometry::symmetric_start(spec);
  const Eigen::Vector3d offset = spec.objects[0].centre - start.objects[0].centre;
  // The run relocates no node (time.relocation_quality is 0 by default with
  // the key: the search is not a smooth function of the mesh, so it would
  // put back a drift that does not vanish with the offset). gmsh's worst
  // elements are relocated here instead, on the symmetric mesh, where the
  // search keeps the symmetry exactly (mesh::NodeRelocation pairs mirror
  // nodes): measured, an element of quality 0.048 folded (0.0005) at the
  // second step of a particle at beta = 0.2 otherwise.
  const auto relocated =
      mesh::NodeRelocation(meshed.mesh).improve(meshed.mesh.nodes, kStartRelocationQuality);
  const int carry_steps = physics::carry_objects(meshed.mesh, offset);
  if (!is_root()) return;
  auto& r = meshed.report;
  r["point_symmetric_start"] = {{"offset", {offset.x(), offset.y(), offset.z()}},
                                {"carry_steps", carry_steps},
                                {"min_quality_gmsh", r["min_quality"]},
                                {"relocated_nodes", relocated.nodes_moved},
                                {"min_quality_before", relocated.smallest_quality},
                                {"fingerprint_gmsh", r["fingerprint"]}};
  describe_moved_mesh(config, case_objects(config), meshed);
}

/// [[objects]] initial_deformation = "taylor": the map that turns the drop's
/// sphere into the steady ellipsoid of small-deformation theory about its
/// centre: semi-axes R s, R / s, R (s^2 = (1 + D) / (1 - D), so that
/// (L - B) / (L + B) = D and the volume is kept), the long axis at
/// Chaffey-Brenner's angle theta from the flow direction, towards +y.
physics::ObjectDeformation taylor_start(const io::CaseConfig& config, int object) {
  const io::ObjectConfig& o = config.objects[object - 1];
  const double radius = io::mean_radius(o.geometry);
  const double ca = config.matrix_viscosity * config.shear_rate * radius / o.interfacial_tension;
  const double d = analysis::theory::taylor_deformation(o.viscosity_ratio, ca);
  const double theta =
      analysis::theory::chaffey_brenner_angle_deg(o.viscosity_ratio, ca) * M_PI / 180.0;
  const double s = std::sqrt((1.0 + d) / (1.0 - d));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  physics::ObjectDeformation f;
  f.object = object;
  f.centre = o.geometry.centre;
  f.map = turn * Eigen::Vector3d(s, 1.0 / s, 1.0).asDiagonal() * turn.transpose();
  return f;
}

/// The objects that start deformed, deformed; their start in the mesh report.
void deform_to_start(const io::CaseConfig& config, MeshedCase& meshed) {
  std::vector<physics::ObjectDeformation> deformations;
  nlohmann::json report = nlohmann::json::array();
  for (int k = 1; k <= static_cast<int>(config.objects.size()); ++k) {
    if (config.objects[k - 1].initial_deformation != io::InitialDeformation::taylor) continue;
    deformations.push_back(taylor_start(config, k));
    const Eigen::Matrix3d& m = deformations.back().map;
    report.push_back({{"object", k}, {"map", {{m(0, 0), m(0, 1), m(0, 2)}, {m(1, 0), m(1, 1), m(1, 2)},
                                              {m(2, 0), m(2, 1), m(2, 2)}}}});
  }
  if (deformations.empty()) return;
  physics::deform_objects(meshed.mesh, deformations);
  if (!is_root()) return;
  meshed.report["initial_deformation"] = report;
  std::vector<geometry::Ellipsoid> objects = case_objects(config);
  for (const auto& f : deformations) objects[f.object - 1].map = f.map * objects[f.object - 1].map;
  describe_moved_mesh(config, objects, meshed);
}

}  // namespace

void mesh_before_mpi(const io::CaseConfig& config) {
  try {
    early_mesh() = EarlyMesh{io::to_toml(config), mesh_here(config), nullptr};
  } catch (const std::exception&) {
    // build_mesh reports the failure on every rank
    early_mesh() = EarlyMesh{io::to_toml(config), MeshedCase{}, std::current_exception()};
  }
}

// Step 1: rank 0 meshes (gmsh is serial), every rank receives the mesh.
MeshedCase build_mesh(const io::CaseConfig& config) {
  MeshedCase out;
  on_root_sharing_failure([&] {
    auto& early = early_mesh();
    if (early && early->case_toml == io::to_toml(config)) {
      const std::exception_ptr failure = early->failure;
      out = std::move(early->meshed);
      early.reset();
      if (failure) std::rethrow_exception(failure);
    } else {
      out = mesh_here(config);
    }
  });
  parallel::broadcast_mesh(out.mesh, MPI_COMM_WORLD);
  if (config.sizing.point_symmetric_start) carry_to_start(config, out);
  deform_to_start(config, out);
  return out;
}

la::SaddlePointSettings solver_settings(const io::CaseConfig& config) {
  la::SaddlePointSettings s;
  switch (config.solver) {
    case io::SolverType::automatic: s.method = la::SaddlePointMethod::automatic; break;
    case io::SolverType::direct: s.method = la::SaddlePointMethod::direct; break;
    case io::SolverType::iterative: s.method = la::SaddlePointMethod::iterative; break;
  }
  s.rtol = config.rtol;
  s.max_iterations = config.max_iterations;
  s.extrapolated_guess = config.initial_guess == io::InitialGuess::extrapolated;
  s.planned_steps = planned_step_count(config);
  s.relaxing_phase = io::has_relaxing_phase(config);
  return s;
}

long planned_step_count(const io::CaseConfig& config) {
  const io::TimeConfig& time = config.time;
  if (time.end <= 0.0) return 1;  // one Stokes solve of the initial state
  if (time.adaptive_tolerance > 0.0) {  // at least end / the largest step; unbounded: not known
    const bool bounded = time.max_step > 0.0 || redistribution_rate(config) > 0.0;
    return bounded ? static_cast<long>(std::ceil(time.end / adaptive_step_bound(config) - 1e-9)) : 0;
  }
  return static_cast<long>(std::ceil(time.end / time.step - 1e-9));
}

nlohmann::json peak_memory_summary() {
  const auto memory = parallel::peak_memory(PETSC_COMM_WORLD);
  return {{"largest_rank", memory.largest_rank_mb}, {"all_ranks", memory.total_mb}};
}

void draw_plot(const std::string& script, const std::filesystem::path& directory,
               const std::string& picture, bool quiet) {
  if (const char* plots = std::getenv("SOFTFLOW_PLOTS"); plots && std::string(plots) == "0") return;
  const std::filesystem::path path = std::filesystem::path(SOFTFLOW_SOURCE_DIR) / "scripts" / script;
  if (!std::filesystem::exists(path)) return;
  const std::string command = fmt::format("/usr/bin/python3 '{}' '{}' > /dev/null 2>&1",
                                          path.string(), directory.string());
  if (std::system(command.c_str()) != 0 && !quiet)
    fmt::print(stderr, "softflow: warning: could not draw {} (needs python3-matplotlib)\n", picture);
}

}  // namespace softflow::simulation
