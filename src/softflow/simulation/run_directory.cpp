#include "softflow/simulation/run_directory.hpp"

#include <cerrno>
#include <exception>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <signal.h>
#include <unistd.h>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow::simulation {

namespace fs = std::filesystem;

/// Keeps the header and the rows of steps <= `step`; a row cut short by a
/// crash (no final newline) goes too. Rows past the checkpoint are computed
/// again. Returns how many of the steps 0..step have no row (a file deleted
/// or edited since: those rows cannot be computed again).
int truncate_timeseries(const fs::path& path, int step, const std::string& header) {
  std::ifstream in(path, std::ios::binary);
  std::set<int> steps_kept;
  std::ostringstream text;
  text << in.rdbuf();
  std::string all = text.str();
  if (!all.empty() && all.back() != '\n') all.erase(all.rfind('\n') + 1);
  std::istringstream lines(all);
  std::string line, kept;
  bool first_line = true;
  while (std::getline(lines, line)) {
    if (first_line) {
      kept += line + "\n";
      first_line = false;
      continue;
    }
    const auto comma = line.find(',');
    if (comma == std::string::npos) continue;
    try {
      const int row_step = std::stoi(line.substr(0, comma));
      if (row_step <= step) {
        kept += line + "\n";
        if (row_step >= 0) steps_kept.insert(row_step);
      }
    } catch (const std::exception&) {
      // not a row of ours: dropped
    }
  }
  if (kept.empty()) kept = header;
  io::write_text_file_atomically(path, kept);
  return step + 1 - static_cast<int>(steps_kept.size());
}

void open_series(const fs::path& directory, const DropSimulation& sim, RunFiles& files) {
  files.reports = sim.report_files();
  files.streams.clear();
  for (const auto& report : files.reports) {
    auto& file = files.streams.emplace_back(directory / report.name, std::ios::app);
    if (!file) throw Error(fmt::format("cannot append to {}/{}", directory.string(), report.name));
  }
}

void RunFiles::append(const StepReport& report) {
  for (std::size_t i = 0; i < reports.size(); ++i) streams[i] << reports[i].rows(report) << std::flush;
}

void RunFiles::close() {
  for (auto& stream : streams) stream.close();
}

/// The case of `directory`/case.toml must be the one the checkpoint was
/// written with; only [checkpoint] may change between sessions. A case from
/// before [conformation] was run with its steady SUPG parameter.
void check_same_case(const io::CaseConfig& config, const io::Checkpoint& checkpoint,
                     const fs::path& directory) {
  if (checkpoint.softflow_version != SOFTFLOW_VERSION)
    throw InputError(fmt::format(
        "{}: the checkpoint was written by softflow {}, this is softflow {}: continue the run "
        "with softflow {} (results of two versions would not form one run)",
        (directory / kCheckpointFile).string(), checkpoint.softflow_version, SOFTFLOW_VERSION,
        checkpoint.softflow_version));
  io::CaseConfig saved = io::parse_case(checkpoint.case_toml, "checkpoint");
  saved.checkpoint = config.checkpoint;
  // A checkpoint from before [conformation] carried its conformation with the
  // steady SUPG parameter: continuing it needs supg_tau = "steady" (the
  // mismatch below names the line), not the later default.
  if (checkpoint.case_toml.find("[conformation]") == std::string::npos)
    saved.conformation.supg_tau = io::ConformationConfig::SupgTau::steady;
  // Likewise one from before stress_prediction took the Euler prediction.
  if (checkpoint.case_toml.find("stress_prediction") == std::string::npos)
    saved.conformation.stress_prediction = physics::viscoelastic::StressPrediction::euler;
  const std::string expected = io::to_toml(saved), given = io::to_toml(config);
  if (expected == given) return;
  std::istringstream a(expected), b(given);
  std::string line_a, line_b;
  int line = 0;
  while (true) {
    ++line;
    const bool more_a = static_cast<bool>(std::getline(a, line_a));
    const bool more_b = static_cast<bool>(std::getline(b, line_b));
    if (!more_a && !more_b) break;
    if (!more_a) line_a.clear();
    if (!more_b) line_b.clear();
    if (line_a != line_b) break;
  }
  throw InputError(fmt::format(
      "{}: not the case the checkpoint was written with (resolved line {}: '{}' here, '{}' in "
      "the checkpoint). A restart continues the same case; only [checkpoint] may change. To "
      "run a changed case, start it with softflow run",
      (directory / "case.toml").string(), line, line_b, line_a));
}

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

nlohmann::json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

std::string run_status(const fs::path& directory) {
  const auto summary = read_json_file(directory / "summary.json");
  if (summary.is_object() && summary.contains("status") && summary["status"].is_string())
    return summary["status"];
  const auto progress = read_json_file(directory / "progress.json");
  if (!progress.is_object() || !progress.contains("status") || !progress["status"].is_string())
    return "";
  const std::string status = progress["status"];
  if (status != "running") return status;
  // A process killed outright (SIGKILL, the machine's OOM killer, a node
  // lost) writes nothing more: its last word is "running". Its pid tells,
  // on the host that ran it.
  if (!progress.contains("pid") || !progress["pid"].is_number_integer()) return status;
  const long pid = progress["pid"];
  if (progress.value("host", std::string()) != host_name() || pid <= 0) return status;
  if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return "killed";
  return status;
}

void refuse_to_replace_unfinished_run(const fs::path& directory) {
  std::error_code ec;
  const bool checkpoint = fs::exists(directory / kCheckpointFile, ec);
  const auto progress = read_json_file(directory / "progress.json");
  std::string status = run_status(directory);
  // The caller holds the directory's io::RunLock, so no process of this
  // host writes it; a "running" here is a run on another host (or a pid
  // reused since the run was killed): it may be live, and two writers lose
  // results (issue 33).
  if (status == "running") {
    const long pid = progress.is_object() ? progress.value("pid", 0L) : 0L;
    const std::string host = progress.is_object() ? progress.value("host", std::string()) : "";
    throw io::DirectoryBusy(fmt::format(
        "{}/progress.json says a run is still running there (pid {} on {}{}): two runs in one "
        "directory would mix and lose results. If that run has really ended (its machine "
        "rebooted, or the pid belongs to another process now), start afresh with "
        "`softflow run ... --overwrite`{}",
        directory.string(), pid, host == host_name() ? "this host" : fmt::format("host '{}'", host),
        host == host_name() ? ", a process that is not softflow" : "",
        checkpoint ? fmt::format(" or continue it with `softflow restart {}`", directory.string())
                   : std::string()));
  }
  if (status == "killed") {
    const long step = progress.is_object() ? progress.value("step", 0L) : 0L;
    throw InputError(fmt::format(
        "{} holds a run that was killed at step {} (stopped without a final checkpoint; pid {} "
        "is gone): {}, or start afresh with `softflow run ... --overwrite`",
        directory.string(), step, progress.value("pid", 0L),
        checkpoint ? fmt::format("continue it from its last checkpoint with `softflow restart {}`",
                                 directory.string())
                   : std::string("it has no checkpoint to continue from, but its results so far "
                                 "would be replaced")));
  }
  if (!checkpoint) return;
  if (status.empty()) status = "interrupted";
  if (status == "completed" || status == "stopped") return;
  throw InputError(
      fmt::format("{} holds an unfinished run (status \"{}\"), with a checkpoint: continue it "
                  "with `softflow restart {}`, or start afresh with `softflow run ... --overwrite`",
                  directory.string(), status, directory.string()));
}

}  // namespace softflow::simulation
