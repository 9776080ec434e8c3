// The shear flow's point symmetry, the rotation by pi about the z axis
// R (x, y, z) = (-x, -y, z), on a mesh: which node is which node's image.
#pragma once

#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// R p, exact (two sign flips).
inline Point half_turn(const Point& p) { return {-p.x(), -p.y(), p.z()}; }

/// image[i] = the node at exactly R x_i, when R maps the mesh onto itself:
/// every node has an image (a mesh made point-symmetric has them to the bit)
/// and every tetrahedron's image is a tetrahedron. Empty otherwise: for an
/// unstructured mesh at the first node without an image; a structured
/// grid's nodes may all have images while its elements do not.
[[nodiscard]] std::vector<int> half_turn_images(const Mesh& mesh);

}  // namespace softflow::mesh
