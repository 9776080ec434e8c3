#include "softflow/simulation/modules/viscoelastic_module.hpp"

#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow::simulation {

const io::ReportTable<StressRow>& stress_table() {
  using C = io::Column<StressRow>;
  constexpr auto kInteger = kIntegerColumn;
  constexpr auto kFull = kStateColumn;
  constexpr auto kShort = io::ColumnFormat::real(6);
  auto mean = [](int i, int j) {
    return [i, j](const StressRow& r) { return r.stress.mean(i, j); };
  };
  static const io::ReportTable<StressRow> table(
      "stress.csv", "region with a conformation tensor and step",
      "Volume averages <tau> of the polymer or elastic stress tau = G (c - I) over the region "
      "(0: the matrix, k: object k).",
      with_step_and_time<StressRow>(std::vector<C>{
          {"region", "", "region (0 the matrix, k object k)", kInteger,
           [](const StressRow& r) { return r.stress.region; }},
          {"volume", "length^3", "region volume", kFull,
           [](const StressRow& r) { return r.stress.volume; }},
          {"tau_xx", "stress", "<tau_xx>", kFull, mean(0, 0)},
          {"tau_yy", "stress", "<tau_yy>", kFull, mean(1, 1)},
          {"tau_zz", "stress", "<tau_zz>", kFull, mean(2, 2)},
          {"tau_xy", "stress", "<tau_xy>", kFull, mean(0, 1)},
          {"tau_yz", "stress", "<tau_yz>", kFull, mean(1, 2)},
          {"tau_xz", "stress", "<tau_xz>", kFull, mean(0, 2)},
          {"N1", "stress", "<tau_xx> - <tau_yy>", kFull,
           [](const StressRow& r) { return r.stress.first_normal_stress_difference(); }},
          {"tau_1", "stress", "largest eigenvalue of <tau>", kFull,
           [](const StressRow& r) { return r.stress.principal(0); }},
          {"tau_2", "stress", "middle eigenvalue of <tau>", kFull,
           [](const StressRow& r) { return r.stress.principal(1); }},
          {"tau_3", "stress", "smallest eigenvalue of <tau>", kFull,
           [](const StressRow& r) { return r.stress.principal(2); }},
          {"spread", "", "sqrt(<|tau - <tau>|^2>) / |<tau>|: 0 for a uniform stress", kShort,
           [](const StressRow& r) { return r.stress.spread; }}}));
  return table;
}

ViscoelasticModule::ViscoelasticModule(const ModuleSetup& setup)
    : phases_(setup.mesh, {setup.models.begin(), setup.models.end()}, setup.stokes.interface_slip(),
              io::conformation_supg_taus(setup.config),
              setup.config.conformation.stress_prediction, setup.config.conformation.devss_g) {}

bool ViscoelasticModule::wanted(const ModuleSetup& setup) {
  return ViscoelasticPhases::needed({setup.models.begin(), setup.models.end()});
}

void ViscoelasticModule::restart_time_history() { phases_.restart_time_history(); }

void ViscoelasticModule::carry_over(StepModule& old, const fem::MeshTransfer& transfer) {
  auto& before = dynamic_cast<ViscoelasticModule&>(old);
  phases_.carry_over(before.phases_, transfer);
}

void ViscoelasticModule::contribute(physics::StokesProblem& problem, const StepContext& context) {
  problem.viscoelastic = phases_.coupling(context.mesh_velocity, context.dt);
}

void ViscoelasticModule::advance(const StepContext& context) {
  phases_.advance(context.stokes.dofs(), context.solution, context.dt, context.time, context.step);
}

void ViscoelasticModule::measure(const StepContext& context, StepReport& report) {
  last_.clear();
  for (int r = 0; r <= context.mesh.n_objects; ++r)
    if (phases_.models()[r].has_conformation()) last_.push_back(phases_.region_stress(r));
  report.stresses = last_;
}

std::vector<fem::Field*> ViscoelasticModule::fields() {
  // The transport's history and G are in state_parts(); these three are
  // written for ParaView and checkpointed as fields.
  return phases_.output_fields();
}

std::vector<StatePart> ViscoelasticModule::state_parts() { return {phases_.state_part()}; }

std::vector<ReportFile> ViscoelasticModule::report_files() const {
  return {{stress_table().file(), stress_table().header(), [](const StepReport& report) {
             std::string out;
             for (const auto& s : report.stresses) out += stress_table().row({report, s});
             return out;
           }}};
}

void ViscoelasticModule::summarise(nlohmann::json& summary) const {
  // The final row of stress.csv per region, from the same declarations.
  nlohmann::json regions = nlohmann::json::array();
  const StepReport none;
  for (const auto& s : last_) regions.push_back(stress_table().json_row({none, s}, {"step", "t"}));
  summary["final_stress"] = regions;
}

}  // namespace softflow::simulation
