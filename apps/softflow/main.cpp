// softflow: drops and soft particles in shear flow (ALE finite elements, P2/P1 tetrahedra).
//
//   softflow run examples/drop_shear.toml          solve, write output/<case>/
//   softflow mesh examples/drop_shear.toml         mesh only, report sizes and quality
//   softflow check examples/drop_shear.toml        validate the case file
//   softflow theory --lambda 1.4 --ca 0.2          Taylor, Chaffey-Brenner, ... values
//   mpirun -np 2 softflow run CASE.toml            the same, on 2 MPI ranks
//   softflow run CASE.toml -- -stokes_ksp_monitor  PETSc options after "--"
//
// Exit codes: 0 success, 1 bad input (case file, command line), 2 meshing
// failed or degraded, 3 solver failed, 4 any other error.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <petscsys.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/simulation/stokes_run.hpp"

namespace {

enum ExitCode { kOk = 0, kInputError = 1, kMeshError = 2, kSolverError = 3, kOtherError = 4 };

// PETSc lifetime for the whole program; options after "--" go to PETSc only.
class PetscSession {
 public:
  explicit PetscSession(std::vector<char*> petsc_args) : args_(std::move(petsc_args)) {
    int argc = static_cast<int>(args_.size());
    char** argv = args_.data();
    if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
      throw softflow::Error("PETSc failed to initialise");
  }
  ~PetscSession() { PetscFinalize(); }
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;

 private:
  std::vector<char*> args_;
};

bool is_root() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank == 0;
}

void insert_case_petsc_options(const softflow::io::CaseConfig& config) {
  if (!config.petsc_options.empty() &&
      PetscOptionsInsertString(nullptr, config.petsc_options.c_str()) != 0)
    throw softflow::InputError(fmt::format("solver.petsc_options = \"{}\": PETSc rejected it",
                                           config.petsc_options));
}

int report(const char* kind, const std::exception& e, int code) {
  if (is_root()) std::cerr << "softflow: " << kind << e.what() << "\n";
  return code;
}

}  // namespace

int main(int argc, char** argv) {
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
  app.set_version_flag("--version", SOFTFLOW_VERSION);
  std::string case_file;
  std::string output_dir;
  bool quiet = false;

  auto* run = app.add_subcommand("run", "mesh the case, solve it, write results to the output directory");
  run->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);
  run->add_option("-o,--output", output_dir, "output directory (overrides [output] directory)");
  run->add_flag("-q,--quiet", quiet, "print nothing but errors");

  auto* mesh = app.add_subcommand("mesh", "mesh the case and report nodes, elements and quality");
  mesh->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);

  auto* check = app.add_subcommand("check", "validate a case file and print the resolved case");
  check->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);

  double lambda = 1.0, ca = 0.1;
  auto* theory = app.add_subcommand(
      "theory", "small-deformation theory: Taylor D (eq. 1.1), Chaffey-Brenner theta (eq. 2.59), ...");
  theory->add_option("--lambda", lambda, "viscosity ratio eta_d / eta_m")->capture_default_str();
  theory->add_option("--ca", ca, "capillary number eta_m gamma_dot R / Gamma")->capture_default_str();

  try {
    int n = static_cast<int>(ours.size());
    app.parse(n, ours.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kOk : kInputError;
  }

  if (*theory) {  // no PETSc, no case file: a pure query
    try {
      std::cout << softflow::analysis::theory::theory_table(lambda, ca);
      return kOk;
    } catch (const softflow::InputError& e) {
      std::cerr << "softflow: " << e.what() << "\n";
      return kInputError;
    }
  }

  try {
    PetscSession petsc_session(petsc);
    try {
      const auto config = softflow::io::read_case_file(case_file);
      insert_case_petsc_options(config);
      if (*check) {
        softflow::geometry::validate(config.shear_cell_spec());
        if (is_root()) std::cout << softflow::io::to_toml(config);
      } else if (*mesh) {
        softflow::simulation::mesh_case(config, false);
      } else if (*run) {
        softflow::simulation::RunOptions options;
        if (!output_dir.empty()) options.output_directory = output_dir;
        options.quiet = quiet;
        softflow::simulation::run_case(config, options);
      }
      return kOk;
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
    std::cerr << "softflow: " << e.what() << "\n";
    return kOtherError;
  }
}
