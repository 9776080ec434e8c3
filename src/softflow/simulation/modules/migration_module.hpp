// Cross-stream migration as a module of the time step (thesis chapter 3, eqs. 3.5-3.6):
// per object the centre of volume y_p, the migration velocity v_p = dy_p/dt, the
// surface imbalance Delta S and the gap to the walls; migration.csv, and the end of
// a run whose object comes closer to a wall than time.min_wall_gap.
#pragma once

#include <vector>

#include "softflow/analysis/migration_measures.hpp"
#include "softflow/io/report_table.hpp"
#include "softflow/simulation/step_module.hpp"

namespace softflow::simulation {

/// What the module measures of one object at one time.
struct MigrationState {
  int object = 0;                   ///< 1-based
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< (x_p, y_p, z_p)
  double migration_velocity = 0.0;  ///< v_p: the centre's velocity along y (eqs. 2.51-2.54)
  analysis::SurfaceImbalance imbalance;
  /// The smallest distance from an interface node to a wall, and which wall
  /// (+1 the upper, y = H/2; -1 the lower).
  double wall_gap = 0.0;
  int nearest_wall = 1;
  double radius = 1.0;  ///< R = (abc)^(1/3) of the case's object
  double height = 1.0;  ///< H, the distance between the walls
};

/// What one row of migration.csv is made from.
struct MigrationRow {
  const StepReport& report;
  const MigrationState& object;
};

/// migration.csv: one row per object and step.
const io::ReportTable<MigrationRow>& migration_table();

/// In every run with objects. Stage measure: a MigrationState per object
/// from its corrected interface (Delta S on the curved P2 surface,
/// analysis::surface_imbalance), v_p from the run's centre velocity (the
/// BDF derivative of the centre of volume the tracker already takes).
/// finished(): an object's interface within time.min_wall_gap radii of a
/// wall (0 = never).
class MigrationModule final : public StepModule {
 public:
  explicit MigrationModule(const ModuleSetup& setup);
  [[nodiscard]] static bool wanted(const ModuleSetup& setup);

  [[nodiscard]] std::string name() const override { return "migration"; }
  void measure(const StepContext& context, StepReport& report) override;
  [[nodiscard]] std::vector<ReportFile> report_files() const override;
  void summarise(nlohmann::json& summary) const override;
  [[nodiscard]] std::string finished() const override;

  [[nodiscard]] const std::vector<MigrationState>& last() const { return last_; }

 private:
  double half_height_;
  std::vector<double> radii_;  // R = (abc)^(1/3) per object, as the case gives it
  double min_wall_gap_;  // in radii; 0 = off
  double time_ = 0.0;
  std::vector<MigrationState> last_;
};

}  // namespace softflow::simulation
