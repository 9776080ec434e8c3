#include "case_files.hpp"

#include <vector>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/simulation/sweep.hpp"

namespace softflow::app {

bool is_sweep_file(const std::filesystem::path& path) {
  try {
    return !io::sweep_parameters(simulation::read_case_text(path), path.string()).empty();
  } catch (const std::exception&) {
    return false;  // the case reader reports the problem
  }
}

io::CaseConfig read_case(const std::filesystem::path& path) {
  try {
    return io::read_case_file(path);
  } catch (const InputError&) {
    std::vector<io::SweepParameter> varied;
    try {
      varied = io::sweep_parameters(simulation::read_case_text(path), path.string());
    } catch (const std::exception&) {
    }
    if (varied.empty()) throw;
    std::string names;
    for (const auto& p : varied) names += (names.empty() ? "" : ", ") + p.path;
    throw InputError(fmt::format(
        "{}: {} {} a list of values, which makes the file a parameter sweep: run it with "
        "`softflow sweep {}` (or give one value for a single run)",
        path.string(), names, varied.size() == 1 ? "is" : "are", path.string()));
  }
}

io::CaseConfig read_valid_case(const std::filesystem::path& path) {
  const auto config = read_case(path);
  try {
    geometry::validate(config.shear_cell_spec());
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  return config;
}

io::Sweep valid_sweep(const std::string& path) {
  auto expanded = io::expand_sweep(simulation::read_case_text(path), path);
  simulation::check_cases(expanded, path, simulation::SweepOptions{});
  return expanded;
}

}  // namespace softflow::app
