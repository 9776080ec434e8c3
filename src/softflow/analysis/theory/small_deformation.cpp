#include "softflow/analysis/theory/small_deformation.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "softflow/analysis/theory/oldroyd_emulsion.hpp"
#include "softflow/common/error.hpp"

namespace softflow::analysis::theory {

namespace {

constexpr double kQuarterPi = std::numbers::pi / 4.0;

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

/// Theory inputs are ratios of viscosities, times and moduli: finite, >= 0.
void require_non_negative(const char* name, double value) {
  if (!std::isfinite(value) || value < 0.0) {
    throw InputError(fmt::format("theory: {} = {} must be a finite number >= 0", name, value));
  }
}

/// Slope dtheta/dCa of eq. 2.59 (radians), the first term of eq. 2.60 too.
double chaffey_brenner_slope(double lambda) {
  return (19.0 * lambda + 16.0) * (2.0 * lambda + 3.0) / (80.0 * (1.0 + lambda));
}

/// Coefficient of p Ca in eq. 2.60 (matrix elasticity), radians.
double greco_matrix_coefficient(double lambda) {
  return (176.0 + 436.0 * lambda + 323.0 * lambda * lambda) /
         (30.0 * (1.0 + lambda) * (16.0 + 19.0 * lambda));
}

/// Coefficient of p_d Ca in eq. 2.60 (drop elasticity), radians.
double greco_drop_coefficient(double lambda) {
  return (9.0 * lambda * lambda + 6.0 * lambda * lambda * lambda) /
         (8.0 * (1.0 + lambda) * (16.0 + 19.0 * lambda));
}

/// Coefficient of p Ca for second-order fluids with Psi_2 = 0, derived
/// here (scripts/theory/second_order_fluid_drop/), radians.
double second_order_fluid_matrix_coefficient(double lambda) {
  return (19.0 * lambda * lambda + 32.0 * lambda + 16.0) /
         (2.0 * (1.0 + lambda) * (16.0 + 19.0 * lambda));
}

/// Coefficient of p_d Ca, as above.
double second_order_fluid_drop_coefficient(double lambda) {
  return 3.0 * lambda * lambda / (2.0 * (1.0 + lambda) * (16.0 + 19.0 * lambda));
}

}  // namespace

double second_order_fluid_angle_deg(double lambda, double ca, double p, double p_d) {
  require_non_negative("lambda", lambda);
  require_non_negative("Ca", ca);
  require_non_negative("p", p);
  require_non_negative("p_d", p_d);
  const double elastic = p * second_order_fluid_matrix_coefficient(lambda) +
                         p_d * second_order_fluid_drop_coefficient(lambda);
  return degrees(kQuarterPi - chaffey_brenner_slope(lambda) * ca - elastic * ca);
}

double taylor_deformation(double lambda, double ca) {
  require_non_negative("lambda", lambda);
  require_non_negative("Ca", ca);
  return (19.0 * lambda + 16.0) / (16.0 * lambda + 16.0) * ca;  // eq. 1.1
}

double chaffey_brenner_angle_deg(double lambda, double ca) {
  require_non_negative("lambda", lambda);
  require_non_negative("Ca", ca);
  return degrees(kQuarterPi - chaffey_brenner_slope(lambda) * ca);  // eq. 2.59
}

double greco_angle_deg(double lambda, double ca, double p, double p_d) {
  require_non_negative("lambda", lambda);
  require_non_negative("Ca", ca);
  require_non_negative("p", p);
  require_non_negative("p_d", p_d);
  // eq. 2.60: the thesis breaks the line after "+" and starts the next with
  // "- Ca[...]"; the bracket is subtracted (elasticity lowers theta, §1.2).
  const double elastic =
      p * greco_matrix_coefficient(lambda) + p_d * greco_drop_coefficient(lambda);
  return degrees(kQuarterPi - chaffey_brenner_slope(lambda) * ca - elastic * ca);
}

double slip_taylor_deformation(double lambda, double ca, double alpha) {
  require_non_negative("lambda", lambda);
  require_non_negative("Ca", ca);
  require_non_negative("alpha", alpha);
  // SPEC §10, from the O(Ca) normal-stress imbalance of the slip field.
  return (19.0 * lambda + 16.0 + 80.0 * alpha * lambda) /
         (16.0 * (1.0 + lambda + 5.0 * alpha * lambda)) * ca;
}

double roscoe_small_ca_deformation(double ca_e) { return kelvin_voigt_small_ca_deformation(ca_e, 0.0); }

double roscoe_small_ca_angle_deg(double ca_e) { return kelvin_voigt_small_ca_angle_deg(ca_e, 0.0); }

// The derivation (docs/viscoelastic.md): at small strain the sphere's
// interior strain rate is uniform, E_in = (5 E - S / eta_m) / (2 lambda_s + 3)
// with S = 2 G eps the elastic stress (Eshelby's relation for a viscous
// sphere carrying a uniform extra stress), and the strain obeys the linearised
// upper-convected law d eps/dt = E_in + W eps - eps W. Its steady solution has
// principal strains +-a in the shear plane, D = a, and
// tan 2 theta = 2 / ((2 lambda_s + 3) Ca_e); first order in Ca_e gives the
// two functions below.
double kelvin_voigt_small_ca_deformation(double ca_e, double lambda_s) {
  require_non_negative("Ca_e", ca_e);
  require_non_negative("mu_d / eta_m", lambda_s);
  return 1.25 * ca_e;
}

double kelvin_voigt_small_ca_angle_deg(double ca_e, double lambda_s) {
  require_non_negative("Ca_e", ca_e);
  require_non_negative("mu_d / eta_m", lambda_s);
  return degrees(kQuarterPi - 0.25 * (2.0 * lambda_s + 3.0) * ca_e);
}

std::string theory_table(double lambda, double ca, const TheoryQuery& query) {
  // Every line goes through the public functions, which validate lambda, Ca.
  const double cb = chaffey_brenner_angle_deg(lambda, ca);
  const double per_p = degrees(greco_matrix_coefficient(lambda) * ca);
  const double per_p_d = degrees(greco_drop_coefficient(lambda) * ca);
  std::string out = fmt::format(
      "Small-deformation theory, unbounded simple shear, lambda = {:g}, Ca = {:g}\n"
      "(first order in Ca; theta is the long axis against the flow direction)\n",
      lambda, ca);
  out += fmt::format("  Taylor D (eq. 1.1)                    {:.6g}\n",
                     taylor_deformation(lambda, ca));
  out += fmt::format("  Chaffey-Brenner theta (eq. 2.59)      {:.6g} deg\n", cb);
  out +=
      fmt::format("  Greco theta (eq. 2.60)                {:.6g} - ({:.4g} p + {:.4g} p_d) deg\n",
                  cb, per_p, per_p_d);
  out += "    (p = Psi_1 Gamma / (2 R eta^2) of the matrix, p_d the same for the drop)\n";
  out += fmt::format("  Second-order fluids, Psi_2 = 0        {:.6g} - ({:.4g} p + {:.4g} p_d) deg\n",
                     cb, degrees(second_order_fluid_matrix_coefficient(lambda) * ca),
                     degrees(second_order_fluid_drop_coefficient(lambda) * ca));
  out += "    (derived in softflow, docs/viscoelastic.md; differs from eq. 2.60 as printed)\n";
  if (query.p != 0.0 || query.p_d != 0.0)
    out += fmt::format("    at p = {:g}, p_d = {:g}:                 {:.6g} deg (shift {:+.4g} deg)\n",
                       query.p, query.p_d, greco_angle_deg(lambda, ca, query.p, query.p_d),
                       greco_angle_deg(lambda, ca, query.p, query.p_d) - cb);
  if (query.p != 0.0 || query.p_d != 0.0)
    out += fmt::format("    second-order fluids at p, p_d:      {:.6g} deg (shift {:+.4g} deg)\n",
                       second_order_fluid_angle_deg(lambda, ca, query.p, query.p_d),
                       second_order_fluid_angle_deg(lambda, ca, query.p, query.p_d) - cb);
  const std::vector<double> slips =
      query.slip ? std::vector<double>{*query.slip} : std::vector<double>{0.1, 1.0};
  for (const double alpha : slips) {
    out += fmt::format("  Slip drop D, slip alpha = {:<4g}        {:.6g}\n", alpha,
                       slip_taylor_deformation(lambda, ca, alpha));
  }
  const double ca_e = query.ca_e.value_or(ca);
  out += fmt::format("  Neo-Hookean sphere, Ca_e = {:g} (Roscoe): D {:.6g}, theta {:.6g} deg\n", ca_e,
                     roscoe_small_ca_deformation(ca_e), roscoe_small_ca_angle_deg(ca_e));
  if (const auto lambda_s = query.solid_viscosity_ratio)
    out += fmt::format("  Kelvin-Voigt sphere, Ca_e = {:g}, mu_d / eta_m = {:g}: D {:.6g}, theta {:.6g} deg\n",
                       ca_e, *lambda_s, kelvin_voigt_small_ca_deformation(ca_e, *lambda_s),
                       kelvin_voigt_small_ca_angle_deg(ca_e, *lambda_s));
  const double alpha = query.slip.value_or(0.0);
  const ScaledModuli m = oldroyd_moduli(lambda, query.phi, query.omega_star, alpha);
  const auto c = oldroyd_dilute_coefficient(lambda, query.omega_star, alpha);
  out += fmt::format(
      "  Oldroyd emulsion, phi = {:g}, omega* = {:g}, slip alpha = {:g} (appendices A-B):\n"
      "    G' R / Gamma {:.6g}, G'' / (eta_m omega) {:.6g}; dilute eta*/eta_m = 1 + ({:.6g} {:+.6g} i) phi\n",
      query.phi, query.omega_star, alpha, m.storage, m.loss, c.real(), c.imag());
  return out;
}

}  // namespace softflow::analysis::theory
