// la::NestedSaddlePoint, the iterative Stokes path's operator: [A G; G^T 0]
// stored as A and G. It must act exactly as the same system assembled into
// one matrix (products, Dirichlet elimination), and hand its blocks to
// PCFIELDSPLIT by reference.
//
// Runs on 1 rank and, as part of mpi_fem_layer, on 2.
#include <array>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/nested_saddle_point.hpp"
#include "softflow/la/vector_values.hpp"

using namespace softflow;

namespace {

// Nodes carry 3 primal unknowns, every other node one constraint unknown
// too, numbered node by node (as fem::DofMap numbers velocity and pressure).
constexpr int kNodes = 12;
bool has_constraint(int node) { return node % 2 == 0; }
int first_dof(int node) {
  int d = 0;
  for (int k = 0; k < node; ++k) d += 3 + (has_constraint(k) ? 1 : 0);
  return d;
}
const int kUnknowns = first_dof(kNodes);

struct Numbering {
  la::OwnershipRange range;             // this rank's unknowns
  std::vector<PetscInt> primal, constraint;  // owned, whole-system numbering
  std::vector<int> position;            // any dof -> its position within its field
  std::vector<char> is_constraint;      // any dof
};

Numbering numbering() {
  Numbering n;
  const int rank = la::mpi_rank(), size = la::mpi_size();
  const int first_node = rank * kNodes / size, last_node = (rank + 1) * kNodes / size;
  n.range = {first_dof(first_node), first_dof(last_node)};
  int n_primal = 0, n_constraint = 0;
  for (int node = 0; node < kNodes; ++node) {
    for (int c = 0; c < 3; ++c) {
      n.position.push_back(n_primal++);
      n.is_constraint.push_back(0);
    }
    if (has_constraint(node)) {
      n.position.push_back(n_constraint++);
      n.is_constraint.push_back(1);
    }
  }
  for (PetscInt d = n.range.begin; d < n.range.end; ++d)
    (n.is_constraint[d] ? n.constraint : n.primal).push_back(d);
  return n;
}

/// Elements of 4 nodes (the same on every rank): their dofs and a random
/// symmetric saddle-point matrix [K B; B^T 0].
struct Element {
  std::vector<PetscInt> dofs;
  Eigen::MatrixXd matrix;
};

std::vector<Element> elements() {
  std::mt19937 random(7);
  std::uniform_int_distribution<int> node(0, kNodes - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Element> out;
  for (int e = 0; e < 20; ++e) {
    std::array<int, 4> nodes{};
    for (int& a : nodes) a = node(random);  // repeats allowed: summed
    Element el;
    for (int a : nodes)
      for (int c = 0; c < 3; ++c) el.dofs.push_back(first_dof(a) + c);
    for (int a : nodes)
      if (has_constraint(a)) el.dofs.push_back(first_dof(a) + 3);
    const int n = static_cast<int>(el.dofs.size()), nu = 12;
    el.matrix = Eigen::MatrixXd::Zero(n, n);
    Eigen::MatrixXd k = Eigen::MatrixXd::NullaryExpr(nu, nu, [&] { return value(random); });
    el.matrix.topLeftCorner(nu, nu) = k * k.transpose() + Eigen::MatrixXd::Identity(nu, nu);
    Eigen::MatrixXd b = Eigen::MatrixXd::NullaryExpr(nu, n - nu, [&] { return value(random); });
    el.matrix.topRightCorner(nu, n - nu) = b;
    el.matrix.bottomLeftCorner(n - nu, nu) = b.transpose();
    out.push_back(std::move(el));
  }
  return out;
}

la::Vector random_vector(const Numbering& n, unsigned seed) {
  la::Vector v = la::make_vector(n.range.size(), kUnknowns);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<double> all(kUnknowns);
  for (double& a : all) a = value(random);
  la::set_owned_values(v.get(), std::vector<double>(all.begin() + n.range.begin,
                                                    all.begin() + n.range.end));
  return v;
}

double max_difference(Vec a, Vec b) {
  la::Vector d;
  EXPECT_EQ(VecDuplicate(a, d.out()), 0);
  EXPECT_EQ(VecWAXPY(d.get(), -1.0, a, b), 0);
  PetscReal norm = 0.0;
  EXPECT_EQ(VecNorm(d.get(), NORM_INFINITY, &norm), 0);
  return norm;
}

/// The same elements assembled both ways; rows of other ranks dropped (-1),
/// each rank assembling every element (as StokesSystem does for the
/// elements it shares).
struct Systems {
  explicit Systems(la::CsrMatrix::Format primal_format);
  Numbering n = numbering();
  la::IndexSet primal_is = la::make_index_set(n.primal, 1);
  la::IndexSet constraint_is = la::make_index_set(n.constraint, 1);
  la::CsrMatrix whole{n.range, kUnknowns, n.range, kUnknowns};
  la::NestedSaddlePoint nested{n.range, kUnknowns, primal_is.get(), constraint_is.get()};
};

Systems::Systems(la::CsrMatrix::Format primal_format) {
  nested.primal().set_format(primal_format);
  const auto els = elements();
  std::vector<std::array<la::CsrMatrix::Block, 3>> blocks;
  for (const Element& el : els) {
    std::vector<PetscInt> rows, u_rows, u_columns, p_columns;
    for (PetscInt d : el.dofs) rows.push_back(n.range.owns(d) ? d : -1);
    for (std::size_t k = 0; k < el.dofs.size(); ++k) {
      const PetscInt d = el.dofs[k];
      if (n.is_constraint[d]) {
        p_columns.push_back(n.position[d]);
      } else {
        u_rows.push_back(rows[k] < 0 ? -1 : n.position[d]);
        u_columns.push_back(n.position[d]);
      }
    }
    blocks.push_back({whole.add_block(std::span<const PetscInt>(rows),
                                      std::span<const PetscInt>(el.dofs)),
                      nested.primal().add_block(std::span<const PetscInt>(u_rows),
                                                std::span<const PetscInt>(u_columns)),
                      nested.coupling().add_block(std::span<const PetscInt>(u_rows),
                                                  std::span<const PetscInt>(p_columns))});
  }
  whole.create();
  nested.create();
  for (std::size_t e = 0; e < els.size(); ++e) {
    const auto& m = els[e].matrix;
    const auto nu = static_cast<Eigen::Index>(12), np = m.rows() - nu;
    whole.set_block(blocks[e][0], m);
    nested.primal().set_block(blocks[e][1], m.topLeftCorner(nu, nu));
    nested.coupling().set_block(blocks[e][2], m.topRightCorner(nu, np));
  }
  whole.assemble();
  nested.assemble();
}

/// Every test runs with A in PETSc's format and in hypre's (the default
/// for the Stokes velocity block under BoomerAMG).
class NestedSaddlePoint : public ::testing::TestWithParam<la::CsrMatrix::Format> {};

}  // namespace

TEST_P(NestedSaddlePoint, MultipliesAsTheSameSystemAssembledIntoOneMatrix) {
  Systems s(GetParam());
  const la::Vector x = random_vector(s.n, 3);
  la::Vector y_whole = la::make_vector(s.n.range.size(), kUnknowns);
  la::Vector y_nested = la::make_vector(s.n.range.size(), kUnknowns);
  ASSERT_EQ(MatMult(s.whole.get(), x.get(), y_whole.get()), 0);
  ASSERT_EQ(MatMult(s.nested.op(), x.get(), y_nested.get()), 0);
  PetscReal size = 0.0;
  VecNorm(y_whole.get(), NORM_INFINITY, &size);
  EXPECT_GT(size, 1.0);
  EXPECT_LT(max_difference(y_whole.get(), y_nested.get()), 1e-13 * size);
}

TEST_P(NestedSaddlePoint, EliminatesDirichletDataAsMatZeroRowsColumnsDoes) {
  Systems s(GetParam());
  // Every third owned primal unknown is prescribed.
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  for (std::size_t k = 0; k < s.n.primal.size(); k += 3) {
    rows.push_back(s.n.primal[k]);
    values.push_back(0.5 + static_cast<double>(s.n.primal[k]));
  }
  la::Vector rhs_whole = random_vector(s.n, 5), rhs_nested = random_vector(s.n, 5);
  la::Vector x_whole = random_vector(s.n, 9), x_nested = random_vector(s.n, 9);
  // The whole matrix: values in x, then MatZeroRowsColumns moves them to rhs.
  ASSERT_EQ(VecSetValues(x_whole.get(), static_cast<PetscInt>(rows.size()), rows.data(),
                         values.data(), INSERT_VALUES),
            0);
  ASSERT_EQ(VecAssemblyBegin(x_whole.get()), 0);
  ASSERT_EQ(VecAssemblyEnd(x_whole.get()), 0);
  ASSERT_EQ(MatZeroRowsColumns(s.whole.get(), static_cast<PetscInt>(rows.size()), rows.data(), 1.0,
                               x_whole.get(), rhs_whole.get()),
            0);
  s.nested.eliminate_primal(rows, values, rhs_nested.get(), x_nested.get());
  EXPECT_LT(max_difference(rhs_whole.get(), rhs_nested.get()), 1e-12);
  EXPECT_LT(max_difference(x_whole.get(), x_nested.get()), 1e-15);
  // And the eliminated operators agree.
  const la::Vector v = random_vector(s.n, 11);
  la::Vector y_whole = la::make_vector(s.n.range.size(), kUnknowns);
  la::Vector y_nested = la::make_vector(s.n.range.size(), kUnknowns);
  ASSERT_EQ(MatMult(s.whole.get(), v.get(), y_whole.get()), 0);
  ASSERT_EQ(MatMult(s.nested.op(), v.get(), y_nested.get()), 0);
  EXPECT_LT(max_difference(y_whole.get(), y_nested.get()), 1e-12);
  // A primal unknown of another field is refused.
  if (!s.n.constraint.empty()) {
    const std::vector<PetscInt> bad{s.n.constraint.front()};
    const std::vector<PetscScalar> zero{0.0};
    EXPECT_THROW(s.nested.eliminate_primal(bad, zero, rhs_nested.get(), x_nested.get()),
                 SolverError);
  }
}

TEST_P(NestedSaddlePoint, HandsItsBlocksToTheFieldsplitByReference) {
  // What the memory saving rests on: extracting a field's block from the
  // nest (MatCreateSubMatrix, as PCFIELDSPLIT does) returns the block itself.
  Systems s(GetParam());
  Mat a = nullptr, g = nullptr;
  ASSERT_EQ(MatCreateSubMatrix(s.nested.preconditioning(), s.primal_is.get(), s.primal_is.get(),
                               MAT_INITIAL_MATRIX, &a),
            0);
  ASSERT_EQ(MatCreateSubMatrix(s.nested.preconditioning(), s.primal_is.get(),
                               s.constraint_is.get(), MAT_INITIAL_MATRIX, &g),
            0);
  EXPECT_EQ(a, s.nested.primal().get());
  EXPECT_EQ(g, s.nested.coupling().get());
  MatDestroy(&a);
  MatDestroy(&g);
}

INSTANTIATE_TEST_SUITE_P(Formats, NestedSaddlePoint,
                         ::testing::Values(la::CsrMatrix::Format::petsc_aij,
                                           la::CsrMatrix::Format::hypre_parcsr),
                         [](const auto& info) {
                           return info.param == la::CsrMatrix::Format::petsc_aij ? "aij" : "hypre";
                         });
