// la::CsrMatrix, the one assembly path of every operator: blocks summed as
// given (non-symmetric, -1 indices dropped), rows of other ranks summed by
// their owner, each assembly replacing the last, solvers told of new values.
//
// Runs on 1 rank and, as part of mpi_fem_layer, on 2.
#include <array>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <petsc/private/petscimpl.h>  // PetscObjectStateGet: how solvers notice new values

#include "softflow/common/error.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/hypre_matrix.hpp"

using namespace softflow;

namespace {

/// An even split of n indices over the ranks.
la::OwnershipRange even_split(PetscInt n) {
  const PetscInt size = la::mpi_size(), rank = la::mpi_rank();
  return {rank * n / size, (rank + 1) * n / size};
}

/// Every rank's owned rows of a matrix, compared with a dense expectation.
void expect_equal(Mat m, la::OwnershipRange rows, const Eigen::MatrixXd& expected) {
  for (PetscInt i = rows.begin; i < rows.end; ++i)
    for (PetscInt j = 0; j < expected.cols(); ++j) {
      PetscScalar v = 0.0;
      ASSERT_EQ(MatGetValues(m, 1, &i, 1, &j, &v), 0);
      EXPECT_NEAR(v, expected(i, j), 1e-14 * (1.0 + std::abs(expected(i, j)))) << i << "," << j;
    }
}

}  // namespace

TEST(CsrMatrix, AssemblesNonSymmetricBlocksAsGivenAndDropsNegativeIndices) {
  // Two overlapping 3x3 blocks on a 4x4 matrix, one index -1: the result
  // must be their (i, j)-wise sum, not the transpose's.
  const PetscInt n = 4;
  const la::OwnershipRange all{la::mpi_rank() == 0 ? 0 : n, n};  // rank 0 owns every row
  la::CsrMatrix m(all, n, all, n);
  const std::array<PetscInt, 3> rows_a{0, 1, 2}, rows_b{1, -1, 3};
  la::CsrMatrix::Block a{}, b{};
  if (la::mpi_rank() == 0) {
    a = m.add_block(std::span<const PetscInt>(rows_a), std::span<const PetscInt>(rows_a));
    b = m.add_block(std::span<const PetscInt>(rows_b), std::span<const PetscInt>(rows_b));
  }
  m.create();
  Eigen::Matrix3d ka, kb;
  ka << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  kb << 10, 20, 30, 40, 50, 60, 70, 80, 90;
  if (la::mpi_rank() == 0) {
    m.set_block(a, ka);
    m.set_block(b, kb);
  }
  m.assemble();
  Eigen::Matrix4d expected = Eigen::Matrix4d::Zero();
  expected.topLeftCorner<3, 3>() = ka;
  const int map_b[3] = {1, -1, 3};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (map_b[i] >= 0 && map_b[j] >= 0) expected(map_b[i], map_b[j]) += kb(i, j);
  if (la::mpi_rank() == 0)
    for (PetscInt i = 0; i < n; ++i)
      for (PetscInt j = 0; j < n; ++j) {
        PetscScalar v = 0.0;
        ASSERT_EQ(MatGetValues(m.get(), 1, &i, 1, &j, &v), 0);
        EXPECT_EQ(v, expected(i, j)) << i << "," << j;
      }
}

