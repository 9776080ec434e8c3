// Builds the shear cell with suspended objects as a curved P2 mesh (gmsh).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry {

enum class ObjectShape { sphere, ellipsoid };

/// One suspended object. Lengths are in the case's length unit.
struct ObjectSpec {
  ObjectShape shape = ObjectShape::sphere;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  /// Semi-axes along the body axes; a sphere has three equal entries.
  Eigen::Vector3d semi_axes = Eigen::Vector3d::Ones();
  /// Body orientation: R = Rz(rz) * Ry(ry) * Rx(rx), angles in degrees.
  Eigen::Vector3d rotation_deg = Eigen::Vector3d::Zero();
};

/// Mesh resolution: size graded from the interface to the far field.
struct MeshSizing {
  /// P2 nodes around the equator of each object (thesis: 28/40/50). The
  /// interface element size is h = 2 pi r / (equator_nodes / 2), r the
  /// object's smallest semi-axis.
  int equator_nodes = 40;
  /// Element size far from the objects (at the walls).
  double far_size = 3.0;
  /// Size growth with distance from the interface: h(d) = h0 + growth * d.
  double growth = 0.4;
  /// The same growth inside the objects, towards their centres; unset =
  /// growth. 0 keeps the interface size throughout an object: the fields
  /// that live only there (a particle's Finger tensor, a drop's conformation)
  /// are then resolved like the interface, and a strongly deformed object
  /// has interior vertices to relocate instead of one hub.
  std::optional<double> interior_growth;
  /// Run gmsh's high-order optimisation (fixes inverted curved elements).
  bool optimize_high_order = true;
  /// Element size at the walls y = +-H/2, growing away from them like the
  /// interface's: h(d_wall) = wall_size + growth * d_wall. Unset: no wall
  /// grading (far_size reaches the walls), the meshes of before the key.
  std::optional<double> wall_size;
  /// At least this many elements across the gap between an object and a
  /// wall narrower than gap_elements interface elements (see
  /// wall_gap_element_size): the elements in such a gap follow its width,
  /// also on the object's surface facing the wall, whatever the interface
  /// size; only a gap narrower than smallest_wall_gap is refused. Unset:
  /// kDefaultGapElements across the gaps narrower than one interface element
  /// only (those validate() refused before the rule), so that every mesh
  /// made before it stays the same to the bit.
  std::optional<int> gap_elements;
  static constexpr int kDefaultGapElements = 2;
  /// Make the mesh symmetric under the shear flow's point symmetry, the
  /// rotation by pi about the z axis, (x, y, z) -> (-x, -y, z): gmsh meshes
  /// the half y >= 0 (its cut plane y = 0 symmetric under x -> -x) and the
  /// lower half is its image (point_symmetric_mesh.hpp). Every object must be
  /// mapped onto itself (centred on the z axis, turned about z only). An
  /// object centred there cannot cross streamlines, and on such a mesh it
  /// does not numerically either (docs/confinement.md, "The noise floor of
  /// a migration measurement"). Off (the default): gmsh meshes the whole
  /// cell, the meshes of before the key to the bit.
  bool point_symmetric = false;
  /// Mesh the cell as point_symmetric does with its one object moved onto
  /// the z axis (symmetric_start(spec)), then carry the object to its
  /// centre by the mesh motion's extension (physics::carry_objects, done by
  /// simulation::build_mesh; build_shear_cell returns the mesh before it).
  /// The half turn then maps the mesh onto the mesh of the mirror start
  /// (-x, -y) to the extension's round-off, so the discretisation error
  /// that breaks the symmetry grows from zero with the offset instead of
  /// being the fixed drift of an unstructured mesh: a migration velocity
  /// near the centre plane is then resolved relative to itself
  /// (docs/confinement.md). One object only.
  bool point_symmetric_start = false;
  [[nodiscard]] int elements_across_gaps() const { return gap_elements.value_or(kDefaultGapElements); }
};

struct ShearCellSpec {
  mesh::Box box;
  std::vector<ObjectSpec> objects;
  MeshSizing sizing;
};

