#include "softflow/la/nested_saddle_point.hpp"

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::la {

namespace {

PetscErrorCode shell_multiply(Mat shell, Vec x, Vec y) {
  NestedSaddlePoint* op = nullptr;
  PetscCall(MatShellGetContext(shell, &op));
  try {
    op->multiply(x, y);
  } catch (const std::exception&) {
    return PETSC_ERR_LIB;  // PETSc reports it up the Krylov method's stack
  }
  return 0;
}

}  // namespace

NestedSaddlePoint::FieldNumbering::FieldNumbering(IS owned_indices) : owned(owned_indices) {
  PetscInt n_local = 0, first = 0;
  check(ISGetLocalSize(owned, &n_local), "ISGetLocalSize");
  if (MPI_Exscan(&n_local, &first, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD) != MPI_SUCCESS ||
      MPI_Allreduce(&n_local, &n_global, 1, MPIU_INT, MPI_SUM, PETSC_COMM_WORLD) != MPI_SUCCESS)
    throw SolverError("NestedSaddlePoint: MPI_Exscan/MPI_Allreduce failed");
  if (mpi_rank() == 0) first = 0;  // MPI_Exscan leaves rank 0's result undefined
  range = {first, first + n_local};
}

NestedSaddlePoint::NestedSaddlePoint(OwnershipRange range, PetscInt n_global, IS primal,
                                     IS constraint)
    : range_(range),
      n_global_(n_global),
      primal_(primal),
      constraint_(constraint),
      field_of_(static_cast<std::size_t>(range.size()), 0),
      a_(primal_.range, primal_.n_global, primal_.range, primal_.n_global),
      g_(primal_.range, primal_.n_global, constraint_.range, constraint_.n_global) {
  if (primal_.range.size() + constraint_.range.size() != range_.size() ||
      primal_.n_global + constraint_.n_global != n_global_)
    throw SolverError(fmt::format(
        "NestedSaddlePoint: the fields' {} + {} unknowns on this rank are not the system's {}",
        primal_.range.size(), constraint_.range.size(), range_.size()));
  const PetscInt* c = nullptr;
  check(ISGetIndices(constraint, &c), "ISGetIndices");
  for (PetscInt k = 0; k < constraint_.range.size(); ++k) {
    if (!range_.owns(c[k])) {
      ISRestoreIndices(constraint, &c);
      throw SolverError("NestedSaddlePoint: a constraint unknown outside this rank's range");
    }
    field_of_[c[k] - range_.begin] = 1;
  }
  check(ISRestoreIndices(constraint, &c), "ISRestoreIndices");
}

void NestedSaddlePoint::create() {
  // The fields' block sizes (velocity: 3 components a node) carry over to
  // the blocks, as PCFIELDSPLIT's extracted copies had them.
  PetscInt primal_block = 1, constraint_block = 1;
  check(ISGetBlockSize(primal_.owned, &primal_block), "ISGetBlockSize");
  check(ISGetBlockSize(constraint_.owned, &constraint_block), "ISGetBlockSize");
  a_.set_block_sizes(primal_block, primal_block);
  g_.set_block_sizes(primal_block, constraint_block);
  a_.create();
  g_.create();
  check(MatCreateTranspose(g_.get(), transpose_.out()), "MatCreateTranspose");
  IS fields[2] = {primal_.owned, constraint_.owned};
  Mat blocks[4] = {a_.get(), g_.get(), transpose_.get(), nullptr};
  check(MatCreateNest(PETSC_COMM_WORLD, 2, fields, 2, fields, blocks, nest_.out()),
        "MatCreateNest");
  check(MatCreateShell(PETSC_COMM_WORLD, range_.size(), range_.size(), n_global_, n_global_, this,
                       shell_.out()),
        "MatCreateShell");
  check(MatShellSetOperation(shell_.get(), MATOP_MULT,
                             reinterpret_cast<void (*)(void)>(shell_multiply)),
        "MatShellSetOperation");
  check(MatCreateVecs(a_.get(), primal_in_.out(), primal_out_.out()), "MatCreateVecs");
  check(MatCreateVecs(g_.get(), constraint_in_.out(), nullptr), "MatCreateVecs");
  check(VecDuplicate(constraint_in_.get(), constraint_out_.out()), "VecDuplicate");
}

void NestedSaddlePoint::assemble() {
  a_.assemble();
  g_.assemble();
  mark_changed();
}

void NestedSaddlePoint::mark_changed() {
  // PCSetUp rebuilds only if its matrix's state moved, and the nest's own
  // does not follow its blocks'; assembling it moves it (the blocks are
  // assembled already: no work but a pass over their rows).
  check(MatAssemblyBegin(nest_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyBegin(nest)");
  check(MatAssemblyEnd(nest_.get(), MAT_FINAL_ASSEMBLY), "MatAssemblyEnd(nest)");
}

void NestedSaddlePoint::permute(Vec whole, Vec primal, Vec constraint, bool to_fields) const {
  PetscScalar *w = nullptr, *u = nullptr, *p = nullptr;
  check(VecGetArray(whole, &w), "VecGetArray");
  check(VecGetArray(primal, &u), "VecGetArray");
  check(VecGetArray(constraint, &p), "VecGetArray");
  PetscInt iu = 0, ip = 0;
  for (std::size_t i = 0; i < field_of_.size(); ++i) {
    PetscScalar& field_entry = field_of_[i] ? p[ip++] : u[iu++];
    if (to_fields) field_entry = w[i];
    else w[i] = field_entry;
  }
  check(VecRestoreArray(constraint, &p), "VecRestoreArray");
  check(VecRestoreArray(primal, &u), "VecRestoreArray");
  check(VecRestoreArray(whole, &w), "VecRestoreArray");
}

void NestedSaddlePoint::multiply(Vec x, Vec y) {
  permute(x, primal_in_.get(), constraint_in_.get(), true);
  check(MatMult(a_.get(), primal_in_.get(), primal_out_.get()), "MatMult(A)");
  check(MatMultAdd(g_.get(), constraint_in_.get(), primal_out_.get(), primal_out_.get()),
        "MatMultAdd(G)");
  check(MatMultTranspose(g_.get(), primal_in_.get(), constraint_out_.get()),
        "MatMultTranspose(G)");
  permute(y, primal_out_.get(), constraint_out_.get(), false);
}

void NestedSaddlePoint::eliminate_primal(std::span<const PetscInt> rows,
                                         std::span<const PetscScalar> values, Vec rhs, Vec x) {
  if (rows.size() != values.size())
    throw SolverError("NestedSaddlePoint::eliminate_primal: rows and values differ in length");
  // The known values' products leave every row: rhs -= op g.
  Vector known, product;
  check(VecDuplicate(rhs, known.out()), "VecDuplicate");
  check(VecDuplicate(rhs, product.out()), "VecDuplicate");
  check(VecSet(known.get(), 0.0), "VecSet");
  PetscScalar* g = nullptr;
  check(VecGetArray(known.get(), &g), "VecGetArray");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (!range_.owns(rows[k]) || field_of_[rows[k] - range_.begin])
      throw SolverError(fmt::format(
          "NestedSaddlePoint::eliminate_primal: unknown {} is not a primal unknown of this rank",
          rows[k]));
    g[rows[k] - range_.begin] = values[k];
  }
  check(VecRestoreArray(known.get(), &g), "VecRestoreArray");
  multiply(known.get(), product.get());
  check(VecAXPY(rhs, -1.0, product.get()), "VecAXPY");
  // The constrained rows: u = g.
  PetscScalar *b = nullptr, *u = nullptr;
  check(VecGetArray(rhs, &b), "VecGetArray");
  check(VecGetArray(x, &u), "VecGetArray");
  for (std::size_t k = 0; k < rows.size(); ++k) {
    b[rows[k] - range_.begin] = values[k];
    u[rows[k] - range_.begin] = values[k];
  }
  check(VecRestoreArray(x, &u), "VecRestoreArray");
  check(VecRestoreArray(rhs, &b), "VecRestoreArray");
  // Their positions within the primal field.
  std::vector<PetscInt> positions;
  positions.reserve(rows.size());
  {
    std::vector<PetscInt> position_of(field_of_.size(), -1);
    PetscInt next = primal_.range.begin;
    for (std::size_t i = 0; i < field_of_.size(); ++i)
      if (!field_of_[i]) position_of[i] = next++;
    for (PetscInt r : rows) positions.push_back(position_of[r - range_.begin]);
  }
  a_.zero_rows_columns(positions, 1.0);
  check(MatZeroRows(g_.get(), static_cast<PetscInt>(positions.size()), positions.data(), 0.0,
                    nullptr, nullptr),
        "MatZeroRows(G)");
  mark_changed();
}

}  // namespace softflow::la
