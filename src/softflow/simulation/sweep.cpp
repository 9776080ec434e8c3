#include "softflow/simulation/sweep.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <array>
#include <map>
#include <sstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/run_support.hpp"

extern char** environ;

namespace softflow::simulation {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr int kInterrupted = 5;     // main.cpp's exit code of a run stopped on request
constexpr int kFailedEarlier = -2;  // a case skipped because it failed in an earlier sweep

// ---------------------------------------------------------------------------
// Stop requests: installed without SA_RESTART, so that waitpid returns at once.

volatile std::sig_atomic_t g_signal = 0;

void on_signal(int signal) { g_signal = signal; }

class SweepSignals {
 public:
  SweepSignals() {
    g_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = 0;
    for (std::size_t i = 0; i < kSignals.size(); ++i)
      sigaction(kSignals[i], &action, &previous_[i]);
  }
  ~SweepSignals() {
    for (std::size_t i = 0; i < kSignals.size(); ++i)
      sigaction(kSignals[i], &previous_[i], nullptr);
  }
  SweepSignals(const SweepSignals&) = delete;
  SweepSignals& operator=(const SweepSignals&) = delete;

 private:
  static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGUSR1};
  std::array<struct sigaction, 3> previous_{};
};

// ---------------------------------------------------------------------------

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nlohmann::json read_summary(const fs::path& run_directory) {
  std::ifstream in(run_directory / "summary.json");
  if (!in) return nullptr;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return nullptr;
  }
}

std::string status_of(const fs::path& run_directory) { return run_status(run_directory); }

/// Starts `args` with stdout and stderr appended to `log`.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log.c_str(),
                                   O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args.front().c_str(), &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (rc != 0) throw Error(fmt::format("cannot start {}: {}", args.front(), std::strerror(rc)));
  return pid;
}

/// The last non-empty line of a log: usually the case's error message.
std::string last_line(const fs::path& log) {
  std::istringstream lines(read_text(log));
  std::string line, last;
  while (std::getline(lines, line))
    if (!line.empty()) last = line;
  return last;
}

// ---------------------------------------------------------------------------
// The table of results.

struct Row {
  std::string label;
  std::vector<std::string> values;  // one per parameter
  std::string status;
  std::string steady;  ///< "yes" / "no" for runs that stop at steady state, else ""
  int object = 0;
  nlohmann::json numbers;  // column -> number
};

const std::vector<std::string>& numeric_columns() {
  static const std::vector<std::string> columns = {"steps",       "t",
                                                   "D",           "theta_deg",
                                                   "L",           "B",
                                                   "W",           "volume_drift",
                                                   "taylor_D",    "chaffey_brenner_theta_deg",
                                                   "steady_t",    "wall_seconds"};
  return columns;
}

