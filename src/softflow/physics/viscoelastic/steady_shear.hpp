// Steady simple shear of a viscoelastic liquid, u = (gamma_dot y, 0, 0): the
// homogeneous state where the conformation equation (constitutive.hpp)
// balances, 0 = L c + c L^T + r(c) with L = gamma_dot e_x e_y^T. Gives the
// viscometric functions a case's dimensionless groups need at the flow's own
// shear rate, where the zero-shear ones differ (Giesekus, FENE-P): thesis
// ch. 3 defines p = N / Ca_e^2 with N = N_1 / (2 G_p) and N_1 the first normal
// stress difference of the sheared matrix.
#pragma once

#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::physics::viscoelastic {

/// The steady state of one liquid in simple shear.
struct SteadyShear {
  Mat3 conformation;  ///< c, with c_xz = c_yz = 0
  Mat3 stress;        ///< the polymer stress tau(c) (eq. 2.6)
  int newton_steps = 0;

  /// tau_xy (the polymer's part; add mu gamma_dot for the whole shear stress).
  [[nodiscard]] double shear_stress() const { return stress(0, 1); }
  /// N_1 = tau_xx - tau_yy.
  [[nodiscard]] double first_normal_stress_difference() const { return stress(0, 0) - stress(1, 1); }
  /// N_2 = tau_yy - tau_zz.
  [[nodiscard]] double second_normal_stress_difference() const { return stress(1, 1) - stress(2, 2); }
};

/// The steady simple shear of `model` at `shear_rate` >= 0, by Newton's method
/// on (c_xx, c_yy, c_zz, c_xy), continued from rest in steps of the shear rate
/// small enough for each Newton solve to converge to round-off. Throws
/// softflow::Error for a model that does not relax (Newtonian, the solids:
/// a solid has no steady state in shear) or when no steady state is found
/// (e.g. UCM-like growth past FENE-P's extensibility cannot happen, but a
/// law without one would be reported).
[[nodiscard]] SteadyShear steady_simple_shear(const Constitutive& model, double shear_rate);

}  // namespace softflow::physics::viscoelastic
