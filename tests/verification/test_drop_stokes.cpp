// Two-phase Stokes around a spherical drop meshed by gmsh: exact instantaneous
// field in shear for several viscosity ratios, and the static drop (Laplace).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "softflow/analysis/interface_measures.hpp"
#include "softflow/analysis/theory/drop_in_linear_flow.hpp"
#include "softflow/geometry/shear_cell.hpp"
#include "support/exact_stokes.hpp"

using namespace softflow;
namespace test_support = softflow::test_support;
using analysis::theory::DropInLinearFlow;
using Eigen::Vector3d;

namespace {

// A unit sphere in a box of side `side`; all box faces Dirichlet when not periodic.
geometry::ShearCellSpec drop_cell(double side, int equator_nodes, double far_size, bool periodic,
                                  double growth = 0.3) {
  geometry::ShearCellSpec spec;
  spec.box.length = spec.box.height = spec.box.width = side;
  spec.box.periodic_x = spec.box.periodic_z = periodic;
  spec.objects.push_back(geometry::ObjectSpec{});
  spec.sizing.equator_nodes = equator_nodes;
  spec.sizing.far_size = far_size;
  spec.sizing.growth = growth;
  return spec;
}

double slope(double e_coarse, double e_fine, double h_coarse, double h_fine) {
  return std::log(e_coarse / e_fine) / std::log(h_coarse / h_fine);
}

}  // namespace

class DropInShear : public ::testing::TestWithParam<double> {};

TEST_P(DropInShear, InstantaneousExactFieldConvergesUnderRefinement) {
  // One Stokes solve on a spherical interface in simple shear, the exact
  // velocity on the box faces, Gamma = 0.5 (Laplace jump 1 on R = 1).
  //
  // The refinement is uniform in shape (growth scaled with h0): with a fixed
  // growth the elements a little away from the drop barely shrink, and the
  // exterior disturbance (~ r^-2 .. r^-4, steep at r = 1) stays
  // pre-asymptotic; even its P2 interpolant then converges at only ~h^2.2.
  // At these resolutions (N = 24..48) the interpolant itself reaches slopes
  // ~2.75 (velocity L2) and ~2 (pressure L2); the finite-element error stays
  // within ~10 % of it (measured, docs/validation/stokes_drop.md). Pressure
  // is compared up to a constant: with velocity given on the whole boundary
  // it is determined only up to one, and pinning it at a vertex shifts the
  // discrete field by that vertex's own error.
  const double lambda = GetParam(), gamma = 0.5;
  const auto exact = DropInLinearFlow::simple_shear(DropInLinearFlow::Kind::instantaneous, lambda,
                                                    1.0, gamma);
  const test_support::ExactStokes fields{
      [&](const Vector3d& x, int region) { return exact.velocity(x, region == 1); },
      [&](const Vector3d& x, int region) { return exact.pressure(x, region == 1); }, nullptr};
  std::vector<double> h, eu, ep, jump_error;
  for (int n : {24, 36, 48}) {
    const double h0 = 2 * M_PI / (n / 2.0);
    const auto mesh = geometry::build_shear_cell(drop_cell(6.0, n, 2.5 * h0, false, 0.3 * 24 / n));
    physics::StokesSystem system(mesh, la::SaddlePointSettings{});
    physics::StokesProblem problem;
    problem.viscosity = {1.0, lambda};
    problem.interfacial_tension = {gamma};
    problem.boundary_velocity = [&](const Vector3d& x) { return exact.velocity(x, false); };
    problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
    problem.pressure_gauge_value = exact.pressure(mesh.nodes[problem.pressure_gauge_node], false);
    const auto result = system.solve(problem);
    const auto errors = fem::stokes_errors(mesh, system.dofs(), result.solution, fields.velocity,
                                           fields.pressure);
    const auto measures = analysis::object_measures(mesh, system.dofs(), result.solution);
    h.push_back(h0);
    eu.push_back(errors.velocity_l2);
    ep.push_back(errors.pressure_l2_mean_free);
    // Exact jump averaged over the sphere: 2 Gamma (the outer pressure averages to zero).
    jump_error.push_back(std::abs(measures[0].pressure_jump - 2 * gamma));
    std::printf("lambda %.1f  N %2d  unknowns %7d  |u-u_h| %.3e  |p-p_h|/const %.3e  jump %.6f (exact %.1f)\n",
                lambda, n, system.dofs().n_dofs(), errors.velocity_l2, errors.pressure_l2_mean_free,
                measures[0].pressure_jump, 2 * gamma);
  }
  const double su = slope(eu[1], eu[2], h[1], h[2]), sp = slope(ep[1], ep[2], h[1], h[2]);
  std::printf("lambda %.1f slopes (N 36 -> 48): velocity %.2f  pressure %.2f\n", lambda, su, sp);
  EXPECT_GT(slope(eu[0], eu[1], h[0], h[1]), 2.0);
  EXPECT_GT(su, 2.5);
  EXPECT_GT(sp, 1.7);
  EXPECT_LT(jump_error[2], 0.01 * 2 * gamma);
}

INSTANTIATE_TEST_SUITE_P(ViscosityRatios, DropInShear, ::testing::Values(0.5, 1.0, 5.0));

TEST(StaticDrop, LaplacePressureJumpAndSpuriousCurrentsFallWithRefinement) {
  // No flow, Gamma = 1, R = 1: p_drop - p_matrix = 2, u = 0 exactly; the
  // discrete curved interface leaves small spurious velocities.
  std::vector<double> max_u;
  for (int n : {16, 28, 40}) {
    const auto mesh = geometry::build_shear_cell(drop_cell(8.0, n, 2.0, true));
    physics::StokesSystem system(mesh, la::SaddlePointSettings{});
    physics::StokesProblem problem;
    problem.viscosity = {1.0, 1.0};
    problem.interfacial_tension = {1.0};
    problem.boundary_velocity = [](const Vector3d&) { return Vector3d::Zero(); };
    problem.pressure_gauge_node = physics::default_pressure_gauge_node(mesh);
    const auto result = system.solve(problem);
    const auto m = analysis::object_measures(mesh, system.dofs(), result.solution);
    const double u = analysis::max_velocity(system.dofs(), result.solution);
    max_u.push_back(u);
    std::printf("N %2d  unknowns %7d  jump %.6f  (2 Gamma/R = 2, rel. error %.2e)  max|u| %.3e\n", n,
                system.dofs().n_dofs(), m[0].pressure_jump, std::abs(m[0].pressure_jump - 2) / 2, u);
    if (n == 40) {
      EXPECT_NEAR(m[0].pressure_jump, 2.0, 0.005 * 2.0);  // default resolution
    }
  }
  EXPECT_LT(max_u[1], max_u[0]);
  EXPECT_LT(max_u[2], max_u[1]);
}
