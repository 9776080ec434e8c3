// What every softflow command shares: the exit codes, PETSc's lifetime,
// printing once under mpirun, and the checks of the user's PETSc options.
#pragma once

#include <ostream>
#include <vector>

#include "softflow/io/case_config.hpp"

namespace softflow::app {

/// The program's exit codes (README.md, main.cpp's header).
enum ExitCode {
  kOk = 0,
  kInputError = 1,
  kMeshError = 2,
  kSolverError = 3,
  kOtherError = 4,
  kInterrupted = 5,
  kAccuracyError = 6,
};

/// PETSc (and MPI) for the whole program; options after "--" go to PETSc only.
class PetscSession {
 public:
  explicit PetscSession(std::vector<char*> petsc_args);
  ~PetscSession();
  PetscSession(const PetscSession&) = delete;
  PetscSession& operator=(const PetscSession&) = delete;

 private:
  std::vector<char*> args_;
};

/// Before MPI starts (command-line errors): whether this process is the
/// launcher's rank 0, so that under mpirun a message is printed once, not
/// once per rank. Outside a launcher every process is.
bool launcher_rank_zero();

/// std::cerr on the launcher's rank 0, a sink elsewhere.
std::ostream& error_stream();
/// std::cout on the launcher's rank 0, a sink elsewhere.
std::ostream& output_stream();

/// Rank 0 of PETSC_COMM_WORLD (PETSc running).
bool is_root();

/// The case's solver.petsc_options into PETSc's options database.
void insert_case_petsc_options(const io::CaseConfig& config);

/// The Stokes solver's PETSc options (prefix stokes_, from the case's
/// petsc_options or after "--") are read once here, on a scratch solver,
/// with PETSc's own error printing off: a wrong value (e.g. an unknown
/// -stokes_ksp_type) is bad input (InputError: exit 1 with one line), not a
/// PETSc error dump at the first solve.
void check_petsc_options(const io::CaseConfig& config);

/// The options the user gave (solver.petsc_options and after "--") that
/// nothing read by the end: most likely misspelt. PETSc would run on
/// silently; say so, as its -options_left does.
void warn_unused_petsc_options(const io::CaseConfig& config,
                               const std::vector<char*>& command_line);

}  // namespace softflow::app
