// The bulk stress of eq. 4.1 through the bulk_stress module (bulk_stress.csv,
// summary.json's final_bulk_stress), against exact values:
//  - a pure matrix in oscillatory shear: plane Couette flow is in the P2
//    space, so over any cube (its faces cutting the elements anyhow) the
//    averaged shear stress is eta_m times the wall shear rate and the normal
//    stress differences vanish, to round-off;
//  - a drop just set in shear from a sphere: its stresslet S_xy (the
//    stresslet_xy column) is that of a viscous sphere without tension (a
//    sphere's tension force is isotropic: it has not begun to restore
//    anything), (5/2) (lambda - 1) / (lambda + 3/2) eta gamma_dot V, the
//    high-frequency limit of Oldroyd's emulsion (docs/emulsions.md); at
//    second order in the mesh size;
//  - the same with Navier slip: Oldroyd's high-frequency limit with slip
//    (appendix B as SPEC §9 corrects it), which the slip term of eq. 4.1
//    brings the stresslet to (without it S would be twice as large).
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <mpi.h>

#include "softflow/io/case_config.hpp"
#include "softflow/simulation/drop_run.hpp"
#include "softflow/simulation/run_support.hpp"

using namespace softflow;
namespace fs = std::filesystem;

namespace {

nlohmann::json run(const std::string& text, const std::string& name) {
  const fs::path directory = fs::temp_directory_path() / ("softflow_bulk_stress_" + name);
  const auto config = io::parse_case(
      text + "[output]\nfields = false\ndirectory = \"" + directory.string() + "\"\n", name);
  simulation::RunOptions options;
  options.quiet = true;
  options.overwrite = true;
  auto summary = simulation::run_drop_case(config, options, simulation::build_mesh(config));
  fs::remove_all(directory);
  return summary;
}

bool root() {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank == 0;
}

}  // namespace

TEST(BulkStress, PureMatrixInOscillatoryShearIsViscosityTimesWallShearRate) {
  // gamma = 0.1, omega = 2: u_w = H/2 gamma omega sin(omega t); 3 steps of 0.05.
  for (const double side : {2.0, 3.3}) {
    const auto s = run("[cell]\nlength = 4.0\nheight = 4.0\nwidth = 4.0\n"
                       "[matrix]\nviscosity = 1.5\n"
                       "[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.1\nfrequency = 2.0\n"
                       "[mesh]\nfar_size = 0.9\n[time]\nstep = 0.05\nend = 0.15\n"
                       "[bulk_stress]\nbox_side = " + std::to_string(side) + "\n",
                       "matrix");
    if (!root()) continue;
    const auto& b = s.at("final_bulk_stress");
    const double t = s.at("time"), wall_rate = 0.1 * 2.0 * std::sin(2.0 * t);
    ASSERT_GT(std::abs(wall_rate), 0.05);
    EXPECT_NEAR(b.at("shear_rate").get<double>(), wall_rate, 1e-10 * std::abs(wall_rate)) << side;
    EXPECT_NEAR(b.at("sigma_xy").get<double>(), 1.5 * wall_rate, 1e-10 * std::abs(wall_rate)) << side;
    EXPECT_NEAR(b.at("viscosity").get<double>(), 1.5, 1e-9) << side;
    EXPECT_NEAR(b.at("N1").get<double>(), 0.0, 1e-10) << side;
    EXPECT_NEAR(b.at("N2").get<double>(), 0.0, 1e-10) << side;
    EXPECT_NEAR(b.at("sigma_xz").get<double>(), 0.0, 1e-10) << side;
    EXPECT_EQ(b.at("objects").get<int>(), 0);
    EXPECT_EQ(b.at("phi").get<double>(), 0.0);
  }
}

