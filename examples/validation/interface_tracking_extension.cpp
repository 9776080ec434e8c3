// Validation: interface tracking of a sphere in extensional flow u = (x, -y/2, -z/2) to t = 0.5
// (thesis §2.4.1, Figs. 2.4-2.6). Prints CSV: study, k, equator_nodes, nodes, dt, E_max, E_2.
// scripts/validation/interface_tracking.py turns it into docs/validation/.
#include <cstdio>

#include <petscsys.h>

#include "support/verification/extensional_flow.hpp"

using softflow::verification::track_sphere_in_extension;

namespace {
void print(const char* study, double k, int n, double dt) {
  const auto e = track_sphere_in_extension(n, dt, k);
  std::printf("%s,%g,%d,%d,%g,%.6e,%.6e\n", study, k, e.equator_nodes, e.interface_nodes, e.dt,
              e.e_max, e.e_2);
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv) {
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0) return 1;
  std::printf("study,k,equator_nodes,interface_nodes,dt,e_max,e_2\n");
  for (double k : {0.0, 10.0})
    for (double dt : {0.1, 0.05, 0.025, 0.0125, 0.005, 0.0025}) print("time", k, 100, dt);
  for (int n : {20, 28, 40, 56, 80, 100, 140}) print("space", 0.0, n, 0.002);
  PetscFinalize();
  return 0;
}
