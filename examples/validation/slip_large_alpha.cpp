// Validation: one Stokes solve around a spherical slip drop as the slip coefficient grows.
//
//   slip_large_alpha > table.csv
//
// verification::slip_drop_in_shear (unit sphere, lambda = 1, box [-3,3]^3,
// the exact instantaneous slip field on the box faces, no tension) for
// alpha = 1 ... 1e6 and inf (free slip) on meshes of 16 to 40 equator
// nodes: the L2 errors of the velocity and of the slip velocity against the
// exact field (SPEC §10), the slip dissipation against the exact one, and
// the energy balance (viscous + slip dissipation = work of the boundary).
// scripts/validation/slip_large_alpha.py turns the CSV into docs/validation/.
#include <cmath>
#include <cstdio>
#include <limits>

#include <petscsys.h>

#include "support/verification/slip_drop.hpp"

using namespace softflow;

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  std::printf("equator_nodes,alpha,unknowns,velocity_l2,jump_l2,exact_jump_l2,slip_dissipation,"
              "exact_slip_dissipation,viscous_dissipation,boundary_work\n");
  const double inf = std::numeric_limits<double>::infinity();
  for (int n : {16, 24, 32, 40})
    for (double alpha : {1.0, 10.0, 100.0, 1e3, 1e4, 1e6, inf}) {
      const auto r = verification::slip_drop_in_shear(1.0, alpha, 0.0, n);
      std::printf("%d,%g,%d,%.6e,%.6e,%.6e,%.6e,%.6e,%.10e,%.10e\n", n, alpha, r.unknowns,
                  r.velocity_l2, r.jump_l2, r.exact_jump_l2, r.slip_dissipation,
                  r.exact_slip_dissipation, r.viscous_dissipation, r.boundary_work);
      std::fflush(stdout);
    }
  PetscFinalize();
  return 0;
}
