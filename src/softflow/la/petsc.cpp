#include "softflow/la/petsc.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::la {

void check(PetscErrorCode code, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw SolverError(fmt::format("PETSc error in {}: {} (code {})", what, text ? text : "?", code));
}

int mpi_rank(MPI_Comm comm) {
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

void broadcast_text(std::string& text, int root, MPI_Comm comm) {
  int n = static_cast<int>(text.size());
  MPI_Bcast(&n, 1, MPI_INT, root, comm);
  text.resize(static_cast<std::size_t>(n));
  if (n > 0) MPI_Bcast(text.data(), n, MPI_CHAR, root, comm);
}

int mpi_size(MPI_Comm comm) {
  int s = 1;
  MPI_Comm_size(comm, &s);
  return s;
}

Vector make_vector(PetscInt n_local, PetscInt n_global) {
  Vector v;
  check(VecCreateMPI(PETSC_COMM_WORLD, n_local, n_global, v.out()), "VecCreateMPI");
  return v;
}

IndexSet make_index_set(std::span<const PetscInt> owned_indices, PetscInt block_size) {
  IndexSet is;
  check(ISCreateGeneral(PETSC_COMM_WORLD, static_cast<PetscInt>(owned_indices.size()),
                        owned_indices.data(), PETSC_COPY_VALUES, is.out()),
        "ISCreateGeneral");
  if (block_size > 1) check(ISSetBlockSize(is.get(), block_size), "ISSetBlockSize");
  return is;
}

Solver lu_solver(Mat a, const std::string& prefix) {
  Solver ksp;
  check(KSPCreate(PETSC_COMM_WORLD, ksp.out()), "KSPCreate");
  check(KSPSetOptionsPrefix(ksp.get(), prefix.c_str()), "KSPSetOptionsPrefix");
  check(KSPSetOperators(ksp.get(), a, a), "KSPSetOperators");
  check(KSPSetType(ksp.get(), KSPPREONLY), "KSPSetType");
  PC pc = nullptr;
  check(KSPGetPC(ksp.get(), &pc), "KSPGetPC");
  check(PCSetType(pc, PCLU), "PCSetType");
  check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  check(KSPSetFromOptions(ksp.get()), "KSPSetFromOptions");
  return ksp;
}

void make_shell_preconditioner(PC pc, void* context, PetscErrorCode (*set_up)(PC),
                               PetscErrorCode (*apply)(PC, Vec, Vec),
                               PetscErrorCode (*destroy)(PC), const char* name) {
  check(PCSetType(pc, PCSHELL), "PCSetType(shell)");
  check(PCShellSetContext(pc, context), "PCShellSetContext");
  check(PCShellSetSetUp(pc, set_up), "PCShellSetSetUp");
  check(PCShellSetApply(pc, apply), "PCShellSetApply");
  check(PCShellSetDestroy(pc, destroy), "PCShellSetDestroy");
  check(PCShellSetName(pc, name), "PCShellSetName");
}

NullSpace rigid_body_modes(std::span<const PetscScalar> xyz) {
  const auto n = static_cast<PetscInt>(xyz.size());
  Vector coordinates;
  check(VecCreateMPI(PETSC_COMM_WORLD, n, PETSC_DETERMINE, coordinates.out()), "VecCreateMPI");
  check(VecSetBlockSize(coordinates.get(), 3), "VecSetBlockSize");
  PetscScalar* x = nullptr;
  check(VecGetArray(coordinates.get(), &x), "VecGetArray");
  std::copy(xyz.begin(), xyz.end(), x);
  check(VecRestoreArray(coordinates.get(), &x), "VecRestoreArray");
  NullSpace modes;
  check(MatNullSpaceCreateRigidBody(coordinates.get(), modes.out()), "MatNullSpaceCreateRigidBody");
  return modes;
}

void attach_null_space(Mat matrix, std::span<const Vec> basis) {
  std::vector<Vector> units(basis.size());
  std::vector<Vec> handles;
  for (std::size_t i = 0; i < basis.size(); ++i) {
    check(VecDuplicate(basis[i], units[i].out()), "VecDuplicate");
    check(VecCopy(basis[i], units[i].get()), "VecCopy");
    check(VecNormalize(units[i].get(), nullptr), "VecNormalize");
    handles.push_back(units[i].get());
  }
  // The matrix keeps references to the null space and its vectors.
  NullSpace space;
  check(MatNullSpaceCreate(PETSC_COMM_WORLD, PETSC_FALSE, static_cast<PetscInt>(handles.size()),
                           handles.data(), space.out()),
        "MatNullSpaceCreate");
  check(MatSetNullSpace(matrix, space.get()), "MatSetNullSpace");
  check(MatSetTransposeNullSpace(matrix, space.get()), "MatSetTransposeNullSpace");
}

}  // namespace softflow::la
