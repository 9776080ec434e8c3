// The gaps between a mesh's objects and the walls, and between objects, as
// the mesh resolves them now (issue 31, the remesh trigger `remesh.gap_elements`):
// an object that migrates towards a wall, or two that approach each other,
// squeeze the elements of the gap between them while the ALE motion keeps the
// node count; the gap's elements across, counted as the mesher counts them
// (measure_segment), say when a remesh must restore them.
#pragma once

#include <optional>
#include <vector>

#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

/// Each object's interface nodes (the P2 nodes of its interface faces, once
/// each), by object (index k - 1 for object k): its current surface as points.
std::vector<std::vector<Eigen::Vector3d>> interface_points(const mesh::Mesh& mesh);

/// One gap of an object: to a wall (other = 0) or to another object.
struct ObjectGap {
  int object = 0;  ///< 1-based
  int other = 0;   ///< 1-based object, or 0 for a wall
  /// The segment between the closest interface nodes (or the interface node
  /// nearest the wall and the wall), its length and the elements across it.
  WallGapResolution resolution;
};

/// Of the gaps narrower than `narrower_than` (each object to its nearer wall,
/// each pair of objects), the one crossed by the fewest elements; none when
/// no gap is that narrow. Interface nodes stand for the surfaces (their P2
/// nodes lie on the curved interface), so a gap is measured to within the
/// surface's sag between nodes, O(h^3) for P2.
std::optional<ObjectGap> least_resolved_gap(const mesh::Mesh& mesh, double narrower_than);

}  // namespace softflow::geometry
