// gmsh's side of the shear-cell meshers (internal to geometry/): one API
// session, the size field, periodicity and reading a P2 mesh back into a
// mesh::Mesh. Shared by build_shear_cell (OCC geometry) and remesh (the
// current interfaces as discrete surfaces), so both make meshes the same way.
#include "softflow/geometry/gmsh_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <gmsh.h>

#include "softflow/common/error.hpp"
#include "softflow/mesh/node_classes.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::geometry::detail {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using mesh::BoundaryTag;

namespace {
std::string num(double v) { return fmt::format("{:.6g}", v); }
std::string vec(const Vector3d& v) { return fmt::format("({}, {}, {})", num(v.x()), num(v.y()), num(v.z())); }
}  // namespace

// ---------------------------------------------------------------------------
// gmsh session
// ---------------------------------------------------------------------------

GmshSession::GmshSession() {
  try {
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::option::setNumber("General.Verbosity", 2);  // keep only errors and warnings in the log
    gmsh::logger::start();
    gmsh::model::add("shear_cell");
  } catch (...) {
    throw MeshError("gmsh could not be initialised");
  }
}

GmshSession::~GmshSession() {
  try {
    gmsh::logger::stop();
    gmsh::finalize();
  } catch (...) {  // a destructor must not throw; nothing useful to do
  }
}

void GmshSession::run(const std::string& stage, const std::function<void()>& body) {
  try {
    body();
  } catch (const Error&) {
    throw;
  } catch (const std::string& e) {
    fail(stage, e);
  } catch (const char* e) {
    fail(stage, e ? e : "");
  } catch (const std::exception& e) {
    fail(stage, e.what());
  } catch (int code) {
    fail(stage, fmt::format("error code {}", code));
  } catch (...) {
    fail(stage, "unknown exception");
  }
  const std::string errors = new_errors();
  if (!errors.empty()) throw MeshError(fmt::format("gmsh failed while {}: {}", stage, errors));
}

void GmshSession::fail(const std::string& stage, const std::string& what) {
  const std::string errors = new_errors();
  throw MeshError(
      fmt::format("gmsh failed while {}: {}{}{}", stage, what, errors.empty() ? "" : "; ", errors));
}

// Distinct error lines logged since the last call (at most three: a
// failing size field repeats the same error thousands of times).
std::string GmshSession::new_errors() {
  std::vector<std::string> log;
  try {
    gmsh::logger::get(log);
  } catch (...) {
    return {};
  }
  // The high-order optimiser reports the elements it could not lift above
  // its target (Mesh.HighOrderThresholdMin, a scaled Jacobian of 0.1) as
  // errors, yet keeps the mesh, valid or not: check_quality judges it
  // (inverted elements fail there, naming where). Dense emulsions (drops
  // 0.1 R apart) always leave a few such elements.
  auto optimiser_shortfall = [](const std::string& line) {
    return line.find("critical value") != std::string::npos;
  };
  std::vector<std::string> errors;
  for (std::size_t i = seen_; i < log.size() && errors.size() < 3; ++i)
    if (log[i].rfind("Error", 0) == 0 && !optimiser_shortfall(log[i]) &&
        std::find(errors.begin(), errors.end(), log[i]) == errors.end())
      errors.push_back(log[i]);
  seen_ = log.size();
  return fmt::format("{}", fmt::join(errors, "; "));
}

// ---------------------------------------------------------------------------
// Periodicity
// ---------------------------------------------------------------------------

std::vector<double> translation(double dx, double dy, double dz) {
  return {1, 0, 0, dx, 0, 1, 0, dy, 0, 0, 1, dz, 0, 0, 0, 1};  // 4x4 affine, by rows
}

