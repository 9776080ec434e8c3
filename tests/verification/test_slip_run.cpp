// Time runs with interface slip: a run checkpointed at step 3 and restarted
// continues to the same flow (both velocity copies and the multipliers),
// shape and slip as the run that never stopped; also with a viscoelastic
// drop, whose conformation is transported with its own velocity copy. And
// the physics' direction: slip lowers the drop's deformation.
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"
#include "support/verification/restart_runs.hpp"

using namespace softflow;

namespace {

io::CaseConfig slip_case(const std::string& object, const std::string& name) {
  return io::parse_case("[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n[[objects]]\n" + object +
                            "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
                            "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n",
                        name);
}

void expect_exact_restart(const io::CaseConfig& config, const std::string& name) {
  const auto runs = verification::run_and_restart(config, 3, 6, name);
  ASSERT_TRUE(runs.uninterrupted->interface_slip()) << name;
  ASSERT_EQ(runs.last.slips.size(), 1u);
  EXPECT_GT(runs.last.slips[0].mean_slip_speed, 1e-3) << name;  // the copies really differ
  EXPECT_GT(runs.last.slips[0].dissipation, 0.0) << name;

  const auto differences = verification::output_field_differences(*runs.uninterrupted, *runs.restarted);
  for (std::size_t f = 0; f < differences.size(); ++f)
    EXPECT_LT(differences[f], 1e-10) << name << " field " << f;
  EXPECT_NEAR(runs.again.objects[0].deformation, runs.last.objects[0].deformation, 1e-12) << name;
  EXPECT_NEAR(runs.again.slips[0].dissipation, runs.last.slips[0].dissipation, 1e-10) << name;
  EXPECT_EQ(runs.restarted->stokes().n_factorizations(), runs.uninterrupted->stokes().n_factorizations())
      << name;
}

}  // namespace

TEST(SlipRun, NewtonianSlipDropRestartsToRoundOff) {
  expect_exact_restart(slip_case("viscosity_ratio = 3.0\ncapillary_number = 0.2\nslip = 1.0\n", "slip"),
                       "slip_drop");
}

TEST(SlipRun, UcmSlipDropRestartsToRoundOff) {
  expect_exact_restart(slip_case("model = \"ucm\"\npolymer_viscosity = 2.0\nrelaxation_time = 0.2\n"
                                 "capillary_number = 0.2\nslip = 0.5\n",
                                 "ucm_slip"),
                       "ucm_slip_drop");
}

TEST(SlipRun, SlipLowersTheDeformation) {
  // lambda = 3, Ca = 0.2 after 10 steps (t = 0.5): D falls with alpha, as
  // the slip generalisation of Taylor's law says at steady state.
  double previous = 1.0;
  for (double alpha : {0.0, 0.3, 3.0}) {
    const auto config = slip_case(
        fmt::format("viscosity_ratio = 3.0\ncapillary_number = 0.2\nslip = {}\n", alpha), "slip_d");
    simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
    simulation::StepReport r;
    for (int n = 0; n < 10; ++n) r = sim.step();
    std::printf("alpha %.1f: D(t = 0.5) = %.5f\n", alpha, r.objects[0].deformation);
    EXPECT_LT(r.objects[0].deformation, previous) << alpha;
    previous = r.objects[0].deformation;
  }
}

TEST(SlipRun, TheInitialRowHasTheInterfaceArea) {
  // Issue 33: slip.csv's row 0 gave area 0 (timeseries.csv 12.53).
  const auto config = slip_case("capillary_number = 0.1\nslip = 1.0\n", "slip_row0");
  auto meshed = simulation::build_mesh(config);
  simulation::DropSimulation sim(config, std::move(meshed.mesh));
  const auto first = sim.initial_report();
  ASSERT_EQ(first.slips.size(), 1u);
  // The same curved surface by two quadratures (degree 5 here, the
  // tracker's own there): 2e-6 apart at 16 equator nodes.
  EXPECT_NEAR(first.slips[0].area, first.objects[0].area, 1e-5 * first.objects[0].area);
  EXPECT_EQ(first.slips[0].mean_slip_speed, 0.0);
  EXPECT_EQ(first.slips[0].dissipation, 0.0);
}
