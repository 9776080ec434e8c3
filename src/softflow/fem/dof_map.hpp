// Unknowns of several fields on one mesh: spaces composed into one numbering.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "softflow/fem/space.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::fem {

/// One field of a composed system: a name (used by solvers and output), a
/// scalar space and the number of components on it (3 for a velocity, 1
/// for a pressure, 6 for a symmetric tensor).
struct FieldSpec {
  std::string name;
  std::shared_ptr<const Space> space;
  int components = 1;
};

/// Contiguous range [begin, end) of dofs owned by this MPI rank.
struct DofRange {
  int begin = 0;
  int end = 0;
  [[nodiscard]] bool owns(int dof) const { return dof >= begin && dof < end; }
  [[nodiscard]] int size() const { return end - begin; }
};

/// The node range [first, last) of `rank` out of `n_ranks`: an equal share
/// of the nodes (periodic copies, which hold no unknowns, included). Every
/// node-numbered unknown set (dof maps, fields, the ALE's free unknowns) and
/// the element ownership (fem::owned_elements: an element belongs to the
/// rank of its first vertex's representative) split this way, so a rank's
/// elements write mostly its own rows: assembly sends only the rows of
/// elements cut by a partition boundary. (Ranges balanced by each set's own
/// unknown count, used before, put the cut elsewhere for every set: at 152k
/// Stokes unknowns on 2 ranks a tenth of the matrix entries then travelled
/// through PETSc's stash and assembly did not speed up.)
std::pair<int, int> rank_node_range(int n_nodes, int rank, int n_ranks);

/// The unknowns of several fields numbered together, e.g. the Taylor-Hood
/// pair (velocity = 3 x P2, pressure = P1 per region, thesis §2.3.1).
///
/// Numbering: node by node (representative order); at each node field by
/// field, each field's copies (regions) in order, each copy's components
/// in order. All unknowns of one node are contiguous, so contiguous node
/// ranges give contiguous dof ranges: each MPI rank owns one block of rows.
///
/// Element dofs: field by field; within a field node by node in the
/// element's local order (mesh::Tet10), components innermost. For the
/// Taylor-Hood pair: velocity of local node k, component c at 3k + c, then
/// the pressure of vertex i at 30 + i. Sizes follow from the spaces.
class DofMap {
 public:
  DofMap(const mesh::Mesh& mesh, std::vector<FieldSpec> fields);

  [[nodiscard]] int n_dofs() const { return n_dofs_; }
  [[nodiscard]] int n_fields() const { return static_cast<int>(fields_.size()); }
  [[nodiscard]] const FieldSpec& field(int f) const { return fields_[f]; }
  /// Index of the field called `name`; throws if there is none.
  [[nodiscard]] int field_index(const std::string& name) const;
  /// Number of dofs of field f (all components, all copies).
  [[nodiscard]] int n_field_dofs(int f) const { return n_field_dofs_[f]; }

  /// Dof of field f, component c at `node` as seen from `region` (see
  /// Space::dof for continuous spaces); -1 where the field has no value.
  [[nodiscard]] int dof(int f, int node, int region, int component = 0) const;

  /// Dofs of tetrahedron `tet` (element_size() entries, order above).
  [[nodiscard]] std::span<const int> element_dofs(int tet) const {
    return {element_dofs_.data() + static_cast<std::size_t>(tet) * element_size_,
            static_cast<std::size_t>(element_size_)};
  }
  [[nodiscard]] int element_size() const { return element_size_; }
  /// Position of field f's first entry within element_dofs().
  [[nodiscard]] int element_offset(int f) const { return element_offset_[f]; }
  /// Entries of field f within element_dofs(): nodes x components.
  [[nodiscard]] int element_field_size(int f) const {
    return fields_[f].space->n_element_nodes() * fields_[f].components;
  }

  [[nodiscard]] int field_of(int dof) const { return dof_field_[dof]; }
  [[nodiscard]] int component_of(int dof) const { return dof_component_[dof]; }
  /// Representative geometry node of a dof.
  [[nodiscard]] int node_of(int dof) const { return dof_node_[dof]; }
  /// Region of a dof (for a continuous space: the lowest region at its node).
  [[nodiscard]] int region_of(int dof) const { return dof_region_[dof]; }
  /// Every dof of field f, ascending.
  [[nodiscard]] std::vector<int> field_dofs(int f) const;

  /// This rank's dofs: those of its node range (rank_node_range).
  [[nodiscard]] DofRange ownership(int rank, int n_ranks) const;
  /// First dof of representative node `node` (n_dofs() for node == n_nodes).
  [[nodiscard]] int dof_offset_of_node(int node) const { return node_offset_[node]; }

 private:
  std::vector<FieldSpec> fields_;
  int n_dofs_ = 0;
  int element_size_ = 0;
  std::vector<int> n_field_dofs_;
  std::vector<int> element_offset_;
  std::vector<std::vector<int>> space_to_dof_;  // per field: space dof -> first component's dof
  std::vector<int> node_offset_;
  std::vector<int> element_dofs_;
  std::vector<int> dof_field_, dof_component_, dof_node_, dof_region_;
};

}  // namespace softflow::fem
