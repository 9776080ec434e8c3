// Steady convection-diffusion with SUPG on a P1 per-region space: a
// manufactured solution with a jump at the interface, on curved meshes.
#pragma once

namespace softflow::verification {

struct ConvectionDiffusionErrors {
  int n = 0;          ///< cubes per box edge (h = 2 / n)
  int unknowns = 0;
  double peclet = 0;  ///< element Peclet number |b| h / (2 eps)
  double l2 = 0.0;    ///< ||phi_h - phi||_L2 over both regions
  double h1 = 0.0;    ///< |phi_h - phi|_H1 (seminorm)
  double overshoot = 0.0;  ///< max over vertices of phi_h - phi (oscillations)
};

/// Solves, on [-1, 1]^3 in n^3 cubes (6 tetrahedra each) whose central cubes
/// (|x|_inf < 1/2) are region 1, all nodes moved by a smooth map that curves
/// the elements and the interface,
///
///   (1) eps (grad v, grad phi_h)
///   (2)   + (v, b . grad phi_h)                               (non-symmetric)
///   (3)   + sum_e (b . grad v, tau_e (b . grad phi_h))_e      (SUPG, if `supg`)
///       = (v, f) + sum_e (b . grad v, tau_e f)_e
///
/// for phi_h in P1 per region (one copy per side of the interface), with
/// phi_h = phi on the outer boundary and on each side of the interface,
/// f = -eps lap phi + b . grad phi, b = (1, 0.6, -0.3) and a smooth exact
/// phi that differs between the regions. For P1 the element residual lacks
/// -eps lap phi_h; tau's Peclet factor (fem::supg_tau) makes that
/// inconsistency O(h^2). Assembled through la::CsrMatrix (the general,
/// non-symmetric path), solved by MUMPS LU. Collective.
ConvectionDiffusionErrors solve_convection_diffusion(int n, double eps, bool supg);

}  // namespace softflow::verification
