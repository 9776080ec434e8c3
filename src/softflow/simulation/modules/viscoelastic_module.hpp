// The viscoelastic phases as a module of the time step: the conformation fields of
// the phases that have one (thesis §2.3.1-2.3.2), their coupling to the Stokes
// step, their transport, the per-region mean stress and stress.csv.
#pragma once

#include "softflow/io/report_table.hpp"
#include "softflow/simulation/step_module.hpp"
#include "softflow/simulation/viscoelastic_phases.hpp"

namespace softflow::simulation {

struct StepReport;

/// What one row of stress.csv is made from.
struct StressRow {
  const StepReport& report;
  const RegionStress& stress;
};

/// stress.csv: one row per region with a conformation tensor and step.
const io::ReportTable<StressRow>& stress_table();

/// Stages: restart_histories (BDF1 again), solve_flow (the D'Avino-Hulsen /
/// DEVSS-G data of c_n, u_m, G_n), advance_fields (s = log c to t_{n+1},
/// then c, tau, G), measure (StepReport::stresses: <tau> per region).
class ViscoelasticModule final : public StepModule {
 public:
  explicit ViscoelasticModule(const ModuleSetup& setup);
  /// Whether some phase of the case has a conformation tensor.
  [[nodiscard]] static bool wanted(const ModuleSetup& setup);

  [[nodiscard]] std::string name() const override { return "viscoelastic"; }
  void restart_time_history() override;
  /// The conformation fields, the DEVSS-G gradient G_n and the transport's
  /// s_{n-1} carried over (ViscoelasticPhases::carry_over).
  void carry_over(StepModule& old, const fem::MeshTransfer& transfer) override;
  void contribute(physics::StokesProblem& problem, const StepContext& context) override;
  void advance(const StepContext& context) override;
  void measure(const StepContext& context, StepReport& report) override;
  [[nodiscard]] std::vector<fem::Field*> fields() override;
  [[nodiscard]] std::vector<StatePart> state_parts() override;
  [[nodiscard]] std::vector<ReportFile> report_files() const override;
  void summarise(nlohmann::json& summary) const override;

  [[nodiscard]] const ViscoelasticPhases& phases() const { return phases_; }

 private:
  ViscoelasticPhases phases_;
  std::vector<RegionStress> last_;  // the last measure()
};

}  // namespace softflow::simulation
