#include "softflow/la/block_corrected.hpp"

#include <utility>

#include "softflow/la/shell_smoother.hpp"

namespace softflow::la {

namespace {

struct Context {
  PC smoother = nullptr;
  std::vector<PetscInt> rows;  // local positions
  const bool* active = nullptr;
  IS block = nullptr;  // the rows, global
  Mat block_matrix = nullptr;
  KSP block_solver = nullptr;
  bool factored = false;  // for the preconditioning matrix of the last setup
  Vec residual = nullptr, block_residual = nullptr, block_correction = nullptr;
};

/// P_II of the pc's preconditioning matrix, extracted and factored.
PetscErrorCode factor_block(PC pc, Context& ctx) {
  PetscFunctionBeginUser;
  Mat a = nullptr, p = nullptr;
  PetscCall(PCGetOperators(pc, &a, &p));
  const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(pc));
  if (!ctx.block) {
    PetscInt first = 0;
    PetscCall(MatGetOwnershipRange(p, &first, nullptr));
    std::vector<PetscInt> global(ctx.rows);
    for (auto& g : global) g += first;
    PetscCall(ISCreateGeneral(comm, static_cast<PetscInt>(global.size()), global.data(),
                              PETSC_COPY_VALUES, &ctx.block));
    PetscCall(MatCreateVecs(a, &ctx.residual, nullptr));
  }
  PetscCall(MatDestroy(&ctx.block_matrix));
  PetscCall(MatCreateSubMatrix(p, ctx.block, ctx.block, MAT_INITIAL_MATRIX, &ctx.block_matrix));
  if (!ctx.block_solver) {
    PetscCall(KSPCreate(comm, &ctx.block_solver));
    PetscCall(KSPSetType(ctx.block_solver, KSPPREONLY));
    PC lu = nullptr;
    PetscCall(KSPGetPC(ctx.block_solver, &lu));
    PetscCall(PCSetType(lu, PCLU));
    PetscCall(PCFactorSetMatSolverType(lu, MATSOLVERMUMPS));
    PetscCall(MatCreateVecs(ctx.block_matrix, &ctx.block_correction, &ctx.block_residual));
  }
  PetscCall(KSPSetOperators(ctx.block_solver, ctx.block_matrix, ctx.block_matrix));
  PetscCall(KSPSetUp(ctx.block_solver));
  ctx.factored = true;
  PetscFunctionReturn(0);
}

PetscErrorCode set_up(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(set_up_shell_smoother(pc, ctx->smoother));
  ctx->factored = false;
  if (*ctx->active) PetscCall(factor_block(pc, *ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode apply(PC pc, Vec r, Vec y) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PCApply(ctx->smoother, r, y));
  if (!*ctx->active) PetscFunctionReturn(0);
  if (!ctx->factored) PetscCall(factor_block(pc, *ctx));
  Mat a = nullptr;
  PetscCall(PCGetOperators(pc, &a, nullptr));
  PetscCall(MatMult(a, y, ctx->residual));
  PetscCall(VecAYPX(ctx->residual, -1.0, r));  // r - A y
  const PetscScalar* from = nullptr;
  PetscScalar* to = nullptr;
  PetscCall(VecGetArrayRead(ctx->residual, &from));
  PetscCall(VecGetArray(ctx->block_residual, &to));
  for (std::size_t i = 0; i < ctx->rows.size(); ++i) to[i] = from[ctx->rows[i]];
  PetscCall(VecRestoreArray(ctx->block_residual, &to));
  PetscCall(VecRestoreArrayRead(ctx->residual, &from));
  PetscCall(KSPSolve(ctx->block_solver, ctx->block_residual, ctx->block_correction));
  const PetscScalar* c = nullptr;
  PetscScalar* out = nullptr;
  PetscCall(VecGetArrayRead(ctx->block_correction, &c));
  PetscCall(VecGetArray(y, &out));
  for (std::size_t i = 0; i < ctx->rows.size(); ++i) out[ctx->rows[i]] += c[i];
  PetscCall(VecRestoreArray(y, &out));
  PetscCall(VecRestoreArrayRead(ctx->block_correction, &c));
  PetscFunctionReturn(0);
}

PetscErrorCode view(PC pc, PetscViewer viewer) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PCView(ctx->smoother, viewer));
  PetscCall(PetscViewerASCIIPrintf(
      viewer, "then an exact solve (LU) on %d of this rank's rows (%s)\n",
      static_cast<int>(ctx->rows.size()), *ctx->active ? "active" : "inactive"));
  PetscFunctionReturn(0);
}

PetscErrorCode destroy(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PCDestroy(&ctx->smoother));
  PetscCall(ISDestroy(&ctx->block));
  PetscCall(MatDestroy(&ctx->block_matrix));
  PetscCall(KSPDestroy(&ctx->block_solver));
  PetscCall(VecDestroy(&ctx->residual));
  PetscCall(VecDestroy(&ctx->block_residual));
  PetscCall(VecDestroy(&ctx->block_correction));
  delete ctx;
  PetscFunctionReturn(0);
}

}  // namespace

void make_block_corrected(PC pc, PC smoother, std::vector<PetscInt> rows, const bool* active) {
  auto* ctx = new Context;
  ctx->smoother = smoother;
  ctx->rows = std::move(rows);
  ctx->active = active;
  make_shell_preconditioner(pc, ctx, set_up, apply, destroy,
                            "softflow: smoother + exact block solve");
  check(PCShellSetView(pc, view), "PCShellSetView");
}

}  // namespace softflow::la
