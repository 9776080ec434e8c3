// The first (BDF1) step of a translating object (issue 35, item 6: a
// migrating particle must keep its volume). The first predictor is x_1 = x_0
// (eq. 2.47), so the centre velocity U of eqs. 2.51-2.52 from the predicted
// surface is 0 there, and the corrector (eq. 2.48) moved the nodes with
// (u.n) n only: a drop carried along at u ~ 1 lost the tangential part of
// its translation, -0.92 % of its volume at dt = 0.1 (second order in u dt:
// -0.28 % at 0.05, -0.08 % at 0.025), dipped by 5.7e-3 R in y, and BDF2's
// next step overshot to +1.08 %, which stopped the run (time.max_volume_drift
// 1 %). The tracker now takes U at a BDF1 step from the flow itself,
// dX/dt = int_S (x - X)(u.n) ds / V.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
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

struct Row {
  double t, yc, volume;
};

// timeseries.csv: step, t, object, D, theta_deg, L, B, W, xc, yc, zc, uc, vc, wc, volume, ...
std::vector<Row> series(const fs::path& directory) {
  std::ifstream in(directory / "timeseries.csv");
  std::string line;
  std::getline(in, line);
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> v;
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) v.push_back(field);
    rows.push_back({std::stod(v.at(1)), std::stod(v.at(9)), std::stod(v.at(14))});
  }
  return rows;
}

}  // namespace

TEST(FirstStepTranslation, ADropCarriedByTheShearKeepsItsVolumeAndItsStreamline) {
  const fs::path directory = fs::temp_directory_path() / "softflow_first_step_translation";
  const auto config = io::parse_case(
      "[cell]\nlength = 8.0\nheight = 5.0\nwidth = 8.0\n"
      "[[objects]]\ncentre = [0.0, 1.0, 0.0]\ncapillary_number = 0.1\n"
      "[mesh]\nequator_nodes = 16\nfar_size = 1.5\n"
      "[time]\nstep = 0.1\nend = 0.2\n"
      "[output]\nfields = false\ndirectory = \"" + directory.string() + "\"\n",
      "translating");
  simulation::RunOptions options;
  options.quiet = true;
  options.overwrite = true;
  // Before: an AccuracyError at step 2 (volume +1.08 %).
  ASSERT_NO_THROW(simulation::run_drop_case(config, options, simulation::build_mesh(config)));
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) return;
  const auto rows = series(directory);
  ASSERT_EQ(rows.size(), 3u);
  // Measured after: -0.26 % and -0.19 %, the first step's change of a drop
  // that does not translate (-0.07 % at dt = 0.05 for the centred drop of
  // test_centred_drift) grown with dt; before, -0.92 % and +1.08 %.
  for (std::size_t i = 1; i < rows.size(); ++i)
    EXPECT_LT(std::abs(rows[i].volume / rows[0].volume - 1.0), 4e-3) << "t = " << rows[i].t;
  // The centre stays on its streamline (measured 4.5e-4; before, 5.7e-3).
  EXPECT_LT(std::abs(rows[1].yc - rows[0].yc), 1e-3);
  fs::remove_all(directory);
}
