// Interface tracking in extensional flow: the thesis §2.4.1 verification problem.
#pragma once

namespace softflow::verification {

struct TrackingErrors {
  int equator_nodes = 0;
  int interface_nodes = 0;
  double dt = 0.0;
  double e_max = 0.0;  ///< max_i |x_i - x_i,an| / R
  double e_2 = 0.0;    ///< sqrt(mean_i |x_i - x_i,an|^2) / R
};

/// A unit sphere's P2 surface mesh (gmsh, `equator_nodes` P2 nodes around
/// the equator) moved by the interface tracker in u = (x, -y/2, -z/2) to
/// t = 0.5. Fluid points of the sphere form the spheroid with semi-axes
/// e^t, e^{-t/2}, e^{-t/2}; x_i,an is where the ray from the origin through
/// node i meets it (thesis §2.4.1). k is the redistribution factor.
/// `step_variation` v > 0 alternates the steps between (1 + v) dt and
/// (1 - v) dt (pairs of steps average dt), which exercises the
/// variable-step BDF2 and predictor at ratios (1 -+ v) / (1 +- v).
TrackingErrors track_sphere_in_extension(int equator_nodes, double dt, double k,
                                         double step_variation = 0.0);

}  // namespace softflow::verification
