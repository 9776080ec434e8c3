#include "softflow/la/saddle_point_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/la/block_corrected.hpp"

namespace softflow::la {

void set_default_option(const std::string& name, const std::string& value) {
  PetscBool set = PETSC_FALSE;
  check(PetscOptionsHasName(nullptr, nullptr, name.c_str(), &set), "PetscOptionsHasName");
  if (!set) check(PetscOptionsSetValue(nullptr, name.c_str(), value.c_str()), "PetscOptionsSetValue");
}

namespace {

// Outer choices are set through the API (so two solvers in one process
// never see each other's choice); KSPSetFromOptions still lets the user
// override them with -<prefix>ksp_type etc.
void configure_direct(const SaddlePointSettings& s, KSP ksp) {
  // GMRES around the LU: one iteration with fresh factors, a few with
  // factors of an earlier (slightly different) matrix when they are reused.
  check(KSPSetType(ksp, s.max_reuse_iterations > 0 ? KSPGMRES : KSPPREONLY), "KSPSetType");
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  check(PCSetType(pc, PCLU), "PCSetType");
  check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
  // Saddle-point LU pivots off the diagonal; give MUMPS room to do so.
  set_default_option("-mat_mumps_icntl_14", "80");
}

void configure_iterative(const SaddlePointSettings& s, KSP ksp,
                         const std::vector<NamedIndexSet>& fields, MatNullSpace near_nullspace) {
  // Settings measured best on this machine (PLATFORM.md): lower-triangular
  // Schur factorisation, Schur complement approximated by the scaled
  // pressure mass matrix (the A11 block of the preconditioning matrix),
  // BoomerAMG tuned for 3D P2 velocity blocks, Jacobi on the pressure mass.
  // GMRES preconditioned on the right: the preconditioner (preonly blocks,
  // one AMG V-cycle) is a fixed linear operator, so flexible GMRES's second
  // basis is not needed; same iterations, one vector per iteration instead
  // of two (measured at 152k: 60 iterations either way, 937 -> 864 MB).
  // An inner Krylov solver set from the command line makes it nonlinear:
  // then -stokes_ksp_type fgmres. No restart below 200 iterations (at 30,
  // 60 iterations became 82).
  check(KSPSetType(ksp, KSPGMRES), "KSPSetType");
  check(KSPSetPCSide(ksp, PC_RIGHT), "KSPSetPCSide");
  check(KSPGMRESSetRestart(ksp, 200), "KSPGMRESSetRestart");
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  check(PCSetType(pc, PCFIELDSPLIT), "PCSetType");
  // Named fields, so every split can be tuned from the command line.
  for (const auto& f : fields)
    check(PCFieldSplitSetIS(pc, f.name.c_str(), f.rows), "PCFieldSplitSetIS");
  // The first field's near-nullspace reaches its sub-matrix through the
  // index set (PCFIELDSPLIT looks for "nearnullspace" composed on it); GAMG
  // uses it, and BoomerAMG when asked for interpolation vectors.
  if (near_nullspace && !fields.empty())
    check(PetscObjectCompose(reinterpret_cast<PetscObject>(fields.front().rows), "nearnullspace",
                             reinterpret_cast<PetscObject>(near_nullspace)),
          "PetscObjectCompose(nearnullspace)");
  if (fields.size() == 2) {
    check(PCFieldSplitSetType(pc, PC_COMPOSITE_SCHUR), "PCFieldSplitSetType");
    check(PCFieldSplitSetSchurFactType(pc, PC_FIELDSPLIT_SCHUR_FACT_LOWER), "SchurFactType");
    check(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_A11, nullptr), "SchurPre");
  } else {
    check(PCFieldSplitSetType(pc, PC_COMPOSITE_MULTIPLICATIVE), "PCFieldSplitSetType");
  }
  // The sub-solvers exist only after setup, so their defaults go through the
  // options database (only fieldsplit solvers with this prefix read them).
  // The first field is the velocity-like primal block; the others are
  // constraint-like (pressure: the scaled mass matrix, Jacobi is exact enough).
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const std::string v = "-" + s.prefix + "fieldsplit_" + fields[i].name + "_";
    set_default_option(v + "ksp_type", "preonly");
    if (i > 0) {
      set_default_option(v + "pc_type", "jacobi");
      continue;
    }
    set_default_option(v + "pc_type", "hypre");
    set_default_option(v + "pc_hypre_type", "boomeramg");
    set_default_option(v + "pc_hypre_boomeramg_strong_threshold", "0.7");
    set_default_option(v + "pc_hypre_boomeramg_coarsen_type", "HMIS");
    set_default_option(v + "pc_hypre_boomeramg_interp_type", "ext+i");
    set_default_option(v + "pc_hypre_boomeramg_P_max", "4");
    set_default_option(v + "pc_hypre_boomeramg_agg_nl", "1");
  }
}

