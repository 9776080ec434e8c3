#include "softflow/la/two_level.hpp"

#include <mpi.h>

#include <Eigen/Dense>

#include "softflow/la/shell_smoother.hpp"

namespace softflow::la {

namespace {

/// -log_view's line for the coarse part of an application (the smoother's
/// is its own PCApply).
PetscLogEvent coarse_event() {
  static PetscLogEvent event = [] {
    PetscLogEvent e = 0;
    PetscClassId id = 0;
    check(PetscClassIdRegister("softflow two-level", &id), "PetscClassIdRegister");
    check(PetscLogEventRegister("TwoLevelCoarse", id, &e), "PetscLogEventRegister");
    return e;
  }();
  return event;
}

struct Context {
  PC smoother = nullptr;
  const std::vector<SparseVector>* z = nullptr;
  std::vector<SparseVector> az;  // A z_k, this rank's nonzero rows
  Eigen::PartialPivLU<Eigen::MatrixXd> coarse;
  Vec work = nullptr, product = nullptr;
};

/// w_k = z_k . r for every k: local sums, one reduction.
PetscErrorCode dots(const std::vector<SparseVector>& z, Vec r, Eigen::VectorXd& w) {
  PetscFunctionBeginUser;
  const PetscScalar* a = nullptr;
  PetscCall(VecGetArrayRead(r, &a));
  w.setZero(static_cast<Eigen::Index>(z.size()));
  for (std::size_t k = 0; k < z.size(); ++k)
    for (std::size_t i = 0; i < z[k].index.size(); ++i) w(k) += z[k].value[i] * a[z[k].index[i]];
  PetscCall(VecRestoreArrayRead(r, &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, w.data(), static_cast<int>(w.size()), MPI_DOUBLE,
                             MPI_SUM, PetscObjectComm(reinterpret_cast<PetscObject>(r))));
  PetscFunctionReturn(0);
}

/// y += scale * sum_k c_k v_k.
PetscErrorCode add(const std::vector<SparseVector>& v, const Eigen::VectorXd& c, double scale,
                   Vec y) {
  PetscFunctionBeginUser;
  PetscScalar* a = nullptr;
  PetscCall(VecGetArray(y, &a));
  for (std::size_t k = 0; k < v.size(); ++k)
    for (std::size_t i = 0; i < v[k].index.size(); ++i)
      a[v[k].index[i]] += scale * c(k) * v[k].value[i];
  PetscCall(VecRestoreArray(y, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode set_up(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  Mat a = nullptr;
  PetscCall(PCGetOperators(pc, &a, nullptr));
  PetscCall(set_up_shell_smoother(pc, ctx->smoother));
  if (!ctx->work) PetscCall(MatCreateVecs(a, &ctx->work, &ctx->product));
  const auto& z = *ctx->z;
  const auto n = static_cast<Eigen::Index>(z.size());
  ctx->az.assign(z.size(), {});
  Eigen::MatrixXd e(n, n);
  Eigen::VectorXd column;
  for (Eigen::Index j = 0; j < n; ++j) {
    PetscCall(VecSet(ctx->work, 0.0));
    PetscScalar* w = nullptr;
    PetscCall(VecGetArray(ctx->work, &w));
    for (std::size_t i = 0; i < z[j].index.size(); ++i) w[z[j].index[i]] = z[j].value[i];
    PetscCall(VecRestoreArray(ctx->work, &w));
    PetscCall(MatMult(a, ctx->work, ctx->product));
    PetscCall(dots(z, ctx->product, column));
    e.col(j) = column;
    const PetscScalar* v = nullptr;
    PetscInt size = 0;
    PetscCall(VecGetLocalSize(ctx->product, &size));
    PetscCall(VecGetArrayRead(ctx->product, &v));
    for (PetscInt i = 0; i < size; ++i)
      if (v[i] != 0.0) {
        ctx->az[j].index.push_back(i);
        ctx->az[j].value.push_back(v[i]);
      }
    PetscCall(VecRestoreArrayRead(ctx->product, &v));
  }
  ctx->coarse.compute(e);
  PetscFunctionReturn(0);
}

PetscErrorCode apply(PC pc, Vec r, Vec y) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  if (ctx->z->empty()) {
    PetscCall(PCApply(ctx->smoother, r, y));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogEventBegin(coarse_event(), pc, r, y, 0));
  Eigen::VectorXd w;
  PetscCall(dots(*ctx->z, r, w));
  const Eigen::VectorXd c = ctx->coarse.solve(w);
  PetscCall(VecCopy(r, ctx->work));
  PetscCall(add(ctx->az, c, -1.0, ctx->work));  // r - A Z c
  PetscCall(PetscLogEventEnd(coarse_event(), pc, r, y, 0));
  PetscCall(PCApply(ctx->smoother, ctx->work, y));
  PetscCall(PetscLogEventBegin(coarse_event(), pc, r, y, 0));
  PetscCall(add(*ctx->z, c, 1.0, y));
  PetscCall(PetscLogEventEnd(coarse_event(), pc, r, y, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode view(PC pc, PetscViewer viewer) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(PetscViewerASCIIPrintf(viewer, "exact solve on %d coarse vectors, then:\n",
                                   static_cast<int>(ctx->z->size())));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PCView(ctx->smoother, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode destroy(PC pc) {
  PetscFunctionBeginUser;
  Context* ctx = nullptr;
  PetscCall(PCShellGetContext(pc, &ctx));
  PetscCall(VecDestroy(&ctx->work));
  PetscCall(VecDestroy(&ctx->product));
  PetscCall(PCDestroy(&ctx->smoother));
  delete ctx;
  PetscFunctionReturn(0);
}

}  // namespace

void make_two_level(PC pc, PC smoother, const std::vector<SparseVector>& basis) {
  auto* ctx = new Context;
  ctx->smoother = smoother;
  ctx->z = &basis;
  make_shell_preconditioner(pc, ctx, set_up, apply, destroy, "softflow: coarse solve + smoother");
  check(PCShellSetView(pc, view), "PCShellSetView");
}

}  // namespace softflow::la