/// How a mesh resolves the gap between an object and a wall, measured along
/// the shortest segment from the object's surface to the wall.
struct WallGapResolution {
  int object = 0;        ///< 1-based
  int side = 0;          ///< +1 upper wall, -1 lower
  double gap = 0.0;      ///< the segment's length
  int tets_crossed = 0;  ///< matrix tetrahedra the segment passes through
  /// The mean edge length of those tetrahedra (their straight edges).
  double mean_edge = 0.0;
  /// gap / mean_edge: the elements across the gap, as mesh.gap_elements counts them.
  [[nodiscard]] double elements_across() const { return mean_edge > 0.0 ? gap / mean_edge : 0.0; }
};

/// What the mesher reports.
struct MeshReport {
  int n_nodes = 0;
  int n_tets = 0;
  int n_interface_nodes = 0;  ///< P2 nodes on all interfaces
  int n_equator_nodes = 0;    ///< effective P2 nodes on the first object's equator: 2 x 2 pi r / mean edge
  /// Tetrahedron vertices strictly inside the objects (all objects): with
  /// the default growth a sphere of 28 equator nodes has a single one, a hub
  /// whose star of elements is all there is to deform.
  int n_object_interior_vertices = 0;
  double min_quality = 0.0;   ///< mesh::min_quality of the result
  /// Vertices embedded below caps that folded once curved (the mesh was then
  /// made again with them; 0: the first mesh was valid).
  int cap_vertices = 0;
  double seconds = 0.0;
  /// mesh::fingerprint of the result: equal fingerprints, the same mesh to
  /// the bit (how a user checks that a case meshes reproducibly).
  std::uint64_t fingerprint = 0;
  /// The narrowest object-wall gap that needed refining (narrower than
  /// gap_elements interface elements), as meshed; empty when none did.
  std::optional<WallGapResolution> wall_gap;
};

/// Body orientation of an object: R = Rz * Ry * Rx (rotation_deg, degrees);
/// the body axes are the columns of R.
Eigen::Matrix3d rotation_matrix(const ObjectSpec& object);

/// Interface element size h0 = 2 pi r / (equator_nodes / 2), r the object's
/// smallest semi-axis: the mesh size on the object's surface, and the
/// minimum gap validate() demands between the object and another object or
/// a periodic face (walls: smallest_wall_gap).
double interface_element_size(const ObjectSpec& object, const MeshSizing& sizing);

/// The most elongated ellipsoid (a_max / a_min) that `equator_nodes` mesh,
/// min(N / 8, 150 / N) (validate() refuses more; at most 150 / 35 = 4.29,
/// at N = 35). Its interface elements follow its smallest semi-axis,
/// h = 4 pi a_min / N. Resolved: an element turns at most a quarter circle
/// along the sharpest curvature, radius a_min^2 / a_max (as a sphere's do
/// at the coarsest 8 equator nodes): a_max / a_min <= N / 8. Finished: gmsh's
/// curved (P2) meshing of an ellipsoid, a dilated sphere, slows steeply
/// with the nodes around its longest circumference, N a_max / a_min
/// (measured with `softflow mesh`, defaults otherwise, on 2 cores shared
/// with other work: 20-60 s at 120; 30-105 s at 150, oblate 3 at N = 50
/// with min quality 0.005, and one oblate 2.5 at N = 60 failing after
/// 107 s; at 160, 24-84 s and an oblate [0.25, 1, 1] at N = 40 failing
/// after 76 s; at 180 over 3 minutes; at 320 over 10; at 40,000,
/// [0.001, 1, 1], no end): at most 150.
double largest_ellipsoid_ratio(int equator_nodes);
inline constexpr double kMaxLongestCircumferenceNodes = 150.0;

/// The surface an object is, as a map of the unit sphere: x = centre + map u,
/// |u| = 1 (map = R diag(semi-axes) for an ObjectSpec; a linear deformation
/// F of the object about its centre makes it F map).
struct Ellipsoid {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d map = Eigen::Matrix3d::Identity();
};
Ellipsoid ellipsoid_of(const ObjectSpec& object);

/// The gap between an object and the wall y = side * H/2 (side = +1 the
/// upper wall, -1 the lower): H/2 - side * y_c - (the object's half extent in
/// y); negative when the object crosses the wall. `closest` receives the
/// object's point nearest that wall.
double wall_gap(const ObjectSpec& object, const mesh::Box& box, int side,
                Eigen::Vector3d* closest = nullptr);
double wall_gap(const Ellipsoid& object, const mesh::Box& box, int side,
                Eigen::Vector3d* closest = nullptr);

