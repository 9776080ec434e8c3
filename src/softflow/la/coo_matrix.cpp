#include "softflow/la/coo_matrix.hpp"

#include <algorithm>

namespace softflow::la {

CooMatrix::CooMatrix(OwnershipRange rows, PetscInt n_global_rows, OwnershipRange columns,
                     PetscInt n_global_columns)
    : row_range_(rows), column_range_(columns), n_rows_(n_global_rows),
      n_columns_(n_global_columns) {}

void CooMatrix::create() {
  check(MatCreate(PETSC_COMM_WORLD, matrix_.out()), "MatCreate");
  check(MatSetSizes(matrix_.get(), row_range_.size(), column_range_.size(), n_rows_, n_columns_),
        "MatSetSizes");
  check(MatSetType(matrix_.get(), MATAIJ), "MatSetType");
  // PETSc may reorder the index arrays and keeps its own map from value
  // positions to nonzeros: the lists are not needed afterwards.
  n_entries_ = rows_.size();
  check(MatSetPreallocationCOO(matrix_.get(), static_cast<PetscCount>(n_entries_), rows_.data(),
                               columns_.data()),
        "MatSetPreallocationCOO");
  // Dirichlet rows are zeroed between assemblies (MatZeroRows); the pattern
  // must survive that, or the next MatSetValuesCOO writes through a stale map.
  check(MatSetOption(matrix_.get(), MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE), "MatSetOption");
  std::vector<PetscInt>().swap(rows_);
  std::vector<PetscInt>().swap(columns_);
  values_.assign(n_entries_, 0.0);
}

void CooMatrix::zero_values() { std::fill(values_.begin(), values_.end(), 0.0); }

void CooMatrix::assemble() {
  check(MatSetValuesCOO(matrix_.get(), values_.data(), INSERT_VALUES), "MatSetValuesCOO");
}

}  // namespace softflow::la
