// A k-d tree of points for nearest-point queries, internal to geometry/: the
// remesher's size field asks for the distance to an interface at every point
// gmsh meshes (~10^5-10^6 queries, each O(log n) here instead of O(n)), and
// an interface's resampling projects each new node onto the old surface.
#pragma once

#include <algorithm>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace softflow::geometry::detail {

class PointTree {
 public:
  explicit PointTree(std::vector<Eigen::Vector3d> points)
      : points_(std::move(points)), order_(points_.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    build(0, static_cast<int>(order_.size()), 0);
  }
  /// Index of a point closest to x; -1 for an empty tree.
  [[nodiscard]] int nearest(const Eigen::Vector3d& x) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    search(0, static_cast<int>(order_.size()), 0, x, best, best_d2);
    return best;
  }

 private:
  // Median split of order_[begin, end) along axis, recursively.
  void build(int begin, int end, int axis) {
    if (end - begin <= 1) return;
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) { return points_[a][axis] < points_[b][axis]; });
    build(begin, mid, (axis + 1) % 3);
    build(mid + 1, end, (axis + 1) % 3);
  }
  void search(int begin, int end, int axis, const Eigen::Vector3d& x, int& best,
              double& best_d2) const {
    if (begin >= end) return;
    const int mid = (begin + end) / 2;
    const int i = order_[mid];
    const double d2 = (points_[i] - x).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
    const double offset = x[axis] - points_[i][axis];
    const int next = (axis + 1) % 3;
    if (offset < 0.0) {
      search(begin, mid, next, x, best, best_d2);
      if (offset * offset < best_d2) search(mid + 1, end, next, x, best, best_d2);
    } else {
      search(mid + 1, end, next, x, best, best_d2);
      if (offset * offset < best_d2) search(begin, mid, next, x, best, best_d2);
    }
  }

  std::vector<Eigen::Vector3d> points_;
  std::vector<int> order_;
};

}  // namespace softflow::geometry::detail
