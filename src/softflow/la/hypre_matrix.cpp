#include "softflow/la/hypre_matrix.hpp"

#include <algorithm>
#include <type_traits>

#include <petscmathypre.h>
// hypre's internal headers: the ParCSR arrays (PETSc's MATHYPRE reads them
// the same way) and the IJ matrix's object, to hand it over to PETSc.
#include <_hypre_IJ_mv.h>
#include <_hypre_parcsr_mv.h>
#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::la {

// hypre's arrays are lent out as PETSc's types: the same integers (Debian
// builds both with 32-bit indices) and doubles.
static_assert(std::is_same_v<HYPRE_Int, PetscInt> && std::is_same_v<HYPRE_BigInt, PetscInt>,
              "hypre and PETSc must use the same integer type");
static_assert(std::is_same_v<HYPRE_Complex, PetscScalar>, "hypre and PETSc scalars differ");

namespace {

void check_hypre(HYPRE_Int code, const char* what) {
  if (code != 0) {
    HYPRE_ClearAllErrors();
    throw SolverError(fmt::format("hypre: {} failed (error {})", what, code));
  }
}

/// Puts each row of the diagonal part in the documented order: its own
/// column first (hypre's assembly swaps it there), the others ascending.
/// The values are all zero still, so only the columns move.
void order_diagonal_part(hypre_CSRMatrix* diagonal) {
  const HYPRE_Int n = hypre_CSRMatrixNumRows(diagonal);
  const HYPRE_Int* start = hypre_CSRMatrixI(diagonal);
  HYPRE_Int* column = hypre_CSRMatrixJ(diagonal);
  for (HYPRE_Int r = 0; r < n; ++r) {
    HYPRE_Int* first = column + start[r];
    HYPRE_Int* last = column + start[r + 1];
    if (first != last && *first == r) ++first;
    std::sort(first, last);
  }
}

}  // namespace

Matrix create_hypre_matrix(OwnershipRange rows, PetscInt n_global,
                           const std::vector<PetscInt>& row_start,
                           const std::vector<PetscInt>& columns) {
  const PetscInt n_local = rows.size();
  std::vector<HYPRE_Int> diagonal_sizes(static_cast<std::size_t>(n_local));
  std::vector<HYPRE_Int> off_diagonal_sizes(static_cast<std::size_t>(n_local));
  PetscInt longest = 0;
  for (PetscInt r = 0; r < n_local; ++r) {
    const PetscInt* first = columns.data() + row_start[r];
    const PetscInt* last = columns.data() + row_start[r + 1];
    const auto in_range = std::count_if(first, last, [&](PetscInt c) { return rows.owns(c); });
    diagonal_sizes[r] = static_cast<HYPRE_Int>(in_range);
    off_diagonal_sizes[r] = static_cast<HYPRE_Int>((last - first) - in_range);
    longest = std::max<PetscInt>(longest, last - first);
  }

  HYPRE_IJMatrix ij = nullptr;
  check_hypre(HYPRE_IJMatrixCreate(PETSC_COMM_WORLD, rows.begin, rows.end - 1, rows.begin,
                                   rows.end - 1, &ij),
              "HYPRE_IJMatrixCreate");
  try {
    check_hypre(HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR), "HYPRE_IJMatrixSetObjectType");
    // Exact sizes: hypre writes each row straight into its final arrays
    // (no auxiliary per-row buffers).
    check_hypre(HYPRE_IJMatrixSetDiagOffdSizes(ij, diagonal_sizes.data(), off_diagonal_sizes.data()),
                "HYPRE_IJMatrixSetDiagOffdSizes");
    check_hypre(HYPRE_IJMatrixInitialize_v2(ij, HYPRE_MEMORY_HOST), "HYPRE_IJMatrixInitialize");
    const std::vector<HYPRE_Complex> zeros(static_cast<std::size_t>(longest), 0.0);
    for (PetscInt r = 0; r < n_local; ++r) {
      HYPRE_Int n = static_cast<HYPRE_Int>(row_start[r + 1] - row_start[r]);
      const HYPRE_BigInt row = rows.begin + r;
      check_hypre(HYPRE_IJMatrixSetValues(ij, 1, &n, &row, columns.data() + row_start[r], zeros.data()),
                  "HYPRE_IJMatrixSetValues");
    }
    check_hypre(HYPRE_IJMatrixAssemble(ij), "HYPRE_IJMatrixAssemble");
  } catch (...) {
    HYPRE_IJMatrixDestroy(ij);
    throw;
  }
  hypre_ParCSRMatrix* parcsr = nullptr;
  check_hypre(HYPRE_IJMatrixGetObject(ij, reinterpret_cast<void**>(&parcsr)), "HYPRE_IJMatrixGetObject");
  // PETSc takes the ParCSR matrix over; the IJ interface that built it goes.
  hypre_IJMatrixObject(ij) = nullptr;
  HYPRE_IJMatrixDestroy(ij);
  order_diagonal_part(hypre_ParCSRMatrixDiag(parcsr));

  Matrix matrix;
  const PetscErrorCode code = MatCreateFromParCSR(parcsr, MATHYPRE, PETSC_OWN_POINTER, matrix.out());
  if (code != 0) {
    // Once PETSc made the matrix it owns the ParCSR (freed with it).
    if (!matrix.get()) hypre_ParCSRMatrixDestroy(parcsr);
    check(code, "MatCreateFromParCSR");
  }
  PetscInt rows_here = 0, global = 0;
  check(MatGetLocalSize(matrix.get(), &rows_here, nullptr), "MatGetLocalSize");
  check(MatGetSize(matrix.get(), &global, nullptr), "MatGetSize");
  if (rows_here != n_local || global != n_global)
    throw SolverError(fmt::format("create_hypre_matrix: hypre made {} of {} rows, not {} of {}",
                                  rows_here, global, n_local, n_global));
  return matrix;
}

