// Time-dependent walls ([flow] type) and several objects in one time run.
//
// 1. Without objects the Stokes solution is the wall-driven linear profile
//    u = (gamma_dot(t) y, 0, 0) at every step, whatever the wall history
//    (start-up, cessation, oscillatory): P2 holds it exactly, so round-off.
// 2. A drop under small-amplitude oscillatory shear deforms periodically:
//    D(t) oscillates at twice the imposed frequency (D is blind to the sign of
//    the shear), which locates the imposed frequency in the response.
// 3. Two drops in one time run: each object is tracked and measured, and the
//    mesh is not translated with either (it follows one object only).
#include <cmath>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "softflow/io/case_config.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"
#include "softflow/simulation/case_flow.hpp"
#include "softflow/simulation/drop_simulation.hpp"
#include "softflow/simulation/report_tables.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;

namespace {

io::CaseConfig parse(const std::string& text) { return io::parse_case(text, "time_dependent"); }

/// Max over all velocity dofs of |u_h - gamma_dot(t) y e_x|.
double profile_error(const simulation::DropSimulation& sim, const physics::WallMotion& walls) {
  const auto& dofs = sim.stokes().dofs();
  const auto& u = sim.solution();
  double worst = 0.0;
  for (int d = 0; d < dofs.n_dofs(); ++d) {
    if (dofs.field_of(d) != physics::kVelocityField) continue;
    const auto& x = sim.mesh().nodes[dofs.node_of(d)];
    const double exact = dofs.component_of(d) == 0 ? walls.shear_rate(sim.time()) * x.y() : 0.0;
    worst = std::max(worst, std::abs(u[d] - exact));
  }
  return worst;
}

}  // namespace

TEST(TimeDependentWalls, WithoutObjectsEveryStepIsTheExactLinearProfile) {
  const std::string base =
      "[cell]\nlength = 4.0\nheight = 4.0\nwidth = 4.0\n[mesh]\nfar_size = 1.5\n"
      "[time]\nstep = 0.25\nend = 3.0\n[output]\nfields = false\n";
  for (const std::string flow :
       {"type = \"start_up\"\nshear_rate = 0.5", "type = \"cessation\"\nstop_time = 1.0",
        "type = \"oscillatory\"\nstrain_amplitude = 0.2\nfrequency = 2.0"}) {
    const auto config = parse(base + "[flow]\n" + flow + "\n");
    const auto walls = simulation::wall_motion(config);
    simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
    double worst = 0.0, largest_rate = 0.0;
    for (int n = 0; n < 12; ++n) {
      sim.step();
      worst = std::max(worst, profile_error(sim, walls));
      largest_rate = std::max(largest_rate, std::abs(walls.shear_rate(sim.time())));
    }
    EXPECT_LT(worst, 1e-9 * std::max(1.0, largest_rate)) << flow;
    EXPECT_GT(largest_rate, 0.1) << flow;  // the walls did move
    if (config.flow.type == io::FlowType::cessation) {
      EXPECT_EQ(walls.shear_rate(sim.time()), 0.0);
    }
  }
}

TEST(TimeDependentWalls, ADropUnderOscillatoryShearDeformsAtTheImposedFrequency) {
  // gamma0 = 0.2, omega = 2 pi / 2.5 (period 2.5), Ca at the rate amplitude;
  // a viscous drop (relaxation time ~ Ca (19 lambda + 16)(2 lambda + 3) /
  // (40 (lambda + 1)) ~ 0.1 of the period) follows the shear closely. Run
  // 2 periods and read the period of D(t) from its maxima in the second.
  const double omega = 2.0 * M_PI / 2.5;
  const auto config = parse(fmt::format(
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.2\nfrequency = {}\n"
      "[[objects]]\nviscosity_ratio = 1.0\ncapillary_number = 0.2\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = 0.05\nend = 5.0\n[output]\nfields = false\n",
      omega));
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  std::vector<double> t, d;
  for (int n = 0; n < 100; ++n) {
    const auto r = sim.step();
    t.push_back(r.time);
    d.push_back(r.objects.front().deformation);
  }
  // Local maxima of D after the first period.
  std::vector<double> peaks;
  for (std::size_t i = 1; i + 1 < d.size(); ++i)
    if (t[i] > 2.5 && d[i] > d[i - 1] && d[i] >= d[i + 1]) peaks.push_back(t[i]);
  ASSERT_GE(peaks.size(), 2u) << "D(t) does not oscillate";
  // Two maxima per period of the wall motion (|shear| peaks twice).
  const double spacing = (peaks.back() - peaks.front()) / (peaks.size() - 1);
  EXPECT_NEAR(spacing, 2.5 / 2.0, 0.1);
  const double d_max = *std::max_element(d.begin() + 50, d.end());
  const double d_min = *std::min_element(d.begin() + 50, d.end());
  EXPECT_GT(d_max - d_min, 0.5 * d_max);  // a real oscillation, not noise about a mean
}

