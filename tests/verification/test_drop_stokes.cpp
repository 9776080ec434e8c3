// Two-phase Stokes around a spherical drop meshed by gmsh: the exact
// instantaneous field in shear for several viscosity ratios, and the static
// drop (Laplace jump, spurious currents).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/la/saddle_point_solver.hpp"
#include "support/verification/drop_cases.hpp"

using namespace softflow;

namespace {
double slope(double e_coarse, double e_fine, double h_coarse, double h_fine) {
  return std::log(e_coarse / e_fine) / std::log(h_coarse / h_fine);
}
}  // namespace

class DropInShear : public ::testing::TestWithParam<double> {};

TEST_P(DropInShear, CoarseMeshesApproachTheExactField) {
  // The default suite's version of DropInShearSlow below, at N = 16 and 24
  // (about 1 s per viscosity ratio). Still pre-asymptotic for lambda != 1
  // (measured slopes: velocity 1.7-2.6, pressure 1.2-2.1), so the bounds
  // only catch a broken solve or coupling: an error that does not fall, or
  // a Laplace jump off by more than 0.5 %.
  const double lambda = GetParam(), gamma = 0.5;
  std::vector<verification::DropSolveResult> runs;
  for (int n : {16, 24}) {
    runs.push_back(verification::drop_in_shear(lambda, gamma, n));
    const auto& r = runs.back();
    std::printf("lambda %.1f  N %2d  unknowns %7d  |u-u_h| %.3e  |p-p_h|/const %.3e  jump %.6f (exact %.1f)\n",
                lambda, n, r.unknowns, r.velocity_l2, r.pressure_l2, r.pressure_jump,
                r.exact_pressure_jump);
  }
  const double su = slope(runs[0].velocity_l2, runs[1].velocity_l2, runs[0].h0, runs[1].h0);
  const double sp = slope(runs[0].pressure_l2, runs[1].pressure_l2, runs[0].h0, runs[1].h0);
  std::printf("lambda %.1f slopes (N 16 -> 24): velocity %.2f  pressure %.2f\n", lambda, su, sp);
  EXPECT_GT(su, 1.5);
  EXPECT_GT(sp, 1.0);
  EXPECT_LT(std::abs(runs[1].pressure_jump - runs[1].exact_pressure_jump), 0.005 * runs[1].exact_pressure_jump);
}

INSTANTIATE_TEST_SUITE_P(ViscosityRatios, DropInShear, ::testing::Values(0.5, 1.0, 5.0));

// Meshes up to N = 48: label slow (tests/README.md).
class DropInShearSlow : public ::testing::TestWithParam<double> {};

TEST_P(DropInShearSlow, InstantaneousExactFieldConvergesUnderRefinement) {
  // Gamma = 0.5: Laplace jump 1 on R = 1. Expected asymptotic slopes 3
  // (velocity L2) and 2 (pressure L2, compared up to a constant: with the
  // velocity given on the whole boundary the pressure is fixed only up to
  // one, and pinning it at a vertex shifts it by that vertex's error). For
  // lambda != 1 the exterior disturbance is steep at r = 1; at N = 24..48
  // the exact solution's own P2/P1 interpolant converges at ~2.75 / ~2 and
  // the finite-element error stays within ~10 % of it (investigated; see
  // docs/validation/stokes_drop.md). These bounds are what that allows.
  const double lambda = GetParam(), gamma = 0.5;
  std::vector<verification::DropSolveResult> runs;
  for (int n : {24, 36, 48}) {
    runs.push_back(verification::drop_in_shear(lambda, gamma, n));
    const auto& r = runs.back();
    std::printf("lambda %.1f  N %2d  unknowns %7d  |u-u_h| %.3e  |p-p_h|/const %.3e  jump %.6f (exact %.1f)\n",
                lambda, n, r.unknowns, r.velocity_l2, r.pressure_l2, r.pressure_jump,
                r.exact_pressure_jump);
  }
  auto su = [&](int i) { return slope(runs[i].velocity_l2, runs[i + 1].velocity_l2, runs[i].h0, runs[i + 1].h0); };
  auto sp = [&](int i) { return slope(runs[i].pressure_l2, runs[i + 1].pressure_l2, runs[i].h0, runs[i + 1].h0); };
  std::printf("lambda %.1f slopes (N 36 -> 48): velocity %.2f  pressure %.2f\n", lambda, su(1), sp(1));
  EXPECT_GT(su(0), 2.0);
  EXPECT_GT(su(1), 2.5);
  EXPECT_GT(sp(1), 1.7);
  EXPECT_LT(std::abs(runs[2].pressure_jump - runs[2].exact_pressure_jump), 0.01 * runs[2].exact_pressure_jump);
}

