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

  /// Whether tetrahedron `tet`'s points are held.
  [[nodiscard]] bool holds(int tet) const {
    return !slot_of_tet_.empty() && slot_of_tet_[static_cast<std::size_t>(tet)] >= 0;
  }
  /// The tensor at point q of a held tetrahedron.
  [[nodiscard]] viscoelastic::Mat3 get(int tet, int q) const {
    const double* v = &values_[offset(tet, q)];
    viscoelastic::Mat3 a;
    a << v[0], v[3], v[5], v[3], v[1], v[4], v[5], v[4], v[2];
    return a;
  }
  /// Sets it from a symmetric tensor (its upper triangle: xx, yy, zz, xy, yz, xz).
  void set(int tet, int q, const viscoelastic::Mat3& a) {
    double* v = &values_[offset(tet, q)];
    v[0] = a(0, 0), v[1] = a(1, 1), v[2] = a(2, 2), v[3] = a(0, 1), v[4] = a(1, 2), v[5] = a(0, 2);
  }
  [[nodiscard]] std::span<const int> tets() const { return tets_; }
  [[nodiscard]] int points_per_tet() const { return points_; }

 private:
  static constexpr std::size_t kComponents = 6;  // a symmetric tensor, packed
  [[nodiscard]] std::size_t offset(int tet, int q) const {
    const auto slot = static_cast<std::size_t>(slot_of_tet_[static_cast<std::size_t>(tet)]);
    return (slot * static_cast<std::size_t>(points_) + static_cast<std::size_t>(q)) * kComponents;
  }

  int points_ = 0;
  std::vector<int> tets_;
  std::vector<int> slot_of_tet_;  // -1 for a tetrahedron not held
  std::vector<double> values_;
};

}  // namespace softflow::physics
