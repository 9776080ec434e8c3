// Reading the case files a command is given: a single case (keys, then
// geometry) or a sweep (every combination), with the file named in errors.
#pragma once

#include <filesystem>
#include <string>

#include "softflow/io/case_config.hpp"
#include "softflow/io/sweep_case.hpp"

namespace softflow::app {

/// Whether the file has lists of values (a parameter sweep); false for a
/// file that cannot be read, which the case reader then reports.
bool is_sweep_file(const std::filesystem::path& path);

/// The case, every key checked. A case file with lists is a sweep: says so
/// rather than "must be a number" (InputError).
io::CaseConfig read_case(const std::filesystem::path& path);

/// read_case, then its geometry (overlaps, walls); geometry errors name the
/// file as key errors do.
io::CaseConfig read_valid_case(const std::filesystem::path& path);

/// A sweep file expanded, every combination checked as `softflow sweep`
/// checks it (keys, geometry, time.end > 0: simulation::check_cases);
/// errors name the file and the combination.
io::Sweep valid_sweep(const std::string& path);

}  // namespace softflow::app
