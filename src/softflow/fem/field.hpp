// Finite-element functions: a space, its components, and a ghosted PETSc vector.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/state.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/tabulation.hpp"
#include "softflow/la/csr_matrix.hpp"
#include "softflow/la/petsc.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// One quadrature point of one element: where the integrand is evaluated.
struct QuadraturePoint {
  const TetTabulation* tab = nullptr;             ///< the rule and shape functions tabulated on it
  int tet = 0;
  int region = 0;
  int q = 0;                                       ///< index in the tabulation's rule
  Eigen::Vector3d x = Eigen::Vector3d::Zero();     ///< physical position
  double weight = 0.0;                             ///< rule weight x |det J|
  element::TetMapPoint map;                        ///< the P2 map's Jacobian there
};

/// The elements this rank works on, the same for every field so that one
/// element loop can read several fields: those whose first vertex's
/// representative lies in this rank's share of the nodes (contiguous
/// node ranges of about equal size, the order the dof maps number in).
std::vector<int> owned_elements(const mesh::Mesh& mesh);

/// Every element with a node (representative) in [first_node, last_node):
/// those whose matrix rows a rank with that node range assembles (a
/// superset of owned_elements for the rank's own range; elements cut by a
/// partition boundary belong to both sides). Fields are ghosted for them.
std::vector<int> elements_touching(const mesh::Mesh& mesh, int first_node, int last_node);

/// A field has at most this many components (a full 3 x 3 tensor), so its
/// values at a point and an element's coefficients have a fixed capacity and
/// live on the stack: evaluation at quadrature points, in every element loop
/// of every step, allocates nothing (the heap's share of a 40-node Giesekus
/// step was about a tenth, measured with perf).
inline constexpr int kMaxFieldComponents = 9;
inline constexpr int kMaxElementCoefficients = 10 * kMaxFieldComponents;  // P2's 10 nodes
/// u_h at a point (one entry per component).
using PointValue =
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxFieldComponents, 1>;
/// grad u_h at a point (one row per component).
using PointGradient =
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::ColMajor, kMaxFieldComponents, 3>;
/// One element's coefficients (nodes x components, node-major).
using ElementCoefficients =
    Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxElementCoefficients, 1>;

/// The quadrature points of tetrahedron `tet` on the current mesh.
std::vector<QuadraturePoint> quadrature_points(const mesh::Mesh& mesh, const TetTabulation& tab,
                                               int tet);

/// A finite-element function u_h = sum_j u_j phi_j with `components`
/// components on a scalar space (a velocity: 3 x P2; a log-conformation
/// tensor: 6 x P1 per region).
///
/// Storage is a ghosted PETSc vector in the field's own numbering (a
/// one-field fem::DofMap): each rank owns a contiguous range of dofs and
/// keeps as ghosts the other dofs of every element touching its node range
/// (fem::elements_touching, common to all fields). After update_ghosts()
/// every field's values there are readable without communication:
/// integrals loop over fem::owned_elements (each element once), assembly
/// may loop over every element with a row here. (Every rank still holds the whole mesh and dof map;
/// issue 12 makes those rank-local.)
class Field {
 public:
  Field(const mesh::Mesh& mesh, std::string name, std::shared_ptr<const Space> space,
        int components);

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const Space& space() const { return *dofs_.field(0).space; }
  [[nodiscard]] int components() const { return dofs_.field(0).components; }
  /// The field's own numbering (one field, components innermost).
  [[nodiscard]] const DofMap& dofs() const { return dofs_; }
  [[nodiscard]] const mesh::Mesh& mesh() const { return mesh_; }
  [[nodiscard]] DofRange ownership() const { return range_; }
  [[nodiscard]] std::span<const int> owned_elements() const { return owned_elements_; }

