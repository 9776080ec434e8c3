#include "softflow/simulation/moduli_study.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "softflow/analysis/theory/oldroyd_emulsion.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/io/run_lock.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace fs = std::filesystem;

namespace {

constexpr const char* kSeedPath = "emulsion.seed";

/// A case that cannot give moduli is refused naming the key.
void check_moduli_case(const io::SweepCase& c, const std::string& source) {
  const io::CaseConfig& config = c.config;
  const auto refuse = [&](const std::string& why) {
    throw InputError(fmt::format("{} [case {}]: {}", source, c.label.empty() ? config.name : c.label, why));
  };
  if (config.flow.type != io::FlowType::oscillatory)
    refuse("flow.type must be \"oscillatory\": the moduli are fitted to oscillatory shear");
  if (!(config.bulk_stress.box_side > 0.0))
    refuse("bulk_stress.box_side = 0: the moduli are fitted to the bulk stress over a centred cube; "
           "give its side (> 0)");
  if (config.objects.empty()) refuse("no [[objects]]: an emulsion needs drops");
  const io::ObjectConfig& drop = config.objects.front();
  if (drop.model != physics::viscoelastic::ConstitutiveModel::newtonian || !(drop.interfacial_tension > 0.0))
    refuse("objects[1] must be a Newtonian drop with interfacial tension (Oldroyd's emulsion)");
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / static_cast<double>(v.size());
}

double sample_std(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double s = 0.0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size() - 1));
}

/// Eq. 4.3, the linearity check: with flow.strain_amplitude among the varied
/// parameters, each point's moduli against those of the smallest amplitude
/// with the same other values (the response is linear when they agree).
std::string linearity_section(const io::Sweep& sweep, const std::vector<ModuliPoint>& points) {
  int strain = -1, column = 0;
  for (const auto& p : sweep.parameters) {
    if (p.path == kSeedPath) continue;
    if (p.path == "flow.strain_amplitude") strain = column;
    ++column;
  }
  if (strain < 0) return {};
  const auto others = [strain](const ModuliPoint& p) {
    auto l = p.labels;
    l.erase(l.begin() + strain);
    return l;
  };
  std::string md =
      "\n## Linearity (eq. 4.3)\n\nEach strain amplitude's moduli against those of the smallest "
      "with the same other parameters: a linear response has the same G' and G''.\n\n"
      "| point | strain amplitude | G' change | G'' change |\n|---|---|---|---|\n";
  for (const auto& p : points) {
    const ModuliPoint* base = nullptr;
    for (const auto& q : points)
      if (others(q) == others(p) && q.fitted > 0 &&
          (base == nullptr || std::stod(q.labels[strain]) < std::stod(base->labels[strain])))
        base = &q;
    if (base == nullptr || base == &p || p.fitted == 0) continue;
    const auto rest = others(p);
    md += fmt::format("| {} | {} vs {} | {:+.3g} % | {:+.3g} % |\n",
                      rest.empty() ? std::string("-") : fmt::format("{}", fmt::join(rest, ", ")),
                      p.labels[strain], base->labels[strain],
                      100.0 * (p.storage_mean / base->storage_mean - 1.0),
                      100.0 * (p.loss_mean / base->loss_mean - 1.0));
  }
  return md;
}

}  // namespace

std::vector<ModuliPoint> collect_moduli(const io::Sweep& sweep, const fs::path& directory) {
  int seed = -1;
  for (std::size_t p = 0; p < sweep.parameters.size(); ++p)
    if (sweep.parameters[p].path == kSeedPath) seed = static_cast<int>(p);
  std::map<std::vector<int>, std::size_t> index;  // the other parameters' choice -> point
  std::vector<ModuliPoint> points;
  std::vector<const io::SweepCase*> first_case;  // per point: its drops' lambda and slip
  std::vector<std::vector<double>> storage, loss, phi;
  for (const auto& c : sweep.cases) {
    std::vector<int> key;
    std::vector<std::string> labels;
    for (std::size_t p = 0; p < sweep.parameters.size(); ++p) {
      if (static_cast<int>(p) == seed) continue;
      key.push_back(c.choice[p]);
      labels.push_back(sweep.parameters[p].labels[c.choice[p]]);
    }
    auto [it, added] = index.try_emplace(key, points.size());
    if (added) {
      ModuliPoint point;
      point.labels = labels;
      const io::ObjectConfig& drop = c.config.objects.front();
      point.omega_star = c.config.flow.frequency * c.config.matrix_viscosity * io::mean_radius(drop.geometry) /
                         drop.interfacial_tension;
      points.push_back(point);
      first_case.push_back(&c);
      storage.emplace_back();
      loss.emplace_back();
      phi.emplace_back();
    }
    ModuliPoint& point = points[it->second];
    point.cases.push_back(c.label);
    std::ifstream in(directory / c.label / "summary.json");
    if (!in) continue;
    nlohmann::json s;
    try {
      s = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception&) {
      continue;
    }
    if (s.value("status", "") != "completed" || !s.contains("moduli")) continue;
    const auto& m = s["moduli"];
    if (!m.contains("G_storage_R_over_Gamma")) continue;
    storage[it->second].push_back(m["G_storage_R_over_Gamma"].get<double>());
    loss[it->second].push_back(m["G_loss_over_eta_m_omega"].get<double>());
    phi[it->second].push_back(m["volume_fraction"].get<double>());
    point.worst_residual = std::max(point.worst_residual, m.value("fit_residual_stress", 0.0));
  }
  for (std::size_t k = 0; k < points.size(); ++k) {
    ModuliPoint& point = points[k];
    point.fitted = static_cast<int>(storage[k].size());
    point.phi = mean(phi[k]);
    point.storage_mean = mean(storage[k]);
    point.storage_std = sample_std(storage[k]);
    point.loss_mean = mean(loss[k]);
    point.loss_std = sample_std(loss[k]);
    if (point.fitted == 0) {
      point.oldroyd_storage = point.oldroyd_loss = NAN;
      continue;
    }
    const io::ObjectConfig& drop = first_case[k]->config.objects.front();
    const auto theory = analysis::theory::oldroyd_moduli(drop.viscosity_ratio, point.phi, point.omega_star, drop.slip);
    point.oldroyd_storage = theory.storage;
    point.oldroyd_loss = theory.loss;
  }
  return points;
}