/// The element size across the gap g between an object and a wall when that
/// gap needs refining: g / n, n = sizing.elements_across_gaps(), when g is
/// narrower than n interface elements h0 (mesh.gap_elements given) or than
/// one (unset, the default). The mesher then sizes elements near the gap as
/// (d_wall + d_object) / (kGapSizeFactor n), the local gap width over the
/// count, on the object's surface too. +inf otherwise: no gap term, the mesh
/// of before the rule, to the bit.
double wall_gap_element_size(const ObjectSpec& object, const MeshSizing& sizing, double gap);

/// The narrowest distance between the surfaces of objects a and b as the spec
/// describes them (negative when they intersect): exact for two spheres, else
/// each surface sampled against the other (at the finer of a few thousand
/// points and the interface element size of `sizing`). validate() and the
/// size field's gap term judge pairs by it.
double object_gap(const ObjectSpec& a, const ObjectSpec& b, const MeshSizing& sizing);

/// The same rule for the gap g between two objects (after a remesh: drops
/// passing each other), with the smaller of their interface element sizes.
double object_gap_element_size(const ObjectSpec& a, const ObjectSpec& b, const MeshSizing& sizing,
                               double gap);

/// The mesher asks kGapSizeFactor * gap_elements elements across a narrow
/// object-wall gap, so that gap_elements are there by measure_wall_gap's
/// count (gap / mean edge of the tetrahedra its shortest segment crosses).
inline constexpr double kGapSizeFactor = 1.5;

/// Gap elements may be at most this many times smaller than the interface
/// elements: the smallest wall gap validate() accepts is
/// gap_elements h0 / kMaxGapRefinement (h0 the interface element size).
/// Measured (docs/confinement.md; beta = 0.4, L = W = 20 R): gmsh meshes
/// such gaps well at any refinement tried (min quality 0.19-0.31 down to a
/// gap of 0.01 R at 16 equator nodes, 157 times smaller elements), but the
/// mesh grows like R / gap, the gap's refinement soon outweighing the
/// interface's: 17k nodes at a gap of 0.15 R (the thesis's y_p0 = 0.27 H),
/// 43k at 0.05 R, 80k at 0.025 R, 191k at 0.01 R. 64 keeps a sphere's mesh
/// below about 100k nodes at 16-28 equator nodes.
inline constexpr double kMaxGapRefinement = 64.0;

/// gap_elements h0 / kMaxGapRefinement: the narrowest gap between `object`
/// and a wall the mesh resolves with `sizing`.
double smallest_wall_gap(const ObjectSpec& object, const MeshSizing& sizing);

/// The resolution of the gap between `object` and its nearer wall in `mesh`
/// (`object` = 0 in the result: the caller knows which it is).
WallGapResolution measure_wall_gap(const mesh::Mesh& mesh, const ObjectSpec& object);
WallGapResolution measure_wall_gap(const mesh::Mesh& mesh, const Ellipsoid& object);

/// The matrix tetrahedra the straight segment p -> q passes through and their
/// mean (straight) edge: the resolution of a gap spanned by the segment
/// (side and object 0; gap = |q - p|).
WallGapResolution measure_segment(const mesh::Mesh& mesh, const Eigen::Vector3d& p, const Eigen::Vector3d& q);

/// Checks the spec (objects inside the box, at least smallest_wall_gap from
/// the walls and from each other, one interface element from periodic faces,
/// ellipsoids the mesh resolves). Throws InputError naming the offending
/// object (1-based index, as in the case file), what is wrong and the keys
/// that change it.
void validate(const ShearCellSpec& spec);

/// The note printed when gmsh has meshed `spec` for `seconds`: what in the
/// spec makes meshing slow (an elongated ellipsoid, many objects under the
/// curved-element optimiser, a large mesh) and the keys that change it.
std::string slow_meshing_note(const ShearCellSpec& spec, double seconds);

/// Meshes the cell with gmsh (OCC): box fragmented with the objects,
/// periodic in x and/or z, P2 curved elements. Calls validate() first.
/// With sizing.point_symmetric_start, the mesh of symmetric_start(spec).
mesh::Mesh build_shear_cell(const ShearCellSpec& spec, MeshReport* report = nullptr);

/// For mesh.point_symmetric_start: the spec whose point-symmetric mesh is
/// carried to `spec`'s placement, its one object on the z axis (x = y = 0,
/// z kept). Expects a spec validate() accepted.
[[nodiscard]] ShearCellSpec symmetric_start(const ShearCellSpec& spec);

}  // namespace softflow::geometry