// Slave = max face, master = min face; the affine map takes master to slave.
void set_periodicity(const mesh::Box& box, const CellEntities& e) {
  auto faces = [&](BoundaryTag t) { return e.box_faces[static_cast<int>(t)]; };
  if (box.periodic_x)
    gmsh::model::mesh::setPeriodic(2, faces(BoundaryTag::x_max), faces(BoundaryTag::x_min),
                                   translation(box.length, 0, 0));
  if (box.periodic_z)
    gmsh::model::mesh::setPeriodic(2, faces(BoundaryTag::z_max), faces(BoundaryTag::z_min),
                                   translation(0, 0, box.width));
}

// ---------------------------------------------------------------------------
// Size field
// ---------------------------------------------------------------------------

// Min(far_size, min_k (h0_k + g d_k)), g = growth outside object k and
// interior_growth inside it, d_k an approximate distance to object k's
// surface: |r - a| for a sphere, |rho - 1| * min semi-axis for an
// ellipsoid, rho the normalised radius in the body frame. Evaluated in C++
// through gmsh's size callback: as a MathEval expression its cost grew with
// the number of objects per query (50 objects: no mesh after 10 minutes);
// here 50 objects mesh in seconds. The arithmetic is the expression's,
// term by term, so meshes are unchanged.
//
// Two more terms, each only when asked for, so that the meshes of cases
// without them stay the same to the bit:
//  - walls (mesh.wall_size): wall_size + growth d_wall, d_wall = H/2 - |y|;
//  - a gap between object k and a wall that needs refining
//    (wall_gap_element_size): (d_wall + d_k) / gap_elements. In the
//    gap, d_wall + d_k is its local width (the gap's narrowest g at the
//    closest point, widening away from it), so the elements there follow the
//    gap, on the object's surface as well (d_k = 0: the size is the distance
//    to the wall over the count); away from the gap the term grows at most
//    at rate 2 / gap_elements and soon exceeds the others. The count is
//    asked kGapSizeFactor times over: gmsh's tetrahedra come out larger than
//    asked there (mean edge 1.32 x the size at the gap's narrowest point,
//    measured at 12 equator nodes and a gap of 0.15 R), so that the mean
//    edge of the tetrahedra the gap's shortest segment crosses
//    (measure_wall_gap) is at most gap / gap_elements.
//  - a gap between objects j and k that needs refining (the same rule,
//    object_gap_element_size): (d_j + d_k) / gap_elements, the local width of
//    the gap between their surfaces over the count (object_gap, or
//    surface_gap at a remesh, decides which pairs). Such gaps come from
//    dense emulsions and from drops passing each other; validate() refuses
//    pairs closer than smallest_wall_gap, as it refuses walls.
class SizeField {
 public:
  /// `surfaces` empty: the objects of the spec as they are described
  /// (analytic distances); else one per object, its current surface.
  SizeField(const ShearCellSpec& spec, const std::vector<SurfaceDistance>& surfaces)
      : far_(spec.sizing.far_size),
        half_height_(spec.box.height / 2),
        growth_(spec.sizing.growth),
        gap_divisor_(kGapSizeFactor * spec.sizing.elements_across_gaps()),
        wall_size_(spec.sizing.wall_size) {
    for (std::size_t k = 0; k < spec.objects.size(); ++k) {
      const ObjectSpec& o = spec.objects[k];
      Term t;
      for (int side : {1, -1}) {
        const double gap = surfaces.empty() ? wall_gap(o, spec.box, side) : surfaces[k].wall_gap(side);
        if (std::isfinite(wall_gap_element_size(o, spec.sizing, gap))) t.gap_walls.push_back(side);
      }
      if (!surfaces.empty()) t.surface = surfaces[k].distance;
      t.h0 = interface_element_size(o, spec.sizing);
      t.growth = spec.sizing.growth;
      t.interior_growth = spec.sizing.interior_growth.value_or(spec.sizing.growth);
      if (o.shape == ObjectShape::sphere) {
        t.sphere = true;
        t.rows = Matrix3d::Identity();
        t.offset = -o.centre;
        t.scale = o.semi_axes.x();
      } else {
        const Matrix3d to_body = rotation_matrix(o).transpose();
        for (int i = 0; i < 3; ++i) {
          t.rows.row(i) = to_body.row(i) / o.semi_axes[i];
          t.offset[i] = -t.rows.row(i).dot(o.centre);
        }
        t.scale = o.semi_axes.minCoeff();
      }
      terms_.push_back(t);
    }
    for (std::size_t j = 0; j < spec.objects.size(); ++j)
      for (std::size_t k = j + 1; k < spec.objects.size(); ++k) {
        const double gap = surfaces.empty() ? object_gap(spec.objects[j], spec.objects[k], spec.sizing)
                                            : surface_gap(surfaces[j], surfaces[k]);
        if (std::isfinite(object_gap_element_size(spec.objects[j], spec.objects[k], spec.sizing, gap)))
          gap_pairs_.push_back({static_cast<int>(j), static_cast<int>(k)});
      }
  }

