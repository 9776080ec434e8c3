// Navier slip between the two velocity copies of an interface, through
// collocated Lagrange multipliers (thesis §2.3.1, eqs. 2.17-2.18).
#pragma once

#include <array>
#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "softflow/element/isoparametric.hpp"
#include "softflow/fem/dof_map.hpp"
#include "softflow/mesh/mesh.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"

namespace softflow::physics {

/// Field index of the multipliers in a slip system's dof map (after
/// kVelocityField = 0 and kPressureField = 1).
inline constexpr int kMultiplierField = 2;

// The discrete slip coupling. Unknowns: a velocity copy per region (3 x P2,
// u_m outside, u_d inside an object) and, at every interface node i, a
// multiplier lambda_i (3 x P2 on the interface, fem::Continuity::on_interfaces).
//
//  momentum, matrix copy:  ... + integral_S lambda_h . v_m ds
//  momentum, object copy:  ... - integral_S lambda_h . v_d ds  (+ the tension load)
//  constraint, per node i: D_i [ integral_S N_i (u_m - u_d)_h ds
//                                - alpha integral_S N_i T_i (T lambda)_h ds ] = 0
//
// with T_i = I - n_i n_i (n_i the nodal normal) and (T lambda)_h =
// sum_j N_j T_j lambda_j. The constraint is the transpose of the coupling
// less alpha times the tangential multipliers' mass: the system is
// symmetric. Its normal part is the weak continuity of the normal velocity
// (test n_i N_i), its tangential part the Navier law with lambda the
// traction sigma_m n: the tension load goes to the object's copy, so the
// matrix copy's rows read R_m(v) + integral lambda.v = 0, and the matrix
// weak form has R_m(v) = -integral_S (sigma_m n).v (n the object's outward
// normal). Taking v = u and testing the constraint with lambda gives
// viscous dissipation + integral_S lambda_h.(u_m - u_d) ds = wall work +
// tension work, the slip dissipation being alpha integral |(T lambda)_h|^2
// >= 0 for every mesh.
//
// Why symmetric (issue 33): an earlier form collocated the constraint at
// the nodes (s_i [(u_m - u_d)_i - alpha T_i lambda_i] = 0) against the
// integrated coupling. Its small inconsistency forced the one motion the
// slip law alone holds, the rigid rotation of a near-spherical drop's
// inside, with a weight alpha: at alpha = 1e3 on 16 equator nodes the
// velocity was 8x off and the slip dissipation negative. A symmetric
// system is the minimum of an energy with a non-negative slip term, which
// no inconsistency can make negative or amplify (docs/validation/slip_drop.md).
//
// D_i = n_i n_i + T_i / (1 + alpha) weights each node's three rows (the
// solution does not change) so that they stay of one size as alpha grows;
// alpha = inf is free slip, T lambda = 0. With alpha = 0 the constraint
// gives u_m = u_d at every node: the continuous velocity of the no-slip
// system, the same discrete solution.

/// Unit outward normal at every interface node of `geometry`, indexed by
/// mesh node (zero elsewhere): the tracker's node normals (node_normals).
std::vector<Eigen::Vector3d> interface_node_normals(std::span<const InterfaceMesh> surfaces,
                                                    const mesh::Mesh& geometry);

/// s_i = integral_S N_i^2 ds summed over the node's triangles, of every
/// interface node (indexed by mesh node, zero elsewhere): the size of a
/// node's constraint rows, for the iterative method's Schur estimate.
std::vector<double> interface_node_scale(const mesh::Mesh& geometry);

/// The nodal normals of one interface triangle (its 6 nodes, in order).
using TriangleNormals = std::array<Eigen::Vector3d, 6>;

/// The discrete traction at a point of an interface triangle with P2 shape
/// values `shape` and unit normal `normal` there, from the nodal
/// multipliers (columns): sum_a N_a [(n_a . lambda_a) n + T_a lambda_a].
/// The normal part follows the surface's own normal, the tangential part
/// the nodes' tangent planes.
Eigen::Vector3d slip_traction(const std::array<double, 6>& shape, const Eigen::Vector3d& normal,
                              const TriangleNormals& nodal, const Eigen::Matrix<double, 3, 6>& lambda);

/// The 18 x 18 matrix C of the coupling on one triangle with nodes `x`:
/// integral lambda_h . v_h ds = v^T C lambda (lambda_h as slip_traction),
/// rows (node b, component i) of v, columns (node a, component j) of lambda.
Eigen::Matrix<double, 18, 18> slip_coupling_matrix(const element::TriangleNodes& x,
                                                   const TriangleNormals& nodal);

/// The constraint rows of one interface triangle (surface mass `mass`,
/// coupling `coupling` = slip_coupling_matrix) over (u_m, u_d, lambda) of
/// its 6 nodes: D_a C_ba^T [I, -I] and -alpha D_a M_ab T_a T_b, with T the
/// nodal tangential projection of `nodal` and D_a = n_a n_a + T_a / (1 +
/// alpha) the row weights (the comment above). alpha = inf: free slip.
Eigen::Matrix<double, 18, 54> slip_constraint_block(const Eigen::Matrix<double, 18, 18>& coupling,
                                                   const Eigen::Matrix<double, 6, 6>& mass,
                                                   const TriangleNormals& nodal, double alpha);

/// The iterative method's preconditioning at one interface node of a slip
/// system, whose velocity copies make each object's velocity block a pure
/// traction problem: singular (rigid motions), so the Schur factorisation
/// needs help.
///  - `jump_penalty` on (u_m, u_d) of the node: gamma [I, -I; -I, I] with
///    gamma = 0.01 (a_m + a_d), a_m and a_d the operator's diagonal at the
///    two copies (an augmented-Lagrangian idea), which makes the velocity
///    block regular. Measured (unit drop, N 16, alpha 1, rtol 1e-10; the
///    no-slip system takes 70 iterations): factor 0.01 -> 114 / 133
///    iterations at lambda 0.1 / 10, 0.001 -> 122 / 127, 0.1 -> 154 at
///    lambda 0.1, 0.5 -> stalls near 1e-9, 4 and 20 stall near 1e-5 and
///    1e-3: the penalty should only just lift the rigid modes.
///  - `schur_estimate` on the node's multipliers: the Schur complement
///    -D A^-1 B^T node by node, with D and B^T both s [I, -I] on the node (s
///    = interface_node_scale, the mass lumped to its diagonal) and the 2 x 2
///    model [a_m + g, -g; -g, a_d + g] of the penalised block: -s^2 c W with
///    c = (a_m + a_d) / (a_m a_d + g (a_m + a_d)) and W = n n + T / (1 +
///    alpha) the constraint rows' weights (slip_constraint_block; the
///    constraint's own -alpha tangential mass is in the operator). Like the
///    pressure's -M/eta it is negative definite; Jacobi on it completes the
///    preconditioner.
/// Of interface node `node` of `object` with nodal normal `normal`, scale
/// s and slip alpha; `diagonal` is the operator's diagonal over this rank's
/// rows, the first being dof `first_row`, and a_m, a_d its means over the
/// three components of the node's two velocity copies (owned with the
/// node: dofs are numbered node by node).
struct SlipNodePreconditioner {
  Eigen::Matrix<double, 6, 6> jump_penalty;
  Eigen::Matrix3d schur_estimate;
};
SlipNodePreconditioner slip_node_preconditioner(const fem::DofMap& dofs, const double* diagonal,
                                                int first_row, int node, int object,
                                                const Eigen::Vector3d& normal, double scale,
                                                double alpha);

/// Per object, from a slip system's solution on `geometry` with the nodal
/// normals (interface_node_normals) it was assembled with.
struct SlipMeasures {
  double area = 0.0;
  /// integral_S |(I - n n)(u_m - u_d)| ds / area and its largest nodal value.
  double mean_slip_speed = 0.0;
  double max_slip_speed = 0.0;
  /// integral_S lambda_h . (u_m - u_d) ds: the power the slip dissipates
  /// (alpha times the tangential multipliers' mass norm: never negative).
  double dissipation = 0.0;
  /// integral_S |lambda_h . (u_m - u_d)| ds: the scale against which a
  /// negative dissipation is more than round-off.
  double absolute_power = 0.0;
};

/// Whether `m`'s slip dissipation is negative beyond round-off (1e-9 of its
/// absolute_power): with the symmetric coupling it is alpha |(T lambda)_h|^2
/// >= 0, so such a value is a solve gone wrong, not physics.
bool dissipation_is_negative(const SlipMeasures& m);

/// The largest dimensionless slip alpha R / eta_m that a mesh of
/// `equator_nodes` resolves (docs/validation/slip_large_alpha.md). The
/// inside of a near-spherical drop can turn rigidly at no viscous cost;
/// only the slip law, with weight 1 / alpha, sets that rotation, against
/// the discrete interface's own asphericity (~ h^2): measured on the
/// sphere in shear, the slip velocity's error stays within twice its
/// alpha = 10 value up to alpha ~ 100 (N / 16)^4.
double largest_resolved_slip(int equator_nodes);

/// SlipMeasures of objects 1..n_objects (index k - 1). `solution` holds
/// every dof of `dofs` (a slip system's map: velocity per region plus
/// multipliers).
std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const Eigen::Vector3d> node_normals,
                                        std::span<const double> solution);
/// The same reading only the interface dofs through `value(dof)`: the
/// velocity copies and multipliers of interface nodes (e.g. a
/// la::SelectedEntries of a distributed solution).
std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const Eigen::Vector3d> node_normals,
                                        const std::function<double(int dof)>& value);

}  // namespace softflow::physics
