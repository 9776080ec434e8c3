// The transient of a drop starting to deform in shear on a coarse mesh:
// the time-integration test problem shared by tests and validation programs.
#pragma once

#include <string>
#include <vector>

namespace softflow::verification {

struct DropTransient {
  double dt = 0.0;
  bool semi_implicit_tension = false;
  std::vector<double> time, deformation;  ///< D(t) at every step, t = 0 included
  /// Empty if the run reached t_end; else why it stopped (e.g. mesh degraded).
  std::string stop_reason;
};

/// A unit drop, lambda = 1, Ca = 0.1 (Gamma = 10), in an 8^3 periodic cell
/// with 16 equator nodes (the regression case's mesh), from rest to t_end.
DropTransient deform_drop_in_shear(double dt, double t_end, bool semi_implicit_tension);

/// max over the common output times t >= from_time of |D_a(t) - D_b(t)|;
/// b's step must divide a's.
double max_deformation_difference(const DropTransient& a, const DropTransient& b,
                                  double from_time = 0.0);

}  // namespace softflow::verification
