#include "softflow/simulation/adaptive_stepping.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/run_support.hpp"

namespace softflow::simulation {

double adaptive_step_size(double proposed, double t, double end, const physics::WallMotion& walls) {
  double dt = proposed;
  if (t + 1.01 * dt >= end) dt = end - t;
  if (const auto jump = walls.jump_time(); jump && *jump > t + 1e-12 * std::max(1.0, std::abs(t)) &&
                                           t + dt > *jump)
    dt = *jump - t;
  return dt;
}

StepTaker::StepTaker(const io::CaseConfig& config, std::optional<AdaptiveSteps>& adaptive, bool quiet)
    : config_(config),
      adaptive_(adaptive),
      controller_(adaptive ? std::optional(step_controller(config)) : std::nullopt),
      walls_(wall_motion(config)),
      quiet_(quiet) {}

StepReport StepTaker::take(DropSimulation& sim) {
  if (!adaptive_) return sim.step();
  auto& a = *adaptive_;
  while (true) {
    const double dt = adaptive_step_size(a.next_step, sim.time(), config_.time.end, walls_);
    const StateRecord before = sim.save_step_state();
    StepReport r;
    time::StepDecision decision;
    std::string why;
    bool failed = false;
    try {
      r = sim.step(dt);
      // A BDF1 step (the first, or the one after a jump) predicts x_n:
      // no estimate (NaN); keep its size.
      decision = std::isnan(r.interface_change) ? time::StepDecision{true, dt}
                                                : controller_->judge(dt, r.interface_change);
      if (!decision.accepted)
        why = fmt::format("estimate {:.3g} > time.adaptive_tolerance = {:g}", r.interface_change,
                          config_.time.adaptive_tolerance);
    } catch (const Error& e) {
      if (dynamic_cast<const InputError*>(&e)) throw;
      decision = controller_->after_failure(dt);
      if (decision.next_step == 0.0) throw;  // the smallest step failed too
      why = e.what();
      failed = true;
    }
    if (decision.accepted) {
      a.next_step = time::next_planned_step(a.next_step, dt, decision.next_step);
      a.smallest = std::min(a.smallest, dt);
      a.largest = std::max(a.largest, dt);
      return r;
    }
    if (decision.next_step == 0.0)
      throw AccuracyError(fmt::format(
          "step {} (t = {:.4f}): no step down to time.step / 1000 = {:g} meets "
          "time.adaptive_tolerance = {:g} ({}): raise the tolerance or refine the mesh",
          sim.steps() + 1, sim.time(), config_.time.step / 1000.0, config_.time.adaptive_tolerance,
          why));
    ++(failed ? a.failed : a.rejected);
    sim.restore_step_state(before);
    a.next_step = decision.next_step;
    if (!quiet_ && is_root()) {
      fmt::print("step {} (t = {:.4f}) taken again with dt = {:.4g} instead of {:.4g}: {}\n",
                 sim.steps() + 1, sim.time(), decision.next_step, dt, why);
      std::fflush(stdout);
    }
  }
}

}  // namespace softflow::simulation
