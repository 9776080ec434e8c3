#include "softflow/geometry/remesh.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <utility>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <gmsh.h>

#include "softflow/common/error.hpp"
#include "softflow/geometry/gmsh_mesh.hpp"
#include "softflow/geometry/object_gaps.hpp"
#include "softflow/mesh/node_relocation.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/mesh/renumber.hpp"

namespace softflow::geometry {

using Eigen::Vector3d;
using mesh::BoundaryTag;

namespace {

constexpr int kGmshTriangle3 = 2;
/// Discrete interface surfaces get tags from here on, clear of the six
/// built-in-kernel box faces.
constexpr int kFirstInterfaceSurface = 1000;
/// Elements below this quality once the interfaces are curved again get
/// their free nodes relocated (the moving mesh's time.relocation_quality
/// default).
constexpr double kRelocationQuality = 0.2;

// ---------------------------------------------------------------------------
// Distance to an object's current surface, for the size field
// ---------------------------------------------------------------------------

// Closest point of triangle abc to p (Ericson, Real-Time Collision
// Detection, §5.1.5): by the Voronoi region of p over the vertices, edges
// and face.
Vector3d closest_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// A k-d tree of points for nearest-point queries (the size field asks for
// the distance to the interface at every point gmsh meshes: ~10^5-10^6
// queries, each O(log n) here instead of O(n)).
class PointTree {
 public:
  explicit PointTree(std::vector<Vector3d> points) : points_(std::move(points)), order_(points_.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    build(0, static_cast<int>(order_.size()), 0);
  }
  /// Index of a point closest to x.
  [[nodiscard]] int nearest(const Vector3d& x) const {
    int best = -1;
    double best_d2 = std::numeric_limits<double>::infinity();
    search(0, static_cast<int>(order_.size()), 0, x, best, best_d2);
    return best;
  }

 private:
  // Median split of order_[begin, end) along axis, recursively.
  void build(int begin, int end, int axis) {
    if (end - begin <= 1) return;
    const int mid = (begin + end) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) { return points_[a][axis] < points_[b][axis]; });
    build(begin, mid, (axis + 1) % 3);
    build(mid + 1, end, (axis + 1) % 3);
  }
  void search(int begin, int end, int axis, const Vector3d& x, int& best, double& best_d2) const {
    if (begin >= end) return;
    const int mid = (begin + end) / 2;
    const int i = order_[mid];
    const double d2 = (points_[i] - x).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
    const double offset = x[axis] - points_[i][axis];
    const int next = (axis + 1) % 3;
    if (offset < 0.0) {
      search(begin, mid, next, x, best, best_d2);
      if (offset * offset < best_d2) search(mid + 1, end, next, x, best, best_d2);
    } else {
      search(mid + 1, end, next, x, best, best_d2);
      if (offset * offset < best_d2) search(begin, mid, next, x, best, best_d2);
    }
  }

  std::vector<Vector3d> points_;
  std::vector<int> order_;
};

// One object's interface as straight triangles of its corner nodes: the
// distance of a point to it is the distance to the triangles around the
// nearest vertex (exact wherever the closest surface point lies on one of
// them; elsewhere within a fraction of an element, which only grades the
// sizes), and a point is inside where it lies behind the nearest vertex's
// outward (area-weighted) normal.
class InterfaceDistance {
 public:
  InterfaceDistance(const mesh::Mesh& m, int object) {
    std::map<int, int> local;  // mesh node -> vertex index
    for (std::size_t f = 0; f < m.interface_faces.size(); ++f) {
      if (m.interface_object[f] != object) continue;
      std::array<int, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const int node = m.interface_faces[f][k];
        const auto [it, added] = local.emplace(node, static_cast<int>(vertices_.size()));
        if (added) vertices_.push_back(m.nodes[node]);
        tri[k] = it->second;
      }
      triangles_.push_back(tri);
    }
    normals_.assign(vertices_.size(), Vector3d::Zero());
    around_.resize(vertices_.size());
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const auto& tri = triangles_[t];
      // Right-hand normal out of the object (mesh::Mesh's orientation), |n| = 2 area.
      const Vector3d n =
          (vertices_[tri[1]] - vertices_[tri[0]]).cross(vertices_[tri[2]] - vertices_[tri[0]]);
      for (int v : tri) {
        normals_[v] += n;
        around_[v].push_back(static_cast<int>(t));
      }
    }
    tree_ = std::make_shared<PointTree>(vertices_);
  }

  double operator()(const Vector3d& x, bool& inside) const {
    const int v = tree_->nearest(x);
    double best = std::numeric_limits<double>::infinity();
    for (int t : around_[v]) {
      const auto& tri = triangles_[t];
      const Vector3d q = closest_on_triangle(x, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]]);
      best = std::min(best, (x - q).norm());
    }
    inside = (x - vertices_[v]).dot(normals_[v]) < 0.0;
    return best;
  }

 private:
  std::vector<Vector3d> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Vector3d> normals_;
  std::vector<std::vector<int>> around_;
  std::shared_ptr<PointTree> tree_;  // shared: the size callback copies the functor
};

