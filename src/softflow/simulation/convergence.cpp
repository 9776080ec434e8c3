#include "softflow/simulation/convergence.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "softflow/analysis/richardson.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace {

namespace fs = std::filesystem;

/// One level's result for one object, from its summary.json.
struct LevelResult {
  int equator_nodes = 0;  ///< asked for (mesh.equator_nodes)
  /// What the mesher made (summary.json's mesh report), which is what sets
  /// the element size: gmsh rounds the equator's division (21 for 20, 41
  /// for 39), unevenly from level to level. 0 until the level has run.
  int meshed_equator_nodes = 0;
  double far_size = 0.0, growth = 0.0;
  std::string status;  ///< "" when the level has no summary
  long unknowns = 0;
  int steps = 0;
  double time = 0.0;
  std::string steady;  ///< "yes", "no", or "" (not watched)
  double wall_seconds = 0.0;
  std::vector<double> deformation, theta_deg;  ///< per object
};

LevelResult read_level(const io::SweepCase& c, const fs::path& directory) {
  LevelResult r;
  r.equator_nodes = c.config.sizing.equator_nodes;
  r.far_size = c.config.sizing.far_size;
  r.growth = c.config.sizing.growth;
  std::ifstream in(directory / c.label / "summary.json");
  if (!in) {
    // A level that failed before its run started (e.g. meshing) has only its log.
    std::error_code ec;
    const fs::path log = directory / "logs" / (c.label + ".log");
    if (fs::exists(log, ec) && fs::file_size(log, ec) > 0)
      r.status = fmt::format("failed (logs/{}.log)", c.label);
    return r;
  }
  nlohmann::json s;
  try {
    s = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return r;
  }
  r.status = s.value("status", "");
  if (s.contains("mesh") && s["mesh"].is_object())
    r.meshed_equator_nodes = s["mesh"].value("equator_nodes", 0);
  r.unknowns = s.value("unknowns", 0L);
  r.steps = s.value("steps", 0);
  r.time = s.value("time", 0.0);
  r.wall_seconds = s.value("wall_seconds", 0.0);
  if (s.contains("steady") && s["steady"].is_object())
    r.steady = s["steady"].value("reached", false) ? "yes" : "no";
  const auto number_or_nan = [](const nlohmann::json& o, const char* key) {
    return o.contains(key) && o[key].is_number() ? o[key].get<double>() : NAN;  // null: undefined
  };
  for (const auto& o : s.value("final", nlohmann::json::array())) {
    r.deformation.push_back(number_or_nan(o, "D"));
    r.theta_deg.push_back(number_or_nan(o, "theta_deg"));
  }
  return r;
}

std::string optional_number(const std::optional<double>& x, int digits = 6) {
  return x ? io::table_number(*x, digits) : std::string("—");
}

/// Two orders agree when they differ by at most 25 % of the larger.
bool orders_agree(std::optional<double> a, std::optional<double> b) {
  return a && b && std::abs(*a - *b) <= 0.25 * std::max(*a, *b);
}

/// "yes" when the two finest triples both have an order and these agree;
/// "unknown" with a single triple; else "no". With the order given
/// (--order): whether the finest triple's observed order agrees with it
/// ("unknown" with two levels, which cannot show one).
std::string asymptotic_verdict(const std::vector<analysis::RichardsonEstimate>& triples,
                               std::optional<double> given) {
  if (given) {
    if (triples.empty()) return "unknown";
    return orders_agree(triples.back().order, given) ? "yes" : "no";
  }
  if (triples.size() < 2) return "unknown";
  return orders_agree(triples[triples.size() - 2].order, triples.back().order) ? "yes" : "no";
}

}  // namespace

