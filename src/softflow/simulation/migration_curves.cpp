#include "softflow/simulation/migration_curves.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/io/output_directory.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

namespace fs = std::filesystem;

namespace {

/// The rows of a CSV file as name -> value maps.
std::vector<std::map<std::string, double>> read_csv(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot read it (a run of softflow with objects writes it)", path.string()));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream header(line); std::getline(header, line, ',');) names.push_back(line);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::map<std::string, double> row;
    std::stringstream cells(line);
    std::string cell;
    for (std::size_t c = 0; c < names.size() && std::getline(cells, cell, ','); ++c) {
      try {
        row[names[c]] = std::stod(cell);
      } catch (const std::exception&) {
        row[names[c]] = std::nan("");
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

double field(const std::map<std::string, double>& row, const std::string& name, const fs::path& file) {
  const auto it = row.find(name);
  if (it == row.end())
    throw InputError(fmt::format("{}: no column '{}' (written by an older softflow?)", file.string(), name));
  return it->second;
}

/// One run's rows of object 1 from t >= transient, in time order.
std::vector<MigrationPoint> kept_rows(const fs::path& dir, double transient) {
  const fs::path file = dir / "migration.csv";
  std::vector<MigrationPoint> rows;
  for (const auto& row : read_csv(file)) {
    if (field(row, "object", file) != 1.0) continue;
    MigrationPoint p;
    p.t = field(row, "t", file);
    if (p.t < transient) continue;
    p.y_p = field(row, "y_p", file);
    p.y_rel = field(row, "y_p_rel", file);
    p.v_p = field(row, "v_p", file);
    p.delta_s = field(row, "delta_s", file);
    rows.push_back(p);
  }
  std::stable_sort(rows.begin(), rows.end(),
                   [](const auto& a, const auto& b) { return a.t < b.t; });
  return rows;
}

/// The slope of y_p(t) between the first and the last row.
double mean_velocity(const std::vector<MigrationPoint>& rows) {
  if (rows.size() < 2) return std::nan("");
  return (rows.back().y_p - rows.front().y_p) / (rows.back().t - rows.front().t);
}

/// A run as assemble_migration reads it.
struct StartRun {
  fs::path dir;
  double y0 = 0.0;  ///< the object's centre height in the case
  std::vector<MigrationPoint> rows;
};

/// Row by row, the point-symmetric mean (q(start) - q(mirror)) / 2 of the
/// quantities odd under the half turn about z (y_p, y_p / y_p,max, v_p, Delta S).
std::vector<MigrationPoint> mirror_mean(const StartRun& start, const StartRun& mirror) {
  const auto& a = start.rows;
  const auto& b = mirror.rows;
  const auto same_time = [](double s, double t) {
    return std::abs(s - t) <= 1e-9 * std::max(1.0, std::abs(t));
  };
  std::size_t k = 0;
  while (k < std::min(a.size(), b.size()) && same_time(a[k].t, b[k].t)) ++k;
  if (k < a.size() || k < b.size())
    throw InputError(fmt::format(
        "--mirror: {} and its mirror start {} have different times after --transient ({} and {} "
        "rows{}): a "
        "pair is averaged row by row, so run both with the same time step to the same end",
        start.dir.string(), mirror.dir.string(), a.size(), b.size(),
        k < std::min(a.size(), b.size())
            ? fmt::format("; row {}: t = {:g} and {:g}", k, a[k].t, b[k].t)
            : ""));
  std::vector<MigrationPoint> mean(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    mean[i].t = a[i].t;
    mean[i].y_p = 0.5 * (a[i].y_p - b[i].y_p);
    mean[i].y_rel = 0.5 * (a[i].y_rel - b[i].y_rel);
    mean[i].v_p = 0.5 * (a[i].v_p - b[i].v_p);
    mean[i].delta_s = 0.5 * (a[i].delta_s - b[i].delta_s);
  }
  return mean;
}

/// No mirror start given for a run (mirror_partners).
constexpr std::size_t kNoMirror = static_cast<std::size_t>(-1);

/// Each start at +y_p0 with its mirror start at -y_p0, and each run without a
/// mirror start alone (second = kNoMirror), in the order given.
std::vector<std::pair<std::size_t, std::size_t>> mirror_partners(const std::vector<StartRun>& runs,
                                                                 double y_max) {
  const double tolerance = 1e-6 * y_max;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const StartRun& r = runs[i];
    if (std::abs(r.y0) <= tolerance)
      throw InputError(
          fmt::format("--mirror: {} starts on the centre plane (y_p0 = {:g}), its own mirror "
                      "image: --mirror pairs starts at +y_p0 and -y_p0",
                      r.dir.string(), r.y0));
    for (std::size_t j = 0; j < i; ++j)
      if (std::abs(runs[j].y0 - r.y0) <= tolerance)
        throw InputError(
            fmt::format("--mirror: {} and {} both start at y_p0 = {:g}: give one start and one "
                        "mirror start per height",
                        runs[j].dir.string(), r.dir.string(), r.y0));
    std::size_t partner = kNoMirror;
    for (std::size_t j = 0; j < runs.size(); ++j)
      if (std::abs(runs[j].y0 + r.y0) <= tolerance) partner = j;
    if (partner == kNoMirror)
      pairs.emplace_back(i, kNoMirror);
    else if (r.y0 > 0.0)
      pairs.emplace_back(i, partner);
  }
  return pairs;
}

}  // namespace

MigrationCurves assemble_migration(const std::vector<fs::path>& directories, double transient,
                                   double segment, RunPairing pairing) {
  if (directories.empty()) throw InputError("softflow migration: give the run directories to combine");
  if (!(transient >= 0.0))
    throw InputError(fmt::format("--transient = {:g}: must be a time >= 0", transient));
  if (!(segment > 0.0) || !std::isfinite(segment))
    throw InputError(fmt::format("--segment = {:g}: must be a time > 0", segment));
  MigrationCurves curves;
  curves.transient = transient;
  curves.segment = segment;
  std::vector<StartRun> starts;
  for (std::size_t r = 0; r < directories.size(); ++r) {
    const fs::path& dir = directories[r];
    const auto config = io::read_case_file(dir / "case.toml");
    if (config.objects.empty())
      throw InputError(fmt::format("{}: the case has no object", dir.string()));
    const auto& object = config.objects.front();
    const double radius = io::mean_radius(object.geometry);
    const double beta = 2.0 * radius / config.box.height;
    const double ca_e = io::elastic_capillary_number(config, object).value_or(0.0);
    const double y_max = 0.5 * config.box.height - radius;
    if (r == 0) {
      curves.blockage_ratio = beta;
      curves.y_max = y_max;
      curves.capillary_number = ca_e;
    } else if (std::abs(beta - curves.blockage_ratio) > 1e-9 ||
               std::abs(ca_e - curves.capillary_number) > 1e-12 ||
               std::abs(y_max - curves.y_max) > 1e-9 * curves.y_max) {
      throw InputError(
          fmt::format("{}: beta = {:g}, Ca_e = {:g}, y_p,max = H/2 - R = {:g}, but {} has beta = "
                      "{:g}, Ca_e = {:g}, "
                      "y_p,max = {:g}: a master curve combines runs of one particle and flow from "
                      "different starts",
                      dir.string(), beta, ca_e, y_max, directories.front().string(),
                      curves.blockage_ratio, curves.capillary_number, curves.y_max));
    }
    starts.push_back({dir, object.geometry.centre.y(), kept_rows(dir, transient)});
  }
  // The series the curves are made of: each run, or each mirror pair's mean.
  std::vector<std::vector<MigrationPoint>> series;
  if (pairing == RunPairing::mirror) {
    for (const auto& [s, m] : mirror_partners(starts, curves.y_max)) {
      const StartRun& start = starts[s];
      curves.runs.push_back(start.dir);
      if (m == kNoMirror) {
        curves.mirror_pairs.push_back(
            {start.dir, {}, start.y0 / curves.y_max, mean_velocity(start.rows), std::nan("")});
        series.push_back(start.rows);
        continue;
      }
      const StartRun& mirror = starts[m];
      series.push_back(mirror_mean(start, mirror));
      curves.mirror_pairs.push_back({start.dir, mirror.dir, start.y0 / curves.y_max,
                                     mean_velocity(start.rows), mean_velocity(mirror.rows)});
    }
  } else {
    for (auto& start : starts) {
      curves.runs.push_back(start.dir);
      series.push_back(std::move(start.rows));
    }
  }
  // Each series' finite rows (in time order, as kept_rows and mirror_mean give
  // them) are its points and are cut into its stretches.
  for (std::size_t r = 0; r < series.size(); ++r) {
    std::vector<MigrationPoint> rows;
    for (MigrationPoint p : series[r]) {
      p.run = static_cast<int>(r);
      if (std::isfinite(p.v_p) && std::isfinite(p.y_rel)) rows.push_back(p);
    }
    curves.points.insert(curves.points.end(), rows.begin(), rows.end());
    std::size_t begin = 0;
    while (begin + 1 < rows.size()) {
      std::size_t end = begin + 1;
      while (end + 1 < rows.size() && rows[end].t - rows[begin].t < segment * (1.0 - 1e-9)) ++end;
      // A short remainder joins this stretch rather than standing alone.
      if (rows.back().t - rows[end].t < 0.5 * segment * (1.0 + 1e-9)) end = rows.size() - 1;
      const auto& a = rows[begin];
      const auto& b = rows[end];
      curves.segments.push_back({static_cast<int>(r), a.t, b.t, 0.5 * (a.y_rel + b.y_rel),
                                 (b.y_p - a.y_p) / (b.t - a.t)});
      begin = end;
    }
  }
  std::sort(curves.segments.begin(), curves.segments.end(),
            [](const MigrationSegment& a, const MigrationSegment& b) { return a.y_rel < b.y_rel; });
  std::sort(curves.points.begin(), curves.points.end(),
            [](const MigrationPoint& a, const MigrationPoint& b) { return a.y_rel < b.y_rel; });
  const auto& pts = curves.points;
  const auto& segs = curves.segments;
  curves.neutral = neutral_heights(master_curve(segs));
  // Eq. 3.7: v_p linear in y_rel near the centre plane, through the origin.
  double syy = 0.0, syv = 0.0;
  for (const auto& p : pts)
    if (std::abs(p.y_rel) <= 0.1) {
      syy += p.y_rel * p.y_rel;
      syv += p.y_rel * p.v_p;
      ++curves.slope_points;
    }
  if (curves.slope_points >= 2 && syy > 0.0) {
    const double s = syv / syy;
    double residual = 0.0, scale = 0.0;
    for (const auto& p : pts)
      if (std::abs(p.y_rel) <= 0.1) {
        residual += std::pow(p.v_p - s * p.y_rel, 2);
        scale += p.v_p * p.v_p;
      }
    curves.slope = s;
    curves.slope_residual = scale > 0.0 ? std::sqrt(residual / scale) : 0.0;
  }
  curves.theory_slope = -2.0 * std::pow(curves.blockage_ratio, 3) * curves.capillary_number;  // eq. 3.8
  return curves;
}

std::string describe(NeutralHeight::Kind kind) {
  switch (kind) {
    case NeutralHeight::Kind::stable: return "stable (particles gather)";
    case NeutralHeight::Kind::unstable: return "unstable";
    case NeutralHeight::Kind::touching:
      return "touching (v_p = 0 there, of one sign on both sides)";
    case NeutralHeight::Kind::at_end:
      return "at an end of the measured heights (its kind needs the next height)";
  }
  return "";
}

MasterCurve master_curve(const std::vector<MigrationSegment>& segments) {
  MasterCurve c;
  std::vector<int> merged;  // stretches averaged into each node
  for (const auto& s : segments) {
    if (!c.y_rel.empty() && s.y_rel - c.y_rel.back() < 1e-12) {
      c.v_p.back() += (s.v_p - c.v_p.back()) / ++merged.back();  // running mean
      continue;
    }
    c.y_rel.push_back(s.y_rel);
    c.v_p.push_back(s.v_p);
    merged.push_back(1);
  }
  return c;
}

std::vector<NeutralHeight> neutral_heights(const MasterCurve& curve) {
  const auto& ys = curve.y_rel;
  const auto& vs = curve.v_p;
  const std::size_t n = ys.size();
  std::vector<NeutralHeight> out;
  for (std::size_t i = 0; i < n; ++i) {
    if (vs[i] == 0.0) {  // on the node itself
      if (n < 2) continue;
      const bool has_below = i > 0, has_above = i + 1 < n;
      NeutralHeight h;
      h.y_rel = ys[i];
      h.error =
          0.5 * std::max(has_below ? ys[i] - ys[i - 1] : 0.0, has_above ? ys[i + 1] - ys[i] : 0.0);
      // Its kind from the nearest non-zero v_p on either side (past neighbouring zeros).
      std::size_t below = i, above = i;
      while (below > 0 && vs[below] == 0.0) --below;
      while (above + 1 < n && vs[above] == 0.0) ++above;
      if (vs[below] == 0.0 || vs[above] == 0.0)
        h.kind = NeutralHeight::Kind::at_end;
      else if (vs[below] > 0.0 && vs[above] < 0.0)
        h.kind = NeutralHeight::Kind::stable;
      else if (vs[below] < 0.0 && vs[above] > 0.0)
        h.kind = NeutralHeight::Kind::unstable;
      else
        h.kind = NeutralHeight::Kind::touching;
      out.push_back(h);
      continue;
    }
    if (i + 1 < n && vs[i + 1] != 0.0 && (vs[i] > 0.0) != (vs[i + 1] > 0.0)) {
      NeutralHeight h;
      h.y_rel = ys[i] + (ys[i + 1] - ys[i]) * vs[i] / (vs[i] - vs[i + 1]);
      h.error = 0.5 * (ys[i + 1] - ys[i]);
      h.kind = vs[i] > 0.0 ? NeutralHeight::Kind::stable : NeutralHeight::Kind::unstable;
      out.push_back(h);
    }
  }
  return out;
}

namespace {

/// The time to go from y1 to y2 on a piece where the velocity is linear,
/// v(y) = v1 + slope (y - y1), and keeps v1's (non-zero) sign: the integral
/// of dy / v.
double piece_time(double y1, double y2, double v1, double slope) {
  const double x = slope * (y2 - y1) / v1;  // v(y2) / v1 - 1 > -1
  if (std::abs(x) < 1e-12) return (y2 - y1) / v1;
  return std::log1p(x) / slope;
}

/// The master curve as quasi_steady_trajectory integrates it: heights ys
/// (increasing) and d(y_rel)/dt vs, linear between them.
struct PiecewiseCurve {
  std::vector<double> ys, vs;
  /// On piece k (between nodes k and k + 1), exact at both nodes.
  double velocity(std::size_t k, double y) const {
    const double w = (y - ys[k]) / (ys[k + 1] - ys[k]);
    return (1.0 - w) * vs[k] + w * vs[k + 1];
  }
  double slope(std::size_t k) const { return (vs[k + 1] - vs[k]) / (ys[k + 1] - ys[k]); }
};

}  // namespace

QuasiSteadyTrajectory quasi_steady_trajectory(const MigrationCurves& curves, double y_start,
                                              double neutral_tolerance, const std::string& option) {
  if (!(curves.y_max > 0.0))
    throw InputError(
        fmt::format("{}: y_p,max = H/2 - R = {:g} is not positive", option, curves.y_max));
  if (!(neutral_tolerance > 0.0 && neutral_tolerance < 1.0))
    throw InputError(
        fmt::format("neutral tolerance = {:g}: must lie in (0, 1)", neutral_tolerance));
  for (const auto& s : curves.segments)
    if (!std::isfinite(s.v_p) || !std::isfinite(s.y_rel))
      throw InputError(fmt::format(
          "{}: run {} has a non-finite y_p or v_p over t = {:g}-{:g}", option,
          curves.runs.size() > static_cast<std::size_t>(s.run) ? curves.runs[s.run].string()
                                                               : std::to_string(s.run),
          s.t_begin, s.t_end));
  // The neutral heights' curve, in y_p / y_p,max per unit time.
  const MasterCurve master = master_curve(curves.segments);
  PiecewiseCurve c{master.y_rel, master.v_p};
  for (double& v : c.vs) v /= curves.y_max;
  const auto& ys = c.ys;
  const auto& vs = c.vs;
  const std::size_t n = ys.size();
  if (n < 2)
    throw InputError(
        fmt::format("{}: the master curve has {} stretch height(s); a trajectory needs two "
                    "or more (more runs, or a shorter --segment)",
                    option, n));
  // A start a round-off beyond an end (a height computed from the same rows) is that end.
  const double round_off = 1e-9 * (ys.back() - ys.front());
  if (y_start < ys.front() && y_start >= ys.front() - round_off) y_start = ys.front();
  if (y_start > ys.back() && y_start <= ys.back() + round_off) y_start = ys.back();
  if (!(y_start >= ys.front() && y_start <= ys.back()))
    throw InputError(
        fmt::format("{} = {:g}: outside the measured heights, y_p / y_p,max = {:.4f} ... {:.4f} "
                    "(the stretches' middles); start within them",
                    option, y_start, ys.front(), ys.back()));

  QuasiSteadyTrajectory path;
  path.y_start = y_start;
  path.t.push_back(0.0);
  path.y_rel.push_back(y_start);
  // The piece [ys[k], ys[k + 1]] holding the start, and the velocity there
  // (a node's own value on a node).
  std::size_t k =
      std::min<std::size_t>(std::upper_bound(ys.begin(), ys.end(), y_start) - ys.begin(), n - 1) -
      1;
  const double v0 = c.velocity(k, y_start);
  if (v0 == 0.0) {
    path.neutral_height = y_start;
    path.ends_at = fmt::format(
        "at a neutral height, y_p / y_p,max = {:.4f} (v_p = 0 where it starts)", y_start);
    path.y_end = y_start;
    return path;
  }
  const int direction = v0 > 0.0 ? 1 : -1;
  const auto ahead = [&](double v) { return direction > 0 ? v > 0.0 : v < 0.0; };
  // Where it ends: the first node ahead where v_p no longer points onwards
  // marks a neutral height in the piece before it (v_p = 0 there, or between
  // the two by the linear root); it is approached ever more slowly
  // (exponentially in time), so the path stops within the tolerance of it,
  // which may lie pieces before it. Without one, the last measured height.
  double end = direction > 0 ? ys.back() : ys.front();
  for (std::size_t j = k;; j = direction > 0 ? j + 1 : j - 1) {
    const std::size_t far = direction > 0 ? j + 1 : j;
    if (!ahead(vs[far])) {
      const std::size_t near = direction > 0 ? j : j + 1;
      // The zero between `near` (v_p onwards) and `far` (zero, or back): the
      // one of migration.md's list (its height and kind), found as the entry
      // nearest the linear root so that the two agree to the bit.
      const double root = vs[far] != 0.0
                              ? ys[near] + (ys[far] - ys[near]) * vs[near] / (vs[near] - vs[far])
                              : ys[far];
      const std::vector<NeutralHeight> zeros = neutral_heights(master);
      const NeutralHeight zero =
          *std::min_element(zeros.begin(), zeros.end(), [&](const auto& a, const auto& b) {
            return std::abs(a.y_rel - root) < std::abs(b.y_rel - root);
          });
      const double y_n = zero.y_rel;
      // Near the centre plane a tolerance relative to y_n would shrink to
      // nothing: there it is relative to 0.1 y_p,max.
      const double band = neutral_tolerance * std::max(std::abs(y_n), 0.1);
      path.neutral_height = y_n;
      end = y_n - direction * band;
      // Approached along v_p, a zero is stable, touching (v_p onwards again
      // beyond a zero node) or at an end (v_p = 0 on to the last height).
      path.ends_at = fmt::format("within {:g} % of the {}neutral height y_p / y_p,max = {:.4f}",
                                 100.0 * neutral_tolerance,
                                 zero.kind == NeutralHeight::Kind::stable ? "stable " : "", y_n);
      if (zero.kind == NeutralHeight::Kind::at_end)
        path.ends_at += " (v_p = 0 from there to the last measured height)";
      if (zero.kind == NeutralHeight::Kind::touching)
        path.ends_at += " (v_p = 0 there, and points onwards again beyond it)";
      break;
    }
    if ((direction > 0 && far == n - 1) || (direction < 0 && far == 0)) break;
  }
  if (path.ends_at.empty())
    path.ends_at = fmt::format(
        "at the {} measured height, y_p / y_p,max = {:.4f} (no neutral height on the way)",
        direction > 0 ? "highest" : "lowest", end);
  // Along the pieces to `end`, eight samples each.
  double t = 0.0, y = y_start;
  while (direction * (end - y) > 0.0) {
    const double piece_end = direction > 0 ? std::min(ys[k + 1], end) : std::max(ys[k], end);
    const double from = y;
    for (int i = 1; i <= 8 && piece_end != from; ++i) {
      const double next = i == 8 ? piece_end : from + (piece_end - from) * i / 8.0;
      t += piece_time(y, next, c.velocity(k, y), c.slope(k));
      y = next;
      path.t.push_back(t);
      path.y_rel.push_back(y);
    }
    if (y == end) break;
    k = direction > 0 ? k + 1 : k - 1;
  }
  path.duration = t;
  path.y_end = y;
  return path;
}

void write_migration(const MigrationCurves& c, const fs::path& out,
                     const std::optional<QuasiSteadyTrajectory>& trajectory) {
  std::string csv = "run,t,y_p,y_p_rel,v_p,delta_s\n";
  for (const auto& p : c.points)
    csv += fmt::format("{},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g}\n", p.run, p.t, p.y_p, p.y_rel,
                       p.v_p, p.delta_s);
  std::string md = fmt::format(
      "# Migration master curves\n\nbeta = 2R/H = {:.4g}, Ca_e = {:g}; rows with t < {:g} dropped "
      "(the initial transient); {} points from {} {}. Generated by `softflow migration`.\n\n",
      c.blockage_ratio, c.capillary_number, c.transient, c.points.size(), c.runs.size(),
      c.mirror_pairs.empty() ? "runs" : "starts (mirror pairs and runs alone)");
  const auto kept = [&](std::size_t r) {
    return std::count_if(c.points.begin(), c.points.end(),
                         [r](const MigrationPoint& p) { return p.run == static_cast<int>(r); });
  };
  if (c.mirror_pairs.empty()) {
    md += "| run | directory | points kept |\n|---|---|---|\n";
    for (std::size_t r = 0; r < c.runs.size(); ++r)
      md += fmt::format("| {} | {} | {} |\n", r, c.runs[r].string(), kept(r));
  } else {
    md +=
        "Each run below is a start and its mirror start (`--mirror`), or a run given without "
        "one (then its own rows): the curves are the pairs' point-symmetric means, (q(start) - q(mirror)) / 2 row by row, which drop what the two "
        "meshes add in common, (q(start) + q(mirror)) / 2; an error odd in y_p stays. Mean v_p: "
        "the slope of y_p(t) over each run's kept rows.\n\n"
        "| run | start | mirror start | y_p0 / y_p,max | points kept | mean v_p, start | mean v_p, "
        "mirror | mirror-averaged | the meshes' part |\n|---|---|---|---|---|---|---|---|---|\n";
    for (std::size_t r = 0; r < c.mirror_pairs.size(); ++r) {
      const auto& m = c.mirror_pairs[r];
      if (!m.paired())
        md += fmt::format(
            "| {} | {} | none given: the run alone, its meshes' part kept | {:.4f} | {} | "
            "{:.4g} | | | |\n",
            r, m.start.string(), m.y_rel0, kept(r), m.v_start);
      else
        md += fmt::format("| {} | {} | {} | {:.4f} | {} | {:.4g} | {:.4g} | {:.4g} | {:.4g} |\n", r,
                          m.start.string(), m.mirror.string(), m.y_rel0, kept(r), m.v_start,
                          m.v_mirror, m.v_mirror_averaged(), m.v_meshes());
    }
  }
  md += fmt::format("\n## Mean migration over stretches of {:g} time units\n\n"
                    "The slope of y_p(t) over each stretch (the per-step v_p swings with the "
                    "particle's tank-treading); the neutral heights below are where it changes "
                    "sign.\n\n| run | t | y_p / y_p,max | v_p |\n|---|---|---|---|\n",
                    c.segment);
  for (const auto& s : c.segments)
    md += fmt::format("| {} | {:g}-{:g} | {:.4f} | {:.4g} |\n", s.run, s.t_begin, s.t_end, s.y_rel, s.v_p);
  md += "\n## Neutral heights (v_p = 0)\n\n";
  if (c.neutral.empty()) md += "None: the stretches' v_p has one sign.\n";
  else {
    md += "| y_p / y_p,max | +- | kind |\n|---|---|---|\n";
    for (const auto& n : c.neutral)
      md += fmt::format("| {:.4f} | {:.4f} | {} |\n", n.y_rel, n.error, describe(n.kind));
  }
  md += "\n## Near the centre plane (|y_p / y_p,max| <= 0.1, eq. 3.7)\n\n";
  if (c.slope)
    md += fmt::format("v_p = {:.4g} y_p / y_p,max (least squares through the origin, {} points, relative "
                      "rms residual {:.2g}); eq. 3.8 gives -2 beta^3 Ca_e = {:.4g} (ratio {:.3g}).\n",
                      *c.slope, c.slope_points, c.slope_residual, c.theory_slope,
                      c.theory_slope != 0.0 ? *c.slope / c.theory_slope : std::nan(""));
  else
    md += "Fewer than two points there: no slope.\n";
  std::string path_csv;
  if (trajectory) {
    const auto& p = *trajectory;
    md += fmt::format(
        "\n## Quasi-steady trajectory from y_p / y_p,max = {:.4f}\n\n"
        "dy_p/dt = v_p(y_p) along the stretches' curve (linear between them, integrated exactly; "
        "migration_trajectory.csv): it ends {} after t = {:.6g} (gamma_dot t with the runs' "
        "shear rate), at y_p / y_p,max = {:.4f} (y_p = {:.6g}). It holds where the particle settles "
        "faster than it migrates (docs/confinement.md, \"The quasi-steady trajectory\").\n",
        p.y_start, p.ends_at, p.duration, p.y_end, p.y_end * c.y_max);
    path_csv = "t,y_p,y_p_rel\n";
    for (std::size_t i = 0; i < p.t.size(); ++i)
      path_csv += fmt::format("{:.10g},{:.10g},{:.10g}\n", p.t[i], p.y_rel[i] * c.y_max, p.y_rel[i]);
  }
  md += "\n![migration](migration.png)\n";
  fs::create_directories(out);
  io::write_text_file_atomically(out / "migration_curves.csv", csv);
  if (trajectory) io::write_text_file_atomically(out / "migration_trajectory.csv", path_csv);
  io::write_text_file_atomically(out / "migration.md", md);
  // Nothing of an earlier call beside these curves: its trajectory, its picture.
  if (!trajectory) fs::remove(out / "migration_trajectory.csv");
  fs::remove(out / "migration.png");
  draw_plot("plot_migration.py", out, "migration.png", false);
}

}  // namespace softflow::simulation