std::vector<detail::SurfaceDistance> surface_distances(const mesh::Mesh& m) {
  std::vector<detail::SurfaceDistance> out(m.n_objects);
  auto points = interface_points(m);
  for (int k = 0; k < m.n_objects; ++k) {
    double y_max = -std::numeric_limits<double>::infinity();
    double y_min = std::numeric_limits<double>::infinity();
    for (const Vector3d& x : points[k]) {
      y_max = std::max(y_max, x.y());
      y_min = std::min(y_min, x.y());
    }
    out[k].distance = InterfaceDistance(m, k + 1);
    out[k].gap_upper = m.box.height / 2 - y_max;
    out[k].gap_lower = m.box.height / 2 + y_min;
    out[k].points = std::move(points[k]);
  }
  return out;
}

// ---------------------------------------------------------------------------
// The model: box (built-in kernel) and interfaces (discrete surfaces)
// ---------------------------------------------------------------------------

// Where the box is now: the walls' nodes span it (the ALE translation d1
// moves every node along x, the box's faces too; nothing moves in y or z).
Vector3d box_origin(const mesh::Mesh& m) {
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (std::size_t f = 0; f < m.boundary_faces.size(); ++f)
    for (int node : m.boundary_faces[f]) lo = lo.cwiseMin(m.nodes[node]);
  if (!lo.allFinite()) throw MeshError("the mesh to remesh has no wall faces");
  return lo;
}

// Adds object k's interface (corner nodes and triangles) as discrete surface
// kFirstInterfaceSurface + k. gmsh's node tag of a mesh node is its index
// + 1, so that the new mesh's interface nodes are found again by tag.
int add_interface(const mesh::Mesh& m, int object, std::size_t& element_tag) {
  const int surface = kFirstInterfaceSurface + object;
  gmsh::model::addDiscreteEntity(2, surface);
  std::vector<std::size_t> node_tags, triangle_nodes, element_tags;
  std::vector<double> coordinates;
  std::vector<char> added(m.n_nodes(), 0);
  for (std::size_t f = 0; f < m.interface_faces.size(); ++f) {
    if (m.interface_object[f] != object) continue;
    for (int k = 0; k < 3; ++k) {
      const int node = m.interface_faces[f][k];
      triangle_nodes.push_back(static_cast<std::size_t>(node) + 1);
      if (added[node]) continue;
      added[node] = 1;
      node_tags.push_back(static_cast<std::size_t>(node) + 1);
      for (int d = 0; d < 3; ++d) coordinates.push_back(m.nodes[node][d]);
    }
    element_tags.push_back(++element_tag);
  }
  gmsh::model::mesh::addNodes(2, surface, node_tags, coordinates);
  gmsh::model::mesh::addElementsByType(surface, kGmshTriangle3, element_tags, triangle_nodes);
  return surface;
}

