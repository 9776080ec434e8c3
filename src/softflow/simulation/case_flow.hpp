// The case as the physics needs it: materials per region, wall motion, and the
// Stokes problem at a time t. Every run builds its Stokes problem here.
#pragma once

#include <vector>

#include "softflow/io/case_config.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"
#include "softflow/physics/stokes/wall_motion.hpp"

namespace softflow::simulation {

/// The walls' speed history of the case: io::wall_motion (found here by
/// argument-dependent lookup too).
using io::wall_motion;

/// k of the tangential redistribution u_t = k grad_s c (eq. 2.30), in 1/time:
/// interface.redistribution_factor (k / gamma_dot) times the shear rate; at
/// rest the factor itself.
double redistribution_rate(const io::CaseConfig& config);

/// The constitutive model of each region (0 = matrix, k = object k), from the case.
std::vector<physics::viscoelastic::Constitutive> phase_models(const io::CaseConfig& config);

/// The instantaneous Stokes problem of the case at time t on `mesh`:
/// materials, interfacial tensions, walls at t, the pressure gauge. Loads
/// that depend on the time loop's state (the semi-implicit tension) are
/// added by the caller.
physics::StokesProblem stokes_problem(const io::CaseConfig& config, const mesh::Mesh& mesh,
                                      double t);
/// The same with the run's constitutive models (phase_models(config), built
/// once per run), which give each region's viscosity.
physics::StokesProblem stokes_problem(const io::CaseConfig& config,
                                      const std::vector<physics::viscoelastic::Constitutive>& models,
                                      const mesh::Mesh& mesh, double t);

}  // namespace softflow::simulation
