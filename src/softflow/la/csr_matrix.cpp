#include "softflow/la/csr_matrix.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/la/hypre_matrix.hpp"

namespace softflow::la {

namespace {
/// PETSc's own compressed-row arrays of a sequential AIJ part (row starts,
/// column indices; no copy), lent until restore_structure.
void get_structure(Mat m, const PetscInt** start, const PetscInt** index) {
  PetscInt n = 0;
  PetscBool done = PETSC_FALSE;
  check(MatGetRowIJ(m, 0, PETSC_FALSE, PETSC_FALSE, &n, start, index, &done), "MatGetRowIJ");
  if (!done) throw SolverError("CsrMatrix: PETSc gave no row structure");
}
PetscErrorCode restore_structure(Mat m, const PetscInt* start, const PetscInt* index) {
  PetscInt n = 0;
  PetscBool done = PETSC_FALSE;
  return MatRestoreRowIJ(m, 0, PETSC_FALSE, PETSC_FALSE, &n, &start, &index, &done);
}
void check_mpi(int code, const char* what) {
  if (code != MPI_SUCCESS) throw SolverError(fmt::format("CsrMatrix: {} failed ({})", what, code));
}
// Rows are gathered in chunks of at most this many entries with repeats
// (each nonzero comes once per element sharing it), so that building the
// pattern never holds the whole repeated list: 64 MB at 4-byte indices.
constexpr std::size_t kChunkEntries = std::size_t{1} << 24;
}  // namespace

CsrMatrix::CsrMatrix(OwnershipRange rows, PetscInt n_global_rows, OwnershipRange columns,
                     PetscInt n_global_columns)
    : row_range_(rows), column_range_(columns), n_rows_(n_global_rows),
      n_columns_(n_global_columns) {}

CsrMatrix::~CsrMatrix() {
  // An assembly interrupted by an exception still holds PETSc's arrays.
  if (open_ && format_ == Format::petsc_aij) {
    MatSeqAIJRestoreArray(diagonal_, &diagonal_values_);
    if (off_diagonal_) MatSeqAIJRestoreArray(off_diagonal_, &off_diagonal_values_);
    restore_structure(diagonal_, nullptr, diagonal_columns_);  // errors ignored: a destructor
    if (off_diagonal_) restore_structure(off_diagonal_, nullptr, off_diagonal_columns_);
  }
}

void CsrMatrix::exchange_remote_rows() {
  // Rows declared here but owned elsewhere: their owner must have their
  // columns in its pattern. Sent as [row, n, n columns] records.
  const int size = mpi_size();
  std::vector<PetscInt> ends(size);
  const PetscInt end = row_range_.end;
  check_mpi(MPI_Allgather(&end, 1, MPIU_INT, ends.data(), 1, MPIU_INT, PETSC_COMM_WORLD),
        "MPI_Allgather");
  std::vector<std::vector<PetscInt>> outgoing(size);
  for (const BlockLayout& block : blocks_) {
    const PetscInt* rows = indices_.data() + block.indices;
    const PetscInt* columns = rows + block.n_rows;
    for (std::uint32_t i = 0; i < block.n_rows; ++i) {
      const PetscInt r = rows[i];
      if (r < 0 || row_range_.owns(r)) continue;
      const int owner = static_cast<int>(std::upper_bound(ends.begin(), ends.end(), r) - ends.begin());
      auto& out = outgoing.at(owner);
      out.push_back(r);
      const std::size_t n_at = out.size();
      out.push_back(0);
      for (std::uint32_t j = 0; j < block.n_columns; ++j)
        if (columns[j] >= 0) out.push_back(columns[j]);
      out[n_at] = static_cast<PetscInt>(out.size() - n_at - 1);
    }
  }
  std::vector<int> send_counts(size), receive_counts(size), send_at(size, 0), receive_at(size, 0);
  std::vector<PetscInt> send;
  for (int p = 0; p < size; ++p) {
    send_at[p] = static_cast<int>(send.size());
    send_counts[p] = static_cast<int>(outgoing[p].size());
    send.insert(send.end(), outgoing[p].begin(), outgoing[p].end());
  }
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT,
                     PETSC_COMM_WORLD), "MPI_Alltoall");
  int total = 0;
  for (int p = 0; p < size; ++p) {
    receive_at[p] = total;
    total += receive_counts[p];
  }
  received_.resize(total);
  check_mpi(MPI_Alltoallv(send.data(), send_counts.data(), send_at.data(), MPIU_INT, received_.data(),
                      receive_counts.data(), receive_at.data(), MPIU_INT, PETSC_COMM_WORLD),
        "MPI_Alltoallv");
  int any = 0;
  const int mine = send.empty() ? 0 : 1;
  check_mpi(MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD), "MPI_Allreduce");
  any_remote_ = any != 0;
}

