// Navier slip at the interfaces as a module of the time step: the slip measures
// of every object (docs/slip.md), the energy check and slip.csv. The slip's
// terms of the Stokes system (a velocity copy per region, the multipliers)
// are the Stokes system's own (physics::StokesSystem with interface slip).
#pragma once

#include "softflow/io/report_table.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/simulation/step_module.hpp"

namespace softflow::simulation {

/// What one row of slip.csv is made from.
struct SlipRow {
  const StepReport& report;
  int object;  ///< 1-based
  const physics::SlipMeasures& slip;
};

/// slip.csv: one row per object and step.
const io::ReportTable<SlipRow>& slip_table();

/// Stage measure: StepReport::slips, per object; stops the run
/// (AccuracyError) if an interface's slip dissipation is negative beyond
/// round-off: energy made at the interface means a wrong solution.
class SlipModule final : public StepModule {
 public:
  explicit SlipModule(const ModuleSetup& setup);
  /// Whether some object of the case has Navier slip.
  [[nodiscard]] static bool wanted(const ModuleSetup& setup);

  [[nodiscard]] std::string name() const override { return "slip"; }
  void measure(const StepContext& context, StepReport& report) override;
  [[nodiscard]] std::vector<ReportFile> report_files() const override;
  void summarise(nlohmann::json& summary) const override;

 private:
  std::vector<physics::SlipMeasures> last_;  // the last measure()
};

}  // namespace softflow::simulation
