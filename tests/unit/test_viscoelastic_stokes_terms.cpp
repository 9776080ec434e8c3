// The D'Avino-Hulsen and DEVSS-G terms of the Stokes element
// (physics/stokes/viscoelastic_terms.hpp) against the weak form written
// out directly: for a velocity u linear in x (exact in P2), the element's
// matrix times u minus its load must equal, test function by test function,
//
//   integral D(v) : G (c_pred(u) - I) - theta integral D(v) : (G_n + G_n^T),
//
// with c_pred the whole prediction (ConformationPrediction with the full
// convection (u - u_m).grad c_n and L = grad u) and D(v) built as a 3 x 3
// tensor. This checks the split into matrix and load, the index order of
// every term and the signs, on curved (perturbed) elements.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "softflow/element/isoparametric.hpp"
#include "softflow/fem/field.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/stokes/viscoelastic_terms.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

using namespace softflow;
namespace ve = physics::viscoelastic;

namespace {

/// A uniform P2 function's coefficient vector of a linear field, element order.
Eigen::Matrix<double, 30, 1> element_velocity(const element::TetNodes& x, const Eigen::Matrix3d& a,
                                               const Eigen::Vector3d& b) {
  Eigen::Matrix<double, 30, 1> u;
  for (int k = 0; k < 10; ++k) u.segment<3>(3 * k) = a * x.col(k) + b;
  return u;
}

void check_model(const ve::Constitutive& model, bool devss) {
  auto mesh = mesh::structured_box({1.0, 1.0, 1.0, false, false}, 1, 1, 1);
  // Curve the elements: move every mid-edge node a little, smoothly.
  for (auto& p : mesh.nodes)
    p += 0.03 * Eigen::Vector3d(std::sin(3 * p.y()), std::sin(2 * p.z()), std::sin(4 * p.x()));
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  fem::Field c(mesh, "conformation", p1, 6), um(mesh, "mesh_velocity", p2, 3),
      gstar(mesh, "velocity_gradient", p1, 9);
  // c_n = I + a symmetric positive part varying linearly in x.
  c.interpolate([](const Eigen::Vector3d& x, int) {
    ve::Mat3 m;
    m << 1.5 + 0.2 * x.x(), 0.3 * x.y(), 0.1, 0.3 * x.y(), 1.1 + 0.1 * x.z(), -0.2 * x.x(), 0.1,
        -0.2 * x.x(), 0.9 + 0.3 * x.y();
    return Eigen::VectorXd(ve::pack_symmetric(m));
  });
  um.interpolate([](const Eigen::Vector3d& x, int) {
    return Eigen::VectorXd(Eigen::Vector3d(0.2 * x.y() * x.y(), -0.1 * x.z(), 0.3 * x.x()));
  });
  gstar.interpolate([](const Eigen::Vector3d& x, int) {
    Eigen::VectorXd g(9);
    for (int i = 0; i < 9; ++i) g(i) = 0.1 * (i + 1) + 0.05 * i * x.x() - 0.02 * x.z();
    return g;
  });
  physics::ViscoelasticCoupling coupling;
  coupling.models = {model};
  coupling.conformation = &c;
  coupling.mesh_velocity = &um;
  coupling.velocity_gradient = devss ? &gstar : nullptr;
  coupling.dt = 0.07;
  const double theta = coupling.devss_theta(0);
  if (devss) {
    EXPECT_GT(theta, 0.0);
  }

  Eigen::Matrix3d a;
  a << 0.3, 1.0, -0.2, 0.1, -0.5, 0.4, 0.7, -0.3, 0.2;
  const Eigen::Vector3d b(0.1, -0.2, 0.3);
  const fem::TetTabulation tab(4);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const auto points = fem::quadrature_points(mesh, tab, t);
    physics::TetMatrix ke = physics::TetMatrix::Zero();
    physics::TetVector fe = physics::TetVector::Zero();
    physics::add_viscoelastic_tet_terms(coupling, points, ke, fe);
    const auto x = fem::tet_nodes(mesh, t);
    const Eigen::Matrix<double, 30, 1> u = element_velocity(x, a, b);
    const Eigen::Matrix<double, 30, 1> discrete =
        ke.topLeftCorner<30, 30>() * u - fe.head<30>();
    EXPECT_EQ(ke.rightCols<4>().norm() + ke.bottomRows<4>().norm(), 0.0);  // velocity block only

    Eigen::Matrix<double, 30, 1> direct = Eigen::Matrix<double, 30, 1>::Zero();
    for (const auto& p : points) {
      const Eigen::Matrix<double, 10, 3> g = element::physical_gradients<10>(tab.p2_grad[p.q], p.map);
      const ve::Mat3 cn = ve::unpack_symmetric(c.value(p));
      std::array<ve::Mat3, 3> grad_c;
      const Eigen::MatrixXd gc = c.gradient(p);
      for (int d = 0; d < 3; ++d) grad_c[d] = ve::unpack_symmetric(gc.col(d));
      const Eigen::Vector3d w = a * p.x + b - Eigen::Vector3d(um.value(p));
      const ve::ConformationPrediction prediction(model, cn, ve::convective_derivative(w, grad_c),
                                                  coupling.dt);
      const ve::Mat3 tau = model.modulus() * (prediction(a) - ve::Mat3::Identity());
      const Eigen::VectorXd gv = gstar.value(p);
      ve::Mat3 gs;
      gs << gv(0), gv(1), gv(2), gv(3), gv(4), gv(5), gv(6), gv(7), gv(8);
      const ve::Mat3 devss_stress = devss ? ve::Mat3(theta * (gs + gs.transpose())) : ve::Mat3::Zero();
      for (int k = 0; k < 10; ++k)
        for (int comp = 0; comp < 3; ++comp) {
          ve::Mat3 grad_v = ve::Mat3::Zero();  // (grad v)_ij = dv_i/dx_j, v = N_k e_comp
          grad_v.row(comp) = g.row(k);
          const ve::Mat3 dv = 0.5 * (grad_v + grad_v.transpose());
          direct(3 * k + comp) += p.weight * (dv.cwiseProduct(tau - devss_stress)).sum();
        }
    }
    EXPECT_LT((discrete - direct).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + direct.cwiseAbs().maxCoeff()))
        << ve::to_string(model.model()) << " tet " << t;
  }
}

}  // namespace

