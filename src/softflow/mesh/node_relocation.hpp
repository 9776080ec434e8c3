// Optimisation-based relocation of free mesh nodes: keeps a moving ALE mesh
// valid where a harmonic extension alone folds it.
#pragma once

#include <array>
#include <vector>

#include "softflow/mesh/mesh.hpp"

namespace softflow::mesh {

/// Why: the harmonic extension of the interface motion (physics/ale) keeps
/// element volumes in proportion but not their angles. Where a drop or a
/// tensionless particle stretches, a tetrahedron that touches the interface
/// with one face turns until its interior edge leaving an interface vertex
/// lies almost in the curved interface: the straight shape stays fair
/// (mean ratio ~0.7) while det J of the P2 map at that vertex goes to zero
/// (measured: a drop at Ca 0.3 on a 20-node mesh stopped with quality
/// < 0.02 at D = 0.20, element 210 throughout). Its fourth vertex and its
/// interior edge nodes are free, and moving them restores the element.
///
/// What: for every tetrahedron below a target quality, each of its free
/// vertices, then each of its free edge nodes, is moved by a compass
/// (pattern) search that maximises the smallest tet_quality of the elements
/// around it. A vertex takes the edge nodes of its edges along by half its
/// move (each edge keeps its curvature); an edge node alone bends its edge
/// (the tangent of edge (a, b) at a is 4 x_ab - 3 x_a - x_b, so it turns
/// the corner where the element folds). Fixed: every node on an interface
/// or the outer boundary, and every node of a periodic class (the copies
/// must keep differing by lattice vectors). Deterministic, so every rank
/// of a replicated mesh gets the same result.
///
/// On a mesh that the half turn R (x, y, z) -> (-x, -y, z) maps onto itself
/// (mesh.point_symmetric, geometry/point_symmetric_mesh.hpp) the relocation
/// keeps that symmetry: each pair of mirror nodes is searched once and its
/// image put at the R-image of the result, and nodes on the z axis (their
/// own images) stay fixed. Searching both copies independently breaks it,
/// since the search tries its directions in one fixed order that R does not
/// preserve: a centred drop relocated so (8-18 nodes moved at the first step
/// on the migration figures' meshes) drifted across streamlines at 6e-5 to
/// 2.4e-4 gamma_dot R where without relocation it stays at y = 0 to 1e-14.
class NodeRelocation {
 public:
  explicit NodeRelocation(const Mesh& mesh);

  struct Report {
    int nodes_moved = 0;
    double quality_before = 1.0;  ///< smallest quality of the elements below the target
    double quality_after = 1.0;   ///< the same elements' smallest quality after the moves
    /// Smallest quality over every element after the moves (1 without
    /// elements): what a caller checks next, without scanning again.
    double smallest_quality = 1.0;
  };

  /// Relocates, in `nodes` (positions of the constructor's mesh, possibly
  /// moved since), the free nodes of the elements with quality below
  /// `target`. A node moves only if that raises the smallest quality of the
  /// elements around it; at most `sweeps` passes over the bad elements.
  Report improve(std::vector<Point>& nodes, double target, int sweeps = 3) const;

  [[nodiscard]] bool is_free(int node) const { return free_[node] != 0; }

 private:
  /// Smallest quality of the tetrahedra around `node` on `nodes`.
  [[nodiscard]] double local_quality(const std::vector<Point>& nodes, int node) const;
  /// Moves `node` by `shift` and, if it is a vertex, its edge nodes by half of it.
  void shift(std::vector<Point>& nodes, int node, const Point& shift) const;
  /// Compass search for one node; true if it moved.
  bool relocate(std::vector<Point>& nodes, int node) const;

  /// Puts the image of `node` and of its edge nodes at the R-images of
  /// their positions (on a point-symmetric mesh; nothing otherwise).
  void mirror(std::vector<Point>& nodes, int node) const;

  std::vector<Tet10> tets_;
  std::vector<char> free_;
  /// image_[i]: the node at R x_i on a point-symmetric mesh; empty otherwise.
  std::vector<int> image_;
  std::vector<std::vector<int>> tets_of_node_;
  std::vector<std::vector<int>> edge_nodes_of_vertex_;  ///< edge nodes of the vertex's edges
  std::vector<std::array<int, 2>> edge_ends_;           ///< an edge node's vertices; -1 for a vertex
};

}  // namespace softflow::mesh
