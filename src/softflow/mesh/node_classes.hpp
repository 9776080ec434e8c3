// Classes of nodes that are one point (periodic copies, mirror images): a
// union-find whose representative is the smallest index of its class, so
// that the classes, and whatever is numbered from them, do not depend on the
// order in which the pairs were found.
#pragma once

#include <algorithm>
#include <vector>

namespace softflow::mesh {

class NodeClasses {
 public:
  explicit NodeClasses(int n) : parent_(n) {
    for (int i = 0; i < n; ++i) parent_[i] = i;
  }
  /// The smallest node of i's class.
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace softflow::mesh
