// Pieces every kind of run shares: rank-0 work with shared failure, meshing, solver settings.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::simulation {

bool is_root();

/// Runs `work` on rank 0 only; a failure there is rethrown on every rank with
/// the same type (input / mesh / other) and message, so no rank waits forever.
void on_root_sharing_failure(const std::function<void()>& work);

struct MeshedCase {
  mesh::Mesh mesh;
  nlohmann::json report;  ///< nodes, tetrahedra, interface/equator nodes, min quality, seconds
};

/// Step 1 of every run: rank 0 meshes (gmsh is serial), every rank receives
/// the mesh. Rank 0 takes the mesh mesh_before_mpi made for the same case,
/// if there is one.
MeshedCase build_mesh(const io::CaseConfig& config);

/// Meshes `config` now and keeps the mesh for build_mesh: called before MPI
/// starts, by the process that will be rank 0. gmsh's meshes used to depend
/// in the last bits on the heap's layout, which MPI's threads make differ
/// from run to run (measured: 4 different meshes of one case in 6 runs after
/// MPI_Init, 1 in 10 before it). gmsh now runs in a DeterministicHeapScope
/// (common/deterministic_heap.hpp) and `softflow mesh`, `softflow run` and
/// rank 0 of an MPI run give the same mesh to the bit, before MPI or after
/// (meshing before it stays: it costs nothing). A failure is
/// not reported here: build_mesh reports it on every rank (without meshing
/// again).
void mesh_before_mpi(const io::CaseConfig& config);

/// The Stokes solver's settings for `config`. solver.type = "auto" stays
/// SaddlePointMethod::automatic, with the case's planned_steps: the
/// StokesSystem decides it from its number of unknowns and those steps
/// (la::resolve_method); stokes().settings() then holds the method it chose.
la::SaddlePointSettings solver_settings(const io::CaseConfig& config);

/// The time steps a case plans (what solver.type = "auto" weighs a
/// factorisation against): end / step for constant steps, end / the largest
/// adaptive step (max_step and the redistribution's bound, adaptive_step_bound:
/// a lower bound) for adaptive ones, 0 (not known) for adaptive steps
/// without any bound, 1 for end = 0 (one solve). A steady stop may end the
/// run earlier; the count is the whole run's, so a restart chooses as the
/// run did.
long planned_step_count(const io::CaseConfig& config);

/// summary.json's "peak_memory_mb": the largest rank's and all ranks' peak
/// resident set (parallel::peak_memory). Collective.
nlohmann::json peak_memory_summary();

/// Draws `picture` (e.g. "deformation.png") in `directory` with the
/// repository's scripts/<script> (matplotlib): a missing Python or
/// matplotlib costs the picture, with a warning unless `quiet`, not the run.
/// SOFTFLOW_PLOTS=0 in the environment skips every picture: starting
/// Python and matplotlib takes ~1 s, most of a short run's time (the test
/// suite sets it, but for the tests that check the pictures).
void draw_plot(const std::string& script, const std::filesystem::path& directory,
               const std::string& picture, bool quiet);

}  // namespace softflow::simulation