INSTANTIATE_TEST_SUITE_P(ViscosityRatios, DropInShearSlow, ::testing::Values(0.5, 1.0, 5.0));

TEST(StaticDrop, LaplacePressureJumpAndSpuriousCurrentsFallWithRefinement) {
  // No flow, Gamma = 1, R = 1: p_drop - p_matrix = 2 and u = 0 exactly; the
  // discrete curved interface leaves small spurious velocities.
  std::vector<double> max_u;
  for (int n : {16, 28, 40}) {
    const auto r = verification::static_drop(n);
    max_u.push_back(r.max_velocity);
    std::printf("N %2d  unknowns %7d  jump %.6f  (2 Gamma/R = 2, rel. error %.2e)  max|u| %.3e\n", n,
                r.unknowns, r.pressure_jump, std::abs(r.pressure_jump - 2) / 2, r.max_velocity);
    if (n == 40) {
      EXPECT_NEAR(r.pressure_jump, 2.0, 0.005 * 2.0);  // the default resolution
    }
  }
  EXPECT_LT(max_u[1], max_u[0]);
  EXPECT_LT(max_u[2], max_u[1]);
}

class IterativeAgainstDirect : public ::testing::TestWithParam<double> {};

TEST_P(IterativeAgainstDirect, SameDiscreteSolutionAtExtremeViscosityRatios) {
  // The fieldsplit solver (GMRES, lower Schur factorisation with the
  // viscosity-weighted pressure mass, BoomerAMG on the velocity with the
  // rigid-body near-nullspace) against MUMPS on one drop, lambda = 0.01 and
  // 100. Both solve the same discrete system: the difference of the two
  // solutions falls with the Krylov tolerance (by more than 100 from rtol
  // 1e-8 to 1e-11) and ends far below the discretisation error; the
  // iteration count stays bounded.
  const double lambda = GetParam();
  const auto direct = verification::drop_in_shear(lambda, 0.5, 16);
  auto difference_at = [&](double rtol, int& iterations) {
    la::SaddlePointSettings iterative;
    iterative.method = la::SaddlePointMethod::iterative;
    iterative.rtol = rtol;
    const auto krylov = verification::drop_in_shear(lambda, 0.5, 16, iterative);
    EXPECT_EQ(direct.solution.size(), krylov.solution.size());
    double difference = 0.0, size = 0.0;
    for (std::size_t i = 0; i < direct.solution.size(); ++i) {
      difference = std::max(difference, std::abs(direct.solution[i] - krylov.solution[i]));
      size = std::max(size, std::abs(direct.solution[i]));
    }
    iterations = krylov.iterations;
    std::printf("lambda %g, rtol %g: %d unknowns, %d iterations, max |x_it - x_direct| / max |x| = %.2e\n",
                lambda, rtol, direct.unknowns, krylov.iterations, difference / size);
    return difference / size;
  };
  int loose_iterations = 0, tight_iterations = 0;
  const double loose = difference_at(1e-8, loose_iterations);
  const double tight = difference_at(1e-11, tight_iterations);
  EXPECT_GT(loose / tight, 100.0);
  EXPECT_LT(tight, 1e-6);  // the velocity's discretisation error here is ~1e-2 of it
  EXPECT_LT(tight_iterations, 200);
}