int run_moduli_study(const fs::path& case_file, const SweepOptions& options) {
  const std::string text = read_case_text(case_file);
  io::Sweep sweep = io::expand_sweep(text, case_file.string());
  if (sweep.parameters.empty())
    throw InputError(fmt::format(
        "{}: no parameter is a list: a moduli study averages over random configurations, e.g. "
        "seed = [1, 2, 3, 4, 5] under [emulsion] (and frequency = [...] under [flow] for a "
        "frequency sweep); one configuration runs with softflow run (summary.json's moduli)",
        case_file.string()));
  for (const auto& c : sweep.cases) check_moduli_case(c, case_file.string());
  check_cases(sweep, case_file.string(), options);
  const io::RunLock lock(sweep.directory, "moduli");
  const int code = run_cases(sweep, text, case_file.string(), options);

  const fs::path directory = sweep.directory;
  const auto points = collect_moduli(sweep, directory);
  std::vector<std::string> names;
  for (const auto& p : sweep.parameters)
    if (p.path != kSeedPath) names.push_back(p.name);
  std::string csv;
  for (const auto& n : names) csv += n + ",";
  csv += "omega_star,configurations,fitted,phi,G_storage_R_over_Gamma,G_storage_std,"
         "G_loss_over_eta_m_omega,G_loss_std,oldroyd_G_storage,oldroyd_G_loss,worst_fit_residual\n";
  std::string md = fmt::format(
      "# Moduli of {}\n\n"
      "Each point: the mean and sample standard deviation over its configurations (the cases "
      "that differ only in emulsion.seed) of G' R / Gamma and G'' / (eta_m omega), fitted to the "
      "last bulk_stress.fit_periods periods of <sigma_xy> and <2 D_xy> over the centred cube "
      "(thesis eqs. 4.6-4.7); phi the mean volume fraction in the cube; Oldroyd's emulsion "
      "(appendices A-B) at that phi beside them. Runs: sweep.md.\n\n",
      sweep.name);
  md += "| ";
  for (const auto& n : names) md += n + " | ";
  md += "omega* | fitted | phi | G' R/Gamma | Oldroyd | G''/(eta_m omega) | Oldroyd | worst residual |\n|";
  for (std::size_t k = 0; k < names.size() + 8; ++k) md += "---|";
  md += "\n";
  for (const auto& p : points) {
    for (const auto& l : p.labels) csv += l + ",";
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", io::table_number(p.omega_star, 8),
                       p.cases.size(), p.fitted, io::table_number(p.phi, 8),
                       io::table_number(p.storage_mean, 8), io::table_number(p.storage_std, 8),
                       io::table_number(p.loss_mean, 8), io::table_number(p.loss_std, 8),
                       io::table_number(p.oldroyd_storage, 8), io::table_number(p.oldroyd_loss, 8),
                       io::table_number(p.worst_residual, 3));
    md += "| ";
    for (const auto& l : p.labels) md += l + " | ";
    const auto with_std = [&](double m, double s) {
      return p.fitted > 1 ? fmt::format("{} ± {}", io::table_number(m, 5), io::table_number(s, 2))
                          : io::table_number(m, 5);
    };
    md += fmt::format("{} | {}/{} | {} | {} | {} | {} | {} | {} |\n",
                      io::table_number(p.omega_star, 5), p.fitted, p.cases.size(),
                      io::table_number(p.phi, 4), with_std(p.storage_mean, p.storage_std),
                      io::table_number(p.oldroyd_storage, 5), with_std(p.loss_mean, p.loss_std),
                      io::table_number(p.oldroyd_loss, 5), io::table_number(p.worst_residual, 2));
  }
  md += linearity_section(sweep, points);
  if (code != 0)
    md += "\nNot every case completed (exit code " + std::to_string(code) +
          "): run `softflow moduli` again to resume; the means are over the completed ones.\n";
  io::write_text_file_atomically(directory / "moduli.csv", csv);
  io::write_text_file_atomically(directory / "moduli.md", md);
  draw_plot("plot_moduli.py", directory, "moduli.png", options.quiet);
  if (!options.quiet) {
    fmt::print("{}", md.substr(md.find("| ")));
    fmt::print("wrote {}/moduli.md, moduli.csv, moduli.png\n", directory.string());
  }
  return code;
}

}  // namespace softflow::simulation
