// Assembly and solution of the two-phase Taylor-Hood Stokes system with PETSc.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "softflow/common/state.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/nested_saddle_point.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/la/saddle_point_solver.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/stokes/stokes_kernels.hpp"
#include "softflow/physics/stokes/stokes_problem.hpp"

namespace softflow::physics {

/// Field indices of the Taylor-Hood dof map (make_stokes_dof_map).
inline constexpr int kVelocityField = 0;
inline constexpr int kPressureField = 1;

/// The unknowns of thesis §2.3.1: velocity = 3 x P2, continuous across
/// interfaces (no slip) or, with `interface_slip`, one copy per region
/// coupled by multipliers (field "multiplier", kMultiplierField, 3 x P2 on
/// the interfaces; physics/stokes/interface_slip.hpp); pressure = P1 per
/// region, so it may jump across an interface. Fields "velocity"
/// (kVelocityField) and "pressure" (kPressureField).
fem::DofMap make_stokes_dof_map(const mesh::Mesh& mesh, bool interface_slip);

/// The 18 unknowns (6 nodes x 3 components) of `field` (velocity or, with
/// slip, the multipliers) on interface triangle `face`, as seen from
/// `region`: the side's own velocity copy with slip, the shared one without;
/// the multipliers' region is the face's object.
[[nodiscard]] std::array<PetscInt, 18> interface_face_dofs(const fem::DofMap& dofs, const mesh::Mesh& mesh, int face,
                                                           int field, int region);

/// Where a solve leaves its solution: distributed only (a time loop, whose
/// stages read what they need of it), or also gathered on every rank (one
/// solve's analysis and output, tests).
enum class SolutionLayout { distributed, gathered };

struct StokesResult {
  /// This rank's rows of the Stokes dof map (its ownership()), as solved.
  la::Vector distributed;
  /// Every dof, on every rank: with SolutionLayout::gathered only, else empty.
  std::vector<double> solution;
  la::SolveReport solve;
  double assembly_seconds = 0.0;
};

/// The two-phase Stokes solve of thesis §2.3.1 (Newtonian phases):
///
///   find u (P2, continuous), p (P1 per region) such that for all v, q
///   (1) sum_r (2 eta_r D(v), D(u))_r
///   (2)   - sum_r (div v, p)_r
///   (3)   + sum_k Gamma_k integral_{S_k} (grad_s v)^T : (I - n n) ds   = (v, f)
///   (4) - sum_r (q, div u)_r                                          = 0
///
/// with u = g on the walls and pressure fixed at one matrix vertex. Mesh and
/// dof map are replicated on every rank; each rank assembles its own rows of
/// every element that has one (la::CsrMatrix): nothing crosses ranks.
///
/// The block system and the preconditioner of the iterative method:
///
///     [ A   B^T ] [u]   [f]          P = [ A    0      ]
///     [ B   0   ] [p] = [0]              [ B  -M/eta   ]
///
/// A = (1) plus the semi-implicit tension's surface Laplacian, B = (4),
/// M/eta the pressure mass weighted by 1/viscosity per phase, assembled as a
/// matrix of the pressure space alone (P's other blocks are the operator's).
class StokesSystem {
 public:
  /// `interface_slip`: separate velocity copies at interfaces coupled by
  /// multipliers, for problems with Navier slip (StokesProblem::slip).
  StokesSystem(const mesh::Mesh& mesh, const la::SaddlePointSettings& settings,
               bool interface_slip = false);
  ~StokesSystem();
  StokesSystem(const StokesSystem&) = delete;
  StokesSystem& operator=(const StokesSystem&) = delete;

  [[nodiscard]] const fem::DofMap& dofs() const { return dofs_; }
  [[nodiscard]] const mesh::Mesh& mesh() const { return mesh_; }
  /// Whether the velocity has a copy per region coupled by slip multipliers.
  [[nodiscard]] bool interface_slip() const { return slip_; }
  /// With slip: the nodal normals the slip rows use on `geometry`
  /// (interface_node_normals), which slip_measures needs.
  [[nodiscard]] std::vector<Eigen::Vector3d> slip_node_normals(const mesh::Mesh& geometry) const {
    return interface_node_normals(surfaces_, geometry);
  }
  [[nodiscard]] la::OwnershipRange ownership() const { return range_; }
  /// Preconditioner builds so far (LU factorisations with the direct method).
  [[nodiscard]] int n_factorizations() const { return solver_->n_setups(); }
  /// The solver, for saving and restoring its preconditioner reuse state (restarts).
  [[nodiscard]] la::SaddlePointSolver& solver() { return *solver_; }

