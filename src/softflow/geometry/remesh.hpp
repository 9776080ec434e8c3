// Remeshing the shear cell around its current interfaces (issue 31): a new P2
// mesh of the domain a run has deformed, with the interfaces kept as they are.
#pragma once

#include <vector>

#include "softflow/geometry/interface_surface.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

/// How a remesh treats each object's interface.
enum class InterfaceRemeshing {
  keep,       ///< node for node: the interface trackers' histories carry over as they are
  resample,   ///< afresh at the case's sizes (resample_interface)
  automatic,  ///< resample the interfaces that no longer fit their sizes (needs_resampling), keep
              ///< the others
};

/// Thresholds of InterfaceRemeshing::automatic. Fresh gmsh interfaces of a
/// sphere (12-32 equator nodes) fit within size mismatch 1.33-1.72 and
/// curved shape 0.50-0.57; the particle that had migrated away from the
/// wall it was meshed against had 7.7 and 0.033 when its remeshes stopped
/// improving the mesh (tests/unit/test_interface_resampling.cpp,
/// docs/remeshing.md).
inline constexpr double kResampleSizeMismatch = 2.0;
inline constexpr double kResampleCurvedShape = 0.25;
/// Whether `fit` calls for a fresh interface.
bool needs_resampling(const InterfaceFit& fit);

/// What a remesh did.
struct RemeshReport {
  int nodes_before = 0, nodes_after = 0;
  int tets_before = 0, tets_after = 0;
  double quality_before = 0.0, quality_after = 0.0;  ///< mesh::min_quality
  /// mesh::min_interface_shape of the interfaces kept: the new elements on
  /// them are shaped by these triangles, which the remesh does not change.
  double interface_shape = 1.0;
  int algorithm = 1;  ///< gmsh's Mesh.Algorithm3D of the mesh kept: 1 Delaunay, 10 HXT
  /// Per object: whether its interface was resampled, and how it fitted its
  /// sizes before.
  std::vector<char> resampled;
  std::vector<InterfaceFit> fit_before;
  /// Interface triangles of all objects before and after.
  int interface_triangles_before = 0, interface_triangles_after = 0;
  /// Largest relative change of an enclosed volume (round-off either way).
  double volume_change = 0.0;
  double seconds = 0.0;
};

/// A new mesh and how its nodes relate to the old one's.
struct Remeshed {
  mesh::Mesh mesh;
  /// For every node of the old mesh: its node in the new mesh if it lies on
  /// a kept interface (every P2 node of a kept interface is carried over, at
  /// the same position), else -1 (the nodes of a resampled interface are new).
  std::vector<int> new_node_of_old;
  /// For every node of the new mesh: where it lay on the old interface if
  /// it is a node of a resampled interface (its old triangle's mesh nodes
  /// and reference coordinates there), else an origin with triangle -1.
  std::vector<InterfaceSurface::Origin> old_surface_point;
  RemeshReport report;
};

/// Meshes the domain of `current` (a mesh of `spec`'s cell whose nodes a run
/// has moved) again, with the same interfaces:
///
///  - each object's interface, kept or resampled as `interfaces` says (a
///    resampled one is a new triangulation of the same curved surface,
///    enclosing the same volume to round-off): its corner-node
///    triangulation is handed to gmsh as a discrete surface, which gmsh
///    keeps as it is (same vertices, same triangles); after the P2
///    elevation every interface edge's mid-node is put back where the
///    surface has it. A kept interface is therefore the old one node for
///    node, and so are the volume it encloses and its area, to round-off;
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
///
/// `tracked`, if given, is `current` with the interface nodes where the
/// run's trackers have them (x_n; a run's mesh has them at the step's
/// prediction): a resampled interface is taken from it, so that its volume
/// is the tracked one. A kept interface is `current`'s either way.
Remeshed remesh(const ShearCellSpec& spec, const mesh::Mesh& current,
                InterfaceRemeshing interfaces = InterfaceRemeshing::keep,
                const mesh::Mesh* tracked = nullptr);

}  // namespace softflow::geometry
