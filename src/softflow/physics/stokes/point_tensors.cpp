#include "softflow/physics/stokes/point_tensors.hpp"

namespace softflow::physics {

PointTensors::PointTensors(int n_tets, std::span<const int> tets, int points_per_tet)
    : points_(points_per_tet),
      tets_(tets.begin(), tets.end()),
      slot_of_tet_(static_cast<std::size_t>(n_tets), -1),
      values_(tets.size() * static_cast<std::size_t>(points_per_tet) * kComponents, 0.0) {
  for (std::size_t s = 0; s < tets_.size(); ++s)
    slot_of_tet_[static_cast<std::size_t>(tets_[s])] = static_cast<int>(s);
}

}  // namespace softflow::physics
