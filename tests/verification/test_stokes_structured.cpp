// Stokes verification on structured meshes: exactness and convergence rates.
#include <cmath>

#include <gtest/gtest.h>

#include "support/exact_stokes.hpp"

using namespace softflow;
namespace test_support = softflow::test_support;
using Eigen::Vector3d;

namespace {

mesh::Box cube(double side) {
  mesh::Box b;
  b.length = b.height = b.width = side;
  b.periodic_x = b.periodic_z = false;
  return b;
}

// u = (y^2 + x, z^2 - 2y, x^2 + z), p = x + 2y - z: divergence free, in the
// P2/P1 space of a straight-sided mesh. f = -eta lap u + grad p.
test_support::ExactStokes quadratic_solution(double eta) {
  return {[](const Vector3d& x, int) {
            return Vector3d(x[1] * x[1] + x[0], x[2] * x[2] - 2 * x[1], x[0] * x[0] + x[2]);
          },
          [](const Vector3d& x, int) { return x[0] + 2 * x[1] - x[2]; },
          [eta](const Vector3d&, int) { return Vector3d(-2 * eta + 1, -2 * eta + 2, -2 * eta - 1); }};
}

// u = curl(0, 0, phi) with phi = sin x sin y cos z; lap u = -3u; p = sin(x + y + z).
test_support::ExactStokes trigonometric_solution(double eta) {
  auto u = [](const Vector3d& x, int) {
    return Vector3d(std::sin(x[0]) * std::cos(x[1]) * std::cos(x[2]),
                    -std::cos(x[0]) * std::sin(x[1]) * std::cos(x[2]), 0.0);
  };
  return {u, [](const Vector3d& x, int) { return std::sin(x[0] + x[1] + x[2]); },
          [eta, u](const Vector3d& x, int r) {
            return Vector3d(3 * eta * u(x, r) + std::cos(x[0] + x[1] + x[2]) * Vector3d::Ones());
          }};
}

}  // namespace

TEST(StokesExactness, QuadraticVelocityLinearPressureOnDistortedMesh) {
  auto mesh = mesh::structured_box(cube(2.0), 3, 3, 3);
  test_support::distort_affinely(mesh, 2.0 / 3, 0.25, 7);
  const double eta = 1.7;
  // Direct solve: round-off.
  const auto direct = test_support::solve_against_exact(mesh, quadratic_solution(eta), {eta});
  EXPECT_LT(direct.errors.velocity_max_nodal, 1e-10);
  EXPECT_LT(direct.errors.pressure_max_nodal, 1e-9);
  // Fieldsplit solve at rtol 1e-12: the same discrete solution to solver tolerance.
  const auto iterative = test_support::solve_against_exact(mesh, quadratic_solution(eta), {eta}, {},
                                                           la::SaddlePointMethod::iterative);
  EXPECT_LT(iterative.errors.velocity_max_nodal, 1e-8);
  EXPECT_LT(iterative.errors.pressure_max_nodal, 1e-6);
}

TEST(StokesExactness, LinearVelocityConstantPressureOnCurvedMesh) {
  // Isoparametric P2 reproduces fields linear in x on curved elements
  // (quadratic fields are reproduced only on straight-sided elements).
  auto mesh = mesh::structured_box(cube(2.0), 3, 3, 3);
  mesh::map_nodes(mesh, [](const Vector3d& x) { return test_support::curving_map(x, 0.15); });
  test_support::ExactStokes linear{
      [](const Vector3d& x, int) { return Vector3d(x[1] + 0.5 * x[0], 0.3 * x[2], -0.5 * x[2] + x[0]); },
      [](const Vector3d&, int) { return 0.25; }, [](const Vector3d&, int) { return Vector3d::Zero(); }};
  const auto run = test_support::solve_against_exact(mesh, linear, {1.0});
  EXPECT_LT(run.errors.velocity_max_nodal, 1e-10);
  EXPECT_LT(run.errors.pressure_max_nodal, 1e-9);
}

