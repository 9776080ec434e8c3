// Transfer of finite-element fields from a mesh to a remeshed one of the same
// domain (issue 31): interpolation region by region, never across an interface.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "softflow/fem/dof_map.hpp"
#include "softflow/fem/space.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// Finds points in the tetrahedra of one region of a curved P2 mesh: an
/// axis-aligned bounding-box tree over the region's elements, then Newton on
/// the element's quadratic map x(xi) = sum_k x_k N_k(xi) for the reference
/// coordinates.
class RegionLocator {
 public:
  RegionLocator(const mesh::Mesh& mesh, int region);
  ~RegionLocator();
  RegionLocator(RegionLocator&&) noexcept;
  RegionLocator& operator=(RegionLocator&&) = delete;

  struct Hit {
    int tet = -1;
    Eigen::Vector3d xi = Eigen::Vector3d::Zero();
    /// How far xi lies outside the reference tetrahedron (0 inside): max of
    /// -xi_i and sum xi - 1. Points of the region lie inside an element to
    /// round-off; points just outside the region (the mid-node of a straight
    /// edge between two vertices of a curved interface) are extrapolated
    /// from the nearest element of the region.
    double outside = 0.0;
  };
  /// The element of the region containing x, else the one x lies least
  /// outside of (among the elements near x).
  [[nodiscard]] Hit locate(const Eigen::Vector3d& x) const;

 private:
  struct Tree;
  const mesh::Mesh& mesh_;
  std::unique_ptr<Tree> tree_;
};

/// Interpolates fields of an old mesh onto a new mesh of the same domain
/// and regions (geometry::remesh), dof by dof:
///
///  - a node the two meshes share (every interface P2 node: remesh keeps
///    them) takes the old value of its own copy, region by region: exact;
///  - any other node takes the value of the old field's polynomial at its
///    position, evaluated in the element of the old mesh that contains it
///    AND belongs to the region the value is for. A per-region field (P1
///    pressure, log-conformation, a slip velocity) is thus never smeared
///    across an interface, where it jumps.
///
/// Order: the transferred field is the nodal interpolant, on the new mesh,
/// of the old field; for a smooth u interpolated on the old mesh (degree p),
/// |u_new - u| = O(h^{p+1}) at the new nodes (P2: h^3, P1: h^2), measured in
/// tests/unit/test_remesh.cpp.
class MeshTransfer {
 public:
  /// `new_node_of_old[i]` is old node i's node in the new mesh, -1 if none
  /// (geometry::Remeshed::new_node_of_old). Both meshes must outlive this.
  MeshTransfer(const mesh::Mesh& old_mesh, const mesh::Mesh& new_mesh, std::span<const int> new_node_of_old);
  ~MeshTransfer();

  /// The values on `new_space` of a field with `components` components per
  /// dof (component innermost, as Field::gather gives them) whose values on
  /// `old_space` are `old_values`. The spaces must have the same degree and
  /// continuity.
  [[nodiscard]] std::vector<double> transfer(const Space& old_space, const Space& new_space, int components,
                                             std::span<const double> old_values) const;

  /// The same for a vector over a composed dof map (e.g. a Stokes solution:
  /// velocity, pressure, slip multipliers), field by field; `old_dofs` and
  /// `new_dofs` must compose the same fields. Interface-only fields (slip
  /// multipliers) live on carried nodes only and are copied.
  [[nodiscard]] std::vector<double> transfer(const DofMap& old_dofs, const DofMap& new_dofs,
                                             std::span<const double> old_values) const;

  /// A P2 field given at every geometry node (continuous, e.g. the mesh
  /// velocity), at every node of the new mesh.
  [[nodiscard]] std::vector<Eigen::Vector3d> transfer_nodal(std::span<const Eigen::Vector3d> old_values) const;

  /// The largest RegionLocator::Hit::outside over the transferred points
  /// (how far any value was extrapolated, in reference coordinates).
  [[nodiscard]] double largest_extrapolation() const { return largest_outside_; }

 private:
  /// Where (node, region) of the new mesh lies in the old one: the old node
  /// it is (tet = -1, xi unused, node = old node), or an element and xi.
  struct Place {
    int old_node = -1;
    RegionLocator::Hit hit;
  };
  const Place& place(int node, int region) const;
  /// Weights of the old element's nodes (P1: 4, P2: 10) at a located place.
  static std::array<double, 10> weights(int degree, const RegionLocator::Hit& hit);

  const mesh::Mesh& old_;
  const mesh::Mesh& new_;
  std::vector<int> old_node_of_new_;
  std::vector<RegionLocator> locators_;  // one per region of the old mesh
  mutable std::unordered_map<long long, Place> places_;
  mutable double largest_outside_ = 0.0;
};

}  // namespace softflow::fem
