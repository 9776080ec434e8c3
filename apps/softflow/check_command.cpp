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

namespace softflow::app {

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
        std::cout << fmt::format("{}: valid, a sweep of {} cases\n", file, expanded.cases.size());
        continue;
      }
      auto config = read_valid_case(file);
      if (config.petsc_options.empty() && petsc.size() == 1)
        std::cout << fmt::format("{}: valid\n", file);
      else
        with_petsc.emplace_back(file, std::move(config));
    } catch (const InputError& e) {
      refuse(e.what(), kInputError);
    } catch (const std::exception& e) {
      refuse(fmt::format("{}: error: {}", file, e.what()), kOtherError);
    }
  }
  if (with_petsc.empty()) return code;
  std::string command_line;  // the options after "--", given to every case
  for (std::size_t i = 1; i < petsc.size(); ++i) command_line += std::string(" ") + petsc[i];
  PetscSession session({petsc.front()});
  for (const auto& [file, config] : with_petsc) {
    PetscOptions options = nullptr;
    PetscOptionsCreate(&options);
    PetscOptionsInsertString(options, command_line.c_str());
    PetscOptionsPush(options);
    try {
      insert_case_petsc_options(config);
      check_petsc_options(config);
      std::cout << fmt::format("{}: valid\n", file);
    } catch (const InputError& e) {
      refuse(fmt::format("{}: {}", file, e.what()), kInputError);
    }
    PetscOptionsPop();
    PetscOptionsDestroy(&options);
  }
  return code;
}

}  // namespace softflow::app
