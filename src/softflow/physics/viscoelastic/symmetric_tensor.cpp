#include "softflow/physics/viscoelastic/symmetric_tensor.hpp"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::physics::viscoelastic {

namespace {

// Asymmetry allowed in an input, relative to its largest entry: tensors
// assembled as sums of products (L c + c L^T, interpolated P1 fields) are
// symmetric only to round-off, a genuinely asymmetric one is a caller's bug.
constexpr double kSymmetryTolerance = 1e-10;

}  // namespace

Mat3 from_eigen(const Mat3& vectors, const Vec3& values) {
  // The product is symmetric only to round-off; a tensor stored by its six
  // components (s, c) must be exactly so.
  const Mat3 a = vectors * values.asDiagonal() * vectors.transpose();
  return 0.5 * (a + a.transpose());
}

SymmetricEigen symmetric_eigen(const Mat3& a) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(a(i, j)))
        throw Error(
            fmt::format("symmetric tensor with a non-finite entry: a({}, {}) = {}", i, j, a(i, j)));
  const double scale = a.cwiseAbs().maxCoeff();
  const double asymmetry = (a - a.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > kSymmetryTolerance * scale)
    throw Error(
        fmt::format("tensor is not symmetric: max |a_ij - a_ji| = {:g} for "
                    "max |a_ij| = {:g}",
                    asymmetry, scale));
  const Mat3 symmetric = 0.5 * (a + a.transpose());
  const Eigen::SelfAdjointEigenSolver<Mat3> solver(symmetric, Eigen::ComputeEigenvectors);
  if (solver.info() != Eigen::Success)
    throw Error("symmetric eigen-decomposition did not converge");
  return {solver.eigenvalues(), solver.eigenvectors()};
}

Mat3 matrix_log(const Mat3& c) {
  const auto eig = symmetric_eigen(c);
  // Ascending values: the first is the smallest.
  if (!(eig.values(0) > 0.0))
    throw Error(
        fmt::format("log of a tensor that is not positive definite: eigenvalues {:g}, "
                    "{:g}, {:g} (a conformation tensor must stay SPD)",
                    eig.values(0), eig.values(1), eig.values(2)));
  return from_eigen(eig.vectors, eig.values.array().log().matrix());
}

Mat3 matrix_exp(const Mat3& s) {
  const auto eig = symmetric_eigen(s);
  return from_eigen(eig.vectors, eig.values.array().exp().matrix());
}

}  // namespace softflow::physics::viscoelastic
