// The pointwise right-hand side of the log-conformation equation (thesis
// eq. 2.10, SPEC §2 part 5): the Fattal-Kupferman decomposition of the
// velocity gradient and the relaxation term g(s).
//
// With s = log c, c = R Lambda R^T (Lambda = diag(Lambda_i) = exp(sigma_i),
// sigma_i the eigenvalues of s) and L_ij = du_i/dx_j, Fattal & Kupferman
// (J. Non-Newt. Fluid Mech. 123, 2004) write
//
//   L = Omega + B + N c^{-1},   Omega, N antisymmetric, B symmetric, B c = c B,
//
// so that L c + c L^T = (Omega c - c Omega) + 2 B c. In the eigenbasis,
// M = R^T L R and the decomposition becomes, entry by entry (i != j),
//
//   M_ii = B~_ii,   M_ij = W_ij + N~_ij / Lambda_j,   M_ji = -W_ij - N~_ij / Lambda_i,
//
// solved by W_ij = (Lambda_j M_ij + Lambda_i M_ji) / (Lambda_j - Lambda_i),
// N~_ij = Lambda_j (M_ij - W_ij); then B = R diag(M_ii) R^T, Omega = R W R^T.
// The conformation equation (constitutive.hpp)
//
//   dc/dt = L c + c L^T - (1/lambda) ((c - I) + alpha (c - I)^2)
//
// becomes, for s (the relaxation commutes with c, so d(log c) = c^{-1} dc there),
//
//   ds/dt = (Omega s - s Omega) + 2 B + g(s) / lambda,                       (*)
//   g(s)  = R diag((1 - Lambda_i - alpha (Lambda_i - 1)^2) / Lambda_i) R^T,
//
// with g = 0 for the elastic solids. For any model, g(s)/lambda = c^{-1} r(c)
// with r the relaxation of its conformation equation (constitutive.hpp), and
// log_conformation_rate takes its eigenvalues from the model
// (ConstitutiveLaw::log_relaxation; FENE-P: (e^{-sigma_i} - f)/lambda).
// Eq. 2.10's h(grad u, s) is minus the right-hand side of (*), and the convected equation is
// ds/dt + (u - u_m).grad s - (Omega s - s Omega) - 2 B - g(s)/lambda = 0.
//
// Equal eigenvalues. When Lambda_i = Lambda_j, W_ij has a zero denominator:
// c is a multiple of the identity on the plane of e_i, e_j, so any rotation
// of that plane leaves c unchanged (W_ij is indeterminate) and any symmetric
// tensor of that plane commutes with c (B may have an (i, j) entry). The
// natural split of the plane's block of M is then into its antisymmetric
// part, the rotation W_ij = (M_ij - M_ji)/2, and its symmetric part, the
// stretch B~_ij = (M_ij + M_ji)/2, with N~_ij = 0. This is also the correct
// limit of (*): its (i, j) entry in the eigenbasis is, with
// Delta = sigma_j - sigma_i, exactly (the Daleckii-Krein derivative of log)
//
//   W_ij Delta = (Lambda_j M_ij + Lambda_i M_ji) Delta / (Lambda_j - Lambda_i)
//              = (M_ij + M_ji) + Delta (M_ij - M_ji)/2 + Delta^2 (M_ij + M_ji)/12 + O(Delta^3),
//
// and the split above gives 2 B~_ij + W_ij Delta = (M_ij + M_ji) + Delta (M_ij - M_ji)/2:
// the same up to Delta^2 |M| / 6. It is therefore used whenever
// |Delta| <= kDegenerateLogGap (1e-6, an error below 2e-13 |M|), which also
// keeps W, and so Omega, bounded by |M| / kDegenerateLogGap: the generic
// formula divides by Lambda_j - Lambda_i -> 0 and makes the global-frame
// product Omega s - s Omega lose digits as eps |s| |M| / Delta. Above the
// threshold, B commutes with c exactly; below it only to
// kDegenerateLogGap |M| |c|. log_conformation_rate therefore forms (*) in
// the eigenbasis, where W_ij Delta is computed with expm1 and stays exact
// to round-off for every gap; prefer it to building (*) from Omega and B.
#pragma once

#include "softflow/physics/viscoelastic/constitutive.hpp"
#include "softflow/physics/viscoelastic/symmetric_tensor.hpp"

namespace softflow::physics::viscoelastic {

/// Eigenvalue gaps |sigma_j - sigma_i| of s = log c (relative gaps of c)
/// at or below which the pair is treated as equal (see the header comment).
inline constexpr double kDegenerateLogGap = 1e-6;

/// L = omega + b + n c^{-1}, in the global frame.
struct FattalKupferman {
  Mat3 omega;  ///< Omega: antisymmetric, the rotation of c's eigenvectors
  Mat3 b;      ///< B: symmetric, commutes with c; the stretch
  Mat3 n;      ///< N: antisymmetric; drops out of L c + c L^T
};

/// The Fattal-Kupferman decomposition of L (L_ij = du_i/dx_j) at the
/// conformation c = exp(s), given the eigen-decomposition of s.
[[nodiscard]] FattalKupferman fattal_kupferman(const Mat3& velocity_gradient,
                                               const SymmetricEigen& log_conformation);
/// The same, decomposing s first.
[[nodiscard]] FattalKupferman fattal_kupferman(const Mat3& velocity_gradient,
                                               const Mat3& log_conformation);

/// The Giesekus g(s) = R diag((1 - Lambda_i - alpha (Lambda_i - 1)^2) / Lambda_i) R^T,
/// Lambda_i = exp(sigma_i) (alpha = 0: Oldroyd-B/UCM), formed with expm1 so
/// that g stays accurate near c = I (the law of giesekus.cpp at lambda = 1).
[[nodiscard]] Mat3 relaxation_function(double mobility, const SymmetricEigen& log_conformation);

/// ds/dt = (Omega s - s Omega) + 2 B + g(s)/lambda: eq. (*) above, the
/// log-conformation equation without convection, i.e. minus eq. 2.10's
/// h(grad u, s), g(s)/lambda the model's log_relaxation. g = 0 for the
/// solids. Throws softflow::Error for a Newtonian phase, as symmetric_eigen
/// for a non-symmetric s, and SolverError for an s outside the model's
/// domain (FENE-P: tr exp(s) >= L^2).
[[nodiscard]] Mat3 log_conformation_rate(const Constitutive& model, const Mat3& velocity_gradient,
                                         const Mat3& log_conformation);

}  // namespace softflow::physics::viscoelastic
