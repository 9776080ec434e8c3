#include "softflow/fem/space.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::fem {

Space::Space(const mesh::Mesh& mesh, int degree, Continuity continuity)
    : degree_(degree), continuity_(continuity) {
  if (degree != 1 && degree != 2)
    throw InputError(fmt::format("fem::Space: degree {} (allowed: 1, 2)", degree));
  const int n_nodes = mesh.n_nodes();
  const int per_element = n_element_nodes();
  master_.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i) master_[i] = mesh.master(i);

  // Regions touching each representative node through the element nodes
  // this space uses (for an interface space: the object of each interface
  // triangle through its 3 or 6 nodes).
  std::vector<std::vector<int>> regions(n_nodes);
  auto touch = [&](int node, int region) {
    auto& r = regions[master_[node]];
    if (std::find(r.begin(), r.end(), region) == r.end()) r.push_back(region);
  };
  if (continuity == Continuity::on_interfaces) {
    for (std::size_t f = 0; f < mesh.interface_faces.size(); ++f)
      for (int k = 0; k < (degree == 1 ? 3 : 6); ++k)
        touch(mesh.interface_faces[f][k], mesh.interface_object[f]);
  }
  for (int t = 0; t < mesh.n_tets() && per_element > 0; ++t) {
    for (int k = 0; k < per_element; ++k) touch(mesh.tets[t][k], mesh.tet_region[t]);
  }

  copy_begin_.assign(n_nodes + 1, 0);
  for (int n = 0; n < n_nodes; ++n) {
    copy_begin_[n] = static_cast<int>(copies_.size());
    auto& r = regions[n];
    if (r.empty()) continue;
    std::sort(r.begin(), r.end());
    if (continuity_ != Continuity::per_region) r.resize(1);  // objects never touch
    for (int region : r) {
      copies_.push_back({region, n_dofs_++});
      dof_node_.push_back(n);
      dof_region_.push_back(region);
    }
  }
  copy_begin_[n_nodes] = static_cast<int>(copies_.size());

  element_dofs_.resize(static_cast<std::size_t>(mesh.n_tets()) * per_element);
  for (int t = 0; t < mesh.n_tets(); ++t)
    for (int k = 0; k < per_element; ++k)
      element_dofs_[static_cast<std::size_t>(t) * per_element + k] =
          dof(mesh.tets[t][k], mesh.tet_region[t]);
}

std::string Space::describe() const {
  const char* kind = continuity_ == Continuity::continuous   ? "continuous"
                     : continuity_ == Continuity::per_region ? "per region"
                                                             : "on interfaces";
  return fmt::format("P{} {}", degree_, kind);
}

std::span<const Space::Copy> Space::copies(int node) const {
  const int n = master_[node];
  return {copies_.data() + copy_begin_[n],
          static_cast<std::size_t>(copy_begin_[n + 1] - copy_begin_[n])};
}

int Space::dof(int node, int region) const {
  const auto c = copies(node);
  if (continuity_ != Continuity::per_region) return c.empty() ? -1 : c.front().dof;
  for (const Copy& copy : c)
    if (copy.region == region) return copy.dof;
  return -1;
}

}  // namespace softflow::fem
