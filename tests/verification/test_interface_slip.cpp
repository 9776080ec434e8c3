// Navier slip through collocated multipliers (physics/stokes/interface_slip.hpp):
// one Stokes solve around a spherical slip drop in shear against the exact
// instantaneous field, the discrete energy balance, and alpha = 0 against
// the no-slip system.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "support/verification/slip_drop.hpp"

using softflow::verification::slip_drop_in_shear;
using softflow::verification::SlipDropResult;

namespace {
double slope(double e_coarse, double e_fine, double h_coarse, double h_fine) {
  return std::log(e_coarse / e_fine) / std::log(h_coarse / h_fine);
}
void print(const char* label, double lambda, double alpha, const SlipDropResult& r) {
  std::printf("%s lambda %.1f alpha %.1f N %2d unknowns %6d |u-u_h| %.3e |p-p_h| %.3e "
              "|jump-exact| %.3e (|jump| %.3e) slip diss. %.5e (exact %.5e, Navier %.5e)\n",
              label, lambda, alpha, r.equator_nodes, r.unknowns, r.velocity_l2, r.pressure_l2,
              r.jump_l2, r.exact_jump_l2, r.slip_dissipation, r.exact_slip_dissipation,
              r.navier_dissipation);
}
}  // namespace

TEST(InterfaceSlip, ZeroSlipGivesTheNoSlipSolution) {
  // The two paths solve the same discrete problem: u_m = u_d at every node.
  const auto slip = slip_drop_in_shear(2.0, 0.0, 0.5, 16, true);
  const auto plain = slip_drop_in_shear(2.0, 0.0, 0.5, 16, false);
  print("slip path", 2.0, 0.0, slip);
  print("no-slip  ", 2.0, 0.0, plain);
  EXPECT_NEAR(slip.velocity_l2, plain.velocity_l2, 1e-9 * plain.velocity_l2);
  EXPECT_NEAR(slip.pressure_l2, plain.pressure_l2, 1e-8 * plain.pressure_l2);
  EXPECT_NEAR(slip.viscous_dissipation, plain.viscous_dissipation, 1e-9 * plain.viscous_dissipation);
  EXPECT_LT(slip.jump_l2, 1e-10);
  EXPECT_LT(std::abs(slip.slip_dissipation), 1e-10 * slip.viscous_dissipation);
}

TEST(InterfaceSlip, ViscousPlusSlipDissipationEqualsTheWorkOfTheBoundary) {
  // No tension: the power the boundary puts in leaves through the viscous
  // and the slip dissipation; the slip part is a sizeable share at alpha = 1.
  for (double alpha : {0.1, 1.0}) {
    const auto r = slip_drop_in_shear(1.0, alpha, 0.0, 16);
    print("energy", 1.0, alpha, r);
    std::printf("  viscous %.8e + slip %.8e = %.8e vs boundary work %.8e (tension work %.1e)\n",
                r.viscous_dissipation, r.slip_dissipation, r.viscous_dissipation + r.slip_dissipation,
                r.boundary_work, r.tension_work);
    EXPECT_GT(r.slip_dissipation, 0.0);
    EXPECT_NEAR(r.viscous_dissipation + r.slip_dissipation, r.boundary_work,
                1e-8 * r.boundary_work);
    // The Navier law ties the dissipation to the multipliers (tangential part).
    EXPECT_NEAR(r.slip_dissipation, r.navier_dissipation, 0.05 * r.navier_dissipation);
  }
}

TEST(InterfaceSlip, WithTensionTheBalanceIncludesTheTensionWork) {
  const auto r = slip_drop_in_shear(1.0, 1.0, 0.5, 16);
  EXPECT_NEAR(r.viscous_dissipation + r.slip_dissipation, r.boundary_work + r.tension_work,
              1e-8 * r.boundary_work);
}

TEST(InterfaceSlip, IterativeSolverAgreesWithTheDirectOne) {
  // FGMRES + Schur fieldsplit with the multipliers beside the pressure
  // (their Schur complement estimated from A's diagonal): the same solution.
  for (double lambda : {0.1, 10.0}) {
    const auto direct = slip_drop_in_shear(lambda, 1.0, 0.5, 16);
    const auto iterative = slip_drop_in_shear(lambda, 1.0, 0.5, 16, true, true);
    std::printf("lambda %.1f: iterative %d iterations; |u-u_h| %.9e vs direct %.9e; slip diss. %.9e vs %.9e\n",
                lambda, iterative.iterations, iterative.velocity_l2, direct.velocity_l2,
                iterative.slip_dissipation, direct.slip_dissipation);
    EXPECT_NEAR(iterative.velocity_l2, direct.velocity_l2, 1e-6 * direct.velocity_l2);
    EXPECT_NEAR(iterative.slip_dissipation, direct.slip_dissipation, 1e-6 * direct.slip_dissipation);
    EXPECT_NEAR(iterative.viscous_dissipation, direct.viscous_dissipation, 1e-7 * direct.viscous_dissipation);
  }
}

class SlipDropInShear : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(SlipDropInShear, ApproachesTheExactSlipField) {
  // Two coarse meshes (N = 16, 24), as DropInShear for the no-slip drop:
  // errors fall, the slip jump and dissipation approach the exact ones.
  const auto [lambda, alpha] = GetParam();
  std::vector<SlipDropResult> runs;
  for (int n : {16, 24}) {
    runs.push_back(slip_drop_in_shear(lambda, alpha, 0.5, n));
    print("exact", lambda, alpha, runs.back());
  }
  const double su = slope(runs[0].velocity_l2, runs[1].velocity_l2, runs[0].h0, runs[1].h0);
  const double sp = slope(runs[0].pressure_l2, runs[1].pressure_l2, runs[0].h0, runs[1].h0);
  const double sj = slope(runs[0].jump_l2, runs[1].jump_l2, runs[0].h0, runs[1].h0);
  std::printf("lambda %.1f alpha %.1f slopes (N 16 -> 24): velocity %.2f pressure %.2f jump %.2f\n",
              lambda, alpha, su, sp, sj);
  EXPECT_GT(su, 1.5);
  EXPECT_GT(sp, 1.0);
  EXPECT_GT(sj, 1.5);
  const auto& fine = runs.back();
  EXPECT_LT(fine.jump_l2, 0.05 * fine.exact_jump_l2);
  EXPECT_NEAR(fine.slip_dissipation, fine.exact_slip_dissipation, 0.03 * fine.exact_slip_dissipation);
}

INSTANTIATE_TEST_SUITE_P(
    SlipAndViscosityRatios, SlipDropInShear,
    ::testing::Values(std::pair{1.0, 0.1}, std::pair{1.0, 1.0}, std::pair{1.0, 10.0},
                      std::pair{0.5, 1.0}, std::pair{5.0, 1.0}));
