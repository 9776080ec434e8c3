#include "softflow/geometry/shear_cell.hpp"
#include "softflow/geometry/point_symmetric_mesh.hpp"
#include "softflow/geometry/gmsh_mesh.hpp"
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

// Two objects closer than gap_elements interface elements get the size
// field's gap term (gmsh_mesh.cpp), as an object and a wall do: the narrowest
// gap accepted is the wall's, smallest_wall_gap of the finer object.
void check_pair(int i, int j, const ShearCellSpec& spec) {
  const ObjectSpec &a = spec.objects[i], &b = spec.objects[j];
  const double h = std::max(interface_element_size(a, spec.sizing), interface_element_size(b, spec.sizing));
  const double g_min = std::min(smallest_wall_gap(a, spec.sizing), smallest_wall_gap(b, spec.sizing));
  const double distance = (a.centre - b.centre).norm();
  if (distance >= a.semi_axes.maxCoeff() + b.semi_axes.maxCoeff() + h) return;  // bounding spheres apart

  const std::string resolved = fmt::format(
      "the narrowest gap the mesh resolves with mesh.gap_elements = {} at these interface elements is {}",
      spec.sizing.elements_across_gaps(), num(g_min));
  if (a.shape == ObjectShape::sphere && b.shape == ObjectShape::sphere) {
    const double minimum = a.semi_axes.x() + b.semi_axes.x() + g_min;
    if (distance >= minimum) return;
    if (distance <= a.semi_axes.x() + b.semi_axes.x())
      throw InputError(fmt::format("{}: {} overlaps {} (centres {} apart, radii {} and {}); move it or make it "
                                   "smaller",
                                   label(j), describe(b), label(i), num(distance), num(a.semi_axes.x()),
                                   num(b.semi_axes.x())));
    throw InputError(fmt::format("{}: {} is too close to {} (centres {} apart, gap {} < {}: {}); move it or make "
                                 "it smaller",
                                 label(j), describe(b), label(i), num(distance),
                                 num(distance - a.semi_axes.x() - b.semi_axes.x()), num(g_min), resolved));
  }
  const double gap = object_gap(a, b, spec.sizing);
  if (gap >= g_min) return;
  if (gap < 0.0)
    throw InputError(fmt::format("{}: {} overlaps {} (the surfaces intersect); move it or make it smaller",
                                 label(j), describe(b), label(i)));
  throw InputError(fmt::format("{}: {} is too close to {} (gap about {} < {}: {}); move it or make it smaller",
                               label(j), describe(b), label(i), num(gap), num(g_min), resolved));
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
        "({}.centre), set mesh.point_symmetric_start = true to mesh it there and carry it to "
        "its centre, or set mesh.point_symmetric = false",
        label(k), describe(o), label(k)));
  if (o.shape == ObjectShape::ellipsoid && !(half_turns(o.rotation_deg.x()) && half_turns(o.rotation_deg.y())))
    throw InputError(fmt::format(
        "{}: {} is turned about x or y by {}, and mesh.point_symmetric = true needs it mapped "
        "onto itself by the rotation by 180 deg about z: turn it about z only ({}.rotation_deg "
        "= [0, 0, rz]) or set mesh.point_symmetric = false",
        label(k), describe(o), vec(o.rotation_deg), label(k)));
}

// mesh.point_symmetric_start carries one object from the z axis to its
// centre: the object must be mapped onto itself by the half turn once there.
void check_symmetric_start(const ShearCellSpec& spec) {
  const int n = static_cast<int>(spec.objects.size());
  if (n != 1)
    throw InputError(fmt::format(
        "mesh.point_symmetric_start = true carries one object from the z axis to its centre, "
        "and the case has {} objects: describe one object or set mesh.point_symmetric_start = "
        "false",
        n));
  ObjectSpec on_axis = spec.objects[0];
  on_axis.centre.x() = on_axis.centre.y() = 0.0;
  check_point_symmetric(0, on_axis);
}

}  // namespace

ShearCellSpec symmetric_start(const ShearCellSpec& spec) {
  ShearCellSpec out = spec;
  out.sizing.point_symmetric_start = false;
  out.sizing.point_symmetric = true;
  for (ObjectSpec& o : out.objects) o.centre.x() = o.centre.y() = 0.0;
  return out;
}

double largest_ellipsoid_ratio(int equator_nodes) {
  const double n = equator_nodes;
  return std::min(n / 8.0, kMaxLongestCircumferenceNodes / n);
}

Ellipsoid ellipsoid_of(const ObjectSpec& object) {
  return {object.centre, rotation_matrix(object) * object.semi_axes.asDiagonal()};
}

