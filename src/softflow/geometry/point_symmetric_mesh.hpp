// A mesh of the whole shear cell made symmetric under the shear flow's point
// symmetry: the rotation by pi about the vorticity axis z,
// R (x, y, z) = (-x, -y, z).
//
// Simple shear u = (gamma_dot y, 0, 0) between walls y = +-H/2 is invariant
// under R, and so is an object centred on the z axis (a sphere, or an
// ellipsoid turned about z only). The exact solution is then R-symmetric and
// its centre of volume cannot move in x or y: any drift across streamlines
// (v_p = dy_p/dt, thesis eq. 3.6's companion measure) is numerical. On an
// unstructured gmsh mesh the discrete problem is not R-symmetric and such an
// object drifts (docs/confinement.md, "The noise floor"); on a mesh that R
// maps onto itself every step of the discrete problem (Stokes, the interface
// tracker, the mesh motion) is R-equivariant, so the drift is round-off.
#pragma once

#include <vector>

#include "softflow/mesh/half_turn.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

/// The whole cell from a mesh of its upper half y >= 0 and the nodes of the
/// half's cut plane y = 0, whose mesh R must map onto itself (x -> -x on the
/// plane). The lower half is the image of the upper one under R: nodes off
/// the plane get an image each, a node on the plane is identified with its
/// mirror node (x -> -x) there. Cut-plane nodes are put exactly on y = 0 and
/// pairs exactly at (+-x, 0, z), so that R maps the result onto itself to
/// the bit. Tetrahedra keep their orientation (R is a proper rotation), and
/// so do interface faces (outward stays outward); the bottom wall is the
/// image of the top one, x_min faces of x_max ones. `half` must carry no
/// periodic identification: the whole mesh's is made here by coordinates
/// (periodic_classes). Throws MeshError when a cut-plane node has no mirror
/// node.
mesh::Mesh complete_by_half_turn(const mesh::Mesh& half, const std::vector<int>& cut_nodes);

/// The periodic node classes of `m` (its box says which directions are
/// periodic) by coordinates: a node on x = L/2 is identified with the node
/// at x - L on x = -L/2, likewise in z; corner edges collapse to one class
/// through a union-find whose representative is the smallest index. Empty
/// when nothing is periodic. Throws MeshError when a node on a periodic face
/// has no image on the opposite face.
std::vector<int> periodic_classes(const mesh::Mesh& m);

/// How many nodes of `m` have no node within `tolerance` of their image
/// under R: 0 for a mesh that R maps onto itself, most of them for an
/// unstructured one.
int nodes_without_half_turn_image(const mesh::Mesh& m, double tolerance);

}  // namespace softflow::geometry
