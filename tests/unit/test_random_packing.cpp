// Random sequential addition of monodisperse spheres (geometry/random_packing).
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/geometry/random_packing.hpp"

using softflow::InputError;
using softflow::geometry::random_sequential_addition;
using softflow::geometry::RandomPacking;
using softflow::geometry::sphere_count;

namespace {

RandomPacking packing(double phi, double gap, std::uint64_t seed) {
  RandomPacking p;
  p.region = Eigen::Vector3d(12.0, 10.0, 14.0);
  p.radius = 1.0;
  p.volume_fraction = phi;
  p.min_gap = gap;
  p.seed = seed;
  return p;
}

}  // namespace

TEST(RandomPacking, TheCountFollowsTheVolumeFraction) {
  const auto p = packing(0.2, 0.1, 1);
  const double v = 4.0 / 3.0 * std::numbers::pi;
  EXPECT_EQ(sphere_count(p), std::lround(0.2 * 12 * 10 * 14 / v));  // 80
  EXPECT_EQ(sphere_count(packing(1e-6, 0.1, 1)), 1);               // at least one
}

TEST(RandomPacking, SpheresKeepTheGapFromEachOtherAndFromEveryFace) {
  const auto p = packing(0.15, 0.1, 3);
  const auto centres = random_sequential_addition(p);
  ASSERT_EQ(static_cast<int>(centres.size()), sphere_count(p));
  for (std::size_t i = 0; i < centres.size(); ++i) {
    for (int d = 0; d < 3; ++d)
      EXPECT_LE(std::abs(centres[i][d]) + p.radius + p.min_gap, p.region[d] / 2 + 1e-12) << i;
    for (std::size_t j = 0; j < i; ++j) EXPECT_GE((centres[i] - centres[j]).norm(), 2 * p.radius + p.min_gap);
  }
  // Spread over the region: each half of each axis holds between a third and
  // two thirds of the spheres (60 spheres; a clustered generator fails this).
  for (int d = 0; d < 3; ++d) {
    int positive = 0;
    for (const auto& c : centres) positive += c[d] > 0.0 ? 1 : 0;
    EXPECT_GT(positive, static_cast<int>(centres.size()) / 3) << "axis " << d;
    EXPECT_LT(positive, 2 * static_cast<int>(centres.size()) / 3) << "axis " << d;
  }
}

TEST(RandomPacking, TheSameSeedGivesTheSameCentresToTheBitAnotherSeedOthers) {
  const auto a = random_sequential_addition(packing(0.15, 0.2, 11));
  const auto b = random_sequential_addition(packing(0.15, 0.2, 11));
  const auto c = random_sequential_addition(packing(0.15, 0.2, 12));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]);
  EXPECT_NE(a.front(), c.front());
}

TEST(RandomPacking, AJammedOrTooSmallRegionIsRefusedWithWhatWasReached) {
  auto p = packing(0.45, 0.0, 1);  // beyond random sequential addition's jamming (~0.38)
  p.attempts_per_sphere = 2000;
  try {
    (void)random_sequential_addition(p);
    FAIL() << "phi = 0.45 packed";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("volume fraction"), std::string::npos) << msg;
    EXPECT_NE(msg.find("of 0.45 asked"), std::string::npos) << msg;
  }
  auto small = packing(0.1, 0.5, 1);
  small.region = Eigen::Vector3d(2.5, 10.0, 10.0);  // 2 (R + gap) = 3 > 2.5
  EXPECT_THROW((void)random_sequential_addition(small), InputError);
}

// The thesis's frame layout: the centres in a core cube, the spheres crossing
// its faces but kept whole in the cell. At phi = 0.26 in a core of side 8 R
// the spheres that must lie wholly inside jam (their centres have only a
// 5.8 R cube); counted by their centres they pack.
TEST(RandomPacking, WithAContainerTheRegionBoundsOnlyTheCentres) {
  RandomPacking p;
  p.region = Eigen::Vector3d::Constant(8.0);
  p.radius = 1.0;
  p.volume_fraction = 0.26;
  p.min_gap = 0.1;
  p.attempts_per_sphere = 20000;
  EXPECT_THROW((void)random_sequential_addition(p), InputError);

  p.container = Eigen::Vector3d::Constant(12.0);
  p.face_gap = 0.3;
  const auto centres = random_sequential_addition(p);
  ASSERT_EQ(static_cast<int>(centres.size()), sphere_count(p));  // 32: still phi of the region
  ASSERT_EQ(sphere_count(p), 32);
  int crossing = 0;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    for (int d = 0; d < 3; ++d) {
      EXPECT_LE(std::abs(centres[i][d]), 4.0) << i;                      // centre in the core
      EXPECT_LE(std::abs(centres[i][d]) + 1.0 + 0.3, 6.0 + 1e-12) << i;  // whole in the cell
    }
    crossing += (centres[i].cwiseAbs().array() + 1.0 > 4.0).any() ? 1 : 0;
    for (std::size_t j = 0; j < i; ++j) EXPECT_GE((centres[i] - centres[j]).norm(), 2.1);
  }
  EXPECT_GT(crossing, 8);  // many cross the core's faces, as the layout allows

  // A container that leaves a sphere no room is refused as a small region is.
  p.container = Eigen::Vector3d(2.5, 12.0, 12.0);
  EXPECT_THROW((void)random_sequential_addition(p), InputError);
}
