// Richardson extrapolation of a quantity computed on a sequence of meshes:
// the observed order, the extrapolated value and the error of the finest.
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace softflow::analysis {

/// From three levels with sizes h1 > h2 > h3 (any ratios) and values q1, q2,
/// q3, assuming q = q_inf + C h^p:
///   (q2 - q1) / (q3 - q2) = (h1^p - h2^p) / (h2^p - h3^p)   determines p,
///   q_inf = q3 - (q3 - q2) h3^p / (h3^p - h2^p).
struct RichardsonEstimate {
  /// The differences q2 - q1 and q3 - q2 have the same sign and shrink: the
  /// only case in which p and q_inf mean anything. Otherwise (oscillating
  /// or growing differences: not in the asymptotic range) they are empty.
  bool monotone = false;
  std::optional<double> order;         ///< p, within [kMinOrder, kMaxOrder]
  std::optional<double> extrapolated;  ///< q_inf
  /// |q3 - q_inf| when monotone; else max(|q2 - q1|, |q3 - q2|), an honest
  /// bound of the scatter rather than an estimate.
  double error_of_finest = 0.0;
};

inline constexpr double kMinOrder = 0.1;
inline constexpr double kMaxOrder = 12.0;

/// The estimate from the three levels (h, q) given. Throws softflow::Error
/// unless h1 > h2 > h3 > 0 and every value is finite.
RichardsonEstimate richardson(double h1, double q1, double h2, double q2, double h3, double q3);

/// From two levels h1 > h2 with values q1, q2 and the order p known (from an
/// earlier study of the same family of meshes, or from theory):
///   q_inf = q2 + (q2 - q1) h2^p / (h1^p - h2^p).
/// Two levels cannot check p: `order` is the one given, `monotone` true, and
/// error_of_finest = |q2 - q_inf|. Throws softflow::Error unless
/// h1 > h2 > 0, both values are finite and p lies in [kMinOrder, kMaxOrder].
RichardsonEstimate richardson_with_order(double h1, double q1, double h2, double q2, double order);

/// For levels ordered coarse to fine (at least three): the estimate of each
/// consecutive triple, coarsest triple first. The last one uses the finest
/// meshes; agreement of the orders shows the sequence is asymptotic.
std::vector<RichardsonEstimate> richardson_triples(std::span<const double> h,
                                                   std::span<const double> q);

}  // namespace softflow::analysis
