#include "softflow/geometry/point_symmetric_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/mesh/node_classes.hpp"

namespace softflow::geometry {

namespace {

// Points hashed on a grid of cells `tolerance` wide: a point within
// `tolerance` of a query lies in one of the 27 cells around the query's.
class PointIndex {
 public:
  explicit PointIndex(double tolerance) : tolerance_(tolerance) {}

  void insert(int index, const mesh::Point& p) { cells_[key(cell(p))].push_back({index, p}); }

  // The nearest point within the tolerance, -1 if none.
  [[nodiscard]] int find(const mesh::Point& p) const {
    const auto c = cell(p);
    int best = -1;
    double best_distance = tolerance_;
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) {
          const auto it = cells_.find(key({c[0] + i, c[1] + j, c[2] + k}));
          if (it == cells_.end()) continue;
          for (const auto& [index, q] : it->second) {
            const double d = (q - p).norm();
            if (d <= best_distance) {
              best_distance = d;
              best = index;
            }
          }
        }
    return best;
  }

 private:
  [[nodiscard]] std::array<std::int64_t, 3> cell(const mesh::Point& p) const {
    return {static_cast<std::int64_t>(std::floor(p.x() / tolerance_)),
            static_cast<std::int64_t>(std::floor(p.y() / tolerance_)),
            static_cast<std::int64_t>(std::floor(p.z() / tolerance_))};
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::int64_t v : c) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return h;
  }

  double tolerance_;
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, mesh::Point>>> cells_;
};

// A length far below any element and far above gmsh's round-off on copied
// (periodic) nodes, which is ~1e-15 of the box.
double matching_tolerance(const mesh::Box& box) {
  return 1e-8 * std::max({box.length, box.height, box.width});
}

mesh::BoundaryTag rotated(mesh::BoundaryTag tag) {
  using mesh::BoundaryTag;
  switch (tag) {
    case BoundaryTag::wall_bottom: return BoundaryTag::wall_top;
    case BoundaryTag::wall_top: return BoundaryTag::wall_bottom;
    case BoundaryTag::x_min: return BoundaryTag::x_max;
    case BoundaryTag::x_max: return BoundaryTag::x_min;
    default: return tag;  // R keeps z
  }
}

template <std::size_t n>
std::array<int, n> mapped(const std::array<int, n>& element, const std::vector<int>& image) {
  std::array<int, n> out{};
  for (std::size_t k = 0; k < n; ++k) out[k] = image[element[k]];
  return out;
}

}  // namespace

mesh::Mesh complete_by_half_turn(const mesh::Mesh& half, const std::vector<int>& cut_nodes) {
  if (!half.periodic_master.empty())
    throw MeshError("complete_by_half_turn: the half mesh must carry no periodic identification");
  const double tolerance = matching_tolerance(half.box);
  mesh::Mesh m = half;
  const int n_half = half.n_nodes();

  // The cut plane: each node's mirror (x -> -x) is a node of the plane, put
  // exactly at the mirrored position so that R maps the mesh onto itself to
  // the bit, not to gmsh's round-off.
  PointIndex plane(tolerance);
  for (int i : cut_nodes) plane.insert(i, half.nodes[i]);
  std::vector<int> image(n_half, -1);
  for (int i : cut_nodes) {
    const mesh::Point& p = half.nodes[i];
    if (std::abs(p.y()) > tolerance)
      throw MeshError(fmt::format("cut-plane node {} at y = {:g} is off the plane y = 0", i, p.y()));
    const int j = plane.find(mesh::half_turn(p));
    if (j < 0)
      throw MeshError(fmt::format("cut-plane node {} at ({:g}, 0, {:g}) has no mirror node at x = {:g}: "
                                  "the plane's mesh is not symmetric",
                                  i, p.x(), p.z(), -p.x()));
    image[i] = j;
  }
  for (int i : cut_nodes) {
    const int j = image[i];
    if (image[j] != i) throw MeshError("cut-plane mirror nodes do not pair up");
    const mesh::Point& p = half.nodes[i];
    if (i == j)
      m.nodes[i] = {0.0, 0.0, p.z()};  // on the axis
    else if (p.x() > 0.0 || (p.x() == 0.0 && i < j)) {
      m.nodes[i] = {p.x(), 0.0, p.z()};
      m.nodes[j] = {-p.x(), 0.0, p.z()};
    }
  }
  // Every other node gets an image of its own.
  for (int i = 0; i < n_half; ++i) {
    if (image[i] >= 0) continue;
    image[i] = m.n_nodes();
    m.nodes.push_back(mesh::half_turn(m.nodes[i]));
    m.is_vertex.push_back(half.is_vertex[i]);
  }

  // R has determinant +1: positively oriented tetrahedra stay so, and a
  // face's right-hand normal turns with it (outward stays outward).
  for (int t = 0; t < half.n_tets(); ++t) {
    m.tets.push_back(mapped(half.tets[t], image));
    m.tet_region.push_back(half.tet_region[t]);
  }
  for (std::size_t f = 0; f < half.interface_faces.size(); ++f) {
    m.interface_faces.push_back(mapped(half.interface_faces[f], image));
    m.interface_object.push_back(half.interface_object[f]);
  }
  for (std::size_t f = 0; f < half.boundary_faces.size(); ++f) {
    m.boundary_faces.push_back(mapped(half.boundary_faces[f], image));
    m.boundary_face_tag.push_back(rotated(half.boundary_face_tag[f]));
  }
  m.periodic_master = periodic_classes(m);
  return m;
}

std::vector<int> periodic_classes(const mesh::Mesh& m) {
  const mesh::Box& b = m.box;
  if (!b.periodic_x && !b.periodic_z) return {};
  const double tolerance = matching_tolerance(b);
  mesh::NodeClasses classes(m.n_nodes());
  auto identify = [&](int axis, double period) {
    const double half = period / 2;
    PointIndex low(tolerance);
    for (int i = 0; i < m.n_nodes(); ++i)
      if (std::abs(m.nodes[i][axis] + half) <= tolerance) low.insert(i, m.nodes[i]);
    mesh::Point shift = mesh::Point::Zero();
    shift[axis] = period;
    for (int i = 0; i < m.n_nodes(); ++i) {
      if (std::abs(m.nodes[i][axis] - half) > tolerance) continue;
      const int j = low.find(m.nodes[i] - shift);
      if (j < 0)
        throw MeshError(fmt::format("node {} at ({:g}, {:g}, {:g}) on a periodic face has no image on the "
                                    "opposite face",
                                    i, m.nodes[i].x(), m.nodes[i].y(), m.nodes[i].z()));
      classes.unite(i, j);
    }
  };
  if (b.periodic_x) identify(0, b.length);
  if (b.periodic_z) identify(2, b.width);
  std::vector<int> master(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) master[i] = classes.find(i);
  return master;
}

int nodes_without_half_turn_image(const mesh::Mesh& m, double tolerance) {
  PointIndex all(tolerance);
  for (int i = 0; i < m.n_nodes(); ++i) all.insert(i, m.nodes[i]);
  int missing = 0;
  for (const auto& p : m.nodes)
    if (all.find(mesh::half_turn(p)) < 0) ++missing;
  return missing;
}

}  // namespace softflow::geometry