// The box [x0, x0 + L] x [-H/2, H/2] x [z0, z0 + W] in the built-in kernel,
// its faces recorded by BoundaryTag; then one volume for the matrix (the
// box less the objects) and one per object, bounded by their interfaces.
void add_box_and_volumes(const mesh::Box& b, const Vector3d& origin, const std::vector<int>& interfaces,
                         detail::CellEntities& e) {
  namespace geo = gmsh::model::geo;
  std::array<int, 8> corner{};  // index ix + 2 iy + 4 iz
  for (int i = 0; i < 8; ++i)
    corner[i] = geo::addPoint(origin.x() + (i & 1) * b.length, origin.y() + ((i >> 1) & 1) * b.height,
                              origin.z() + ((i >> 2) & 1) * b.width);
  std::map<std::pair<int, int>, int> lines;
  auto line = [&](int a, int c) {
    if (const auto it = lines.find({c, a}); it != lines.end()) return -it->second;
    if (const auto it = lines.find({a, c}); it != lines.end()) return it->second;
    return lines[{a, c}] = geo::addLine(a, c);
  };
  // A face of the corners i0..i3 (a cycle).
  auto face = [&](std::array<int, 4> i) {
    std::vector<int> loop;
    for (int k = 0; k < 4; ++k) loop.push_back(line(corner[i[k]], corner[i[(k + 1) % 4]]));
    return geo::addPlaneSurface({geo::addCurveLoop(loop)});
  };
  auto set = [&](BoundaryTag t, int surface) { e.box_faces[static_cast<int>(t)] = {surface}; };
  set(BoundaryTag::x_min, face({0, 2, 6, 4}));
  set(BoundaryTag::x_max, face({1, 3, 7, 5}));
  set(BoundaryTag::wall_bottom, face({0, 1, 5, 4}));
  set(BoundaryTag::wall_top, face({2, 3, 7, 6}));
  set(BoundaryTag::z_min, face({0, 1, 3, 2}));
  set(BoundaryTag::z_max, face({4, 5, 7, 6}));
  std::vector<int> box_faces;
  for (const auto& faces : e.box_faces) box_faces.push_back(faces.front());
  std::vector<int> matrix_shells{geo::addSurfaceLoop(box_faces)};
  for (int surface : interfaces) {
    const int shell = geo::addSurfaceLoop({surface});
    matrix_shells.push_back(shell);
    e.object_volume.push_back(geo::addVolume({shell}));
    e.object_surfaces.push_back({surface});
  }
  e.matrix = geo::addVolume(matrix_shells);
  geo::synchronize();
}

// ---------------------------------------------------------------------------
// The interfaces carried over
// ---------------------------------------------------------------------------

using Edge = std::pair<int, int>;
Edge edge(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// Each old interface edge (its two corner nodes) -> its mid-node.
std::map<Edge, int> interface_mid_nodes(const mesh::Mesh& m) {
  std::map<Edge, int> mid;
  for (const auto& tri : m.interface_faces)
    for (int k = 0; k < 3; ++k) {
      const auto& e = mesh::kTriangleEdges[k];
      mid[edge(tri[e[0]], tri[e[1]])] = tri[3 + k];
    }
  return mid;
}

// The old mesh's interface nodes, found by position: the new mesh's
// interface corner nodes are the old ones to the bit (gmsh keeps a discrete
// surface's nodes), and each interface edge's mid-node is the old one.
class OldInterfaces {
 public:
  explicit OldInterfaces(const mesh::Mesh& old) : old_(old), mid_(interface_mid_nodes(old)) {
    for (const auto& tri : old.interface_faces)
      for (int k = 0; k < 3; ++k) vertex_.emplace(key(old.nodes[tri[k]]), tri[k]);
  }
  /// The old interface vertex at x; MeshError if there is none.
  [[nodiscard]] int vertex_at(const Vector3d& x) const {
    const auto it = vertex_.find(key(x));
    if (it == vertex_.end())
      throw MeshError(fmt::format("remeshing moved an interface vertex (a new one at ({}, {}, {}))", x.x(), x.y(),
                                  x.z()));
    return it->second;
  }
  /// The old mid-node of the interface edge between old vertices a and b.
  [[nodiscard]] int mid_node(int a, int b) const {
    const auto it = mid_.find(edge(a, b));
    if (it == mid_.end()) throw MeshError("remeshing changed an interface triangulation (a new edge)");
    return it->second;
  }
  [[nodiscard]] const Vector3d& position(int node) const { return old_.nodes[node]; }

 private:
  static std::array<double, 3> key(const Vector3d& x) { return {x.x(), x.y(), x.z()}; }
  const mesh::Mesh& old_;
  std::map<Edge, int> mid_;
  std::map<std::array<double, 3>, int> vertex_;
};

// Puts each interface edge's mid-node of the new mesh back where the old
// mesh had it (gmsh elevates a discrete surface on the straight chords),
// after checking that the corners are the old ones to the bit, and returns
// new_node_of_old for every interface node.
std::vector<int> carry_interfaces_over(const mesh::Mesh& old, const OldInterfaces& interfaces, mesh::Mesh& m) {
  std::vector<int> new_node_of_old(old.n_nodes(), -1);
  for (const auto& tri : m.interface_faces) {
    std::array<int, 3> corner{};
    for (int k = 0; k < 3; ++k) new_node_of_old[corner[k] = interfaces.vertex_at(m.nodes[tri[k]])] = tri[k];
    for (int k = 0; k < 3; ++k) {
      const auto& e = mesh::kTriangleEdges[k];
      const int mid = interfaces.mid_node(corner[e[0]], corner[e[1]]);
      m.nodes[tri[3 + k]] = old.nodes[mid];
      new_node_of_old[mid] = tri[3 + k];
    }
  }
  return new_node_of_old;
}

// One remesh with gmsh's 3D algorithm `algorithm` (Mesh.Algorithm3D).
Remeshed remesh_with(const ShearCellSpec& spec, const mesh::Mesh& current, const OldInterfaces& old_interfaces,
                     int algorithm) {
  Remeshed out;
  mesh::Mesh& m = out.mesh;
  {
    detail::GmshSession session;
    detail::CellEntities entities;
    session.run("adding the interfaces and the box", [&] {
      std::size_t element_tag = 0;
      std::vector<int> interfaces;
      for (int k = 1; k <= current.n_objects; ++k) interfaces.push_back(add_interface(current, k, element_tag));
      add_box_and_volumes(spec.box, box_origin(current), interfaces, entities);
    });
    session.run("setting periodicity and mesh size", [&] {
      detail::set_periodicity(spec.box, entities);
      detail::set_size_and_order(spec, surface_distances(current));
    });
    session.run("remeshing", [algorithm] {
      gmsh::option::setNumber("Mesh.Algorithm3D", algorithm);
      // One thread: HXT's mesh depends on the thread count and schedule
      // otherwise, and a restart must remesh to the same mesh.
      gmsh::option::setNumber("General.NumThreads", 1);
      gmsh::option::setNumber("Mesh.MaxNumThreads3D", 1);
      gmsh::model::mesh::generate(3);
    });
    session.run("reading the mesh", [&] { m = detail::read_mesh(spec, entities); });
  }
  if (m.interface_faces.size() != current.interface_faces.size())
    throw MeshError(fmt::format("remeshing changed the interfaces: {} triangles, before {}",
                                m.interface_faces.size(), current.interface_faces.size()));
  out.new_node_of_old = carry_interfaces_over(current, old_interfaces, m);
  // gmsh shaped the elements along the straight chords; with the interface
  // curved again, an element with a face or an edge on it may fold where
  // the interface bends into it. Their free nodes are relocated as the
  // moving mesh does it (interface, boundary and periodic nodes stay).
  const mesh::NodeRelocation relocation(m);
  relocation.improve(m.nodes, kRelocationQuality);
  const std::vector<int> renumbered = mesh::renumber_nodes_spatially(m);
  for (int& node : out.new_node_of_old)
    if (node >= 0) node = renumbered[node];
  detail::verify_periodic(m);
  out.report.quality_after = mesh::min_quality(m);
  return out;
}

}  // namespace

