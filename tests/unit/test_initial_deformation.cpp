// [[objects]] initial_deformation = "taylor": the sphere's mesh deformed into
// the steady ellipsoid of small-deformation theory before the first step.
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "softflow/analysis/ellipsoid_fit.hpp"
#include "softflow/analysis/theory/small_deformation.hpp"
#include "softflow/common/error.hpp"
#include "softflow/io/case_config.hpp"
#include "softflow/mesh/quality.hpp"
#include "softflow/simulation/run_support.hpp"
#include "support/input_errors.hpp"
#include "support/region_volumes.hpp"

namespace softflow {
namespace {

using test_support::region_volumes;

const std::string kDrop =
    "[cell]\nlength = 8.0\nheight = 8.0\nwidth = 8.0\n[mesh]\nequator_nodes = 12\n"
    "far_size = 3.0\n[[objects]]\ncentre = [0.5, 0.25, 0.0]\nviscosity_ratio = 2.0\n"
    "capillary_number = 0.15\n";

std::string error_of(const std::string& text) { return test_support::case_error_of(text); }

TEST(InitialDeformation, TheSpheresMeshBecomesTheTheorysEllipsoidWithItsVolume) {
  const io::CaseConfig sphere_case = io::parse_case(kDrop, "c.toml");
  const io::CaseConfig taylor_case =
      io::parse_case(kDrop + "initial_deformation = \"taylor\"\n", "c.toml");
  ASSERT_EQ(taylor_case.objects[0].initial_deformation, io::InitialDeformation::taylor);
  const mesh::Mesh sphere = simulation::build_mesh(sphere_case).mesh;
  const simulation::MeshedCase deformed = simulation::build_mesh(taylor_case);
  const mesh::Mesh& taylor = deformed.mesh;
  // The same mesh, nodes moved: the discretisation is the sphere's.
  ASSERT_EQ(taylor.n_nodes(), sphere.n_nodes());
  ASSERT_EQ(taylor.tets, sphere.tets);
  EXPECT_NEAR(region_volumes(taylor)[1], region_volumes(sphere)[1], 1e-12 * region_volumes(sphere)[1]);
  EXPECT_GT(mesh::min_quality(taylor), 0.0);
  // The interface nodes lie on the ellipsoid: semi-axes R s, R / s, R, the
  // long one at Chaffey-Brenner's angle in the shear plane.
  const double ca = 0.15, lambda = 2.0;
  const double d = analysis::theory::taylor_deformation(lambda, ca);
  const double theta = analysis::theory::chaffey_brenner_angle_deg(lambda, ca);
  const double s = std::sqrt((1.0 + d) / (1.0 - d));
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(theta * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d centre(0.5, 0.25, 0.0), semi_axes(s, 1.0 / s, 1.0);
  std::vector<Eigen::Vector3d> surface;
  for (const auto& face : taylor.interface_faces)
    for (int node : face) surface.push_back(taylor.nodes[node]);
  double worst = 0.0;
  for (const Eigen::Vector3d& x : surface) {
    const Eigen::Vector3d body = turn.transpose() * (x - centre);
    worst = std::max(worst, std::abs(body.cwiseQuotient(semi_axes).norm() - 1.0));
  }
  // The sphere's P2 nodes lie on the sphere to round-off, the map keeps that.
  EXPECT_LT(worst, 1e-12);
  const analysis::EllipsoidFit fit = analysis::fit_ellipsoid(surface);
  EXPECT_NEAR(fit.deformation, d, 1e-10);
  EXPECT_NEAR(fit.theta_deg, theta, 1e-8);
  // Walls and the liquid far away stay.
  for (const auto& face : sphere.boundary_faces)
    for (int node : face) EXPECT_EQ(taylor.nodes[node], sphere.nodes[node]);
  EXPECT_TRUE(deformed.report.contains("initial_deformation"));
}

TEST(InitialDeformation, TheMeshReportDescribesTheDeformedDropsWallGap) {
  // A drop close to the upper wall (gap 0.25 R, below one interface element:
  // gmsh refines it and the report measures it): after the Taylor start the
  // report's wall gap is the ellipsoid's, H/2 - y_c - (its half extent in
  // y), not the sphere's that gmsh meshed.
  const std::string text =
      "[cell]\nlength = 6.0\nheight = 3.0\nwidth = 6.0\n[mesh]\nequator_nodes = 12\n"
      "far_size = 2.0\n[[objects]]\ncentre = [0.0, 0.25, 0.0]\nviscosity_ratio = 1.0\n"
      "capillary_number = 0.2\ninitial_deformation = \"taylor\"\n";
  const simulation::MeshedCase deformed = simulation::build_mesh(io::parse_case(text, "c.toml"));
  ASSERT_TRUE(deformed.report.contains("wall_gap"));
  const double d = analysis::theory::taylor_deformation(1.0, 0.2);
  const double theta = analysis::theory::chaffey_brenner_angle_deg(1.0, 0.2) * M_PI / 180.0;
  const double s = std::sqrt((1.0 + d) / (1.0 - d));
  // The y extent of the turned ellipsoid: sqrt((s sin theta)^2 + (cos theta / s)^2).
  const double extent = std::hypot(s * std::sin(theta), std::cos(theta) / s);
  const double gap = 1.5 - 0.25 - extent;
  const double reported = deformed.report["wall_gap"]["gap"];
  EXPECT_NEAR(reported, gap, 1e-12);
  EXPECT_GT(std::abs(reported - 0.25), 1e-2);  // not the sphere's gap
  EXPECT_EQ(deformed.report["wall_gap"]["object"], 1);
  EXPECT_GT(deformed.report["wall_gap"]["tetrahedra_crossed"].get<int>(), 0);
  // The interface's highest node lies on the ellipsoid, at most at its top.
  double top = -1e300;
  for (const auto& face : deformed.mesh.interface_faces)
    for (int node : face) top = std::max(top, deformed.mesh.nodes[node].y());
  EXPECT_LE(top, 1.5 - gap + 1e-12);
  EXPECT_GT(top, 1.5 - gap - 0.05);
}

TEST(InitialDeformation, OnlyWhatTheTheoryDescribesIsAccepted) {
  EXPECT_EQ(error_of(kDrop + "initial_deformation = \"taylor\"\n"), "");
  EXPECT_NE(error_of(kDrop + "initial_deformation = \"round\"\n").find("objects[1].initial_deformation"),
            std::string::npos);
  std::string e = error_of(kDrop + "initial_deformation = \"taylor\"\nslip = 0.1\n");
  EXPECT_NE(e.find("objects[1].initial_deformation = \"taylor\": with slip > 0"), std::string::npos) << e;
  e = error_of(
      "[[objects]]\nmodel = \"neo_hookean\"\nelastic_capillary_number = 0.1\n"
      "initial_deformation = \"taylor\"\n");
  EXPECT_NE(e.find("a Newtonian drop's; model = \"neo_hookean\""), std::string::npos) << e;
  e = error_of("[flow]\ntype = \"oscillatory\"\nstrain_amplitude = 0.1\nfrequency = 1.0\n"
               "periods = 1\n[[objects]]\ninitial_deformation = \"taylor\"\n");
  EXPECT_NE(e.find("steady shape in steady shear"), std::string::npos) << e;
  e = error_of("[[objects]]\nshape = \"ellipsoid\"\nsemi_axes = [1.2, 1.0, 0.9]\n"
               "initial_deformation = \"taylor\"\n");
  EXPECT_NE(e.find("objects[1].initial_deformation"), std::string::npos) << e;
}

}  // namespace
}  // namespace softflow
