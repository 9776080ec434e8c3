#include "softflow/mesh/node_relocation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "softflow/mesh/half_turn.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::mesh {


NodeRelocation::NodeRelocation(const Mesh& mesh)
    : tets_(mesh.tets),
      free_(mesh.nodes.size(), 1),
      tets_of_node_(mesh.nodes.size()),
      edge_nodes_of_vertex_(mesh.nodes.size()),
      edge_ends_(mesh.nodes.size(), {-1, -1}) {
  for (const auto& faces : {std::cref(mesh.interface_faces), std::cref(mesh.boundary_faces)})
    for (const auto& tri : faces.get())
      for (int node : tri) free_[node] = 0;
  for (int i = 0; i < mesh.n_nodes(); ++i)
    if (mesh.master(i) != i) free_[i] = free_[mesh.master(i)] = 0;
  image_ = half_turn_images(mesh);
  for (int i = 0; i < static_cast<int>(image_.size()); ++i)
    if (image_[i] == i) free_[i] = 0;  // on the z axis: a move off it would break the symmetry
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const auto& tet = mesh.tets[t];
    for (int k = 0; k < 10; ++k) tets_of_node_[tet[k]].push_back(t);
    for (int e = 0; e < 6; ++e) {
      for (int end : kTetEdges[e]) edge_nodes_of_vertex_[tet[end]].push_back(tet[4 + e]);
      edge_ends_[tet[4 + e]] = {tet[kTetEdges[e][0]], tet[kTetEdges[e][1]]};
    }
  }
  for (auto& list : edge_nodes_of_vertex_) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
}

double NodeRelocation::local_quality(const std::vector<Point>& nodes, int node) const {
  double q = std::numeric_limits<double>::infinity();
  for (int t : tets_of_node_[node]) q = std::min(q, tet_quality(nodes, tets_[t]));
  return q;
}

void NodeRelocation::shift(std::vector<Point>& nodes, int node, const Point& shift) const {
  nodes[node] += shift;
  for (int edge_node : edge_nodes_of_vertex_[node]) nodes[edge_node] += 0.5 * shift;
}

void NodeRelocation::mirror(std::vector<Point>& nodes, int node) const {
  if (image_.empty()) return;
  nodes[image_[node]] = half_turn(nodes[node]);
  for (int edge_node : edge_nodes_of_vertex_[node]) nodes[image_[edge_node]] = half_turn(nodes[edge_node]);
}

bool NodeRelocation::relocate(std::vector<Point>& nodes, int node) const {
  // Step scale: a fifth of the distance to the nearest vertex of the
  // elements around, halved on every unsuccessful round down to 1/64 of it
  // (a few dozen quality evaluations).
  double shortest = std::numeric_limits<double>::infinity();
  for (int t : tets_of_node_[node])
    for (int v = 0; v < 4; ++v)
      if (tets_[t][v] != node) shortest = std::min(shortest, (nodes[tets_[t][v]] - nodes[node]).norm());
  // The 26 directions to the neighbours of a cube's centre: with the 6
  // axes alone the search stalls where two elements' qualities cross (the
  // smallest quality has a kink there that only a diagonal step climbs).
  static const std::vector<Point> kDirections = [] {
    std::vector<Point> d;
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k)
          if (i != 0 || j != 0 || k != 0) d.push_back(Point(i, j, k).normalized());
    return d;
  }();
  double best = local_quality(nodes, node);
  bool moved = false;
  // An edge node first tries its chord's midpoint: a straight edge.
  if (const auto& [a, b] = edge_ends_[node]; a >= 0) {
    const Point to_midpoint = 0.5 * (nodes[a] + nodes[b]) - nodes[node];
    shift(nodes, node, to_midpoint);
    if (const double q = local_quality(nodes, node); q > best) {
      best = q;
      moved = true;
    } else {
      shift(nodes, node, -to_midpoint);
    }
  }
  // At most 60 rounds: each accepted move raises the quality strictly, but
  // a long walk at one step size is not worth its cost.
  int rounds = 0;
  for (double step = 0.2 * shortest; step > shortest / 64.0 && rounds < 60; ++rounds) {
    bool improved = false;
    for (const auto& d : kDirections) {
      shift(nodes, node, step * d);
      const double q = local_quality(nodes, node);
      if (q > best) {
        best = q;
        improved = moved = true;
        break;  // keep going from the better point with the same step
      }
      shift(nodes, node, -step * d);
    }
    if (!improved) step *= 0.5;
  }
  return moved;
}

NodeRelocation::Report NodeRelocation::improve(std::vector<Point>& nodes, double target,
                                                   int sweeps) const {
  Report report;
  // One scan serves both the search for bad elements and the caller's
  // smallest quality; after the moves only elements around a moved node
  // change (a vertex's edge nodes lie on its own elements).
  std::vector<double> quality(tets_.size());
  std::vector<int> bad;
  for (int t = 0; t < static_cast<int>(tets_.size()); ++t) {
    quality[t] = tet_quality(nodes, tets_[t]);
    if (quality[t] < target) bad.push_back(t);
  }
  auto smallest = [&] {
    return quality.empty() ? 1.0 : *std::min_element(quality.begin(), quality.end());
  };
  if (bad.empty()) {
    report.smallest_quality = smallest();
    return report;
  }
  auto worst_of_bad = [&] {
    double q = 1.0;
    for (int t : bad) q = std::min(q, quality[t]);
    return q;
  };
  report.quality_before = worst_of_bad();
  std::vector<char> counted(nodes.size(), 0);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    bool any = false;
    // Vertices first (they move the element), then the edge nodes (they
    // bend its edges: the tangent of edge (a, b) at a is 4 x_ab - 3 x_a - x_b,
    // so an edge node turns the element's corner where it folds).
    for (const auto& [first, last] : {std::pair{0, 4}, std::pair{4, 10}})
      for (int t : bad)
        for (int k = first; k < last; ++k) {
          // A mirror pair is searched from its smaller index, whichever
          // of the two elements is being repaired.
          const int node = image_.empty() ? tets_[t][k] : std::min(tets_[t][k], image_[tets_[t][k]]);
          if (!free_[node]) continue;
          const bool moved = relocate(nodes, node);
          // Also after no move: a rejected trial step, undone by
          // subtracting it, can leave an ulp behind.
          mirror(nodes, node);
          if (!moved) continue;
          any = true;
          for (int moved : {node, image_.empty() ? node : image_[node]}) {
            if (!counted[moved]) ++report.nodes_moved;
            counted[moved] = 1;
          }
        }
    if (!any) break;
  }
  for (int node = 0; node < static_cast<int>(nodes.size()); ++node)
    if (counted[node])
      for (int t : tets_of_node_[node]) quality[t] = tet_quality(nodes, tets_[t]);
  report.quality_after = worst_of_bad();
  report.smallest_quality = smallest();
  return report;
}

}  // namespace softflow::mesh