void CsrMatrix::build_pattern(std::vector<PetscInt>& row_start, std::vector<PetscInt>& columns) const {
  const auto n_local = static_cast<std::size_t>(row_range_.size());
  // Visits every (owned local row, valid column) pair with repeats: the
  // blocks declared here and the rows other ranks declared for us.
  auto for_each_entry = [&](auto&& visit) {
    for_each_owned_entry(visit);
    for (std::size_t at = 0; at < received_.size(); at += 2 + received_[at + 1]) {
      const auto local = static_cast<std::size_t>(received_[at] - row_range_.begin);
      for (PetscInt k = 0; k < received_[at + 1]; ++k) visit(local, received_[at + 2 + k]);
    }
  };
  std::vector<std::size_t> repeats(n_local, 0);
  for_each_entry([&](std::size_t local, PetscInt) { ++repeats[local]; });

  row_start.assign(n_local + 1, 0);
  columns.clear();
  std::vector<std::size_t> cursor;
  std::vector<PetscInt> chunk;
  for (std::size_t lo = 0; lo < n_local;) {
    std::size_t hi = lo, n = 0;
    while (hi < n_local && (hi == lo || n + repeats[hi] <= kChunkEntries)) n += repeats[hi++];
    cursor.assign(hi - lo + 1, 0);
    for (std::size_t r = lo; r < hi; ++r) cursor[r - lo + 1] = cursor[r - lo] + repeats[r];
    chunk.resize(n);
    for_each_entry([&](std::size_t local, PetscInt c) {
      if (local >= lo && local < hi) chunk[cursor[local - lo]++] = c;
    });
    std::size_t begin = 0;
    for (std::size_t r = lo; r < hi; ++r) {
      const auto first = chunk.begin() + static_cast<std::ptrdiff_t>(begin);
      const auto last = first + static_cast<std::ptrdiff_t>(repeats[r]);
      std::sort(first, last);
      columns.insert(columns.end(), first, std::unique(first, last));
      row_start[r + 1] = static_cast<PetscInt>(columns.size());
      begin += repeats[r];
    }
    lo = hi;
  }
}

void CsrMatrix::create() {
  exchange_remote_rows();
  std::vector<PetscInt> row_start, columns;
  build_pattern(row_start, columns);
  std::vector<PetscInt>().swap(received_);
  n_local_nonzeros_ = columns.size();
  if (format_ == Format::hypre_parcsr)
    create_in_hypre(row_start, columns);
  else
    create_in_petsc(row_start, columns);
  read_row_layout(row_start, columns);

  // The remote rows' buffers.
  std::size_t n_remote_values = 0;
  for (Block b = 0; b < blocks_.size(); ++b) {
    BlockLayout& block = blocks_[b];
    const PetscInt* rows = indices_.data() + block.indices;
    block.remote = remote_rows_.size();
    for (std::uint32_t i = 0; i < block.n_rows; ++i) {
      if (rows[i] < 0 || row_range_.owns(rows[i])) continue;
      remote_rows_.push_back({b, i, n_remote_values});
      n_remote_values += block.n_columns;
    }
  }
  remote_values_.assign(n_remote_values, 0.0);
}

void CsrMatrix::create_in_hypre(const std::vector<PetscInt>& row_start,
                                const std::vector<PetscInt>& columns) {
  if (row_range_.begin != column_range_.begin || row_range_.end != column_range_.end ||
      n_rows_ != n_columns_)
    throw SolverError("CsrMatrix: the hypre format needs a square matrix with rows and columns "
                      "distributed alike");
  if (any_remote_)
    throw SolverError("CsrMatrix: the hypre format takes no rows of other ranks");
  matrix_ = create_hypre_matrix(row_range_, n_rows_, row_start, columns);
  global_of_off_diagonal_ = parcsr_arrays(matrix_.get()).global_of_off_diagonal;
  check(MatSetBlockSizes(matrix_.get(), row_block_size_, column_block_size_), "MatSetBlockSizes");
  check(MatSetOption(matrix_.get(), MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE), "MatSetOption");
}

