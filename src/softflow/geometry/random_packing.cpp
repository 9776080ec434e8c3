#include "softflow/geometry/random_packing.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::geometry {

namespace {

// [0, 1) from the top 53 bits: std::uniform_real_distribution's output is
// left to each standard library, this is not.
double unit_interval(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

double sphere_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

}  // namespace

int sphere_count(const RandomPacking& p) {
  const double region = p.region.prod();
  return std::max(1, static_cast<int>(std::lround(p.volume_fraction * region / sphere_volume(p.radius))));
}

std::vector<Eigen::Vector3d> random_sequential_addition(const RandomPacking& p) {
  const double face_gap = p.face_gap.value_or(p.min_gap);
  if (!(p.radius > 0.0) || !(p.min_gap >= 0.0) || !(face_gap >= 0.0) || !(p.volume_fraction > 0.0) ||
      p.attempts_per_sphere < 1)
    throw InputError(fmt::format("random packing: radius {} must be > 0, min_gap {} and face gap {} >= 0, volume "
                                 "fraction {} > 0",
                                 p.radius, p.min_gap, face_gap, p.volume_fraction));
  // Centres lie where their sphere keeps face_gap from every face of the
  // box it must lie in (and, with a container, inside the region).
  const Eigen::Vector3d whole = p.container.value_or(p.region);
  // |centre| <= fits along each axis keeps the sphere in the whole box.
  const Eigen::Vector3d fits = whole / 2.0 - Eigen::Vector3d::Constant(p.radius + face_gap);
  const Eigen::Vector3d half = p.container ? fits.cwiseMin(p.region / 2.0) : fits;
  if ((fits.array() < 0.0).any())
    throw InputError(fmt::format(
        "random packing: a sphere of radius {} with gap {} to the faces does not fit "
        "in a {} of {} x {} x {}",
        p.radius, face_gap, p.container ? "container" : "region", whole.x(), whole.y(), whole.z()));
  const int count = sphere_count(p);
  const double separation = 2.0 * p.radius + p.min_gap;
  std::mt19937_64 rng(p.seed);
  std::vector<Eigen::Vector3d> centres;
  centres.reserve(count);
  while (static_cast<int>(centres.size()) < count) {
    bool placed = false;
    for (int attempt = 0; attempt < p.attempts_per_sphere && !placed; ++attempt) {
      Eigen::Vector3d c;
      for (int d = 0; d < 3; ++d) c[d] = (2.0 * unit_interval(rng) - 1.0) * half[d];
      placed = true;
      for (const auto& other : centres)
        if ((c - other).squaredNorm() < separation * separation) {
          placed = false;
          break;
        }
      if (placed) centres.push_back(c);
    }
    if (!placed)
      throw InputError(fmt::format(
          "random packing: after {} candidates no place was left for sphere {} of {} (volume fraction "
          "{:.4g} reached of {:.4g} asked, gap {}): random sequential addition jams below phi ~ 0.38; "
          "lower the volume fraction or the gap, or enlarge the region",
          p.attempts_per_sphere, centres.size() + 1, count,
          static_cast<double>(centres.size()) * sphere_volume(p.radius) / p.region.prod(), p.volume_fraction,
          p.min_gap));
  }
  return centres;
}

}  // namespace softflow::geometry
