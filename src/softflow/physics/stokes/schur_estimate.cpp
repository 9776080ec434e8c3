#include "softflow/physics/stokes/schur_estimate.hpp"

#include <algorithm>

namespace softflow::physics {

double pressure_mass_weight(double viscosity_ratio) {
  // 1 up to lambda = 1, rising smoothly to 2 for a rigid drop: measured
  // better than the bound's 3 (34k, with the rigid-motion coarse space:
  // 35 / 36 iterations at lambda = 100 for 2 / 3, 39 for 1; at 152k
  // without it 57 / 59; bench/schur_spectrum.py: the spread of the
  // spectrum with Jacobi on the mass is flat between 2 and 3 from lambda 10).
  if (viscosity_ratio <= 1.0) return 1.0;
  return 1.0 + (viscosity_ratio - 1.0) / (viscosity_ratio + 1.0);
}

double constant_pressure_correction(double eta_object, double eta_matrix, double volume) {
  return -std::max(0.0, 0.5 * (eta_matrix - eta_object)) / volume;
}

}  // namespace softflow::physics