INSTANTIATE_TEST_SUITE_P(ViscosityRatios, IterativeAgainstDirect, ::testing::Values(0.01, 100.0));

TEST(IterativeRobustness, IterationsHardlyDependOnTheViscosityRatio) {
  // The iterative solver's coarse spaces (docs/stokes_engine.md): the
  // rigid motions of a drop more viscous than the matrix, solved exactly
  // beside BoomerAMG, and the constant pressure of a less viscous one, set
  // right in the Schur complement's estimate; with the drop's block of
  // -M/eta weighted above lambda = 1. Without them this drop needs 46 / 41 /
  // 39 / 44 / 58 iterations at lambda = 0.01 / 0.1 / 1 / 10 / 100 (1.49x;
  // at 152k unknowns 1.63x); with them 41 / 40 / 39 / 41 / 42.
  la::SaddlePointSettings iterative;
  iterative.method = la::SaddlePointMethod::iterative;
  std::vector<int> iterations;
  for (double lambda : {0.01, 0.1, 1.0, 10.0, 100.0}) {
    iterations.push_back(verification::drop_in_shear(lambda, 0.5, 16, iterative).iterations);
    std::printf("lambda %g: %d iterations\n", lambda, iterations.back());
  }
  const auto [fewest, most] = std::minmax_element(iterations.begin(), iterations.end());
  EXPECT_LE(*most, 1.2 * *fewest);
}

TEST(IterativeRobustness, EachObjectGetsTheCoarseSpaceOfItsSide) {
  // A drop less viscous than the matrix: one Schur correction, c = -(eta_m -
  // eta_d) / (2 V) with V the drop's volume read off the assembled mass; no
  // velocity coarse space. More viscous: its six rigid motions and no
  // correction. Equal: neither.
  la::SaddlePointSettings iterative;
  iterative.method = la::SaddlePointMethod::iterative;
  const auto soft = verification::drop_in_shear(0.1, 0.5, 16, iterative);
  ASSERT_EQ(soft.schur_correction_coefficients.size(), 1u);
  const double volume = -(1.0 - 0.1) / (2.0 * soft.schur_correction_coefficients[0]);
  std::printf("lambda 0.1: drop volume from the mass %.8f, of its tetrahedra %.8f\n", volume,
              soft.drop_volume);
  EXPECT_NEAR(volume, soft.drop_volume, 1e-10 * soft.drop_volume);
  EXPECT_EQ(soft.primal_coarse_vectors, 0);
  const auto stiff = verification::drop_in_shear(10.0, 0.5, 16, iterative);
  EXPECT_TRUE(stiff.schur_correction_coefficients.empty());
  EXPECT_EQ(stiff.primal_coarse_vectors, 6);
  const auto equal = verification::drop_in_shear(1.0, 0.5, 16, iterative);
  EXPECT_TRUE(equal.schur_correction_coefficients.empty());
  EXPECT_EQ(equal.primal_coarse_vectors, 0);
}

