#include "softflow/fem/dof_map.hpp"

#include <algorithm>

namespace softflow::fem {

namespace {
// Regions touching each representative node, sorted; and whether the node is a vertex.
struct NodeUse {
  std::vector<int> regions;
  bool vertex = false;
};
}  // namespace

StokesDofMap::StokesDofMap(const mesh::Mesh& mesh, bool double_interface_velocity)
    : double_velocity_(double_interface_velocity) {
  const int n_nodes = mesh.n_nodes();
  master_.resize(n_nodes);
  for (int i = 0; i < n_nodes; ++i) master_[i] = mesh.master(i);

  std::vector<NodeUse> use(n_nodes);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const int region = mesh.tet_region[t];
    for (int k = 0; k < 10; ++k) {
      NodeUse& u = use[master_[mesh.tets[t][k]]];
      if (std::find(u.regions.begin(), u.regions.end(), region) == u.regions.end())
        u.regions.push_back(region);
      if (k < 4) u.vertex = true;
    }
  }

  node_copies_.resize(n_nodes);
  node_offset_.assign(n_nodes + 1, 0);
  int next = 0;
  for (int n = 0; n < n_nodes; ++n) {
    node_offset_[n] = next;
    NodeUse& u = use[n];
    if (u.regions.empty()) continue;
    std::sort(u.regions.begin(), u.regions.end());
    auto& copies = node_copies_[n];
    for (int r : u.regions) copies.push_back({r, -1, -1});
    // Velocity: one copy per region if doubled, else one shared by all.
    for (std::size_t c = 0; c < copies.size(); ++c) {
      if (c == 0 || double_velocity_) {
        copies[c].velocity = next;
        for (int d = 0; d < 3; ++d) {
          is_velocity_.push_back(1);
          dof_region_.push_back(copies[c].region);
          dof_node_.push_back(n);
        }
        next += 3;
      } else {
        copies[c].velocity = copies[0].velocity;
      }
    }
    // Pressure: always one per region at vertices.
    if (u.vertex) {
      for (auto& c : copies) {
        c.pressure = next++;
        is_velocity_.push_back(0);
        dof_region_.push_back(c.region);
        dof_node_.push_back(n);
      }
    }
  }
  node_offset_[n_nodes] = next;
  n_dofs_ = next;
  n_velocity_ = static_cast<int>(std::count(is_velocity_.begin(), is_velocity_.end(), 1));

  tet_dofs_.resize(mesh.n_tets());
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const int region = mesh.tet_region[t];
    TetDofs& dofs = tet_dofs_[t];
    for (int k = 0; k < 10; ++k) {
      const int v = velocity_dof(mesh.tets[t][k], region);
      for (int d = 0; d < 3; ++d) dofs[3 * k + d] = v + d;
    }
    for (int i = 0; i < 4; ++i) dofs[kVelocityPerTet + i] = pressure_dof(mesh.tets[t][i], region);
  }
}

const std::vector<StokesDofMap::Copy>& StokesDofMap::copies(int node) const {
  return node_copies_[master_[node]];
}

int StokesDofMap::velocity_dof(int node, int region) const {
  for (const Copy& c : copies(node))
    if (c.region == region) return c.velocity;
  return -1;
}

int StokesDofMap::first_velocity_dof(int node) const {
  const auto& c = copies(node);
  return c.empty() ? -1 : c.front().velocity;
}

int StokesDofMap::pressure_dof(int node, int region) const {
  for (const Copy& c : copies(node))
    if (c.region == region) return c.pressure;
  return -1;
}

}  // namespace softflow::fem
