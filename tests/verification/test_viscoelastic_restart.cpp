// Runs with viscoelastic phases restart to round-off: the checkpoint carries
// the log-conformation at both BDF levels, the conformation and stress
// fields, the DEVSS-G gradient and the record of the matrices the Stokes
// factors were built from (which read the conformation), so a run
// checkpointed at step 3 and restarted continues to the same flow, shape
// and conformation as the run that never stopped. Two phases: a
// neo-Hookean particle in a Newtonian matrix, and a Newtonian drop in an
// Oldroyd-B matrix.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"
#include "support/verification/restart_runs.hpp"

using namespace softflow;

namespace {

void expect_exact_restart(const std::string& phases, const std::string& name) {
  const auto config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n" + phases +
          "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
          "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n",
      name);
  const auto runs = verification::run_and_restart(config, 3, 6, name);
  ASSERT_NE(runs.uninterrupted->viscoelastic(), nullptr) << name;
  EXPECT_TRUE(runs.checkpoint.state.contains("fields/log_conformation/values")) << name;
  EXPECT_TRUE(runs.checkpoint.state.contains("viscoelastic/transport/previous")) << name;
  EXPECT_TRUE(runs.checkpoint.state.contains("viscoelastic/prediction_defect/values")) << name;
  ASSERT_FALSE(runs.last.stresses.empty());
  EXPECT_GT(std::abs(runs.last.stresses.front().mean(0, 1)), 1e-3) << name;  // a stress built up

  const auto differences = verification::output_field_differences(*runs.uninterrupted, *runs.restarted);
  ASSERT_GE(differences.size(), 4u);  // Stokes + log_conformation, conformation, polymer_stress
  for (std::size_t f = 0; f < differences.size(); ++f)
    EXPECT_LT(differences[f], 1e-10) << name << " field " << f;
  EXPECT_NEAR(runs.again.objects.front().deformation, runs.last.objects.front().deformation, 1e-12) << name;
  EXPECT_NEAR(runs.again.stresses.front().mean(0, 1), runs.last.stresses.front().mean(0, 1), 1e-10) << name;
  EXPECT_EQ(runs.restarted->stokes().n_factorizations(), runs.uninterrupted->stokes().n_factorizations())
      << name;
}

}  // namespace

TEST(ViscoelasticRestart, NeoHookeanParticleContinuesToRoundOff) {
  expect_exact_restart(
      "[[objects]]\nmodel = \"neo_hookean\"\nelastic_capillary_number = 0.1\n", "particle");
}

TEST(ViscoelasticRestart, DropInOldroydBMatrixContinuesToRoundOff) {
  expect_exact_restart(
      "[matrix]\nmodel = \"oldroyd_b\"\nsolvent_viscosity = 0.5\npolymer_viscosity = 0.5\n"
      "relaxation_time = 0.5\n[[objects]]\nviscosity_ratio = 1.0\ncapillary_number = 0.1\n",
      "drop_in_oldroyd_b");
}

TEST(ViscoelasticFailure, ANonFiniteConformationStopsTheRunNamingWhereAndWhatToTry) {
  // A log-conformation that is no longer finite (here: planted in a saved
  // state) must stop the step with a SolverError (exit code 3) that names
  // the step, the time, the phase and what to try, not run on with NaN.
  const auto config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\nmodel = \"neo_hookean\"\nelastic_capillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n",
      "nan_particle");
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  sim.step();
  io::Checkpoint checkpoint;
  sim.save(checkpoint);
  // NaN in the particle's copy of s (region 1), every component.
  const auto sources = sim.output_fields();
  const fem::DofMap* dofs = sources.at(1).dofs;  // log_conformation (after velocity/pressure)
  auto entry = checkpoint.state.entries().at("fields/log_conformation/values");
  ASSERT_EQ(static_cast<int>(entry.values.size()), dofs->n_dofs());
  for (int d = 0; d < dofs->n_dofs(); ++d)
    if (dofs->region_of(d) == 1) entry.values[d] = std::nan("");
  checkpoint.state.insert("fields/log_conformation/values", entry);
  simulation::DropSimulation broken(config, checkpoint.reference_mesh);
  broken.restore(checkpoint);
  try {
    broken.step();
    FAIL() << "a non-finite conformation was carried on";
  } catch (const SolverError& e) {
    const std::string message = e.what();
    for (const char* piece : {"step 2", "t = 0.1000", "log-conformation", "in object 1", "neo_hookean",
                              "time.step", "finer mesh"})
      EXPECT_NE(message.find(piece), std::string::npos) << piece << " in: " << message;
  }
}