io::Sweep mesh_levels(const std::string& toml_text, const std::string& source_name,
                      const ConvergeOptions& options) {
  if (!io::sweep_parameters(toml_text, source_name).empty())
    throw InputError(fmt::format("{}: a case file with lists is a sweep; softflow converge takes "
                                 "one case and makes the meshes itself",
                                 source_name));
  const auto& listed = options.equator_nodes;
  if (options.order && !(*options.order >= analysis::kMinOrder && *options.order <= analysis::kMaxOrder))
    throw InputError(fmt::format("--order {:g}: the order of the error must lie in [{:g}, {:g}]", *options.order,
                                 analysis::kMinOrder, analysis::kMaxOrder));
  // An observed order needs three meshes; a known one (--order) two.
  const std::size_t fewest = options.order ? 2 : 3;
  const char* why = options.order ? "two meshes with --order" : "an order needs three meshes; two with --order";
  if (!listed.empty()) {
    if (listed.size() < fewest || listed.size() > 8)
      throw InputError(fmt::format("--equator-nodes {}: {} to 8 levels ({})", fmt::join(listed, ","), fewest, why));
    for (std::size_t k = 0; k < listed.size(); ++k)
      if (listed[k] < 8 || (k > 0 && listed[k] <= listed[k - 1]))
        throw InputError(fmt::format("--equator-nodes {}: ascending counts, each at least 8",
                                     fmt::join(listed, ",")));
  } else {
    if (options.levels < static_cast<int>(fewest) || options.levels > 8)
      throw InputError(fmt::format("--levels {}: between {} and 8 ({})", options.levels, fewest, why));
    if (!(options.factor > 1.0 && options.factor <= 2.0))
      throw InputError(fmt::format("--factor {}: the refinement ratio must lie in (1, 2]",
                                   options.factor));
  }
  const io::CaseConfig base = io::parse_case(toml_text, source_name);
  if (!(base.time.end > 0.0))
    throw InputError(fmt::format(
        "{}: time.end = {:g}: softflow converge compares the final (ideally steady) D and theta "
        "of runs in time; set time.end > 0, best with time.steady_tolerance > 0",
        source_name, base.time.end));
  io::Sweep sweep;
  sweep.name = base.name;
  sweep.directory = base.output_directory;
  io::SweepParameter parameter{"mesh.equator_nodes", "equator_nodes", {}, {}};
  const int n0 = base.sizing.equator_nodes;
  std::vector<int> counts = listed;
  if (listed.empty()) {
    for (int k = 0; k < options.levels; ++k) {
      int n = static_cast<int>(std::lround(n0 * std::pow(options.factor, k)));
      if (!counts.empty() && n <= counts.back()) n = counts.back() + 1;
      counts.push_back(n);
    }
  }
  for (std::size_t k = 0; k < counts.size(); ++k) {
    const int n = counts[k];
    io::SweepCase c;
    c.label = fmt::format("N{}", n);
    c.choice = {static_cast<int>(k)};
    c.config = base;
    const double scale = static_cast<double>(n0) / n;
    c.config.sizing.equator_nodes = n;
    c.config.sizing.far_size = base.sizing.far_size * scale;
    c.config.sizing.growth = base.sizing.growth * scale;
    if (base.sizing.interior_growth) c.config.sizing.interior_growth = *base.sizing.interior_growth * scale;
    c.config.name = fmt::format("{}_{}", base.name, c.label);
    c.config.output_directory = (fs::path(base.output_directory) / c.label).string();
    c.toml_text = io::to_toml(c.config);
    // The generated file must read back as the same case (its validation included).
    c.config = io::parse_case(c.toml_text, fmt::format("{} [level {}]", source_name, c.label));
    parameter.labels.push_back(std::to_string(n));
    parameter.numbers.push_back(n);
    sweep.cases.push_back(std::move(c));
  }
  sweep.parameters.push_back(std::move(parameter));
  return sweep;
}

