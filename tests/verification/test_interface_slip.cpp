// Navier slip through collocated multipliers (physics/stokes/interface_slip.hpp):
// one Stokes solve around a spherical slip drop in shear against the exact
// instantaneous field, the discrete energy balance, and alpha = 0 against
// the no-slip system.
#include <cmath>
#include <cstdio>
#include <limits>
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
    // The Navier law ties the dissipation to the multipliers (tangential
    // part): the constraint makes it alpha |(T lambda)_h|^2 with the nodes'
    // tangent planes; navier_dissipation projects on the surface's own
    // normal instead (measured 2.4e-4 and 2.8e-4 apart; the collocated
    // constraint of before: 5 %).
    EXPECT_NEAR(r.slip_dissipation, r.navier_dissipation, 1e-3 * r.navier_dissipation);
  }
}

TEST(InterfaceSlip, WithTensionTheBalanceIncludesTheTensionWork) {
  const auto r = slip_drop_in_shear(1.0, 1.0, 0.5, 16);
  EXPECT_NEAR(r.viscous_dissipation + r.slip_dissipation, r.boundary_work + r.tension_work,
              1e-8 * r.boundary_work);
}

TEST(InterfaceSlip, IterativeSolverAgreesWithTheDirectOne) {
  // GMRES + Schur fieldsplit with the multipliers beside the pressure
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

double relative(double a, double b) { return std::abs(a / b - 1.0); }

/// Two solves on meshes with `coarse` and `fine` equator nodes: observed
/// slopes of the velocity, pressure and jump errors, and the fine solve.
struct Rates {
  double velocity = 0.0, pressure = 0.0, jump = 0.0, dissipation = 0.0;
  SlipDropResult fine;
};

Rates observed_rates(double lambda, double alpha, int coarse, int fine) {
  const auto a = slip_drop_in_shear(lambda, alpha, 0.5, coarse);
  const auto b = slip_drop_in_shear(lambda, alpha, 0.5, fine);
  print("exact", lambda, alpha, a);
  print("exact", lambda, alpha, b);
  Rates r{slope(a.velocity_l2, b.velocity_l2, a.h0, b.h0),
          slope(a.pressure_l2, b.pressure_l2, a.h0, b.h0), slope(a.jump_l2, b.jump_l2, a.h0, b.h0),
          slope(relative(a.slip_dissipation, a.exact_slip_dissipation),
                relative(b.slip_dissipation, b.exact_slip_dissipation), a.h0, b.h0),
          b};
  std::printf("lambda %.1f alpha %.1f slopes (N %d -> %d): velocity %.2f pressure %.2f jump %.2f "
              "slip dissipation %.2f\n",
              lambda, alpha, coarse, fine, r.velocity, r.pressure, r.jump, r.dissipation);
  return r;
}

class SlipDropInShear : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(SlipDropInShear, ApproachesTheExactSlipField) {
  // N = 24 -> 32 (about 4 s per case). N = 16 is pre-asymptotic (measured
  // slopes 16 -> 24: velocity 1.4-2.2, pressure 0.6-1.1, as for the no-slip
  // drop); from 24 on the rates are those of SlipDropInShearSlow below.
  const auto [lambda, alpha] = GetParam();
  const auto r = observed_rates(lambda, alpha, 24, 32);
  EXPECT_GT(r.velocity, 2.3);
  EXPECT_GT(r.pressure, 1.6);
  EXPECT_GT(r.jump, 1.9);
  const auto& fine = r.fine;
  EXPECT_LT(fine.jump_l2, 0.1 * fine.exact_jump_l2);
  // The slip dissipation alpha |(T lambda)_h|^2 converges from below at
  // second order (measured 24 -> 32: slopes 2.3-2.6, 5-7 % off at N = 32).
  EXPECT_GT(r.dissipation, 1.8);
  EXPECT_LT(relative(fine.slip_dissipation, fine.exact_slip_dissipation), 0.1);
}

INSTANTIATE_TEST_SUITE_P(
    SlipAndViscosityRatios, SlipDropInShear,
    ::testing::Values(std::pair{1.0, 0.1}, std::pair{1.0, 1.0}, std::pair{1.0, 10.0},
                      std::pair{0.5, 1.0}, std::pair{5.0, 1.0}));

// Meshes up to N = 48 (54k unknowns): label slow (tests/README.md).
class SlipDropInShearSlow : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(SlipDropInShearSlow, RatesOfTheTaylorHoodElement) {
  // Measured slopes 32 -> 48 over the nine alpha x lambda pairs of the
  // issue: velocity L2 2.66-3.11 (the no-slip drop's P2 interpolant
  // converges at ~2.75 on these graded meshes), pressure 1.82-1.93, jump
  // 2.1-3.5 (2.1-2.2 at alpha = 0.1 with lambda != 1: the collocated law
  // reads the traction (O(h^2) at nodes) through nodal normals (O(h^2)),
  // so 2 is the rate to expect). The slip dissipation of the symmetric
  // coupling (issue 33) converges at slopes 2.2-3.1, within 2.1 % at N = 48.
  const auto [lambda, alpha] = GetParam();
  const auto r = observed_rates(lambda, alpha, 32, 48);
  EXPECT_GT(r.velocity, 2.5);
  EXPECT_GT(r.pressure, 1.7);
  EXPECT_GT(r.jump, 1.9);
  EXPECT_GT(r.dissipation, 1.9);
  EXPECT_LT(relative(r.fine.slip_dissipation, r.fine.exact_slip_dissipation), 0.03);
}

INSTANTIATE_TEST_SUITE_P(
    AllPairs, SlipDropInShearSlow,
    ::testing::Values(std::pair{0.5, 0.1}, std::pair{0.5, 1.0}, std::pair{0.5, 10.0},
                      std::pair{1.0, 0.1}, std::pair{1.0, 1.0}, std::pair{1.0, 10.0},
                      std::pair{5.0, 0.1}, std::pair{5.0, 1.0}, std::pair{5.0, 10.0}));

// Large slip (issue 33). The inside of a spherical drop may turn rigidly
// at no viscous cost: only the slip law, with weight 1 / alpha, sets its
// rotation. The earlier collocated constraint forced that rotation through
// its inconsistency with a weight alpha (N = 16, alpha = 1e3: velocity
// error 7.96 against 0.067 at alpha = 10, slip dissipation -0.127); the
// symmetric coupling cannot (docs/validation/slip_large_alpha.md).

TEST(InterfaceSlipLarge, DissipationIsNeverNegativeAndTheEnergyBalances) {
  for (double alpha : {1e3, 1e6, std::numeric_limits<double>::infinity()}) {
    const auto r = slip_drop_in_shear(1.0, alpha, 0.0, 16);
    print("large", 1.0, alpha, r);
    EXPECT_GE(r.slip_dissipation, -1e-12 * r.viscous_dissipation) << alpha;
    EXPECT_NEAR(r.viscous_dissipation + r.slip_dissipation, r.boundary_work,
                1e-8 * r.boundary_work) << alpha;
  }
}

TEST(InterfaceSlipLarge, FreeSlipCarriesNoTangentialTraction) {
  // alpha = inf: (T lambda)_h = 0, so nothing is dissipated at the interface.
  const auto r = slip_drop_in_shear(1.0, std::numeric_limits<double>::infinity(), 0.0, 16);
  EXPECT_LT(std::abs(r.slip_dissipation), 1e-12 * r.viscous_dissipation);
  EXPECT_NEAR(r.viscous_dissipation, r.boundary_work, 1e-8 * r.boundary_work);
}

TEST(InterfaceSlipLarge, AThousandfoldSlipIsAsAccurateAsAModerateOne) {
  // N = 32: alpha = 1e3 against the exact field, beside alpha = 10 on the
  // same mesh (measured: velocity 1.88e-2 vs 1.53e-2, slip velocity 4.6 %
  // vs 3.8 %; the collocated constraint gave 0.29 and 72 %).
  const auto moderate = slip_drop_in_shear(1.0, 10.0, 0.0, 32);
  const auto large = slip_drop_in_shear(1.0, 1e3, 0.0, 32);
  print("moderate", 1.0, 10.0, moderate);
  print("large", 1.0, 1e3, large);
  EXPECT_LT(large.velocity_l2, 1.5 * moderate.velocity_l2);
  EXPECT_LT(large.jump_l2, 0.06 * large.exact_jump_l2);
  EXPECT_LT(relative(large.slip_dissipation, large.exact_slip_dissipation), 0.1);
}