  double operator()(double x, double y, double z) const {
    double size = far_;
    // Each object's distance, kept for the gaps between objects (none: no vector).
    thread_local std::vector<double> distances;
    if (!gap_pairs_.empty()) distances.resize(terms_.size());
    for (std::size_t k = 0; k < terms_.size(); ++k) {
      const Term& t = terms_[k];
      bool inside = false;
      const double distance =
          t.surface ? t.surface(Vector3d(x, y, z), inside) : described_distance(t, x, y, z, inside);
      size = std::min(size, t.h0 + (inside ? t.interior_growth : t.growth) * distance);
      for (int side : t.gap_walls)
        size = std::min(size, (half_height_ - side * y + distance) / gap_divisor_);
      if (!gap_pairs_.empty()) distances[k] = distance;
    }
    for (const auto& [j, k] : gap_pairs_) size = std::min(size, (distances[j] + distances[k]) / gap_divisor_);
    if (wall_size_) size = std::min(size, *wall_size_ + growth_ * (half_height_ - std::abs(y)));
    return size;
  }

 private:
  struct Term {
    bool sphere = false;
    Matrix3d rows = Matrix3d::Identity();  ///< x -> rows x + offset: centred (sphere) or body, normalised
    Vector3d offset = Vector3d::Zero();
    double scale = 1.0;                    ///< sphere: radius; ellipsoid: min semi-axis
    double h0 = 0.0, growth = 0.0, interior_growth = 0.0;
    std::vector<int> gap_walls;  ///< sides (+1 upper, -1 lower) of walls too close for h0
    /// The current surface's distance instead of the analytic one (remesh).
    std::function<double(const Vector3d&, bool&)> surface;
  };

  // The distance to the object as the spec describes it: |r - a| for a
  // sphere, |rho - 1| * min semi-axis for an ellipsoid.
  static double described_distance(const Term& t, double x, double y, double z, bool& inside) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      // c0 x + c1 y + c2 z + c3, left to right, zero coefficients skipped.
      double v = 0.0;
      bool any = false;
      const double c[3] = {t.rows(i, 0), t.rows(i, 1), t.rows(i, 2)};
      const double p[3] = {x, y, z};
      for (int j = 0; j < 3; ++j)
        if (c[j] != 0.0) {
          v = any ? v + c[j] * p[j] : c[j] * p[j];
          any = true;
        }
      if (t.offset[i] != 0.0) v = any ? v + t.offset[i] : t.offset[i];
      sum += v * v;
    }
    const double r = std::sqrt(sum);
    inside = r < (t.sphere ? t.scale : 1.0);
    return t.sphere ? std::abs(r - t.scale) : std::abs(r - 1.0) * t.scale;
  }

  // The narrowest distance between two current surfaces (a remesh): j's nodes
  // against k's distance (object_gap is the described objects').
  static double surface_gap(const SurfaceDistance& j, const SurfaceDistance& k) {
    double gap = std::numeric_limits<double>::infinity();
    for (const Vector3d& p : j.points) {
      bool inside = false;
      const double d = k.distance(p, inside);
      gap = std::min(gap, inside ? 0.0 : d);
    }
    return gap;
  }

  double far_;
  double half_height_;
  double growth_;
  double gap_divisor_;  ///< kGapSizeFactor * gap_elements
  std::optional<double> wall_size_;
  std::vector<Term> terms_;
  std::vector<std::pair<int, int>> gap_pairs_;  ///< objects whose gap needs refining
};