double wall_gap(const Ellipsoid& object, const mesh::Box& box, int side, Vector3d* closest) {
  // The ellipsoid x = c + M u, |u| = 1, reaches furthest along e_y at
  // u = M^T e_y / |M^T e_y|: y_c + |M^T e_y| (half_extents' y).
  const Vector3d direction = object.map.row(1).transpose();  // M^T e_y
  const double extent = direction.norm();
  if (closest) *closest = object.centre + side * object.map * direction / extent;
  return box.height / 2 - side * object.centre.y() - extent;
}

double wall_gap(const ObjectSpec& object, const mesh::Box& box, int side, Vector3d* closest) {
  return wall_gap(ellipsoid_of(object), box, side, closest);
}

double wall_gap_element_size(const ObjectSpec& object, const MeshSizing& sizing, double gap) {
  const double h0 = interface_element_size(object, sizing);
  const int n = sizing.elements_across_gaps();
  // Unset, only the gaps the one-element rule of before refused are refined.
  const double refined_below = sizing.gap_elements ? n * h0 : h0;
  if (gap >= refined_below) return std::numeric_limits<double>::infinity();
  return gap / n;
}

double object_gap(const ObjectSpec& a, const ObjectSpec& b, const MeshSizing& sizing) {
  if (a.shape == ObjectShape::sphere && b.shape == ObjectShape::sphere)
    return (a.centre - b.centre).norm() - a.semi_axes.x() - b.semi_axes.x();
  const double h = std::max(interface_element_size(a, sizing), interface_element_size(b, sizing));
  return std::min(sampled_gap(a, b, h), sampled_gap(b, a, h));
}

double object_gap_element_size(const ObjectSpec& a, const ObjectSpec& b, const MeshSizing& sizing,
                               double gap) {
  const ObjectSpec& finer = interface_element_size(a, sizing) <= interface_element_size(b, sizing) ? a : b;
  return wall_gap_element_size(finer, sizing, gap);
}

double smallest_wall_gap(const ObjectSpec& object, const MeshSizing& sizing) {
  return sizing.elements_across_gaps() * interface_element_size(object, sizing) / kMaxGapRefinement;
}

void validate(const ShearCellSpec& spec) {
  validate_box(spec.box);
  validate_sizing(spec.sizing);
  if (spec.sizing.point_symmetric_start) check_symmetric_start(spec);
  for (int k = 0; k < static_cast<int>(spec.objects.size()); ++k) {
    validate_shape(k, spec.objects[k]);
    if (spec.sizing.point_symmetric && !spec.sizing.point_symmetric_start)
      check_point_symmetric(k, spec.objects[k]);
    check_resolution(k, spec.objects[k], spec.sizing);
    const double h = interface_element_size(spec.objects[k], spec.sizing);
    check_wall(k, spec.objects[k], spec.box, spec.sizing);
    for (int axis : {0, 2}) check_axis(k, spec.objects[k], spec.box, axis, h);
  }
  for (int j = 1; j < static_cast<int>(spec.objects.size()); ++j)
    for (int i = 0; i < j; ++i) check_pair(i, j, spec);
}

// ---------------------------------------------------------------------------
// Geometry (OCC); the gmsh session, size field and mesh reading are
// gmsh_mesh.cpp's, shared with remesh()
// ---------------------------------------------------------------------------

