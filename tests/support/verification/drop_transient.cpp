#include "support/verification/drop_transient.hpp"

#include <cmath>
#include <map>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::verification {

DropTransient deform_drop_in_shear(double dt, double t_end, bool semi_implicit_tension) {
  const std::string text = fmt::format(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\nviscosity_ratio = 1.0\ncapillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = {}\nend = {}\n"
      "[interface]\nsemi_implicit_tension = {}\n"
      "[output]\nfields = false\n",
      dt, t_end, semi_implicit_tension);
  const auto config = io::parse_case(text, "deform_drop_in_shear");
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  DropTransient out;
  out.dt = dt;
  out.semi_implicit_tension = semi_implicit_tension;
  auto record = [&](const simulation::StepReport& r) {
    out.time.push_back(r.time);
    out.deformation.push_back(r.objects.front().deformation);
  };
  record(sim.initial_report());
  const int steps = static_cast<int>(std::lround(t_end / dt));
  try {
    for (int n = 0; n < steps; ++n) record(sim.step());
  } catch (const Error& e) {
    out.stop_reason = e.what();
  }
  return out;
}

double max_deformation_difference(const DropTransient& a, const DropTransient& b,
                                  double from_time) {
  std::map<long, double> fine;  // time in units of b's step -> D
  for (std::size_t i = 0; i < b.time.size(); ++i)
    fine[std::lround(b.time[i] / b.dt)] = b.deformation[i];
  double worst = 0.0;
  for (std::size_t i = 0; i < a.time.size(); ++i) {
    if (a.time[i] < from_time - 1e-9) continue;
    const auto it = fine.find(std::lround(a.time[i] / b.dt));
    if (it != fine.end()) worst = std::max(worst, std::abs(a.deformation[i] - it->second));
  }
  return worst;
}

}  // namespace softflow::verification