/// Calls visit(KSP, index) for each split's solver of a fieldsplit preconditioner
/// that has been set up (the velocity's first); nothing for another type.
template <class Visit>
void for_each_split(KSP ksp, Visit&& visit) {
  PC pc = nullptr;
  check(KSPGetPC(ksp, &pc), "KSPGetPC");
  PetscBool fieldsplit = PETSC_FALSE;
  check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &fieldsplit),
        "PetscObjectTypeCompare");
  if (!fieldsplit) return;  // the user chose another preconditioner
  PCCompositeType type;
  check(PCFieldSplitGetType(pc, &type), "PCFieldSplitGetType");
  PetscInt n = 0;
  KSP* splits = nullptr;
  if (type == PC_COMPOSITE_SCHUR) check(PCFieldSplitSchurGetSubKSP(pc, &n, &splits), "PCFieldSplitSchurGetSubKSP");
  else check(PCFieldSplitGetSubKSP(pc, &n, &splits), "PCFieldSplitGetSubKSP");
  for (PetscInt k = 0; k < n; ++k) visit(splits[k], k);
  check(PetscFree(splits), "PetscFree");
}

/// Keeps (or frees to rebuild) the preconditioner of the fieldsplit's first
/// split (the velocity AMG) along with the outer one. KSPSetReusePreconditioner
/// on the outer solver alone skips PCFIELDSPLIT's setup, but a split whose
/// matrix is the operator's own block (la::NestedSaddlePoint: a reference,
/// not a copy frozen at setup) sees that block change and would rebuild its
/// AMG at every solve. The other splits (Jacobi on the pressure mass) stay
/// as they were: rebuilt whenever their matrix changes, which costs nothing.
void keep_primal_split(KSP ksp, bool keep) {
  for_each_split(ksp, [&](KSP split, PetscInt k) {
    if (k == 0)
      check(KSPSetReusePreconditioner(split, keep ? PETSC_TRUE : PETSC_FALSE),
            "KSPSetReusePreconditioner");
  });
}

}  // namespace

bool primal_split_uses_hypre(const SaddlePointSettings& settings, const std::string& primal_name) {
  if (settings.method != SaddlePointMethod::iterative) return false;
  auto option_is = [](const std::string& name, const char* expected) {
    char value[64] = "";
    PetscBool set = PETSC_FALSE;
    check(PetscOptionsGetString(nullptr, nullptr, name.c_str(), value, sizeof value, &set),
          "PetscOptionsGetString");
    return !set || std::string(value) == expected;
  };
  return option_is("-" + settings.prefix + "pc_type", "fieldsplit") &&
         option_is("-" + settings.prefix + "fieldsplit_" + primal_name + "_pc_type", "hypre");
}

long direct_solver_crossover_steps(long unknowns) {
  if (unknowns < kRunLengthRuleFrom) return 0;
  return static_cast<long>(std::ceil(100.0 * std::pow(static_cast<double>(unknowns) / 95000.0, 1.5)));
}

MethodChoice choose_method(SaddlePointMethod method, long unknowns, long planned_steps,
                           bool relaxing_phase) {
  using enum SaddlePointMethod;
  if (method != automatic) return {method, "solver.type"};
  if (unknowns > kDirectSolverLimit)
    return {iterative, fmt::format("auto: {} unknowns, above the {} a factorisation fits in memory for",
                                   unknowns, kDirectSolverLimit)};
  const long crossover = direct_solver_crossover_steps(unknowns);
  if (crossover == 0)
    return {direct, fmt::format("auto: {} unknowns, fewer than {}: a factorisation costs seconds",
                                unknowns, kRunLengthRuleFrom)};
  if (relaxing_phase && unknowns >= kRelaxingPhaseIterativeFrom)
    return {iterative, fmt::format("auto: {} unknowns with a viscoelastic liquid, at least the {} from "
                                   "which its changing stress terms make reused factors slower than the "
                                   "iterative path",
                                   unknowns, kRelaxingPhaseIterativeFrom)};
  if (planned_steps > 0 && planned_steps < crossover)
    return {iterative, fmt::format("auto: {} steps planned, fewer than the {} a factorisation of {} "
                                   "unknowns needs to pay off",
                                   planned_steps, crossover, unknowns)};
  const std::string planned = planned_steps > 0 ? fmt::format("{}", planned_steps) : "unknown";
  return {direct, fmt::format("auto: {} steps planned, at least the {} a factorisation of {} "
                              "unknowns needs to pay off",
                              planned, crossover, unknowns)};
}

