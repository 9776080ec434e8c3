// Functions of symmetric 3x3 tensors by eigen-projection: the spectral
// decomposition, log and exp (the maps c = exp(s), s = log c of the
// log-conformation method, SPEC §2 part 5).
#pragma once

#include <Eigen/Core>

namespace softflow::physics::viscoelastic {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

/// a = R diag(values) R^T with R orthogonal (its columns are the unit
/// eigenvectors) and the values ascending.
struct SymmetricEigen {
  Vec3 values;
  Mat3 vectors;  ///< R
};

/// R diag(values) R^T, exactly symmetric: the inverse of symmetric_eigen,
/// and the way every function of a symmetric tensor is applied,
/// f(a) = R diag(f(values)) R^T.
[[nodiscard]] Mat3 from_eigen(const Mat3& vectors, const Vec3& values);

/// The spectral decomposition of a symmetric tensor, by Eigen's iterative
/// (tridiagonal QL) solver rather than its closed-form 3x3 one: the closed
/// form loses eigenvector accuracy when eigenvalues nearly coincide, which
/// is exactly the state c = I every flow starts from. Throws softflow::Error
/// if an entry is not finite or the tensor is not symmetric to a relative
/// 1e-10 (max-norm); the symmetric part is decomposed.
[[nodiscard]] SymmetricEigen symmetric_eigen(const Mat3& a);

/// log c = R diag(log Lambda_i) R^T for symmetric positive definite c.
/// Throws softflow::Error naming the smallest eigenvalue if c is not
/// positive definite, or as symmetric_eigen.
[[nodiscard]] Mat3 matrix_log(const Mat3& c);

/// exp s = R diag(exp sigma_i) R^T for symmetric s (any sign); SPD result.
/// Throws as symmetric_eigen.
[[nodiscard]] Mat3 matrix_exp(const Mat3& s);

}  // namespace softflow::physics::viscoelastic