  /// The global (owned) form, for solvers. After writing to it, call update_ghosts().
  [[nodiscard]] Vec vector() const { return vector_.get(); }
  /// Refreshes the ghost values and the local copy evaluation reads. Collective.
  void update_ghosts();
  /// Sets every owned dof from its node's position and region
  /// (nodal interpolation), then updates ghosts. Collective.
  void interpolate(const std::function<Eigen::VectorXd(const Eigen::Vector3d&, int region)>& f);
  /// Copies this field's values out of a vector over a composed dof map
  /// (e.g. the velocity out of a Stokes solution, every dof on every rank)
  /// and updates ghosts. The space must be the one `source` uses for `field`.
  void assign_from(const DofMap& source, int field, std::span<const double> values);
  /// The same from a distributed vector over `source` (e.g. the Stokes
  /// solution as solved): every value read is this rank's own. Collective.
  void assign_from(const DofMap& source, int field, Vec values);
  /// Every value, gathered on every rank (output, checkpoints, small
  /// problems: counted by la::full_gathers). Collective.
  [[nodiscard]] std::vector<double> gather() const;
  /// Sets every owned value from a full vector (as gather() returns) and updates ghosts.
  void scatter(std::span<const double> all);
  /// The values as one record entry (la::save_vector: gathered for a
  /// checkpoint, this rank's for a step snapshot), and back; `columns`
  /// only shapes the entry. Collective.
  void save(StateRecord& record, const std::string& key, int columns = 1) const;
  void restore(const StateRecord& record, const std::string& key, int columns = 1);

  /// Coefficients of element `tet` (n_element_nodes x components, node-major).
  [[nodiscard]] ElementCoefficients element_coefficients(int tet) const;
  /// u_h at a quadrature point of an element of this rank's (components).
  [[nodiscard]] PointValue value(const QuadraturePoint& p) const;
  /// grad u_h there: row c = gradient of component c, through the curved
  /// map's Jacobian (isoparametric: exact for fields linear in x).
  [[nodiscard]] PointGradient gradient(const QuadraturePoint& p) const;
  /// u_h at reference point xi of element `tet`.
  [[nodiscard]] PointValue value_at_reference(int tet, const Eigen::Vector3d& xi) const;

  /// The element of this rank's that contains x, and x's reference
  /// coordinates in it (Newton on the curved map); nothing if none does.
  struct Location {
    int tet;
    Eigen::Vector3d xi;
  };
  [[nodiscard]] std::optional<Location> locate(const Eigen::Vector3d& x,
                                               double tolerance = 1e-10) const;
  /// u_h at a physical point owned by this rank (in the lowest-numbered
  /// element containing it: at an interface, the lower region's side).
  [[nodiscard]] std::optional<Eigen::VectorXd> value_at_point(const Eigen::Vector3d& x) const;

 private:
  [[nodiscard]] int local_index(int dof) const { return local_index_[dof]; }
  void check_source(const DofMap& source, int field) const;

  const mesh::Mesh& mesh_;
  std::string name_;
  DofMap dofs_;
  DofRange range_;
  std::vector<int> owned_elements_;
  std::vector<int> local_index_;  // dof -> position in the local form, -1 if not on this rank
  la::Vector vector_;
  std::vector<double> local_;     // owned then ghost values, as of the last update_ghosts()
};

/// A square operator on a field's dofs, assembled element by element: one
/// dense block per element of this rank's, declared in owned_elements()
/// order (blocks[e] belongs to owned_elements()[e]) and the pattern
/// created. Every element loop over a field assembles through it.
struct ElementMatrix {
  std::unique_ptr<la::CsrMatrix> matrix;
  std::vector<la::CsrMatrix::Block> blocks;
};
[[nodiscard]] ElementMatrix element_matrix(const Field& field);

/// The field as a part of a run's state ("fields/<name>"): Field::save and
/// Field::restore. Collective.
StatePart state_part(Field& field);

/// Solves `ksp` (an operator on `scalar`'s dofs: target's space, one
/// component) once per component, rhs[c] for component c, and writes the
/// solutions into `target`'s components (the same node ranges: owned scalar
/// dof i is owned component dof i * n_c + c). The caller updates target's
/// ghosts. Throws SolverError "<what> failed: <reason>". Collective.
void solve_by_component(KSP ksp, std::span<const la::Vector> rhs, Field& scalar, Field& target,
                        const std::string& what);

/// L2 projection onto a field's space: find u_h with (u_h, v) = (f, v) for
/// every v, component by component, with f evaluated at the quadrature
/// points of the current mesh (degree-`quadrature_degree` rule). Per region
/// spaces project each region separately, as their basis functions do.
/// Solved with CG + Jacobi to a relative residual of 1e-12. Collective.
void l2_project(const std::function<Eigen::VectorXd(const QuadraturePoint&)>& f, Field& target,
                int quadrature_degree = 5);

}  // namespace softflow::fem
