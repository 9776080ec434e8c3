// One object's interface as its own curved P2 surface mesh.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "softflow/mesh/mesh.hpp"

namespace softflow::physics {

using Vec3 = Eigen::Vector3d;

/// The interface S of object `object`: the quadratic triangles of the volume
/// mesh that bound it (thesis eq. 2.43), renumbered locally, oriented with the
/// normal pointing out of the object.
struct InterfaceMesh {
  int object = 0;                          ///< 1-based
  std::vector<int> volume_node;            ///< local node -> volume mesh node
  std::vector<std::array<int, 6>> triangles;  ///< local node indices

  [[nodiscard]] int n_nodes() const { return static_cast<int>(volume_node.size()); }
};

InterfaceMesh extract_interface(const mesh::Mesh& mesh, int object);

/// Positions of the interface nodes taken from the volume mesh.
std::vector<Vec3> interface_positions(const InterfaceMesh& s, const mesh::Mesh& mesh);

/// Volume V (eq. 2.53), first moment Q (eq. 2.54) and area of the closed
/// surface with node positions x: V = 1/3 int_S n.x ds, Q = 1/2 int_S n |x|^2 ds.
struct SurfaceIntegrals {
  double volume = 0.0;
  Vec3 first_moment = Vec3::Zero();
  double area = 0.0;
  [[nodiscard]] Vec3 centre_of_volume() const { return first_moment / volume; }
};
SurfaceIntegrals surface_integrals(const InterfaceMesh& s, const std::vector<Vec3>& x);

/// Unit outward normal at each node of the surface at positions x: the
/// triangles' normals at the node averaged with their areas as weights (the
/// P2 surface is only continuous, so the triangles sharing a node disagree
/// slightly about its normal).
std::vector<Vec3> node_normals(const InterfaceMesh& s, const std::vector<Vec3>& x);

/// Area of each triangle at positions x.
std::vector<double> triangle_areas(const InterfaceMesh& s, const std::vector<Vec3>& x);

}  // namespace softflow::physics
