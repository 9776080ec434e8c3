// No stage of a time step gathers a whole distributed vector (issue 12):
// the Stokes solution stays distributed, the velocity the conformation is
// transported with is read from this rank's rows, and the interface stages
// (tracking, semi-implicit tension, slip measures) read only the interface
// dofs. Checked by counting la::gather_to_all calls, the one way to gather a
// whole vector, over the steps of runs that use every stage: two drops,
// a UCM drop with its log-conformation and DEVSS-G gradient, a slip drop;
// with an adaptive run's in-memory snapshot, from which a step taken back
// is taken again.
// Output and checkpoints (outside the step) still gather, counted too.
//
// Not counted: the mesh motion copies the moved nodes' displacement to every
// rank, because every rank holds the whole mesh (docs/benchmarks/scaling.md).
//
// Runs on 1 rank and, as mpi_rank_local_steps, on 2.
#include <gtest/gtest.h>

#include "softflow/io/case_config.hpp"
#include "softflow/io/checkpoint.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;

namespace {

struct Counts {
  long steps = 0;   // gathers during the steps
  long output = 0;  // gathers of one output + one checkpoint
};

Counts count_gathers(const std::string& objects, const std::string& name,
                     const std::string& solver = "auto") {
  const auto config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n[solver]\ntype = \"" + solver + "\"\n" +
          objects +
          "[mesh]\nequator_nodes = 16\nfar_size = 2.5\n"
          "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n",
      name);
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  Counts counts;
  long before = la::full_gathers();
  for (int n = 0; n < 2; ++n) {  // BDF1, then BDF2 with the semi-implicit tension's w
    const auto report = sim.step();
    EXPECT_EQ(report.step, n + 1) << name;
  }
  // An adaptive run's snapshot before each step, and a step taken back and
  // taken again from it: the same step again (to the solver tolerance: the
  // kept preconditioner differs).
  const auto snapshot = sim.save_step_state();
  const auto first = sim.step();
  sim.restore_step_state(snapshot);
  const auto again = sim.step();
  EXPECT_EQ(again.step, 3) << name;
  for (std::size_t k = 0; k < first.objects.size(); ++k) {
    EXPECT_NEAR(again.objects[k].deformation, first.objects[k].deformation, 1e-8) << name;
    EXPECT_NEAR(again.objects[k].volume, first.objects[k].volume, 1e-8) << name;
  }
  counts.steps = la::full_gathers() - before;
  before = la::full_gathers();
  (void)sim.output_fields();
  io::Checkpoint checkpoint;
  sim.save(checkpoint);
  counts.output = la::full_gathers() - before;
  return counts;
}

const std::string kTwoDrops =
    "[[objects]]\ncentre = [0.0, 1.6, 0.0]\nviscosity_ratio = 1.0\ncapillary_number = 0.2\n"
    "[[objects]]\ncentre = [0.0, -1.6, 0.0]\nviscosity_ratio = 1.0\ncapillary_number = 0.2\n";

}  // namespace

TEST(RankLocalSteps, TwoDropsGatherNothingWhole) {
  const auto counts = count_gathers(kTwoDrops, "two_drops");
  EXPECT_EQ(counts.steps, 0);
  EXPECT_GT(counts.output, 0);  // the counter sees gathers: output writes the whole solution
}

TEST(RankLocalSteps, TwoDropsWithTheIterativeSolverGatherNothingWhole) {
  // The iterative path sets the pressure level after the solve (one reduction).
  const auto counts = count_gathers(kTwoDrops, "two_drops_iterative", "iterative");
  EXPECT_EQ(counts.steps, 0);
  EXPECT_GT(counts.output, 0);
}

TEST(RankLocalSteps, UcmDropGathersNothingWhole) {
  const auto counts = count_gathers(
      "[[objects]]\nmodel = \"ucm\"\npolymer_viscosity = 1.0\nrelaxation_time = 0.1\n"
      "capillary_number = 0.1\n",
      "ucm_drop");
  EXPECT_EQ(counts.steps, 0);
  EXPECT_GT(counts.output, 0);
}

TEST(RankLocalSteps, SlipDropGathersNothingWhole) {
  const auto counts = count_gathers(
      "[[objects]]\nviscosity_ratio = 3.0\ncapillary_number = 0.2\nslip = 1.0\n", "slip_drop");
  EXPECT_EQ(counts.steps, 0);
  EXPECT_GT(counts.output, 0);
}