TEST(SeveralObjects, TwoDropsRunInTimeEachTrackedAndMeasured) {
  const auto config = parse(
      "[cell]\nlength = 12.0\nheight = 8.0\nwidth = 8.0\n"
      "[[objects]]\ncentre = [-2.5, 1.0, 0.0]\ncapillary_number = 0.2\n"
      "[[objects]]\ncentre = [2.5, -1.0, 0.0]\ncapillary_number = 0.2\nviscosity_ratio = 2.0\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n"
      "[time]\nstep = 0.05\nend = 1.0\n[output]\nfields = false\n");
  simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
  simulation::StepReport r;
  for (int n = 0; n < 6; ++n) r = sim.step();
  ASSERT_EQ(r.objects.size(), 2u);
  for (const auto& o : r.objects) {
    EXPECT_GT(o.deformation, 0.01) << "object " << o.object;
    EXPECT_LT(o.ellipsoid_deviation, 0.05) << "object " << o.object;
  }
  // The drop above the centre plane moves with +x, the one below with -x.
  EXPECT_GT(r.objects[0].centre_velocity.x(), 0.5);
  EXPECT_LT(r.objects[1].centre_velocity.x(), -0.5);
  // Each row of the time series names its object.
  const auto rows = simulation::timeseries_rows(r);
  EXPECT_NE(rows.find(fmt::format("{},{:.10g},1,", r.step, r.time)), std::string::npos);
  EXPECT_NE(rows.find(fmt::format("{},{:.10g},2,", r.step, r.time)), std::string::npos);
}

TEST(TimeDependentWalls, ADropRelaxingAfterCessationIsSecondOrderInTime) {
  // The coarse drop of the regression case, walls stopped at t = 0.5, D at
  // t = 1. Every BDF history restarts at first order at the stop: without
  // that, the stencils spanning the jump made the relaxation first order
  // (differences 8.0e-4, 3.9e-4, 1.9e-4 at dt = 0.05 ... 0.00625); with
  // it, 2.9e-4, 7.2e-5, 1.8e-5 (order 2.02, 2.01).
  const std::string base =
      "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n"
      "[flow]\ntype = \"cessation\"\nstop_time = 0.5\n"
      "[[objects]]\nviscosity_ratio = 1.0\ncapillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 2.0\n[output]\nfields = false\n";
  std::vector<double> d;
  for (double dt : {0.05, 0.025, 0.0125}) {
    const auto config = parse(base + fmt::format("[time]\nstep = {}\nend = 1.0\n", dt));
    simulation::DropSimulation sim(config, simulation::build_mesh(config).mesh);
    simulation::StepReport last;
    for (int n = 0; n < static_cast<int>(std::lround(1.0 / dt)); ++n) last = sim.step();
    EXPECT_NEAR(sim.time(), 1.0, 1e-12);
    d.push_back(last.objects.front().deformation);
  }
  const double order = std::log2((d[0] - d[1]) / (d[1] - d[2]));
  fmt::print("D(t = 1) at dt = 0.05, 0.025, 0.0125: {:.8f} {:.8f} {:.8f}; order {:.2f}\n", d[0], d[1],
             d[2], order);
  EXPECT_GT(order, 1.8);
}
