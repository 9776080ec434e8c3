#include "softflow/simulation/case_flow.hpp"

namespace softflow::simulation {

physics::WallMotion wall_motion(const io::CaseConfig& config) {
  const double h = config.box.height;
  const auto& flow = config.flow;
  switch (flow.type) {
    case io::FlowType::steady: return physics::WallMotion::steady(h, config.shear_rate);
    case io::FlowType::start_up: return physics::WallMotion::start_up(h, config.shear_rate);
    case io::FlowType::cessation:
      return physics::WallMotion::cessation(h, config.shear_rate, flow.stop_time);
    case io::FlowType::oscillatory:
      return physics::WallMotion::oscillatory(h, flow.strain_amplitude, flow.frequency);
  }
  return physics::WallMotion::steady(h, config.shear_rate);  // not reached: every type above
}

}  // namespace softflow::simulation