TEST(ViscoelasticStokesTerms, MatrixAndLoadReproduceThePredictedStress) {
  check_model(ve::Constitutive::oldroyd_b(0.3, 2.0, 1.5), false);
  check_model(ve::Constitutive::oldroyd_b(0.3, 2.0, 1.5), true);
  check_model(ve::Constitutive::giesekus(0.0, 1.0, 0.8, 0.2), true);
  check_model(ve::Constitutive::neo_hookean(3.0), true);
}

TEST(ViscoelasticStokesTerms, DevssThetaAndStepViscosity) {
  physics::ViscoelasticCoupling coupling;
  coupling.models = {ve::Constitutive::newtonian(2.0), ve::Constitutive::ucm(4.0, 0.5),
                     ve::Constitutive::kelvin_voigt(0.1, 10.0)};
  coupling.dt = 0.01;
  auto mesh = mesh::structured_box({1.0, 1.0, 1.0, false, false}, 1, 1, 1);
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  fem::Field c(mesh, "conformation", p1, 6), g(mesh, "velocity_gradient", p1, 9);
  coupling.conformation = &c;
  // No projected gradient yet (first step): no DEVSS term anywhere.
  EXPECT_EQ(coupling.devss_theta(1), 0.0);
  EXPECT_DOUBLE_EQ(coupling.step_viscosity(1), 4.0 * 0.01);  // UCM: mu = 0, G dt
  coupling.velocity_gradient = &g;
  EXPECT_EQ(coupling.devss_theta(0), 0.0);                   // Newtonian: none
  EXPECT_DOUBLE_EQ(coupling.devss_theta(1), 2.0);            // eta_p = G lambda
  EXPECT_DOUBLE_EQ(coupling.devss_theta(2), 10.0 * 0.01);    // solid: G dt
  EXPECT_DOUBLE_EQ(coupling.step_viscosity(0), 2.0);
  EXPECT_DOUBLE_EQ(coupling.step_viscosity(2), 0.1 + 0.1 + 0.1);
}
