// One assembly path for every sparse matrix: dense element blocks summed
// into a fixed compressed-row pattern, in place.
#pragma once

#include <cassert>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// A distributed sparse matrix assembled from dense element blocks.
///
/// Every block's rows and columns are declared once (add_block); create()
/// builds the compressed-row pattern of this rank's rows from them and
/// hands it to PETSc (AIJ) or hypre (ParCSR, see Format). Each assembly
/// then adds the blocks' values straight into the library's own value
/// arrays: a block's columns are sorted once, and each of its rows is
/// walked along the stored (sorted) row in one pass. No coordinate list,
/// no value buffer, nothing stored per element entry.
///
/// Why not keep each element entry's position in its row (2 bytes an entry,
/// what this class did before): 0.47 kB per unknown for P2/P1 Stokes, a
/// tenth of the iterative solver's memory at 1M unknowns, to save a merge
/// of 30 short sorted lists per element (measured: +20-25 % assembly time,
/// 0.08 -> 0.10 s at 34k, 0.39 -> 0.47 s at 152k; the solve takes 6 s there).
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
                       static_cast<std::uint32_t>(columns.size()), 0});
    for (Index r : rows) indices_.push_back(static_cast<PetscInt>(r));
    for (Index c : columns) indices_.push_back(static_cast<PetscInt>(c));
    return blocks_.size() - 1;
  }
  /// Rows (columns) come in groups of this many, e.g. 3 velocity
  /// components of a node: BoomerAMG then coarsens each component apart
  /// (PCHYPRE reads the block size). Before create().
  void set_block_sizes(PetscInt rows, PetscInt columns) {
    row_block_size_ = rows;
    column_block_size_ = columns;
  }
  /// How the values are stored. petsc_aij: PETSc's AIJ. hypre_parcsr:
  /// hypre's ParCSR inside a MATHYPRE, for a square matrix that BoomerAMG
  /// preconditions: PCHYPRE takes it as it is, where from AIJ it builds a
  /// copy as large as the matrix (the velocity block of P2/P1 Stokes: ~1 kB
  /// per unknown, a third of the iterative solver's peak at 934k unknowns).
  /// The matrix then multiplies through hypre and must not take rows of
  /// other ranks. Before create().
  enum class Format { petsc_aij, hypre_parcsr };
  void set_format(Format format) { format_ = format; }
  /// Builds the matrix with the declared pattern (all zeros). Collective.
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
    sort_columns(block);
    std::size_t remote = block.remote;
    for (std::uint32_t i = 0; i < block.n_rows; ++i) {
      const PetscInt r = rows[i];
      if (r < 0) continue;
      if (!row_range_.owns(r)) {  // summed by PETSc at assemble()
        PetscScalar* out = remote_values_.data() + remote_rows_[remote++].values;
        for (std::uint32_t j = 0; j < block.n_columns; ++j) out[j] += values(i, j);
        continue;
      }
      // PETSc's row: this rank's columns (local numbers) in one array, the
      // others (positions in the sorted global list garray) in another,
      // each sorted; the block's sorted columns advance through both.
      const RowLayout& row = row_layout_[r - row_range_.begin];
      const PetscInt* diagonal = diagonal_columns_ + row.diagonal;
      PetscScalar* diagonal_value = diagonal_values_ + row.diagonal;
      // hypre keeps the row's own entry first, before the sorted rest.
      const PetscInt own = format_ == Format::hypre_parcsr ? r - row_range_.begin : -1;
      const PetscInt* off_diagonal = off_diagonal_columns_ + row.off_diagonal;
      PetscScalar* off_diagonal_value = off_diagonal_values_ + row.off_diagonal;
      for (const auto& [column, j] : sorted_columns_) {
        if (column_range_.owns(column)) {
          const PetscInt local = column - column_range_.begin;
          if (local == own) {
            diagonal_values_[row.diagonal - 1] += values(i, j);
            continue;
          }
          while (*diagonal < local) ++diagonal, ++diagonal_value;
          assert(*diagonal == local);
          *diagonal_value += values(i, j);
        } else {
          while (global_of_off_diagonal_[*off_diagonal] < column) ++off_diagonal, ++off_diagonal_value;
          assert(global_of_off_diagonal_[*off_diagonal] == column);
          *off_diagonal_value += values(i, j);
        }
      }
    }
  }
  /// Passes the values added since the last assembly to the matrix
  /// (replacing its entries; none added = a zero matrix). Collective.
  void assemble();

  /// Replaces the owned rows and columns `rows` (global, any order) by those
  /// of the identity times `diagonal` (Dirichlet data eliminated
  /// symmetrically); the pattern stays for the next assembly. Collective.
  void zero_rows_columns(std::span<const PetscInt> rows, PetscScalar diagonal);

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
    std::size_t remote;   ///< its first row in remote_rows_
  };
  /// Where an owned row's entries live in PETSc's arrays. PETSc stores a
  /// row's columns of this rank's column range ("diagonal" part) apart
  /// from the others, each part sorted by global column.
  struct RowLayout {
    /// First entry in each array (hypre_parcsr: of the diagonal part after
    /// the row's own entry, which sits just before).
    PetscInt diagonal = 0, off_diagonal = 0;
  };
  struct RemoteRow {
    Block block;
    std::uint32_t row;   ///< within the block
    std::size_t values;  ///< first of the block's n_columns values in remote_values_
  };

  /// sorted_columns_ = block b's valid columns (column, position), sorted.
  void sort_columns(const BlockLayout& block) {
    const PetscInt* columns = indices_.data() + block.indices + block.n_rows;
    sorted_columns_.clear();
    for (std::uint32_t j = 0; j < block.n_columns; ++j)
      if (columns[j] >= 0) sorted_columns_.emplace_back(columns[j], j);
    // A few dozen entries, mostly in runs already (a node's components).
    for (std::size_t k = 1; k < sorted_columns_.size(); ++k)
      for (std::size_t m = k; m > 0 && sorted_columns_[m].first < sorted_columns_[m - 1].first; --m)
        std::swap(sorted_columns_[m], sorted_columns_[m - 1]);
  }
  /// Starts an assembly: takes PETSc's value arrays and zeros them.
  void open();
  /// Calls visit(local row, column) for every declared entry in an owned
  /// row and a valid column, in declaration order.
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
  /// Checks the stored pattern against ours and records each row's layout.
  void read_row_layout(const std::vector<PetscInt>& row_start, const std::vector<PetscInt>& columns);
  /// create() for each format: the matrix with the pattern, zeros.
  void create_in_petsc(const std::vector<PetscInt>& row_start, const std::vector<PetscInt>& columns);
  void create_in_hypre(const std::vector<PetscInt>& row_start, const std::vector<PetscInt>& columns);
  /// The stored row structure (PETSc's arrays borrowed until the matching
  /// release_structure; hypre's directly).
  struct Structure {
    const PetscInt *diagonal_start = nullptr, *diagonal_columns = nullptr;
    const PetscInt *off_diagonal_start = nullptr, *off_diagonal_columns = nullptr;
  };
  Structure borrow_structure() const;
  void release_structure(const Structure& s) const;

  OwnershipRange row_range_, column_range_;
  PetscInt n_rows_, n_columns_;
  PetscInt row_block_size_ = 1, column_block_size_ = 1;
  std::vector<PetscInt> indices_;
  std::vector<BlockLayout> blocks_;
  std::vector<std::pair<PetscInt, std::uint32_t>> sorted_columns_;  // set_block's scratch
  std::vector<RowLayout> row_layout_;
  std::vector<RemoteRow> remote_rows_;
  std::vector<PetscScalar> remote_values_;
  std::vector<PetscInt> received_;  ///< until create(): [row, n, n columns] records
  bool any_remote_ = false;          ///< on any rank
  std::size_t n_local_nonzeros_ = 0, n_diagonal_nonzeros_ = 0, n_off_diagonal_nonzeros_ = 0;
  Mat diagonal_ = nullptr, off_diagonal_ = nullptr;  // PETSc's AIJ parts (not owned)
  PetscScalar* diagonal_values_ = nullptr;
  PetscScalar* off_diagonal_values_ = nullptr;
  // The stored column indices (while open): local columns of the diagonal
  // part; of the off-diagonal part positions in global_of_off_diagonal_.
  const PetscInt* diagonal_columns_ = nullptr;
  const PetscInt* off_diagonal_columns_ = nullptr;
  const PetscInt* global_of_off_diagonal_ = nullptr;  // PETSc's garray, hypre's col_map_offd
  bool open_ = false;
  Format format_ = Format::petsc_aij;
  Matrix matrix_;
};

}  // namespace softflow::la
