// Finite-element functions on the curved mesh: interpolation, values and
// gradients at quadrature points, point evaluation, transfer from a composed
// dof map, L2 projection. (The assembly they rest on: test_csr_matrix.cpp.)
//
// MPI-agnostic: every check is made on the elements a rank owns.
#include <cmath>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/fem/field.hpp"
#include "support/verification/curved_box.hpp"
#include "softflow/physics/stokes/stokes_system.hpp"

using namespace softflow;
using Eigen::Vector3d;
using Eigen::VectorXd;

namespace {

mesh::Mesh curved_box(int n, double amplitude = 0.08) {
  return verification::curved_box_with_block(n, amplitude);
}

VectorXd linear(const Vector3d& x, int region) {
  VectorXd v(2);
  v << 1.0 + 2.0 * x.x() - 3.0 * x.y() + 0.5 * x.z(), region - x.x() + 4.0 * x.z();
  return v;
}

Eigen::MatrixXd linear_gradient(int) {
  Eigen::MatrixXd g(2, 3);
  g << 2.0, -3.0, 0.5, -1.0, 0.0, 4.0;
  return g;
}

double quadratic(const Vector3d& x) { return x.x() * x.y() - 2.0 * x.z() * x.z() + x.x(); }
Vector3d quadratic_gradient(const Vector3d& x) {
  return {x.y() + 1.0, x.x(), -4.0 * x.z()};
}

}  // namespace

TEST(Field, LinearFieldsAreExactInP2OnCurvedAndInP1OnStraightElements) {
  // The isoparametric property: sum_k x_k N_k(xi) = x, so functions linear
  // in x are P2 functions, values and gradients, also on curved elements. A
  // P1 function lambda_i(xi(x)) is linear in x only where the map is affine.
  const fem::TetTabulation tab(4);
  for (int degree : {1, 2})
    for (auto continuity : {fem::Continuity::continuous, fem::Continuity::per_region}) {
      const auto mesh = curved_box(3, degree == 2 ? 0.08 : 0.0);
      auto space = std::make_shared<fem::Space>(mesh, degree, continuity);
      fem::Field u(mesh, "u", space, 2);
      // A continuous space can only hold a field that agrees across the
      // interface: the region term then goes.
      const bool jumps = continuity == fem::Continuity::per_region;
      u.interpolate([&](const Vector3d& x, int r) { return linear(x, jumps ? r : 0); });
      double error = 0.0;
      for (int t : u.owned_elements())
        for (const auto& p : fem::quadrature_points(mesh, tab, t)) {
          const int r = jumps ? p.region : 0;
          error = std::max(error, (u.value(p) - linear(p.x, r)).cwiseAbs().maxCoeff());
          error = std::max(error, (u.gradient(p) - linear_gradient(r)).cwiseAbs().maxCoeff());
        }
      EXPECT_LT(error, 1e-12) << space->describe();
    }
}

TEST(Field, AFullTensorOnP2FillsThePointValuesCapacityAndMoreComponentsAreRefused) {
  // Values at points have a fixed capacity (fem::kMaxFieldComponents, no heap):
  // the largest field, nine components on P2, still evaluates exactly.
  const fem::TetTabulation tab(4);
  const auto mesh = curved_box(2);
  auto space = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  fem::Field tensor(mesh, "grad_u", space, fem::kMaxFieldComponents);
  Eigen::Matrix<double, 9, 3> slope;
  for (int c = 0; c < 9; ++c) slope.row(c) << c + 1.0, -0.5 * c, 2.0 - c;
  tensor.interpolate([&](const Vector3d& x, int) -> VectorXd { return slope * x; });
  double error = 0.0;
  for (int t : tensor.owned_elements())
    for (const auto& p : fem::quadrature_points(mesh, tab, t)) {
      const fem::PointValue v = tensor.value(p);
      ASSERT_EQ(v.size(), 9);
      error = std::max(error, (v - slope * p.x).cwiseAbs().maxCoeff());
      error = std::max(error, (tensor.gradient(p) - slope).cwiseAbs().maxCoeff());
    }
  EXPECT_LT(error, 1e-12);
  EXPECT_THROW(fem::Field(mesh, "too_many", space, fem::kMaxFieldComponents + 1), Error);
  EXPECT_THROW(fem::Field(mesh, "none", space, 0), Error);
}

