// Degrees of freedom of the P2/P1 Taylor-Hood pair per subdomain, with
// double interface nodes and periodic identification.
#pragma once

#include <array>
#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// Unknowns of a two-phase (or multiphase) Stokes problem (thesis §2.3.1).
///
/// Each subdomain (matrix = region 0, object k = region k) has its own
/// pressure unknowns, so every interface vertex carries one pressure per
/// side: pressure may jump across the interface. Velocity is shared across
/// an interface (no slip: continuous velocity) unless `double_interface_velocity`
/// is set, in which case interface nodes carry one velocity per side too and
/// the coupling is left to constraints (slip, later).
///
/// Periodic nodes share the unknowns of their representative node.
///
/// Numbering: node by node (in representative-node order), each node's
/// velocity copies (3 dofs each, x y z) then its pressure copies. Unknowns of
/// one node are therefore contiguous, and contiguous node ranges map to
/// contiguous dof ranges, which gives each MPI rank a compact block of rows.
class StokesDofMap {
 public:
  static constexpr int kVelocityPerTet = 30;  ///< 10 nodes x 3 components
  static constexpr int kPressurePerTet = 4;
  static constexpr int kDofsPerTet = kVelocityPerTet + kPressurePerTet;
  using TetDofs = std::array<int, kDofsPerTet>;

  StokesDofMap(const mesh::Mesh& mesh, bool double_interface_velocity);

  [[nodiscard]] int n_dofs() const { return n_dofs_; }
  [[nodiscard]] int n_velocity_dofs() const { return n_velocity_; }
  [[nodiscard]] int n_pressure_dofs() const { return n_dofs_ - n_velocity_; }
  [[nodiscard]] bool double_interface_velocity() const { return double_velocity_; }

  /// Element dofs: velocity of local node k, component c at 3k + c; pressure
  /// of local vertex i at 30 + i.
  [[nodiscard]] const TetDofs& tet_dofs(int tet) const { return tet_dofs_[tet]; }

  /// First velocity dof (x component) of `node` as seen from `region`, -1 if
  /// the node does not touch that region.
  [[nodiscard]] int velocity_dof(int node, int region) const;
  /// First velocity dof of `node` in the lowest region touching it (the
  /// only one for nodes off the interfaces), -1 if the node is unused.
  [[nodiscard]] int first_velocity_dof(int node) const;
  /// Pressure dof of vertex `node` as seen from `region`, -1 if none.
  [[nodiscard]] int pressure_dof(int node, int region) const;

  /// True for velocity dofs, false for pressure dofs.
  [[nodiscard]] bool is_velocity(int dof) const { return is_velocity_[dof] != 0; }
  /// Region whose unknown `dof` is (for a shared velocity: the lowest region).
  [[nodiscard]] int region_of(int dof) const { return dof_region_[dof]; }
  /// Geometry node (a representative) that `dof` lives on.
  [[nodiscard]] int node_of(int dof) const { return dof_node_[dof]; }

  /// One past the last dof of representative nodes [0, node), for
  /// splitting dofs into contiguous per-rank ranges.
  [[nodiscard]] int dof_offset_of_node(int node) const { return node_offset_[node]; }

 private:
  struct Copy {
    int region;
    int velocity;  // first of 3, or -1
    int pressure;  // or -1
  };
  const std::vector<Copy>& copies(int node) const;

  bool double_velocity_;
  int n_dofs_ = 0;
  int n_velocity_ = 0;
  std::vector<int> master_;                    // node -> representative
  std::vector<std::vector<Copy>> node_copies_;  // per representative node
  std::vector<int> node_offset_;
  std::vector<TetDofs> tet_dofs_;
  std::vector<char> is_velocity_;
  std::vector<int> dof_region_;
  std::vector<int> dof_node_;
};

}  // namespace softflow::fem