TEST(IterativeAgainstDirectWithGamg, AnotherVelocityPreconditionerGetsTheBlockInPetscFormat) {
  // The velocity block is stored in hypre's format only while BoomerAMG
  // takes it (the default); a user's other choice, here PETSc's GAMG, gets
  // it as AIJ and solves the same system.
  la::SaddlePointSettings iterative;
  iterative.method = la::SaddlePointMethod::iterative;
  iterative.rtol = 1e-11;
  iterative.prefix = "gamg_choice_";
  EXPECT_TRUE(la::primal_split_uses_hypre(iterative, "velocity"));
  ASSERT_EQ(PetscOptionsSetValue(nullptr, "-gamg_choice_fieldsplit_velocity_pc_type", "gamg"), 0);
  EXPECT_FALSE(la::primal_split_uses_hypre(iterative, "velocity"));
  const auto krylov = verification::drop_in_shear(1.0, 0.5, 16, iterative);
  ASSERT_EQ(PetscOptionsClearValue(nullptr, "-gamg_choice_fieldsplit_velocity_pc_type"), 0);
  const auto direct = verification::drop_in_shear(1.0, 0.5, 16);
  ASSERT_EQ(direct.solution.size(), krylov.solution.size());
  double difference = 0.0, size = 0.0;
  for (std::size_t i = 0; i < direct.solution.size(); ++i) {
    difference = std::max(difference, std::abs(direct.solution[i] - krylov.solution[i]));
    size = std::max(size, std::abs(direct.solution[i]));
  }
  std::printf("GAMG on the velocity: %d iterations, max |x_it - x_direct| / max |x| = %.2e\n",
              krylov.iterations, difference / size);
  EXPECT_LT(difference / size, 1e-6);
  la::SaddlePointSettings direct_settings;
  EXPECT_FALSE(la::primal_split_uses_hypre(direct_settings, "velocity"));
}

TEST(IterativeReuse, AKeptPreconditionerSolvesTheChangedSystemAndIsRebuiltOnceItCostsTooMuch) {
  // One Stokes system solved for lambda = 1, 1.05, 1.1 (a slowly changing
  // system, as in a time loop), then 1000 (a jump). The iterative method keeps
  // its fieldsplit/AMG preconditioner while it costs at most
  // max_reuse_growth times the fewest iterations since its build: the small
  // changes reuse it and still reach the direct solution of their own
  // system; at the jump the kept one is given up for a fresh one.
  const std::vector<double> lambdas{1.0, 1.05, 1.1, 1000.0, 1000.0};
  la::SaddlePointSettings iterative;
  iterative.method = la::SaddlePointMethod::iterative;
  iterative.rtol = 1e-10;
  const auto runs = verification::drop_in_shear_sequence(lambdas, 0.5, 16, iterative);
  for (std::size_t k = 0; k < runs.size(); ++k)
    std::printf("lambda %g: %d iterations, preconditioner %s, %d builds\n", lambdas[k],
                runs[k].iterations, runs[k].reused_preconditioner ? "kept" : "built",
                runs[k].preconditioner_builds);
  EXPECT_FALSE(runs[0].reused_preconditioner);
  EXPECT_TRUE(runs[1].reused_preconditioner);
  EXPECT_TRUE(runs[2].reused_preconditioner);
  EXPECT_EQ(runs[2].preconditioner_builds, 1);
  // The jump: the kept preconditioner would need 494 iterations here
  // (measured without the cap); it is given up after 2 x 1.3 x the fewest
  // (41 -> 106) and the solve restarts with a fresh one (~100 more). The
  // next solve keeps that one. (The velocity block lives in hypre's format,
  // so a kept AMG smooths with the current block on its finest level and
  // only its coarse levels are old: a jump to lambda = 30 costs it 93
  // iterations, within the allowance, where a frozen copy needed 365.)
  EXPECT_FALSE(runs[3].reused_preconditioner);
  EXPECT_EQ(runs[3].preconditioner_builds, 2);
  EXPECT_LT(runs[3].iterations, 300);
  EXPECT_TRUE(runs[4].reused_preconditioner);
  EXPECT_EQ(runs[4].preconditioner_builds, 2);
  for (std::size_t k : {std::size_t{2}, std::size_t{4}}) {
    const auto direct = verification::drop_in_shear(lambdas[k], 0.5, 16);
    double difference = 0.0, size = 0.0;
    for (std::size_t i = 0; i < direct.solution.size(); ++i) {
      difference = std::max(difference, std::abs(direct.solution[i] - runs[k].solution[i]));
      size = std::max(size, std::abs(direct.solution[i]));
    }
    EXPECT_LT(difference / size, 1e-6) << "lambda " << lambdas[k];
  }
}
