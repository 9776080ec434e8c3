// Richardson extrapolation: exact on q = q_inf + C h^p for any ratios of h,
// flags oscillating and diverging sequences, refuses bad levels.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/analysis/richardson.hpp"
#include "softflow/common/error.hpp"

using namespace softflow;
using analysis::richardson;
using analysis::richardson_triples;

TEST(Richardson, RecoversOrderAndLimitOfAPowerLawForUnevenRatios) {
  for (double p : {1.0, 2.0, 3.0, 3.7}) {
    for (double c : {0.3, -2.0}) {
      const double h[] = {1.0 / 16, 1.0 / 20, 1.0 / 26};  // ratios 1.25 and 1.3
      const auto q = [&](double x) { return 0.11 + c * std::pow(x, p); };
      const auto e = richardson(h[0], q(h[0]), h[1], q(h[1]), h[2], q(h[2]));
      ASSERT_TRUE(e.monotone);
      EXPECT_NEAR(*e.order, p, 1e-8) << "p = " << p << ", C = " << c;
      EXPECT_NEAR(*e.extrapolated, 0.11, 1e-13);
      EXPECT_NEAR(e.error_of_finest, std::abs(c) * std::pow(h[2], p), 1e-13);
    }
  }
}

TEST(Richardson, AHigherOrderTermShowsInTheTriplesOrders) {
  // q = 1 + h^2 + 40 h^3: coarse triples see an order above 2, finer ones approach 2.
  std::vector<double> h, q;
  for (int n : {8, 12, 18, 27, 40, 60}) {
    h.push_back(1.0 / n);
    q.push_back(1.0 + std::pow(1.0 / n, 2) + 40 * std::pow(1.0 / n, 3));
  }
  const auto triples = richardson_triples(h, q);
  ASSERT_EQ(triples.size(), 4u);
  for (std::size_t k = 0; k < triples.size(); ++k) {
    ASSERT_TRUE(triples[k].monotone);
    EXPECT_GT(*triples[k].order, 2.0);
    if (k > 0) EXPECT_LT(*triples[k].order, *triples[k - 1].order);
  }
  EXPECT_LT(std::abs(*triples.back().extrapolated - 1.0), std::abs(q.back() - 1.0) / 10);
}

TEST(Richardson, OscillatingOrGrowingDifferencesHaveNoOrder) {
  const auto oscillating = richardson(0.3, 1.0, 0.2, 1.01, 0.1, 1.005);
  EXPECT_FALSE(oscillating.monotone);
  EXPECT_FALSE(oscillating.order.has_value());
  EXPECT_FALSE(oscillating.extrapolated.has_value());
  EXPECT_NEAR(oscillating.error_of_finest, 0.01, 1e-15);
  // Same sign but growing: diverging, not converging.
  const auto growing = richardson(0.3, 1.0, 0.2, 1.001, 0.1, 1.01);
  EXPECT_FALSE(growing.monotone);
  EXPECT_NEAR(growing.error_of_finest, 0.009, 1e-15);
}

TEST(Richardson, EqualValuesAreConverged) {
  const auto e = richardson(0.3, 2.5, 0.2, 2.5, 0.1, 2.5);
  EXPECT_TRUE(e.monotone);
  EXPECT_EQ(*e.extrapolated, 2.5);
  EXPECT_EQ(e.error_of_finest, 0.0);
}

TEST(Richardson, RefusesLevelsOutOfOrderAndNonFiniteValues) {
  EXPECT_THROW(richardson(0.1, 1, 0.2, 1, 0.3, 1), Error);
  EXPECT_THROW(richardson(0.3, 1, 0.2, NAN, 0.1, 1), Error);
  const std::vector<double> two{0.2, 0.1};
  EXPECT_THROW(richardson_triples(two, two), Error);
}

TEST(RichardsonWithOrder, TwoLevelsAndTheRightOrderGiveTheLimitOfAPowerLaw) {
  for (double p : {2.0, 3.0}) {
    const double h1 = 1.0 / 27, h2 = 1.0 / 32;  // the main drop's coarse levels (meshed)
    const auto q = [&](double x) { return 0.1098 + 0.4 * std::pow(x, p); };
    const auto e = analysis::richardson_with_order(h1, q(h1), h2, q(h2), p);
    ASSERT_TRUE(e.order.has_value());
    EXPECT_EQ(*e.order, p);
    EXPECT_NEAR(*e.extrapolated, 0.1098, 1e-14);
    EXPECT_NEAR(e.error_of_finest, 0.4 * std::pow(h2, p), 1e-14);
  }
}

TEST(RichardsonWithOrder, AWrongOrderMissesTheLimitByWhatTheTriplesWouldShow) {
  // Data of order 2 extrapolated as if of order 3 keeps part of the error:
  // exactly (q2 - q_inf)(1 - (r^2 - 1) / (r^3 - 1)), r = h1 / h2.
  const double h1 = 0.1, h2 = 0.08, r = h1 / h2;
  const double q1 = 1.0 + h1 * h1, q2 = 1.0 + h2 * h2;
  const auto e = analysis::richardson_with_order(h1, q1, h2, q2, 3.0);
  EXPECT_NEAR(*e.extrapolated - 1.0, h2 * h2 * (1.0 - (r * r - 1.0) / (r * r * r - 1.0)), 1e-15);
}

TEST(RichardsonWithOrder, RefusesRisingSizesNonFiniteValuesAndOrdersOutOfRange) {
  EXPECT_THROW(analysis::richardson_with_order(0.1, 1.0, 0.2, 1.1, 2.0), Error);
  EXPECT_THROW(analysis::richardson_with_order(0.2, NAN, 0.1, 1.1, 2.0), Error);
  EXPECT_THROW(analysis::richardson_with_order(0.2, 1.0, 0.1, 1.1, 0.0), Error);
  EXPECT_THROW(analysis::richardson_with_order(0.2, 1.0, 0.1, 1.1, 20.0), Error);
}