TEST(CsrMatrix, SumsBlocksAcrossRanksAndEachAssemblyReplacesTheLast) {
  // Random blocks over a rectangular 23 x 17 matrix, rows and columns split
  // evenly over the ranks; every rank draws the same blocks and declares
  // every size-th one, so on 2 ranks about half the rows of each rank's
  // blocks belong to the other rank. Some indices are -1.
  const PetscInt n_rows = 23, n_columns = 17;
  const auto rows = even_split(n_rows), columns = even_split(n_columns);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> row_index(-1, n_rows - 1), column_index(-1, n_columns - 1),
      shape(1, 5);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  struct Declared {
    std::vector<PetscInt> rows, columns;
    la::CsrMatrix::Block block = 0;
  };
  std::vector<Declared> mine;
  std::vector<Declared> all;
  la::CsrMatrix m(rows, n_rows, columns, n_columns);
  for (int b = 0; b < 60; ++b) {
    Declared d;
    d.rows.resize(shape(rng));
    d.columns.resize(shape(rng));
    for (auto& r : d.rows) r = row_index(rng);
    for (auto& c : d.columns) c = column_index(rng);
    all.push_back(d);
    if (b % la::mpi_size() == la::mpi_rank()) {
      d.block = m.add_block(std::span<const PetscInt>(d.rows), std::span<const PetscInt>(d.columns));
      mine.push_back(d);
    }
  }
  m.create();
  PetscObjectState before = 0, after = 0;
  for (int assembly = 0; assembly < 2; ++assembly) {
    // The same draws on every rank: every rank knows the whole expectation.
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n_rows, n_columns);
    std::size_t k = 0;
    for (std::size_t b = 0; b < all.size(); ++b) {
      Eigen::MatrixXd block(all[b].rows.size(), all[b].columns.size());
      for (Eigen::Index i = 0; i < block.rows(); ++i)
        for (Eigen::Index j = 0; j < block.cols(); ++j) block(i, j) = value(rng);
      for (Eigen::Index i = 0; i < block.rows(); ++i)
        for (Eigen::Index j = 0; j < block.cols(); ++j)
          if (all[b].rows[i] >= 0 && all[b].columns[j] >= 0)
            expected(all[b].rows[i], all[b].columns[j]) += block(i, j);
      if (static_cast<int>(b) % la::mpi_size() == la::mpi_rank()) m.set_block(mine[k++].block, block);
    }
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &before), 0);
    m.assemble();
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &after), 0);
    EXPECT_NE(before, after) << "a solver would not see the new values";
    expect_equal(m.get(), rows, expected);
  }
  // Nothing set: a zero matrix, not the last one.
  m.assemble();
  expect_equal(m.get(), rows, Eigen::MatrixXd::Zero(n_rows, n_columns));
}

TEST(CsrMatrix, KeepsItsPatternThroughDirichletRowsAndColumns) {
  // A 1D Laplacian from 2 x 2 blocks; rows/columns 0 and n-1 eliminated
  // (MatZeroRowsColumns, as the Stokes and ALE systems do), then assembled
  // again: the second assembly must land on the same entries.
  const PetscInt n = 10;
  const auto range = even_split(n);
  la::CsrMatrix m(range, n, range, n);
  std::vector<la::CsrMatrix::Block> blocks;
  for (PetscInt e = 0; e + 1 < n; ++e)
    if (range.owns(e)) {
      const std::array<PetscInt, 2> d{e, e + 1};
      blocks.push_back(m.add_block(std::span<const PetscInt>(d), std::span<const PetscInt>(d)));
    }
  m.create();
  Eigen::Matrix2d k;
  k << 1, -1, -1, 1;
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n);
  for (PetscInt e = 0; e + 1 < n; ++e) expected.block<2, 2>(e, e) += k;
  for (int assembly = 0; assembly < 2; ++assembly) {
    for (auto b : blocks) m.set_block(b, k);
    m.assemble();
    expect_equal(m.get(), range, expected);
    const std::array<PetscInt, 2> boundary{0, n - 1};
    std::vector<PetscInt> owned;
    for (PetscInt r : boundary)
      if (range.owns(r)) owned.push_back(r);
    ASSERT_EQ(MatZeroRowsColumns(m.get(), static_cast<PetscInt>(owned.size()), owned.data(), 1.0,
                                 nullptr, nullptr),
              0);
  }
}