TEST(StokesConvergence, ManufacturedSolutionOnCurvedMeshesGivesOptimalRates) {
  // Velocity L2 ~ h^3, pressure L2 ~ h^2 for Taylor-Hood.
  std::vector<double> h, eu, ep;
  for (int n : {3, 6, 12}) {
    auto mesh = mesh::structured_box(cube(2.0), n, n, n);
    mesh::map_nodes(mesh, [](const Vector3d& x) { return test_support::curving_map(x, 0.15); });
    const auto run = test_support::solve_against_exact(mesh, trigonometric_solution(1.0), {1.0});
    h.push_back(2.0 / n);
    eu.push_back(run.errors.velocity_l2);
    ep.push_back(run.errors.pressure_l2);
    std::printf("n = %2d  dofs = %7d  |u - u_h| = %.3e  |p - p_h| = %.3e\n", n, run.n_dofs,
                run.errors.velocity_l2, run.errors.pressure_l2);
  }
  const double slope_u = std::log(eu[1] / eu[2]) / std::log(h[1] / h[2]);
  const double slope_p = std::log(ep[1] / ep[2]) / std::log(h[1] / h[2]);
  std::printf("slopes: velocity %.2f, pressure %.2f\n", slope_u, slope_p);
  EXPECT_GT(slope_u, 2.8);
  EXPECT_GT(slope_p, 1.8);
}

TEST(StokesExactness, PeriodicShearCellReproducesLinearShear) {
  // Walls at y = +-1 moving with +-1, periodic in x and z: u = (y, 0, 0), p = 0,
  // on a curved mesh, without and with an inner subdomain of equal viscosity
  // (exercises the doubled interface pressures and the periodic identification).
  mesh::Box box = cube(2.0);
  box.periodic_x = box.periodic_z = true;
  const test_support::ExactStokes shear{
      [](const Vector3d& x, int) { return Vector3d(x[1], 0, 0); },
      [](const Vector3d&, int) { return 0.0; }, [](const Vector3d&, int) { return Vector3d::Zero(); }};
  for (bool with_object : {false, true}) {
    SCOPED_TRACE(with_object ? "inner subdomain, lambda = 1" : "no object");
    auto mesh = mesh::structured_box(box, 4, 4, 4);
    mesh::map_nodes(mesh, [](const Vector3d& x) { return test_support::curving_map(x, 0.1); });
    if (with_object) {
      mesh.n_objects = 1;
      for (int t = 0; t < mesh.n_tets(); ++t) {
        Vector3d c = Vector3d::Zero();
        for (int k = 0; k < 4; ++k) c += mesh.nodes[mesh.tets[t][k]] / 4;
        if (c.cwiseAbs().maxCoeff() < 0.5) mesh.tet_region[t] = 1;
      }
    }
    const auto run = test_support::solve_against_exact(mesh, shear, {1.0, 1.0}, {0.0});
    EXPECT_LT(run.errors.velocity_max_nodal, 1e-11);
    EXPECT_LT(run.errors.pressure_max_nodal, 1e-10);
  }
}

TEST(StokesExactness, TwoPhaseShearAcrossAPlaneInterfaceWithViscosityContrast) {
  // Region 1 (y > 0, viscosity 4) over region 0 (viscosity 1): piecewise
  // linear shear u = (a_r y, 0, 0) with equal shear stress eta_r a_r, p = 0.
  mesh::Box box = cube(2.0);
  box.periodic_x = box.periodic_z = true;
  auto mesh = mesh::structured_box(box, 4, 4, 4);
  mesh.n_objects = 1;
  for (int t = 0; t < mesh.n_tets(); ++t) {
    double yc = 0;
    for (int k = 0; k < 4; ++k) yc += mesh.nodes[mesh.tets[t][k]].y() / 4;
    if (yc > 0) mesh.tet_region[t] = 1;
  }
  const double eta1 = 4.0, a0 = 1.0, a1 = a0 / eta1;
  const test_support::ExactStokes shear{
      [=](const Vector3d& x, int) { return Vector3d(x[1] < 0 ? a0 * x[1] : a1 * x[1], 0, 0); },
      [](const Vector3d&, int) { return 0.0; }, [](const Vector3d&, int) { return Vector3d::Zero(); }};
  const auto run = test_support::solve_against_exact(mesh, shear, {1.0, eta1}, {0.0});
  EXPECT_LT(run.errors.velocity_max_nodal, 1e-11);
  EXPECT_LT(run.errors.pressure_max_nodal, 1e-10);
}