std::function<double(const Vector3d&)> size_field(const ShearCellSpec& spec,
                                                  const std::vector<SurfaceDistance>& surfaces) {
  return
      [field = SizeField(spec, surfaces)](const Vector3d& x) { return field(x.x(), x.y(), x.z()); };
}

void set_size_and_order(const ShearCellSpec& spec, const std::vector<SurfaceDistance>& surfaces) {
  gmsh::model::mesh::setSizeCallback([field = SizeField(spec, surfaces)](int, int, double x, double y,
                                                                         double z) { return field(x, y, z); });
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::option::setNumber("Mesh.MeshSizeMax", spec.sizing.far_size);
  // Order and optimisation go through generate(): in 4.8 the high-order
  // optimiser only runs there (model::mesh::setOrder() never calls it).
  // Level 2 (elastic + optimisation) may throw; level 1 suffices.
  gmsh::option::setNumber("Mesh.ElementOrder", 2);
  gmsh::option::setNumber("Mesh.HighOrderOptimize", spec.sizing.optimize_high_order ? 1 : 0);
  // The optimiser moves edge nodes on the periodic faces (by up to ~1e-5
  // here); re-placing them by the periodicity transform afterwards keeps
  // the faces exact copies. The default (0, "identical parametrisations")
  // leaves the slave copies off by that much.
  gmsh::option::setNumber("Mesh.HighOrderPeriodic", 2);
}

// ---------------------------------------------------------------------------
// Mesh extraction
// ---------------------------------------------------------------------------

constexpr int kGmshTet10 = 11;
constexpr int kGmshTriangle6 = 9;

// perm[ours] = gmsh's local index, found from gmsh's reference coordinates
// (gmsh's Tet10 puts (2,3) before (1,3); ours is VTK's order).
template <std::size_t n_edges>
std::vector<int> node_permutation(int type, const std::array<std::array<int, 2>, n_edges>& edges) {
  std::string name;
  int dim = 0, order = 0, n_nodes = 0, n_primary = 0;
  std::vector<double> ref;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, n_nodes, ref, n_primary);
  const int n_vertices = dim + 1;
  if (n_nodes != n_vertices + static_cast<int>(n_edges) || n_primary != n_vertices)
    throw MeshError(fmt::format("gmsh element type {} ({}) is not the expected P2 element", type, name));
  auto at = [&](int node) {
    Vector3d x = Vector3d::Zero();
    for (int d = 0; d < dim; ++d) x[d] = ref[dim * node + d];
    return x;
  };
  std::vector<int> perm(n_nodes);
  for (int v = 0; v < n_vertices; ++v) perm[v] = v;
  for (std::size_t e = 0; e < n_edges; ++e) {
    const Vector3d mid = 0.5 * (at(edges[e][0]) + at(edges[e][1]));
    int found = -1;
    for (int node = n_vertices; node < n_nodes; ++node)
      if ((at(node) - mid).norm() < 1e-12) found = node;
    if (found < 0) throw MeshError(fmt::format("gmsh element {} has no node at an edge midpoint", name));
    perm[n_vertices + e] = found;
  }
  return perm;
}

