#include "softflow/fem/dof_map.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::fem {

DofMap::DofMap(const mesh::Mesh& mesh, std::vector<FieldSpec> fields) : fields_(std::move(fields)) {
  const int n_nodes = mesh.n_nodes();
  for (const auto& f : fields_)
    if (!f.space || f.components < 1 || f.space->n_nodes() != n_nodes)
      throw InputError(fmt::format("DofMap: field '{}' needs a space on this mesh and at least "
                                   "one component", f.name));

  const int n_f = n_fields();
  n_field_dofs_.assign(n_f, 0);
  space_to_dof_.resize(n_f);
  for (int f = 0; f < n_f; ++f) space_to_dof_[f].assign(fields_[f].space->n_dofs(), -1);

  // Node by node, field by field, copy by copy, component by component.
  node_offset_.assign(n_nodes + 1, 0);
  for (int n = 0; n < n_nodes; ++n) {
    node_offset_[n] = n_dofs_;
    if (mesh.master(n) != n) continue;  // periodic copies own nothing
    for (int f = 0; f < n_f; ++f) {
      const int n_c = fields_[f].components;
      for (const Space::Copy& copy : fields_[f].space->copies(n)) {
        space_to_dof_[f][copy.dof] = n_dofs_;
        for (int c = 0; c < n_c; ++c) {
          dof_field_.push_back(f);
          dof_component_.push_back(c);
          dof_node_.push_back(n);
          dof_region_.push_back(copy.region);
        }
        n_dofs_ += n_c;
        n_field_dofs_[f] += n_c;
      }
    }
  }
  node_offset_[n_nodes] = n_dofs_;

  element_offset_.assign(n_f, 0);
  for (int f = 0; f < n_f; ++f) {
    element_offset_[f] = element_size_;
    element_size_ += element_field_size(f);
  }
  element_dofs_.resize(static_cast<std::size_t>(mesh.n_tets()) * element_size_);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    int* out = element_dofs_.data() + static_cast<std::size_t>(t) * element_size_;
    for (int f = 0; f < n_f; ++f) {
      const int n_c = fields_[f].components;
      for (int space_dof : fields_[f].space->element_dofs(t)) {
        const int first = space_to_dof_[f][space_dof];
        for (int c = 0; c < n_c; ++c) *out++ = first + c;
      }
    }
  }
}

int DofMap::field_index(const std::string& name) const {
  for (int f = 0; f < n_fields(); ++f)
    if (fields_[f].name == name) return f;
  throw InputError(fmt::format("DofMap: no field called '{}'", name));
}

int DofMap::dof(int f, int node, int region, int component) const {
  const int space_dof = fields_[f].space->dof(node, region);
  return space_dof < 0 ? -1 : space_to_dof_[f][space_dof] + component;
}

std::vector<int> DofMap::field_dofs(int f) const {
  std::vector<int> out;
  out.reserve(n_field_dofs_[f]);
  for (int d = 0; d < n_dofs_; ++d)
    if (dof_field_[d] == f) out.push_back(d);
  return out;
}

std::pair<int, int> rank_node_range(int n_nodes, int rank, int n_ranks) {
  const long n = n_nodes;
  return {static_cast<int>(n * rank / n_ranks), static_cast<int>(n * (rank + 1) / n_ranks)};
}

DofRange DofMap::ownership(int rank, int n_ranks) const {
  const auto [first, last] = rank_node_range(static_cast<int>(node_offset_.size()) - 1, rank, n_ranks);
  return {node_offset_[first], rank + 1 == n_ranks ? n_dofs_ : node_offset_[last]};
}

}  // namespace softflow::fem
