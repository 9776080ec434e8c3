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

/// tau of a transient problem stepped with dt: the steady tau (above) and
/// dt / 2 combined as 1 / tau^2 = 1 / tau_steady^2 + (2 / dt)^2 (Shakib,
/// Hughes & Johan 1991; Tezduyar 1992), so that tau <= dt / 2. Why: where
/// the transport speed |b| is small (inside a tank-treading elastic
/// particle, b = u - u_mesh) the steady tau is large, and its weight
/// tau b.grad v ~ (h / 2) b/|b| . grad v on the time derivative does not
/// shrink with dt; measured, a neo-Hookean particle's shape then did not
/// converge as dt fell, and does with this tau (docs/viscoelastic.md, "The
/// SUPG parameter and the time step"). 0 where the steady tau is 0 (no
/// transport: no streamline term).
inline double transient_supg_tau(double steady_tau, double dt) {
  if (steady_tau <= 0.0) return 0.0;
  const double inverse_dt = 2.0 / dt;
  return 1.0 / std::sqrt(1.0 / (steady_tau * steady_tau) + inverse_dt * inverse_dt);
}

}  // namespace softflow::fem
