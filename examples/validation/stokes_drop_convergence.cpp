// Validation: one two-phase Stokes solve around a spherical drop, under mesh refinement.
//
//   stokes_drop_convergence > table.csv
//
// Part 1, drop in shear (verification::drop_in_shear): unit sphere in a box
// [-3,3]^3, the exact instantaneous field on the box faces, Gamma = 0.5,
// lambda = 0.5, 1, 5; L2 errors of velocity and pressure (up to a constant)
// and the error of the area-averaged pressure jump (exact: 2 Gamma = 1).
// Part 2, static drop (verification::static_drop): the Laplace jump
// 2 Gamma / R = 2 and the spurious velocity.
// scripts/validation/stokes_drop.py turns the CSV into docs/validation/.
#include <cmath>
#include <cstdio>

#include <petscsys.h>

#include "support/verification/drop_cases.hpp"

using namespace softflow;

namespace {
void print(const char* name, double lambda, const verification::DropSolveResult& r) {
  std::printf("%s,%g,%d,%.6f,%d,%.6e,%.6e,%.6e,%.6e\n", name, lambda, r.equator_nodes, r.h0,
              r.unknowns, r.velocity_l2, r.pressure_l2,
              std::abs(r.pressure_jump - r.exact_pressure_jump), r.max_velocity);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  std::printf("case,lambda,equator_nodes,h0,unknowns,velocity_l2,pressure_l2,jump_error,max_velocity\n");
  for (double lambda : {0.5, 1.0, 5.0})
    for (int n : {24, 36, 48, 64}) print("shear", lambda, verification::drop_in_shear(lambda, 0.5, n));
  for (int n : {16, 28, 40, 50}) print("static", 1.0, verification::static_drop(n));
  PetscFinalize();
  return 0;
}
