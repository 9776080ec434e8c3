#include "softflow/simulation/modules/migration_module.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow::simulation {

const io::ReportTable<MigrationRow>& migration_table() {
  using C = io::Column<MigrationRow>;
  constexpr auto kInteger = kIntegerColumn;
  constexpr auto kFull = kStateColumn;
  static const io::ReportTable<MigrationRow> table(
      "migration.csv", "object and step",
      "Cross-stream migration (thesis chapter 3): the centre of volume y_p, the migration velocity "
      "v_p = dy_p/dt and the surface imbalance Delta S of eq. 3.6 on the curved P2 interface, and "
      "the object's gap to the walls y = +-H/2.",
      with_step_and_time<MigrationRow>(std::vector<C>{
          {"object", "", "object number", kInteger, [](const MigrationRow& r) { return r.object.object; }},
          {"y_p", "length", "centre of volume, y (0: the centre plane)", kFull,
           [](const MigrationRow& r) { return r.object.centre.y(); }},
          {"y_p_rel", "", "y_p / y_p,max, y_p,max = H/2 - R the highest centre a sphere of the "
           "object's volume can reach (the abscissa of eqs. 3.7-3.8)", kFull,
           [](const MigrationRow& r) { return r.object.centre.y() / (0.5 * r.object.height - r.object.radius); }},
          {"v_p", "length/time", "migration velocity dy_p/dt (the BDF derivative of the centre)", kFull,
           [](const MigrationRow& r) { return r.object.migration_velocity; }},
          {"delta_s", "", "Delta S = (S(n_y > 0) - S(n_y < 0)) / (S / 2), eq. 3.6: > 0 when more "
           "surface faces the upper wall", kFull,
           [](const MigrationRow& r) { return r.object.imbalance.delta_s(); }},
          {"area_up", "length^2", "S(n_y > 0)", kFull,
           [](const MigrationRow& r) { return r.object.imbalance.area_positive; }},
          {"area_down", "length^2", "S(n_y < 0)", kFull,
           [](const MigrationRow& r) { return r.object.imbalance.area_negative; }},
          {"wall_gap", "length", "smallest distance from an interface node to a wall", kFull,
           [](const MigrationRow& r) { return r.object.wall_gap; }},
          {"nearest_wall", "", "+1 the upper wall (y = H/2), -1 the lower", kInteger,
           [](const MigrationRow& r) { return r.object.nearest_wall; }}}));
  return table;
}

MigrationModule::MigrationModule(const ModuleSetup& setup)
    : half_height_(setup.config.box.height / 2.0), min_wall_gap_(setup.config.time.min_wall_gap) {
  for (const auto& object : setup.config.objects) radii_.push_back(io::mean_radius(object.geometry));
}

bool MigrationModule::wanted(const ModuleSetup& setup) { return !setup.config.objects.empty(); }

void MigrationModule::measure(const StepContext& context, StepReport& report) {
  time_ = context.time;
  last_.clear();
  for (std::size_t k = 0; k < context.interfaces.size(); ++k) {
    const auto& tracker = context.interfaces[k];
    const auto& x = tracker.positions();
    const auto m = analysis::migration_measures(tracker.surface(), x);
    MigrationState s;
    s.object = static_cast<int>(k) + 1;
    s.centre = m.centre;
    s.imbalance = m.imbalance;
    s.radius = radii_.at(k);
    s.height = 2.0 * half_height_;
    for (const auto& o : report.objects)
      if (o.object == s.object) s.migration_velocity = o.centre_velocity.y();
    double upper = std::numeric_limits<double>::infinity(), lower = upper;
    for (const auto& p : x) {
      upper = std::min(upper, half_height_ - p.y());
      lower = std::min(lower, p.y() + half_height_);
    }
    s.wall_gap = std::min(upper, lower);
    s.nearest_wall = upper <= lower ? 1 : -1;
    last_.push_back(s);
  }
}

std::vector<ReportFile> MigrationModule::report_files() const {
  return {{migration_table().file(), migration_table().header(), [this](const StepReport& report) {
             std::string out;
             for (const auto& s : last_) out += migration_table().row({report, s});
             return out;
           }}};
}

void MigrationModule::summarise(nlohmann::json& summary) const {
  nlohmann::json objects = nlohmann::json::array();
  const StepReport none;
  for (const auto& s : last_) objects.push_back(migration_table().json_row({none, s}, {"step", "t"}));
  summary["final_migration"] = objects;
}

std::string MigrationModule::finished() const {
  if (min_wall_gap_ <= 0.0) return {};
  for (const auto& s : last_)
    if (s.wall_gap < min_wall_gap_ * s.radius)
      return fmt::format(
          "object {} came within {:.4g} of the {} wall (time.min_wall_gap = {:g} radii = {:.4g}) "
          "at t = {:.4f}, y_p = {:.5g}",
          s.object, s.wall_gap, s.nearest_wall > 0 ? "upper" : "lower", min_wall_gap_,
          min_wall_gap_ * s.radius, time_, s.centre.y());
  return {};
}

}  // namespace softflow::simulation
