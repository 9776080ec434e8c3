#include "softflow/analysis/harmonic_fit.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>

namespace softflow::analysis {

HarmonicFit fit_harmonic(std::span<const double> t, std::span<const double> y, double omega) {
  if (t.size() != y.size()) throw std::invalid_argument("fit_harmonic: t and y differ in length");
  if (t.size() < 4) throw std::invalid_argument("fit_harmonic: fewer than 4 samples");
  if (!(omega > 0.0)) throw std::invalid_argument("fit_harmonic: omega must be > 0");
  const auto n = static_cast<Eigen::Index>(t.size());
  Eigen::MatrixXd basis(n, 3);
  Eigen::VectorXd values(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    basis(k, 0) = 1.0;
    basis(k, 1) = std::cos(omega * t[k]);
    basis(k, 2) = std::sin(omega * t[k]);
    values(k) = y[k];
  }
  // A QR of the basis itself, not the normal equations: over a whole number of
  // periods the columns are near-orthogonal, but over a short window they are not.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(basis);
  if (qr.rank() < 3)
    throw std::invalid_argument("fit_harmonic: the samples cannot separate mean, cosine and sine");
  const Eigen::Vector3d c = qr.solve(values);
  HarmonicFit fit;
  fit.mean = c(0);
  fit.amplitude = {c(1), -c(2)};  // a cos + b sin = Re((a - i b) e^{i omega t})
  fit.samples = t.size();
  const double misfit = (basis * c - values).norm() / std::sqrt(static_cast<double>(n));
  fit.residual = misfit / std::abs(fit.amplitude);
  return fit;
}

std::size_t last_periods_start(std::span<const double> t, double omega, double periods) {
  if (t.empty()) return 0;
  const double span = periods * 2.0 * std::numbers::pi / omega;
  // The window is (t_end - span, t_end]: a sample at its start has the phase of
  // t_end and would count that phase twice. Rounding must not let it in.
  const double from = t.back() - span * (1.0 - 1e-9);
  // Covered if the record reaches back to the window's start, the first sample
  // standing for the step that led to it (a run's first solve is at t = dt).
  const double first_step = t.size() > 1 ? t[1] - t[0] : 0.0;
  if (t.front() - first_step > from) return t.size();
  std::size_t k = t.size();
  while (k > 0 && t[k - 1] > from) --k;
  return k;
}

std::complex<double> complex_modulus(std::complex<double> stress, std::complex<double> shear_rate,
                                     double omega) {
  return std::complex<double>(0.0, omega) * stress / shear_rate;
}

}  // namespace softflow::analysis
