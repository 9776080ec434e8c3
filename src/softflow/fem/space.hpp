// Scalar Lagrange spaces (P1, P2) on the curved tetrahedral mesh.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// How a space treats interfaces between regions (matrix = 0, object k = k).
enum class Continuity {
  /// One value per geometry node, shared by every region touching it:
  /// continuous across interfaces (the no-slip velocity, the ALE displacement).
  continuous,
  /// One copy per region at every node that region touches: double (or
  /// multiple) values at interface nodes, so the field may jump there
  /// (pressure, the log-conformation tensor, a slip velocity).
  per_region,
  /// Values only at the nodes of interface triangles, one per node (region
  /// = the object), none inside elements: the Lagrange multipliers of
  /// constraints that couple the two sides of an interface (slip).
  on_interfaces,
};

/// A scalar P1 or P2 Lagrange space on the isoparametric P2 mesh.
///
/// Degrees of freedom sit at geometry nodes: the 4 vertices of each
/// tetrahedron for P1, all 10 nodes for P2 (the element's local node order
/// is that of mesh::Tet10, so a P1 element uses its first 4 entries).
/// Periodic nodes share the dofs of their representative (mesh.master).
///
/// Numbering: node by node in representative order, each node's copies in
/// increasing region order. Contiguous node ranges therefore give contiguous
/// dof ranges, which is what the composed DofMap and the per-rank ownership
/// build on.
class Space {
 public:
  /// One value of the space at a representative node, seen from `region`.
  struct Copy {
    int region;
    int dof;
  };

  Space(const mesh::Mesh& mesh, int degree, Continuity continuity);

  [[nodiscard]] int degree() const { return degree_; }
  [[nodiscard]] Continuity continuity() const { return continuity_; }
  /// Local nodes per tetrahedron: 4 (P1) or 10 (P2); 0 for a space that
  /// lives on the interfaces only.
  [[nodiscard]] int n_element_nodes() const {
    if (continuity_ == Continuity::on_interfaces) return 0;
    return degree_ == 1 ? 4 : 10;
  }
  [[nodiscard]] int n_dofs() const { return n_dofs_; }
  [[nodiscard]] int n_nodes() const { return static_cast<int>(master_.size()); }
  /// "P2 continuous", "P1 per region": for messages and output.
  [[nodiscard]] std::string describe() const;

  /// The values of the space at mesh node `node` (any node; periodic copies
  /// answer for their representative), one per region for a per-region
  /// space, one (region = lowest region touching the node) for a continuous
  /// one, none at nodes the space does not use (edge nodes for P1).
  [[nodiscard]] std::span<const Copy> copies(int node) const;
  /// The dof of `node` as seen from `region`: for a per-region space -1 if
  /// that region does not touch the node; for a continuous or interface
  /// space the node's one dof whatever the region. -1 where the space has
  /// no value.
  [[nodiscard]] int dof(int node, int region) const;
  /// The dofs of tetrahedron `tet` in local node order (n_element_nodes()).
  [[nodiscard]] std::span<const int> element_dofs(int tet) const {
    return {element_dofs_.data() + static_cast<std::size_t>(tet) * n_element_nodes(),
            static_cast<std::size_t>(n_element_nodes())};
  }
  /// Representative node and region of a dof (for a continuous space the
  /// region is the lowest one touching the node).
  [[nodiscard]] int node_of(int dof) const { return dof_node_[dof]; }
  [[nodiscard]] int region_of(int dof) const { return dof_region_[dof]; }

 private:
  int degree_;
  Continuity continuity_;
  int n_dofs_ = 0;
  std::vector<int> master_;
  std::vector<int> copy_begin_;  // per node (representatives), into copies_
  std::vector<Copy> copies_;
  std::vector<int> element_dofs_;
  std::vector<int> dof_node_;
  std::vector<int> dof_region_;
};

}  // namespace softflow::fem