  /// Assembles the problem on the current mesh and solves it. `step`: the
  /// time step this solve ends, in a time loop; the initial guess is then
  /// extrapolated from the last two solutions when they were steps too
  /// (settings().extrapolated_guess), else it is the last solution.
  StokesResult solve(const StokesProblem& problem, SolutionLayout layout = SolutionLayout::gathered,
                     std::optional<double> step = std::nullopt);
  /// A jump of the walls before the next solve: its guess and the next one's
  /// are the last solution alone (a line through solutions on both sides of
  /// the jump points nowhere); the line starts again after them.
  void restart_guess_history() {
    older_solution_.reset();
    previous_step_ = 0.0;
  }
  /// The guess history's place: the solves so far (kept in a step's saved state).
  [[nodiscard]] long guess_history_mark() const { return solves_; }
  /// Back to `mark` after a rejected or failed step: if one solve came
  /// since, its place in the history is undone, so that the retried step
  /// extrapolates along the solutions before it with its own step; if none,
  /// nothing changes; more than one (not a single step) restarts the line.
  void rewind_guess_history(long mark);
  /// Whether assembling sends matrix rows to other ranks (it does not:
  /// each rank assembles its own rows of every element it shares).
  [[nodiscard]] bool assembly_crosses_ranks() const {
    return (a_ && a_->rows_cross_ranks()) || (nested_ && nested_->rows_cross_ranks()) ||
           (pmat_ && pmat_->rows_cross_ranks()) ||
           (schur_ && schur_->rows_cross_ranks());
  }
  /// The solver settings in use (solver.type "auto" resolved).
  [[nodiscard]] const la::SaddlePointSettings& settings() const { return settings_; }
  /// Why settings().method is the one in use (la::choose_method).
  [[nodiscard]] const std::string& method_reason() const { return method_reason_; }

  /// The direct method's factorisation reuse as a part of the run's state
  /// ("stokes"): whether the next solve refactors, the builds so far, and
  /// for the factors in use and for MUMPS's symbolic analysis (the first
  /// factorisation) what their matrices were made of (nodes, viscosities,
  /// tensions, the semi-implicit term's theta dt and normals, the gauge).
  /// restore_state() assembles and factors those matrices again, in the
  /// same order, so a restarted run keeps the very same factors and its
  /// later solves agree with an uninterrupted run's to round-off (fresh
  /// factors would change every later solve at the solver tolerance). The
  /// iterative method's kept preconditioner is rebuilt the same way.
  [[nodiscard]] StatePart state_part();

