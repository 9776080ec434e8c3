#include "softflow/simulation/drop_run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <limits>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <memory>
#include <numbers>
#include <optional>
#include <deque>
#include <set>
#include <sstream>
#include <string>

#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>
#include <mpi.h>

#include "softflow/analysis/steady_state.hpp"
#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/simulation/remesh_triggers.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_directory.hpp"
#include "softflow/simulation/adaptive_stepping.hpp"
#include "softflow/simulation/run_ledger.hpp"
#include "softflow/simulation/run_progress.hpp"
#include "softflow/simulation/run_records.hpp"
#include "softflow/simulation/report_tables.hpp"
#include "softflow/simulation/stop_requests.hpp"
#include "softflow/time/step_controller.hpp"

namespace softflow::simulation {

namespace {

namespace fs = std::filesystem;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// True on every rank if true on any: all ranks must take the same branch.
bool on_any_rank(bool local) {
  int l = local ? 1 : 0, any = 0;
  MPI_Allreduce(&l, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return any != 0;
}

/// A failure of the same type with a longer message.
[[noreturn]] void rethrow_with_message(const std::exception_ptr& failure,
                                       const std::string& message) {
  try {
    std::rethrow_exception(failure);
  } catch (const MeshError&) {
    throw MeshError(message);
  } catch (const SolverError&) {
    throw SolverError(message);
  } catch (const AccuracyError&) {
    throw AccuracyError(message);
  } catch (const InputError&) {
    throw InputError(message);
  } catch (const Error&) {
    throw Error(message);
  }
}

constexpr const char* kRemeshHeader =
    "step,t,reason,nodes_before,nodes_after,quality_before,quality_after,volume_change,"
    "transfer_extrapolation,seconds,interface_shape,algorithm,interface_triangles_before,"
    "interface_triangles_after,interfaces_resampled";

/// One row of remesh.csv (the header first when the file is new; a file a
/// run started before a column was added gets the current header, its rows
/// kept: the new columns are empty there).
void append_remesh_row(const fs::path& directory, const RemeshEvent& e) {
  const fs::path path = directory / "remesh.csv";
  if (fs::exists(path)) {
    std::ifstream in(path);
    std::string header, rest, line;
    std::getline(in, header);
    if (header != kRemeshHeader) {
      while (std::getline(in, line)) rest += line + "\n";
      in.close();
      io::write_text_file_atomically(path, std::string(kRemeshHeader) + "\n" + rest);
    }
  }
  const bool fresh = !fs::exists(path);
  std::ofstream out(path, std::ios::app);
  if (fresh) out << kRemeshHeader << "\n";
  out << fmt::format(
      "{},{:.10g},\"{}\",{},{},{:.6g},{:.6g},{:.3e},{:.3e},{:.4g},{:.4g},{},{},{},{}\n", e.step,
      e.time, e.reason, e.nodes_before, e.nodes_after, e.quality_before, e.quality_after,
      e.volume_change, e.extrapolation, e.seconds, e.interface_shape, e.algorithm,
      e.interface_triangles_before, e.interface_triangles_after, e.resampled);
  if (!out) throw Error(fmt::format("cannot write {}", path.string()));
}

/// The loop from the simulation's current step to time.end, shared by a
/// fresh run and a restart: steps, output, checkpoints, stop requests and
/// failures, then the summary.
nlohmann::json continue_run(const io::CaseConfig& config, const RunOptions& options,
                            const fs::path& directory, DropSimulation& sim, RunLedger ledger,
                            StepReport last, RunFiles& files, CheckpointMark checkpoint) {
  const bool root = is_root();
  const bool console = !options.quiet && root;
  const auto session_start = Clock::now();
  const nlohmann::json n_steps = planned_steps(config);
  const int first_step = sim.steps();
  leave_startup();  // from here a stop request checkpoints after the step
  const physics::WallMotion walls = wall_motion(config);
  const double earlier_wall_seconds = ledger.wall_seconds;
  StepTaker stepper(config, ledger.adaptive, options.quiet);
  SessionPace pace(config, first_step, ledger.adaptive.has_value());
  CheckpointSchedule schedule(config, options);
  double checkpoint_bytes = 0.0;

  auto write_checkpoint = [&] {
    const auto begin = Clock::now();
    RunLedger saved = ledger;
    saved.wall_seconds = earlier_wall_seconds + seconds_since(session_start);
    // Saving is collective (distributed fields gather their values), so every
    // rank saves; only rank 0 writes.
    io::Checkpoint c;
    sim.save(c);
    on_root_sharing_failure([&] {
      c.softflow_version = SOFTFLOW_VERSION;
      c.case_toml = io::to_toml(config);
      c.run_json = to_json(saved).dump();
      io::write_checkpoint(directory / kCheckpointFile, c);
      checkpoint_bytes = static_cast<double>(fs::file_size(directory / kCheckpointFile));
    });
    checkpoint = {sim.steps(), sim.time()};
    schedule.record_checkpoint(seconds_since(begin));
  };

  std::string status = "running", stop_reason;
  std::exception_ptr failure;
  RemeshTriggers triggers(config);
  bool symmetric_start_noted = false;
  try {
    while (!at_end(config, sim.steps(), sim.time())) {
      if (config.remesh.enabled()) {
        const MeshCondition now = triggers.measure(sim.mesh(), sim.time(), sim.mesh_quality());
        if (const std::string why = triggers.due(now, ledger.last_remesh_time); !why.empty()) {
          // Before the step, outside the step taker (whose retries restore a
          // state of the mesh they started on). A checkpoint follows at once:
          // a restart continues on the new mesh without meshing again.
          ledger.last_remesh_time = sim.time();
          RemeshEvent e;
          try {
            e = sim.remesh(why);
          } catch (const MeshError& remesh_failure) {
            // The run goes on with its mesh (time.min_quality still stops it
            // with its diagnosis).
            triggers.failed(now);
            if (root)
              fmt::print(stderr, "softflow: note: remeshing at step {} (t = {:.4f}) failed, the run goes on "
                         "with its mesh: {}\n", sim.steps(), sim.time(), remesh_failure.what());
            continue;
          }
          triggers.remeshed(triggers.measure(sim.mesh(), sim.time(), e.quality_after));
          // gmsh's new mesh is not the mirror case's image: from here the
          // drift across streamlines no longer vanishes with the offset.
          if (root && config.sizing.point_symmetric_start && !symmetric_start_noted) {
            symmetric_start_noted = true;
            fmt::print(stderr,
                       "softflow: note: the remesh at step {} (t = {:.4f}) gives up "
                       "mesh.point_symmetric_start: the new mesh is not the image of its mirror "
                       "case's; remesh.quality = 0 (now {:g}) keeps the symmetric mesh "
                       "(docs/confinement.md)\n",
                       e.step, e.time, config.remesh.quality);
          }
          // The modules are new objects: their report files' rows with them.
          files.reports = sim.report_files();
          write_checkpoint();
          on_root_sharing_failure([&] { append_remesh_row(directory, e); });
          if (console)
            fmt::print(
                "remesh at step {} (t = {:.4f}): {}; nodes {} -> {}, worst quality {:.3f} -> "
                "{:.3f} "
                "({}; worst interface triangle {:.3f}), {}volume change {:.1e}, {:.2f} s\n",
                e.step, e.time, e.reason, e.nodes_before, e.nodes_after, e.quality_before,
                e.quality_after, e.algorithm, e.interface_shape,
                e.resampled > 0
                    ? fmt::format("{} interface(s) resampled ({} -> {} triangles), ", e.resampled,
                                  e.interface_triangles_before, e.interface_triangles_after)
                    : std::string(),
                e.volume_change, e.seconds);
        }
      }
      last = stepper.take(sim);
      add(ledger.total, last.stages);
      ledger.stokes_iterations += last.stokes_iterations;
      ++ledger.timed_steps;
      schedule.record_step(last.step_seconds);
      const double elapsed = seconds_since(session_start);
      const double eta = pace.eta(last, elapsed);
      // Gathering a field is collective: every rank takes part, rank 0 writes.
      const bool fields_due = config.write_fields && config.time.fields_interval > 0 &&
                              last.step % config.time.fields_interval == 0;
      const auto fields = fields_due ? sim.output_fields() : std::vector<io::FieldData>{};
      on_root_sharing_failure([&] {
        files.append(last);
        if (files.fields && fields_due) files.fields->write(sim.mesh(), fields, sim.time(), last.step);
        io::write_text_file_atomically(
            directory / "progress.json",
            progress_json(last, n_steps, config, "running", earlier_wall_seconds + elapsed, eta,
                          checkpoint)
                    .dump(2) +
                "\n");
      });
      if (console) print_step(last, n_steps, eta);
      sim.check_volumes();
      if (ledger.steady) {
        ledger.steady->add(last.time, steady_sample(last, walls));
        if (ledger.steady->reached_at()) {  // set by add() at the first steady sample
          if (console) print_steady(last, *ledger.steady, config);
          break;  // the final checkpoint follows the loop
        }
      }
      if (const std::string why = sim.finish_reason(); !why.empty()) {
        stop_reason = ledger.finished = why;  // a module's end (e.g. a neutral height): completed
        if (console) fmt::print("{}\n", why);
        break;  // the final checkpoint follows the loop
      }
      if (at_end(config, sim.steps(), sim.time())) break;  // the final checkpoint follows the loop

      const int signal = stop_requested();
      const bool stop = signal != 0 || on_any_rank(schedule.limit_near());
      if (stop || schedule.due(sim.steps())) write_checkpoint();
      if (stop) {
        status = "interrupted";
        stop_reason = signal != 0 ? fmt::format("interrupted by {} at step {} (t = {:.4f})",
                                                signal_name(signal), sim.steps(), sim.time())
                                  : fmt::format(
                                        "stopped at step {} (t = {:.4f}) before the wall-time "
                                        "limit of {:g} s",
                                        sim.steps(), sim.time(), *options.wall_time_limit);
        break;
      }
    }
    if (status == "running") {
      write_checkpoint();  // lets a later, longer run continue from the end
      status = "completed";
    }
  } catch (const Error& e) {
    failure = std::current_exception();
    status = "stopped";
    stop_reason = e.what();
    stop_reason += checkpoint.step >= 0
                       ? fmt::format(
                             ". The last checkpoint (step {}, t = {:.4f}) and the output "
                             "so far are in {}",
                             checkpoint.step, checkpoint.time, directory.string())
                       : fmt::format(
                             ". The output so far is in {} (no checkpoint was written{})",
                             directory.string(), no_checkpoint_advice(config, stop_reason));
  }

  ledger.wall_seconds = earlier_wall_seconds + seconds_since(session_start);
  auto summary = make_summary(config, sim, ledger, last, status, stop_reason, checkpoint);
  summary["peak_memory_mb"] = peak_memory_summary();  // collective
  if (checkpoint_bytes > 0)  // what a checkpoint costs: the last one written in this session
    summary["checkpoint_cost"] = {{"bytes", checkpoint_bytes},
                                  {"seconds", schedule.last_checkpoint_seconds()}};
  const bool written =
      config.time.fields_interval > 0 && sim.steps() % config.time.fields_interval == 0;
  const bool final_fields = config.write_fields && sim.steps() > first_step && !written && !failure;
  const auto fields = final_fields ? sim.output_fields() : std::vector<io::FieldData>{};  // collective
  on_root_sharing_failure([&] {
    if (files.fields && final_fields) files.fields->write(sim.mesh(), fields, sim.time(), sim.steps());
    io::write_text_file_atomically(directory / "summary.json", summary.dump(2) + "\n");
    io::write_text_file_atomically(
        directory / "progress.json",
        progress_json(last, n_steps, config, status, ledger.wall_seconds, 0.0, checkpoint).dump(2) +
            "\n");
    files.close();
    draw_plot("plot_timeseries.py", directory, "deformation.png", false);
  });
  // A failure says where the output is in its own message, after which "wrote" would mislead.
  if (console && !failure) fmt::print("wrote {}\n", directory.string());
  if (failure) rethrow_with_message(failure, stop_reason);
  if (status == "interrupted")
    throw RunInterrupted(fmt::format("{}; checkpoint written: continue with `softflow restart {}`",
                                     stop_reason, directory.string()));
  return summary;
}

}  // namespace

void check_initial_mesh_quality(const io::CaseConfig& config, const mesh::Mesh& mesh) {
  const double quality = mesh::min_quality(mesh);
  if (quality >= config.time.min_quality) return;
  // Below remesh.quality the run remeshes before its first step: that mesh
  // is the one time.min_quality then judges (gmsh's graded meshes of a
  // near-wall particle start at 0.018; the remesher's at 0.21).
  if (quality < config.remesh.quality) return;
  throw MeshError(fmt::format(
      "the initial mesh has minimum element quality {:.3g} at {}, below time.min_quality = {:.3g}, "
      "so the run would stop at its first step. "
      "Mesh finer or smoother: a larger mesh.equator_nodes (now {}), a smaller mesh.far_size (now "
      "{:g}) or mesh.growth (now {:g}){}; or lower time.min_quality",
      quality, mesh::describe_element(mesh, mesh::worst_tet(mesh)), config.time.min_quality,
      config.sizing.equator_nodes, config.sizing.far_size, config.sizing.growth,
      config.sizing.optimize_high_order ? "" : ", mesh.optimize_high_order = true"));
}

nlohmann::json run_drop_case(const io::CaseConfig& config, const RunOptions& options,
                             MeshedCase meshed) {
  const fs::path directory = options.output_directory.value_or(fs::path(config.output_directory));
  if (!options.overwrite)
    on_root_sharing_failure([&] { refuse_to_replace_unfinished_run(directory); });
  check_initial_mesh_quality(config, meshed.mesh);
  // Staged, then committed at once: an older directory is replaced in one
  // step, and from then on the run writes in place, so that its progress,
  // time series and checkpoints are readable while it runs.
  std::unique_ptr<io::OutputDirectory> output;
  on_root_sharing_failure([&] { output = std::make_unique<io::OutputDirectory>(directory, true); });
  RunLedger ledger;
  ledger.mesh_report = meshed.report;
  ledger.steady = steady_monitor(config);
  ledger.adaptive = adaptive_steps(config);
  if (const auto warning = redistribution_step_warning(config)) {
    if (is_root()) fmt::print(stderr, "softflow: warning: {}\n", *warning);
    ledger.warnings.push_back(*warning);  // summary.json's warnings
  }
  leave_startup();  // the staging directory exists: a stop request now removes it cleanly
  DropSimulation sim(config, std::move(meshed.mesh));
  const StepReport first = sim.initial_report();
  if (const int signal = stop_requested())
    throw RunInterrupted(fmt::format(
        "stopped by {} during set-up, before the first step: nothing to continue from and no "
        "results written; run the case again to start it",
        signal_name(signal)));
  if (ledger.steady) ledger.steady->add(first.time, steady_sample(first, wall_motion(config)));
  if (!options.quiet && is_root())
    fmt::print("Stokes solver: {} ({})\n",
               sim.stokes().settings().method == la::SaddlePointMethod::direct ? "direct" : "iterative",
               sim.stokes().method_reason());
  if (!options.quiet && is_root() && config.time.end > 0.0)
    fmt::print("Time steps: {}\n", describe_steps(config));
  RunFiles files;
  on_root_sharing_failure([&] {
    output->write_text("case.toml", io::to_toml(config));
    for (const auto& report : sim.report_files())
      output->write_text(report.name, report.header + report.rows(first));
    output->commit();
    open_series(directory, sim, files);
    if (config.write_fields)
      files.fields =
          std::make_unique<io::FieldSeries>(directory / "fields", directory / "fields.pvd");
  });
  return continue_run(config, options, directory, sim, std::move(ledger), first, files, {});
}

nlohmann::json restart_drop_case(const io::CaseConfig& config, const fs::path& directory,
                                 const RunOptions& options) {
  const bool root = is_root();
  if (root) io::remove_stale_temporaries(directory / kCheckpointFile);
  const std::string previous = root ? run_status(directory) : std::string();
  // The caller holds the directory's io::RunLock: "running" is a run on
  // another host (or a reused pid), perhaps live.
  if (!options.overwrite)
    on_root_sharing_failure([&] {
      if (previous != "running") return;
      const auto progress = read_json_file(directory / "progress.json");
      throw io::DirectoryBusy(fmt::format(
          "{}/progress.json says the run is still running (pid {} on host '{}'): two writers "
          "would mix and lose results. If that run has really ended, continue it with "
          "`softflow restart {} --force`",
          directory.string(), progress.value("pid", 0L), progress.value("host", std::string()),
          directory.string()));
    });
  // Every rank reads the checkpoint: each holds the full replicated state.
  const io::Checkpoint checkpoint = io::read_checkpoint(directory / kCheckpointFile);
  check_same_case(config, checkpoint, directory);
  RunLedger ledger = ledger_from_json(checkpoint.run_json, config);
  const bool steady = ledger.steady && ledger.steady->reached_at();
  if (at_end(config, checkpoint.step, checkpoint.time) || steady || !ledger.finished.empty()) {
    if (!options.quiet && root)
      fmt::print("{}: the run is complete ({}step {}, t = {:.4f}); nothing to do\n",
                 directory.string(), steady ? "steady state at " : "", checkpoint.step,
                 checkpoint.time);
    std::ifstream in(directory / "summary.json");
    try {
      return in ? nlohmann::json::parse(in) : nlohmann::json::object();
    } catch (const nlohmann::json::exception&) {
      return nlohmann::json::object();
    }
  }
  ++ledger.sessions;
  DropSimulation sim(config, checkpoint.reference_mesh);
  sim.restore(checkpoint);
  leave_startup();
  if (const int signal = stop_requested())
    throw RunInterrupted(fmt::format(
        "stopped by {} during the restart's set-up: {} is as it was; `softflow restart {}` "
        "continues it",
        signal_name(signal), directory.string(), directory.string()));
  RunFiles files;
  on_root_sharing_failure([&] {
    for (const auto& report : sim.report_files()) {
      const std::string& file = report.name;
      const int steps = truncate_timeseries(directory / file, checkpoint.step, report.header);
      if (steps <= 0) continue;
      const std::string warning = fmt::format(
          "{}/{} has no rows for {} of the steps 0..{} the checkpoint covers (deleted or edited "
          "since): the run continues from the checkpoint, but those rows are lost for good",
          directory.string(), file, steps, checkpoint.step);
      fmt::print(stderr, "softflow: warning: {}\n", warning);
      ledger.warnings.push_back(warning);
    }
    open_series(directory, sim, files);
    if (config.write_fields) {
      files.fields =
          std::make_unique<io::FieldSeries>(directory / "fields", directory / "fields.pvd");
      files.fields->resume(checkpoint.step);
    }
  });
  if (!options.quiet && root)
    fmt::print("restarting {} ({}) from its checkpoint: step {}{}, t = {:.4f}\n",
               directory.string(),
               previous == "killed" ? "killed: stopped without a final checkpoint"
                                    : fmt::format("status \"{}\"", previous),
               checkpoint.step,
               ledger.adaptive ? std::string()
                               : fmt::format("/{}", planned_steps(config).get<long>()),
               checkpoint.time);
  return continue_run(config, options, directory, sim, std::move(ledger), sim.current_report(),
                      files, {checkpoint.step, checkpoint.time});
}

}  // namespace softflow::simulation
