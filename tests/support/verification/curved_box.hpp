// The curved two-region test mesh the finite-element layer is verified on.
#pragma once

#include "softflow/mesh/mesh.hpp"

namespace softflow::verification {

/// [-1, 1]^3 in n^3 cubes (6 tetrahedra each, no periodicity), the central
/// cubes (|x|_inf < 1/2) region 1, and every node moved by
/// x + amplitude sin(pi x) sin(pi y) sin(pi z) (1, -0.7, 0.4): the map
/// vanishes on the box faces and curves every element and the interface
/// (amplitude 0: straight elements).
mesh::Mesh curved_box_with_block(int n, double amplitude);

}  // namespace softflow::verification
