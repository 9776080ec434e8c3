// A drop-in-shear run in time: the loop, its progress, checkpoints, time series, summary and plot.
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/stokes_run.hpp"

namespace softflow::simulation {

/// Runs `config` from t = 0 to time.end with the thesis's Steps 1-5
/// (DropSimulation).
///
/// The output directory is created when the run starts (replacing an older
/// one at once, atomically) and stays readable while it runs; every file in
/// it is replaced atomically or only appended to:
///   case.toml        the resolved case
///   timeseries.csv   one row per object and step, appended each step
///   progress.json    step, t, D, theta, status, ETA: rewritten each step
///   checkpoint.h5    the state to continue from ([checkpoint] intervals, the
///                    end, a stop request, the wall-time limit)
///   fields.pvd       ParaView series (every time.fields_interval steps, and the last)
///   summary.json     final D and theta, theory, wall time, unknowns, steps,
///                    volume drift, status, and why the run stopped
///   deformation.png  D(t), theta(t) beside Taylor and Chaffey-Brenner
///
/// A failure (MeshError, SolverError, AccuracyError) keeps what was
/// computed and the last checkpoint, writes the summary with the reason and
/// is rethrown. SIGINT, SIGTERM or SIGUSR1 (on any rank), or the wall-time
/// limit, end the run after the current step with a checkpoint: RunInterrupted
/// is thrown once everything is written. A directory that holds an
/// interrupted run is not replaced unless options.overwrite.
/// A mesh that starts below time.min_quality would stop the run at its first
/// step with advice about the time step: MeshError saying what it is and
/// which mesh keys change it (issue 11), before anything is written. Not when
/// the mesh is also below remesh.quality: the run remeshes before its first
/// step, and time.min_quality judges that mesh.
void check_initial_mesh_quality(const io::CaseConfig& config, const mesh::Mesh& mesh);

nlohmann::json run_drop_case(const io::CaseConfig& config, const RunOptions& options,
                             MeshedCase meshed);

/// Continues the run in `directory` from its checkpoint.h5, in place: the
/// time series is cut back to the checkpoint's step and appended to, the
/// field series extended. `config` is the directory's case.toml; it must be
/// the case the checkpoint was written with ([checkpoint] settings aside) and
/// the checkpoint must come from this softflow version, or InputError says
/// why not. A run already complete is left as it is.
nlohmann::json restart_drop_case(const io::CaseConfig& config,
                                 const std::filesystem::path& directory, const RunOptions& options);

/// Throws if a fresh run in `directory` would throw work away or share it
/// with another writer: io::DirectoryBusy if progress.json records a run
/// still "running" (the caller holds the io::RunLock, so that run is on
/// another host, or its pid was reused); InputError for a killed run (with
/// or without a checkpoint) and for an unfinished run with a checkpoint.
/// `softflow run --overwrite` skips the check.
void refuse_to_replace_unfinished_run(const std::filesystem::path& directory);

/// The status of the run in `directory`: summary.json's if there is one,
/// else progress.json's, where "running" with a recorded pid of this host
/// that is no live process becomes "killed" (stopped without a final
/// checkpoint: SIGKILL, out of memory, a lost node). "" if neither file is
/// readable. A pid reused since by another process reads as "running".
std::string run_status(const std::filesystem::path& directory);

/// This machine's host name, as recorded in progress.json.
std::string host_name();

/// Name of the checkpoint file in a run's output directory.
inline constexpr const char* kCheckpointFile = "checkpoint.h5";

}  // namespace softflow::simulation
