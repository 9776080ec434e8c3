// A preconditioner followed by an exact solve on a block of its unknowns.
#pragma once

#include <vector>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// Makes `pc` a shell preconditioner: `smoother` (e.g. BoomerAMG) on the
/// whole space, then an exact solve on the block I of the unknowns `rows`
/// for what the smoother left,
///   y = S r,   y_I += (P_II)^{-1} (r - A y)_I,
/// A and P the pc's operator and preconditioning matrix, P_II factored
/// (MUMPS LU) at each setup. For a few stiff rows that AMG cannot coarsen
/// (a penalty coupling the components of a vector field along a surface)
/// and that are few enough to factor. `rows`: this rank's positions in
/// the pc's vectors (local, ascending). While `*active` is false the block
/// is neither factored nor solved: `pc` is the smoother alone (the owner
/// switches it where it pays; the pointee must outlive `pc`). `pc` takes
/// over `smoother`.
void make_block_corrected(PC pc, PC smoother, std::vector<PetscInt> rows, const bool* active);

}  // namespace softflow::la