TEST(BulkStress, PureMatrixHasTheModuliOfANewtonianLiquid) {
  // One period (flow.periods = 1: time.step 0.1 shortened to pi / 32): the fit of eqs.
  // 4.6-4.7 over it gives G' = 0 and G'' = eta omega, the shear rate the walls', to round-off.
  const auto s = run("[cell]\nlength = 4.0\nheight = 4.0\nwidth = 4.0\n"
                     "[matrix]\nviscosity = 1.5\n"
                     "[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.1\nfrequency = 2.0\n"
                     "periods = 1\n[mesh]\nfar_size = 0.9\n[time]\nstep = 0.1\n"
                     "[bulk_stress]\nbox_side = 3.3\nfit_periods = 1\n",
                     "matrix_moduli");
  if (!root()) return;
  EXPECT_NEAR(s.at("time").get<double>(), std::numbers::pi, 1e-12);
  EXPECT_EQ(s.at("steps").get<int>(), 32);
  const auto& m = s.at("moduli");
  EXPECT_EQ(m.at("samples").get<int>(), 32);
  EXPECT_NEAR(m.at("G_storage").get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(m.at("G_loss").get<double>(), 1.5 * 2.0, 1e-12);
  EXPECT_NEAR(m.at("G_loss_over_eta_m_omega").get<double>(), 1.0, 1e-12);
  EXPECT_NEAR(m.at("shear_rate_amplitude").get<double>(), 0.2, 1e-12);
  EXPECT_NEAR(m.at("shear_rate_phase_vs_wall").get<double>(), 0.0, 1e-12);
  EXPECT_LT(m.at("fit_residual_stress").get<double>(), 1e-12);
  EXPECT_FALSE(m.contains("oldroyd"));  // no drops
}

TEST(BulkStress, ADropSetInShearHasTheStressletOfAViscousSphereWithoutTension) {
  // lambda = 3, R = 1, one step of 1e-3 from the sphere, cell 24 x 16 x 24
  // (blockage 1/8: the walls move S by ~0.1 %, measured against 12 x 8 x 12).
  const double lambda = 3.0, volume = 4.0 / 3.0 * std::numbers::pi;
  const double exact = 2.5 * (lambda - 1.0) / (lambda + 1.5) * volume;  // eta = gamma_dot = 1
  std::vector<double> stresslet, size;
  for (const int nodes : {20, 28}) {
    const auto s = run("[cell]\nlength = 24.0\nheight = 16.0\nwidth = 24.0\n"
                       "[[objects]]\nradius = 1.0\nviscosity_ratio = 3.0\ncapillary_number = 0.05\n"
                       "[mesh]\nequator_nodes = " + std::to_string(nodes) + "\n"
                       "[time]\nstep = 0.001\nend = 0.001\n[bulk_stress]\nbox_side = 4.0\n",
                       "drop" + std::to_string(nodes));
    if (!root()) return;
    stresslet.push_back(s.at("final_bulk_stress").at("stresslet_xy").get<double>());
    size.push_back(1.0 / s.at("mesh").at("equator_nodes").get<double>());
  }
  // Measured: +3.3 % at 20 nodes, +1.5 % at 28; the two levels extrapolated
  // at order 2 within 0.4 % of the theory.
  const double e20 = stresslet[0] / exact - 1.0, e28 = stresslet[1] / exact - 1.0;
  EXPECT_LT(std::abs(e28), std::abs(e20));
  const double r = std::pow(size[1] / size[0], 2.0);
  const double extrapolated = stresslet[1] + (stresslet[1] - stresslet[0]) * r / (1.0 - r);
  EXPECT_NEAR(extrapolated / exact, 1.0, 0.01) << "S_xy at 20 and 28 nodes: " << stresslet[0] << ", "
                                               << stresslet[1] << "; exact " << exact;
}

TEST(BulkStress, ADropWithSlipSetInShearHasOldroydsHighFrequencyStresslet) {
  // lambda = 3, alpha = 1: c = [5 (l - 1)(19 l + 16) + 10 a l (19 l - 40)] /
  // [(19 l + 16)(2 l + 3) + 10 a l (19 l + 24)] = 1240 / 3087 (oldroyd_dilute_coefficient
  // at omega -> oo), against 1.1111 without slip: the slip term of eq. 4.1 carries the difference.
  const double volume = 4.0 / 3.0 * std::numbers::pi, exact = 1240.0 / 3087.0 * volume;
  std::vector<double> error;
  for (const int nodes : {20, 28, 40}) {
    const auto s = run("[cell]\nlength = 24.0\nheight = 16.0\nwidth = 24.0\n"
                       "[[objects]]\nradius = 1.0\nviscosity_ratio = 3.0\ncapillary_number = 0.05\n"
                       "slip = 1.0\n[mesh]\nequator_nodes = " + std::to_string(nodes) + "\n"
                       "[time]\nstep = 0.001\nend = 0.001\n[bulk_stress]\nbox_side = 4.0\n",
                       "slip" + std::to_string(nodes));
    if (!root()) return;
    const auto& b = s.at("final_bulk_stress");
    error.push_back(b.at("stresslet_xy").get<double>() / exact - 1.0);
    // The slip term is as large as the stresslet itself here (measured: -1.05 of it).
    EXPECT_LT(b.at("slip_xy").get<double>() * 64.0, -0.5 * exact) << nodes;
  }
  // Measured: +8.4 %, +2.6 %, +0.10 % (meshed 21, 29, 42 equator nodes; observed order ~2.9).
  EXPECT_LT(std::abs(error[1]), std::abs(error[0]));
  EXPECT_LT(std::abs(error[2]), std::abs(error[1]));
  EXPECT_LT(std::abs(error[2]), 0.01) << "errors " << error[0] << ", " << error[1] << ", " << error[2];
}
