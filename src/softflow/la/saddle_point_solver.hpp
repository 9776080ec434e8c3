// Krylov/direct solvers for the Taylor-Hood saddle-point system.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "softflow/la/coarse_corrected_jacobi.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/la/two_level.hpp"

namespace softflow::la {

enum class SaddlePointMethod {
  /// direct for a run long enough to repay the factorisation
  /// (direct_solver_crossover_steps) up to kDirectSolverLimit unknowns,
  /// iterative otherwise; the system that owns the matrix resolves it
  /// (resolve_method) before the solver is made, since only it knows the size.
  automatic,
  direct,     ///< MUMPS LU (exact; practical up to ~150k unknowns, PLATFORM.md)
  iterative,  ///< GMRES (right) + lower Schur fieldsplit, BoomerAMG on velocity
};

/// Above this many unknowns SaddlePointMethod::automatic solves iteratively:
/// MUMPS LU took 3.5 GB and 77 s at 124k unknowns, 19 GB and 1000 s at 366k
/// on this machine, FGMRES + Schur fieldsplit 0.8 GB / 7 s and 2.2 GB / 29 s
/// (PLATFORM.md); below it the direct solver's factor reuse wins.
inline constexpr int kDirectSolverLimit = 150000;

/// The number of time steps from which factoring once (and reusing the
/// factors as a preconditioner) costs less than the iterative path, for a
/// system of `unknowns`: the factorisation makes the direct path's first
/// step slow (4.0 / 7.4 / 12.3 / 24.4 s against 1.1 / 1.6 / 2.8 / 4.3 s at
/// 28k / 37k / 61k / 94k unknowns) and its later steps only 10-30 %
/// cheaper, so it pays off after S* = 18 / 37 / 54 / 96 steps
/// (docs/benchmarks/solver_crossover.md, bench/run_solver_crossover.py):
/// 100 (unknowns / 95,000)^1.5 fits them within their noise. Below
/// kRunLengthRuleFrom unknowns (not measured; a factorisation takes under
/// 4 s) 0: the direct path for any run, as before the rule.
long direct_solver_crossover_steps(long unknowns);
inline constexpr long kRunLengthRuleFrom = 20000;

/// A resolved method and why it is the one, for the run's report.
struct MethodChoice {
  SaddlePointMethod method;
  std::string reason;
};

/// From this many unknowns SaddlePointMethod::automatic solves a system with
/// a viscoelastic liquid's terms (SaddlePointSettings::relaxing_phase)
/// iteratively whatever the run's length: measured
/// (docs/benchmarks/solver_crossover_stress.md), the reused factors' steps
/// are 14-19 % cheaper than the iterative path's at 29,558 unknowns and
/// 14-21 % dearer at 82,851 (a Giesekus matrix, an Oldroyd-B drop), where
/// a factorisation therefore never pays off.
inline constexpr long kRelaxingPhaseIterativeFrom = 50000;

/// `method` with automatic replaced by the choice for `unknowns` and a run
/// of `planned_steps` time steps (0: not known, taken as a long run):
/// iterative above kDirectSolverLimit (memory), for a run shorter than
/// direct_solver_crossover_steps, or from kRelaxingPhaseIterativeFrom
/// unknowns with `relaxing_phase`; direct otherwise.
MethodChoice choose_method(SaddlePointMethod method, long unknowns, long planned_steps,
                           bool relaxing_phase = false);

/// choose_method's method alone.
inline SaddlePointMethod resolve_method(SaddlePointMethod method, long unknowns,
                                        long planned_steps = 0, bool relaxing_phase = false) {
  return choose_method(method, unknowns, planned_steps, relaxing_phase).method;
}

struct SaddlePointSettings {
  SaddlePointMethod method = SaddlePointMethod::direct;
  /// For SaddlePointMethod::automatic: the run's planned number of time
  /// steps (0: not known), which decides whether a factorisation pays off.
  long planned_steps = 0;
  /// For SaddlePointMethod::automatic: a phase is a viscoelastic liquid, whose
  /// stress terms (D'Avino-Hulsen, DEVSS-G) change the matrix with the
  /// conformation at every step: reused factors then need 14 GMRES
  /// iterations a step (a Giesekus matrix; 2-3 for a Newtonian drop, 9-10 for
  /// an elastic particle or an Oldroyd-B drop) and from kRelaxingPhaseIterativeFrom
  /// unknowns their steps cost more than the iterative path's.
  bool relaxing_phase = false;
  double rtol = 1e-8;
  int max_iterations = 500;
  /// In a time loop, the Krylov initial guess (the iterative method's, and
  /// the direct method's GMRES on kept factors): the line through the last
  /// two solutions extrapolated a step on (as the interface's predictor,
  /// eq. 2.49), or else the last solution. The relative tolerance is on
  /// ||b||, so a guess closer to the answer saves iterations.
  bool extrapolated_guess = true;
  /// Direct method in a time loop: keep the LU factors of an earlier matrix
  /// and precondition GMRES with them while the mesh moves little
  /// (PLATFORM.md: 4-6 iterations at 1-5 % mesh motion instead of a new
  /// factorisation); refactor once a solve needs more than this many
  /// iterations or fails. 0 refactors at every solve.
  int max_reuse_iterations = 25;
  /// Iterative method in a time loop: keep the preconditioner (the
  /// fieldsplit's sub-matrices, the AMG hierarchy) of an earlier matrix and
  /// rebuild it once a solve needs more than this factor times the fewest
  /// iterations any solve needed since the last rebuild, or fails. 0
  /// rebuilds at every solve. -<prefix>pc_reuse_growth overrides it.
  double max_reuse_growth = 1.3;
  /// Options prefix: every choice can be overridden from the command line,
  /// e.g. -stokes_ksp_type gmres or -stokes_fieldsplit_velocity_pc_type gamg.
  std::string prefix = "stokes_";
};

/// Whether the iterative method's first split (field `primal_name`, the
/// velocity) is preconditioned by hypre: the default, unless the options
/// database says otherwise (-<prefix>pc_type, -<prefix>fieldsplit_<name>_pc_type).
/// A matrix it takes is then best stored in hypre's format
/// (CsrMatrix::Format::hypre_parcsr). Read when the matrices are made:
/// options changed later do not move a matrix out of hypre's format.
bool primal_split_uses_hypre(const SaddlePointSettings& settings, const std::string& primal_name);

struct SolveReport {
  int iterations = 0;
  double seconds = 0.0;
  double residual_norm = 0.0;
  std::string reason;
  bool reused_preconditioner = false;
};

/// Solves
///
///   [ A   B^T ] [u]   [f]        preconditioned (iterative) with   [ A    0  ]
///   [ B   0   ] [p] = [g]                                          [ B  -M/eta]
///
/// where A is the viscous block, B the (negative) divergence, and M/eta the
/// P1 pressure mass matrix weighted by 1/viscosity of each phase, which
/// approximates the Schur complement -B A^{-1} B^T. -M/eta comes either as
/// the pressure block of a preconditioning matrix `pmat` or as a matrix of
/// its own (set_operators' `schur`); with the direct method both are
/// ignored.
///
/// The unknowns come as a list of named fields (e.g. "velocity",
/// "pressure"; later multipliers or a conformation tensor). The iterative
/// method splits them by name, so -<prefix>fieldsplit_<name>_pc_type etc.
/// address each one: with two fields a lower Schur factorisation (first =
/// primal, second = constraint), with more a multiplicative split whose
/// fields the user may regroup with -<prefix>pc_fieldsplit_<k>_fields.
class SaddlePointSolver {
 public:
  /// `fields` and `near_nullspace` (the first field's, may be null) are
  /// referenced by PETSc and must stay alive while the solver does.
  SaddlePointSolver(const SaddlePointSettings& settings, const std::vector<NamedIndexSet>& fields,
                    MatNullSpace near_nullspace = nullptr);

