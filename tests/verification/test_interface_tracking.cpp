// Interface tracking in extensional flow (thesis §2.4.1): rates in time and
// space, and the effect of tangential redistribution.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "support/verification/extensional_flow.hpp"

using softflow::verification::track_sphere_in_extension;

namespace {
double slope(double e1, double e2, double h1, double h2) { return std::log(e1 / e2) / std::log(h1 / h2); }
void print(const softflow::verification::TrackingErrors& e, double k) {
  std::printf("N %3d  nodes %5d  k %4.1f  dt %.4f  E_max %.3e  E_2 %.3e\n", e.equator_nodes,
              e.interface_nodes, k, e.dt, e.e_max, e.e_2);
}
}  // namespace

TEST(InterfaceTracking, SecondOrderInTime) {
  // N = 100 equator nodes (50 elements, as the thesis's Fig. 2.4), k = 0:
  // at these steps the time error dominates and falls as dt^2.
  std::vector<softflow::verification::TrackingErrors> e;
  for (double dt : {0.1, 0.05, 0.025}) {
    e.push_back(track_sphere_in_extension(100, dt, 0.0));
    print(e.back(), 0.0);
  }
  const double s1 = slope(e[0].e_2, e[1].e_2, 0.1, 0.05), s2 = slope(e[1].e_2, e[2].e_2, 0.05, 0.025);
  std::printf("E_2 slopes in dt: %.2f %.2f\n", s1, s2);
  EXPECT_GT(s1, 1.8);
  EXPECT_GT(s2, 1.8);
}

TEST(InterfaceTracking, SecondOrderInTimeAtVariableSteps) {
  // Steps alternating between 1.4 dt and 0.6 dt (ratios 0.43 and 2.33):
  // the variable-step BDF2 and predictor keep the order; the constant-step
  // formulas applied to these steps would be first order.
  std::vector<softflow::verification::TrackingErrors> e;
  for (double dt : {0.1, 0.05, 0.025}) {
    e.push_back(track_sphere_in_extension(100, dt, 0.0, 0.4));
    print(e.back(), 0.0);
  }
  const double s1 = slope(e[0].e_2, e[1].e_2, 0.1, 0.05), s2 = slope(e[1].e_2, e[2].e_2, 0.05, 0.025);
  std::printf("E_2 slopes in dt at variable steps: %.2f %.2f\n", s1, s2);
  EXPECT_GT(s1, 1.8);
  EXPECT_GT(s2, 1.8);
}

TEST(InterfaceTracking, ThirdOrderInSpace) {
  // dt = 0.005 (time error negligible), k = 0: E_2 ~ N^-3 with P2 triangles.
  std::vector<softflow::verification::TrackingErrors> e;
  for (int n : {40, 56, 80}) {
    e.push_back(track_sphere_in_extension(n, 0.005, 0.0));
    print(e.back(), 0.0);
  }
  const double s = slope(e[1].e_2, e[2].e_2, 1.0 / 56, 1.0 / 80);
  std::printf("E_2 slope in 1/N (56 -> 80): %.2f\n", s);
  EXPECT_GT(s, 2.6);
}

TEST(InterfaceTracking, TangentialRedistributionLowersTheMaximumError) {
  // Thesis Fig. 2.6: k = 10 lowers E_max about tenfold and E_2 more than twofold at N = 50 elements.
  const auto plain = track_sphere_in_extension(100, 0.005, 0.0);
  const auto redistributed = track_sphere_in_extension(100, 0.005, 10.0);
  print(plain, 0.0);
  print(redistributed, 10.0);
  EXPECT_GT(plain.e_max / redistributed.e_max, 5.0);
  EXPECT_GT(plain.e_2 / redistributed.e_2, 2.0);
}