void CsrMatrix::create_in_petsc(const std::vector<PetscInt>& row_start,
                                const std::vector<PetscInt>& columns) {
  check(MatCreate(PETSC_COMM_WORLD, matrix_.out()), "MatCreate");
  check(MatSetSizes(matrix_.get(), row_range_.size(), column_range_.size(), n_rows_, n_columns_),
        "MatSetSizes");
  check(MatSetBlockSizes(matrix_.get(), row_block_size_, column_block_size_), "MatSetBlockSizes");
  check(MatSetType(matrix_.get(), MATAIJ), "MatSetType");
  // Exactly our pattern, zeros; only the call for the matrix's type acts.
  check(MatSeqAIJSetPreallocationCSR(matrix_.get(), row_start.data(), columns.data(), nullptr),
        "MatSeqAIJSetPreallocationCSR");
  check(MatMPIAIJSetPreallocationCSR(matrix_.get(), row_start.data(), columns.data(), nullptr),
        "MatMPIAIJSetPreallocationCSR");
  // Dirichlet rows are zeroed between assemblies (MatZeroRows); the pattern
  // must survive that: each assembly walks it.
  check(MatSetOption(matrix_.get(), MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE), "MatSetOption");
  check(MatSetOption(matrix_.get(), MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  check(MatSetOption(matrix_.get(), MAT_NO_OFF_PROC_ENTRIES, any_remote_ ? PETSC_FALSE : PETSC_TRUE),
        "MatSetOption");
  PetscBool distributed = PETSC_FALSE;
  check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(matrix_.get()), MATMPIAIJ, &distributed),
        "PetscObjectTypeCompare");
  if (distributed) {
    check(MatMPIAIJGetSeqAIJ(matrix_.get(), &diagonal_, &off_diagonal_, &global_of_off_diagonal_),
          "MatMPIAIJGetSeqAIJ");
  } else {
    diagonal_ = matrix_.get();
    off_diagonal_ = nullptr;
  }
}

CsrMatrix::Structure CsrMatrix::borrow_structure() const {
  if (format_ == Format::hypre_parcsr) {
    const ParCsrArrays a = parcsr_arrays(matrix_.get());
    return {a.diagonal_start, a.diagonal_columns, a.off_diagonal_start, a.off_diagonal_columns};
  }
  Structure s;
  get_structure(diagonal_, &s.diagonal_start, &s.diagonal_columns);
  if (off_diagonal_) get_structure(off_diagonal_, &s.off_diagonal_start, &s.off_diagonal_columns);
  return s;
}

void CsrMatrix::release_structure(const Structure& s) const {
  if (format_ == Format::hypre_parcsr) return;
  check(restore_structure(diagonal_, s.diagonal_start, s.diagonal_columns), "MatRestoreRowIJ");
  if (off_diagonal_)
    check(restore_structure(off_diagonal_, s.off_diagonal_start, s.off_diagonal_columns),
          "MatRestoreRowIJ");
}

void CsrMatrix::read_row_layout(const std::vector<PetscInt>& row_start,
                                const std::vector<PetscInt>& columns) {
  const Structure stored = borrow_structure();
  const bool has_off_diagonal = stored.off_diagonal_start != nullptr;
  // The stored pattern must be exactly ours: set_block walks the arrays
  // assuming every declared entry is there. A mismatch is a bug, not input.
  const auto n_local = static_cast<std::size_t>(row_range_.size());
  row_layout_.assign(n_local, {});
  std::vector<PetscInt> diagonal_part;  // one row's diagonal-part columns, ascending
  bool same = true;
  for (std::size_t r = 0; r < n_local && same; ++r) {
    const PetscInt* first = columns.data() + row_start[r];
    const PetscInt length = row_start[r + 1] - row_start[r];
    const auto low = static_cast<PetscInt>(std::lower_bound(first, first + length, column_range_.begin) - first);
    const auto high = static_cast<PetscInt>(std::lower_bound(first, first + length, column_range_.end) - first);
    const PetscInt* d = stored.diagonal_columns + stored.diagonal_start[r];
    diagonal_part.assign(d, stored.diagonal_columns + stored.diagonal_start[r + 1]);
    RowLayout& row = row_layout_[r];
    row.diagonal = stored.diagonal_start[r];
    if (format_ == Format::hypre_parcsr && !diagonal_part.empty() &&
        diagonal_part.front() == static_cast<PetscInt>(r)) {
      ++row.diagonal;  // the row's own entry leads: move it to its sorted place
      std::rotate(diagonal_part.begin(), diagonal_part.begin() + 1,
                  std::upper_bound(diagonal_part.begin() + 1, diagonal_part.end(), diagonal_part.front()));
    }
    same = static_cast<PetscInt>(diagonal_part.size()) == high - low;
    for (PetscInt k = low; k < high && same; ++k)
      same = diagonal_part[k - low] + column_range_.begin == first[k];
    const PetscInt n_off = length - (high - low);
    if (!has_off_diagonal) {
      same = same && n_off == 0;
      continue;
    }
    row.off_diagonal = stored.off_diagonal_start[r];
    same = same && stored.off_diagonal_start[r + 1] - stored.off_diagonal_start[r] == n_off;
    for (PetscInt k = 0; k < n_off && same; ++k)
      same = global_of_off_diagonal_[stored.off_diagonal_columns[row.off_diagonal + k]] ==
             first[k < low ? k : k + (high - low)];
  }
  n_diagonal_nonzeros_ = static_cast<std::size_t>(stored.diagonal_start[n_local]);
  n_off_diagonal_nonzeros_ = has_off_diagonal ? static_cast<std::size_t>(stored.off_diagonal_start[n_local]) : 0;
  release_structure(stored);
  if (!same) throw SolverError("CsrMatrix: the matrix stored a pattern other than the one declared");
}