SaddlePointSolver::SaddlePointSolver(const SaddlePointSettings& settings,
                                     const std::vector<NamedIndexSet>& fields,
                                     MatNullSpace near_nullspace)
    : settings_(settings) {
  if (settings.method == SaddlePointMethod::automatic)
    throw SolverError("SaddlePointSolver: the method must be resolved (resolve_method) before the solver is made");
  check(KSPCreate(PETSC_COMM_WORLD, ksp_.out()), "KSPCreate");
  check(KSPSetOptionsPrefix(ksp_.get(), settings.prefix.c_str()), "KSPSetOptionsPrefix");
  check(KSPSetTolerances(ksp_.get(), settings.rtol, PETSC_DEFAULT, PETSC_DEFAULT,
                         settings.max_iterations),
        "KSPSetTolerances");
  if (settings.method == SaddlePointMethod::direct) {
    configure_direct(settings, ksp_.get());
  } else {
    configure_iterative(settings, ksp_.get(), fields, near_nullspace);
  }
  check(KSPSetFromOptions(ksp_.get()), "KSPSetFromOptions");
  // The limit a user may have set (-<prefix>ksp_max_it): solve() lowers it
  // for a kept preconditioner and restores it.
  PetscReal rtol = 0.0, atol = 0.0, dtol = 0.0;
  PetscInt max_iterations = 0;
  check(KSPGetTolerances(ksp_.get(), &rtol, &atol, &dtol, &max_iterations), "KSPGetTolerances");
  settings_.max_iterations = static_cast<int>(max_iterations);
  // -<prefix>lu_reuse_max_its N overrides the reuse threshold (tests use a
  // low one to make a short run refactor several times).
  PetscInt reuse = settings_.max_reuse_iterations;
  PetscBool set = PETSC_FALSE;
  check(PetscOptionsGetInt(nullptr, settings_.prefix.c_str(), "-lu_reuse_max_its", &reuse, &set),
        "PetscOptionsGetInt");
  if (set) settings_.max_reuse_iterations = static_cast<int>(reuse);
  // -<prefix>pc_reuse_growth G overrides the iterative method's threshold.
  PetscReal growth = settings_.max_reuse_growth;
  check(PetscOptionsGetReal(nullptr, settings_.prefix.c_str(), "-pc_reuse_growth", &growth, &set),
        "PetscOptionsGetReal");
  if (set) settings_.max_reuse_growth = static_cast<double>(growth);
}

void SaddlePointSolver::set_operators(Mat a, Mat pmat, Mat schur) {
  check(KSPSetOperators(ksp_.get(), a, pmat ? pmat : a), "KSPSetOperators");
  if (!schur || settings_.method != SaddlePointMethod::iterative) return;
  PC pc = nullptr;
  check(KSPGetPC(ksp_.get(), &pc), "KSPGetPC");
  check(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, schur), "SchurPre(user)");
}

void SaddlePointSolver::set_up() {
  check(KSPSetReusePreconditioner(ksp_.get(), PETSC_FALSE), "KSPSetReusePreconditioner");
  check(KSPSetUp(ksp_.get()), "KSPSetUp");
  PC pc = nullptr;
  check(KSPGetPC(ksp_.get(), &pc), "KSPGetPC");
  renew_coarse_space();
  check(PCSetUp(pc), "PCSetUp");
  install_coarse_spaces();
  // The splits' preconditioners too, now: PCFIELDSPLIT builds them at their
  // first solve, and a split's matrix may be the operator's own block,
  // which holds another matrix by then (a restart's first step).
  for_each_split(ksp_.get(), [](KSP split, PetscInt) { check(KSPSetUp(split), "KSPSetUp(split)"); });
  ++n_setups_;
  have_preconditioner_ = true;
}

