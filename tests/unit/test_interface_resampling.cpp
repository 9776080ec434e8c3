// An interface sampled afresh (geometry::resample_interface, issue 31): the
// same curved surface to its own interpolation error, the same enclosed
// volume to round-off, triangles of the sizes asked for; and a remesh that
// resamples only the interfaces that no longer fit their sizes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/element/isoparametric.hpp"
#include "softflow/element/quadrature.hpp"
#include "softflow/geometry/interface_surface.hpp"
#include "softflow/geometry/remesh.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/physics/interface/interface_mesh.hpp"

using namespace softflow;
using Eigen::Vector3d;

namespace {

const Vector3d kCentre(0.1, -0.05, 0.07);

// A unit sphere in a periodic 5 x 5 x 5 cell, `equator_nodes` P2 nodes round its equator.
geometry::ShearCellSpec sphere_cell(int equator_nodes) {
  geometry::ShearCellSpec s;
  s.box = {5, 5, 5, true, true};
  geometry::ObjectSpec o;
  o.centre = kCentre;
  o.semi_axes = Vector3d::Ones();
  s.objects = {o};
  s.sizing.equator_nodes = equator_nodes;
  s.sizing.far_size = 1.0;
  s.sizing.growth = 0.3;
  return s;
}

// Largest | |x - c| - 1 | over the nodes of a surface, or over a grid of
// 91 points on each of its curved triangles: how far it is from the sphere.
double sphere_deviation(const geometry::InterfaceSurface& s, bool nodes_only) {
  double worst = 0.0;
  constexpr int kDivisions = 12;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const auto x = s.triangle_nodes(static_cast<int>(t));
    for (const Vector3d& p : x) worst = std::max(worst, std::abs((p - kCentre).norm() - 1.0));
    if (nodes_only) continue;
    element::TriangleNodes columns;
    for (int k = 0; k < 6; ++k) columns.col(k) = x[k];
    for (int i = 0; i <= kDivisions; ++i)
      for (int j = 0; i + j <= kDivisions; ++j) {
        const Vector3d xi(double(i) / kDivisions, double(j) / kDivisions, 0.0);
        worst = std::max(
            worst, std::abs((element::surface_point(columns, xi).position - kCentre).norm() - 1.0));
      }
  }
  return worst;
}

double min_triangle_shape(const geometry::InterfaceSurface& s) {
  double worst = 1.0;
  for (const auto& t : s.triangles)
    worst =
        std::min(worst, mesh::triangle_shape(s.vertices[t[0]], s.vertices[t[1]], s.vertices[t[2]]));
  return worst;
}

}  // namespace

TEST(InterfaceSurface, ItsVolumeAndAreaAreTheTrackersOwn) {
  const auto m = geometry::build_shear_cell(sphere_cell(16));
  const auto s = geometry::interface_surface(m, 1);
  const auto tracked = physics::extract_interface(m, 1);
  const auto integrals =
      physics::surface_integrals(tracked, physics::interface_positions(tracked, m));
  EXPECT_EQ(s.triangles.size(), tracked.triangles.size());
  EXPECT_NEAR(geometry::enclosed_volume(s), integrals.volume, 1e-13 * integrals.volume);
  EXPECT_NEAR(geometry::surface_area(s), integrals.area, 1e-13 * integrals.area);
}

// Finer and coarser than the mesh's own interface: every new node lies on
// the old curved surface (so no farther from the sphere than that surface
// is), the volume is the old one to round-off, and the triangles have the
// sizes asked for.
TEST(InterfaceResampling, KeepsTheSurfaceAndItsVolumeAtTheSizesAskedFor) {
  const auto m = geometry::build_shear_cell(sphere_cell(24));
  const auto old = geometry::interface_surface(m, 1);
  const double old_deviation = sphere_deviation(old, false);
  const double volume = geometry::enclosed_volume(old);
  for (double h : {0.15, 0.5}) {
    const auto size = [h](const Vector3d&) { return h; };
    geometry::ResamplingReport r;
    const auto s = geometry::resample_interface(old, size, &r);
    const auto fit = geometry::interface_fit(s, size);
    std::printf(
        "h %.2f: %d -> %d triangles, fit %.2f / %.3f, nodes off the sphere %.2e (old surface "
        "%.2e), "
        "volume offset %.2e h, volume %.1e\n",
        h, r.triangles_before, r.triangles_after, fit.size_mismatch, fit.curved_shape,
        sphere_deviation(s, true), old_deviation, r.volume_offset, r.volume_change);
    // A closed surface of genus 0 (V - E + F = 2 with E = 3F/2), every vertex used.
    EXPECT_EQ(s.vertices.size(), s.triangles.size() / 2 + 2);
    EXPECT_NEAR(geometry::enclosed_volume(s), volume, 1e-13 * volume);
    EXPECT_LT(r.volume_change, 1e-13);
    EXPECT_LE(sphere_deviation(s, true), old_deviation + r.volume_offset * h + 1e-12);
    EXPECT_FALSE(geometry::needs_resampling(fit));
    EXPECT_GT(min_triangle_shape(s), 0.5);
    // Triangles of side h tile the area 4 pi: about 4 pi / (sqrt(3)/4 h^2).
    const double expected = 4.0 * M_PI / (std::sqrt(3.0) / 4.0 * h * h);
    EXPECT_GT(r.triangles_after, 0.6 * expected);
    EXPECT_LT(r.triangles_after, 1.6 * expected);
  }
}