// gmsh node tags -> compact 0-based indices of the nodes the tetrahedra use.
class NodeTable {
 public:
  void mark(std::size_t tag) {
    if (tag >= index_.size()) index_.resize(tag + 1, -1);
    index_[tag] = 0;
  }
  // Numbers the marked nodes in increasing tag order and copies their coordinates.
  void number(mesh::Mesh& m) {
    std::vector<std::size_t> tags;
    std::vector<double> coord, param;
    gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, false, false);
    std::vector<int> position(index_.size(), -1);
    for (std::size_t i = 0; i < tags.size(); ++i)
      if (tags[i] < position.size()) position[tags[i]] = static_cast<int>(i);
    for (std::size_t tag = 0; tag < index_.size(); ++tag) {
      if (index_[tag] < 0) continue;
      const int p = position[tag];
      if (p < 0) throw MeshError(fmt::format("gmsh node {} has no coordinates", tag));
      index_[tag] = m.n_nodes();
      m.nodes.emplace_back(coord[3 * p], coord[3 * p + 1], coord[3 * p + 2]);
      m.is_vertex.push_back(0);
    }
  }
  // Compact index of a tag, -1 if no tetrahedron uses it.
  [[nodiscard]] int operator()(std::size_t tag) const { return tag < index_.size() ? index_[tag] : -1; }

 private:
  std::vector<int> index_;
};

// Swaps vertices 1 and 2 and the edge nodes with them.
mesh::Tet10 flipped(const mesh::Tet10& t) {
  return {t[0], t[2], t[1], t[3], t[6], t[5], t[4], t[7], t[9], t[8]};
}
mesh::Triangle6 flipped(const mesh::Triangle6& t) { return {t[0], t[2], t[1], t[5], t[4], t[3]}; }

double vertex_volume6(const mesh::Mesh& m, const mesh::Tet10& t) {
  const auto& x = m.nodes;
  return (x[t[1]] - x[t[0]]).dot((x[t[2]] - x[t[0]]).cross(x[t[3]] - x[t[0]]));
}

// Tetrahedra of every volume, in our node order and positively oriented.
void read_tets(mesh::Mesh& m, const CellEntities& e, NodeTable& nodes) {
  const std::vector<int> perm = node_permutation(kGmshTet10, mesh::kTetEdges);
  std::vector<std::pair<int, std::vector<std::size_t>>> blocks;  // (region, gmsh node tags)
  for (int region = 0; region <= static_cast<int>(e.object_volume.size()); ++region) {
    std::vector<std::size_t> element_tags, node_tags;
    const int volume = region == 0 ? e.matrix : e.object_volume[region - 1];
    gmsh::model::mesh::getElementsByType(kGmshTet10, element_tags, node_tags, volume);
    if (element_tags.empty())
      throw MeshError(fmt::format("gmsh produced no tetrahedra in region {}", region));
    for (std::size_t tag : node_tags) nodes.mark(tag);
    blocks.emplace_back(region, std::move(node_tags));
  }
  nodes.number(m);
  for (const auto& [region, tags] : blocks)
    for (std::size_t first = 0; first < tags.size(); first += 10) {
      mesh::Tet10 t{};
      for (int k = 0; k < 10; ++k) t[k] = nodes(tags[first + perm[k]]);
      if (vertex_volume6(m, t) < 0.0) t = flipped(t);
      for (int k = 0; k < 4; ++k) m.is_vertex[t[k]] = 1;
      m.tets.push_back(t);
      m.tet_region.push_back(region);
    }
}

std::vector<mesh::Triangle6> read_triangles(int surface, const std::vector<int>& perm,
                                            const NodeTable& nodes) {
  std::vector<std::size_t> element_tags, node_tags;
  gmsh::model::mesh::getElementsByType(kGmshTriangle6, element_tags, node_tags, surface);
  std::vector<mesh::Triangle6> out(element_tags.size());
  for (std::size_t f = 0; f < out.size(); ++f)
    for (int k = 0; k < 6; ++k) {
      out[f][k] = nodes(node_tags[6 * f + perm[k]]);
      if (out[f][k] < 0) throw MeshError(fmt::format("surface {} has a node no tetrahedron uses", surface));
    }
  return out;
}