  /// Sets the operator (and preconditioning matrix) for the next solve.
  /// `schur` (iterative method, two fields): the Schur complement's
  /// preconditioning matrix on the second field's space, in the order of
  /// its index set; the other blocks of the preconditioner are then taken
  /// from `pmat` (or `a`), so no second copy of the whole system is needed.
  void set_operators(Mat a, Mat pmat, Mat schur = nullptr);
  /// Solves a x = b, rebuilding the preconditioner unless the reuse policy
  /// keeps it; throws SolverError if the solver does not converge even with
  /// a fresh preconditioner. With `x_is_guess` the Krylov method starts from
  /// x (e.g. the previous time step's solution) instead of zero, if x leaves
  /// a smaller residual than zero does; the tolerance stays relative to |b|,
  /// so a good guess saves iterations.
  SolveReport solve(Vec b, Vec x, bool x_is_guess = false);

  /// Number of preconditioner (re)builds so far (factorisations for the direct method).
  [[nodiscard]] int n_setups() const { return n_setups_; }

  [[nodiscard]] KSP ksp() const { return ksp_.get(); }

  /// The reuse policy's state: whether the next solve builds a fresh
  /// preconditioner, and the builds so far. Checkpoints save it, so that a
  /// restarted run refactors at the same steps as an uninterrupted one.
  [[nodiscard]] bool refactor_next() const { return refactor_next_; }
  /// Iterative method: the fewest iterations since the last rebuild (the
  /// reference of max_reuse_growth).
  [[nodiscard]] int fewest_iterations() const { return fewest_iterations_; }
  /// The next solve builds a fresh preconditioner, whatever the reuse
  /// policy would say (the owner knows the matrix changed too much).
  void refactor_at_next_solve() { refactor_next_ = true; }
  void restore_reuse_state(bool refactor_next, int n_setups, int fewest_iterations) {
    refactor_next_ = refactor_next;
    n_setups_ = n_setups;
    fewest_iterations_ = fewest_iterations;
  }
  /// Iterative method, two fields: a coarse correction of the Schur
  /// complement's preconditioner, Jacobi on `schur` (set_operators), where
  /// that is known to be wrong along a few vectors (the Stokes system: each
  /// drop's constant pressure at low viscosity ratios). Vectors in the
  /// layout of `schur`; the owner may change the coefficients before any
  /// solve. Applies while the second split's pc_type is jacobi (the default).
  [[nodiscard]] CoarseCorrection& schur_correction() { return *schur_correction_; }
  /// Iterative method: vectors of the first field's space that its
  /// preconditioner (BoomerAMG) is to solve exactly, la::make_two_level
  /// (the Stokes system: each very viscous drop's rigid motions). Whether
  /// there are any is read at the first solve; `renew` (may be empty) is
  /// called before every build of the preconditioner to bring the vectors
  /// up to date (e.g. to the current geometry), so that they never change
  /// between a build and the solves that use it.
  void set_primal_coarse_space(std::function<void(std::vector<SparseVector>&)> renew) {
    renew_primal_coarse_space_ = std::move(renew);
  }
  [[nodiscard]] const std::vector<SparseVector>& primal_coarse_space() const {
    return *primal_coarse_space_;
  }
  /// Iterative method: unknowns of the first field (this rank's positions
  /// in its split, ascending) that its preconditioner is to follow by an
  /// exact solve of their block, la::make_block_corrected (the oscillatory
  /// system: the interface nodes' velocities under the tension's stiff
  /// normal coupling at low frequency). Read at the first solve.
  /// It is solved while active (the default), and the switch may change
  /// between solves.
  /// Collective: every rank calls it, with its own rows (maybe none).
  void set_primal_exact_block(std::vector<PetscInt> rows) {
    primal_exact_block_ = std::move(rows);
    has_primal_exact_block_ = true;
  }
  void set_primal_exact_block_active(bool active) { *primal_exact_block_active_ = active; }
  /// Builds the preconditioner (factors) on the current operators now,
  /// without solving: a restart rebuilding the factors an earlier run had.
  void set_up();

