#include "softflow/simulation/modules/slip_module.hpp"

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"

namespace softflow::simulation {

const io::ReportTable<SlipRow>& slip_table() {
  using C = io::Column<SlipRow>;
  constexpr auto kInteger = kIntegerColumn;
  constexpr auto kFull = kStateColumn;
  static const io::ReportTable<SlipRow> table(
      "slip.csv", "object and step",
      "The slip across each interface with Navier slip (docs/slip.md).",
      with_step_and_time<SlipRow>(std::vector<C>{
          {"object", "", "object number", kInteger, [](const SlipRow& r) { return r.object; }},
          {"area", "length^2", "interface area", kFull,
           [](const SlipRow& r) { return r.slip.area; }},
          {"mean_slip_speed", "length/time", "mean of |(I - nn)(u_m - u_d)| over the interface",
           kFull, [](const SlipRow& r) { return r.slip.mean_slip_speed; }},
          {"max_slip_speed", "length/time", "largest nodal |u_m - u_d|", kFull,
           [](const SlipRow& r) { return r.slip.max_slip_speed; }},
          {"slip_dissipation", "power", "integral of lambda . (u_m - u_d): the power the slip "
           "dissipates (never negative)", kFull,
           [](const SlipRow& r) { return r.slip.dissipation; }}}));
  return table;
}

SlipModule::SlipModule(const ModuleSetup& /*setup*/) {}

bool SlipModule::wanted(const ModuleSetup& setup) { return io::has_interface_slip(setup.config); }

void SlipModule::measure(const StepContext& context, StepReport& report) {
  const auto& stokes = context.stokes;
  const auto normals = stokes.slip_node_normals(context.mesh);
  if (!context.interface_values)  // t = 0: the interface is there, nothing moves across it yet
    last_ = physics::slip_measures(context.mesh, stokes.dofs(), normals, [](int) { return 0.0; });
  else
    last_ = physics::slip_measures(context.mesh, stokes.dofs(), normals,
                                   [&values = *context.interface_values](int dof) { return values[dof]; });
  report.slips = last_;
  // Measured on the geometry the system was assembled on (the mesh before
  // Step 5 moves only the trackers' copies), so the identity holds.
  for (std::size_t k = 0; k < last_.size(); ++k) {
    const auto& s = last_[k];
    if (!physics::dissipation_is_negative(s)) continue;
    throw AccuracyError(fmt::format(
        "step {} (t = {:.4f}): object {}: the slip dissipates {:.3e} < 0 (of |power| {:.3e}): "
        "energy would be made at the interface, so the solution is wrong. Check the solver "
        "(solver.type = \"direct\") and that objects[{}].slip is within what the mesh resolves",
        context.step, context.time, k + 1, s.dissipation, s.absolute_power, k + 1));
  }
}

std::vector<ReportFile> SlipModule::report_files() const {
  return {{slip_table().file(), slip_table().header(), [](const StepReport& report) {
             std::string out;
             for (std::size_t k = 0; k < report.slips.size(); ++k)
               out += slip_table().row({report, static_cast<int>(k) + 1, report.slips[k]});
             return out;
           }}};
}

void SlipModule::summarise(nlohmann::json& summary) const {
  nlohmann::json objects = nlohmann::json::array();
  const StepReport none;
  for (std::size_t k = 0; k < last_.size(); ++k)
    objects.push_back(slip_table().json_row({none, static_cast<int>(k) + 1, last_[k]}, {"step", "t"}));
  summary["final_slip"] = objects;
}

}  // namespace softflow::simulation
