#include "softflow/geometry/object_gaps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace softflow::geometry {

using Eigen::Vector3d;

std::vector<std::vector<Vector3d>> interface_points(const mesh::Mesh& m) {
  std::vector<std::vector<Vector3d>> out(m.n_objects);
  std::vector<bool> listed(m.nodes.size(), false);
  for (std::size_t f = 0; f < m.interface_faces.size(); ++f)
    for (int node : m.interface_faces[f])
      if (!listed[node]) {
        listed[node] = true;
        out[m.interface_object[f] - 1].push_back(m.nodes[node]);
      }
  return out;
}

std::optional<ObjectGap> least_resolved_gap(const mesh::Mesh& m, double narrower_than) {
  const auto points = interface_points(m);
  std::optional<ObjectGap> least;
  const auto consider = [&](int object, int other, const Vector3d& p, const Vector3d& q, int side) {
    ObjectGap g{object, other, measure_segment(m, p, q)};
    g.resolution.side = side;
    g.resolution.object = object;
    if (!least || g.resolution.elements_across() < least->resolution.elements_across()) least = g;
  };
  std::vector<Vector3d> lo(m.n_objects), hi(m.n_objects);
  for (int k = 0; k < m.n_objects; ++k) {
    if (points[k].empty()) continue;
    lo[k] = hi[k] = points[k].front();
    for (const Vector3d& x : points[k]) {
      lo[k] = lo[k].cwiseMin(x);
      hi[k] = hi[k].cwiseMax(x);
    }
    // The wall: from the interface node highest (lowest) in y, straight across.
    for (const int side : {1, -1}) {
      const auto extreme = std::max_element(points[k].begin(), points[k].end(),
                                            [&](const Vector3d& a, const Vector3d& b) {
                                              return side * a.y() < side * b.y();
                                            });
      const double gap = m.box.height / 2 - side * extreme->y();
      if (gap > 0.0 && gap < narrower_than)
        consider(k + 1, 0, *extreme, Vector3d(extreme->x(), side * m.box.height / 2, extreme->z()),
                 side);
    }
  }
  // Pairs whose bounding boxes come within narrower_than: their closest nodes.
  // (Objects are not seen across the periodic faces: they keep one interface
  // element from them, build_shear_cell's rule.)
  for (int j = 0; j < m.n_objects; ++j)
    for (int k = j + 1; k < m.n_objects; ++k) {
      if (points[j].empty() || points[k].empty()) continue;
      const Vector3d apart = (lo[k] - hi[j]).cwiseMax(lo[j] - hi[k]).cwiseMax(0.0);
      if (apart.norm() >= narrower_than) continue;
      double best = std::numeric_limits<double>::infinity();
      Vector3d p, q;
      for (const Vector3d& a : points[j])
        for (const Vector3d& b : points[k])
          if (const double d = (a - b).squaredNorm(); d < best) {
            best = d;
            p = a;
            q = b;
          }
      if (std::sqrt(best) < narrower_than) consider(j + 1, k + 1, p, q, 0);
    }
  return least;
}

}  // namespace softflow::geometry
