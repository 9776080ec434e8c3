#include "command_support.hpp"

#include <cctype>
#include <iostream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <petscksp.h>
#include <petscsys.h>

#include "softflow/common/error.hpp"
#include "softflow/parallel/singleton_start.hpp"

namespace softflow::app {

PetscSession::PetscSession(std::vector<char*> petsc_args) : args_(std::move(petsc_args)) {
  int argc = static_cast<int>(args_.size());
  args_.push_back(nullptr);  // argv[argc] == NULL, as MPI_Init walks argv to it
  char** argv = args_.data();
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
    throw Error("PETSc failed to initialise");
}

PetscSession::~PetscSession() { PetscFinalize(); }

bool launcher_rank_zero() { return parallel::launcher_rank().value_or(0) == 0; }

namespace {

/// Where nothing is printed: the ranks other than the launcher's 0.
std::ostream& sink() {
  static std::ostream nowhere(nullptr);
  return nowhere;
}

}  // namespace

std::ostream& error_stream() { return launcher_rank_zero() ? std::cerr : sink(); }

std::ostream& output_stream() { return launcher_rank_zero() ? std::cout : sink(); }

bool is_root() {
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  return rank == 0;
}

void insert_case_petsc_options(const io::CaseConfig& config) {
  if (!config.petsc_options.empty() &&
      PetscOptionsInsertString(nullptr, config.petsc_options.c_str()) != 0)
    throw InputError(
        fmt::format("solver.petsc_options = \"{}\": PETSc rejected it", config.petsc_options));
}

void check_petsc_options(const io::CaseConfig& config) {
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  KSP ksp = nullptr;
  PetscErrorCode code = KSPCreate(PETSC_COMM_WORLD, &ksp);
  if (!code) code = KSPSetOptionsPrefix(ksp, "stokes_");
  if (!code) code = KSPSetFromOptions(ksp);
  if (ksp) KSPDestroy(&ksp);
  PetscPopErrorHandler();
  if (!code) return;
  const char* text = nullptr;
  char* specific = nullptr;
  PetscErrorMessage(code, &text, &specific);
  throw InputError(fmt::format(
      "PETSc options{}: PETSc rejected them: {}",
      config.petsc_options.empty()
          ? " after \"--\""
          : fmt::format(" (solver.petsc_options = \"{}\" or after \"--\")", config.petsc_options),
      specific && *specific ? specific : (text ? text : "unknown error")));
}

void warn_unused_petsc_options(const io::CaseConfig& config,
                               const std::vector<char*>& command_line) {
  std::vector<std::string> names;
  auto collect = [&](const std::string& token) {
    if (token.size() > 1 && token[0] == '-' && std::isalpha(static_cast<unsigned char>(token[1])))
      names.push_back(token);
  };
  std::istringstream words(config.petsc_options);
  for (std::string w; words >> w;) collect(w);
  for (std::size_t i = 1; i < command_line.size(); ++i) collect(command_line[i]);
  std::vector<std::string> unused;
  for (const auto& name : names) {
    PetscBool used = PETSC_TRUE;
    PetscOptionsUsed(nullptr, name.c_str() + 1, &used);  // stored without the "-"
    if (!used) unused.push_back(name);
  }
  if (!unused.empty() && is_root())
    std::cerr << fmt::format("softflow: warning: PETSc never read these options (misspelt?): {}\n",
                             fmt::join(unused, " "));
}

}  // namespace softflow::app
