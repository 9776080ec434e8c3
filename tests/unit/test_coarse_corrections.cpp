// The coarse corrections that make the iterative Stokes preconditioner
// robust in the viscosity ratio: la::make_two_level (an exact solve on a
// few vectors, then a smoother), la::make_coarse_corrected_jacobi (Jacobi
// plus a low-rank term), la::make_block_corrected (a smoother, then an
// exact solve on a block of rows), and the laws that weight them
// (physics/stokes/schur_estimate.hpp). Each preconditioner is applied to a
// vector and compared with the formula evaluated densely.
//
// Runs on 1 rank and, as part of mpi_fem_layer, on 2.
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "softflow/la/block_corrected.hpp"
#include "softflow/la/coarse_corrected_jacobi.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/la/two_level.hpp"
#include "softflow/la/vector_values.hpp"
#include "softflow/physics/stokes/schur_estimate.hpp"

using namespace softflow;

namespace {

constexpr int kSize = 24;

/// This rank's rows: a contiguous block of the kSize.
std::pair<int, int> owned_rows() {
  const int rank = la::mpi_rank(), size = la::mpi_size();
  return {rank * kSize / size, (rank + 1) * kSize / size};
}

/// A random symmetric positive definite matrix with a banded pattern (the
/// same on every rank) and its distributed copy.
Eigen::MatrixXd dense_matrix() {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(kSize, kSize);
  for (int i = 0; i < kSize; ++i)
    for (int j = i + 1; j < std::min(kSize, i + 4); ++j) a(i, j) = a(j, i) = value(random);
  for (int i = 0; i < kSize; ++i) a(i, i) = 4.0 + 2.0 * (1.0 + value(random));
  return a;
}

la::Matrix petsc_matrix(const Eigen::MatrixXd& dense) {
  const auto [first, last] = owned_rows();
  la::Matrix m;
  la::check(MatCreateAIJ(PETSC_COMM_WORLD, last - first, last - first, kSize, kSize, 8, nullptr, 8,
                         nullptr, m.out()),
            "MatCreateAIJ");
  for (int i = first; i < last; ++i)
    for (int j = 0; j < kSize; ++j)
      if (dense(i, j) != 0.0) la::check(MatSetValue(m.get(), i, j, dense(i, j), INSERT_VALUES), "set");
  la::check(MatAssemblyBegin(m.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
  la::check(MatAssemblyEnd(m.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  return m;
}

la::Vector petsc_vector(const Eigen::VectorXd& dense) {
  const auto [first, last] = owned_rows();
  la::Vector v = la::make_vector(last - first, kSize);
  la::scatter_from_all(v.get(), std::span<const double>(dense.data(), kSize));
  return v;
}

Eigen::VectorXd dense_vector(Vec v) {
  const auto all = la::gather_to_all(v);
  return Eigen::Map<const Eigen::VectorXd>(all.data(), static_cast<Eigen::Index>(all.size()));
}

/// Two coarse vectors supported on parts of the rows (overlapping, one
/// crossing the ranks' boundary): dense columns and each rank's sparse part.
Eigen::MatrixXd dense_basis() {
  Eigen::MatrixXd z = Eigen::MatrixXd::Zero(kSize, 2);
  for (int i = 3; i < 10; ++i) z(i, 0) = 1.0;
  for (int i = 8; i < 18; ++i) z(i, 1) = 0.5 * (i - 12);
  return z;
}

std::vector<la::SparseVector> sparse_basis(const Eigen::MatrixXd& z) {
  const auto [first, last] = owned_rows();
  std::vector<la::SparseVector> basis(z.cols());
  for (Eigen::Index k = 0; k < z.cols(); ++k)
    for (int i = first; i < last; ++i)
      if (z(i, k) != 0.0) {
        basis[k].index.push_back(i - first);
        basis[k].value.push_back(z(i, k));
      }
  return basis;
}

Eigen::VectorXd random_dense(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  return Eigen::VectorXd::NullaryExpr(kSize, [&] { return value(random); });
}

/// A shell set up on `a` by `make`, applied to r.
template <class Make>
Eigen::VectorXd apply_shell(Mat a, const Eigen::VectorXd& r, Make&& make) {
  PC pc = nullptr;
  la::check(PCCreate(PETSC_COMM_WORLD, &pc), "PCCreate");
  la::check(PCSetOperators(pc, a, a), "PCSetOperators");
  make(pc);
  la::check(PCSetUp(pc), "PCSetUp");
  la::Vector x = petsc_vector(r), y = petsc_vector(Eigen::VectorXd::Zero(kSize));
  la::check(PCApply(pc, x.get(), y.get()), "PCApply");
  la::check(PCDestroy(&pc), "PCDestroy");
  return dense_vector(y.get());
}

PC jacobi_smoother() {
  PC smoother = nullptr;
  la::check(PCCreate(PETSC_COMM_WORLD, &smoother), "PCCreate");
  la::check(PCSetType(smoother, PCJACOBI), "PCSetType");
  return smoother;
}

}  // namespace

TEST(TwoLevel, SolvesTheCoarseSpaceExactlyAndSmoothsTheRest) {
  const Eigen::MatrixXd a = dense_matrix(), z = dense_basis();
  const la::Matrix m = petsc_matrix(a);
  const auto basis = sparse_basis(z);
  // y = Z c + D^{-1} (r - A Z c), c = (Z^T A Z)^{-1} Z^T r.
  const Eigen::VectorXd r = random_dense(3);
  const Eigen::VectorXd c = (z.transpose() * a * z).lu().solve(z.transpose() * r);
  const Eigen::VectorXd expected =
      z * c + a.diagonal().cwiseInverse().cwiseProduct(r - a * z * c);
  const Eigen::VectorXd y =
      apply_shell(m.get(), r, [&](PC pc) { la::make_two_level(pc, jacobi_smoother(), basis); });
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  // A residual made of coarse vectors alone is answered by them exactly,
  // which the smoother alone would not do.
  const Eigen::VectorXd target = z * Eigen::Vector2d(0.7, -1.3);
  const Eigen::VectorXd exact =
      apply_shell(m.get(), a * target, [&](PC pc) { la::make_two_level(pc, jacobi_smoother(), basis); });
  EXPECT_LT((exact - target).norm(), 1e-12 * target.norm());
  EXPECT_GT((a.diagonal().cwiseInverse().cwiseProduct(a * target) - target).norm(), 0.1 * target.norm());
}

TEST(TwoLevel, AKeptPreconditionerKeepsItsSmootherTooAndARebuildRenewsBoth) {
  // The solver keeps a preconditioner by the shell's reuse flag; the
  // smoother, applied from inside the shell, must not rebuild itself on
  // the changed matrix (BoomerAMG did, at every solve, before its own flag
  // was raised after each build), and a rebuild must renew it with E.
  const Eigen::MatrixXd a = dense_matrix(), z = dense_basis();
  la::Matrix m = petsc_matrix(a);
  const auto basis = sparse_basis(z);
  const Eigen::VectorXd r = random_dense(13);
  PC pc = nullptr;
  la::check(PCCreate(PETSC_COMM_WORLD, &pc), "PCCreate");
  la::check(PCSetOperators(pc, m.get(), m.get()), "PCSetOperators");
  la::make_two_level(pc, jacobi_smoother(), basis);
  auto apply = [&] {
    la::Vector x = petsc_vector(r), y = petsc_vector(Eigen::VectorXd::Zero(kSize));
    la::check(PCApply(pc, x.get(), y.get()), "PCApply");
    return dense_vector(y.get());
  };
  const Eigen::VectorXd built = apply();
  la::check(PCSetReusePreconditioner(pc, PETSC_TRUE), "PCSetReusePreconditioner");
  la::check(MatScale(m.get(), 2.0), "MatScale");
  const Eigen::VectorXd kept = apply();
  EXPECT_LT((kept - built).norm(), 1e-14 * built.norm());
  la::check(PCSetReusePreconditioner(pc, PETSC_FALSE), "PCSetReusePreconditioner");
  const Eigen::VectorXd rebuilt = apply();  // everything on 2A: half the answer
  EXPECT_LT((rebuilt - 0.5 * built).norm(), 1e-12 * built.norm());
  la::check(PCDestroy(&pc), "PCDestroy");
}

TEST(TwoLevel, WithoutCoarseVectorsIsTheSmoother) {
  const Eigen::MatrixXd a = dense_matrix();
  const la::Matrix m = petsc_matrix(a);
  const std::vector<la::SparseVector> none;
  const Eigen::VectorXd r = random_dense(5);
  const Eigen::VectorXd y =
      apply_shell(m.get(), r, [&](PC pc) { la::make_two_level(pc, jacobi_smoother(), none); });
  EXPECT_LT((y - a.diagonal().cwiseInverse().cwiseProduct(r)).norm(), 1e-14 * r.norm());
}

/// The block of rows 5-9 and 14-16 (crossing the ranks' boundary on 2):
/// each rank's local positions.
std::vector<int> block_rows() { return {5, 6, 7, 8, 9, 14, 15, 16}; }

std::vector<PetscInt> local_block_rows() {
  const auto [first, last] = owned_rows();
  std::vector<PetscInt> local;
  for (int i : block_rows())
    if (i >= first && i < last) local.push_back(i - first);
  return local;
}

TEST(BlockCorrected, FollowsTheSmootherByAnExactSolveOnTheBlock) {
  const Eigen::MatrixXd a = dense_matrix();
  const la::Matrix m = petsc_matrix(a);
  const std::vector<int> rows = block_rows();
  const auto n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd block(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) block(i, j) = a(rows[i], rows[j]);
  // y = D^{-1} r, then y_I += A_II^{-1} (r - A y)_I.
  const Eigen::VectorXd r = random_dense(7);
  Eigen::VectorXd expected = a.diagonal().cwiseInverse().cwiseProduct(r);
  const Eigen::VectorXd left = r - a * expected;
  Eigen::VectorXd left_block(n);
  for (Eigen::Index i = 0; i < n; ++i) left_block(i) = left(rows[i]);
  const Eigen::VectorXd correction = block.lu().solve(left_block);
  for (Eigen::Index i = 0; i < n; ++i) expected(rows[i]) += correction(i);
  const bool active = true;
  const Eigen::VectorXd y = apply_shell(m.get(), r, [&](PC pc) {
    la::make_block_corrected(pc, jacobi_smoother(), local_block_rows(), &active);
  });
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  // After it the residual vanishes on the block: the block is solved exactly.
  const Eigen::VectorXd residual = r - a * y;
  for (int i : rows) EXPECT_LT(std::abs(residual(i)), 1e-12 * r.norm());
}

TEST(BlockCorrected, InactiveIsTheSmootherAndMaySwitchOnBetweenApplications) {
  const Eigen::MatrixXd a = dense_matrix();
  const la::Matrix m = petsc_matrix(a);
  const Eigen::VectorXd r = random_dense(9);
  bool active = false;
  PC pc = nullptr;
  la::check(PCCreate(PETSC_COMM_WORLD, &pc), "PCCreate");
  la::check(PCSetOperators(pc, m.get(), m.get()), "PCSetOperators");
  la::make_block_corrected(pc, jacobi_smoother(), local_block_rows(), &active);
  la::check(PCSetUp(pc), "PCSetUp");  // not factored while inactive
  auto apply = [&] {
    la::Vector x = petsc_vector(r), y = petsc_vector(Eigen::VectorXd::Zero(kSize));
    la::check(PCApply(pc, x.get(), y.get()), "PCApply");
    return dense_vector(y.get());
  };
  const Eigen::VectorXd smoothed = apply();
  EXPECT_LT((smoothed - a.diagonal().cwiseInverse().cwiseProduct(r)).norm(), 1e-14 * r.norm());
  active = true;  // factored at its first use
  const Eigen::VectorXd corrected = apply();
  const Eigen::VectorXd residual = r - a * corrected;
  for (int i : block_rows()) EXPECT_LT(std::abs(residual(i)), 1e-12 * r.norm());
  la::check(PCDestroy(&pc), "PCDestroy");
}

TEST(CoarseCorrectedJacobi, AddsTheLowRankTermToJacobi) {
  const Eigen::MatrixXd a = dense_matrix(), z = dense_basis();
  const la::Matrix m = petsc_matrix(a);
  la::CoarseCorrection correction;
  for (Eigen::Index k = 0; k < z.cols(); ++k) correction.vectors.push_back(petsc_vector(z.col(k)));
  correction.coefficients = {-0.25, 3.0};
  const Eigen::VectorXd r = random_dense(9);
  Eigen::VectorXd expected = a.diagonal().cwiseInverse().cwiseProduct(r);
  for (Eigen::Index k = 0; k < z.cols(); ++k)
    expected += correction.coefficients[k] * z.col(k) * z.col(k).dot(r);
  const Eigen::VectorXd y = apply_shell(
      m.get(), r, [&](PC pc) { la::make_coarse_corrected_jacobi(pc, correction); });
  EXPECT_LT((y - expected).norm(), 1e-12 * expected.norm());
  // The coefficients are read at each application: zero leaves Jacobi.
  correction.coefficients = {0.0, 0.0};
  const Eigen::VectorXd plain = apply_shell(
      m.get(), r, [&](PC pc) { la::make_coarse_corrected_jacobi(pc, correction); });
  EXPECT_LT((plain - a.diagonal().cwiseInverse().cwiseProduct(r)).norm(), 1e-14 * r.norm());
}

TEST(SchurEstimate, PressureMassWeightRisesFromOneToTwoAboveLambdaOne) {
  EXPECT_EQ(physics::pressure_mass_weight(0.01), 1.0);
  EXPECT_EQ(physics::pressure_mass_weight(1.0), 1.0);
  EXPECT_NEAR(physics::pressure_mass_weight(10.0), 1.0 + 9.0 / 11.0, 1e-15);
  double previous = 1.0;
  for (double lambda : {1.5, 3.0, 10.0, 100.0, 1e4, 1e8}) {
    const double f = physics::pressure_mass_weight(lambda);
    EXPECT_GT(f, previous) << lambda;
    EXPECT_LT(f, 2.0) << lambda;
    previous = f;
  }
  EXPECT_NEAR(previous, 2.0, 1e-7);
}

TEST(SchurEstimate, ConstantPressureCorrectionOnlyForLessViscousObjects) {
  // eta_k = 0.01, eta_matrix = 1, volume 4: -(1 - 0.01) / 2 / 4.
  EXPECT_NEAR(physics::constant_pressure_correction(0.01, 1.0, 4.0), -0.99 / 8.0, 1e-15);
  EXPECT_EQ(physics::constant_pressure_correction(1.0, 1.0, 4.0), 0.0);
  EXPECT_EQ(physics::constant_pressure_correction(100.0, 1.0, 4.0), 0.0);
}
