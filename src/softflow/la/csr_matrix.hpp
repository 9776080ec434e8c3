// One assembly path for every sparse matrix: dense element blocks summed
// into a fixed compressed-row pattern, in place.
#pragma once

#include <cassert>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// A distributed AIJ matrix assembled from dense element blocks.
///
/// Every block's rows and columns are declared once (add_block); create()
/// builds the compressed-row pattern of this rank's rows from them, hands it
/// to PETSc, and keeps, for each entry of a block, only its offset within
/// its row (2 bytes). Each assembly then adds the blocks' values straight
/// into PETSc's own value arrays: no coordinate list, no value buffer, no
/// search per entry.
///
/// Why not PETSc's coordinate format (MatSetPreallocationCOO, used before):
/// it keeps a permutation of 8 bytes per element entry and a map of 8 bytes
/// per nonzero, and the caller a value buffer of 8 bytes per element entry.
/// For P2/P1 Stokes (each nonzero shared by ~2 elements) that was 4.4 kB per
/// unknown, more than the matrix itself (~1.2 kB). MatSetValues, the other
/// way, searches every row for every entry (~40 ns an entry measured, 5x
/// the Stokes element kernels).
///
/// Rows of other ranks (blocks of elements on the partition boundary) are
/// summed by PETSc at assemble() (MatSetValues, ADD_VALUES); only those few
/// rows keep a value buffer. Rows or columns given as -1 are dropped: one
/// element matrix can feed several blocks of a partitioned operator, e.g.
/// free-free and free-prescribed, by passing index lists in which the other
/// kind is -1.
///
/// Usage: add_block() for every block, then create(); per assembly,
/// set_block() for every contributing block (any order; a block left out
/// contributes nothing, a block set twice counts twice), then assemble().
class CsrMatrix {
 public:
  /// Handle of one block (its declaration index).
  using Block = std::size_t;

  CsrMatrix(OwnershipRange rows, PetscInt n_global_rows, OwnershipRange columns,
            PetscInt n_global_columns);
  ~CsrMatrix();
  CsrMatrix(const CsrMatrix&) = delete;
  CsrMatrix& operator=(const CsrMatrix&) = delete;

  /// Declares a dense block with these global rows and columns (any
  /// integer type: dof maps use int, PETSc may be built with 64-bit PetscInt).
  template <class Index>
  Block add_block(std::span<const Index> rows, std::span<const Index> columns) {
    blocks_.push_back({indices_.size(), static_cast<std::uint32_t>(rows.size()),
                       static_cast<std::uint32_t>(columns.size()), 0, 0});
    for (Index r : rows) indices_.push_back(static_cast<PetscInt>(r));
    for (Index c : columns) indices_.push_back(static_cast<PetscInt>(c));
    return blocks_.size() - 1;
  }
  /// Builds the PETSc matrix with the declared pattern (all zeros). Collective.
  void create();

  /// Adds the values of block b. Any Eigen matrix of the block's shape, in
  /// any storage order: entries are read as (row i, column j), so
  /// non-symmetric element matrices (SUPG, convection) land correctly.
  template <class Derived>
  void set_block(Block b, const Eigen::MatrixBase<Derived>& values) {
    if (!open_) open();
    const BlockLayout& block = blocks_[b];
    assert(values.rows() == block.n_rows && values.cols() == block.n_columns);
    const PetscInt* rows = indices_.data() + block.indices;
    const PetscInt* columns = rows + block.n_rows;
    const std::uint16_t* offset = offsets_.data() + block.offsets;
    std::size_t remote = block.remote;
    for (std::uint32_t i = 0; i < block.n_rows; ++i) {
      const PetscInt r = rows[i];
      if (r < 0) continue;
      if (!row_range_.owns(r)) {  // summed by PETSc at assemble()
        PetscScalar* out = remote_values_.data() + remote_rows_[remote++].values;
        for (std::uint32_t j = 0; j < block.n_columns; ++j) out[j] += values(i, j);
        continue;
      }
      const RowLayout& row = row_layout_[r - row_range_.begin];
      for (std::uint32_t j = 0; j < block.n_columns; ++j)
        if (columns[j] >= 0) entry(row, *offset++) += values(i, j);
    }
  }
  /// Passes the values added since the last assembly to the matrix
  /// (replacing its entries; none added = a zero matrix). Collective.
  void assemble();