 private:
  /// What a matrix (not the right-hand side) depends on.
  struct MatrixRecord {
    std::vector<mesh::Point> nodes;
    StokesProblem problem;  ///< without loads: body force, boundary values, w unused
    /// The viscoelastic coupling's conformation c_n and c_{n-1} (this rank's
    /// values of the fields; empty if inactive or not used) and whether its
    /// DEVSS-G term was on: the matrix reads them, and the BDF step in
    /// problem.viscoelastic.
    std::vector<double> conformation, previous_conformation;
    bool devss = false;
  };
  void save_state(StateRecord& record, const std::string& prefix) const;
  void restore_state(const StateRecord& record, const std::string& prefix);
  /// Assembles the matrix of `record` and builds the preconditioner (factors) on it.
  void factor(const MatrixRecord& record);
  void record_factorization(const StokesProblem& problem);
  /// Whether the direct method's factors were made at a step so different
  /// from `problem`'s that they should be made again (kStaleStepRatio).
  [[nodiscard]] bool factors_are_off_step(const StokesProblem& problem) const;
  void partition();
  void create_matrices();
  /// The iterative method without slip: the Schur complement's
  /// preconditioning matrix -M/eta on the pressure space alone (the
  /// velocity block is A's own), instead of a second copy of the whole
  /// system.
  void create_schur_matrix();
  /// The iterative method without slip: the coarse spaces that make its
  /// preconditioner robust in the viscosity ratio (docs/stokes_engine.md),
  /// chosen at the first assembly by each object's viscosity against the
  /// matrix's. Objects less viscous: their constant pressure corrects the
  /// Schur complement's estimate (schur_estimate.hpp), coefficients
  /// updated here at every assembly. Objects more viscous: their six rigid
  /// motions are solved exactly by the velocity preconditioner
  /// (la::make_two_level), renewed on the assembled geometry at each build
  /// of the preconditioner. Collective.
  void update_coarse_spaces(const StokesProblem& problem);
  /// 1 on the pressure unknowns of `object`, in schur_'s layout.
  [[nodiscard]] la::Vector object_pressure_constant(int object) const;
  /// The six rigid motions of each of `objects` (on its nodes, on
  /// `geometry`), in the velocity block's layout (this rank's part), six
  /// per object in the order given.
  [[nodiscard]] std::vector<la::SparseVector> rigid_motions(const mesh::Mesh& geometry,
                                                           const std::vector<int>& objects) const;
  /// The iterative method without slip: the operator as its velocity block
  /// A and gradient block G (la::NestedSaddlePoint), each numbered by its
  /// field's unknowns in global order (the pressure's by
  /// create_schur_matrix, called before), instead of a_: the
  /// fieldsplit preconditioner then takes A, G and G^T by reference.
  void create_nested_matrices();
  /// The operator the Krylov method multiplies with.
  [[nodiscard]] Mat operator_matrix() const;
  /// Rigid-body modes of the owned velocity dofs: the near-nullspace AMG
  /// needs to coarsen a 3D elasticity-like velocity block well.
  la::NullSpace velocity_near_nullspace() const;
  /// Assembles on `geometry` (the current mesh, or a saved node set of it).
  void assemble(const mesh::Mesh& geometry, const StokesProblem& problem, Vec rhs);
  /// Assembly, Dirichlet elimination and operators handed to the solver:
  /// the system ready to solve, as (right-hand side, initial guess with the
  /// boundary values).
  /// `guess` (distributed like x; null = zero) fills x's free entries.
  std::pair<la::Vector, la::Vector> assemble_system(const mesh::Mesh& geometry,
                                                    const StokesProblem& problem,
                                                    Vec guess = nullptr);
  /// The conformation's record (MatrixRecord::conformation) as a field of
  /// this mesh, for assembling the matrix it was part of.
  [[nodiscard]] fem::Field conformation_field(const std::vector<double>& owned_values) const;
  /// The extrapolated initial guess of a solve ending a step `step`, or null
  /// (solve then starts from the last solution).
  [[nodiscard]] la::Vector initial_guess(std::optional<double> step) const;
  /// Keeps x as the last solution, and the one before as the older if both ended steps.
  void keep_solution(Vec x, std::optional<double> step);
  void apply_dirichlet(const StokesProblem& problem, Vec rhs, Vec x);
  /// Whether the pressure level is set after the solve instead of by a
  /// constrained unknown: the iterative method without slip. Pinning one
  /// pressure value puts a point constraint in the pressure block that
  /// the Schur complement's mass-matrix approximation does not see: at
  /// 152k unknowns it cost 60 iterations instead of 38, and at lambda =
  /// 0.01 76 instead of 45. The operator carries the constant pressure as
  /// its null space instead. (LU needs the constraint; with slip the
  /// constant mode also moves the multipliers, and the slip path keeps it.)
  [[nodiscard]] bool gauge_after_solve() const;
  void attach_pressure_nullspace();
  /// The continuity rows' net flux defect moved to the gauge's row (as the
  /// pinned system has it). Collective.
  void move_flux_defect_to_gauge(const StokesProblem& problem, Vec rhs) const;
  /// Shifts the pressure of every region by one constant so that the gauge
  /// node has the gauge value. Collective.
  void apply_gauge(const StokesProblem& problem, Vec x) const;
  /// The 18 velocity unknowns of interface triangle `face` on the side of
  /// `region` (the same for both with a continuous velocity).
  [[nodiscard]] std::array<PetscInt, 18> interface_velocity_dofs(int face, int region) const;
  /// The side that carries the tension load: the object's copy with slip
  /// (so that the multipliers are the matrix traction), else the shared one.
  [[nodiscard]] int tension_region(int face) const;
  /// What the slip constraint rows need at the interface nodes of the
  /// geometry being assembled (indexed by mesh node).
  struct SlipNodes {
    std::vector<Eigen::Vector3d> normal;  ///< interface_node_normals
    std::vector<double> scale;            ///< s_i, interface_node_scale
    [[nodiscard]] TriangleNormals of(const std::array<int, 6>& tri) const;
  };
  /// The N `dofs` with those of other ranks replaced by -1 (dropped): the
  /// rows this rank assembles of an element it shares.
  template <std::size_t N, class Dofs>
  [[nodiscard]] std::array<PetscInt, N> row_dofs(const Dofs& dofs) const {
    std::array<PetscInt, N> rows;
    for (std::size_t k = 0; k < N; ++k) rows[k] = range_.owns(dofs[k]) ? dofs[k] : -1;
    return rows;
  }
  /// Tetrahedron t's dofs (fem::DofMap::element_dofs) as row_dofs.
  [[nodiscard]] std::array<PetscInt, kTetVelocityDofs + kTetPressureDofs> tet_row_dofs(int t) const {
    return row_dofs<kTetVelocityDofs + kTetPressureDofs>(dofs_.element_dofs(t));
  }
  /// The object (1-based) of an interface node: its multipliers' region.
  [[nodiscard]] int interface_object_of(int node) const;
  /// Slip coupling (interface_slip.hpp): multiplier columns of the velocity
  /// rows of each owned interface face, constraint rows of each face with an
  /// owned multiplier.
  void assemble_slip(const mesh::Mesh& geometry, const StokesProblem& problem,
                     const SlipNodes& nodes);
  /// The iterative method's preconditioning matrix: the jump penalty and the
  /// multipliers' Schur complement estimate in their constraint block (after
  /// a_ is assembled: it reads a_'s diagonal).
  void assemble_slip_schur_estimate(const StokesProblem& problem, const SlipNodes& nodes);
  /// The iterative method with slip: the null vector's multipliers (-n_a)
  /// at this geometry, attached to the operator again.
  void attach_slip_pressure_nullspace(const SlipNodes& nodes);

