// A symmetric 3 x 3 tensor at every quadrature point of some tetrahedra:
// state that lives where the Stokes assembly integrates, not at nodes (the
// viscoelastic prediction's defect, prediction_defect.hpp).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::physics {

class PointTensors {
 public:
  PointTensors() = default;
  /// Zero tensors at `points_per_tet` points of each tetrahedron in `tets`
  /// (indices below n_tets).
  PointTensors(int n_tets, std::span<const int> tets, int points_per_tet);

  /// The tensor at point q of tetrahedron `tet`; nullptr for a tetrahedron not held.
  [[nodiscard]] const viscoelastic::Mat3* find(int tet, int q) const {
    const int slot = slot_of_tet_.empty() ? -1 : slot_of_tet_[static_cast<std::size_t>(tet)];
    return slot < 0 ? nullptr : &values_[static_cast<std::size_t>(slot) * points_ + q];
  }
  [[nodiscard]] viscoelastic::Mat3& at(int tet, int q) {
    return values_[static_cast<std::size_t>(slot_of_tet_[static_cast<std::size_t>(tet)]) * points_ +
                   q];
  }
  [[nodiscard]] std::span<const int> tets() const { return tets_; }
  [[nodiscard]] int points_per_tet() const { return points_; }
  [[nodiscard]] int n_tets() const { return static_cast<int>(slot_of_tet_.size()); }

 private:
  int points_ = 0;
  std::vector<int> tets_;
  std::vector<int> slot_of_tet_;  // -1 for a tetrahedron not held
  std::vector<viscoelastic::Mat3> values_;
};

}  // namespace softflow::physics