 private:
  SolveReport solve_once(Vec b, Vec x, bool reuse, bool x_is_guess, int max_iterations);
  /// Whether |b - A x| < |b|: x is a better start than zero.
  [[nodiscard]] bool reduces_residual(Vec b, Vec x) const;

  /// After the outer setup, which makes the splits, once: the velocity
  /// split's preconditioner is followed by la::make_block_corrected if
  /// there is a primal exact block, then wrapped by la::make_two_level if
  /// there is a primal coarse space, and the Schur split's Jacobi becomes
  /// la::make_coarse_corrected_jacobi if there is a Schur correction.
  void install_coarse_spaces();
  /// Before a build of the preconditioner: the primal coarse space renewed.
  void renew_coarse_space();
  SaddlePointSettings settings_;
  // On the heap, and declared before ksp_ so that they outlive it: the
  // splits' shell preconditioners point to them.
  std::unique_ptr<CoarseCorrection> schur_correction_ = std::make_unique<CoarseCorrection>();
  std::unique_ptr<std::vector<SparseVector>> primal_coarse_space_ =
      std::make_unique<std::vector<SparseVector>>();
  std::function<void(std::vector<SparseVector>&)> renew_primal_coarse_space_;
  std::vector<PetscInt> primal_exact_block_;
  bool has_primal_exact_block_ = false;
  std::unique_ptr<bool> primal_exact_block_active_ = std::make_unique<bool>(true);
  bool coarse_spaces_installed_ = false;
  Solver ksp_;
  bool have_preconditioner_ = false;
  bool refactor_next_ = true;
  int n_setups_ = 0;
  int fewest_iterations_ = 0;
};

/// Sets `-name value` in PETSc's options database unless the user already set it.
void set_default_option(const std::string& name, const std::string& value);

}  // namespace softflow::la