  [[nodiscard]] Mat get() const { return matrix_.get(); }
  /// Hands the assembled matrix over (for operators assembled once).
  Matrix release();
  /// Nonzeros of this rank's rows.
  [[nodiscard]] std::size_t n_local_nonzeros() const { return n_local_nonzeros_; }
  /// Whether any rank declared rows another rank owns (summed through
  /// PETSc at each assembly); false when every rank assembles only its own.
  [[nodiscard]] bool rows_cross_ranks() const { return any_remote_; }

 private:
  struct BlockLayout {
    std::size_t indices;  ///< rows, then columns, in indices_
    std::uint32_t n_rows, n_columns;
    std::size_t offsets;  ///< its owned rows' valid entries in offsets_
    std::size_t remote;   ///< its first row in remote_rows_
  };
  /// Where an owned row's entries live in PETSc's arrays. PETSc stores a
  /// row's columns of this rank's column range ("diagonal" part) apart
  /// from the others, each part sorted by global column: the row's global
  /// order is [n_low off-diagonal][n_diagonal diagonal][the rest off-diagonal].
  struct RowLayout {
    PetscInt diagonal = 0, off_diagonal = 0;  ///< first entry in each array
    std::uint16_t n_low = 0, n_diagonal = 0;
  };
  struct RemoteRow {
    Block block;
    std::uint32_t row;   ///< within the block
    std::size_t values;  ///< first of the block's n_columns values in remote_values_
  };

  PetscScalar& entry(const RowLayout& row, unsigned k) {
    if (k < row.n_low) return off_diagonal_values_[row.off_diagonal + k];
    if (k < row.n_low + row.n_diagonal) return diagonal_values_[row.diagonal + k - row.n_low];
    return off_diagonal_values_[row.off_diagonal + k - row.n_diagonal];
  }
  /// Starts an assembly: takes PETSc's value arrays and zeros them.
  void open();
  /// Calls visit(local row, column) for every declared entry in an owned
  /// row and a valid column, in declaration order (offsets_'s order).
  template <class Visit>
  void for_each_owned_entry(Visit&& visit) const {
    for (const BlockLayout& block : blocks_) {
      const PetscInt* rows = indices_.data() + block.indices;
      const PetscInt* columns = rows + block.n_rows;
      for (std::uint32_t i = 0; i < block.n_rows; ++i) {
        if (!row_range_.owns(rows[i])) continue;
        const auto local = static_cast<std::size_t>(rows[i] - row_range_.begin);
        for (std::uint32_t j = 0; j < block.n_columns; ++j)
          if (columns[j] >= 0) visit(local, columns[j]);
      }
    }
  }
  /// Sends the columns of rows declared here but owned by other ranks to
  /// their owners (received_), who need them in their pattern. Collective.
  void exchange_remote_rows();
  /// The sorted, unique columns of every owned row (CSR, local row pointers).
  void build_pattern(std::vector<PetscInt>& row_start, std::vector<PetscInt>& columns) const;
  /// Checks PETSc's stored pattern against ours and records each row's layout.
  void read_row_layout(const std::vector<PetscInt>& row_start, const std::vector<PetscInt>& columns);

  OwnershipRange row_range_, column_range_;
  PetscInt n_rows_, n_columns_;
  std::vector<PetscInt> indices_;
  std::vector<BlockLayout> blocks_;
  std::vector<std::uint16_t> offsets_;
  std::vector<RowLayout> row_layout_;
  std::vector<RemoteRow> remote_rows_;
  std::vector<PetscScalar> remote_values_;
  std::vector<PetscInt> received_;  ///< until create(): [row, n, n columns] records
  bool any_remote_ = false;          ///< on any rank
  std::size_t n_local_nonzeros_ = 0, n_diagonal_nonzeros_ = 0, n_off_diagonal_nonzeros_ = 0;
  Mat diagonal_ = nullptr, off_diagonal_ = nullptr;  // PETSc's parts (not owned)
  PetscScalar* diagonal_values_ = nullptr;
  PetscScalar* off_diagonal_values_ = nullptr;
  bool open_ = false;
  Matrix matrix_;
};

}  // namespace softflow::la
