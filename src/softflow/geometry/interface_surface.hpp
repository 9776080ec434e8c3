// One object's closed interface as a curved P2 triangulation, apart from any
// volume mesh: what a remesh keeps, or samples afresh (issue 31).
//
// A run's tangential redistribution keeps the interface's triangles in the
// proportions of the mesh it started from (eq. 2.32's reference areas), and
// its P2 edge nodes may slide along their edges. Both are harmless while the
// object stays where it was meshed; a particle that starts near a wall
// (its interface refined towards the gap) and migrates away keeps a patch of
// triangles 5-10 times smaller than the interface size the case asks for,
// whose edge nodes sit a quarter of an edge off centre: every element with a
// face there is poorly shaped, however the volume is remeshed. Sampling the
// interface afresh, on the curved surface and at the case's sizes, removes
// both; the enclosed volume is restored to round-off.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

/// A closed, outward-oriented P2 triangulation: corner vertices, triangles
/// of three corner indices (right-hand normal out of the object), and each
/// triangle's three edge nodes in mesh::kTriangleEdges order.
struct InterfaceSurface {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<Eigen::Vector3d, 3>> edge_nodes;
  /// Kept interfaces only: the mesh node of each vertex and of each
  /// triangle's edge nodes (-1 for a resampled surface, whose nodes are new).
  std::vector<int> mesh_vertex;
  std::vector<std::array<int, 3>> mesh_edge_node;
  /// Resampled surfaces only: where each vertex and each triangle's edge
  /// nodes lie on the surface they were sampled from (before the volume's
  /// offset), as that surface's triangle and reference coordinates: what
  /// carries a field of the old nodes (a tracker's x_{n-1}) to the new ones.
  struct Origin {
    int triangle = -1;
    Eigen::Vector2d xi = Eigen::Vector2d::Zero();
    /// That triangle's 6 mesh nodes (corners, then edge nodes), if the
    /// surface sampled from was a mesh's (interface_surface); else -1.
    std::array<int, 6> mesh_nodes{-1, -1, -1, -1, -1, -1};
  };
  std::vector<Origin> vertex_origin;
  std::vector<std::array<Origin, 3>> edge_node_origin;

  [[nodiscard]] bool resampled() const { return mesh_vertex.empty(); }
  /// The 6 nodes of triangle t as a P2 triangle (corners, then edge nodes).
  [[nodiscard]] std::array<Eigen::Vector3d, 6> triangle_nodes(int t) const;
};

/// Object `object`'s (1-based) interface in `mesh`, node for node.
InterfaceSurface interface_surface(const mesh::Mesh& mesh, int object);

/// The volume a closed P2 triangulation encloses, 1/3 int x.n ds, exact
/// (the integrand is a polynomial of degree 4 on each triangle).
double enclosed_volume(const InterfaceSurface& surface);

/// Its area (the degree-7 rule of physics::surface_integrals).
double surface_area(const InterfaceSurface& surface);

/// How well a surface fits the sizes it should have.
struct InterfaceFit {
  /// Largest of size/target and target/size over the triangles (size: the
  /// side of the equilateral triangle of the same area; target: `size` at
  /// the triangle's centroid). 1 when every triangle has its size.
  double size_mismatch = 1.0;
  /// Smallest over the triangles of their corner shape (mesh::triangle_shape)
  /// times the distortion of their curved map (min / max area scale at the
  /// corners, edge nodes and the quadrature points): 1 for an equilateral
  /// triangle with centred edge nodes; an edge node a quarter of an edge
  /// off centre gives ~0.5.
  double curved_shape = 1.0;
};
InterfaceFit interface_fit(const InterfaceSurface& surface,
                           const std::function<double(const Eigen::Vector3d&)>& size);

/// What resample_interface did.
struct ResamplingReport {
  int triangles_before = 0, triangles_after = 0;
  /// The uniform normal offset that restored the enclosed volume, relative
  /// to the largest target size (the surface's sag between the old and the
  /// new nodes: O(h^3) for P2).
  double volume_offset = 0.0;
  /// |V_after / V_before - 1| after the offset (round-off).
  double volume_change = 0.0;
};

/// A new triangulation of `surface` with triangles of the sizes `size`
/// asks for: gmsh's frontal-Delaunay on a parametrisation of the surface
/// (each P2 triangle given as its four straight sub-triangles), every new
/// vertex and every chord midpoint then projected to the closest point of
/// the curved P2 surface, and all nodes finally offset along the surface
/// normal by one common distance so that the enclosed volume is the old one
/// to round-off. The shape is the old one to within the P2 surface's own
/// interpolation error. Throws MeshError if gmsh fails.
InterfaceSurface resample_interface(const InterfaceSurface& surface,
                                    const std::function<double(const Eigen::Vector3d&)>& size,
                                    ResamplingReport* report = nullptr);

}  // namespace softflow::geometry