// Fresh meshes fit their sizes: `auto` leaves them alone.
TEST(InterfaceResampling, AFreshInterfaceFitsItsSizes) {
  for (int nodes : {12, 20, 32}) {
    const auto spec = sphere_cell(nodes);
    const auto m = geometry::build_shear_cell(spec);
    const double h0 = geometry::interface_element_size(spec.objects[0], spec.sizing);
    const auto fit = geometry::interface_fit(geometry::interface_surface(m, 1),
                                             [h0](const Vector3d&) { return h0; });
    std::printf("%d equator nodes: size mismatch %.2f, curved shape %.3f\n", nodes,
                fit.size_mismatch, fit.curved_shape);
    EXPECT_FALSE(geometry::needs_resampling(fit)) << nodes << " equator nodes";
  }
}

// A sphere meshed next to a wall (its interface refined towards the narrow
// gap) that has moved to the middle of the cell: its interface no longer
// fits the sizes of where it is. `auto` resamples it, and only it; the new
// cell is valid, the volume the old one to round-off.
TEST(InterfaceResampling, ARemeshResamplesAnInterfaceRefinedForAGapItHasLeft) {
  geometry::ShearCellSpec near = sphere_cell(16);
  near.box = {6, 3, 6, true, true};
  near.objects[0].centre = Vector3d(0.0, 0.3, 0.0);  // 0.2 from the upper wall
  near.sizing.gap_elements = 3;
  mesh::Mesh m = geometry::build_shear_cell(near);
  // The sphere moves down by 0.3 to the centre plane; the matrix follows it
  // smoothly to nothing 1.2 from its surface.
  for (auto& x : m.nodes) {
    const double r = (x - near.objects[0].centre).norm();
    const double s = std::clamp((r - 1.0) / 1.2, 0.0, 1.0);
    x.y() -= 0.3 * std::pow(1.0 - s * s, 2);
  }
  geometry::ShearCellSpec centred = near;
  centred.objects[0].centre = Vector3d::Zero();
  const auto before = geometry::interface_surface(m, 1);
  const double volume = geometry::enclosed_volume(before);

  const auto kept = geometry::remesh(centred, m, geometry::InterfaceRemeshing::keep);
  const auto r = geometry::remesh(centred, m, geometry::InterfaceRemeshing::automatic);
  std::printf(
      "interface refined for a gap it has left: fit %.2f / %.3f; kept: quality %.3f, %d triangles; "
      "automatic: resampled %d, quality %.3f, %d -> %d triangles, %d -> %d nodes\n",
      r.report.fit_before[0].size_mismatch, r.report.fit_before[0].curved_shape,
      kept.report.quality_after, kept.report.interface_triangles_after, r.report.resampled[0],
      r.report.quality_after, r.report.interface_triangles_before,
      r.report.interface_triangles_after, kept.report.nodes_after, r.report.nodes_after);
  EXPECT_EQ(kept.report.resampled[0], 0);
  ASSERT_EQ(r.report.resampled[0], 1);
  EXPECT_LT(r.report.interface_triangles_after, r.report.interface_triangles_before);
  EXPECT_GT(r.report.quality_after, 0.0);
  EXPECT_NEAR(geometry::enclosed_volume(geometry::interface_surface(r.mesh, 1)), volume,
              1e-13 * volume);
  // No node of the old interface is carried: its nodes are new.
  EXPECT_TRUE(
      std::all_of(r.new_node_of_old.begin(), r.new_node_of_old.end(), [](int n) { return n < 0; }));
}
