// Structured P2 tetrahedral meshes of a box, for the verification and unit tests (not
// shipped in softflow_core: the program meshes with gmsh, geometry/shear_cell).
#pragma once

#include <functional>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// A box split into nx * ny * nz cubes of 6 tetrahedra each (Kuhn
/// triangulation, conforming across cubes), P2 with straight edges, one
/// region (the matrix). Faces normal to x (z) are periodic if
/// box.periodic_x (periodic_z), otherwise tagged boundary faces.
/// The box is [-L/2, L/2] x [-H/2, H/2] x [-W/2, W/2].
Mesh structured_box(const Box& box, int nx, int ny, int nz);

/// Moves every geometry node (vertices and edge nodes) by x -> map(x). A
/// nonlinear map curves the elements: the result is a genuinely
/// isoparametric mesh.
void map_nodes(Mesh& mesh, const std::function<Point(const Point&)>& map);

}  // namespace softflow::mesh
