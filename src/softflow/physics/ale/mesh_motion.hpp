// ALE mesh motion (thesis §2.3.3, eq. 2.55 as corrected in SPEC §9):
// the displacement d of the mesh nodes solves  div(k_e grad d) = 0,
// k_e = 1 / (volume of element e), with the interface displacement as
// Dirichlet data and d = 0 on the outer boundary (walls, non-periodic faces).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/state.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::physics {

enum class AleMethod {
  /// direct up to kAleDirectLimit unknowns, iterative above (README.md).
  automatic,
  /// MUMPS Cholesky, factored once; one triangular solve with the three
  /// components as a block right-hand side per call. Fastest per call at
  /// 10k-100k unknowns, but its memory grows like n^(4/3).
  direct,
  /// CG + hypre BoomerAMG, set up once, each component warm-started from its
  /// previous solution.
  iterative,
};

/// Largest number of unknowns for which AleMethod::automatic factors: about
/// the mesh size at which the Stokes solve turns iterative
/// (la::kDirectSolverLimit, 150k Stokes unknowns ~ 50k nodes), where memory
/// is what limits a run. Measured on the 374k-unknown drop (125k ALE
/// unknowns, issue 12): the Cholesky factor took a time step from 1099 to
/// 1779 MB for 0.81 -> 0.24 s of ALE per 11.6 s step.
inline constexpr int kAleDirectLimit = 50000;

struct AleSettings {
  AleMethod method = AleMethod::automatic;
  /// Iterative method: CG stops at unpreconditioned residual <= rtol * norm(rhs).
  double rtol = 1e-10;
  int max_iterations = 1000;  ///< iterative method
  /// Options prefix: e.g. -ale_pc_type gamg, -ale_ksp_monitor override the choices.
  std::string prefix = "ale_";
};

/// Element matrix of the mesh-motion operator in the local P2 node order.
using AleTetMatrix = Eigen::Matrix<double, 10, 10>;

/// k_e * integral over the tetrahedron of grad N_i . grad N_j, with
/// k_e = 1 / (volume of the tetrahedron), on the isoparametric P2 map.
/// Returns the volume. Throws SolverError on a non-positive Jacobian.
double ale_tet_matrix(const element::TetNodes& x, const fem::TetTabulation& tab, AleTetMatrix& out);

/// Harmonic-type extension of the interface displacement into the volume:
///
///   div(k_e grad d) = 0   in every tetrahedron (matrix and objects),
///   d = d_S               on every interface node (mesh.interface_faces),
///   d = 0                 on every outer boundary node (mesh.boundary_faces),
///
/// solved for the three components separately with one scalar operator.
///
/// The operator lives on the REFERENCE mesh given to the constructor and is
/// assembled, and its preconditioner/factorisation built, once: a deliberate
/// speed choice. Because it is linear, extending the per-step increment and
/// adding it to the current positions is the same as extending the total
/// interface displacement from the reference positions; the weight
/// k_e = 1/V_e of the reference elements makes the big far-field elements
/// absorb the deformation and keeps the small interface elements stiff.
///
/// Unknowns: one per representative node (periodic copies share it, so
/// periodic nodes keep differing by lattice vectors). Prescribed nodes are
/// eliminated: the system has only free unknowns, and the right-hand side
/// is -C d_S with C the free-interface coupling block, kept from assembly.
/// A node on both an interface and the outer boundary (objects never touch
/// the box, so in principle none) follows the interface.
///
/// Parallel layout as fem::DofMap: the mesh is replicated, each rank owns
/// the free unknowns of its node range (fem::rank_node_range) and assembles
/// the tetrahedra whose first node's representative is in it; their rows of
/// other ranks reach their owner through la::CsrMatrix (once per rebuild of
/// the operator).
class AleMeshMotion {
 public:
  explicit AleMeshMotion(const mesh::Mesh& reference, const AleSettings& settings = {});
  ~AleMeshMotion();
  AleMeshMotion(const AleMeshMotion&) = delete;
  AleMeshMotion& operator=(const AleMeshMotion&) = delete;

  /// Displacement of every mesh node (replicated on every rank) given the
  /// displacement of the interface nodes. The input is indexed by mesh node
  /// and must have mesh.n_nodes() entries; only interface nodes are read
  /// (interface_nodes()), and the result equals the input there exactly.
  /// Collective. Throws SolverError if CG does not converge.
  std::vector<Eigen::Vector3d> solve(const std::vector<Eigen::Vector3d>& interface_displacement);

  /// Every mesh node on an interface: the nodes solve() reads.
  [[nodiscard]] const std::vector<int>& interface_nodes() const { return interface_nodes_; }
  /// Global number of free (solved-for) unknowns per component.
  [[nodiscard]] int n_unknowns() const { return n_free_; }
  /// This rank's contiguous range of free unknowns.
  [[nodiscard]] la::OwnershipRange ownership() const { return free_range_; }
  /// The method in use (never automatic).
  [[nodiscard]] AleMethod method() const { return method_; }

