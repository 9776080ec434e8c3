// One instantaneous two-phase Stokes solve from a case file: mesh, solve, analyse, write.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"

namespace softflow::simulation {

struct RunOptions {
  /// Overrides [output] directory.
  std::optional<std::filesystem::path> output_directory;
  /// No progress lines; errors only.
  bool quiet = false;
  /// A run in time checkpoints and stops (RunInterrupted) before this many
  /// seconds have passed since `started`.
  std::optional<double> wall_time_limit;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  /// Start afresh even where the output directory holds an unfinished run.
  bool overwrite = false;
};

/// Meshes the case (rank 0; replicated to all ranks), reports the mesh and,
/// given `output`, writes it there to look at before a run: mesh.pvd with
/// matrix.vtu, object_k.vtu (each element's quality as cell data), mesh.json
/// (the report) and case.toml (the resolved case), all or nothing
/// (io::OutputDirectory). `output` may not hold anything but an earlier
/// mesh: a run's results are never replaced (InputError).
nlohmann::json mesh_case(const io::CaseConfig& config, bool quiet,
                         const std::optional<std::filesystem::path>& output = {});

/// Runs the case: steps of the thesis's algorithm that exist so far —
///   1. mesh the shear cell (geometry::build_shear_cell),
///   2. assemble and solve the two-phase Stokes system (physics::StokesSystem),
///   3. measure each object (analysis::object_measures),
///   4. write case.toml, summary.json and fields.pvd atomically.
/// Returns the summary written to summary.json.
nlohmann::json run_case(const io::CaseConfig& config, const RunOptions& options);

}  // namespace softflow::simulation
