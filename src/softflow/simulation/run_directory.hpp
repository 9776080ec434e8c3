// A run's output directory between sessions: the files a run keeps open, cutting the
// series back to a checkpoint, the case a checkpoint belongs to. (Who may write the
// directory, run_status and the refusal to replace, are declared in drop_run.hpp.)
#pragma once

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/io/vtu_writer.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::simulation {

/// The files a run keeps open (rank 0 only): its report files
/// (DropSimulation::report_files, timeseries.csv first) and the fields.
struct RunFiles {
  std::vector<ReportFile> reports;
  std::vector<std::ofstream> streams;  ///< one per report, for appending
  std::unique_ptr<io::FieldSeries> fields;
  /// Appends each report's rows of `report`.
  void append(const StepReport& report);
  void close();
};

/// Keeps the header and the rows of steps <= `step`; a row cut short by a
/// crash (no final newline) goes too. Rows past the checkpoint are computed
/// again. Returns how many of the steps 0..step have no row (a file deleted
/// or edited since: those rows cannot be computed again).
int truncate_timeseries(const std::filesystem::path& path, int step, const std::string& header);

/// Opens the simulation's report files for appending.
void open_series(const std::filesystem::path& directory, const DropSimulation& sim, RunFiles& files);

/// The case of `directory`/case.toml must be the one the checkpoint was
/// written with; only [checkpoint] may change between sessions. A checkpoint
/// whose case has no [conformation] was written with supg_tau = "steady", one
/// without stress_prediction with stress_prediction = "euler".
void check_same_case(const io::CaseConfig& config, const io::Checkpoint& checkpoint,
                     const std::filesystem::path& directory);

/// A JSON file, or null if it cannot be read or parsed.
nlohmann::json read_json_file(const std::filesystem::path& path);

}  // namespace softflow::simulation
