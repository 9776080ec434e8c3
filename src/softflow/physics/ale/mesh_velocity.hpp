// Mesh velocity of the ALE description (thesis §2.3.3, Step 3).
#pragma once

#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::physics {

/// u_m at every geometry node after a step of size dt, by the same Gear
/// formula the interface uses (time/bdf.hpp): BDF1 (x_new - x) / dt when
/// there is no older level (x_old empty), BDF2 after: (3/2 x_new - 2 x +
/// 1/2 x_old) / dt at a constant step, the variable-step coefficients when
/// the step before (from x_old to x) had another size dt_previous.
/// The Newtonian Stokes solve does not need it; the convective terms of
/// the ALE transport equations (viscoelastic stress, particles) do.
std::vector<mesh::Point> bdf_mesh_velocity(const std::vector<mesh::Point>& x_new,
                                           const std::vector<mesh::Point>& x,
                                           const std::vector<mesh::Point>& x_old, double dt,
                                           double dt_previous);

}  // namespace softflow::physics
