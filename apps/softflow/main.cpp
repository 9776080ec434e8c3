// softflow: drops and soft particles in shear flow (ALE finite elements, P2/P1 tetrahedra).
//
//   softflow run examples/drop_shear.toml          solve, write output/<case>/
//   softflow restart output/drop_shear             continue a run from its checkpoint
//   softflow sweep examples/sweep_ca.toml -j 2     every combination of listed parameters
//   softflow converge CASE.toml --levels 4         one case on refined meshes, extrapolated
//   softflow mesh examples/drop_shear.toml         mesh only, report sizes and quality
//   softflow mesh CASE.toml -o DIR                 ... and write it for ParaView (DIR/mesh.pvd)
//   softflow check examples/drop_shear.toml        validate the case file
//   softflow keys                                  every case-file key (docs/case_file_keys.md)
//   softflow theory --lambda 1.4 --ca 0.2          Taylor, Chaffey-Brenner, ... values
//   softflow theory --lambda 1 --ca 0.1 --slip 0.5 ... and the slip-drop D at alpha = 0.5
//   mpirun -np 2 softflow run CASE.toml            the same, on 2 MPI ranks
//   softflow run CASE.toml -- -stokes_ksp_monitor  PETSc options after "--"
//
// Exit codes (also in README.md):
//   0 success
//   1 bad input (case file, command line, an incompatible checkpoint)
//   2 meshing failed, or the moving mesh degraded (an element collapsing)
//   3 the solver failed: no convergence, or NaN/Inf in the solution
//   4 any other error (file system, ...)
//   5 interrupted on request (SIGINT, SIGTERM, SIGUSR1, --wall-time-limit)
//     after writing a checkpoint: `softflow restart DIR` continues the run
//   6 an accuracy limit was passed (time.max_volume_drift, an interface blown
//     up past an ellipsoid fit)
// A run in time that stops with 2, 3, 5 or 6 keeps its output so far, its
// last checkpoint, and a summary.json saying why.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <petscsys.h>

#include "case_files.hpp"
#include "check_command.hpp"
#include "command_support.hpp"
#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/io/sweep_case.hpp"
#include "softflow/parallel/singleton_start.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/frequency_response.hpp"
#include "softflow/simulation/migration_curves.hpp"
#include "softflow/simulation/moduli_study.hpp"
#include "softflow/simulation/report_tables.hpp"
#include "softflow/simulation/run_support.hpp"
#include "softflow/simulation/stokes_run.hpp"
#include "softflow/simulation/stop_requests.hpp"
#include "softflow/simulation/convergence.hpp"
#include "softflow/simulation/sweep.hpp"

// The commands' shared pieces (command_support, case_files, check_command).
using namespace softflow::app;

namespace {

/// "3600", "90s", "45m", "2h", "1.5h" -> seconds.
std::string parse_duration(const std::string& text, double& seconds) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return fmt::format("--wall-time-limit {}: must be a duration such as 3600, 90m or 2h", text);
  }
  const std::string unit = text.substr(used);
  const double scale = unit.empty() || unit == "s" ? 1.0 : unit == "m" ? 60.0 : unit == "h" ? 3600.0 : 0.0;
  if (scale == 0.0 || !(value > 0.0))
    return fmt::format("--wall-time-limit {}: must be a positive duration such as 3600, 90m or 2h",
                       text);
  seconds = value * scale;
  return "";
}

/// gmsh's geometry kernel, OpenCASCADE, picks its memory manager from
/// MMGT_OPT when its library loads, before main. Debian's default (the TBB
/// allocator) makes the same case mesh differently from run to run: the
/// same elements, but some node coordinates differing in the last bit
/// (issue 11 item 4: about 40 of 2,800 nodes, different ones every run;
/// such a bit can tip a later decision of the mesher and change the mesh's
/// quality). OpenCASCADE's own manager (MMGT_OPT=1) gave the same mesh in
/// every process, so softflow restarts itself once with it unless the user
/// chose a manager. (Since gmsh runs in a DeterministicHeapScope, measured
/// meshes are the same to the bit with either manager; the restart stays as
/// the configuration the regression references were made with.) Commands
/// that never mesh skip it: loading the libraries a second time doubled
/// their start-up (0.9 s against 0.4 s for `softflow check`, measured).
void use_reproducible_occ_memory_manager(int argc, char** argv) {
  if (std::getenv("MMGT_OPT") != nullptr) return;  // set: the user's choice, or done
  static const std::set<std::string> never_mesh{"check", "keys", "columns", "migration", "theory",
                                                "--help", "-h", "--version"};
  if (argc < 2 || never_mesh.count(argv[1]) > 0) return;
  if (::setenv("MMGT_OPT", "1", 1) != 0) return;
  ::execv("/proc/self/exe", argv);  // returns only on failure: go on as before
}

