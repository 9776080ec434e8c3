#include "softflow/analysis/theory/oldroyd_emulsion.hpp"

#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::analysis::theory {

namespace {

using Complex = std::complex<double>;
constexpr Complex kI{0.0, 1.0};

void require(bool ok, const char* name, double value, const char* allowed) {
  if (!ok) throw InputError(fmt::format("theory: {} = {} must be {}", name, value, allowed));
}

void check_emulsion(double lambda, double phi, double alpha) {
  require(std::isfinite(lambda) && lambda >= 0.0, "lambda", lambda, "a finite number >= 0");
  require(std::isfinite(phi) && phi >= 0.0 && phi < 1.0, "phi", phi, "in [0, 1)");
  require(std::isfinite(alpha) && alpha >= 0.0, "alpha", alpha, "a finite number >= 0");
}

}  // namespace

OldroydConstants oldroyd_constants(double lambda, double phi, double alpha) {
  check_emulsion(lambda, phi, alpha);
  const double l = lambda, slip = alpha * lambda;
  const double denominator = 10.0 * (l + 1.0) - 2.0 * (5.0 * l + 2.0) * phi + 10.0 * slip * (5.0 - 2.0 * phi);
  const double viscosity =  // eq. B.1 (A.3 at alpha = 0)
      (10.0 * (l + 1.0) + 3.0 * (5.0 * l + 2.0) * phi + 10.0 * slip * (3.0 * phi + 5.0)) / denominator;
  const double tension_term = 19.0 * l + 16.0;
  const double relaxation =  // eq. B.2 as corrected (A.4 at alpha = 0)
      (tension_term * (2.0 * l + 3.0 - 2.0 * (l - 1.0) * phi) +
       2.0 * slip * (5.0 * (19.0 * l + 24.0) - 2.0 * (19.0 * l - 40.0) * phi)) /
      (4.0 * denominator);
  const double retardation =  // eq. B.3 as corrected (A.5 at alpha = 0)
      (tension_term * (2.0 * l + 3.0 + 3.0 * (l - 1.0) * phi) +
       2.0 * slip * (5.0 * (19.0 * l + 24.0) + 3.0 * (19.0 * l - 40.0) * phi)) /
      (4.0 * denominator);
  return {viscosity, relaxation, retardation};
}

std::complex<double> oldroyd_complex_modulus(double lambda, double phi, double omega_star,
                                             double alpha) {
  require(std::isfinite(omega_star) && omega_star > 0.0, "omega_star", omega_star,
          "a finite number > 0");
  const OldroydConstants c = oldroyd_constants(lambda, phi, alpha);
  const Complex i_omega = kI * omega_star;
  return i_omega * (c.viscosity + i_omega * c.retardation) / (1.0 + i_omega * c.relaxation_time);
}

ScaledModuli oldroyd_moduli(double lambda, double phi, double omega_star, double alpha) {
  const Complex g = oldroyd_complex_modulus(lambda, phi, omega_star, alpha);
  return {g.real(), g.imag() / omega_star};
}

std::complex<double> oldroyd_dilute_coefficient(double lambda, double omega_star, double alpha) {
  check_emulsion(lambda, 0.0, alpha);
  require(std::isfinite(omega_star) && omega_star >= 0.0, "omega_star", omega_star,
          "a finite number >= 0");
  const double l = lambda, slip = alpha * lambda;
  const double steady = 5.0 * (5.0 * l + 2.0) + 50.0 * slip;  // N1 + D1
  const double elastic = 5.0 * (l - 1.0) * (19.0 * l + 16.0) + 10.0 * slip * (19.0 * l - 40.0);  // X1 - T1
  const double d0 = 10.0 * (l + 1.0) + 50.0 * slip;
  const double t0 = (19.0 * l + 16.0) * (2.0 * l + 3.0) + 10.0 * slip * (19.0 * l + 24.0);
  const Complex i_omega = kI * omega_star;
  return (steady + i_omega * elastic / 4.0) / (d0 + i_omega * t0 / 4.0);
}

}  // namespace softflow::analysis::theory
