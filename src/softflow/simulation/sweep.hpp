// `softflow sweep`: every combination of a case file's listed parameters, N runs at a time, one
// table.
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "softflow/io/sweep_case.hpp"

namespace softflow::simulation {

struct SweepOptions {
  int jobs = 1;                    ///< cases run at the same time (each a serial softflow process)
  bool quiet = false;              ///< no line per case; errors only
  std::filesystem::path softflow;  ///< the executable that runs each case
  std::vector<std::string> petsc_args;  ///< passed to every case after "--"
  /// Stop before this many seconds after `started`: each case gets the time
  /// left as its own --wall-time-limit, and no case starts with less than
  /// kMinimumCaseSeconds left.
  std::optional<double> wall_time_limit;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
};

/// A case is not started with less wall time left than this (seconds): it
/// would spend it meshing and factoring, and stop before its first step.
inline constexpr double kMinimumCaseSeconds = 10.0;

/// Runs a sweep (io::expand_sweep) in its output directory D:
///   D/cases/<label>.toml   the generated case files
///   D/<label>/             each case's run (run_drop_case's files)
///   D/logs/<label>.log     each case's messages
///   D/sweep.csv, sweep.md  one row per case and object: the varied values,
///                          status, steps, t and the final D, theta, L, B, W,
///                          volume drift beside Taylor D and Chaffey-Brenner theta
///   D/sweep_theory.csv     Taylor / Chaffey-Brenner along the first parameter
///                          when it is a capillary number or viscosity ratio
///   D/sweep.json           parameters and cases; D/sweep.png the plot
/// Each case is its own process (`softflow run` or `softflow restart`), so
/// that one failing case never takes the others down. Re-running the sweep
/// skips completed cases (and ones that failed: their failure would repeat),
/// restarts interrupted ones from their checkpoints, and starts afresh any
/// whose generated case file changed. The wall-time limit, SIGINT, SIGTERM or SIGUSR1 stop
/// launching cases; running ones checkpoint and stop (SIGTERM and SIGUSR1
/// are passed on to them; a terminal's Ctrl-C reaches them directly).
/// Returns the exit code: 0 every case completed, 5 interrupted (run the
/// sweep again to resume), else the exit code of the first failed case (4
/// for one that failed in an earlier sweep).
int run_sweep(const std::filesystem::path& case_file, const SweepOptions& options);

/// The text of the case file a sweep or convergence study starts from;
/// InputError for a directory or a file that cannot be opened.
std::string read_case_text(const std::filesystem::path& case_file);

/// InputError if a case of `sweep` cannot run (geometry, time.end = 0) or
/// the options are out of range: before anything is written.
void check_cases(const io::Sweep& sweep, const std::string& source, const SweepOptions& options);

/// run_sweep for cases already made (e.g. the mesh levels of `softflow
/// converge`): `text` is the file they came from (saved as D/sweep.toml),
/// `source` its name in messages. The caller holds the directory's
/// io::RunLock.
int run_cases(const io::Sweep& sweep, const std::string& text, const std::string& source,
              const SweepOptions& options);

/// A sweep's exit code from its cases' (in case order): the first failed
/// case's code (4 for one skipped because it failed earlier: its code is in
/// its log), else 5 if a case was interrupted or never started (-1), else 0
/// (a stop request after the last case started, all completed: 0).
int sweep_exit_code(const std::vector<int>& exit_codes);

/// sweep_theory.csv: Taylor D and Chaffey-Brenner theta along the first
/// parameter when it is object 1's capillary number or viscosity ratio, one
/// curve per combination of the other parameters (columns group, the
/// parameter, taylor_D, chaffey_brenner_theta_deg); the other quantity is
/// each case's own (io::capillary_number: also when it gives
/// interfacial_tension). Empty when there is no such curve.
std::string theory_curve_csv(const io::Sweep& sweep);

}  // namespace softflow::simulation