TEST(CsrMatrix, HypreFormatHoldsTheSameValuesWithEachRowsOwnEntryFirst) {
  // The velocity block's format for BoomerAMG: random element-like blocks
  // (one index list for rows and columns, rows of other ranks dropped as
  // StokesSystem drops them) on 26 x 26. The values must be the same as
  // the dense sum at every assembly; hypre's layout must be the documented
  // one (own entry first in the diagonal part, the rest ascending); the
  // Dirichlet elimination must keep the pattern for the next assembly.
  const PetscInt n = 26;
  const auto range = even_split(n);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> index(-1, n - 1), shape(2, 6);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<std::vector<PetscInt>> all;
  for (int b = 0; b < 40; ++b) {
    std::vector<PetscInt> d(shape(rng));
    for (auto& i : d) i = index(rng);
    all.push_back(d);
  }
  la::CsrMatrix m(range, n, range, n);
  m.set_format(la::CsrMatrix::Format::hypre_parcsr);
  std::vector<la::CsrMatrix::Block> blocks;
  for (const auto& d : all) {
    std::vector<PetscInt> rows = d;
    for (auto& r : rows)
      if (!range.owns(r)) r = -1;
    blocks.push_back(m.add_block(std::span<const PetscInt>(rows), std::span<const PetscInt>(d)));
  }
  m.create();
  PetscBool is_hypre = PETSC_FALSE;
  ASSERT_EQ(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(m.get()), MATHYPRE, &is_hypre), 0);
  EXPECT_TRUE(is_hypre);

  const la::ParCsrArrays a = la::parcsr_arrays(m.get());
  for (PetscInt r = 0; r < range.size(); ++r) {
    const PetscInt first = a.diagonal_start[r], last = a.diagonal_start[r + 1];
    bool own = false;
    for (PetscInt k = first; k < last; ++k) own = own || a.diagonal_columns[k] == r;
    if (own) {
      EXPECT_EQ(a.diagonal_columns[first], r) << "row " << r;
    }
    for (PetscInt k = first + (own ? 2 : 1); k < last; ++k)
      EXPECT_LT(a.diagonal_columns[k - 1], a.diagonal_columns[k]) << "row " << r;
    for (PetscInt k = a.off_diagonal_start[r] + 1; k < a.off_diagonal_start[r + 1]; ++k)
      EXPECT_LT(a.global_of_off_diagonal[a.off_diagonal_columns[k - 1]],
                a.global_of_off_diagonal[a.off_diagonal_columns[k]]) << "row " << r;
  }

  // Owned rows 0 and n-1 and every fifth prescribed.
  std::vector<PetscInt> prescribed;
  for (PetscInt r = range.begin; r < range.end; ++r)
    if (r == 0 || r == n - 1 || r % 5 == 2) prescribed.push_back(r);
  std::vector<char> is_prescribed(n, 0);
  for (PetscInt r = 0; r < n; ++r) is_prescribed[r] = (r == 0 || r == n - 1 || r % 5 == 2);
  PetscObjectState before = 0, after = 0;
  for (int assembly = 0; assembly < 2; ++assembly) {
    Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(n, n);
    for (std::size_t b = 0; b < all.size(); ++b) {
      const auto& d = all[b];
      Eigen::MatrixXd block(d.size(), d.size());
      for (Eigen::Index i = 0; i < block.rows(); ++i)
        for (Eigen::Index j = 0; j < block.cols(); ++j) block(i, j) = value(rng);
      for (std::size_t i = 0; i < d.size(); ++i)
        for (std::size_t j = 0; j < d.size(); ++j)
          if (d[i] >= 0 && d[j] >= 0) expected(d[i], d[j]) += block(i, j);
      m.set_block(blocks[b], block);
    }
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &before), 0);
    m.assemble();
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &after), 0);
    EXPECT_NE(before, after) << "a solver would not see the new values";
    expect_equal(m.get(), range, expected);

    // CsrMatrix's own elimination (hypre's searches the row list per entry);
    // on 2 ranks the prescribed columns of the other rank's rows included.
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &before), 0);
    m.zero_rows_columns(prescribed, 1.0);
    ASSERT_EQ(PetscObjectStateGet(reinterpret_cast<PetscObject>(m.get()), &after), 0);
    EXPECT_NE(before, after) << "a solver would not see the elimination";
    for (PetscInt r = 0; r < n; ++r)
      if (is_prescribed[r]) {
        expected.row(r).setZero();
        expected.col(r).setZero();
        expected(r, r) = 1.0;
      }
    expect_equal(m.get(), range, expected);
  }
}

TEST(CsrMatrix, HypreFormatRefusesWhatItCannotHold) {
  // Not square: refused on every rank.
  const auto rows = even_split(6), columns = even_split(4);
  la::CsrMatrix rectangular(rows, 6, columns, 4);
  rectangular.set_format(la::CsrMatrix::Format::hypre_parcsr);
  EXPECT_THROW(rectangular.create(), SolverError);
  // Rows of another rank: refused on every rank (known to all at create).
  if (la::mpi_size() > 1) {
    const auto range = even_split(8);
    la::CsrMatrix m(range, 8, range, 8);
    m.set_format(la::CsrMatrix::Format::hypre_parcsr);
    const std::array<PetscInt, 2> d{3, 4};  // row 4 on rank 1, row 3 on rank 0
    if (la::mpi_rank() == 0) m.add_block(std::span<const PetscInt>(d), std::span<const PetscInt>(d));
    EXPECT_THROW(m.create(), SolverError);
  }
}