void read_faces(mesh::Mesh& m, const CellEntities& e, const mesh::Box& box, const NodeTable& nodes) {
  const std::vector<int> perm = node_permutation(kGmshTriangle6, mesh::kTriangleEdges);
  for (int tag = 0; tag < 6; ++tag) {
    const auto t = static_cast<BoundaryTag>(tag);
    if ((box.periodic_x && (t == BoundaryTag::x_min || t == BoundaryTag::x_max)) ||
        (box.periodic_z && (t == BoundaryTag::z_min || t == BoundaryTag::z_max)))
      continue;  // periodic faces are interior to the periodic domain
    for (int surface : e.box_faces[tag])
      for (const auto& f : read_triangles(surface, perm, nodes)) {
        m.boundary_faces.push_back(f);
        m.boundary_face_tag.push_back(t);
      }
  }
  for (std::size_t k = 0; k < e.object_surfaces.size(); ++k)
    for (int surface : e.object_surfaces[k])
      for (const auto& f : read_triangles(surface, perm, nodes)) {
        m.interface_faces.push_back(f);
        m.interface_object.push_back(static_cast<int>(k) + 1);
      }
}

struct FaceKeyHash {
  std::size_t operator()(const std::array<int, 3>& k) const {
    std::size_t h = 0;
    for (int v : k) h = h * 1000003u ^ static_cast<std::size_t>(v);
    return h;
  }
};

std::array<int, 3> face_key(int a, int b, int c) {
  std::array<int, 3> k{a, b, c};
  std::sort(k.begin(), k.end());
  return k;
}

// Orients each face so that its right-hand normal points away from its
// adjacent tetrahedron of region `inside(face)`: out of the object for
// interfaces, out of the domain for the box. The opposite vertex of a
// positively oriented tetrahedron decides, which works for any shape.
void orient_faces(const mesh::Mesh& m, std::vector<mesh::Triangle6>& faces,
                  const std::function<int(std::size_t)>& inside) {
  std::unordered_map<std::array<int, 3>, std::size_t, FaceKeyHash> index;
  index.reserve(2 * faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    index.emplace(face_key(faces[f][0], faces[f][1], faces[f][2]), f);
  std::vector<int> opposite(faces.size(), -1);
  constexpr int kFaces[4][4] = {
      {1, 2, 3, 0}, {0, 2, 3, 1}, {0, 1, 3, 2}, {0, 1, 2, 3}};  // 3 on the face, 1 off
  for (int t = 0; t < m.n_tets(); ++t)
    for (const auto& lf : kFaces) {
      const auto& tet = m.tets[t];
      const auto it = index.find(face_key(tet[lf[0]], tet[lf[1]], tet[lf[2]]));
      if (it != index.end() && m.tet_region[t] == inside(it->second)) opposite[it->second] = tet[lf[3]];
    }
  for (std::size_t f = 0; f < faces.size(); ++f) {
    if (opposite[f] < 0) throw MeshError("a surface triangle has no adjacent tetrahedron on its inner side");
    const auto& x = m.nodes;
    const auto& tri = faces[f];
    const Vector3d normal = (x[tri[1]] - x[tri[0]]).cross(x[tri[2]] - x[tri[0]]);
    if (normal.dot(x[opposite[f]] - x[tri[0]]) > 0.0) faces[f] = flipped(tri);
  }
}

// Periodic node classes from gmsh's slave -> master pairs on points, curves
// and surfaces (high-order nodes included). Corner edges of a doubly
// periodic box have 4 copies, linked by pairs through different entities:
// the union-find collapses them. Must run before any write/read of the mesh.
void read_periodic(mesh::Mesh& m, const NodeTable& nodes) {
  if (!m.box.periodic_x && !m.box.periodic_z) return;
  mesh::NodeClasses classes(m.n_nodes());
  for (int dim = 0; dim <= 2; ++dim) {
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities, dim);
    for (const auto& [d, tag] : entities) {
      int master_entity = tag;
      std::vector<std::size_t> slaves, masters;
      std::vector<double> affine;
      gmsh::model::mesh::getPeriodicNodes(dim, tag, master_entity, slaves, masters, affine, true);
      for (std::size_t i = 0; i < slaves.size(); ++i) {
        const int a = nodes(slaves[i]), b = nodes(masters[i]);
        if (a < 0 || b < 0) throw MeshError("a periodic node pair refers to a node no tetrahedron uses");
        classes.unite(a, b);
      }
    }
  }
  m.periodic_master.resize(m.n_nodes());
  for (int i = 0; i < m.n_nodes(); ++i) m.periodic_master[i] = classes.find(i);
}