SolveReport SaddlePointSolver::solve(Vec b, Vec x, bool x_is_guess) {
  // A guess worse than zero is dropped: after a jump in the loads (walls
  // stopped, flow reversed) the previous step's flow can leave a residual
  // far above |b|, which the Krylov method would even report as divergence.
  if (x_is_guess && !reduces_residual(b, x)) x_is_guess = false;
  const bool direct = settings_.method == SaddlePointMethod::direct;
  const bool may_reuse = direct ? settings_.max_reuse_iterations > 0 : settings_.max_reuse_growth > 0.0;
  const bool reuse = may_reuse && have_preconditioner_ && !refactor_next_;
  // A kept iterative preconditioner gets twice its allowance before the
  // solve starts over with a fresh one: after a jump (a new viscosity, a
  // step after a restart of the flow) the old one can need many times the
  // iterations of a fresh one (measured: 365 against 70).
  const int cap = reuse && !direct
                      ? std::max(10, static_cast<int>(std::ceil(2.0 * settings_.max_reuse_growth *
                                                                fewest_iterations_)))
                      : settings_.max_iterations;
  SolveReport r = solve_once(b, x, reuse, x_is_guess, std::min(cap, settings_.max_iterations));
  // Stale factors or a misleading guess: once more with fresh factors from zero.
  int failed_iterations = 0;
  double failed_seconds = 0.0;
  if ((reuse || x_is_guess) && r.reason.rfind("DIVERGED", 0) == 0) {
    failed_iterations = r.iterations;
    failed_seconds = r.seconds;
    r = solve_once(b, x, false, false, settings_.max_iterations);
  }
  if (r.reason == "DIVERGED_NANORINF") {
    throw SolverError(fmt::format(
        "the Stokes system holds NaN or Inf ({} after {} iterations): a parameter far out of "
        "range (capillary number, interfacial tension, viscosity ratio) or a tangled mesh; check "
        "the case's values, or try a smaller time.step",
        r.reason, r.iterations));
  }
  if (r.reason.rfind("DIVERGED", 0) == 0) {
    // The advice depends on the method: switching to the direct solver is
    // no help when it is the direct solver whose factorisation failed.
    const char* advice =
        direct ? (r.reason == "DIVERGED_PC_FAILED"
                      ? "the LU factorisation failed (a zero pivot: check solver.petsc_options for a "
                        "factorisation without pivoting, the case's viscosities and tensions, or a "
                        "tangled mesh; try a smaller time.step)"
                      : "try a smaller time.step or a finer mesh")
               : "try [solver] type = \"direct\", a larger max_iterations, or a finer mesh";
    throw SolverError(fmt::format("Stokes solver did not converge: {} after {} iterations "
                                  "(residual {:.3e}); {}",
                                  r.reason, r.iterations, r.residual_norm, advice));
  }
  if (direct) {
    refactor_next_ = r.iterations > settings_.max_reuse_iterations;
  } else {
    // The fewest iterations since the rebuild measure how good a fresh
    // preconditioner is for this run (the first solve, from zero, needs
    // more than later ones from the previous step's flow); once the kept
    // one costs max_reuse_growth times that, rebuilding pays.
    fewest_iterations_ = r.reused_preconditioner ? std::min(fewest_iterations_, r.iterations)
                                                 : r.iterations;
    refactor_next_ = r.iterations > settings_.max_reuse_growth * std::max(fewest_iterations_, 1);
  }
  // The report counts the attempt given up too (the policy above judged
  // the preconditioner that produced the answer).
  r.iterations += failed_iterations;
  r.seconds += failed_seconds;
  return r;
}

void SaddlePointSolver::renew_coarse_space() {
  if (renew_primal_coarse_space_) renew_primal_coarse_space_(*primal_coarse_space_);
}

