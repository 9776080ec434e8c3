// One assembly path for every sparse matrix: element blocks in coordinate format.
#pragma once

#include <span>
#include <vector>

#include <Eigen/Core>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// A distributed AIJ matrix assembled from dense element blocks.
///
/// The (row, column) list of every block is handed to PETSc once
/// (MatSetPreallocationCOO); each later assembly fills a value buffer in the
/// same order and passes it in one call (MatSetValuesCOO), and PETSc sums
/// repeated entries and routes off-rank rows itself. MatSetValues, by
/// contrast, searches every row for every entry (~40 ns an entry measured,
/// 5x the Stokes element kernels).
///
/// Rows or columns given as -1 are dropped (PETSc ignores negative COO
/// indices): one element matrix can feed several blocks of a partitioned
/// operator, e.g. free-free and free-prescribed, by passing index lists in
/// which the other kind is -1.
///
/// Usage: add_block() for every element, then create(); per assembly,
/// set_block() for every element (any order) and assemble().
class CooMatrix {
 public:
  /// Handle of one block: the offset of its first value in the buffer.
  using Block = std::size_t;

  CooMatrix(OwnershipRange rows, PetscInt n_global_rows, OwnershipRange columns,
            PetscInt n_global_columns);

  /// Declares a dense block with these global rows and columns (any
  /// integer type: dof maps use int, PETSc may be built with 64-bit PetscInt).
  template <class Index>
  Block add_block(std::span<const Index> rows, std::span<const Index> columns) {
    const Block b = rows_.size();
    for (Index r : rows)
      for (Index c : columns) {
        rows_.push_back(static_cast<PetscInt>(r));
        columns_.push_back(static_cast<PetscInt>(c));
      }
    return b;
  }
  /// Builds the PETSc matrix with the declared pattern. Collective.
  void create();

  /// Stores the values of block b. Any Eigen matrix of the block's shape,
  /// in any storage order: entries are read as (row i, column j), so
  /// non-symmetric element matrices (SUPG, convection) land correctly.
  template <class Derived>
  void set_block(Block b, const Eigen::MatrixBase<Derived>& values) {
    PetscScalar* out = values_.data() + b;
    for (Eigen::Index i = 0; i < values.rows(); ++i)
      for (Eigen::Index j = 0; j < values.cols(); ++j) *out++ = values(i, j);
  }
  /// Zeros every stored value (before a partial refill).
  void zero_values();
  /// Passes the stored values to the matrix (replacing its entries). Collective.
  void assemble();

  [[nodiscard]] Mat get() const { return matrix_.get(); }
  /// Hands the assembled matrix over (for operators assembled once; the
  /// value buffer is freed with this object).
  Matrix release() { return std::move(matrix_); }
  [[nodiscard]] std::size_t n_entries() const { return n_entries_; }

 private:
  OwnershipRange row_range_, column_range_;
  PetscInt n_rows_, n_columns_;
  std::size_t n_entries_ = 0;
  std::vector<PetscInt> rows_, columns_;  // until create(): PETSc keeps its own map
  std::vector<PetscScalar> values_;
  Matrix matrix_;
};

}  // namespace softflow::la
