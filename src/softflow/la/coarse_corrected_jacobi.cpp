#include "softflow/la/coarse_corrected_jacobi.hpp"

namespace softflow::la {

namespace {

struct Context {
  const CoarseCorrection* correction = nullptr;
  Vec inverse_diagonal = nullptr;
  std::vector<Vec> vectors;          // the correction's, as PETSc wants them
  std::vector<PetscScalar> weights;  // c_k (z_k . r), one reduction for all k
};

PetscErrorCode set_up(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  Mat pmat = nullptr;
  PetscCall(PCGetOperators(pc, nullptr, &pmat));
  if (!ctx->inverse_diagonal) PetscCall(MatCreateVecs(pmat, &ctx->inverse_diagonal, nullptr));
  PetscCall(MatGetDiagonal(pmat, ctx->inverse_diagonal));
  // As PCJACOBI: a zero diagonal entry leaves its unknown alone.
  PetscScalar* d = nullptr;
  PetscInt n = 0;
  PetscCall(VecGetLocalSize(ctx->inverse_diagonal, &n));
  PetscCall(VecGetArray(ctx->inverse_diagonal, &d));
  for (PetscInt i = 0; i < n; ++i) d[i] = d[i] != 0.0 ? 1.0 / d[i] : 1.0;
  PetscCall(VecRestoreArray(ctx->inverse_diagonal, &d));
  PetscFunctionReturn(0);
}

PetscErrorCode apply(PC pc, Vec r, Vec y) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(VecPointwiseMult(y, ctx->inverse_diagonal, r));
  const auto& c = *ctx->correction;
  const auto n = static_cast<PetscInt>(c.vectors.size());
  if (n > 0) {
    ctx->vectors.resize(n);
    ctx->weights.resize(n);
    for (PetscInt k = 0; k < n; ++k) ctx->vectors[k] = c.vectors[k].get();
    PetscCall(VecMDot(r, n, ctx->vectors.data(), ctx->weights.data()));
    for (PetscInt k = 0; k < n; ++k) ctx->weights[k] *= c.coefficients[k];
    PetscCall(VecMAXPY(y, n, ctx->weights.data(), ctx->vectors.data()));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode destroy(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(VecDestroy(&ctx->inverse_diagonal));
  delete ctx;
  PetscFunctionReturn(0);
}

}  // namespace

void make_coarse_corrected_jacobi(PC pc, const CoarseCorrection& correction) {
  auto* ctx = new Context;
  ctx->correction = &correction;
  make_shell_preconditioner(pc, ctx, set_up, apply, destroy, "softflow: Jacobi + coarse correction");
}

}  // namespace softflow::la