void SaddlePointSolver::install_coarse_spaces() {
  if (coarse_spaces_installed_ || settings_.method != SaddlePointMethod::iterative) return;
  coarse_spaces_installed_ = true;  // decided once, whatever the outcome
  if (schur_correction_->empty() && primal_coarse_space_->empty() && !has_primal_exact_block_)
    return;
  PC pc = nullptr;
  check(KSPGetPC(ksp_.get(), &pc), "KSPGetPC");
  PetscBool fieldsplit = PETSC_FALSE;
  check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &fieldsplit),
        "PetscObjectTypeCompare");
  if (!fieldsplit) return;
  PCCompositeType type;
  check(PCFieldSplitGetType(pc, &type), "PCFieldSplitGetType");
  if (type != PC_COMPOSITE_SCHUR) return;
  for_each_split(ksp_.get(), [&](KSP split, PetscInt k) {
    if (k == 0 && (!primal_coarse_space_->empty() || has_primal_exact_block_)) {
      PC split_pc = nullptr;
      check(KSPGetPC(split, &split_pc), "KSPGetPC");
      const char* prefix = nullptr;
      check(KSPGetOptionsPrefix(split, &prefix), "KSPGetOptionsPrefix");
      const MPI_Comm comm = PetscObjectComm(reinterpret_cast<PetscObject>(split));
      // The split's own choice (BoomerAMG by default), made anew from the options.
      PC smoother = nullptr;
      check(PCCreate(comm, &smoother), "PCCreate");
      check(PCSetOptionsPrefix(smoother, prefix), "PCSetOptionsPrefix");
      check(PCSetFromOptions(smoother), "PCSetFromOptions");
      // The block correction is the split's preconditioner, or the two-level
      // one's smoother when there is a coarse space too.
      const bool two_level = !primal_coarse_space_->empty();
      if (has_primal_exact_block_) {
        PC corrected = split_pc;
        if (two_level) check(PCCreate(comm, &corrected), "PCCreate");
        make_block_corrected(corrected, smoother, primal_exact_block_,
                             primal_exact_block_active_.get());
        smoother = corrected;
      }
      if (two_level) make_two_level(split_pc, smoother, *primal_coarse_space_);
      return;
    }
    if (k != 1 || schur_correction_->empty()) return;  // the Schur complement's solver
    PC schur_pc = nullptr;
    check(KSPGetPC(split, &schur_pc), "KSPGetPC");
    PetscBool jacobi = PETSC_FALSE;
    check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(schur_pc), PCJACOBI, &jacobi),
          "PetscObjectTypeCompare");
    if (jacobi) make_coarse_corrected_jacobi(schur_pc, *schur_correction_);
  });
}

bool SaddlePointSolver::reduces_residual(Vec b, Vec x) const {
  Mat a = nullptr;
  check(KSPGetOperators(ksp_.get(), &a, nullptr), "KSPGetOperators");
  la::Vector r;
  check(VecDuplicate(b, r.out()), "VecDuplicate");
  check(MatMult(a, x, r.get()), "MatMult");
  check(VecAYPX(r.get(), -1.0, b), "VecAYPX");  // r = b - A x
  PetscReal residual = 0.0, rhs = 0.0;
  check(VecNorm(r.get(), NORM_2, &residual), "VecNorm");
  check(VecNorm(b, NORM_2, &rhs), "VecNorm");
  return residual < rhs;
}

SolveReport SaddlePointSolver::solve_once(Vec b, Vec x, bool reuse, bool x_is_guess,
                                          int max_iterations) {
  const auto start = std::chrono::steady_clock::now();
  // Only the iteration limit changes (PETSC_DEFAULT keeps the rest).
  check(KSPSetTolerances(ksp_.get(), PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, max_iterations),
        "KSPSetTolerances");
  check(KSPSetInitialGuessNonzero(ksp_.get(), x_is_guess ? PETSC_TRUE : PETSC_FALSE),
        "KSPSetInitialGuessNonzero");
  check(KSPSetReusePreconditioner(ksp_.get(), reuse ? PETSC_TRUE : PETSC_FALSE),
        "KSPSetReusePreconditioner");
  // The splits exist once the preconditioner was built.
  if (settings_.method == SaddlePointMethod::iterative && have_preconditioner_)
    keep_primal_split(ksp_.get(), reuse);
  if (!reuse) {
    renew_coarse_space();
    ++n_setups_;
  }
  have_preconditioner_ = true;
  if (!coarse_spaces_installed_ && settings_.method == SaddlePointMethod::iterative) {
    check(KSPSetUp(ksp_.get()), "KSPSetUp");  // makes the splits
    install_coarse_spaces();
  }
  check(KSPSolve(ksp_.get(), b, x), "KSPSolve");
  SolveReport r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  PetscInt its = 0;
  check(KSPGetIterationNumber(ksp_.get(), &its), "KSPGetIterationNumber");
  r.iterations = static_cast<int>(its);
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(ksp_.get(), &reason), "KSPGetConvergedReason");
  r.reason = KSPConvergedReasons[reason];
  check(KSPGetResidualNorm(ksp_.get(), &r.residual_norm), "KSPGetResidualNorm");
  r.reused_preconditioner = reuse;
  return r;
}

}  // namespace softflow::la