int report(const char* kind, const std::exception& e, int code) {
  if (is_root()) std::cerr << "softflow: " << kind << e.what() << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  softflow::parallel::start_singleton_without_daemon();
  use_reproducible_occ_memory_manager(argc, argv);
  // Split the command line at "--": ours before, PETSc's after.
  std::vector<char*> ours{argv[0]}, petsc{argv[0]};
  bool after = false;
  for (int i = 1; i < argc; ++i) {
    if (!after && std::string(argv[i]) == "--") {
      after = true;
      continue;
    }
    (after ? petsc : ours).push_back(argv[i]);
  }

  CLI::App app{
      "softflow: drops, elastic particles and emulsions in shear flow.\n"
      "Arbitrary-Lagrangian-Eulerian finite elements on curved P2/P1 tetrahedra.\n"
      "Case files are TOML; see examples/drop_shear.toml for every key with its default.\n"
      "PETSc options go after \"--\", e.g. softflow run case.toml -- -stokes_ksp_monitor"};
  app.require_subcommand(1);
  app.footer(
      "Exit codes: 0 success; 1 bad input; 2 meshing failed or the moving mesh degraded; 3 solver\n"
      "failed (no convergence, NaN/Inf); 4 other error; 5 interrupted (signal or wall-time limit)\n"
      "with a checkpoint written: `softflow restart OUTDIR` continues; 6 an accuracy limit passed\n"
      "(volume drift). A run that stops keeps its output, last checkpoint and a summary saying why.");
  app.set_version_flag("--version", SOFTFLOW_VERSION);
  std::string case_file;
  std::string output_dir;
  std::string run_dir;
  std::string wall_time_limit;
  bool quiet = false;
  bool overwrite = false;

  auto* run = app.add_subcommand("run", "mesh the case, solve it, write results to the output directory");
  run->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--output", output_dir, "output directory (overrides [output] directory)");
  run->add_flag("-q,--quiet", quiet, "print nothing but errors");
  run->add_option("--wall-time-limit", wall_time_limit,
                  "checkpoint and stop (exit code 5) before this much wall time has passed: "
                  "seconds, or e.g. 90m, 2h");
  run->add_flag("--overwrite", overwrite,
                "start afresh even where the output directory holds an interrupted run");

  auto* restart = app.add_subcommand(
      "restart",
      "continue the run in an output directory from its checkpoint (after a stop request, the "
      "wall-time limit, or a crash); the time series is continued, not rewritten");
  restart->add_option("directory", run_dir, "the run's output directory")->required()->check(CLI::ExistingDirectory);
  restart->add_flag("-q,--quiet", quiet, "print nothing but errors");
  restart->add_option("--wall-time-limit", wall_time_limit,
                      "checkpoint and stop (exit code 5) before this much wall time has passed");
  restart->add_flag("--force", overwrite,
                    "continue even though progress.json says the run is running on another host "
                    "(after that host died)");

  std::vector<double> response_frequencies;
  std::vector<double> response_log_range;
  auto* response = app.add_subcommand(
      "response",
      "the drops' linear response to small-amplitude oscillatory shear in the frequency domain: one "
      "complex Stokes solve per frequency about the resting spheres, no time stepping; their complex "
      "intrinsic viscosity and the cell's G', G'' beside Oldroyd's emulsion (response.md, .csv, .png)");
  response->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);
  response->add_option("-f,--frequency", response_frequencies,
                       "angular frequencies omega, comma-separated (default: flow.frequency)")
      ->delimiter(',');
  response->add_option("--log-range", response_log_range,
                       "FROM TO COUNT: COUNT angular frequencies evenly spaced in log between FROM and TO")
      ->expected(3);
  std::vector<double> response_cube_sides;
  response
      ->add_option(
          "--cube-sides", response_cube_sides,
          "sides of centred cubes to average the moduli over as well (cubes.csv: phi, G', G'' per "
          "side and frequency), comma-separated: which cube is the bulk (thesis Figs. 4.4-4.5)")
      ->delimiter(',');
  response->add_option("-o,--output", output_dir, "output directory (overrides [output] directory)");
  response->add_flag("-q,--quiet", quiet, "print nothing but errors");

  auto* mesh = app.add_subcommand(
      "mesh",
      "mesh the case and report nodes, elements and quality; with --output, also write the mesh "
      "for ParaView (mesh.pvd: matrix.vtu, object_k.vtu with each element's quality) to look at "
      "before a run");
  mesh->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);
  auto* mesh_output = mesh->add_option(
      "-o,--output", output_dir,
      "write the mesh into this directory (new, or one an earlier `softflow mesh` wrote)");
  mesh->add_flag("-q,--quiet", quiet, "print nothing but errors");

  std::vector<std::string> check_files;
  auto* check = app.add_subcommand(
      "check",
      "validate a case file and print the resolved case; with several files, one line each");
  check->add_option("case", check_files, "case files (TOML)")->required()->check(CLI::ExistingFile);

  auto* keys = app.add_subcommand(
      "keys", "print every case-file key: type, allowed values, default, meaning (Markdown, as in "
              "docs/case_file_keys.md)");

  int jobs = 1;
  auto* columns = app.add_subcommand(
      "columns", "every column of the report files a run writes (timeseries.csv and each "
                 "module's: stress.csv, slip.csv, migration.csv): unit and meaning, as "
                 "docs/output_columns.md");
  auto* sweep = app.add_subcommand(
      "sweep",
      "run every combination of the parameters a case file gives as lists (e.g. capillary_number "
      "= [0.05, 0.1, 0.2]), each in its own subdirectory; then one table and plot of the final "
      "values against theory. Re-running skips finished cases and resumes interrupted ones");
  sweep->add_option("case", case_file, "case file (TOML) with lists")->required()->check(CLI::ExistingFile);
  const CLI::Validator whole_jobs(
      [](const std::string& value) -> std::string {
        try {
          std::size_t used = 0;
          const long n = std::stol(value, &used);
          if (used == value.size() && n >= 1) return {};
        } catch (const std::exception&) {
        }
        return "--jobs = " + value + ": a whole number of cases at a time, at least 1";
      },
      "INT >= 1");
  sweep->add_option("-j,--jobs", jobs, "cases run at the same time (each on one core)")
      ->capture_default_str()
      ->check(whole_jobs);
  sweep->add_flag("-q,--quiet", quiet, "print nothing but errors");
  sweep->add_option("--wall-time-limit", wall_time_limit,
                    "stop before this much wall time has passed: running cases checkpoint (exit "
                    "code 5), no new one starts; run the sweep again to resume");

  auto* moduli = app.add_subcommand(
      "moduli",
      "the linear viscoelastic moduli of an emulsion in oscillatory shear: run a case whose "
      "lists give the random configurations (emulsion.seed = [1, 2, 3, 4, 5]) and frequencies or "
      "volume fractions, as a sweep (resumable), then G' and G'' per point with mean, standard "
      "deviation and Oldroyd's theory beside them (moduli.md, .csv, .png)");
  moduli->add_option("case", case_file, "case file (TOML) with lists")->required()->check(CLI::ExistingFile);
  moduli->add_option("-j,--jobs", jobs, "cases run at the same time (each on one core)")
      ->capture_default_str()
      ->check(whole_jobs);
  moduli->add_flag("-q,--quiet", quiet, "print nothing but errors");
  moduli->add_option("--wall-time-limit", wall_time_limit,
                     "stop before this much wall time has passed; run again to resume");

  softflow::simulation::ConvergeOptions converge_options;
  auto* converge = app.add_subcommand(
      "converge",
      "run one case on a sequence of meshes refined as a whole (equator nodes, far size and "
      "growth by one ratio), then the observed order and the Richardson-extrapolated D and theta "
      "with the error of the finest mesh (converge.md, .csv, .png). Best with time.steady_tolerance "
      "> 0; resumable like a sweep");
  converge->add_option("case", case_file, "case file (TOML): the coarsest level")
      ->required()
      ->check(CLI::ExistingFile);
  auto* levels_option =
      converge->add_option("--levels", converge_options.levels, "meshes (3 to 8; 2 with --order)")->capture_default_str();
  auto* factor_option =
      converge
          ->add_option("--factor", converge_options.factor,
                       "refinement ratio of the element sizes from one level to the next, in (1, 2]")
          ->capture_default_str();
  converge
      ->add_option("--equator-nodes", converge_options.equator_nodes,
                   "the levels' equator nodes instead of --levels/--factor, ascending, comma-separated "
                   "(e.g. 20,25,31,39,49,61,78 to step past a count gmsh cannot mesh); far size and "
                   "growth scale with them")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](std::string& value) {
            return value.empty() ? std::string("an empty count; give equator-node counts, e.g. "
                                               "20,25,31")
                                 : std::string();
          },
          "N,N,..."))
      ->excludes(levels_option)
      ->excludes(factor_option);
  converge->add_option("--order", converge_options.order,
                       "the order of the error, known from an earlier study of the same meshes (the main "
                       "drop's: 3): extrapolate from the finest two levels with it (two levels suffice; with "
                       "more, the observed orders check it)");
  converge->add_option("-j,--jobs", jobs, "levels run at the same time (each on one core)")
      ->capture_default_str();
  converge->add_flag("-q,--quiet", quiet, "print nothing but errors");
  converge->add_option("--wall-time-limit", wall_time_limit,
                       "stop before this much wall time has passed; run again to resume");

  std::vector<std::string> migration_runs;
  double migration_transient = 5.0;
  double migration_segment = 2.0;
  std::string migration_out = "migration";
  auto* migration = app.add_subcommand(
      "migration",
      "combine runs of one particle started at different heights into the migration master "
      "curves v_p(y_p) and Delta S(y_p), the neutral heights and the near-centre slope against "
      "eq. 3.8 (migration.md, migration_curves.csv, migration.png)");
  migration->add_option("directories", migration_runs, "run output directories (each with migration.csv)")
      ->required()
      ->check(CLI::ExistingDirectory);
  migration->add_option("--transient", migration_transient,
                        "drop each run's rows before this time: the start, where the particle "
                        "deforms from a sphere")
      ->capture_default_str();
  migration->add_option("--segment", migration_segment,
                        "the time over which each run's mean v_p (the slope of y_p) is taken for the "
                        "neutral heights")
      ->capture_default_str();
  std::optional<double> migration_from;
  migration->add_option("--trajectory-from", migration_from,
                        "also integrate the quasi-steady trajectory dy_p/dt = v_p(y_p) along the "
                        "master curve from this y_p / y_p,max, to a stable neutral height or the "
                        "end of the measured heights (migration_trajectory.csv)");
  bool migration_mirror = false;
  migration->add_flag("--mirror", migration_mirror,
                      "pair each start at +y_p0 with its mirror start at -y_p0 on a mesh of "
                      "its own, at the same times: the curves are each pair's point-symmetric mean "
                      "(q(+) - q(-)) / 2, which drops what the two meshes add in common, and "
                      "migration.md lists that part (a run without its mirror start enters alone)");
  migration->add_option("-o,--output", migration_out, "where the curves go")->capture_default_str();

  double lambda = 1.0, ca = 0.1;
  auto* theory = app.add_subcommand(
      "theory", "small-deformation theory: Taylor D (eq. 1.1), Chaffey-Brenner theta (eq. 2.59), ...");
  theory->add_option("--lambda", lambda, "viscosity ratio eta_d / eta_m")->capture_default_str();
  theory->add_option("--ca", ca, "capillary number eta_m gamma_dot R / Gamma")->capture_default_str();
  softflow::analysis::theory::TheoryQuery theory_query;
  double ca_e = 0.0;
  theory->add_option("--p", theory_query.p, "matrix elasticity p = Psi_1m Gamma / (2 R eta_m^2) (Greco)")
      ->capture_default_str();
  theory->add_option("--p-d", theory_query.p_d,
                     "drop elasticity p_d = Psi_1d Gamma / (2 R eta_d^2) (Greco)")
      ->capture_default_str();
  auto* ca_e_option = theory->add_option(
      "--ca-e", ca_e, "elastic capillary number eta_m gamma_dot / G (Roscoe; default: --ca)");
  double solid_viscosity_ratio = 0.0;
  auto* solid_viscosity_option = theory->add_option(
      "--solid-viscosity-ratio", solid_viscosity_ratio,
      "Kelvin-Voigt particle: mu_d / eta_m, its viscosity over the matrix's (adds its D and theta)");
  double slip = 0.0;
  auto* slip_option = theory->add_option(
      "--slip", slip,
      "Navier slip alpha = alpha_dim eta_m / R: the slip-drop D (thesis Fig. 2.11) at this alpha "
      "(default: at 0.1 and 1)");
  theory->add_option("--phi", theory_query.phi, "Oldroyd's emulsion: volume fraction of the drops")
      ->capture_default_str();
  theory->add_option("--omega-star", theory_query.omega_star,
                     "Oldroyd's emulsion: frequency omega eta_m R / Gamma")
      ->capture_default_str();

  const auto started = std::chrono::steady_clock::now();
  // A first word that is no subcommand: say so and list them (CLI11 would
  // only say that a subcommand is required).
  if (ours.size() > 1 && ours[1][0] != '-') {
    std::vector<std::string> names;
    for (const auto* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), ours[1]) == names.end()) {
      error_stream() << fmt::format("softflow: unknown subcommand '{}' (allowed: {}); softflow --help "
                               "describes them\n",
                               ours[1], fmt::join(names, ", "));
      return kInputError;
    }
  }
  try {
    int n = static_cast<int>(ours.size());
    app.parse(n, ours.data());
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with code 0: CLI11 prints them.
    if (e.get_exit_code() == 0)
      return app.exit(e, launcher_rank_zero() ? std::cout : error_stream(), error_stream()) == 0
                 ? kOk
                 : kInputError;
    // Like every other message: one line prefixed softflow:, then the way to help.
    error_stream() << "softflow: " << e.what() << "\n"
                   << "Run softflow --help (or softflow SUBCOMMAND --help) for the options.\n";
    return kInputError;
  }
  if ((run->count("--output") > 0 || response->count("--output") > 0) && output_dir.empty()) {
    error_stream() << "softflow: -o/--output is empty: give a directory, or leave the option out to "
                 "use [output] directory\n";
    return kInputError;
  }
  if (mesh->count("--output") > 0 && output_dir.empty()) {
    error_stream() << "softflow: mesh -o/--output is empty: give a directory, or leave the option "
                      "out to only report the mesh\n";
    return kInputError;
  }
  if (!output_dir.empty()) {
    if (const auto what = softflow::io::output_directory_problem(output_dir); !what.empty()) {
      error_stream() << fmt::format(
          "softflow: -o/--output {}: {}\n",
          output_dir.size() > 40 ? output_dir.substr(0, 37) + "..." : output_dir, what);
      return kInputError;
    }
  }
  // PETSc takes a word after "--" that is no option as the value of the
  // option before it, and skips any other without a word.
  if (petsc.size() > 1) {
    const std::vector<std::string> words(petsc.begin() + 1, petsc.end());
    if (const auto what = softflow::io::petsc_words_problem(words); !what.empty()) {
      error_stream() << fmt::format("softflow: PETSc options after \"--\": {}\n", what);
      return kInputError;
    }
  }
  softflow::simulation::RunOptions options;
  options.quiet = quiet;
  options.overwrite = overwrite;
  options.started = started;
  if (!output_dir.empty()) options.output_directory = output_dir;
  if (!wall_time_limit.empty()) {
    double seconds = 0.0;
    if (const auto error = parse_duration(wall_time_limit, seconds); !error.empty()) {
      error_stream() << "softflow: " << error << "\n";
      return kInputError;
    }
    options.wall_time_limit = seconds;
  }

  if (!response_log_range.empty()) {
    const double from = response_log_range[0], to = response_log_range[1], count = response_log_range[2];
    if (!(from > 0.0) || !(to > from) || !(count >= 2.0) || count != std::floor(count) || count > 1000.0) {
      error_stream() << fmt::format("softflow: --log-range {} {} {}: FROM > 0, TO > FROM and a whole COUNT "
                                    "from 2 to 1000 are needed\n",
                                    from, to, count);
      return kInputError;
    }
    for (int k = 0; k < static_cast<int>(count); ++k)
      response_frequencies.push_back(from * std::pow(to / from, k / (count - 1.0)));
  }

  if (*check && check_files.size() > 1) return check_several(check_files, petsc);
  if (*check) case_file = check_files.front();
  if (*check && is_sweep_file(case_file)) {  // every combination validated, none run
    try {
      const auto expanded = valid_sweep(case_file);
      std::cout << fmt::format("# a sweep of {} cases, every one valid; softflow sweep runs them in {}/\n",
                               expanded.cases.size(), expanded.directory);
      for (const auto& c : expanded.cases) std::cout << "#   " << c.label << "\n";
      std::cout << "# the first case, resolved:\n" << softflow::io::to_toml(expanded.cases.front().config);
      return kOk;
    } catch (const softflow::InputError& e) {
      error_stream() << "softflow: " << e.what() << "\n";
      return kInputError;
    }
  }

  if (*sweep || *converge || *moduli) {  // no PETSc here: each case is its own softflow process
    try {
      softflow::simulation::SweepOptions sweep_options;
      sweep_options.jobs = jobs;
      sweep_options.quiet = quiet;
      sweep_options.wall_time_limit = options.wall_time_limit;
      sweep_options.started = started;
      sweep_options.softflow = std::filesystem::read_symlink("/proc/self/exe");
      for (std::size_t i = 1; i < petsc.size(); ++i) sweep_options.petsc_args.emplace_back(petsc[i]);
      if (*converge)
        return softflow::simulation::run_convergence(case_file, converge_options, sweep_options);
      if (*moduli) return softflow::simulation::run_moduli_study(case_file, sweep_options);
      return softflow::simulation::run_sweep(case_file, sweep_options);
    } catch (const softflow::InputError& e) {
      error_stream() << "softflow: " << e.what() << "\n";
      return kInputError;
    } catch (const std::exception& e) {
      error_stream() << "softflow: error: " << e.what() << "\n";
      return kOtherError;
    }
  }

  if (*migration) {  // no PETSc: post-processing of finished runs
    try {
      std::vector<std::filesystem::path> dirs(migration_runs.begin(), migration_runs.end());
      const auto curves = softflow::simulation::assemble_migration(
          dirs, migration_transient, migration_segment,
          migration_mirror ? softflow::simulation::RunPairing::mirror
                           : softflow::simulation::RunPairing::separate);
      std::optional<softflow::simulation::QuasiSteadyTrajectory> trajectory;
      if (migration_from) trajectory = softflow::simulation::quasi_steady_trajectory(curves, *migration_from);
      softflow::simulation::write_migration(curves, migration_out, trajectory);
      if (trajectory && !quiet)
        std::cout << fmt::format("quasi-steady trajectory from y_p / y_p,max = {:g}: ends {} at t = {:.6g}\n",
                                 *migration_from, trajectory->ends_at, trajectory->duration);
      if (!quiet) std::cout << fmt::format("wrote {}/migration.md\n", migration_out);
      return kOk;
    } catch (const softflow::InputError& e) {
      error_stream() << "softflow: " << e.what() << "\n";
      return kInputError;
    } catch (const std::exception& e) {
      error_stream() << "softflow: error: " << e.what() << "\n";
      return kOtherError;
    }
  }

  if (*keys) {  // no PETSc, no case file: the declarations themselves
    std::cout << softflow::io::case_file_keys_markdown();
    return kOk;
  }
  if (*columns) {  // the report files' column declarations
    std::cout << softflow::simulation::output_columns_markdown();
    return kOk;
  }

  if (*theory) {  // no PETSc, no case file: a pure query
    try {
      if (*ca_e_option) theory_query.ca_e = ca_e;
      if (*slip_option) theory_query.slip = slip;
      if (*solid_viscosity_option) theory_query.solid_viscosity_ratio = solid_viscosity_ratio;
      std::cout << softflow::analysis::theory::theory_table(lambda, ca, theory_query);
      return kOk;
    } catch (const softflow::InputError& e) {
      error_stream() << "softflow: " << e.what() << "\n";
      return kInputError;
    }
  }

  // `check` of a case without PETSc options needs no PETSc: starting MPI
  // would take most of its time (~1 s of 1.2 s).
  if (*check && petsc.size() == 1) {
    try {
      const auto config = read_valid_case(case_file);
      if (config.petsc_options.empty()) {
        output_stream() << softflow::io::to_toml(config);
        return kOk;
      }
    } catch (const softflow::InputError& e) {
      error_stream() << "softflow: " << e.what() << "\n";
      return kInputError;
    } catch (const std::exception& e) {
      error_stream() << "softflow: error: " << e.what() << "\n";
      return kOtherError;
    }
  }

  // A stop request during meshing and set-up ends the process at once, exit 5
  // (simulation/stop_requests.hpp); the run itself takes over once it has
  // output to keep.
  const bool mesh_writes = *mesh && *mesh_output;
  if (*run || *restart || *response || mesh_writes) softflow::simulation::install_stop_handler();

  // One writer per output directory, from before meshing to the process's
  // end (io::RunLock): the launcher's rank 0 holds it. A refusal is shared
  // with every rank once MPI runs, below.
  std::optional<softflow::io::RunLock> run_lock;
  std::string lock_refusal;
  if ((*run || *restart || *response || mesh_writes) && launcher_rank_zero()) {
    try {
      std::filesystem::path directory = run_dir;
      if (mesh_writes) {
        directory = output_dir;
      } else if (*run || *response) {
        const auto config = read_valid_case(case_file);
        directory = options.output_directory.value_or(std::filesystem::path(config.output_directory));
      }
      // A request between taking the lock and naming its file to the handler
      // would leave the file behind: held back until the handler knows it.
      const softflow::simulation::StopSignalsHeld held;
      run_lock.emplace(directory, *run        ? "run"
                                  : *response ? "response"
                                  : *restart  ? "restart"
                                              : "mesh");
      softflow::simulation::install_stop_handler(run_lock->lock_file());  // removed on a stop
    } catch (const softflow::InputError&) {
      // reported below, with every rank
    } catch (const std::exception& e) {
      lock_refusal = e.what();
    }
  }

  // The mesh, before MPI starts: only then is it the same in every run
  // (simulation::mesh_before_mpi). Problems surface below, after MPI.
  if ((*run || *mesh || *response) && launcher_rank_zero() && lock_refusal.empty()) {
    try {
      softflow::simulation::mesh_before_mpi(read_valid_case(case_file));
    } catch (const std::exception&) {
    }
  }

  try {
    PetscSession petsc_session(petsc);
    // PETSc installs its own handler for SIGTERM and SIGINT: softflow's comes back.
    if (*run || *restart || *response || mesh_writes)
      softflow::simulation::install_stop_handler(run_lock ? run_lock->lock_file()
                                                          : std::filesystem::path());
    try {
      softflow::simulation::on_root_sharing_failure([&] {
        if (!lock_refusal.empty()) throw softflow::io::DirectoryBusy(lock_refusal);
      });
      if (*restart && !std::filesystem::exists(std::filesystem::path(run_dir) / "case.toml"))
        throw softflow::InputError(fmt::format(
            "{}: not the output directory of a run (it has no case.toml); give the directory a "
            "softflow run wrote",
            run_dir));
      // A restart's case is the resolved case.toml its run wrote (checked
      // against the checkpoint's own copy before anything else happens).
      const auto case_path =
          *restart ? std::filesystem::path(run_dir) / "case.toml" : std::filesystem::path(case_file);
      const auto config = read_valid_case(case_path);
      insert_case_petsc_options(config);
      check_petsc_options(config);
      if (*restart) {
        softflow::simulation::restart_drop_case(config, run_dir, options);
      } else if (*check) {
        if (is_root()) std::cout << softflow::io::to_toml(config);
      } else if (*mesh) {
        softflow::simulation::mesh_case(
            config, quiet,
            mesh_writes ? std::optional<std::filesystem::path>(output_dir) : std::nullopt);
      } else if (*run) {
        softflow::simulation::run_case(config, options);
      } else if (*response) {
        softflow::simulation::ResponseOptions response_options;
        response_options.frequencies = response_frequencies;
        response_options.cube_sides = response_cube_sides;
        response_options.output_directory = options.output_directory;
        response_options.quiet = quiet;
        softflow::simulation::run_frequency_response(config, response_options);
      }
      if (*run || *restart) warn_unused_petsc_options(config, petsc);
      return kOk;
    } catch (const softflow::RunInterrupted& e) {
      return report("", e, kInterrupted);
    } catch (const softflow::AccuracyError& e) {
      return report("accuracy limit: ", e, kAccuracyError);
    } catch (const softflow::InputError& e) {
      return report("", e, kInputError);
    } catch (const softflow::MeshError& e) {
      return report("mesh: ", e, kMeshError);
    } catch (const softflow::SolverError& e) {
      return report("solver failed: ", e, kSolverError);
    } catch (const std::exception& e) {
      return report("error: ", e, kOtherError);
    }
  } catch (const std::exception& e) {
    error_stream() << "softflow: " << e.what() << "\n";
    return kOtherError;
  }
}
