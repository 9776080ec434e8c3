// How the iterative Stokes solver's Schur-complement estimate -M/eta is
// corrected where it is known to be wrong at a viscosity jump.
#pragma once

namespace softflow::physics {

/// The factor on an object's block of the viscosity-scaled pressure mass
/// (M/eta_k times it), for viscosity ratio lambda = eta_k / eta_matrix.
///
/// Why: where the velocity is continuous across no viscosity jump,
/// (div v, q)^2 <= (1/2) a(v, v) |q|^2 / eta bounds the Schur complement by
/// M/(2 eta) (2 D:D = grad v:grad v + (div v)^2 for a periodic or wall-bounded
/// v). Inside a much more viscous drop the velocity is free at the interface
/// (the outer fluid gives way), and only the pointwise (div v)^2 <= 3 D:D
/// holds: up to 3 / 2, three times higher. bench/schur_spectrum.py measures
/// this at 34k unknowns: with lambda = 100 the top 5 % of the spectrum of
/// (M/eta)^{-1} S lie on the drop's pressure, up to 1.47 against 0.50 at
/// lambda = 1. The weight moves them back into the lambda = 1 range.
double pressure_mass_weight(double viscosity_ratio);

/// The coefficient c_k of object k's constant pressure z_k in the Schur
/// preconditioner's coarse correction, P^{-1} r = D^{-1} r + c_k z_k (z_k . r)
/// (la::CoarseCorrection), for the negative estimate -M/eta:
///   c_k = -max(0, (eta_matrix - eta_k) / 2) / V_k,
/// V_k the object's volume.
///
/// Why: a constant pressure in a drop does work only through the net flux
/// across its interface, which the matrix resists as much as the drop, so
/// the Schur complement there is about V_k / (eta_k + eta_matrix) up to a
/// factor, not V_k / eta_k. At lambda = 0.01 M/eta puts it 100x too high
/// (the one outlier of the spectrum at 0.0075, bench/schur_spectrum.py).
/// Jacobi on the P1 mass already weights a constant by about 2.5 eta_k / V_k
/// in the inverse (the diagonal is 0.4 of the row sum); the correction
/// adds (eta_matrix - eta_k) / (2 V_k), nothing from lambda = 1 up. Its
/// factor 1/2 is measured, not derived: 1, 1/2 and 1/3 all move the
/// outlier into the rest of the spectrum (34k, lambda = 0.01, Jacobi:
/// extreme-eigenvalue ratio 72 -> 22), and 1/2 vanishes at lambda = 1.
double constant_pressure_correction(double eta_object, double eta_matrix, double volume);

}  // namespace softflow::physics
