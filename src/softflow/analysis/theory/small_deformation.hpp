// Small-deformation theory of drops and elastic particles in unbounded simple shear: D and theta.
#pragma once

#include <optional>
#include <string>

namespace softflow::analysis::theory {

// All results are steady values, first order in the capillary number, for an
// initially spherical object of radius R in unbounded simple shear
// u_x = shear rate * y. lambda = eta_d / eta_m, Ca = eta_m shear_rate R / Gamma.
// Angles are those of EllipsoidFit::theta_deg: the long axis against the flow
// direction x, positive towards +y, 45 degrees at Ca -> 0. Negative or
// non-finite arguments throw softflow::InputError naming the argument.

/// Taylor (1932), eq. 1.1: D = (19 lambda + 16) / (16 lambda + 16) Ca.
/// Newtonian drop in a Newtonian matrix, no slip; valid for Ca << 1 (the
/// thesis sees agreement up to Ca ~ 0.3 at lambda = 1.4, Fig. 2.10a).
double taylor_deformation(double lambda, double ca);

/// Chaffey & Brenner (1967), eq. 2.59, in degrees:
/// theta = pi/4 - (19 lambda + 16)(2 lambda + 3) / (80 (1 + lambda)) Ca [rad].
/// Same system and range as taylor_deformation (Fig. 2.10b).
double chaffey_brenner_angle_deg(double lambda, double ca);

/// Greco (2002), eq. 2.60, in degrees: drop and matrix both second-order
/// fluids, p = Psi_1m Gamma / (2 R eta_m^2), p_d = Psi_1d Gamma / (2 R eta_d^2):
/// theta = [eq. 2.59] - Ca [p (176 + 436 lambda + 323 lambda^2) / (30 (1 + lambda)(16 + 19 lambda))
///                         + p_d (9 lambda^2 + 6 lambda^3) / (8 (1 + lambda)(16 + 19 lambda))].
/// The first term is Chaffey-Brenner's, so p = p_d = 0 gives eq. 2.59;
/// viscoelasticity on either side lowers theta. D is Taylor's at this order.
/// The thesis finds agreement for Ca <= 0.1 (UCM drop, lambda = 2, p_d = 0.5,
/// Fig. 2.12b).
double greco_angle_deg(double lambda, double ca, double p, double p_d);

/// The same first-order angle derived in this project for second-order
/// fluids with Psi_2 = 0 (UCM and Oldroyd-B at small Deborah numbers), in
/// degrees, with p and p_d as in greco_angle_deg:
/// theta = [eq. 2.59] - Ca [p (19 lambda^2 + 32 lambda + 16) / (2 (1 + lambda)(16 + 19 lambda))
///                         + p_d 3 lambda^2 / (2 (1 + lambda)(16 + 19 lambda))].
/// Derivation (Taylor's base flow, the reciprocal theorem with l = 2
/// traction-driven auxiliary flows, checked by a direct solution):
/// scripts/theory/second_order_fluid_drop/. It differs from eq. 2.60 as the
/// thesis prints it: the drop term by the factor 4 / (2 lambda + 3) (7/4 at
/// lambda = 2), the matrix term except at lambda = 2; docs/viscoelastic.md
/// compares both with the runs. With the same relaxation time in both phases
/// the shift is -De/2 rad whatever lambda.
double second_order_fluid_angle_deg(double lambda, double ca, double p, double p_d);

/// Drop with Navier slip alpha (made dimensionless with R / eta_m) on its
/// interface, SPEC §10 (Ramachandran & Leal, thesis Fig. 2.11):
/// D = (19 lambda + 16 + 80 alpha lambda) / (16 (1 + lambda + 5 alpha lambda)) Ca.
/// alpha = 0 is Taylor's eq. 1.1; thesis range Ca <= 0.1 at lambda = 1.
double slip_taylor_deformation(double lambda, double ca, double alpha);

/// Roscoe (1967), small-Ca_e limit for a neo-Hookean sphere in a Newtonian
/// fluid (SPEC §3): D = 5/4 Ca_e, Ca_e = eta_m shear_rate / G. Linear regime
/// Ca_e <= 0.2 (thesis Fig. 2.14a).
double roscoe_small_ca_deformation(double ca_e);

/// Roscoe (1967), small-Ca_e limit (SPEC §3), in degrees:
/// theta = pi/4 - 3/4 Ca_e [rad]. Same range as roscoe_small_ca_deformation.
double roscoe_small_ca_angle_deg(double ca_e);

/// Kelvin-Voigt sphere (neo-Hookean modulus G plus a viscosity mu_d, tau =
/// 2 mu_d D + G (B - I)) in a Newtonian fluid, first order in Ca_e =
/// eta_m shear_rate / G, lambda_s = mu_d / eta_m (docs/viscoelastic.md
/// derives it): D = 5/4 Ca_e, whatever lambda_s. lambda_s = 0 is Roscoe's
/// neo-Hookean limit.
double kelvin_voigt_small_ca_deformation(double ca_e, double lambda_s);

/// The same sphere's angle, in degrees: theta = pi/4 - (2 lambda_s + 3)/4 Ca_e
/// [rad]. The solid's viscosity lengthens the shape's relaxation time
/// eta_m (2 lambda_s + 3) / (2 G), so the vorticity turns the shape further
/// towards the flow; lambda_s = 0 gives roscoe_small_ca_angle_deg.
double kelvin_voigt_small_ca_angle_deg(double ca_e, double lambda_s);

/// Optional inputs of theory_table beyond lambda and Ca.
struct TheoryQuery {
  double p = 0.0;                    ///< matrix elasticity (Greco)
  double p_d = 0.0;                  ///< drop elasticity (Greco)
  std::optional<double> ca_e;        ///< elastic capillary number (Roscoe); default: Ca
  /// Navier slip alpha (made dimensionless with R / eta_m) of the slip-drop
  /// D; default: the examples alpha = 0.1 and 1.
  std::optional<double> slip;
  /// Kelvin-Voigt particle: its viscosity over the matrix's, mu_d / eta_m.
  std::optional<double> solid_viscosity_ratio;
  /// Oldroyd's emulsion (oldroyd_emulsion.hpp): volume fraction and omega tau_em.
  double phi = 0.1;
  double omega_star = 0.4;
};

/// A few lines for `softflow theory --lambda L --ca C [--p P --p-d PD --ca-e CE --slip A
/// --solid-viscosity-ratio LS]`:
/// Taylor D, Chaffey-Brenner theta, the slip-drop D at the given alpha (else
/// at alpha = 0.1 and 1), the Greco correction as coefficients of p and p_d
/// and its value at the given p, p_d, Roscoe's elastic sphere at Ca_e, and
/// the Kelvin-Voigt sphere's at the given lambda_s, and Oldroyd's emulsion moduli
/// at phi, omega* (with the slip alpha when given) and its dilute coefficient.
std::string theory_table(double lambda, double ca, const TheoryQuery& query = {});

}  // namespace softflow::analysis::theory
