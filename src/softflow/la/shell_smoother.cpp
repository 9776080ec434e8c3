#include "softflow/la/shell_smoother.hpp"

namespace softflow::la {

PetscErrorCode set_up_shell_smoother(PC shell, PC smoother) {
  PetscFunctionBeginUser;
  Mat a = nullptr, p = nullptr;
  PetscCall(PCGetOperators(shell, &a, &p));
  PetscCall(PCSetReusePreconditioner(smoother, PETSC_FALSE));
  PetscCall(PCSetOperators(smoother, a, p));
  PetscCall(PCSetUp(smoother));
  PetscCall(PCSetReusePreconditioner(smoother, PETSC_TRUE));
  PetscFunctionReturn(0);
}

}  // namespace softflow::la
