// A spherical drop with Navier slip in simple shear: one Stokes solve on a
// slip system against the exact instantaneous field, and the discrete
// energy balance. Shared by the slip verification tests and studies.
#pragma once

namespace softflow::verification {

struct SlipDropResult {
  int equator_nodes = 0;
  double h0 = 0.0;  ///< interface element size 2 pi / (N / 2)
  int unknowns = 0;
  double velocity_l2 = 0.0;  ///< vs the exact field, both phases
  double pressure_l2 = 0.0;  ///< up to a constant
  /// L2 norm over the interface of (u_m - u_d) - exact jump, and of the exact jump.
  double jump_l2 = 0.0, exact_jump_l2 = 0.0;
  /// Slip dissipation: computed (integral lambda_h . (u_m - u_d)), exact.
  double slip_dissipation = 0.0, exact_slip_dissipation = 0.0;
  /// Discrete energy terms: viscous dissipation sum_r integral 2 eta D:D,
  /// work of the boundary (the consistent reaction forces times the
  /// boundary velocities), work of the tension load on the velocity.
  double viscous_dissipation = 0.0, boundary_work = 0.0, tension_work = 0.0;
  /// alpha integral |(I - nn) lambda_h|^2: the slip dissipation the Navier
  /// law implies from the multipliers alone.
  double navier_dissipation = 0.0;
  /// Solver iterations (1 for the direct method).
  int iterations = 0;
};

/// Unit drop (viscosity ratio lambda, dimensionless slip alpha, tension
/// gamma) in a box [-3, 3]^3 in simple shear, the exact instantaneous slip
/// field on every box face; mesh as verification::drop_in_shear.
/// `interface_slip = false` solves the no-slip system (alpha must be 0).
/// `iterative`: GMRES with the Schur fieldsplit (rtol 1e-10) instead of LU.
SlipDropResult slip_drop_in_shear(double lambda, double alpha, double gamma, int equator_nodes,
                                  bool interface_slip = true, bool iterative = false);

}  // namespace softflow::verification
