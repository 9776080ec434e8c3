#include "softflow/mesh/renumber.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace softflow::mesh {

namespace {

// Interleaves the low 21 bits of x, y, z into a 63-bit Morton key.
std::uint64_t spread_bits(std::uint64_t v) {
  v &= 0x1fffff;
  v = (v | v << 32) & 0x1f00000000ffffULL;
  v = (v | v << 16) & 0x1f0000ff0000ffULL;
  v = (v | v << 8) & 0x100f00f00f00f00fULL;
  v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
  v = (v | v << 2) & 0x1249249249249249ULL;
  return v;
}

template <class Array>
void remap(std::vector<Array>& items, const std::vector<int>& new_index) {
  for (auto& item : items)
    for (int& node : item) node = new_index[node];
}

}  // namespace

std::vector<int> renumber_nodes_spatially(Mesh& mesh) {
  const int n = mesh.n_nodes();
  if (n == 0) return {};
  Point lo = mesh.nodes[0], hi = mesh.nodes[0];
  for (const auto& x : mesh.nodes) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const Point scale = ((1 << 21) - 1) * (hi - lo).cwiseMax(1e-300).cwiseInverse();
  std::vector<std::uint64_t> key(n);
  for (int i = 0; i < n; ++i) {
    const Point q = (mesh.nodes[i] - lo).cwiseProduct(scale);
    key[i] = spread_bits(static_cast<std::uint64_t>(q.x())) |
             spread_bits(static_cast<std::uint64_t>(q.y())) << 1 |
             spread_bits(static_cast<std::uint64_t>(q.z())) << 2;
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  std::vector<int> new_index(n);
  for (int i = 0; i < n; ++i) new_index[order[i]] = i;

  std::vector<Point> nodes(n);
  std::vector<std::uint8_t> is_vertex(n);
  for (int i = 0; i < n; ++i) {
    nodes[new_index[i]] = mesh.nodes[i];
    is_vertex[new_index[i]] = mesh.is_vertex[i];
  }
  mesh.nodes = std::move(nodes);
  mesh.is_vertex = std::move(is_vertex);
  remap(mesh.tets, new_index);
  remap(mesh.boundary_faces, new_index);
  remap(mesh.interface_faces, new_index);
  if (!mesh.periodic_master.empty()) {
    // Classes keep their members; the representative becomes the smallest new index.
    std::vector<int> smallest(n, n);
    for (int i = 0; i < n; ++i) {
      const int cls = mesh.periodic_master[i];
      smallest[cls] = std::min(smallest[cls], new_index[i]);
    }
    std::vector<int> master(n);
    for (int i = 0; i < n; ++i) master[new_index[i]] = smallest[mesh.periodic_master[i]];
    mesh.periodic_master = std::move(master);
  }
  return new_index;
}

}  // namespace softflow::mesh
