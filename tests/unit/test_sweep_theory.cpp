// The sweep's theory curve: Taylor / Chaffey-Brenner at each case's own capillary number, also
// when the case gives the interfacial tension instead.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/io/sweep_case.hpp"
#include "softflow/simulation/sweep.hpp"

namespace softflow::simulation {
namespace {

/// Rows of a CSV text without its header, split at commas.
std::vector<std::vector<std::string>> rows(const std::string& csv) {
  std::vector<std::vector<std::string>> out;
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // header
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    std::string cell;
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    out.push_back(cells);
  }
  return out;
}

TEST(SweepTheory, ViscosityRatioSweepWithInterfacialTensionUsesItsCapillaryNumber) {
  // Ca = eta_m gamma_dot R / Gamma = 2 * 0.5 * 1.5 / 3 = 0.5, not the default 0.1.
  const io::Sweep sweep = io::expand_sweep(
      "[matrix]\nviscosity = 2.0\n[flow]\nshear_rate = 0.5\n"
      "[[objects]]\nradius = 1.5\ninterfacial_tension = 3.0\nviscosity_ratio = [0.5, 2.0]\n",
      "s.toml");
  ASSERT_EQ(sweep.cases.size(), 2u);
  EXPECT_DOUBLE_EQ(io::capillary_number(sweep.cases[0].config, sweep.cases[0].config.objects[0]),
                   0.5);
  const auto table = rows(theory_curve_csv(sweep));
  ASSERT_GT(table.size(), 10u);
  for (const auto& row : table) {
    ASSERT_EQ(row.size(), 4u);
    const double lambda = std::stod(row[1]);
    EXPECT_NEAR(std::stod(row[2]), analysis::theory::taylor_deformation(lambda, 0.5), 1e-7);
    EXPECT_NEAR(std::stod(row[3]), analysis::theory::chaffey_brenner_angle_deg(lambda, 0.5),
                1e-5);
  }
}

TEST(SweepTheory, CapillaryNumberSweepRunsAlongCa) {
  const io::Sweep sweep = io::expand_sweep(
      "[[objects]]\nviscosity_ratio = 3.0\ncapillary_number = [0.1, 0.2]\n", "s.toml");
  const auto table = rows(theory_curve_csv(sweep));
  ASSERT_FALSE(table.empty());
  const auto& last = table.back();
  EXPECT_NEAR(std::stod(last[1]), 0.22, 1e-12);  // 10 % past the largest Ca
  EXPECT_NEAR(std::stod(last[2]), analysis::theory::taylor_deformation(3.0, 0.22), 1e-7);
}

TEST(SweepTheory, NoCurveAlongOtherParameters) {
  EXPECT_EQ(theory_curve_csv(io::expand_sweep("[time]\nstep = [0.1, 0.05]\n[[objects]]\n", "s.toml")),
            "");
}

}  // namespace
}  // namespace softflow::simulation

namespace softflow::simulation {
namespace {

TEST(SweepExitCode, CompleteUnlessACaseWasInterruptedOrNeverRan) {
  // Issue 33: a stop request after the last case started, every case then
  // completed: the sweep is complete (it exited 5).
  EXPECT_EQ(sweep_exit_code({0, 0, 0}), 0);
  EXPECT_EQ(sweep_exit_code({0, 5, 0}), 5);
  EXPECT_EQ(sweep_exit_code({0, -1}), 5);      // never started
  EXPECT_EQ(sweep_exit_code({5, 3, 0}), 3);    // a failure outranks an interruption
  EXPECT_EQ(sweep_exit_code({0, -2, 2}), 4);   // failed in an earlier sweep: first
}

}  // namespace
}  // namespace softflow::simulation