TEST(Field, QuadraticsAreExactOnStraightElementsAndConvergeOnCurvedOnes) {
  // A quadratic in x is a P2 function only where the map is affine; on a
  // curved element it is quartic in xi, so interpolation is not exact there
  // and its gradient error falls like h^2.
  const fem::TetTabulation tab(5);
  auto max_gradient_error = [&](const mesh::Mesh& mesh) {
    fem::Field u(mesh, "u", std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous), 1);
    u.interpolate([](const Vector3d& x, int) { return VectorXd::Constant(1, quadratic(x)); });
    double value = 0.0, gradient = 0.0;
    for (int t : u.owned_elements())
      for (const auto& p : fem::quadrature_points(mesh, tab, t)) {
        value = std::max(value, std::abs(u.value(p)(0) - quadratic(p.x)));
        gradient = std::max(gradient,
                            (u.gradient(p).row(0).transpose() - quadratic_gradient(p.x)).norm());
      }
    double local[2] = {value, gradient}, global[2];
    MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    return std::pair{global[0], global[1]};
  };
  const auto straight = max_gradient_error(curved_box(2, 0.0));
  EXPECT_LT(straight.first, 1e-13);
  EXPECT_LT(straight.second, 1e-12);
  const auto coarse = max_gradient_error(curved_box(8));
  const auto fine = max_gradient_error(curved_box(16));
  EXPECT_GT(coarse.second, 1e-4);  // curved: not exact
  // Measured max gradient errors at n = 4, 8, 16: 0.111, 0.0339, 0.00888
  // (local orders 1.71, 1.93 -> 2).
  EXPECT_GT(std::log2(coarse.second / fine.second), 1.85);
}

TEST(Field, PointEvaluationFindsTheCurvedElementAndItsReferencePoint) {
  const auto mesh = curved_box(3);
  fem::Field u(mesh, "u", std::make_shared<fem::Space>(mesh, 2, fem::Continuity::per_region), 2);
  u.interpolate(linear);
  for (const Vector3d& x : {Vector3d(0.1, 0.2, -0.3), Vector3d(-0.8, 0.65, 0.7),
                           Vector3d(0.9, -0.9, 0.05)}) {
    const auto value = u.value_at_point(x);
    if (!value) continue;  // on another rank
    const auto where = u.locate(x);
    EXPECT_NEAR((*value - linear(x, mesh.tet_region[where->tet])).norm(), 0.0, 1e-11);
  }
  if (u.ownership().size() == u.dofs().n_dofs()) {  // serial: every point is found
    EXPECT_TRUE(u.value_at_point(Vector3d(0.3, 0.3, 0.3)).has_value());
    EXPECT_FALSE(u.value_at_point(Vector3d(1.5, 0.0, 0.0)).has_value());
  }
}

