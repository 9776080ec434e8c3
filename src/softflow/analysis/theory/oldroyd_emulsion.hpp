// Oldroyd's (1953) linear viscoelasticity of an emulsion of Newtonian drops in
// a Newtonian matrix (thesis appendices A and B): G'(omega), G''(omega).
#pragma once

#include <complex>

namespace softflow::analysis::theory {

// Units: viscosities in eta_m, times in the emulsion time tau_em = eta_m R / Gamma
// (R the drops' radius, Gamma their tension), so omega_star = omega tau_em.
// lambda = eta_d / eta_m, phi the drops' volume fraction, alpha the Navier
// slip of the interface made dimensionless with R / eta_m (as slip_taylor_deformation).
// Arguments outside the ranges below throw softflow::InputError naming them.

/// The three constants of Oldroyd's Jeffreys-type emulsion: eta* = (eta + i omega xi) /
/// (1 + i omega tau) (eqs. A.1-A.2 are its real and imaginary parts times i omega).
struct OldroydConstants {
  double viscosity;        ///< eta / eta_m: eq. A.3 (B.1 with slip), the steady viscosity
  double relaxation_time;  ///< tau / tau_em: eq. A.4 (B.2 as SPEC §9 corrects it)
  double retardation;      ///< xi / (eta_m tau_em): eq. A.5 (B.3 as SPEC §9 corrects it)
};

/// eqs. A.3-A.5 (alpha = 0) and B.1-B.3 with SPEC §9's correction of B.2-B.3
/// (as printed they give G' != 0 at phi = 0 and negative times). Every
/// denominator is 10(lambda+1) - 2(5 lambda+2) phi + 10 alpha lambda (5 - 2 phi),
/// positive for 0 <= phi < 1. lambda >= 0, 0 <= phi < 1, alpha >= 0.
OldroydConstants oldroyd_constants(double lambda, double phi, double alpha = 0.0);

/// The complex modulus G* = G' + i G'' in units of Gamma / R:
/// G* = i omega (eta + i omega xi) / (1 + i omega tau) (eqs. A.1-A.2).
/// At phi = 0 it is the matrix's i omega eta_m. omega_star > 0.
std::complex<double> oldroyd_complex_modulus(double lambda, double phi, double omega_star,
                                             double alpha = 0.0);

/// The moduli as the thesis plots them (Figs. 4.11-4.20): G' scaled by Gamma / R and
/// G'' by eta_m omega (so G'' = 1 for the matrix alone).
struct ScaledModuli {
  double storage;  ///< G' R / Gamma
  double loss;     ///< G'' / (eta_m omega)
};
ScaledModuli oldroyd_moduli(double lambda, double phi, double omega_star, double alpha = 0.0);

/// The dilute limit: eta* / eta_m = 1 + c phi + O(phi^2), c the complex intrinsic
/// viscosity of one drop (its stresslet S_xy = c eta_m V_d times the complex shear
/// rate), exactly the phi-derivative of oldroyd_complex_modulus / (i omega eta_m) at 0:
///   c = [5(5 lambda + 2) + 50 alpha lambda + i omega (X1 - T1) / 4] / [D0 + i omega T0 / 4],
///   X1 - T1 = 5(lambda - 1)(19 lambda + 16) + 10 alpha lambda (19 lambda - 40),
///   D0 = 10(lambda + 1) + 50 alpha lambda, T0 = (19 lambda + 16)(2 lambda + 3) + 10 alpha lambda (19 lambda + 24).
/// omega -> 0: Taylor's (5 lambda + 2) / (2 (lambda + 1)); omega -> oo: the tension-free
/// viscous sphere's 5 (lambda - 1) / (2 lambda + 3) (alpha = 0). omega_star >= 0.
std::complex<double> oldroyd_dilute_coefficient(double lambda, double omega_star, double alpha = 0.0);

}  // namespace softflow::analysis::theory
