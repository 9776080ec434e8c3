// A matrix stored in hypre's own format, for BoomerAMG to take as it is.
#pragma once

#include <span>
#include <vector>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// hypre's compressed-row arrays of this rank's rows of a MATHYPRE,
/// borrowed (valid while the matrix lives and its pattern is unchanged).
/// As PETSc's AIJ, hypre keeps the columns of this rank's column range
/// ("diagonal" part, local numbers) apart from the others ("off-diagonal",
/// positions in the sorted global list global_of_off_diagonal).
struct ParCsrArrays {
  const PetscInt* diagonal_start = nullptr;
  const PetscInt* diagonal_columns = nullptr;
  PetscScalar* diagonal_values = nullptr;
  const PetscInt* off_diagonal_start = nullptr;
  const PetscInt* off_diagonal_columns = nullptr;
  PetscScalar* off_diagonal_values = nullptr;
  const PetscInt* global_of_off_diagonal = nullptr;
};

/// A square MATHYPRE holding exactly the given pattern of this rank's rows
/// (`row_start`: CSR row pointers; `columns`: global, sorted within each
/// row), all zeros. Each row's diagonal part starts with the row's own
/// column when the pattern has it (hypre's rule: its smoothers read the
/// diagonal there), then the rest ascending; the off-diagonal part is
/// ascending. Built directly in hypre's arrays: no PETSc copy, ever.
/// Collective.
Matrix create_hypre_matrix(OwnershipRange rows, PetscInt n_global,
                           const std::vector<PetscInt>& row_start,
                           const std::vector<PetscInt>& columns);

/// The arrays of a matrix made by create_hypre_matrix.
ParCsrArrays parcsr_arrays(Mat hypre_matrix);

/// Replaces the rows and columns `rows` (global, owned here) by
/// those of the identity times `diagonal`, keeping the pattern; what
/// MatZeroRowsColumns does, in one pass over the entries (hypre's own
/// elimination, behind MATHYPRE's MatZeroRowsColumns, searches the row list
/// for every entry: +35 % on the Stokes assembly at 152k unknowns).
/// Collective.
void zero_rows_columns(Mat hypre_matrix, std::span<const PetscInt> rows, PetscScalar diagonal);

}  // namespace softflow::la
