// Random emulsions (thesis ch. 4; issue 32 item 1): monodisperse spheres
// placed by random sequential addition (RSA) in a box, reproducibly from a
// seed, with a minimum gap between spheres and to every face of the box, so
// that no sphere crosses a wall or a periodic face.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace softflow::geometry {

struct RandomPacking {
  /// The box the centres' spheres lie in: centred at the origin with these
  /// sides (the cell, or a centred core cube: the thesis's "frame" layout).
  Eigen::Vector3d region = Eigen::Vector3d::Constant(10.0);
  /// Set: `region` bounds only the centres, and the spheres lie whole in
  /// this box (centred too; the cell): the thesis's frame layout, the drops
  /// whose centres lie in a core cube, crossing its faces. The count is
  /// still phi times the region's volume (drops counted by their centre).
  std::optional<Eigen::Vector3d> container;
  double radius = 1.0;
  /// Volume fraction of the spheres in the region: the count is the
  /// nearest integer to phi V / (4/3 pi R^3) (at least one).
  double volume_fraction = 0.05;
  /// Smallest surface-to-surface distance between spheres, and from a
  /// sphere to the region's faces unless face_gap says otherwise.
  double min_gap = 0.1;
  /// Smallest distance from a sphere to the faces of the region (or of the
  /// container, when set) (unset: min_gap).
  /// A cell's periodic faces need one interface element, which the mesh
  /// cannot refine below, while two spheres may come closer (the size
  /// field's gap rule refines between them).
  std::optional<double> face_gap;
  std::uint64_t seed = 1;
  /// Candidate centres tried per sphere before giving up.
  int attempts_per_sphere = 100000;
};

/// How many spheres `packing` asks for.
[[nodiscard]] int sphere_count(const RandomPacking& packing);

/// The centres, in the order they were placed. Each candidate is uniform in
/// the region shrunk by R + face_gap (with a container: the region within
/// the container shrunk by R + face_gap) and is kept if it lies at least
/// 2 R + min_gap from every sphere placed before. The same packing gives the
/// same centres, to the bit, on every machine (std::mt19937_64 and an
/// explicit map of its 64 bits to [0, 1)). Throws InputError when the
/// region cannot hold one sphere, or when a sphere finds no place after
/// attempts_per_sphere candidates (random sequential addition jams near
/// phi = 0.38 with no gap), naming the fraction reached.
[[nodiscard]] std::vector<Eigen::Vector3d> random_sequential_addition(const RandomPacking& packing);

}  // namespace softflow::geometry
