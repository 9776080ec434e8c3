#include "softflow/geometry/shear_cell.hpp"
#include "softflow/geometry/point_symmetric_mesh.hpp"
#include "softflow/mesh/fingerprint.hpp"
#include "softflow/mesh/renumber.hpp"

#include <algorithm>
#include <set>
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <thread>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <gmsh.h>

#include "softflow/common/deterministic_heap.hpp"
#include "softflow/common/error.hpp"
#include "softflow/mesh/quality.hpp"

namespace softflow::geometry {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using mesh::BoundaryTag;

Matrix3d rotation_matrix(const ObjectSpec& object) {
  const Vector3d a = object.rotation_deg * (M_PI / 180.0);
  return (Eigen::AngleAxisd(a.z(), Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Vector3d::UnitY()) *
          Eigen::AngleAxisd(a.x(), Vector3d::UnitX()))
      .toRotationMatrix();
}

double interface_element_size(const ObjectSpec& object, const MeshSizing& sizing) {
  return 2.0 * M_PI * object.semi_axes.minCoeff() / (0.5 * sizing.equator_nodes);
}

// ---------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------

namespace {

std::string num(double v) { return fmt::format("{:.6g}", v); }
std::string vec(const Vector3d& v) { return fmt::format("({}, {}, {})", num(v.x()), num(v.y()), num(v.z())); }
std::string label(int k) { return fmt::format("objects[{}]", k + 1); }  // 1-based, as in the case file

std::string describe(const ObjectSpec& o) {
  if (o.shape == ObjectShape::sphere)
    return fmt::format("sphere at {} with radius {}", vec(o.centre), num(o.semi_axes.x()));
  return fmt::format("ellipsoid at {} with semi-axes {}", vec(o.centre), vec(o.semi_axes));
}

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

void validate_box(const mesh::Box& box) {
  const std::array<std::pair<const char*, double>, 3> fields{
      {{"length", box.length}, {"height", box.height}, {"width", box.width}}};
  for (const auto& [name, value] : fields)
    if (!positive(value)) throw InputError(fmt::format("box.{} = {}: must be > 0", name, num(value)));
}

void validate_sizing(const MeshSizing& s) {
  if (s.equator_nodes < 8)
    throw InputError(fmt::format("mesh.equator_nodes = {}: must be an integer ≥ 8", s.equator_nodes));
  if (!positive(s.far_size))
    throw InputError(fmt::format("mesh.far_size = {}: must be > 0", num(s.far_size)));
  if (!positive(s.growth)) throw InputError(fmt::format("mesh.growth = {}: must be > 0", num(s.growth)));
  if (s.interior_growth && !(*s.interior_growth >= 0.0 && std::isfinite(*s.interior_growth)))
    throw InputError(fmt::format("mesh.interior_growth = {}: must be >= 0", num(*s.interior_growth)));
  if (s.wall_size && !positive(*s.wall_size))
    throw InputError(fmt::format("mesh.wall_size = {}: must be > 0", num(*s.wall_size)));
  if (s.gap_elements && *s.gap_elements < 1)
    throw InputError(fmt::format("mesh.gap_elements = {}: must be an integer >= 1", *s.gap_elements));
}

void validate_shape(int k, const ObjectSpec& o) {
  if (!o.centre.allFinite())
    throw InputError(fmt::format("{}.centre = {}: must be finite", label(k), vec(o.centre)));
  if (!positive(o.semi_axes.minCoeff()) || !o.semi_axes.allFinite())
    throw InputError(
        fmt::format("{}.semi_axes = {}: every semi-axis must be > 0", label(k), vec(o.semi_axes)));
  if (!o.rotation_deg.allFinite())
    throw InputError(fmt::format("{}.rotation = {}: must be finite", label(k), vec(o.rotation_deg)));
  if (o.shape == ObjectShape::sphere && o.semi_axes.maxCoeff() != o.semi_axes.minCoeff())
    throw InputError(fmt::format("{}.semi_axes = {}: a sphere has three equal semi-axes; use an ellipsoid",
                                 label(k), vec(o.semi_axes)));
}

// Half-widths of the object's axis-aligned bounding box: the ellipsoid
// x = c + R A u, |u| = 1, reaches sqrt(sum_j (R_ij a_j)^2) along axis i.
Vector3d half_extents(const ObjectSpec& o) {
  const Matrix3d m = rotation_matrix(o) * o.semi_axes.asDiagonal();
  return m.rowwise().norm();
}

// The object must stay at least one interface element away from the faces
// normal to `axis` (x or z; the walls have check_wall): closer, gmsh would
// need elements smaller than h there, and an object cut by a periodic face
// cannot be meshed as one region.
void check_axis(int k, const ObjectSpec& o, const mesh::Box& box, int axis, double h) {
  const double half = 0.5 * std::array{box.length, box.height, box.width}[axis];
  const bool periodic = (axis == 0 && box.periodic_x) || (axis == 2 && box.periodic_z);
  const char x = "xyz"[axis];
  const char* half_name = std::array{"L/2", "H/2", "W/2"}[axis];
  const double c = o.centre[axis], extent = half_extents(o)[axis];
  const double allowed = half - h;
  if (std::abs(c) + extent <= allowed) return;

  const bool upper = c >= 0.0;
  const double face = upper ? half : -half, reach = upper ? c + extent : c - extent;
  const std::string what = axis == 1 ? "the wall" : periodic ? "the periodic face" : "the face";
  const std::string rule =
      fmt::format("allowed: |{}_c| + extent ≤ {} − h = {} (h = {}, the interface element size)", x, half_name,
                  num(allowed), num(h));
  if (std::abs(reach) >= half)
    throw InputError(
        fmt::format("{}: {} crosses {} {} = {} (it reaches {} = {}); {}; move it or make it smaller",
                    label(k), describe(o), what, x, num(face), x, num(reach), rule));
  throw InputError(
      fmt::format("{}: {} is too close to {} {} = {} (gap {} < h = {}); {}; move it or make it smaller",
                  label(k), describe(o), what, x, num(face), num(half - std::abs(reach)), num(h), rule));
}

// The walls y = +-H/2: an object may come as close as the mesh resolves with
// mesh.gap_elements elements across the gap (smallest_wall_gap); the mesher
// then sizes the gap's elements by its width (wall_gap_element_size).
void check_wall(int k, const ObjectSpec& o, const mesh::Box& box, const MeshSizing& sizing) {
  const double smallest = smallest_wall_gap(o, sizing);
  for (int side : {1, -1}) {
    const double gap = wall_gap(o, box, side);
    if (gap >= smallest) continue;
    const double wall = side * box.height / 2;
    const double extent = half_extents(o).y();
    const std::string rule = fmt::format(
        "allowed: |y_c| + extent ≤ H/2 − g_min = {} with g_min = mesh.gap_elements h / {:g} = {} "
        "(mesh.gap_elements = {} elements across the gap, each at most {:g} times smaller than "
        "the interface element h = {} of mesh.equator_nodes = {})",
        num(box.height / 2 - smallest), kMaxGapRefinement, num(smallest), sizing.elements_across_gaps(),
        kMaxGapRefinement, num(interface_element_size(o, sizing)), sizing.equator_nodes);
    if (gap <= 0.0)
      throw InputError(fmt::format(
          "{}: {} crosses the wall y = {} (it reaches y = {}); {}; move it ({}.centre), make it "
          "smaller, or make the cell higher (cell.height or cell.blockage_ratio)",
          label(k), describe(o), num(wall), num(o.centre.y() + side * extent), rule, label(k)));
    // The fewest equator nodes that resolve this gap: h0 = 4 pi a_min / N.
    const double needed = std::ceil(4.0 * M_PI * o.semi_axes.minCoeff() * sizing.elements_across_gaps() /
                                    (kMaxGapRefinement * gap) - 1e-9);
    throw InputError(fmt::format(
        "{}: {} is too close to the wall y = {} (gap {} < g_min = {}, the narrowest gap the mesh "
        "resolves); {}; move it ({}.centre), make it smaller, make the cell higher (cell.height "
        "or cell.blockage_ratio), or refine the interface (mesh.equator_nodes ≥ {:.0f} for this "
        "gap) or ask fewer elements across (mesh.gap_elements)",
        label(k), describe(o), num(wall), num(gap), num(smallest), rule, label(k), needed));
  }
}

// Distance from q (body coordinates, centred) to the ellipsoid with
// semi-axes a, for q outside; -1 if q is inside or on it. The closest point
// is x_i = a_i^2 q_i / (t + a_i^2) with t > 0 the root of
// F(t) = sum (a_i q_i / (t + a_i^2))^2 - 1, decreasing on (0, inf).
double outside_distance(const Vector3d& q, const Vector3d& a) {
  const Vector3d y = q.cwiseAbs();
  if (y.cwiseQuotient(a).squaredNorm() <= 1.0) return -1.0;
  auto f = [&](double t) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i) s += std::pow(a[i] * y[i] / (t + a[i] * a[i]), 2);
    return s - 1.0;
  };
  double lo = 0.0, hi = a.maxCoeff() * y.norm();  // F(hi) <= 0
  for (int it = 0; it < 100 && hi - lo > 1e-14 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (f(mid) > 0.0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  Vector3d x;
  for (int i = 0; i < 3; ++i) x[i] = a[i] * a[i] * y[i] / (t + a[i] * a[i]);
  return (y - x).norm();
}

// Smallest distance from points sampled on `from`'s surface to `to`;
// negative if a sample lies inside `to`. The samples (a Fibonacci lattice
// on the unit sphere, mapped to the ellipsoid) are about h/4 apart, so a
// sampled gap >= h guarantees a true gap > h/2 (distance is 1-Lipschitz):
// the test never accepts touching objects. The cap on the count only bites
// for semi-axis ratios above ~20 at 50 equator nodes.
double sampled_gap(const ObjectSpec& from, const ObjectSpec& to, double h) {
  const double ratio = 4.0 * from.semi_axes.maxCoeff() / h;
  const int n = static_cast<int>(std::clamp(4.0 * M_PI * ratio * ratio, 2000.0, 500000.0));
  const Matrix3d map_from = rotation_matrix(from) * from.semi_axes.asDiagonal();
  const Matrix3d to_body = rotation_matrix(to).transpose();
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  double gap = INFINITY;
  for (int m = 0; m < n; ++m) {
    const double z = 1.0 - (2.0 * m + 1.0) / n, r = std::sqrt(1.0 - z * z), phi = m * golden_angle;
    const Vector3d p = from.centre + map_from * Vector3d(r * std::cos(phi), r * std::sin(phi), z);
    const double d = outside_distance(to_body * (p - to.centre), to.semi_axes);
    if (d < 0.0) return -1.0;
    gap = std::min(gap, d);
  }
  return gap;
}

void check_pair(int i, int j, const ShearCellSpec& spec) {
  const ObjectSpec &a = spec.objects[i], &b = spec.objects[j];
  const double h = std::max(interface_element_size(a, spec.sizing), interface_element_size(b, spec.sizing));
  const double distance = (a.centre - b.centre).norm();
  if (distance >= a.semi_axes.maxCoeff() + b.semi_axes.maxCoeff() + h) return;  // bounding spheres apart

  if (a.shape == ObjectShape::sphere && b.shape == ObjectShape::sphere) {
    const double minimum = a.semi_axes.x() + b.semi_axes.x() + h;
    if (distance >= minimum) return;
    const char* verb = distance <= a.semi_axes.x() + b.semi_axes.x() ? "overlaps" : "is too close to";
    throw InputError(
        fmt::format("{}: {} {} {} (centres {} apart, minimum {} = radii + one interface element); move it or "
                    "make it smaller",
                    label(j), describe(b), verb, label(i), num(distance), num(minimum)));
  }
  const double gap = std::min(sampled_gap(a, b, h), sampled_gap(b, a, h));
  if (gap >= h) return;
  if (gap < 0.0)
    throw InputError(fmt::format("{}: {} overlaps {} (the surfaces intersect); move it or make it smaller",
                                 label(j), describe(b), label(i)));
  throw InputError(
      fmt::format("{}: {} is too close to {} (gap about {}, minimum one interface element h = {}); move it "
                  "or make it smaller",
                  label(j), describe(b), label(i), num(gap), num(h)));
}

// An ellipsoid the mesh cannot resolve, or gmsh cannot finish meshing
// (largest_ellipsoid_ratio): [0.001, 1, 1] passed `check` and `softflow
// mesh` ran for over 4 minutes (60 s with the optimiser off).
void check_resolution(int k, const ObjectSpec& o, const MeshSizing& sizing) {
  if (o.shape != ObjectShape::ellipsoid) return;
  const double n = sizing.equator_nodes;
  const double a_min = o.semi_axes.minCoeff(), a_max = o.semi_axes.maxCoeff();
  const double ratio = a_max / a_min;
  if (ratio <= largest_ellipsoid_ratio(sizing.equator_nodes)) return;
  // As doubles: a ratio of 1e300 has no int.
  const double fewest = std::ceil(8.0 * ratio - 1e-9);
  const double most = std::floor(kMaxLongestCircumferenceNodes / ratio + 1e-9);
  const bool no_count = fewest > most;  // no mesh.equator_nodes does both
  std::vector<std::string> why;
  if (ratio > n / 8.0 || no_count)
    why.push_back(fmt::format(
        "to be resolved, its interface elements (they follow the smallest semi-axis: h = 4 pi "
        "a_min / N, here {}) may turn at most a quarter circle along its sharpest curvature "
        "(radius a_min^2 / a_max = {}), as a sphere's do at the coarsest 8 equator nodes, so N "
        ">= 8 a_max / a_min = {}",
        num(interface_element_size(o, sizing)), num(a_min * a_min / a_max), num(8.0 * ratio)));
  if (n * ratio > kMaxLongestCircumferenceNodes || no_count)
    why.push_back(fmt::format(
        "to be meshed in reasonable time, its longest circumference may get at most {:g} nodes "
        "(N a_max / a_min, here {}; gmsh's curved meshing of an ellipsoid slows steeply with "
        "them: at 160 over a minute and a failed mesh, at 320 over 10 minutes), so N <= {:g} "
        "a_min / a_max = {}",
        kMaxLongestCircumferenceNodes, num(n * ratio), kMaxLongestCircumferenceNodes,
        num(kMaxLongestCircumferenceNodes / ratio)));
  const std::string fix =
      no_count ? fmt::format("make it rounder ({}.semi_axes): no mesh.equator_nodes does both "
                             "above a_max / a_min = {:.3g} (at N = 35)",
                             label(k), largest_ellipsoid_ratio(35))
               : fmt::format("set mesh.equator_nodes (now {}) between {:g} and {:g}, or make it "
                             "rounder ({}.semi_axes)",
                             sizing.equator_nodes, fewest, most, label(k));
  throw InputError(fmt::format(
      "{}: {} has a semi-axis ratio a_max / a_min = {} that mesh.equator_nodes = {} cannot mesh "
      "(allowed: a_max / a_min <= min(N / 8, 150 / N) = {}): {}; {}",
      label(k), describe(o), num(ratio), sizing.equator_nodes,
      num(largest_ellipsoid_ratio(sizing.equator_nodes)), fmt::join(why, "; "), fix));
}

// mesh.point_symmetric: the rotation R (x, y, z) -> (-x, -y, z) must map the
// object onto itself, else no mesh is R-symmetric: its centre on the z axis,
// and an ellipsoid turned about z only (R commutes with rotations about z;
// turns by multiples of 180 deg about x or y map the ellipsoid onto itself).
void check_point_symmetric(int k, const ObjectSpec& o) {
  const auto half_turns = [](double degrees) { return std::fmod(degrees, 180.0) == 0.0; };
  if (o.centre.x() != 0.0 || o.centre.y() != 0.0)
    throw InputError(fmt::format(
        "{}: {} is off the z axis, and mesh.point_symmetric = true needs every object mapped "
        "onto itself by the rotation by 180 deg about z: put its centre at x = y = 0 "
        "({}.centre) or set mesh.point_symmetric = false",
        label(k), describe(o), label(k)));
  if (o.shape == ObjectShape::ellipsoid && !(half_turns(o.rotation_deg.x()) && half_turns(o.rotation_deg.y())))
    throw InputError(fmt::format(
        "{}: {} is turned about x or y by {}, and mesh.point_symmetric = true needs it mapped "
        "onto itself by the rotation by 180 deg about z: turn it about z only ({}.rotation_deg "
        "= [0, 0, rz]) or set mesh.point_symmetric = false",
        label(k), describe(o), vec(o.rotation_deg), label(k)));
}

}  // namespace

double largest_ellipsoid_ratio(int equator_nodes) {
  const double n = equator_nodes;
  return std::min(n / 8.0, kMaxLongestCircumferenceNodes / n);
}

double wall_gap(const ObjectSpec& object, const mesh::Box& box, int side, Vector3d* closest) {
  // The ellipsoid x = c + M u, |u| = 1, M = R diag(a), reaches furthest along
  // e_y at u = M^T e_y / |M^T e_y|: y_c + |M^T e_y| (half_extents' y).
  const Matrix3d m = rotation_matrix(object) * object.semi_axes.asDiagonal();
  const Vector3d direction = m.row(1).transpose();  // M^T e_y
  const double extent = direction.norm();
  if (closest) *closest = object.centre + side * m * direction / extent;
  return box.height / 2 - side * object.centre.y() - extent;
}

double wall_gap_element_size(const ObjectSpec& object, const MeshSizing& sizing, double gap) {
  const double h0 = interface_element_size(object, sizing);
  const int n = sizing.elements_across_gaps();
  // Unset, only the gaps the one-element rule of before refused are refined.
  const double refined_below = sizing.gap_elements ? n * h0 : h0;
  if (gap >= refined_below) return std::numeric_limits<double>::infinity();
  return gap / n;
}

double smallest_wall_gap(const ObjectSpec& object, const MeshSizing& sizing) {
  return sizing.elements_across_gaps() * interface_element_size(object, sizing) / kMaxGapRefinement;
}

void validate(const ShearCellSpec& spec) {
  validate_box(spec.box);
  validate_sizing(spec.sizing);
  for (int k = 0; k < static_cast<int>(spec.objects.size()); ++k) {
    validate_shape(k, spec.objects[k]);
    if (spec.sizing.point_symmetric) check_point_symmetric(k, spec.objects[k]);
    check_resolution(k, spec.objects[k], spec.sizing);
    const double h = interface_element_size(spec.objects[k], spec.sizing);
    check_wall(k, spec.objects[k], spec.box, spec.sizing);
    for (int axis : {0, 2}) check_axis(k, spec.objects[k], spec.box, axis, h);
  }
  for (int j = 1; j < static_cast<int>(spec.objects.size()); ++j)
    for (int i = 0; i < j; ++i) check_pair(i, j, spec);
}

// ---------------------------------------------------------------------------
// gmsh session
// ---------------------------------------------------------------------------

namespace {

// One gmsh API lifetime. gmsh 4.8 throws from inside OpenMP loops (e.g. a
// bad mesh size while meshing curves), where nothing can catch it and the
// process terminates. So errors are made non-fatal (AbortOnError = 0) and
// the session polls gmsh's log for them after every stage instead.
// gmsh runs inside a DeterministicHeapScope: its high-order optimiser orders
// elements by address, and only there are those addresses the same in every
// process (common/deterministic_heap.hpp).
class GmshSession {
 public:
  GmshSession() {
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
  ~GmshSession() {
    try {
      gmsh::logger::stop();
      gmsh::finalize();
    } catch (...) {  // a destructor must not throw; nothing useful to do
    }
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  // Runs one stage; gmsh's exceptions (std::string, const char*, int or
  // std::exception in 4.8) and logged errors become MeshError.
  void run(const std::string& stage, const std::function<void()>& body) {
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

 private:
  [[noreturn]] void fail(const std::string& stage, const std::string& what) {
    const std::string errors = new_errors();
    throw MeshError(
        fmt::format("gmsh failed while {}: {}{}{}", stage, what, errors.empty() ? "" : "; ", errors));
  }

  // Distinct error lines logged since the last call (at most three: a
  // failing size field repeats the same error thousands of times).
  std::string new_errors() {
    std::vector<std::string> log;
    try {
      gmsh::logger::get(log);
    } catch (...) {
      return {};
    }
    std::vector<std::string> errors;
    for (std::size_t i = seen_; i < log.size() && errors.size() < 3; ++i)
      if (log[i].rfind("Error", 0) == 0 && std::find(errors.begin(), errors.end(), log[i]) == errors.end())
        errors.push_back(log[i]);
    seen_ = log.size();
    return fmt::format("{}", fmt::join(errors, "; "));
  }

  DeterministicHeapScope heap_;  // open before gmsh::initialize, closed after gmsh::finalize
  std::size_t seen_ = 0;
};

// ---------------------------------------------------------------------------
// Geometry
// ---------------------------------------------------------------------------

// Model entities after the fragment (which renumbers everything).
struct CellEntities {
  int matrix = -1;                                // volume tag
  std::vector<int> object_volume;                 // volume tag of object k (0-based)
  std::vector<std::vector<int>> object_surfaces;  // interface surfaces of object k
  std::array<std::vector<int>, 6> box_faces;      // indexed by BoundaryTag
  // mesh.point_symmetric: the half y >= 0 is meshed; its faces on the cut
  // plane y = 0, split at x = 0 (x < 0 pieces, then their mirror pieces).
  std::vector<int> cut_low, cut_high;
};

// Unit sphere (pole on z) dilated, rotated (Rx, then Ry, then Rz, so that
// R = Rz Ry Rx) and moved to the centre. Spheres skip the transformations:
// an exact OCC sphere with its poles on z, where a drop deforms least.
int add_object(const ObjectSpec& o) {
  const Vector3d& c = o.centre;
  if (o.shape == ObjectShape::sphere)
    return gmsh::model::occ::addSphere(c.x(), c.y(), c.z(), o.semi_axes.x());
  const int tag = gmsh::model::occ::addSphere(0, 0, 0, 1);
  const gmsh::vectorpair v{{3, tag}};
  const Vector3d& a = o.semi_axes;
  gmsh::model::occ::dilate(v, 0, 0, 0, a.x(), a.y(), a.z());
  const Vector3d angle = o.rotation_deg * (M_PI / 180.0);
  for (int axis = 0; axis < 3; ++axis)
    if (angle[axis] != 0.0)
      gmsh::model::occ::rotate(v, 0, 0, 0, axis == 0, axis == 1, axis == 2, angle[axis]);
  gmsh::model::occ::translate(v, c.x(), c.y(), c.z());
  return tag;
}

std::vector<int> boundary_surfaces(int volume) {
  gmsh::vectorpair out;
  gmsh::model::getBoundary({{3, volume}}, out, /*combined=*/false, /*oriented=*/false);
  std::vector<int> tags;
  for (const auto& [dim, tag] : out) tags.push_back(std::abs(tag));
  return tags;
}

// Which box face a flat surface lies on, or -1 for an interface.
int box_face_of(int surface, const mesh::Box& box) {
  double lo[3], hi[3];
  gmsh::model::getBoundingBox(2, surface, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  const std::array<double, 3> half{box.length / 2, box.height / 2, box.width / 2};
  const double tol = 1e-6 * std::max({box.length, box.height, box.width});
  constexpr std::array<std::array<BoundaryTag, 2>, 3> tags{{{BoundaryTag::x_min, BoundaryTag::x_max},
                                                            {BoundaryTag::wall_bottom, BoundaryTag::wall_top},
                                                            {BoundaryTag::z_min, BoundaryTag::z_max}}};
  for (int axis = 0; axis < 3; ++axis) {
    if (hi[axis] - lo[axis] > tol) continue;
    if (std::abs(lo[axis] + half[axis]) < tol) return static_cast<int>(tags[axis][0]);
    if (std::abs(lo[axis] - half[axis]) < tol) return static_cast<int>(tags[axis][1]);
  }
  return -1;
}

// Box fragmented with the objects: conforming interfaces, one volume per
// object and one for the matrix. fragment() reports which output volumes
// come from which input, so no geometric matching is needed for that.
CellEntities build_geometry(const ShearCellSpec& spec) {
  const mesh::Box& b = spec.box;
  const int box =
      gmsh::model::occ::addBox(-b.length / 2, -b.height / 2, -b.width / 2, b.length, b.height, b.width);
  gmsh::vectorpair objects;
  for (const auto& o : spec.objects) objects.push_back({3, add_object(o)});

  CellEntities e;
  std::vector<int> matrix_pieces{box};
  if (!objects.empty()) {
    gmsh::vectorpair out;
    std::vector<gmsh::vectorpair> pieces;
    gmsh::model::occ::fragment({{3, box}}, objects, out, pieces);
    if (pieces.size() != objects.size() + 1)
      throw MeshError("gmsh fragment returned an unexpected piece map");
    matrix_pieces.clear();
    for (std::size_t k = 0; k < objects.size(); ++k) {
      if (pieces[k + 1].size() != 1)
        throw MeshError(fmt::format("{}: the fragment split it into {} volumes", label(static_cast<int>(k)),
                                    pieces[k + 1].size()));
      e.object_volume.push_back(pieces[k + 1][0].second);
    }
    for (const auto& [dim, tag] : pieces[0])
      if (std::find(e.object_volume.begin(), e.object_volume.end(), tag) == e.object_volume.end())
        matrix_pieces.push_back(tag);
  }
  gmsh::model::occ::synchronize();
  if (matrix_pieces.size() != 1)
    throw MeshError(fmt::format("the matrix came out of the fragment as {} volumes", matrix_pieces.size()));
  e.matrix = matrix_pieces[0];

  for (int surface : boundary_surfaces(e.matrix)) {
    const int face = box_face_of(surface, b);
    if (face >= 0) e.box_faces[face].push_back(surface);
  }
  for (std::size_t f = 0; f < e.box_faces.size(); ++f)
    if (e.box_faces[f].size() != 1)
      throw MeshError(
          fmt::format("box face {} has {} surfaces after the fragment", f, e.box_faces[f].size()));
  for (int volume : e.object_volume) e.object_surfaces.push_back(boundary_surfaces(volume));
  return e;
}

// The box's upper half y >= 0 fragmented with the objects' upper halves and
// with the segment x = y = 0 on the cut plane, which splits the plane's
// faces (the matrix's and each object's cross-section) into x < 0 and x > 0
// pieces: set_half_turn_periodicity makes the x > 0 pieces' meshes the
// mirror images of the x < 0 ones, so that the plane's mesh is symmetric
// under x -> -x, R restricted to y = 0.
CellEntities build_half_geometry(const ShearCellSpec& spec) {
  const mesh::Box& b = spec.box;
  const auto upper_half = [&] {
    return gmsh::model::occ::addBox(-b.length / 2, 0.0, -b.width / 2, b.length, b.height / 2, b.width);
  };
  const int box = upper_half();
  gmsh::vectorpair objects;
  for (const auto& o : spec.objects) {
    gmsh::vectorpair out;
    std::vector<gmsh::vectorpair> map;
    gmsh::model::occ::intersect({{3, add_object(o)}}, {{3, upper_half()}}, out, map);
    if (out.size() != 1) throw MeshError("the upper half of an object came out as several volumes");
    objects.push_back(out[0]);
  }
  // The segment is broken at each object's centre: else an object's
  // cross-section would have its half-boundary arc and its diameter between
  // the same two end points, and gmsh 4.8 matches periodic curves by their
  // end points ("could not find counterpart of curve").
  std::vector<double> breaks{-b.width / 2, b.width / 2};
  for (const auto& o : spec.objects) breaks.push_back(o.centre.z());
  std::sort(breaks.begin(), breaks.end());
  gmsh::vectorpair tools = objects;
  int previous = gmsh::model::occ::addPoint(0.0, 0.0, breaks.front());
  for (std::size_t i = 1; i < breaks.size(); ++i) {
    if (breaks[i] == breaks[i - 1]) continue;
    const int next = gmsh::model::occ::addPoint(0.0, 0.0, breaks[i]);
    tools.push_back({1, gmsh::model::occ::addLine(previous, next)});
    previous = next;
  }

  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> pieces;
  gmsh::model::occ::fragment({{3, box}}, tools, out, pieces);
  if (pieces.size() != tools.size() + 1) throw MeshError("gmsh fragment returned an unexpected piece map");
  CellEntities e;
  for (std::size_t k = 0; k < objects.size(); ++k) {
    if (pieces[k + 1].size() != 1)
      throw MeshError(fmt::format("{}: the fragment split its upper half into {} volumes",
                                  label(static_cast<int>(k)), pieces[k + 1].size()));
    e.object_volume.push_back(pieces[k + 1][0].second);
  }
  std::vector<int> matrix_pieces;
  for (const auto& [dim, tag] : pieces[0])
    if (dim == 3 && std::find(e.object_volume.begin(), e.object_volume.end(), tag) == e.object_volume.end())
      matrix_pieces.push_back(tag);
  gmsh::model::occ::synchronize();
  if (matrix_pieces.size() != 1)
    throw MeshError(fmt::format("the matrix came out of the fragment as {} volumes", matrix_pieces.size()));
  e.matrix = matrix_pieces[0];

  const double tol = 1e-6 * std::max({b.length, b.height, b.width});
  struct Flat {
    int tag;
    double lo[3], hi[3];
  };
  std::vector<Flat> cut;
  auto on_cut_plane = [&](int surface, Flat* flat) {
    Flat f{surface, {}, {}};
    gmsh::model::getBoundingBox(2, surface, f.lo[0], f.lo[1], f.lo[2], f.hi[0], f.hi[1], f.hi[2]);
    if (std::abs(f.lo[1]) > tol || std::abs(f.hi[1]) > tol) return false;
    if (flat) *flat = f;
    return true;
  };
  for (int surface : boundary_surfaces(e.matrix)) {
    Flat f{};
    if (on_cut_plane(surface, &f)) {
      cut.push_back(f);
      continue;
    }
    const int face = box_face_of(surface, b);
    if (face >= 0) e.box_faces[face].push_back(surface);
  }
  for (std::size_t f = 0; f < e.box_faces.size(); ++f)
    if (e.box_faces[f].size() != (f == static_cast<std::size_t>(BoundaryTag::wall_bottom) ? 0u : 1u))
      throw MeshError(fmt::format("box face {} has {} surfaces after the fragment of the upper half", f,
                                  e.box_faces[f].size()));
  for (int volume : e.object_volume) {
    std::vector<int> surfaces;
    for (int surface : boundary_surfaces(volume)) {
      Flat f{};
      if (!on_cut_plane(surface, &f)) surfaces.push_back(surface);
      else if (std::none_of(cut.begin(), cut.end(), [&](const Flat& c) { return c.tag == surface; }))
        cut.push_back(f);
    }
    e.object_surfaces.push_back(surfaces);
  }
  // Pair each x < 0 piece with the x > 0 piece whose bounding box is its mirror image.
  for (const Flat& low : cut) {
    if (low.hi[0] > tol) continue;
    int found = -1;
    for (const Flat& high : cut)
      if (high.lo[0] >= -tol && std::abs(high.lo[0] + low.hi[0]) < tol && std::abs(high.hi[0] + low.lo[0]) < tol &&
          std::abs(high.lo[2] - low.lo[2]) < tol && std::abs(high.hi[2] - low.hi[2]) < tol)
        found = high.tag;
    if (found < 0) throw MeshError("a face of the cut plane y = 0 has no mirror face");
    e.cut_low.push_back(low.tag);
    e.cut_high.push_back(found);
  }
  if (e.cut_low.size() * 2 != cut.size())
    throw MeshError(fmt::format("the cut plane y = 0 came out as {} faces, not split into mirror pairs at x = 0",
                                cut.size()));
  return e;
}

// The x > 0 pieces of the cut plane are meshed as the images of the x < 0
// pieces under R (x, y, z) -> (-x, -y, z), which maps y = 0 onto itself by
// x -> -x. Slave is the x > 0 side because the x-periodic face x = L/2 is a
// slave too: their shared edge (x = L/2, y = 0) then has one master, the
// edge at x = -L/2, by both constraints, which give it the same nodes.
void set_half_turn_periodicity(const CellEntities& e) {
  gmsh::model::mesh::setPeriodic(2, e.cut_high, e.cut_low,
                                 {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
}

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
class SizeField {
 public:
  explicit SizeField(const ShearCellSpec& spec)
      : far_(spec.sizing.far_size),
        half_height_(spec.box.height / 2),
        growth_(spec.sizing.growth),
        gap_divisor_(kGapSizeFactor * spec.sizing.elements_across_gaps()),
        wall_size_(spec.sizing.wall_size) {
    for (const auto& o : spec.objects) {
      Term t;
      for (int side : {1, -1})
        if (std::isfinite(wall_gap_element_size(o, spec.sizing, wall_gap(o, spec.box, side))))
          t.gap_walls.push_back(side);
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
  }

  double operator()(double x, double y, double z) const {
    double size = far_;
    for (const auto& t : terms_) {
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
      const double distance = t.sphere ? std::abs(r - t.scale) : std::abs(r - 1.0) * t.scale;
      const bool inside = r < (t.sphere ? t.scale : 1.0);
      size = std::min(size, t.h0 + (inside ? t.interior_growth : t.growth) * distance);
      for (int side : t.gap_walls)
        size = std::min(size, (half_height_ - side * y + distance) / gap_divisor_);
    }
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
  };
  double far_;
  double half_height_;
  double growth_;
  double gap_divisor_;  ///< kGapSizeFactor * gap_elements
  std::optional<double> wall_size_;
  std::vector<Term> terms_;
};

void set_size_and_order(const ShearCellSpec& spec) {
  gmsh::model::mesh::setSizeCallback(
      [field = SizeField(spec)](int, int, double x, double y, double z) { return field(x, y, z); });
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

// Union-find whose representative is the smallest index of its class.
class SmallestRepresentative {
 public:
  explicit SmallestRepresentative(int n) : parent_(n) {
    for (int i = 0; i < n; ++i) parent_[i] = i;
  }
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

// Periodic node classes from gmsh's slave -> master pairs on points, curves
// and surfaces (high-order nodes included). Corner edges of a doubly
// periodic box have 4 copies, linked by pairs through different entities:
// the union-find collapses them. Must run before any write/read of the mesh.
void read_periodic(mesh::Mesh& m, const NodeTable& nodes) {
  if (!m.box.periodic_x && !m.box.periodic_z) return;
  SmallestRepresentative classes(m.n_nodes());
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

// `cut_nodes` (mesh.point_symmetric: the half's nodes on the cut plane, for
// complete_by_half_turn) instead of the periodic pairs: the whole mesh's
// periodic classes are found from it, not from the half's.
mesh::Mesh read_mesh(const ShearCellSpec& spec, const CellEntities& e, std::vector<int>* cut_nodes = nullptr) {
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
// Checks and report
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

// Effective P2 nodes around the first object's equator: 2 pi r / (mean
// interface edge length) edges, two P2 nodes per edge. An unstructured
// surface mesh has no equator line; this is the number the mesh would put on
// a great circle of radius r (the smallest semi-axis), comparable with
// mesh.equator_nodes and with the thesis's 28/40/50.
int count_equator_nodes(const mesh::Mesh& m, const ObjectSpec& object) {
  std::set<std::pair<int, int>> edges;
  for (std::size_t f = 0; f < m.interface_faces.size(); ++f) {
    if (m.interface_object[f] != 1) continue;
    const auto& tri = m.interface_faces[f];
    for (const auto& e : mesh::kTriangleEdges)
      edges.emplace(std::min(tri[e[0]], tri[e[1]]), std::max(tri[e[0]], tri[e[1]]));
  }
  if (edges.empty()) return 0;
  double total = 0.0;
  for (const auto& [a, b] : edges) total += (m.nodes[a] - m.nodes[b]).norm();
  const double mean_edge = total / static_cast<double>(edges.size());
  return static_cast<int>(std::lround(2.0 * 2.0 * M_PI * object.semi_axes.minCoeff() / mean_edge));
}

/// What to change when gmsh fails to mesh the cell: its volume mesher fails
/// for some surface meshes and not for their neighbours, and the curved-
/// element optimiser for some geometries, so the keys that change either.
std::string meshing_advice(const MeshSizing& sizing) {
  return fmt::format(
      "What usually helps: another mesh.equator_nodes (now {}; elongated or thin objects need "
      "more), a smaller mesh.far_size "
      "(now {:g}) or mesh.growth (now {:g}){}",
      sizing.equator_nodes, sizing.far_size, sizing.growth,
      sizing.optimize_high_order ? ", or, when the curved-element optimiser is what failed, "
                                   "mesh.optimize_high_order = false"
                                 : "");
}

/// gmsh gives no progress while it meshes, and its curved-element optimiser
/// can take many minutes (50 objects: more than 10); after `seconds` a note
/// on stderr says what is happening and which keys change it.
/// SOFTFLOW_SLOW_MESHING_NOTE_SECONDS overrides the delay (tests).
double slow_meshing_note_seconds() {
  if (const char* text = std::getenv("SOFTFLOW_SLOW_MESHING_NOTE_SECONDS")) {
    char* end = nullptr;
    const double seconds = std::strtod(text, &end);
    if (end != text && seconds > 0.0) return seconds;
  }
  return 60.0;
}

class SlowStageNote {
 public:
  SlowStageNote(double seconds, std::string note)
      : thread_([this, seconds, note = std::move(note)] {
          std::unique_lock lock(mutex_);
          if (done_changed_.wait_for(lock, std::chrono::duration<double>(seconds),
                                     [this] { return done_; }))
            return;
          std::cerr << note << std::endl;
        }) {}
  ~SlowStageNote() {
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    done_changed_.notify_all();
    thread_.join();
  }
  SlowStageNote(const SlowStageNote&) = delete;
  SlowStageNote& operator=(const SlowStageNote&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable done_changed_;
  bool done_ = false;
  std::thread thread_;  // last: starts once the members it uses exist
};

/// The surface area of an ellipsoid (Thomsen's formula, within 1.1 %).
double surface_area(const Vector3d& a) {
  constexpr double p = 1.6075;
  const double ab = std::pow(a.x() * a.y(), p), ac = std::pow(a.x() * a.z(), p),
               bc = std::pow(a.y() * a.z(), p);
  return 4.0 * M_PI * std::pow((ab + ac + bc) / 3.0, 1.0 / p);
}

MeshReport make_report(const mesh::Mesh& m, const ShearCellSpec& spec, double min_quality, double seconds) {
  MeshReport r;
  r.n_nodes = m.n_nodes();
  r.n_tets = m.n_tets();
  std::vector<char> on_interface(m.n_nodes(), 0);
  for (const auto& face : m.interface_faces)
    for (int node : face) on_interface[node] = 1;
  r.n_interface_nodes = static_cast<int>(std::count(on_interface.begin(), on_interface.end(), 1));
  r.n_equator_nodes = spec.objects.empty() ? 0 : count_equator_nodes(m, spec.objects[0]);
  std::vector<char> in_object(m.n_nodes(), 0);
  for (int t = 0; t < m.n_tets(); ++t)
    if (m.tet_region[t] > 0)
      for (int k = 0; k < 4; ++k) in_object[m.tets[t][k]] = 1;
  for (int node = 0; node < m.n_nodes(); ++node)
    if (in_object[node] && !on_interface[node]) ++r.n_object_interior_vertices;
  r.min_quality = min_quality;
  r.seconds = seconds;
  r.fingerprint = mesh::fingerprint(m);
  for (int k = 0; k < static_cast<int>(spec.objects.size()); ++k) {
    const ObjectSpec& o = spec.objects[k];
    const double gap = std::min(wall_gap(o, spec.box, 1), wall_gap(o, spec.box, -1));
    if (!std::isfinite(wall_gap_element_size(o, spec.sizing, gap))) continue;
    if (r.wall_gap && r.wall_gap->gap <= gap) continue;
    r.wall_gap = measure_wall_gap(m, o);
    r.wall_gap->object = k + 1;
  }
  return r;
}

}  // namespace

std::string slow_meshing_note(const ShearCellSpec& spec, double seconds) {
  const MeshSizing& sizing = spec.sizing;
  const double n = sizing.equator_nodes;
  std::vector<std::string> causes, fixes;
  // An elongated ellipsoid: gmsh curves its elements onto a dilated sphere,
  // slowly, and more slowly the more nodes its longest circumference gets
  // (largest_ellipsoid_ratio). [0.001, 1, 1] used to mesh for minutes under
  // a note that blamed the optimiser; with it off, the time stayed.
  int worst = -1;
  double worst_nodes = 0.0;
  for (int k = 0; k < static_cast<int>(spec.objects.size()); ++k) {
    const ObjectSpec& o = spec.objects[k];
    if (o.shape != ObjectShape::ellipsoid) continue;
    const double nodes = n * o.semi_axes.maxCoeff() / o.semi_axes.minCoeff();
    if (nodes > worst_nodes) {
      worst = k;
      worst_nodes = nodes;
    }
  }
  if (worst >= 0 && worst_nodes >= 80.0) {
    causes.push_back(fmt::format(
        "{} is an ellipsoid with semi-axes {}, whose longest circumference gets N a_max / a_min "
        "= {:.0f} nodes (its elements follow its smallest semi-axis): gmsh curves an ellipsoid's "
        "elements onto a dilated sphere, slowly, and the more slowly the more such nodes ({:g} "
        "is the most `softflow check` accepts)",
        label(worst), vec(spec.objects[worst].semi_axes), worst_nodes,
        kMaxLongestCircumferenceNodes));
    fixes.push_back(fmt::format("fewer mesh.equator_nodes (now {}) or a rounder {}.semi_axes",
                                sizing.equator_nodes, label(worst)));
  }
  // Many objects keep the curved-element optimiser busy (50 spheres at 12
  // equator nodes: more than 10 minutes; seconds without it).
  const std::size_t count = spec.objects.size();
  if (sizing.optimize_high_order && count >= 5) {
    causes.push_back(fmt::format(
        "with {} objects, gmsh's curved-element optimiser (mesh.optimize_high_order = true) can "
        "take many minutes (50 spheres: more than 10)",
        count));
    fixes.push_back(fmt::format(
        "mesh.optimize_high_order = false (then check the minimum quality `softflow mesh` "
        "reports), or a larger mesh.equator_nodes (now {}): coarse curved elements give the "
        "optimiser more to untangle",
        sizing.equator_nodes));
  }
  // A large mesh: about 0.4 N^2 interface nodes on a sphere (650 at N = 40,
  // 4,746 at 110, which meshes in 9 s), times its area over that of the
  // sphere of its smallest semi-axis.
  double interface_nodes = 0.0;
  for (const auto& o : spec.objects) {
    const double a_min = o.semi_axes.minCoeff();
    interface_nodes += 0.4 * n * n * surface_area(o.semi_axes) / (4.0 * M_PI * a_min * a_min);
  }
  if (interface_nodes > 20000.0) {
    causes.push_back(fmt::format(
        "the mesh is large: about {:.0f} interface nodes on {} object{} at mesh.equator_nodes = "
        "{} (the volume has many times more)",
        interface_nodes, count, count == 1 ? "" : "s", sizing.equator_nodes));
    fixes.push_back(fmt::format("fewer mesh.equator_nodes (now {}), a larger mesh.growth (now "
                                "{:g}) or mesh.far_size (now {:g})",
                                sizing.equator_nodes, sizing.growth, sizing.far_size));
  }
  if (causes.empty()) {
    if (sizing.optimize_high_order) {
      causes.push_back(
          "most likely gmsh's curved-element optimiser (mesh.optimize_high_order = true), which "
          "objects near walls or near each other keep busy");
      fixes.push_back("mesh.optimize_high_order = false (then check the minimum quality "
                      "`softflow mesh` reports)");
    } else {
      causes.push_back(fmt::format(
          "nothing in the case explains it ({} object{}, about {:.0f} interface nodes, the "
          "optimiser off): the machine may be busy",
          count, count == 1 ? "" : "s", interface_nodes));
    }
  }
  std::string note = fmt::format("softflow: note: gmsh has been meshing for {:.0f} s. What makes "
                                 "it slow here: {}. It may still succeed",
                                 seconds, fmt::join(causes, "; "));
  if (!fixes.empty())
    note += fmt::format("; to make it faster, stop it and try {}", fmt::join(fixes, ", or "));
  return note;
}

mesh::Mesh build_shear_cell(const ShearCellSpec& spec, MeshReport* report) {
  const auto start = std::chrono::steady_clock::now();
  validate(spec);
  mesh::Mesh m;
  {
    GmshSession session;
    CellEntities entities;
    const bool symmetric = spec.sizing.point_symmetric;
    session.run("building the geometry",
                [&] { entities = symmetric ? build_half_geometry(spec) : build_geometry(spec); });
    session.run("setting periodicity and mesh size", [&] {
      set_periodicity(spec.box, entities);
      if (symmetric) set_half_turn_periodicity(entities);
      set_size_and_order(spec);
    });
    try {
      const double seconds = slow_meshing_note_seconds();
      const SlowStageNote note(seconds, slow_meshing_note(spec, seconds));
      session.run("meshing", [] { gmsh::model::mesh::generate(3); });
    } catch (const MeshError& e) {
      throw MeshError(fmt::format("{}. {}", e.what(), meshing_advice(spec.sizing)));
    }
    std::vector<int> cut_nodes;
    session.run("reading the mesh", [&] { m = read_mesh(spec, entities, symmetric ? &cut_nodes : nullptr); });
    if (symmetric) m = complete_by_half_turn(m, cut_nodes);
  }
  mesh::renumber_nodes_spatially(m);  // compact per-rank node ranges, local element loops
  verify_periodic(m);
  const double q = check_quality(m, spec.sizing.optimize_high_order);
  if (report)
    *report = make_report(m, spec, q,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return m;
}

WallGapResolution measure_wall_gap(const mesh::Mesh& m, const ObjectSpec& object) {
  WallGapResolution r;
  r.side = wall_gap(object, m.box, 1) <= wall_gap(object, m.box, -1) ? 1 : -1;
  Vector3d p;
  r.gap = wall_gap(object, m.box, r.side, &p);
  if (!(r.gap > 0.0)) return r;
  const Vector3d q(p.x(), r.side * m.box.height / 2, p.z());  // the segment p -> q, along y
  const double y_lo = std::min(p.y(), q.y()), y_hi = std::max(p.y(), q.y());
  double edges = 0.0;
  for (int t = 0; t < m.n_tets(); ++t) {
    if (m.tet_region[t] != 0) continue;
    std::array<Vector3d, 4> v;
    for (int k = 0; k < 4; ++k) v[k] = m.nodes[m.tets[t][k]];
    Vector3d lo = v[0], hi = v[0];
    for (const auto& x : v) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    if (p.x() < lo.x() || p.x() > hi.x() || p.z() < lo.z() || p.z() > hi.z() || hi.y() < y_lo ||
        lo.y() > y_hi)
      continue;
    // Barycentric coordinates along the segment, lambda(s) = l0 + s dl, s in [0, 1].
    Matrix3d e;
    for (int k = 0; k < 3; ++k) e.col(k) = v[k + 1] - v[0];
    const Matrix3d inverse = e.inverse();
    const Vector3d a = inverse * (p - v[0]), b = inverse * (q - v[0]);
    const std::array<double, 4> l0{1.0 - a.sum(), a.x(), a.y(), a.z()};
    const std::array<double, 4> l1{1.0 - b.sum(), b.x(), b.y(), b.z()};
    double s0 = 0.0, s1 = 1.0;
    for (int k = 0; k < 4; ++k) {
      const double d = l1[k] - l0[k];
      if (d > 0.0) s0 = std::max(s0, -l0[k] / d);
      else if (d < 0.0) s1 = std::min(s1, -l0[k] / d);
      else if (l0[k] < 0.0) s1 = -1.0;
    }
    if (s1 - s0 <= 1e-9) continue;
    ++r.tets_crossed;
    for (const auto& edge : mesh::kTetEdges) edges += (v[edge[0]] - v[edge[1]]).norm();
  }
  if (r.tets_crossed > 0) r.mean_edge = edges / (6.0 * r.tets_crossed);
  return r;
}

}  // namespace softflow::geometry