void CsrMatrix::open() {
  if (format_ == Format::hypre_parcsr) {
    const ParCsrArrays a = parcsr_arrays(matrix_.get());
    diagonal_columns_ = a.diagonal_columns;
    diagonal_values_ = a.diagonal_values;
    off_diagonal_columns_ = a.off_diagonal_columns;
    off_diagonal_values_ = a.off_diagonal_values;
  } else {
    const PetscInt* start = nullptr;  // row_layout_ has each row's start
    get_structure(diagonal_, &start, &diagonal_columns_);
    if (off_diagonal_) get_structure(off_diagonal_, &start, &off_diagonal_columns_);
    check(MatSeqAIJGetArray(diagonal_, &diagonal_values_), "MatSeqAIJGetArray");
    if (off_diagonal_)
      check(MatSeqAIJGetArray(off_diagonal_, &off_diagonal_values_), "MatSeqAIJGetArray");
  }
  std::fill_n(diagonal_values_, n_diagonal_nonzeros_, 0.0);
  if (n_off_diagonal_nonzeros_ > 0) std::fill_n(off_diagonal_values_, n_off_diagonal_nonzeros_, 0.0);
  std::fill(remote_values_.begin(), remote_values_.end(), 0.0);
  open_ = true;
}

void CsrMatrix::assemble() {
  if (!open_) open();
  open_ = false;
  if (format_ == Format::petsc_aij) {
    check(MatSeqAIJRestoreArray(diagonal_, &diagonal_values_), "MatSeqAIJRestoreArray");
    if (off_diagonal_)
      check(MatSeqAIJRestoreArray(off_diagonal_, &off_diagonal_values_), "MatSeqAIJRestoreArray");
    check(restore_structure(diagonal_, nullptr, diagonal_columns_), "MatRestoreRowIJ");
    if (off_diagonal_)
      check(restore_structure(off_diagonal_, nullptr, off_diagonal_columns_), "MatRestoreRowIJ");
  }
  diagonal_columns_ = off_diagonal_columns_ = nullptr;
  for (const RemoteRow& remote : remote_rows_) {
    const BlockLayout& block = blocks_[remote.block];
    const PetscInt* row = indices_.data() + block.indices + remote.row;
    const PetscInt* columns = indices_.data() + block.indices + block.n_rows;
    // Negative columns are ignored by PETSc.
    check(MatSetValues(matrix_.get(), 1, row, static_cast<PetscInt>(block.n_columns), columns,
                       remote_values_.data() + remote.values, ADD_VALUES),
          "MatSetValues");
  }
  // hypre: the values are in place already; assembling moves the matrix's
  // state (so preconditioners see the change) and does nothing else.
  check(MatAssemblyBegin(matrix_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  check(MatAssemblyEnd(matrix_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
}

void CsrMatrix::zero_rows_columns(std::span<const PetscInt> rows, PetscScalar diagonal) {
  if (format_ == Format::hypre_parcsr) {
    la::zero_rows_columns(matrix_.get(), rows, diagonal);
    // The values changed in place; assembling (nothing to do for hypre)
    // moves the state, so solvers see the change.
    check(MatAssemblyBegin(matrix_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(matrix_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
    return;
  }
  check(MatZeroRowsColumns(matrix_.get(), static_cast<PetscInt>(rows.size()), rows.data(), diagonal,
                           nullptr, nullptr),
        "MatZeroRowsColumns");
}

Matrix CsrMatrix::release() {
  diagonal_ = off_diagonal_ = nullptr;
  return std::move(matrix_);
}

}  // namespace softflow::la