mesh::Mesh read_mesh(const ShearCellSpec& spec, const CellEntities& e, std::vector<int>* cut_nodes) {
  mesh::Mesh m;
  m.box = spec.box;
  m.n_objects = static_cast<int>(spec.objects.size());
  NodeTable nodes;
  read_tets(m, e, nodes);
  read_faces(m, e, spec.box, nodes);
  orient_faces(m, m.boundary_faces, [](std::size_t) { return 0; });
  orient_faces(m, m.interface_faces, [&m](std::size_t f) { return m.interface_object[f]; });
  if (!cut_nodes) {
    read_periodic(m, nodes);
    return m;
  }
  std::set<int> on_plane;
  for (const auto& faces : {e.cut_low, e.cut_high})
    for (int surface : faces) {
      std::vector<std::size_t> tags;
      std::vector<double> coord, param;
      gmsh::model::mesh::getNodes(tags, coord, param, 2, surface, /*includeBoundary=*/true, false);
      for (std::size_t tag : tags) {
        const int node = nodes(tag);
        if (node < 0) throw MeshError("a node of the cut plane belongs to no tetrahedron");
        on_plane.insert(node);
      }
    }
  cut_nodes->assign(on_plane.begin(), on_plane.end());
  return m;
}

// ---------------------------------------------------------------------------
// Checks
// ---------------------------------------------------------------------------

// Every node must differ from its representative by a lattice vector
// (k L, 0, k' W), and every node on a periodic max face must share its class
// with its image on the min face: anything else would silently break the
// periodic dof identification.
void verify_periodic(const mesh::Mesh& m) {
  if (m.periodic_master.empty()) return;
  const mesh::Box& b = m.box;
  const double tol = 1e-9 * std::max({b.length, b.height, b.width});
  auto off_lattice = [](double d, double period, bool periodic) {
    return periodic ? std::abs(d - period * std::round(d / period)) : std::abs(d);
  };
  std::unordered_map<int, std::vector<int>> members;
  for (int i = 0; i < m.n_nodes(); ++i) {
    const int j = m.periodic_master[i];
    const Vector3d d = m.nodes[i] - m.nodes[j];
    const double error = std::max({off_lattice(d.x(), b.length, b.periodic_x), std::abs(d.y()),
                                   off_lattice(d.z(), b.width, b.periodic_z)});
    if (error > tol)
      throw MeshError(
          fmt::format("periodic nodes {} at {} and {} at {} do not differ by a lattice vector (error {})", i,
                      vec(m.nodes[i]), j, vec(m.nodes[j]), num(error)));
    if (j != i) members[j].push_back(i);
  }
  auto has_image = [&](int i, const Vector3d& shift) {
    const Vector3d image = m.nodes[i] - shift;
    const int rep = m.periodic_master[i];
    if ((m.nodes[rep] - image).norm() < tol) return true;
    const auto it = members.find(rep);
    return it != members.end() && std::any_of(it->second.begin(), it->second.end(),
                                              [&](int j) { return (m.nodes[j] - image).norm() < tol; });
  };
  for (int i = 0; i < m.n_nodes(); ++i) {
    const bool x_ok = !b.periodic_x || std::abs(m.nodes[i].x() - b.length / 2) >= tol ||
                      has_image(i, Vector3d(b.length, 0, 0));
    const bool z_ok = !b.periodic_z || std::abs(m.nodes[i].z() - b.width / 2) >= tol ||
                      has_image(i, Vector3d(0, 0, b.width));
    if (!x_ok || !z_ok)
      throw MeshError(fmt::format("node {} at {} on a periodic face is not identified with its image", i,
                                  vec(m.nodes[i])));
  }
}