ParCsrArrays parcsr_arrays(Mat hypre_matrix) {
  hypre_ParCSRMatrix* parcsr = nullptr;
  check(MatHYPREGetParCSR(hypre_matrix, &parcsr), "MatHYPREGetParCSR");
  hypre_CSRMatrix* diagonal = hypre_ParCSRMatrixDiag(parcsr);
  hypre_CSRMatrix* off_diagonal = hypre_ParCSRMatrixOffd(parcsr);
  ParCsrArrays a;
  a.diagonal_start = hypre_CSRMatrixI(diagonal);
  a.diagonal_columns = hypre_CSRMatrixJ(diagonal);
  a.diagonal_values = hypre_CSRMatrixData(diagonal);
  a.off_diagonal_start = hypre_CSRMatrixI(off_diagonal);
  a.off_diagonal_columns = hypre_CSRMatrixJ(off_diagonal);
  a.off_diagonal_values = hypre_CSRMatrixData(off_diagonal);
  a.global_of_off_diagonal = hypre_ParCSRMatrixColMapOffd(parcsr);
  return a;
}

void zero_rows_columns(Mat hypre_matrix, std::span<const PetscInt> rows, PetscScalar diagonal) {
  hypre_ParCSRMatrix* parcsr = nullptr;
  check(MatHYPREGetParCSR(hypre_matrix, &parcsr), "MatHYPREGetParCSR");
  PetscInt first = 0, end = 0;
  check(MatGetOwnershipRange(hypre_matrix, &first, &end), "MatGetOwnershipRange");
  const auto n = static_cast<std::size_t>(end - first);
  std::vector<HYPRE_Int> prescribed(n, 0);
  for (PetscInt r : rows) {
    if (r < first || r >= end)
      throw SolverError(fmt::format("zero_rows_columns: row {} is not owned here", r));
    prescribed[r - first] = 1;
  }
  // The diagonal part: this rank's rows and columns.
  hypre_CSRMatrix* diagonal_part = hypre_ParCSRMatrixDiag(parcsr);
  const HYPRE_Int* start = hypre_CSRMatrixI(diagonal_part);
  const HYPRE_Int* column = hypre_CSRMatrixJ(diagonal_part);
  HYPRE_Complex* value = hypre_CSRMatrixData(diagonal_part);
  for (std::size_t r = 0; r < n; ++r)
    for (HYPRE_Int k = start[r]; k < start[r + 1]; ++k)
      if (prescribed[r]) value[k] = column[k] == static_cast<HYPRE_Int>(r) ? diagonal : 0.0;
      else if (prescribed[column[k]]) value[k] = 0.0;
  if (mpi_size() == 1) return;  // no off-diagonal part
  // The off-diagonal part: its columns' owners say which are prescribed,
  // through the matrix-vector product's communication pattern.
  hypre_CSRMatrix* off_diagonal = hypre_ParCSRMatrixOffd(parcsr);
  hypre_ParCSRCommPkg* pattern = hypre_ParCSRMatrixCommPkg(parcsr);
  if (!pattern) {
    check_hypre(hypre_MatvecCommPkgCreate(parcsr), "hypre_MatvecCommPkgCreate");
    pattern = hypre_ParCSRMatrixCommPkg(parcsr);
  }
  const HYPRE_Int n_sends = hypre_ParCSRCommPkgNumSends(pattern);
  std::vector<HYPRE_Int> sent(static_cast<std::size_t>(hypre_ParCSRCommPkgSendMapStart(pattern, n_sends)));
  for (std::size_t k = 0; k < sent.size(); ++k)
    sent[k] = prescribed[hypre_ParCSRCommPkgSendMapElmt(pattern, static_cast<HYPRE_Int>(k))];
  std::vector<HYPRE_Int> column_prescribed(static_cast<std::size_t>(hypre_CSRMatrixNumCols(off_diagonal)) + 1, 0);
  // Job 11: integers, forward (as the product sends x's entries).
  hypre_ParCSRCommHandle* handle =
      hypre_ParCSRCommHandleCreate(11, pattern, sent.data(), column_prescribed.data());
  hypre_ParCSRCommHandleDestroy(handle);
  start = hypre_CSRMatrixI(off_diagonal);
  column = hypre_CSRMatrixJ(off_diagonal);
  value = hypre_CSRMatrixData(off_diagonal);
  for (std::size_t r = 0; r < n; ++r)
    for (HYPRE_Int k = start[r]; k < start[r + 1]; ++k)
      if (prescribed[r] || column_prescribed[column[k]]) value[k] = 0.0;
}

}  // namespace softflow::la
