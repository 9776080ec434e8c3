// A preconditioner with an exact correction on a few coarse vectors.
#pragma once

#include <vector>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// A vector kept as this rank's nonzero entries: local indices and values
/// (a coarse vector supported on part of the domain costs only that part).
struct SparseVector {
  std::vector<PetscInt> index;
  std::vector<PetscScalar> value;
};

/// Makes `pc` a shell two-level preconditioner: an exact (Galerkin) solve on
/// the span of the vectors z_k (the columns of Z), then `smoother` (e.g.
/// BoomerAMG) on what remains,
///   c = E^{-1} Z^T r,  E = Z^T A Z,   y = Z c + S (r - A Z c),
/// A the pc's operator. For modes the smoother misses that Z spans (the
/// rigid motions of a very viscous drop, which cost only the outer fluid's
/// work). Each setup of `pc` sets `smoother` up on pc's operators and forms
/// E and A Z (kept sparse, like Z); an application costs the smoother's
/// plus one reduction of n numbers and sparse updates.
/// `pc` takes over `smoother` (destroyed with it); `basis` must outlive it.
void make_two_level(PC pc, PC smoother, const std::vector<SparseVector>& basis);

}  // namespace softflow::la
