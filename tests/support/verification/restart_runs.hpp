// A time run interrupted by a checkpoint and continued from it, beside the
// same run uninterrupted: the shared set-up of the exact-restart tests.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/simulation/drop_simulation.hpp"

namespace softflow::verification {

struct RestartRuns {
  std::unique_ptr<simulation::DropSimulation> uninterrupted, restarted;
  /// The state saved after `checkpoint_step` (as written to and read from an HDF5 file).
  io::Checkpoint checkpoint;
  /// The last step's report of each run.
  simulation::StepReport last, again;
};

/// Runs `config` for `steps` steps, writing a checkpoint file after
/// `checkpoint_step`; then reads it back and continues a second simulation
/// from it to the same step. The file (in the temporary directory, named
/// after `name`) is removed.
RestartRuns run_and_restart(const io::CaseConfig& config, int checkpoint_step, int steps,
                            const std::string& name);

/// max |a_i - b_i| over every output field of the two runs, field by field.
std::vector<double> output_field_differences(const simulation::DropSimulation& a,
                                             const simulation::DropSimulation& b);

}  // namespace softflow::verification
