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
/// starts, by the process that will be rank 0. gmsh's meshes depend in the
/// last bits on the heap's layout, which MPI's threads make differ from run
/// to run (measured: 4 different meshes of one case in 6 runs after
/// MPI_Init, 1 in 10 before it; with OpenCASCADE's own memory manager,
/// MMGT_OPT=1, which main arranges). What remains: the mesh still depends
/// on the heap the process built up before meshing, so `softflow mesh`,
/// `softflow run` and rank 0 of an MPI run each give their own mesh of a
/// case, the same in every run but differing from each other in the last
/// bits of some coordinates. A failure is not reported here: build_mesh
/// meshes again and reports it on every rank.
void mesh_before_mpi(const io::CaseConfig& config);

/// Above this many Stokes unknowns solver.type = "auto" solves iteratively:
/// MUMPS LU took 3.5 GB and 77 s at 124k unknowns, 19 GB and 1000 s at 366k
/// on this machine, FGMRES + Schur fieldsplit 0.8 GB / 7 s and 2.2 GB / 29 s
/// (PLATFORM.md); below it the direct solver's factor reuse wins.
inline constexpr int kDirectSolverLimit = 150000;

/// The method solver.type asks for on a system of `unknowns` Stokes unknowns.
la::SaddlePointMethod solver_method(io::SolverType type, int unknowns);

/// The Stokes solver's settings for `config` on `mesh` (which decides
/// solver.type = "auto" by its number of unknowns).
la::SaddlePointSettings solver_settings(const io::CaseConfig& config, const mesh::Mesh& mesh);

/// Draws `picture` (e.g. "deformation.png") in `directory` with the
/// repository's scripts/<script> (matplotlib): a missing Python or
/// matplotlib costs the picture, with a warning unless `quiet`, not the run.
void draw_plot(const std::string& script, const std::filesystem::path& directory,
               const std::string& picture, bool quiet);

}  // namespace softflow::simulation
