#include "softflow/analysis/richardson.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::analysis {

RichardsonEstimate richardson(double h1, double q1, double h2, double q2, double h3, double q3) {
  if (!(h1 > h2 && h2 > h3 && h3 > 0.0))
    throw Error(fmt::format("richardson: mesh sizes must fall, h1 > h2 > h3 > 0; got {}, {}, {}",
                            h1, h2, h3));
  if (!std::isfinite(q1) || !std::isfinite(q2) || !std::isfinite(q3))
    throw Error(fmt::format("richardson: values {}, {}, {} are not all finite", q1, q2, q3));
  RichardsonEstimate e;
  const double d21 = q2 - q1, d32 = q3 - q2;
  e.error_of_finest = std::max(std::abs(d21), std::abs(d32));
  // Equal values (to the last bit) on the two finest: converged as far as
  // these levels can tell.
  if (d32 == 0.0) {
    if (d21 == 0.0) {
      e.monotone = true;
      e.extrapolated = q3;
      e.error_of_finest = 0.0;
    }
    return e;
  }
  const double ratio = d21 / d32;
  // g(p) = (h1^p - h2^p) / (h2^p - h3^p) grows with p from
  // ln(h1/h2) / ln(h2/h3) at p = 0: a ratio of the same sign and larger than
  // g at the smallest order is what converging differences look like.
  const auto g = [&](double p) {
    return (std::pow(h1, p) - std::pow(h2, p)) / (std::pow(h2, p) - std::pow(h3, p));
  };
  if (!(ratio > g(kMinOrder))) return e;
  e.monotone = true;
  double lo = kMinOrder, hi = kMaxOrder;
  if (ratio >= g(hi)) {
    lo = hi;
  } else {
    for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
      const double mid = 0.5 * (lo + hi);
      (g(mid) < ratio ? lo : hi) = mid;
    }
  }
  const double p = 0.5 * (lo + hi);
  e.order = p;
  e.extrapolated = q3 - d32 * std::pow(h3, p) / (std::pow(h3, p) - std::pow(h2, p));
  e.error_of_finest = std::abs(q3 - *e.extrapolated);
  return e;
}

RichardsonEstimate richardson_with_order(double h1, double q1, double h2, double q2, double order) {
  if (!(h1 > h2 && h2 > 0.0))
    throw Error(fmt::format("richardson: mesh sizes must fall, h1 > h2 > 0; got {}, {}", h1, h2));
  if (!std::isfinite(q1) || !std::isfinite(q2))
    throw Error(fmt::format("richardson: values {}, {} are not both finite", q1, q2));
  if (!(order >= kMinOrder && order <= kMaxOrder))
    throw Error(fmt::format("richardson: order {} outside [{}, {}]", order, kMinOrder, kMaxOrder));
  RichardsonEstimate e;
  e.monotone = true;
  e.order = order;
  const double h1p = std::pow(h1, order), h2p = std::pow(h2, order);
  e.extrapolated = q2 + (q2 - q1) * h2p / (h1p - h2p);
  e.error_of_finest = std::abs(q2 - *e.extrapolated);
  return e;
}

std::vector<RichardsonEstimate> richardson_triples(std::span<const double> h,
                                                   std::span<const double> q) {
  if (h.size() != q.size() || h.size() < 3)
    throw Error(fmt::format("richardson: needs at least three levels with one value each; got {} "
                            "sizes and {} values",
                            h.size(), q.size()));
  std::vector<RichardsonEstimate> out;
  for (std::size_t k = 0; k + 2 < h.size(); ++k)
    out.push_back(richardson(h[k], q[k], h[k + 1], q[k + 1], h[k + 2], q[k + 2]));
  return out;
}

}  // namespace softflow::analysis
