// The case's [flow] as the physics needs it: the wall motion of every run.
#pragma once

#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"

namespace softflow::simulation {

/// The walls' speed history u_w(t) of the case's flow type (steady,
/// start_up, cessation, oscillatory), in the case's box height. Every solve
/// takes its boundary velocity from here, so a new flow type is added in one
/// place.
physics::WallMotion wall_motion(const io::CaseConfig& config);

}  // namespace softflow::simulation
