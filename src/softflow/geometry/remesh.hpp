// Remeshing the shear cell around its current interfaces (issue 31): a new P2
// mesh of the domain a run has deformed, with the interfaces kept as they are.
#pragma once

#include <vector>

#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

/// What a remesh did.
struct RemeshReport {
  int nodes_before = 0, nodes_after = 0;
  int tets_before = 0, tets_after = 0;
  double quality_before = 0.0, quality_after = 0.0;  ///< mesh::min_quality
  /// mesh::min_interface_shape of the interfaces kept: the new elements on
  /// them are shaped by these triangles, which the remesh does not change.
  double interface_shape = 1.0;
  int algorithm = 1;  ///< gmsh's Mesh.Algorithm3D of the mesh kept: 1 Delaunay, 10 HXT
  double seconds = 0.0;
};

/// A new mesh and how its nodes relate to the old one's.
struct Remeshed {
  mesh::Mesh mesh;
  /// For every node of the old mesh: its node in the new mesh if it lies on
  /// an interface (every interface P2 node is carried over, at the same
  /// position), else -1.
  std::vector<int> new_node_of_old;
  RemeshReport report;
};

/// Meshes the domain of `current` (a mesh of `spec`'s cell whose nodes a run
/// has moved) again, with the same interfaces:
///
///  - each object's interface: its corner-node triangulation is handed to
///    gmsh as a discrete surface, which gmsh keeps as it is (same vertices,
///    same triangles); after the P2 elevation every interface edge's
///    mid-node is put back at its old position. The curved interface is
///    therefore the old one node for node, and so are the volume it
///    encloses and its area, to round-off;
///  - the box: the cell of `spec` at the position the mesh has been
///    translated to along x (the ALE translation d1 moves the periodic faces
///    too), its walls and periodic faces meshed afresh, periodic as in
///    build_shear_cell;
///  - the size field of `spec.sizing` (h0 of each object's spec, growth,
///    interior growth, wall size, narrow wall gaps) with the distance to the
///    current interface instead of the described shape's.
///
/// Regions, interface and boundary faces, their orientation, the periodic
/// classes, the spatial renumbering and the checks are build_shear_cell's.
/// Throws MeshError when gmsh fails or would change an interface.
Remeshed remesh(const ShearCellSpec& spec, const mesh::Mesh& current);

}  // namespace softflow::geometry
