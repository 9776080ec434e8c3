// A neo-Hookean particle's shape converges as the time step falls
// (docs/viscoelastic.md, "The SUPG parameter and the time step").
//
// With the thesis's steady SUPG parameter tau = h / (2 |u - u_m|) in the
// particle, halving dt from 0.01 to 0.005 to 0.0025 on this mesh changed
// theta at t = 0.6 by +0.031 and then +0.047 deg, and D by -5.8e-5 and then
// -9.7e-5: the differences grew, and kept growing in time. With tau limited
// by the step (the default in elastic solids, fem::transient_supg_tau) they
// shrink: +0.021, +0.011 deg and -1.24e-4, -8.5e-5. The test asks only
// that each halving change D and theta less than the one before; the
// steady parameter fails it by a factor 1.5-1.7, the default passes it by
// 1.4-1.9. Node relocation is off: it moves nodes at steps that depend on
// dt and would add a perturbation of its own (16 nodes keep min quality
// 0.025 to t = 0.6 without it).
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;

namespace {

simulation::ObjectState particle_at_end(double dt) {
  const double end = 0.6;
  const auto config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\nmodel = \"neo_hookean\"\nelastic_capillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 1.0\n"
      "[time]\nrelocation_quality = 0.0\nstep = " +
          std::to_string(dt) + "\nend = 0.6\n[output]\nfields = false\n",
      "particle_time_step");
  simulation::DropSimulation run(config, simulation::build_mesh(config).mesh);
  const int steps = static_cast<int>(std::lround(end / dt));
  simulation::StepReport report;
  for (int n = 1; n <= steps; ++n) report = run.step();
  EXPECT_NEAR(report.time, end, 1e-9);
  return report.objects.front();
}

}  // namespace

TEST(ElasticParticleTimeStepSlow, ShapeChangesLessAtEveryHalvingOfTheStep) {
  const auto coarse = particle_at_end(0.01), medium = particle_at_end(0.005),
             fine = particle_at_end(0.0025);
  const double d1 = medium.deformation - coarse.deformation;
  const double d2 = fine.deformation - medium.deformation;
  const double t1 = medium.theta_deg - coarse.theta_deg;
  const double t2 = fine.theta_deg - medium.theta_deg;
  EXPECT_LT(std::abs(d2), std::abs(d1))
      << "D: " << coarse.deformation << " " << medium.deformation << " " << fine.deformation;
  EXPECT_LT(std::abs(t2), std::abs(t1))
      << "theta: " << coarse.theta_deg << " " << medium.theta_deg << " " << fine.theta_deg;
}