std::vector<Row> collect(const io::Sweep& sweep, const fs::path& directory) {
  std::vector<Row> rows;
  for (const auto& c : sweep.cases) {
    std::vector<std::string> values;
    for (std::size_t p = 0; p < sweep.parameters.size(); ++p)
      values.push_back(sweep.parameters[p].labels[c.choice[p]]);
    const auto summary = read_summary(directory / c.label);
    if (!summary.is_object() || !summary.contains("final")) {
      std::string status = run_status(directory / c.label);
      if (status.empty()) status = fs::exists(directory / c.label) ? "running" : "not run";
      rows.push_back({c.label, values, status, "", 0, {}});
      continue;
    }
    for (const auto& o : summary["final"]) {
      Row row{c.label, values, summary.value("status", ""), "", o.value("object", 0), {}};
      if (summary.contains("steady") && summary["steady"].is_object()) {
        const auto& steady = summary["steady"];
        const bool reached = steady.value("reached", false);
        row.steady = reached ? "yes" : "no";
        if (reached && steady["time"].is_number()) row.numbers["steady_t"] = steady["time"];
      }
      row.numbers["steps"] = summary.value("steps", 0);
      row.numbers["t"] = summary.value("time", 0.0);
      row.numbers["wall_seconds"] = summary.value("wall_seconds", 0.0);
      for (const char* k : {"D", "theta_deg", "L", "B", "W", "volume_drift"})
        if (o.contains(k) && o[k].is_number()) row.numbers[k] = o[k];  // null: undefined
      for (const auto& t : summary.value("theory", nlohmann::json::array()))
        if (t.value("object", 0) == row.object) {
          row.numbers["taylor_D"] = t.value("taylor_D", 0.0);
          row.numbers["chaffey_brenner_theta_deg"] = t.value("chaffey_brenner_theta_deg", 0.0);
        }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

void write_tables(const io::Sweep& sweep, const std::vector<Row>& rows, const fs::path& directory) {
  std::string csv = "case";
  std::string md = "| case";
  for (const auto& p : sweep.parameters) {
    csv += "," + p.name;
    md += " | " + p.name;
  }
  csv += ",status,steady,object";
  md += " | status | steady | object";
  for (const auto& c : numeric_columns()) {
    csv += "," + c;
    md += " | " + c;
  }
  csv += "\n";
  md += " |\n|---|";
  for (std::size_t i = 0; i < sweep.parameters.size() + 3 + numeric_columns().size(); ++i)
    md += "---|";
  md += "\n";
  for (const auto& r : rows) {
    csv += r.label;
    md += "| " + r.label;
    for (const auto& v : r.values) {
      csv += "," + v;
      md += " | " + v;
    }
    csv += fmt::format(",{},{},{}", r.status, r.steady, r.object);
    md += fmt::format(" | {} | {} | {}", r.status, r.steady, r.object);
    for (const auto& c : numeric_columns()) {
      const std::string v = r.numbers.contains(c)
                                ? (c == "steps" ? std::to_string(r.numbers[c].get<int>())
                                                : io::table_number(r.numbers[c].get<double>(), 6))
                                : "";
      csv += "," + v;
      md += " | " + v;
    }
    csv += "\n";
    md += " |\n";
  }
  const std::string intro = fmt::format(
      "# Sweep {}\n\nFinal values of each case (the last step: run long enough for them to be "
      "steady) beside small-deformation theory: Taylor D and Chaffey-Brenner theta. With "
      "time.steady_tolerance > 0 a run stops at steady state: `steady` says whether it got there "
      "before time.end and `steady_t` when. Written by `softflow sweep`; the plot is "
      "sweep.png.\n\n",
      sweep.name);
  io::write_text_file_atomically(directory / "sweep.csv", csv);
  io::write_text_file_atomically(directory / "sweep.md", intro + md);
}

/// sweep_theory.csv, when there is a theory curve.
bool write_theory_curve(const io::Sweep& sweep, const fs::path& directory) {
  const std::string csv = theory_curve_csv(sweep);
  if (csv.empty()) return false;
  io::write_text_file_atomically(directory / "sweep_theory.csv", csv);
  return true;
}

struct Job {
  std::size_t index;
  Clock::time_point start;
};

}  // namespace

std::string theory_curve_csv(const io::Sweep& sweep) {
  if (sweep.parameters.empty()) return "";
  const auto& x = sweep.parameters.front();
  const bool ca = x.path == "objects[1].capillary_number";
  const bool lambda = x.path == "objects[1].viscosity_ratio";
  if (!ca && !lambda) return "";
  double lo = 0.0, hi = 0.0;
  for (double v : x.numbers) hi = std::max(hi, v);
  if (!(hi > 0)) return "";
  if (lambda) {
    lo = *std::min_element(x.numbers.begin(), x.numbers.end());
    lo = std::max(lo / 2, 1e-3);
  }
  hi *= 1.1;
  std::string csv = "group," + x.name + ",taylor_D,chaffey_brenner_theta_deg\n";
  std::map<std::string, bool> done;
  for (const auto& c : sweep.cases) {
    std::string group;
    for (std::size_t p = 1; p < sweep.parameters.size(); ++p)
      group += (group.empty() ? "" : " ") + sweep.parameters[p].name + "=" +
               sweep.parameters[p].labels[c.choice[p]];
    if (done[group] || c.config.objects.empty()) continue;
    done[group] = true;
    const auto& o = c.config.objects.front();
    // An object may give interfacial_tension instead of capillary_number: its
    // Ca then follows from Gamma and the case's shear rate.
    const double fixed_ca = io::capillary_number(c.config, o);
    if (!ca && !std::isfinite(fixed_ca)) continue;  // no tension, no theory
    constexpr int kPoints = 60;
    for (int i = 0; i <= kPoints; ++i) {
      const double v = ca ? hi * i / kPoints : lo * std::pow(hi / lo, double(i) / kPoints);
      const double l = lambda ? v : o.viscosity_ratio;
      const double k = ca ? v : fixed_ca;
      csv += fmt::format("{},{:.8g},{:.8g},{:.8g}\n", group, v,
                         // Taylor's D, generalised to the drop's slip (o.slip = 0: Taylor's).
                         analysis::theory::slip_taylor_deformation(l, k, o.slip),
                         analysis::theory::chaffey_brenner_angle_deg(l, k));
    }
  }
  return csv;
}

std::string read_case_text(const fs::path& case_file) {
  std::error_code ec;
  if (fs::is_directory(case_file, ec))
    throw InputError(fmt::format("{}: is a directory, not a case file", case_file.string()));
  std::string text = read_text(case_file);
  if (text.empty() && !fs::exists(case_file, ec))
    throw InputError(
        fmt::format("{}: cannot open the case file (does it exist?)", case_file.string()));
  return text;
}

int run_sweep(const fs::path& case_file, const SweepOptions& options) {
  const std::string text = read_case_text(case_file);
  const io::Sweep sweep = io::expand_sweep(text, case_file.string());
  if (sweep.parameters.empty())
    throw InputError(fmt::format(
        "{}: no parameter is a list, so there is nothing to sweep: give one or more as lists, "
        "e.g. capillary_number = [0.05, 0.1, 0.2] under [[objects]]; one case runs with softflow "
        "run",
        case_file.string()));
  check_cases(sweep, case_file.string(), options);
  const io::RunLock lock(sweep.directory, "sweep");  // one sweep per directory
  return run_cases(sweep, text, case_file.string(), options);
}

void check_cases(const io::Sweep& sweep, const std::string& source, const SweepOptions& options) {
  for (const auto& c : sweep.cases) {
    try {
      geometry::validate(c.config.shear_cell_spec());  // overlaps, walls: before any case runs
    } catch (const InputError& e) {
      throw InputError(fmt::format("{} [sweep case {}]: {}", source, c.label, e.what()));
    }
  }
  for (const auto& c : sweep.cases)
    if (!(c.config.time.end > 0))
      throw InputError(
          fmt::format("{} [sweep case {}]: time.end = {}: a sweep tabulates runs in "
                      "time, so time.end must be > 0",
                      source, c.label, c.config.time.end));
  if (options.jobs < 1)
    throw InputError(fmt::format("--jobs {}: must be at least 1", options.jobs));
}

int run_cases(const io::Sweep& sweep, const std::string& text, const std::string& source,
              const SweepOptions& options) {
  check_cases(sweep, source, options);
  std::error_code ec;
  const fs::path directory = sweep.directory;
  for (const auto& d : {directory, directory / "cases", directory / "logs"}) {
    fs::create_directories(d, ec);
    if (ec) throw Error(fmt::format("cannot create {}: {}", d.string(), ec.message()));
  }
  io::write_text_file_atomically(directory / "sweep.toml", text);
  nlohmann::json record = {{"name", sweep.name},
                           {"parameters", nlohmann::json::array()},
                           {"cases", nlohmann::json::array()}};
  for (const auto& p : sweep.parameters)
    record["parameters"].push_back({{"path", p.path}, {"name", p.name}, {"values", p.labels}});
  for (const auto& c : sweep.cases) record["cases"].push_back(c.label);
  io::write_text_file_atomically(directory / "sweep.json", record.dump(2) + "\n");

  const std::size_t n = sweep.cases.size();
  if (!options.quiet)
    fmt::print(
        "sweep {}: {} cases of {}, {} at a time, in {}\n", sweep.name, n,
        [&] {
          std::string s;
          for (const auto& p : sweep.parameters)
            s += (s.empty() ? "" : " x ") + fmt::format("{} ({})", p.path, p.labels.size());
          return s;
        }(),
        options.jobs, directory.string());

  SweepSignals signals;
  std::map<pid_t, Job> running;
  std::vector<int> exit_codes(n, -1);
  std::size_t next = 0;
  int stop_signal = 0;
  bool out_of_time = false;
  auto say = [&](std::size_t i, const std::string& what) {
    if (!options.quiet) fmt::print("[{}/{}] {}: {}\n", i + 1, n, sweep.cases[i].label, what);
    std::fflush(stdout);
  };
  while (true) {
    while (stop_signal == 0 && !out_of_time &&
           running.size() < static_cast<std::size_t>(options.jobs) && next < n) {
      const double left =
          options.wall_time_limit
              ? *options.wall_time_limit -
                    std::chrono::duration<double>(Clock::now() - options.started).count()
              : 0.0;
      if (options.wall_time_limit && left < kMinimumCaseSeconds) {
        out_of_time = true;
        if (!options.quiet)
          fmt::print("sweep: {:.0f} s left of the wall-time limit: no further case starts\n", left);
        break;
      }
      const std::size_t i = next++;
      const auto& c = sweep.cases[i];
      const fs::path case_path = directory / "cases" / (c.label + ".toml");
      const fs::path out = directory / c.label;
      const fs::path log = directory / "logs" / (c.label + ".log");
      const bool same_case = read_text(case_path) == c.toml_text;
      const std::string status = same_case ? status_of(out) : "";
      if (status == "completed" || status == "stopped") {
        exit_codes[i] = status == "completed" ? 0 : kFailedEarlier;
        say(i, status == "completed" ? "completed earlier, skipped"
                                     : "failed earlier, skipped (delete its directory to retry)");
        continue;
      }
      std::vector<std::string> args{options.softflow.string()};
      std::string action;
      if (same_case && fs::exists(out / "checkpoint.h5", ec)) {
        args.insert(args.end(), {"restart", out.string(), "-q"});
        action = "restarted from its checkpoint";
      } else {
        io::write_text_file_atomically(case_path, c.toml_text);
        args.insert(args.end(),
                    {"run", case_path.string(), "-o", out.string(), "-q", "--overwrite"});
        action = "started";
      }
      // The case's own limit: the time left, less a second for it to start.
      if (options.wall_time_limit)
        args.insert(args.end(), {"--wall-time-limit", fmt::format("{:.1f}", left - 1.0)});
      if (!options.petsc_args.empty()) {
        args.push_back("--");
        args.insert(args.end(), options.petsc_args.begin(), options.petsc_args.end());
      }
      const pid_t pid = spawn(args, log);
      running[pid] = {i, Clock::now()};
      say(i, action);
    }
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno != EINTR) throw Error(fmt::format("waitpid: {}", std::strerror(errno)));
      if (g_signal != 0 && stop_signal == 0) {
        stop_signal = g_signal;
        if (!options.quiet)
          fmt::print("sweep: stop requested; waiting for {} running case(s) to checkpoint\n",
                     running.size());
        // A terminal's Ctrl-C reaches every process of the group already; a
        // second signal would kill a case before its checkpoint.
        if (stop_signal != SIGINT)
          for (const auto& [child, job] : running) ::kill(child, stop_signal);
      }
      continue;
    }
    const auto job = running.at(pid);
    running.erase(pid);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    exit_codes[job.index] = code;
    const double seconds = std::chrono::duration<double>(Clock::now() - job.start).count();
    const fs::path log = directory / "logs" / (sweep.cases[job.index].label + ".log");
    if (code == 0)
      say(job.index, fmt::format("completed in {:.1f} s", seconds));
    else if (code == kInterrupted)
      say(job.index, "interrupted (run the sweep again to resume it)");
    else
      say(job.index, fmt::format("failed (exit code {}): {}", code, last_line(log)));
  }

  const auto rows = collect(sweep, directory);
  write_tables(sweep, rows, directory);
  write_theory_curve(sweep, directory);
  draw_plot("plot_sweep.py", directory, "sweep.png", options.quiet);
  if (!options.quiet) fmt::print("wrote {}/sweep.md, sweep.csv, sweep.png\n", directory.string());

  return sweep_exit_code(exit_codes);
}

int sweep_exit_code(const std::vector<int>& exit_codes) {
  for (int code : exit_codes) {
    if (code > 0 && code != kInterrupted) return code;
    if (code == kFailedEarlier) return 4;  // its own code is in its log
  }
  // A stop request that came after the last case had started changes
  // nothing if every case then completed: the sweep is complete.
  const bool unfinished = std::any_of(exit_codes.begin(), exit_codes.end(),
                                      [](int c) { return c == kInterrupted || c == -1; });
  return unfinished ? kInterrupted : 0;
}

}  // namespace softflow::simulation