namespace {

using detail::CellEntities;
using detail::GmshSession;

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
  // Many coarse objects keep the curved-element optimiser busy. Measured (50
  // spheres of R = 1 in a 24 x 22 x 24 cell, docs/emulsions.md): more than 10
  // minutes at 12 equator nodes and more than 2.5 at 14, 13 s at 16 and 11 s
  // at 20: a sphere this coarse has one vertex inside it, so its interior
  // tetrahedra span it and its curved faces fold them; the optimiser untangles
  // them blob by blob. Without the optimiser such meshes come out inverted.
  const std::size_t count = spec.objects.size();
  if (sizing.optimize_high_order && count >= 5) {
    causes.push_back(fmt::format(
        "with {} objects, gmsh's curved-element optimiser (mesh.optimize_high_order = true) can "
        "take many minutes on coarse objects (50 spheres: more than 10 at 12 equator nodes, 13 s at 16)",
        count));
    fixes.push_back(fmt::format(
        "a larger mesh.equator_nodes (now {}; 16 or more): coarse curved elements give the optimiser "
        "more to untangle; or mesh.optimize_high_order = false (then check the minimum quality "
        "`softflow mesh` reports: coarse objects come out inverted without it)",
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

namespace {

/// One gmsh meshing of the cell, with `embedded` made vertices of their regions.
mesh::Mesh mesh_cell(const ShearCellSpec& spec,
                     const std::vector<detail::EmbeddedPoint>& embedded) {
  mesh::Mesh m;
  GmshSession session;
  CellEntities entities;
  const bool symmetric = spec.sizing.point_symmetric;
  session.run("building the geometry", [&] {
    entities = symmetric ? build_half_geometry(spec) : build_geometry(spec);
    if (!embedded.empty()) detail::embed_points(entities, embedded, detail::Kernel::occ);
  });
  session.run("setting periodicity and mesh size", [&] {
    detail::set_periodicity(spec.box, entities);
    if (symmetric) set_half_turn_periodicity(entities);
    detail::set_size_and_order(spec);
  });
  try {
    const double seconds = slow_meshing_note_seconds();
    const SlowStageNote note(seconds, slow_meshing_note(spec, seconds));
    session.run("meshing", [] { gmsh::model::mesh::generate(3); });
  } catch (const MeshError& e) {
    throw MeshError(fmt::format("{}. {}", e.what(), meshing_advice(spec.sizing)));
  }
  std::vector<int> cut_nodes;
  session.run("reading the mesh",
              [&] { m = detail::read_mesh(spec, entities, symmetric ? &cut_nodes : nullptr); });
  if (symmetric) m = complete_by_half_turn(m, cut_nodes);
  return m;
}

}  // namespace

mesh::Mesh build_shear_cell(const ShearCellSpec& spec, MeshReport* report) {
  validate(spec);
  if (spec.sizing.point_symmetric_start) return build_shear_cell(symmetric_start(spec), report);
  const auto start = std::chrono::steady_clock::now();
  mesh::Mesh m = mesh_cell(spec, {});
  // A tetrahedron lying flat on an interface with all four vertices on it
  // (a cap, detail::cap_points) can fold once the interface is curved, and
  // gmsh's optimiser cannot lift it (random emulsions at phi = 0.2: three
  // seeds of five had such caps, at quality -1). The mesh is then made
  // again with a vertex below every poor cap. Only a folded mesh is made
  // again: a mesh that came out valid stays as it was (its fingerprint too).
  // The half-turn-symmetric mesher would need each point's image: left out.
  std::vector<detail::EmbeddedPoint> embedded;
  double q = mesh::min_quality(m);
  for (int attempt = 0; q <= 0.0 && attempt < detail::kCapAttempts && !spec.sizing.point_symmetric;
       ++attempt) {
    const auto caps = detail::cap_points(m, detail::kCapQuality);
    if (caps.empty()) break;
    embedded.insert(embedded.end(), caps.begin(), caps.end());
    m = mesh_cell(spec, embedded);
    q = mesh::min_quality(m);
  }
  mesh::renumber_nodes_spatially(m);  // compact per-rank node ranges, local element loops
  detail::verify_periodic(m);
  if (q <= 0.0)
    detail::check_quality(m, spec.sizing.optimize_high_order);  // throws, naming where it folds
  if (report) {
    *report = make_report(m, spec, q,
                          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    report->cap_vertices = static_cast<int>(embedded.size());
  }
  return m;
}

WallGapResolution measure_wall_gap(const mesh::Mesh& m, const Ellipsoid& object) {
  WallGapResolution r;
  r.side = wall_gap(object, m.box, 1) <= wall_gap(object, m.box, -1) ? 1 : -1;
  Vector3d p;
  r.gap = wall_gap(object, m.box, r.side, &p);
  if (!(r.gap > 0.0)) return r;
  const Vector3d q(p.x(), r.side * m.box.height / 2, p.z());  // the segment p -> q, along y
  const WallGapResolution crossed = measure_segment(m, p, q);
  r.tets_crossed = crossed.tets_crossed;
  r.mean_edge = crossed.mean_edge;
  return r;
}

WallGapResolution measure_wall_gap(const mesh::Mesh& m, const ObjectSpec& object) {
  return measure_wall_gap(m, ellipsoid_of(object));
}

WallGapResolution measure_segment(const mesh::Mesh& m, const Vector3d& p, const Vector3d& q) {
  WallGapResolution r;
  r.gap = (q - p).norm();
  const Vector3d seg_lo = p.cwiseMin(q), seg_hi = p.cwiseMax(q);
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
    if ((hi.array() < seg_lo.array()).any() || (lo.array() > seg_hi.array()).any()) continue;
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
