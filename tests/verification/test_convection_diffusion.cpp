// Steady convection-diffusion with SUPG on a P1 per-region space, through the
// general (non-symmetric) coordinate-format assembly: a manufactured
// solution with a jump at the interface, on curved, distorted meshes
// (the problem: support/verification/convection_diffusion.hpp). This is the
// transport problem the log-conformation tensor will solve, per component.
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/la/petsc.hpp"
#include "support/verification/convection_diffusion.hpp"

using namespace softflow;

TEST(ConvectionDiffusionSupg, ConvergesAtP1RatesOnCurvedMeshesWithAJumpAtTheInterface) {
  // eps = 0.05, h = 1/2 .. 1/16: element Peclet numbers from 6 to 0.7, i.e.
  // from convection- to diffusion-dominated.
  std::vector<verification::ConvectionDiffusionErrors> e;
  for (int n : {4, 8, 16, 32}) {
    e.push_back(verification::solve_convection_diffusion(n, 0.05, true));
    if (la::mpi_rank() == 0)
      std::printf("n = %2d  unknowns %7d  Pe %.2f  L2 %.4e  H1 %.4e\n", n, e.back().unknowns,
                  e.back().peclet, e.back().l2, e.back().h1);
  }
  for (std::size_t i = 1; i < e.size(); ++i) {
    const double l2_rate = std::log2(e[i - 1].l2 / e[i].l2);
    const double h1_rate = std::log2(e[i - 1].h1 / e[i].h1);
    if (la::mpi_rank() == 0) std::printf("rates: L2 %.2f  H1 %.2f\n", l2_rate, h1_rate);
    EXPECT_GT(h1_rate, 0.9);
    if (i + 1 == e.size()) {
      EXPECT_GT(l2_rate, 1.85);  // asymptotic P1 rate: 2
    }
  }
}

TEST(ConvectionDiffusionSupg, StabilisesWhereGalerkinOscillates) {
  // Convection-dominated (eps = 0.002, Pe = 73 at n = 8): plain Galerkin
  // overshoots the exact solution; SUPG stays close to it. Measured:
  // see docs/validation/convection_diffusion.md.
  const auto galerkin = verification::solve_convection_diffusion(8, 0.002, false);
  const auto supg = verification::solve_convection_diffusion(8, 0.002, true);
  EXPECT_LT(supg.l2, 0.5 * galerkin.l2);
  EXPECT_LT(supg.overshoot, 0.5 * galerkin.overshoot);
}
