// Krylov/direct solvers for the Taylor-Hood saddle-point system.
#pragma once

#include <string>

#include "softflow/la/petsc.hpp"

namespace softflow::la {

enum class SaddlePointMethod {
  direct,     ///< MUMPS LU (exact; practical up to ~150k unknowns, PLATFORM.md)
  iterative,  ///< FGMRES + lower Schur fieldsplit, BoomerAMG on velocity
};

struct SaddlePointSettings {
  SaddlePointMethod method = SaddlePointMethod::direct;
  double rtol = 1e-8;
  int max_iterations = 500;
  /// Options prefix: every choice can be overridden from the command line,
  /// e.g. -stokes_ksp_type gmres or -stokes_fieldsplit_velocity_pc_type gamg.
  std::string prefix = "stokes_";
};

struct SolveReport {
  int iterations = 0;
  double seconds = 0.0;
  double residual_norm = 0.0;
  std::string reason;
};

/// Solves
///
///   [ A   B^T ] [u]   [f]        preconditioned (iterative) with   [ A    0  ]
///   [ B   0   ] [p] = [g]                                          [ B  -M/eta]
///
/// where A is the viscous block, B the (negative) divergence, and M/eta the
/// P1 pressure mass matrix weighted by 1/viscosity of each phase, which
/// approximates the Schur complement -B A^{-1} B^T. The preconditioning
/// matrix `pmat` carries -M/eta in its pressure block; with the direct
/// method it is ignored.
class SaddlePointSolver {
 public:
  SaddlePointSolver(const SaddlePointSettings& settings, IS velocity_dofs, IS pressure_dofs);

  /// Sets the operator (and preconditioning matrix) and (re)builds the preconditioner.
  void set_operators(Mat a, Mat pmat);
  /// Solves a x = b; throws SolverError if the solver does not converge.
  SolveReport solve(Vec b, Vec x);

  [[nodiscard]] KSP ksp() const { return ksp_.get(); }

 private:
  SaddlePointSettings settings_;
  Solver ksp_;
};

/// Sets `-name value` in PETSc's options database unless the user already set it.
void set_default_option(const std::string& name, const std::string& value);

}  // namespace softflow::la