  const mesh::Mesh& mesh_;
  la::SaddlePointSettings settings_;
  std::string method_reason_;
  bool slip_ = false;
  std::vector<InterfaceMesh> surfaces_;    // with slip: for the node normals
  std::vector<int> owned_interface_nodes_;  // with slip: nodes whose multipliers this rank owns
  std::vector<int> constraint_faces_;       // with slip: faces with a multiplier row here
  fem::DofMap dofs_;
  fem::TetTabulation tabulation_;
  la::OwnershipRange range_;
  /// Elements and interface faces with at least one row on this rank (partition()).
  std::vector<int> assembled_tets_;
  std::vector<int> assembled_faces_;
  using InterfaceMatrix = Eigen::Matrix<double, 18, 18>;
  // The operator: one matrix a_ (direct method, slip), or its two blocks
  // (nested_: iterative without slip).
  std::unique_ptr<la::CsrMatrix> a_;
  std::unique_ptr<la::NestedSaddlePoint> nested_;
  std::vector<la::CsrMatrix::Block> coupling_blocks_;  // nested_'s G, one per tet
  // The iterative method's preconditioning: with slip a whole matrix pmat_
  // (penalised velocity block, constraint estimates); without, only the
  // pressure block -M/eta (schur_), numbered by pressure_position_.
  std::unique_ptr<la::CsrMatrix> pmat_;
  std::unique_ptr<la::CsrMatrix> schur_;
  std::vector<la::CsrMatrix::Block> schur_blocks_;
  std::vector<int> pressure_position_;  // dof -> index among the pressure unknowns, or -1
  bool coarse_spaces_made_ = false;          // update_coarse_spaces
  // The geometry of the last assembly (assemble_system): the rigid motions
  // are renewed on it when the solver builds its preconditioner.
  const mesh::Mesh* assembled_geometry_ = nullptr;
  std::vector<int> schur_correction_objects_;  // the object of each Schur correction vector
  std::vector<la::CsrMatrix::Block> tet_blocks_, interface_blocks_;
  std::vector<la::CsrMatrix::Block> slip_coupling_blocks_, slip_constraint_blocks_;
  std::vector<la::CsrMatrix::Block> slip_penalty_blocks_, slip_compliance_blocks_;  // pmat_ only
  std::vector<la::IndexSet> field_index_sets_;
  std::unique_ptr<la::SaddlePointSolver> solver_;
  /// The last solution (distributed; null before the first solve): the
  /// next solve's initial guess. The dofs never change (the mesh moves, it
  /// is not remeshed), and a step changes the solution by O(dt): a few
  /// Krylov iterations fewer per step.
  la::Vector previous_solution_;
  /// The solution before it (null unless both ended time steps), and the
  /// step between the two: the extrapolated guess's line.
  la::Vector older_solution_;
  double previous_step_ = 0.0;
  /// Solves so far, and the history as it was before the last one (rewind_guess_history).
  long solves_ = 0;
  la::Vector undo_previous_, undo_older_;
  double undo_step_ = 0.0;
  /// 1 at every pressure unknown, 0 elsewhere (gauge_after_solve()).
  la::Vector pressure_constant_;
  std::optional<MatrixRecord> analysis_, factors_;  // analysis_: the direct method's
};

/// The matrix vertex on the bottom wall nearest its centre: where the
/// pressure level is fixed by default.
int default_pressure_gauge_node(const mesh::Mesh& mesh);

}  // namespace softflow::physics
