// The inner preconditioner a shell preconditioner applies (la::make_two_level,
// la::make_block_corrected).
#pragma once

#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// Builds `smoother` on the operators of `shell`, in the shell's setup.
/// The smoother is rebuilt there and only there: PCApply sets a PC up when
/// its matrix changed, and the shell's reuse flag (a kept preconditioner)
/// does not reach it, so it carries its own, raised after the build.
PetscErrorCode set_up_shell_smoother(PC shell, PC smoother);

}  // namespace softflow::la
