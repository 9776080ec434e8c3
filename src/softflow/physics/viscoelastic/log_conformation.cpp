#include "softflow/physics/viscoelastic/log_conformation.hpp"

#include <cmath>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

// The decomposition in the eigenbasis of s: M = W + B~ + N~ Lambda^{-1}.
struct EigenbasisDecomposition {
  Mat3 w = Mat3::Zero();      // antisymmetric
  Mat3 b = Mat3::Zero();      // symmetric; diagonal unless eigenvalues coincide
  Mat3 n = Mat3::Zero();      // antisymmetric
  Mat3 w_gap = Mat3::Zero();  // W_ij (sigma_j - sigma_i): the entries of W s~ - s~ W
};

EigenbasisDecomposition decompose(const Mat3& velocity_gradient, const SymmetricEigen& s) {
  const Mat3& r = s.vectors;
  const Mat3 m = r.transpose() * velocity_gradient * r;
  const Vec3& sigma = s.values;
  EigenbasisDecomposition d;
  for (int i = 0; i < 3; ++i) d.b(i, i) = m(i, i);
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      // Ascending eigenvalues: delta >= 0 up to round-off.
      const double delta = sigma(j) - sigma(i);
      double w = 0.0, n = 0.0, w_gap = 0.0;
      if (std::abs(delta) <= kDegenerateLogGap) {
        // (Nearly) equal eigenvalues: the rotation/stretch split of the
        // plane's block of M (header comment); N~_ij = 0.
        w = 0.5 * (m(i, j) - m(j, i));
        d.b(i, j) = d.b(j, i) = 0.5 * (m(i, j) + m(j, i));
        w_gap = w * delta;
      } else {
        // W_ij = (Lambda_j M_ij + Lambda_i M_ji) / (Lambda_j - Lambda_i),
        // divided through by Lambda_j = exp(sigma_j) so that nothing
        // overflows: (M_ij + e^{-delta} M_ji) / (1 - e^{-delta}), the
        // denominator by expm1 to keep its digits at small gaps.
        const double e = std::exp(-delta);
        const double one_minus_e = -std::expm1(-delta);
        w = (m(i, j) + e * m(j, i)) / one_minus_e;
        // N~_ij = Lambda_j (M_ij - W_ij).
        n = std::exp(sigma(j)) * (m(i, j) - w);
        // W_ij * delta: the DK divided difference, delta / (1 - e^{-delta}) -> 1.
        w_gap = (m(i, j) + e * m(j, i)) * (delta / one_minus_e);
      }
      d.w(i, j) = w;
      d.w(j, i) = -w;
      d.n(i, j) = n;
      d.n(j, i) = -n;
      // (W s~ - s~ W)_ij = W_ij (sigma_j - sigma_i), symmetric in (i, j).
      d.w_gap(i, j) = d.w_gap(j, i) = w_gap;
    }
  }
  return d;
}

}  // namespace

FattalKupferman fattal_kupferman(const Mat3& velocity_gradient,
                                 const SymmetricEigen& log_conformation) {
  const auto d = decompose(velocity_gradient, log_conformation);
  const Mat3& r = log_conformation.vectors;
  return {r * d.w * r.transpose(), r * d.b * r.transpose(), r * d.n * r.transpose()};
}

FattalKupferman fattal_kupferman(const Mat3& velocity_gradient, const Mat3& log_conformation) {
  return fattal_kupferman(velocity_gradient, symmetric_eigen(log_conformation));
}

Mat3 relaxation_function(double mobility, const SymmetricEigen& log_conformation) {
  // The Giesekus law's own g at lambda = 1 (giesekus.cpp).
  const auto law = Constitutive::giesekus(0.0, 1.0, 1.0, mobility);
  return from_eigen(log_conformation.vectors, law.law().log_relaxation(log_conformation.values));
}

Mat3 log_conformation_rate(const Constitutive& model, const Mat3& velocity_gradient,
                           const Mat3& log_conformation) {
  if (!model.has_conformation())
    throw Error("log_conformation_rate: a Newtonian phase has no conformation tensor");
  const auto s = symmetric_eigen(log_conformation);
  const auto d = decompose(velocity_gradient, s);
  // (*) in the eigenbasis: (W s~ - s~ W) + 2 B~ + diag(g_i) / lambda, the
  // last the model's own (ConstitutiveLaw::log_relaxation).
  Mat3 rate = d.w_gap + 2.0 * d.b;
  if (model.relaxes()) rate.diagonal() += model.law().log_relaxation(s.values);
  return s.vectors * rate * s.vectors.transpose();
}

}  // namespace softflow::physics::viscoelastic
