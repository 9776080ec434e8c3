// Jacobi with an additive coarse-space correction, as a PETSc shell preconditioner.
#pragma once

#include <vector>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// A few vectors z_k and coefficients c_k that correct a preconditioner
/// along the z_k, where it is known to be wrong by a known amount:
///   P^{-1} r = D^{-1} r + sum_k c_k z_k (z_k . r).
/// Vectors in the layout of the preconditioned operator; empty: no correction.
struct CoarseCorrection {
  std::vector<Vector> vectors;
  std::vector<double> coefficients;
  [[nodiscard]] bool empty() const { return vectors.empty(); }
};

/// Makes `pc` a shell preconditioner that applies
///   P^{-1} r = D^{-1} r + sum_k c_k z_k (z_k . r),
/// D the diagonal of its preconditioning matrix (read at every setup, as
/// PCJACOBI does) and (z_k, c_k) from `correction`, read at every
/// application: the owner may update the coefficients between solves.
/// `correction` must outlive the preconditioner's use. The sums z_k . r
/// cost one reduction for all k together.
void make_coarse_corrected_jacobi(PC pc, const CoarseCorrection& correction);

}  // namespace softflow::la
