// gmsh's side of the shear-cell meshers, internal to geometry/: the API
// session, the size field, periodicity, and reading the P2 mesh back.
// build_shear_cell (objects as OCC solids) and remesh (objects as their
// current interface triangulations) share it, so that a remeshed cell is
// graded, made periodic, numbered and oriented exactly as a fresh one.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "softflow/common/deterministic_heap.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/mesh.hpp"

namespace softflow::geometry::detail {

/// One gmsh API lifetime. gmsh 4.8 throws from inside OpenMP loops (e.g. a
/// bad mesh size while meshing curves), where nothing can catch it and the
/// process terminates. So errors are made non-fatal (AbortOnError = 0) and
/// the session polls gmsh's log for them after every stage instead.
/// gmsh runs inside a DeterministicHeapScope: its high-order optimiser orders
/// elements by address, and only there are those addresses the same in every
/// process (common/deterministic_heap.hpp).
class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  /// Runs one stage; gmsh's exceptions (std::string, const char*, int or
  /// std::exception in 4.8) and logged errors become MeshError.
  void run(const std::string& stage, const std::function<void()>& body);

 private:
  [[noreturn]] void fail(const std::string& stage, const std::string& what);
  std::string new_errors();
  DeterministicHeapScope heap_;  // open before gmsh::initialize, closed after gmsh::finalize
  std::size_t seen_ = 0;
};

/// The model entities the mesh is read from.
struct CellEntities {
  int matrix = -1;                                // volume tag
  std::vector<int> object_volume;                 // volume tag of object k (0-based)
  std::vector<std::vector<int>> object_surfaces;  // interface surfaces of object k
  std::array<std::vector<int>, 6> box_faces;      // indexed by BoundaryTag
  // mesh.point_symmetric: the half y >= 0 is meshed; its faces on the cut
  // plane y = 0, split at x = 0 (x < 0 pieces, then their mirror pieces).
  std::vector<int> cut_low, cut_high;
};

/// A point gmsh must make a vertex of region `region`'s mesh (0 the matrix,
/// k object k).
struct EmbeddedPoint {
  int region = 0;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
};

/// Meshes made again with points embedded against caps (cap_points), at most.
inline constexpr int kCapAttempts = 3;
/// Caps below this quality get a point below them (the moving mesh's
/// time.relocation_quality default, below which the remesher also relocates).
inline constexpr double kCapQuality = 0.2;

/// Points that break up the "caps" below `quality`: tetrahedra with all four
/// vertices on one interface, two interface triangles and the element
/// between them. Curved, a cap degenerates where its two interface faces
/// meet: both lie in the surface's tangent plane there, so det J of the P2
/// map goes to zero at the shared edge's ends, and only interface nodes
/// could move to save it. A vertex half an edge into the cap's region,
/// below the middle of its interface faces, makes gmsh mesh that place with
/// elements that reach into the region instead. Measured: a resampled
/// particle of 132 interface triangles (a cap at quality -0.003 inside it),
/// and random emulsions at phi = 0.2 (caps at -1 in the matrix, lying flat
/// on a drop).
[[nodiscard]] std::vector<EmbeddedPoint> cap_points(const mesh::Mesh& m, double quality);

/// The geometry kernel the model's entities were made with.
enum class Kernel { occ, built_in };

/// Adds `points` to the model and embeds each in its region's volume.
void embed_points(const CellEntities& e, const std::vector<EmbeddedPoint>& points, Kernel kernel);

/// A 4x4 affine translation, by rows (gmsh's setPeriodic).
std::vector<double> translation(double dx, double dy, double dz);

/// Slave = max face, master = min face; the affine map takes master to slave.
void set_periodicity(const mesh::Box& box, const CellEntities& e);

/// An object's current surface for the size field: the distance of a point
/// to it (and whether the point is inside), and its gap to each wall.
struct SurfaceDistance {
  std::function<double(const Eigen::Vector3d&, bool& inside)> distance;
  double gap_upper = 0.0, gap_lower = 0.0;
  /// The surface's nodes: the gaps to the other objects are measured from them.
  std::vector<Eigen::Vector3d> points;
  [[nodiscard]] double wall_gap(int side) const { return side > 0 ? gap_upper : gap_lower; }
};

/// The size callback (graded from the interfaces, optionally the walls and
/// narrow wall gaps, as MeshSizing says) and P2 order. `surfaces` empty: the
/// objects as the spec describes them; else one per object, the distance to
/// its current surface (the same formula, the same h0 and growths).
void set_size_and_order(const ShearCellSpec& spec, const std::vector<SurfaceDistance>& surfaces = {});

/// The element size that size callback gives at a point.
std::function<double(const Eigen::Vector3d&)> size_field(
    const ShearCellSpec& spec, const std::vector<SurfaceDistance>& surfaces = {});

/// The P2 tetrahedra of every volume (region 0 the matrix, k object k),
/// positively oriented in our node order; boundary faces (walls, and the x/z
/// faces that are not periodic) and interface faces oriented outwards; the
/// periodic node classes from gmsh's pairs (before any write of the mesh).
/// `cut_nodes` (mesh.point_symmetric: the half's nodes on the cut plane, for
/// complete_by_half_turn) instead of the periodic classes: the whole mesh's
/// are found from it, not from the half's.
mesh::Mesh read_mesh(const ShearCellSpec& spec, const CellEntities& e, std::vector<int>* cut_nodes = nullptr);

/// Throws MeshError unless every node differs from its periodic
/// representative by a lattice vector and every max-face node shares its
/// class with its image.
void verify_periodic(const mesh::Mesh& m);

/// The smallest element quality; throws MeshError on a folded curved element.
/// `optimized`: whether gmsh's high-order optimiser ran (the advice differs).
double check_quality(const mesh::Mesh& m, bool optimized);

}  // namespace softflow::geometry::detail
