// Navier slip between the two velocity copies of an interface, through
// collocated Lagrange multipliers (thesis §2.3.1, eqs. 2.17-2.18).
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <Eigen/Core>

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
//  constraint at node i:   s_i [ (u_m,i - u_d,i) - alpha (I - n_i n_i) lambda_i ] = 0
//
// The constraint is collocated at the nodes: its normal part is
// n_i.(u_m,i - u_d,i) = 0 exactly, so the interface tracker sees one
// normal velocity; its tangential part is the Navier law with lambda the
// traction sigma_m n. That lambda is the matrix traction because the
// tension load goes to the object's copy: the matrix copy's rows then read
// R_m(v) + integral lambda.v = 0, and the matrix weak form has
// R_m(v) = -integral_S (sigma_m n).v (n the object's outward normal).
// s_i = integral_S N_i^2 ds summed over the node's triangles scales each
// constraint row like the coupling columns it pairs with, so LU pivots as
// for a symmetric saddle point. With alpha = 0 the constraint gives
// u_m = u_d at every node: the continuous velocity of the no-slip system,
// the same discrete solution. Taking v = u gives the energy balance:
// viscous dissipation + integral_S lambda_h.(u_m - u_d) ds = wall work +
// tension work, the middle term being the slip dissipation.

/// Unit outward normal at every interface node of `geometry`, indexed by
/// mesh node (zero elsewhere): the tracker's node normals (node_normals).
std::vector<Eigen::Vector3d> interface_node_normals(std::span<const InterfaceMesh> surfaces,
                                                    const mesh::Mesh& geometry);

/// s_i of every interface node (indexed by mesh node, zero elsewhere).
std::vector<double> interface_node_scale(const mesh::Mesh& geometry);

/// Per object, from a slip system's solution on `geometry`.
struct SlipMeasures {
  double area = 0.0;
  /// integral_S |(I - n n)(u_m - u_d)| ds / area and its largest nodal value.
  double mean_slip_speed = 0.0;
  double max_slip_speed = 0.0;
  /// integral_S lambda_h . (u_m - u_d) ds: the power the slip dissipates.
  double dissipation = 0.0;
};

/// SlipMeasures of objects 1..n_objects (index k - 1). `solution` holds
/// every dof of `dofs` (a slip system's map: velocity per region plus
/// multipliers).
std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        std::span<const double> solution);
/// The same reading only the interface dofs through `value(dof)`: the
/// velocity copies and multipliers of interface nodes (e.g. a
/// la::SelectedEntries of a distributed solution).
std::vector<SlipMeasures> slip_measures(const mesh::Mesh& geometry, const fem::DofMap& dofs,
                                        const std::function<double(int dof)>& value);

}  // namespace softflow::physics
