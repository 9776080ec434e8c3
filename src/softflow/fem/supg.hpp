// Streamline-upwind/Petrov-Galerkin stabilisation parameters.
#pragma once

#include <cmath>

namespace softflow::fem {

/// Element length for SUPG: the edge of the cube of the same volume as six
/// such tetrahedra, (6 V)^(1/3) (the cube's edge for a Kuhn tetrahedron).
inline double element_length(double volume) { return std::cbrt(6.0 * volume); }

/// tau of the SUPG term  sum_e (b.grad v, tau (b.grad u - eps lap u - f))_e
/// for a P1/P2 element of length h, speed |b| and diffusivity eps:
///
///   tau = h / (2 |b|) (coth Pe - 1/Pe),   Pe = |b| h / (2 eps),
///
/// which tends to h / (2 |b|) (the thesis's tau for pure transport, SPEC §2
/// part 5) as eps -> 0 and to h^2 / (12 eps) (vanishing like the
/// consistency error of a P1 residual without its Laplacian) as Pe -> 0.
inline double supg_tau(double h, double speed, double diffusivity) {
  if (speed <= 0.0) return 0.0;
  const double pure_transport = h / (2.0 * speed);
  if (diffusivity <= 0.0) return pure_transport;
  const double pe = speed * h / (2.0 * diffusivity);
  // coth(Pe) - 1/Pe, by its series where cancellation would lose digits.
  const double xi = pe < 1e-3 ? pe / 3.0 - pe * pe * pe / 45.0 : 1.0 / std::tanh(pe) - 1.0 / pe;
  return pure_transport * xi;
}

}  // namespace softflow::fem