Remeshed remesh(const ShearCellSpec& spec, const mesh::Mesh& current) {
  const auto start = std::chrono::steady_clock::now();
  if (current.n_objects != static_cast<int>(spec.objects.size()))
    throw InputError(fmt::format("remesh: the mesh has {} objects, the spec {}", current.n_objects,
                                 spec.objects.size()));
  const OldInterfaces old_interfaces(current);
  // gmsh's Delaunay first, the algorithm build_shear_cell meshes with: its
  // meshes have the fresh mesh's density (HXT's had 15-20 % fewer nodes for
  // the same size field, and a remeshed drop's D moved by 1.4 % at 20
  // equator nodes where Delaunay's moved it by 0.04 %). Around a discrete
  // interface it sometimes leaves a tetrahedron with all four vertices on
  // the interface, which the curved interface then folds (quality -0.001 to
  // -0.005 at 16-32 equator nodes, whatever the relocation does): below
  // kRelocationQuality HXT is tried too (it left none on the same meshes),
  // and the better mesh kept (measured in tests/unit/test_remesh.cpp).
  Remeshed best;
  std::string failure;
  for (int algorithm : {1, 10}) {
    try {
      Remeshed candidate = remesh_with(spec, current, old_interfaces, algorithm);
      candidate.report.algorithm = algorithm;
      if (best.mesh.tets.empty() || candidate.report.quality_after > best.report.quality_after)
        best = std::move(candidate);
    } catch (const MeshError& e) {
      failure = e.what();
    }
    if (!best.mesh.tets.empty() && best.report.quality_after >= kRelocationQuality) break;
  }
  if (best.mesh.tets.empty()) throw MeshError(failure);
  RemeshReport& r = best.report;
  r.nodes_before = current.n_nodes();
  r.tets_before = current.n_tets();
  r.quality_before = mesh::min_quality(current);
  r.interface_shape = mesh::min_interface_shape(current);
  r.nodes_after = best.mesh.n_nodes();
  r.tets_after = best.mesh.n_tets();
  r.quality_after = detail::check_quality(best.mesh, spec.sizing.optimize_high_order);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return best;
}

}  // namespace softflow::geometry
