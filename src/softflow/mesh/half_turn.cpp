#include "softflow/mesh/half_turn.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace softflow::mesh {

std::vector<int> half_turn_images(const Mesh& mesh) {
  std::map<std::array<double, 3>, int> at;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    at.emplace(std::array{mesh.nodes[i].x(), mesh.nodes[i].y(), mesh.nodes[i].z()}, i);
  std::vector<int> image(mesh.nodes.size(), -1);
  for (int i = 0; i < mesh.n_nodes(); ++i) {
    const Point p = half_turn(mesh.nodes[i]);
    const auto it = at.find({p.x(), p.y(), p.z()});
    if (it == at.end()) return {};
    image[i] = it->second;
  }
  auto sorted = [](std::array<int, 10> t) {
    std::sort(t.begin(), t.end());
    return t;
  };
  std::set<std::array<int, 10>> tets;
  for (const auto& t : mesh.tets) tets.insert(sorted(t));
  for (const auto& t : mesh.tets) {
    std::array<int, 10> mapped{};
    for (int k = 0; k < 10; ++k) mapped[k] = image[t[k]];
    if (!tets.count(sorted(mapped))) return {};
  }
  return image;
}

}  // namespace softflow::mesh
