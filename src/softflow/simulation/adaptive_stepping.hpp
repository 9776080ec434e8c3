// Adaptive time steps (time.adaptive_tolerance > 0): one accepted step, steps that
// miss the tolerance or fail taken back and tried again smaller.
#pragma once

#include <optional>

#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_ledger.hpp"
#include "softflow/time/step_controller.hpp"

namespace softflow::simulation {

/// The size of the next adaptive step from t: the controller's, shortened
/// to land on the end of the run and on a jump of the wall speed (where
/// the BDF histories restart); a last step within 1 % of the end is
/// stretched to it rather than leaving a sliver.
double adaptive_step_size(double proposed, double t, double end, const physics::WallMotion& walls);

/// Takes the run's next step: time.step with constant steps; with adaptive
/// steps the controller's size, and a step whose error estimate exceeds the
/// tolerance, or that fails (solver, mesh quality, an interface that no
/// longer fits), is taken back (DropSimulation::restore_step_state) and
/// tried again smaller, each retry a line on the console unless `quiet`.
/// Throws AccuracyError when no step down to time.step / 1000 meets the
/// tolerance, and rethrows the failure of the smallest step.
class StepTaker {
 public:
  StepTaker(const io::CaseConfig& config, std::optional<AdaptiveSteps>& adaptive, bool quiet);
  StepReport take(DropSimulation& sim);

 private:
  const io::CaseConfig& config_;
  std::optional<AdaptiveSteps>& adaptive_;
  std::optional<time::StepController> controller_;
  physics::WallMotion walls_;
  bool quiet_;
};

}  // namespace softflow::simulation
