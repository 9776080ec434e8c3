// Shape quality of curved P2 tetrahedra: straight-shape measure times curving distortion.
#pragma once

#include <span>
#include <string>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// Quality of one tetrahedron in (-1, 1]: the mean-ratio shape measure of its
/// straight (vertex) tetrahedron, 12 (3|V|)^{2/3} / sum of squared edge
/// lengths (1 for the regular tetrahedron, -> 0 when degenerate), times the
/// distortion min det J / max det J of the P2 map sampled at the 4 vertices,
/// the 6 edge nodes, the centroid and the 14 points of the degree-5
/// quadrature rule the assemblies use. A non-positive Jacobian at any sample
/// gives a quality <= 0 (min det J / max |det J|), so "> 0" means "valid"
/// wherever an assembly evaluates the map.
double tet_quality(const Mesh& mesh, int tet);
/// The same for the tetrahedron `tet` on the node positions `nodes`.
double tet_quality(std::span<const Point> nodes, const Tet10& tet);

/// Smallest tet_quality over the mesh; 1 for a mesh without tetrahedra.
double min_quality(const Mesh& mesh);

/// Index of a tetrahedron of smallest quality; -1 for a mesh without tetrahedra.
int worst_tet(const Mesh& mesh);

/// "element T (region R, near (x, y, z))", the position of its first
/// vertex: how failure messages say where an element is.
std::string describe_element(const Mesh& mesh, int tet);

/// Shape of a triangle's corners, 4 sqrt(3) area / (sum of squared edges):
/// 1 for an equilateral triangle, -> 0 as it degenerates.
double triangle_shape(const Point& a, const Point& b, const Point& c);

/// The smallest triangle_shape of the interface triangles (their corner
/// nodes); 1 without interfaces. A tetrahedron with a face on an interface
/// cannot be much better shaped than that face.
double min_interface_shape(const Mesh& mesh);

}  // namespace softflow::mesh
