#include "check_command.hpp"

#include <algorithm>
#include <exception>
#include <iostream>
#include <utility>

#include <fmt/format.h>
#include <petscsys.h>

#include "case_files.hpp"
#include "command_support.hpp"
#include "softflow/common/error.hpp"
#include "softflow/simulation/run_ledger.hpp"

namespace softflow::app {

namespace {

/// A PETSc options database of its own, the default while it lives: one
/// case's options cannot leak into the next case's check.
class ScopedOptions {
 public:
  /// With the options after "--" (`petsc` from argv[0] on). InputError if
  /// PETSc cannot take them.
  explicit ScopedOptions(const std::vector<char*>& petsc) {
    std::vector<char*> words(petsc.begin() + 1, petsc.end());
    if (PetscOptionsCreate(&options_) != 0 ||
        PetscOptionsInsertArgs(options_, static_cast<int>(words.size()), words.data()) != 0) {
      PetscOptionsDestroy(&options_);
      throw InputError("the PETSc options after \"--\": PETSc could not read them");
    }
    PetscOptionsPush(options_);
  }
  ~ScopedOptions() {
    PetscOptionsPop();
    PetscOptionsDestroy(&options_);
  }
  ScopedOptions(const ScopedOptions&) = delete;
  ScopedOptions& operator=(const ScopedOptions&) = delete;

 private:
  PetscOptions options_ = nullptr;
};

/// "FILE: valid", and the case's warnings (a valid case that will not run
/// well) on the error stream.
void report_valid(const std::string& file, const io::CaseConfig& config) {
  output_stream() << fmt::format("{}: valid\n", file);
  if (const auto warning = simulation::redistribution_step_warning(config))
    error_stream() << fmt::format("softflow: {}: warning: {}\n", file, *warning);
}

}  // namespace

int check_several(const std::vector<std::string>& files, const std::vector<char*>& petsc) {
  int code = kOk;
  auto refuse = [&](const std::string& message, int why) {
    error_stream() << "softflow: " << message << "\n";
    code = std::max(code, why);
  };
  std::vector<std::pair<std::string, io::CaseConfig>> with_petsc;
  for (const auto& file : files) {
    try {
      if (is_sweep_file(file)) {
        const auto expanded = valid_sweep(file);
        output_stream() << fmt::format("{}: valid, a sweep of {} cases\n", file,
                                       expanded.cases.size());
        continue;
      }
      auto config = read_valid_case(file);
      if (config.petsc_options.empty() && petsc.size() == 1)
        report_valid(file, config);
      else
        with_petsc.emplace_back(file, std::move(config));
    } catch (const InputError& e) {
      refuse(e.what(), kInputError);
    } catch (const std::exception& e) {
      refuse(fmt::format("{}: error: {}", file, e.what()), kOtherError);
    }
  }
  if (with_petsc.empty()) return code;
  try {
    PetscSession session({petsc.front()});
    for (const auto& [file, config] : with_petsc) {
      try {
        const ScopedOptions options(petsc);
        insert_case_petsc_options(config);
        check_petsc_options(config);
        report_valid(file, config);
      } catch (const InputError& e) {
        refuse(fmt::format("{}: {}", file, e.what()), kInputError);
      }
    }
  } catch (const std::exception& e) {
    refuse(fmt::format("error: {}", e.what()), kOtherError);
  }
  return code;
}

}  // namespace softflow::app
