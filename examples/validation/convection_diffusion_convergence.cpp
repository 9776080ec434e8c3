// Validation of the finite-element layer's transport path: steady
// convection-diffusion with SUPG on a P1 per-region space (an interface jump,
// curved meshes, the non-symmetric coordinate-format assembly), against a
// manufactured solution, in the diffusion- and the convection-dominated
// regime, with and without SUPG. Prints CSV; scripts/validation/
// convection_diffusion.py turns it into docs/validation/convection_diffusion.*.
//
// Usage: convection_diffusion_convergence
#include <cstdio>

#include <petscsys.h>

#include "support/verification/convection_diffusion.hpp"

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 2;
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank == 0) std::printf("eps,method,n,h,peclet,unknowns,l2,h1,overshoot\n");
  for (double eps : {0.05, 0.002})
    for (bool supg : {true, false})
      for (int n : {4, 8, 16, 32}) {
        const auto e = softflow::verification::solve_convection_diffusion(n, eps, supg);
        if (rank == 0)
          std::printf("%g,%s,%d,%g,%.4g,%d,%.6e,%.6e,%.6e\n", eps, supg ? "SUPG" : "Galerkin", n,
                      2.0 / n, e.peclet, e.unknowns, e.l2, e.h1, e.overshoot);
      }
  PetscFinalize();
  return 0;
}
