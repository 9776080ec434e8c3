// The first harmonic of a periodic signal by least squares, and the complex modulus
// of a stress against a shear rate (thesis eqs. 4.6-4.7: the moduli of an emulsion).
#pragma once

#include <complex>
#include <cstddef>
#include <span>

namespace softflow::analysis {

/// y(t) ~ mean + Re(amplitude e^{i omega t}) over some samples.
struct HarmonicFit {
  double mean = 0.0;
  std::complex<double> amplitude;
  /// Root-mean-square misfit over |amplitude|: what the first harmonic leaves
  /// unexplained (higher harmonics of a nonlinear response, an undecayed
  /// transient, noise). 0 for an exact sinusoid.
  double residual = 0.0;
  std::size_t samples = 0;
};

/// The least-squares fit of mean + a cos(omega t) + b sin(omega t) to (t_k, y_k),
/// amplitude = a - i b. Samples need not be evenly spaced. Throws
/// std::invalid_argument for fewer than 4 samples, unequal lengths, omega <= 0,
/// or samples that cannot separate the three terms (all within a tiny
/// fraction of a period).
HarmonicFit fit_harmonic(std::span<const double> t, std::span<const double> y, double omega);

/// The first sample of the last `periods` periods 2 pi / omega ending at t.back():
/// the window (t.back() - periods 2 pi / omega, t.back()], so that samples at
/// a constant step with a whole number per period cover each phase once (a
/// sample at the window's start, to a 1e-9 relative tolerance, is left out).
/// t ascending. Returns t.size() when the record does not reach back to the
/// window's start (its first sample counting for the step before it).
std::size_t last_periods_start(std::span<const double> t, double omega, double periods);

/// G* = G' + i G'' of a stress against a shear rate of the same frequency:
/// G* = i omega stress / shear_rate (the strain's amplitude is the rate's over
/// i omega), so a Newtonian liquid, stress = eta shear_rate, has G' = 0 and
/// G'' = eta omega whatever the phase of the forcing.
std::complex<double> complex_modulus(std::complex<double> stress, std::complex<double> shear_rate,
                                     double omega);

}  // namespace softflow::analysis