int run_convergence(const fs::path& case_file, const ConvergeOptions& options,
                    const SweepOptions& sweep_options) {
  const std::string text = read_case_text(case_file);
  const io::Sweep sweep = mesh_levels(text, case_file.string(), options);
  check_cases(sweep, case_file.string(), sweep_options);
  const io::RunLock lock(sweep.directory, "converge");  // one study per directory
  if (!sweep_options.quiet && !(sweep.cases.front().config.time.steady_tolerance > 0.0))
    fmt::print("softflow converge: time.steady_tolerance = 0, so each level's values are those at "
               "time.end = {:g}: make sure the runs are steady by then\n",
               sweep.cases.front().config.time.end);
  const int code = run_cases(sweep, text, case_file.string(), sweep_options);

  const fs::path directory = sweep.directory;
  std::vector<LevelResult> levels;
  for (const auto& c : sweep.cases) levels.push_back(read_level(c, directory));
  std::size_t n_objects = 0;
  bool complete = true;
  for (const auto& l : levels) {
    complete = complete && l.status == "completed" && !l.deformation.empty() &&
               l.meshed_equator_nodes > 0;
    n_objects = std::max(n_objects, l.deformation.size());
  }

  std::string csv = "level,equator_nodes,meshed_equator_nodes,far_size,growth,status,unknowns,steps,t,steady,object,D,theta_deg,wall_seconds\n";
  std::string md = fmt::format(
      "# Mesh convergence of {}\n\n{} meshes, {} (equator nodes; far size and growth scaled "
      "with them). Written by `softflow converge`; the runs are in the subdirectories, sweep.md "
      "lists them.\n\n"
      "| level | equator nodes (asked / meshed) | far size | growth | unknowns | steps | t | steady | "
      "object | D | theta [deg] | wall [s] | status |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
      sweep.name, levels.size(),
      options.equator_nodes.empty()
          ? fmt::format("each element size refined by {:g} from one level to the next", options.factor)
          : "at the equator-node counts given (--equator-nodes), every element size scaled with them");
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const auto& l = levels[k];
    for (std::size_t o = 0; o < std::max<std::size_t>(1, l.deformation.size()); ++o) {
      const bool has = o < l.deformation.size();
      const std::string d = has ? io::table_number(l.deformation[o], 8) : "";
      const std::string t = has ? io::table_number(l.theta_deg[o], 8) : "";
      const std::string status = l.status.empty() ? "not run" : l.status;
      csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", k + 1, l.equator_nodes,
                         l.meshed_equator_nodes, io::table_number(l.far_size, 6),
                         io::table_number(l.growth, 6), status, l.unknowns, l.steps,
                         io::table_number(l.time, 6), l.steady, has ? std::to_string(o + 1) : "", d,
                         t, io::table_number(l.wall_seconds, 4));
      md += fmt::format(
          "| {} | {} / {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", k + 1,
          l.equator_nodes, l.meshed_equator_nodes, io::table_number(l.far_size, 4),
          io::table_number(l.growth, 4), l.unknowns, l.steps, io::table_number(l.time, 4), l.steady,
          has ? std::to_string(o + 1) : "", d, t, io::table_number(l.wall_seconds, 3), status);
    }
  }

  nlohmann::json extrapolation = nlohmann::json::array();
  bool distinct = true;
  for (std::size_t k = 1; k < levels.size(); ++k)
    distinct = distinct && levels[k].meshed_equator_nodes > levels[k - 1].meshed_equator_nodes;
  if (complete && !distinct)
    md += "\nNo extrapolation: two levels were meshed with the same number of equator nodes "
          "(see the table); a larger --factor separates them.\n";
  if (complete && distinct) {
    std::vector<double> h;
    for (const auto& l : levels) h.push_back(1.0 / l.meshed_equator_nodes);
    md += "\n## Richardson extrapolation (h = 1 / meshed equator nodes)\n\n"
          "Observed order p of each consecutive triple of levels (coarsest first; \"—\": the "
          "differences oscillate or grow, the levels are not in the asymptotic range), the "
          "extrapolated value from the finest three, and the error estimate of the finest level "
          "(|q_finest − q_extrapolated|; without an order, the larger of the two last "
          "differences). `asymptotic`: whether the orders of the two finest triples agree within "
          "25 % (\"yes\"), which is what makes the extrapolation trustworthy; \"unknown\" with "
          "three levels (one order only).\n\n";
    if (options.order)
      md += fmt::format(
          "With the order given (--order {:g}, known from an earlier study of the same meshes): "
          "the value is extrapolated from the finest two levels with it, q_inf = q2 + (q2 − q1) "
          "h2^p / (h1^p − h2^p); the observed orders (three or more levels) only check it, and "
          "`asymptotic` says whether the finest one agrees with it within 25 % (\"unknown\" with "
          "two levels: nothing checks the order then).\n\n",
          *options.order);
    md += "| object | quantity | orders | asymptotic | extrapolated | finest | error of finest |\n"
          "|---|---|---|---|---|---|---|\n";
    for (std::size_t o = 0; o < n_objects; ++o) {
      for (const bool is_d : {true, false}) {
        std::vector<double> q;
        for (const auto& l : levels) q.push_back(is_d ? l.deformation.at(o) : l.theta_deg.at(o));
        if (!std::all_of(q.begin(), q.end(), [](double x) { return std::isfinite(x); })) {
          md += fmt::format("| {} | {} | undefined on some level (a sphere has no angle) | | | | |\n",
                            o + 1, is_d ? "D" : "theta [deg]");
          continue;
        }
        const auto triples = h.size() >= 3 ? analysis::richardson_triples(h, q)
                                           : std::vector<analysis::RichardsonEstimate>{};
        const std::size_t n = h.size();
        const analysis::RichardsonEstimate finest =
            options.order ? analysis::richardson_with_order(h[n - 2], q[n - 2], h[n - 1], q[n - 1], *options.order)
                          : triples.back();
        std::string orders;
        nlohmann::json order_list = nlohmann::json::array();
        for (const auto& t : triples) {
          orders += (orders.empty() ? "" : ", ") + optional_number(t.order, 3);
          order_list.push_back(t.order ? nlohmann::json(*t.order) : nlohmann::json());
        }
        if (options.order) orders += fmt::format("{}given {:g}", orders.empty() ? "" : "; ", *options.order);
        const char* name = is_d ? "D" : "theta_deg";
        const std::string asymptotic = asymptotic_verdict(triples, options.order);
        md +=
            fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", o + 1, is_d ? "D" : "theta [deg]",
                        orders, asymptotic, optional_number(finest.extrapolated, 7),
                        io::table_number(q.back(), 7), io::table_number(finest.error_of_finest, 2));
        extrapolation.push_back(
            {{"object", o + 1},
             {"quantity", name},
             {"orders", order_list},
             {"order_given", options.order ? nlohmann::json(*options.order) : nlohmann::json()},
             {"asymptotic", asymptotic},
             {"extrapolated",
              finest.extrapolated ? nlohmann::json(*finest.extrapolated) : nlohmann::json()},
             {"finest", q.back()},
             {"error_of_finest", finest.error_of_finest}});
      }
    }
  } else if (!complete) {
    md += "\nNo extrapolation: not every level has completed (run `softflow converge` again to "
          "resume).\n";
  }
  std::vector<int> asked;
  for (const auto& l : levels) asked.push_back(l.equator_nodes);
  io::write_text_file_atomically(directory / "converge.csv", csv);
  io::write_text_file_atomically(directory / "converge.md", md);
  io::write_text_file_atomically(directory / "converge.json",
                                 nlohmann::json{{"factor", options.equator_nodes.empty()
                                                               ? nlohmann::json(options.factor)
                                                               : nlohmann::json()},
                                                {"equator_nodes_asked", asked},
                                                {"extrapolation", extrapolation}}
                                         .dump(2) +
                                     "\n");
  draw_plot("plot_converge.py", directory, "converge.png", sweep_options.quiet);
  if (!sweep_options.quiet) {
    fmt::print("{}", md.substr(md.find("| level")));
    fmt::print("wrote {}/converge.md, converge.csv, converge.png\n", directory.string());
  }
  return code;
}

}  // namespace softflow::simulation