// ---------------------------------------------------------------------------
// Caps
// ---------------------------------------------------------------------------

std::vector<EmbeddedPoint> cap_points(const mesh::Mesh& m, double quality) {
  std::vector<char> on_interface(m.n_nodes(), 0);
  std::map<std::array<int, 3>, Vector3d>
      face_normal;  // sorted corners -> outward (from the object) normal
  for (const auto& f : m.interface_faces) {
    for (int k = 0; k < 3; ++k) on_interface[f[k]] = 1;
    std::array<int, 3> key{f[0], f[1], f[2]};
    std::sort(key.begin(), key.end());
    face_normal[key] = (m.nodes[f[1]] - m.nodes[f[0]]).cross(m.nodes[f[2]] - m.nodes[f[0]]);
  }
  std::vector<EmbeddedPoint> points;
  for (int t = 0; t < m.n_tets(); ++t) {
    const auto& tet = m.tets[t];
    if (!(on_interface[tet[0]] && on_interface[tet[1]] && on_interface[tet[2]] &&
          on_interface[tet[3]]))
      continue;
    if (mesh::tet_quality(m, t) >= quality) continue;
    Vector3d centre = Vector3d::Zero(), normal = Vector3d::Zero();
    double edges = 0.0;
    for (int a = 0; a < 4; ++a) {
      centre += m.nodes[tet[a]] / 4.0;
      for (int b = a + 1; b < 4; ++b) edges += (m.nodes[tet[a]] - m.nodes[tet[b]]).norm() / 6.0;
      std::array<int, 3> key{};
      for (int c = 0, j = 0; c < 4; ++c)
        if (c != a) key[j++] = tet[c];
      std::sort(key.begin(), key.end());
      if (const auto it = face_normal.find(key); it != face_normal.end())
        normal += it->second.normalized();
    }
    if (normal.norm() == 0.0) continue;  // no face on an interface: not a cap
    // Into the element's region: against the outward normal inside an
    // object, along it in the matrix.
    const double into = m.tet_region[t] == 0 ? 1.0 : -1.0;
    points.push_back({m.tet_region[t], centre + into * 0.5 * edges * normal.normalized()});
  }
  return points;
}

void embed_points(const CellEntities& e, const std::vector<EmbeddedPoint>& points, Kernel kernel) {
  std::vector<std::pair<int, int>> added;  // (gmsh point, volume)
  for (const EmbeddedPoint& p : points) {
    const int volume = p.region == 0 ? e.matrix : e.object_volume.at(p.region - 1);
    added.emplace_back(kernel == Kernel::occ
                           ? gmsh::model::occ::addPoint(p.x.x(), p.x.y(), p.x.z())
                           : gmsh::model::geo::addPoint(p.x.x(), p.x.y(), p.x.z()),
                       volume);
  }
  if (kernel == Kernel::occ)
    gmsh::model::occ::synchronize();
  else
    gmsh::model::geo::synchronize();
  for (const auto& [point, volume] : added) gmsh::model::mesh::embed(0, {point}, 3, volume);
}

// Throws if a curved element folds (non-positive Jacobian at a sample point).
// `optimized`: whether gmsh's high-order optimiser ran (the advice differs).
double check_quality(const mesh::Mesh& m, bool optimized) {
  const int worst = mesh::worst_tet(m);
  if (worst < 0) return 1.0;
  const double q = mesh::tet_quality(m, worst);
  if (q <= 0.0) {
    Vector3d centroid = Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centroid += 0.25 * m.nodes[m.tets[worst][k]];
    throw MeshError(
        fmt::format("gmsh produced an inverted curved tetrahedron near {} (quality {}){}",
                    vec(centroid), num(q),
                    optimized ? " although its high-order optimiser ran; refine the interface "
                                "(mesh.equator_nodes) or grade the mesh more gently (mesh.growth)"
                              : "; set mesh.optimize_high_order = true or refine the interface "
                                "(mesh.equator_nodes)"));
  }
  return q;
}


}  // namespace softflow::geometry::detail
