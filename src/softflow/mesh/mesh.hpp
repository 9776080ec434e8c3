// The volume mesh: quadratic (10-node) tetrahedra with region tags, tagged
// boundary and interface triangles, and the periodic node identification.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace softflow::mesh {

using Point = Eigen::Vector3d;

/// Local node order of a 10-node tetrahedron (the VTK_QUADRATIC_TETRA order):
/// vertices 0..3, then edge nodes on (0,1) (1,2) (0,2) (0,3) (1,3) (2,3).
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges{
    {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}};
/// Local node order of a 6-node triangle: vertices 0..2, then edge nodes on
/// (0,1) (1,2) (2,0) (VTK_QUADRATIC_TRIANGLE and gmsh agree).
inline constexpr std::array<std::array<int, 2>, 3> kTriangleEdges{{{0, 1}, {1, 2}, {2, 0}}};

using Tet10 = std::array<int, 10>;
using Triangle6 = std::array<int, 6>;

/// Which part of the outer boundary a triangle lies on.
enum class BoundaryTag : int {
  wall_bottom = 0,  ///< y = -H/2
  wall_top = 1,     ///< y = +H/2
  x_min = 2,        ///< faces only present when x is not periodic
  x_max = 3,
  z_min = 4,        ///< faces only present when z is not periodic
  z_max = 5,
};

/// The shear cell [-L/2, L/2] x [-H/2, H/2] x [-W/2, W/2].
struct Box {
  double length = 0.0;  ///< L, along x (flow)
  double height = 0.0;  ///< H, along y (gradient); walls at y = +-H/2
  double width = 0.0;   ///< W, along z (vorticity)
  bool periodic_x = true;
  bool periodic_z = true;
};

/// Isoparametric P2 mesh of the matrix (region 0) and objects (regions 1..n).
///
/// Geometry nodes are shared by every tetrahedron that touches them, also
/// across an interface: the doubling of unknowns at interfaces is the job of
/// the dof maps (fem/), not of the mesh.
struct Mesh {
  Box box;
  int n_objects = 0;

  std::vector<Point> nodes;        ///< every geometry node (vertices and edge nodes)
  std::vector<std::uint8_t> is_vertex;  ///< 1 for tetrahedron vertices, 0 for edge nodes

  std::vector<Tet10> tets;         ///< in kTetEdges order
  std::vector<int> tet_region;     ///< 0 = matrix, k = object k (1-based)

  std::vector<Triangle6> boundary_faces;       ///< on the outer box
  std::vector<BoundaryTag> boundary_face_tag;

  /// Interface triangles of each object, ordered so that the right-hand normal
  /// (x1 - x0) x (x2 - x0) points out of the object, into the matrix.
  std::vector<Triangle6> interface_faces;
  std::vector<int> interface_object;           ///< object (1-based) of each face

  /// Periodic identification: periodic_master[i] is the representative of the
  /// class of nodes identified with node i by periodicity (i itself if none).
  /// Representatives are closed: periodic_master[periodic_master[i]] ==
  /// periodic_master[i]. Empty means no periodicity.
  std::vector<int> periodic_master;

  [[nodiscard]] int n_nodes() const { return static_cast<int>(nodes.size()); }
  [[nodiscard]] int n_tets() const { return static_cast<int>(tets.size()); }
  [[nodiscard]] int master(int node) const {
    return periodic_master.empty() ? node : periodic_master[node];
  }
};

}  // namespace softflow::mesh
