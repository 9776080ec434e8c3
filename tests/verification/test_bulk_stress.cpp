// The bulk stress of eq. 4.1 through the bulk_stress module (bulk_stress.csv,
// summary.json's final_bulk_stress), against exact values:
//  - a pure matrix in oscillatory shear: plane Couette flow is in the P2
//    space, so over any cube (its faces cutting the elements anyhow) the
//    averaged shear stress is eta_m times the wall shear rate and the normal
//    stress differences vanish, to round-off;
// (A single drop in a cube does not give Taylor's dilute stresslet over the
// cube's volume: the disturbance's far field carries a share of it through the
// cube's faces; docs/emulsions.md.)
#include <cmath>
#include <filesystem>
#include <string>

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
