// Canonical verification problems around a spherical drop, shared by the
// tests and the validation programs so both measure the same thing.
#pragma once

#include <vector>

#include "softflow/la/saddle_point_solver.hpp"

namespace softflow::verification {

struct DropSolveResult {
  int equator_nodes = 0;
  double h0 = 0.0;                ///< interface element size 2 pi / (N / 2)
  int unknowns = 0;
  double velocity_l2 = 0.0;       ///< vs the exact field (shear case only)
  double pressure_l2 = 0.0;       ///< up to a constant (shear case only)
  double pressure_jump = 0.0;     ///< area-averaged p_drop - p_matrix
  double exact_pressure_jump = 0.0;
  double max_velocity = 0.0;
  std::vector<double> solution;   ///< every unknown (velocity, pressure), global numbering
  int iterations = 0;             ///< of the Stokes solve
  bool reused_preconditioner = false;
  int preconditioner_builds = 0;  ///< by the system so far
  /// The iterative solver's coarse spaces after the solve: the Schur
  /// correction's coefficients and the number of velocity coarse vectors.
  std::vector<double> schur_correction_coefficients;
  int primal_coarse_vectors = 0;
  double drop_volume = 0.0;       ///< of the drop's curved tetrahedra
};

/// Unit drop (viscosity ratio lambda, tension gamma) in a box [-3,3]^3 in
/// simple shear, the exact instantaneous field on every box face; meshes
/// refined uniformly in shape (far size 2.5 h0, growth 0.3 * 24 / N).
DropSolveResult drop_in_shear(double lambda, double gamma, int equator_nodes,
                              const la::SaddlePointSettings& settings = {});
/// The same drop solved once per viscosity ratio in `lambdas`, in order, by
/// one Stokes system (as a time loop does: each solve starts from the
/// previous solution and may keep the previous preconditioner).
std::vector<DropSolveResult> drop_in_shear_sequence(const std::vector<double>& lambdas,
                                                    double gamma, int equator_nodes,
                                                    const la::SaddlePointSettings& settings = {});

/// Unit drop with Gamma = 1 at rest in a periodic 8^3 cell with walls at
/// rest (far size 2): the exact solution is u = 0 and a jump 2 Gamma / R = 2.
DropSolveResult static_drop(int equator_nodes);

}  // namespace softflow::verification