TEST(Field, TakesItsValuesOutOfAComposedSolutionAndGathersThemBack) {
  const auto mesh = curved_box(2);
  const auto stokes = physics::make_stokes_dof_map(mesh, false);
  std::vector<double> solution(stokes.n_dofs());
  for (int d = 0; d < stokes.n_dofs(); ++d)
    solution[d] = stokes.field_of(d) == physics::kVelocityField
                      ? mesh.nodes[stokes.node_of(d)](stokes.component_of(d))
                      : 10.0 + stokes.region_of(d);
  fem::Field u(mesh, "velocity", stokes.field(physics::kVelocityField).space, 3);
  fem::Field p(mesh, "pressure", stokes.field(physics::kPressureField).space, 1);
  u.assign_from(stokes, physics::kVelocityField, solution);
  p.assign_from(stokes, physics::kPressureField, solution);
  const fem::TetTabulation tab(2);
  for (int t : u.owned_elements())
    for (const auto& q : fem::quadrature_points(mesh, tab, t)) {
      EXPECT_NEAR((u.value(q) - q.x).norm(), 0.0, 1e-12);
      EXPECT_NEAR((u.gradient(q) - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-11);
    }
  for (int t : p.owned_elements())
    for (const auto& q : fem::quadrature_points(mesh, tab, t))
      EXPECT_DOUBLE_EQ(p.value(q)(0), 10.0 + q.region);

  auto all = u.gather();
  ASSERT_EQ(static_cast<int>(all.size()), u.dofs().n_dofs());
  for (double& v : all) v *= 2.0;
  u.scatter(all);
  for (int t : u.owned_elements())
    for (const auto& q : fem::quadrature_points(mesh, tab, t))
      EXPECT_NEAR((u.value(q) - 2.0 * q.x).norm(), 0.0, 1e-12);
}

TEST(L2Projection, ReproducesAFunctionOfTheSpaceAndProjectsGradients) {
  const auto mesh = curved_box(3);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  fem::Field u(mesh, "u", p2, 1);
  u.interpolate([](const Vector3d& x, int) { return VectorXd::Constant(1, quadratic(x)); });
  // (1) Projecting u_h onto its own space gives u_h back.
  fem::Field w(mesh, "w", p2, 1);
  fem::l2_project([&](const fem::QuadraturePoint& q) { return u.value(q); }, w, 6);
  EXPECT_LT((VectorXd::Map(w.gather().data(), w.dofs().n_dofs()) -
             VectorXd::Map(u.gather().data(), u.dofs().n_dofs()))
                .cwiseAbs()
                .maxCoeff(),
            1e-9);
  // (2) The projected gradient of a field linear in x (DEVSS-G's G of a
  // linear velocity) is that gradient, exactly, in every region.
  fem::Field v(mesh, "v", p2, 2);
  v.interpolate([](const Vector3d& x, int) { return linear(x, 0); });
  fem::Field g(mesh, "G", p1, 6);
  fem::l2_project(
      [&](const fem::QuadraturePoint& q) {
        const Eigen::MatrixXd grad = v.gradient(q);
        return VectorXd(Eigen::Map<const VectorXd>(grad.data(), 6));
      },
      g);
  const fem::TetTabulation tab(3);
  const Eigen::MatrixXd exact = linear_gradient(0);
  for (int t : g.owned_elements())
    for (const auto& q : fem::quadrature_points(mesh, tab, t))
      EXPECT_LT((g.value(q) - Eigen::Map<const VectorXd>(exact.data(), 6)).norm(), 1e-9);
}

TEST(L2Projection, ConvergesAtTheOrderOfTheSpace) {
  // ||u - P u|| = O(h^(p+1)) for smooth u: 3 for P2, 2 for P1, on curved meshes.
  auto smooth = [](const Vector3d& x) { return std::sin(2.0 * x.x()) * std::cos(x.y() + x.z()); };
  auto error = [&](int n, int degree) {
    const auto mesh = curved_box(n);
    fem::Field u(mesh, "u", std::make_shared<fem::Space>(mesh, degree, fem::Continuity::per_region),
                 1);
    fem::l2_project([&](const fem::QuadraturePoint& q) { return VectorXd::Constant(1, smooth(q.x)); },
                    u, 6);
    const fem::TetTabulation tab(6);
    double e2 = 0.0;
    for (int t : u.owned_elements())
      for (const auto& q : fem::quadrature_points(mesh, tab, t))
        e2 += q.weight * std::pow(u.value(q)(0) - smooth(q.x), 2);
    double total = 0.0;
    MPI_Allreduce(&e2, &total, 1, MPI_DOUBLE, MPI_SUM, PETSC_COMM_WORLD);
    return std::sqrt(total);
  };
  // Measured at n = 4, 8, 16: P1 0.112, 0.0278, 0.00669 (orders 2.01,
  // 2.05); P2 0.0153, 0.00239, 0.000343 (2.68, 2.80 -> 3, the curved map's
  // distortion at these coarse levels slowing the approach).
  EXPECT_GT(std::log2(error(4, 1) / error(8, 1)), 1.85);
  EXPECT_GT(std::log2(error(8, 2) / error(16, 2)), 2.7);
}


TEST(StokesAssembly, NoMatrixRowCrossesRanks) {
  // Each rank assembles its own rows of every element with one (cut
  // elements on both sides), so the operator and the iterative method's
  // Schur matrix never route rows through PETSc: on 2 ranks (mpi_fem_layer)
  // the curved box is cut through its elements. Before, an element went to
  // the rank of its first vertex and sent its other rows.
  const auto mesh = curved_box(4);
  for (const bool slip : {false, true}) {
    la::SaddlePointSettings settings;
    settings.method = la::SaddlePointMethod::iterative;
    physics::StokesSystem system(mesh, settings, slip);
    EXPECT_FALSE(system.assembly_crosses_ranks()) << "slip " << slip;
  }
}