  /// The iterative method's warm start (each component's last solution)
  /// under `prefix`: a restarted run that restores it solves every later
  /// step from the same start as an uninterrupted run, so their meshes
  /// agree to round-off instead of to the CG tolerance. Nothing for the
  /// direct method (its answer does not depend on a start). Collective.
  void save_warm_start(StateRecord& record, const std::string& prefix) const;
  /// Reads what save_warm_start wrote (nothing if the record has none, or
  /// for the direct method). Collective.
  void restore_warm_start(const StateRecord& record, const std::string& prefix);

  /// Assembly of the operator (seconds, this rank).
  [[nodiscard]] double assembly_seconds() const { return assembly_seconds_; }
  /// Preconditioner setup or factorisation (seconds).
  [[nodiscard]] double setup_seconds() const { return setup_seconds_; }
  /// Wall time of the last solve() call: right-hand sides, 3 solves, gathers.
  [[nodiscard]] double last_solve_seconds() const { return last_solve_seconds_; }
  /// Krylov iterations of the last solve() per component (1 each for direct).
  [[nodiscard]] const std::array<int, 3>& last_iterations() const { return last_iterations_; }
  [[nodiscard]] int last_total_iterations() const {
    return last_iterations_[0] + last_iterations_[1] + last_iterations_[2];
  }

 private:
  void partition(const mesh::Mesh& mesh);
  void assemble(const mesh::Mesh& mesh);
  void create_solver();
  void interface_rhs(const std::vector<Eigen::Vector3d>& d_s, int component, Vec b);
  void solve_iterative(const std::vector<Eigen::Vector3d>& d_s, int component);
  void solve_direct(const std::vector<Eigen::Vector3d>& d_s);

  AleSettings settings_;
  AleMethod method_ = AleMethod::direct;
  int n_nodes_ = 0;
  std::vector<int> master_;            // node -> representative (identity if not periodic)
  std::vector<int> free_index_;        // representative -> free unknown, -1 if prescribed/unused
  std::vector<int> interface_index_;   // representative -> interface unknown, -1 otherwise
  std::vector<int> interface_source_;  // representative -> node whose input it takes, -1
  std::vector<int> interface_nodes_;
  std::vector<int> owned_interface_source_;  // this rank's interface unknowns -> input node
  std::vector<int> owned_tets_;
  int n_free_ = 0;
  int n_interface_ = 0;
  la::OwnershipRange free_range_;
  la::OwnershipRange interface_range_;

  la::Matrix a_;         // free-free block (SPD)
  la::Matrix coupling_;  // free-interface block C
  la::Solver ksp_;
  la::Vector rhs_, interface_values_;
  std::array<la::Vector, 3> solution_;     // iterative: kept as the next warm start
  la::Matrix rhs_block_, solution_block_;  // direct: the 3 components as dense columns
  la::Vector gathered_;                    // every free unknown, on every rank
  la::Owned<VecScatter, VecScatterDestroy> to_all_;

  double assembly_seconds_ = 0.0;
  double setup_seconds_ = 0.0;
  double last_solve_seconds_ = 0.0;
  std::array<int, 3> last_iterations_{0, 0, 0};
};

/// Carries every object of `mesh` rigidly by `offset` (mesh.point_symmetric_start):
/// the interface nodes move by it, every other node by the mesh motion's
/// extension of it (eq. 2.55), so the objects' interiors move rigidly too
/// (the extension of constant data is constant), the walls stay, and the
/// liquid's elements between them take up the offset. The extension is
/// equivariant under any symmetry of the mesh: carried by -offset, the
/// image of a symmetric mesh is the image of the mesh carried by +offset.
/// Where one extension of the whole offset inverts an element, the offset
/// is taken in 2, 4, ... 16 equal steps, each extended on the mesh the one
/// before left (k_e = 1/V_e stiffens the squeezed elements). Returns the
/// number of steps taken. Collective. Throws MeshError naming
/// mesh.point_symmetric_start if an element inverts even in 16 steps.
int carry_objects(mesh::Mesh& mesh, const Eigen::Vector3d& offset);

/// A linear deformation of one object about a point: x -> centre + map (x - centre).
struct ObjectDeformation {
  int object = 0;  ///< 1-based
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d map = Eigen::Matrix3d::Identity();
};

/// Deforms objects of `mesh` by linear maps ([[objects]] initial_deformation):
/// every node of an object (its interface and interior) moves exactly by its
/// map, every liquid node by the mesh motion's extension of the interface
/// displacement (eq. 2.55, one factored solve), the walls stay. A map of
/// determinant 1 keeps the object's discrete volume exactly (the P2
/// geometry composed with a linear map), and the interface nodes of a
/// sphere land on the ellipsoid the map makes of it. Collective. Throws
/// MeshError naming initial_deformation if an element inverts.
void deform_objects(mesh::Mesh& mesh, const std::vector<ObjectDeformation>& deformations);

}  // namespace softflow::physics
