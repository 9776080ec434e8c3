// The constitutive laws behind one interface (physics/viscoelastic/
// constitutive_law.hpp): each model's stress, relaxation and log-form
// relaxation against the formulas written out by hand, FENE-P's limit
// L^2 -> infinity (Oldroyd-B), its linearised stress, its domain, its
// parameters and keys, the identity a checkpoint saves, and the Stokes
// kernel with a stress that is not affine in c.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/element/isoparametric.hpp"
#include "softflow/fem/field.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/stokes/viscoelastic_terms.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"
#include "softflow/physics/viscoelastic/log_conformation.hpp"

using namespace softflow;
namespace ve = physics::viscoelastic;
using ve::Constitutive;
using ve::ConstitutiveModel;
using ve::Mat3;
using ve::Vec3;

namespace {

const Mat3 kI = Mat3::Identity();

double max_abs(const Mat3& a) { return a.cwiseAbs().maxCoeff(); }

/// A generic SPD conformation (distinct eigenvalues, not axis-aligned), tr c ~ 5.6.
Mat3 sample_c() {
  Mat3 c;
  c << 2.1, 0.4, -0.3,  //
      0.4, 1.5, 0.2,    //
      -0.3, 0.2, 2.0;
  return c;
}

Constitutive fene_p(double mu, double g, double lambda, double l2) {
  return Constitutive::create(ConstitutiveModel::fene_p, {.solvent_viscosity = mu,
                                                          .modulus = g,
                                                          .relaxation_time = lambda,
                                                          .extensibility = l2});
}

/// c^{-1} r(c) from the law's eigenvalues g_i/lambda in the eigenbasis of log c.
Mat3 log_relaxation_matrix(const Constitutive& model, const Mat3& c) {
  const auto s = ve::symmetric_eigen(ve::matrix_log(c));
  return ve::from_eigen(s.vectors, model.law().log_relaxation(s.values));
}

}  // namespace

TEST(ConstitutiveLaws, StressesAndRelaxationsMatchTheirFormulas) {
  const Mat3 c = sample_c();
  const Mat3 a = c - kI;
  // Oldroyd-B, UCM, Giesekus: tau = G (c - I), r = -((c - I) + alpha (c - I)^2)/lambda (eqs. 2.6-2.7).
  const auto ob = Constitutive::oldroyd_b(0.3, 2.0, 0.5);
  EXPECT_LT(max_abs(ve::polymer_stress(ob, c) - 2.0 * a), 1e-15);
  EXPECT_LT(max_abs(ve::conformation_relaxation(ob, c) + a / 0.5), 1e-15);
  const auto ucm = Constitutive::ucm(1.5, 2.0);
  EXPECT_LT(max_abs(ve::conformation_relaxation(ucm, c) + a / 2.0), 1e-15);
  const auto gk = Constitutive::giesekus(0.1, 1.2, 0.8, 0.3);
  EXPECT_LT(max_abs(ve::polymer_stress(gk, c) - 1.2 * a), 1e-15);
  EXPECT_LT(max_abs(ve::conformation_relaxation(gk, c) + (a + 0.3 * a * a) / 0.8), 1e-14);
  // Solids: tau = G (B - I), no relaxation (eqs. 2.21-2.22).
  for (const auto& solid : {Constitutive::neo_hookean(3.0), Constitutive::kelvin_voigt(0.2, 3.0)}) {
    EXPECT_LT(max_abs(ve::polymer_stress(solid, c) - 3.0 * a), 1e-15);
    EXPECT_EQ(max_abs(ve::conformation_relaxation(solid, c)), 0.0);
    EXPECT_EQ(solid.law().log_relaxation(Vec3(0.3, -0.1, 0.2)), Vec3::Zero());
  }
  // FENE-P: f = (L^2 - 3)/(L^2 - tr c), tau = G (f c - I), r = -(f c - I)/lambda.
  const double l2 = 12.0, f = (l2 - 3.0) / (l2 - c.trace());
  const auto fp = fene_p(0.4, 1.5, 0.7, l2);
  EXPECT_LT(max_abs(ve::polymer_stress(fp, c) - 1.5 * (f * c - kI)), 1e-14);
  EXPECT_LT(max_abs(ve::conformation_relaxation(fp, c) + (f * c - kI) / 0.7), 1e-14);
  EXPECT_EQ(max_abs(ve::polymer_stress(fp, kI)), 0.0);  // the rest state c = I is stress-free
  // Newtonian: no stress, no conformation.
  const auto newtonian = Constitutive::newtonian(1.7);
  EXPECT_EQ(max_abs(ve::polymer_stress(newtonian, c)), 0.0);
  EXPECT_THROW((void)ve::conformation_relaxation(newtonian, c), Error);
  EXPECT_THROW((void)newtonian.law().log_relaxation(Vec3::Zero()), Error);
}

TEST(ConstitutiveLaws, LogRelaxationIsTheInverseConformationTimesTheRelaxation) {
  // g(s)/lambda = c^{-1} r(c) (log_conformation.hpp (*)), for every model,
  // near and far from c = I.
  for (const Mat3& c : {sample_c(), Mat3(kI + 1e-7 * (sample_c() - kI)), Mat3(2.5 * kI)}) {
    for (const auto& model :
         {Constitutive::oldroyd_b(0.3, 2.0, 0.5), Constitutive::giesekus(0.1, 1.2, 0.8, 0.3),
          Constitutive::ucm(1.0, 1.3), fene_p(0.4, 1.5, 0.7, 12.0), fene_p(0.0, 1.0, 2.0, 8.0)}) {
      const Mat3 expected = c.inverse() * ve::conformation_relaxation(model, c);
      EXPECT_LT(max_abs(log_relaxation_matrix(model, c) - expected), 1e-13 * (1.0 + max_abs(expected)))
          << ve::to_string(model.model());
    }
  }
  // Accurate at c = I + O(1e-9): relative to the size of r, not of c.
  const Mat3 near = kI + 1e-9 * (sample_c() - kI);
  const auto fp = fene_p(0.4, 1.5, 0.7, 12.0);
  const Mat3 expected = near.inverse() * ve::conformation_relaxation(fp, near);
  EXPECT_LT(max_abs(log_relaxation_matrix(fp, near) - expected), 1e-6 * max_abs(expected));
}

TEST(ConstitutiveLaws, FenePBecomesOldroydBAsTheExtensibilityGrows) {
  const Mat3 c = sample_c();
  Mat3 l;
  l << 0.1, 1.0, 0.0, -0.2, 0.0, 0.3, 0.0, 0.1, -0.1;
  const auto ob = Constitutive::oldroyd_b(0.4, 1.5, 0.7);
  const auto s = ve::matrix_log(c);
  double previous = INFINITY;
  for (const double l2 : {1e2, 1e4, 1e6}) {
    const auto fp = fene_p(0.4, 1.5, 0.7, l2);
    // f - 1 = (tr c - 3)/(L^2 - tr c): every difference shrinks like 1/L^2.
    const double gap = (c.trace() - 3.0) / (l2 - c.trace());
    const double stress = max_abs(ve::polymer_stress(fp, c) - ve::polymer_stress(ob, c));
    const double rate =
        max_abs(ve::log_conformation_rate(fp, l, s) - ve::log_conformation_rate(ob, l, s));
    EXPECT_NEAR(stress, 1.5 * gap * max_abs(c), 1e-10);
    EXPECT_LT(rate, 2.0 * gap / 0.7);
    EXPECT_LT(rate, previous / 50.0);
    previous = rate;
  }
  EXPECT_DOUBLE_EQ(fene_p(0.4, 1.5, 0.7, 10.0).zero_shear_viscosity(),
                   ob.zero_shear_viscosity());  // mu + G lambda (fene_p.cpp)
}

TEST(ConstitutiveLaws, FenePLinearisedStressIsTheDerivative) {
  const auto fp = fene_p(0.4, 1.5, 0.7, 12.0);
  const Mat3 c_n = sample_c();
  Mat3 dc;
  dc << 0.2, -0.1, 0.05, -0.1, 0.3, 0.1, 0.05, 0.1, -0.15;
  const auto derivative = fp.law().stress_derivative(c_n);
  ASSERT_TRUE(derivative.has_trace_part);
  const Mat3 by_derivative =
      ve::polymer_stress(fp, c_n) + derivative.scale * dc + dc.trace() * derivative.trace_part;
  EXPECT_LT(max_abs(fp.law().linearized_stress(c_n, c_n + dc) - by_derivative), 1e-13);
  // Second order: halving the step quarters the linearisation error.
  double previous = 0.0;
  for (const double eps : {1e-1, 5e-2, 2.5e-2}) {
    const double error = max_abs(ve::polymer_stress(fp, c_n + eps * dc) -
                                 fp.law().linearized_stress(c_n, c_n + eps * dc));
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.3);
    }
    previous = error;
  }
  // Affine stresses: the linearisation is the stress itself, derivative G.
  const auto ob = Constitutive::oldroyd_b(0.4, 1.5, 0.7);
  EXPECT_EQ(ob.law().linearized_stress(c_n, c_n + dc), ve::polymer_stress(ob, c_n + dc));
  EXPECT_EQ(ob.law().stress_derivative(c_n).scale, 1.5);
  EXPECT_FALSE(ob.law().stress_derivative(c_n).has_trace_part);
}

TEST(ConstitutiveLaws, FenePRefusesConformationsBeyondItsExtensibility) {
  const auto fp = fene_p(0.4, 1.5, 0.7, 6.0);
  EXPECT_TRUE(fp.law().inadmissible(sample_c() * 0.9).empty());  // tr c = 5.04
  const std::string why = fp.law().inadmissible(sample_c() * 1.2);  // tr c = 6.72
  EXPECT_NE(why.find("tr c = 6.72"), std::string::npos) << why;
  EXPECT_NE(why.find("L^2 = 6"), std::string::npos) << why;
  EXPECT_THROW((void)ve::polymer_stress(fp, sample_c() * 1.2), SolverError);
  EXPECT_THROW((void)fp.law().log_relaxation(Vec3(1.0, 1.0, 1.0)), SolverError);  // tr c = 3e
  for (const auto& other : {Constitutive::oldroyd_b(0.4, 1.5, 0.7), Constitutive::neo_hookean(1.0)})
    EXPECT_TRUE(other.law().inadmissible(100.0 * kI).empty());
}

TEST(ConstitutiveLaws, FenePParametersAreChecked) {
  using M = ConstitutiveModel;
  const auto message = [](const auto& make) {
    try {
      (void)make();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto m = message([] {
    return Constitutive::create(M::fene_p,
                                {.solvent_viscosity = 0.1, .modulus = 1.0, .relaxation_time = 1.0});
  });
  EXPECT_NE(m.find("'fene_p': the extensibility L^2 is required"), std::string::npos) << m;
  m = message([] { return fene_p(0.1, 1.0, 1.0, 3.0); });
  EXPECT_NE(m.find("extensibility L^2 = 3 must exceed 3"), std::string::npos) << m;
  m = message([] {
    return Constitutive::create(M::fene_p, {.solvent_viscosity = 0.1,
                                            .modulus = 1.0,
                                            .relaxation_time = 1.0,
                                            .mobility = 0.2,
                                            .extensibility = 10.0});
  });
  EXPECT_NE(m.find("mobility alpha = 0.2 is not a parameter of this model (only the giesekus"),
            std::string::npos)
      << m;
  m = message([] {
    return Constitutive::create(M::oldroyd_b, {.solvent_viscosity = 0.1,
                                               .modulus = 1.0,
                                               .relaxation_time = 1.0,
                                               .extensibility = 10.0});
  });
  EXPECT_NE(m.find("'oldroyd_b': the extensibility L^2 = 10 is not a parameter of this model "
                   "(only the fene_p model has one)"),
            std::string::npos)
      << m;
  // eta_p instead of G, as for the other liquids.
  const auto by_eta_p = Constitutive::create(
      M::fene_p, {.solvent_viscosity = 0.1, .polymer_viscosity = 2.0, .relaxation_time = 4.0,
                  .extensibility = 50.0});
  EXPECT_DOUBLE_EQ(by_eta_p.modulus(), 0.5);
  EXPECT_EQ(ve::constitutive_model_from_string("fene_p"), M::fene_p);
  EXPECT_EQ(ve::to_string(M::fene_p), "fene_p");
}

TEST(ConstitutiveLaws, ValuesRebuildEveryModel) {
  // The checkpoint identity: create(model(), values()) is the same model.
  for (const auto& model :
       {Constitutive::newtonian(1.7), Constitutive::oldroyd_b(0.3, 2.0, 0.5),
        Constitutive::giesekus(0.1, 1.2, 0.8, 0.3), Constitutive::ucm(1.0, 1.3),
        Constitutive::neo_hookean(3.0), Constitutive::kelvin_voigt(0.2, 3.0),
        fene_p(0.4, 1.5, 0.7, 12.0)}) {
    const auto again = Constitutive::create(model.model(), model.values());
    EXPECT_EQ(again.model(), model.model());
    EXPECT_EQ(again.solvent_viscosity(), model.solvent_viscosity());
    EXPECT_EQ(again.modulus(), model.modulus());
    EXPECT_EQ(again.relaxation_time(), model.relaxation_time());
    EXPECT_EQ(again.mobility(), model.mobility());
    EXPECT_EQ(again.values().extensibility, model.values().extensibility);
    EXPECT_EQ(ve::polymer_stress(again, sample_c()), ve::polymer_stress(model, sample_c()));
  }
  // Copies share the law built once.
  const auto model = fene_p(0.4, 1.5, 0.7, 12.0);
  const Constitutive copy = model;
  EXPECT_EQ(&copy.law(), &model.law());
}

TEST(ConstitutiveLaws, StokesKernelTakesTheLinearisedFenePStress) {
  // The element's matrix times a linear velocity u minus its load equals
  // integral D(v) : tau_lin(c_pred(u)), tau_lin the FENE-P stress linearised
  // at c_n (test_viscoelastic_stokes_terms does the same for affine stresses).
  auto mesh = mesh::structured_box({1.0, 1.0, 1.0, false, false}, 1, 1, 1);
  for (auto& p : mesh.nodes)
    p += 0.02 * Eigen::Vector3d(std::sin(2 * p.z()), std::sin(3 * p.x()), std::sin(p.y()));
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  fem::Field c(mesh, "conformation", p1, 6), um(mesh, "mesh_velocity", p2, 3);
  c.interpolate([](const Eigen::Vector3d& x, int) {
    Mat3 m;
    m << 1.8 + 0.3 * x.y(), 0.4 * x.x(), -0.1, 0.4 * x.x(), 1.2 + 0.2 * x.z(), 0.15 * x.y(), -0.1,
        0.15 * x.y(), 1.0 + 0.2 * x.x();
    return Eigen::VectorXd(ve::pack_symmetric(m));
  });
  um.interpolate([](const Eigen::Vector3d& x, int) {
    return Eigen::VectorXd(Eigen::Vector3d(0.1 * x.z(), 0.2 * x.x() * x.y(), -0.1 * x.y()));
  });
  const auto model = fene_p(0.2, 1.3, 0.6, 9.0);
  physics::ViscoelasticCoupling coupling;
  coupling.models = {model};
  coupling.conformation = &c;
  coupling.mesh_velocity = &um;
  coupling.dt = 0.05;

  Mat3 a;
  a << -0.2, 0.9, 0.1, 0.3, 0.4, -0.5, 0.2, 0.1, -0.2;
  const Eigen::Vector3d b(-0.1, 0.2, 0.05);
  const fem::TetTabulation tab(4);
  for (int t = 0; t < mesh.n_tets(); ++t) {
    const auto points = fem::quadrature_points(mesh, tab, t);
    physics::TetMatrix ke = physics::TetMatrix::Zero();
    physics::TetVector fe = physics::TetVector::Zero();
    physics::add_viscoelastic_tet_terms(coupling, points, ke, fe);
    const auto x = fem::tet_nodes(mesh, t);
    Eigen::Matrix<double, 30, 1> u;
    for (int k = 0; k < 10; ++k) u.segment<3>(3 * k) = a * x.col(k) + b;
    const Eigen::Matrix<double, 30, 1> discrete = ke.topLeftCorner<30, 30>() * u - fe.head<30>();

    Eigen::Matrix<double, 30, 1> direct = Eigen::Matrix<double, 30, 1>::Zero();
    for (const auto& p : points) {
      const Eigen::Matrix<double, 10, 3> g =
          element::physical_gradients<10>(tab.p2_grad[p.q], p.map);
      const Mat3 cn = ve::unpack_symmetric(c.value(p));
      std::array<Mat3, 3> grad_c;
      const Eigen::MatrixXd gc = c.gradient(p);
      for (int d = 0; d < 3; ++d) grad_c[d] = ve::unpack_symmetric(gc.col(d));
      const Eigen::Vector3d w = a * p.x + b - Eigen::Vector3d(um.value(p));
      const ve::ConformationPrediction prediction(model, cn, ve::convective_derivative(w, grad_c),
                                                  coupling.dt);
      const Mat3 tau = model.law().linearized_stress(cn, prediction(a));
      for (int k = 0; k < 10; ++k)
        for (int comp = 0; comp < 3; ++comp) {
          Mat3 grad_v = Mat3::Zero();
          grad_v.row(comp) = g.row(k);
          direct(3 * k + comp) += p.weight * (0.5 * (grad_v + grad_v.transpose())).cwiseProduct(tau).sum();
        }
    }
    EXPECT_LT((discrete - direct).cwiseAbs().maxCoeff(),
              1e-12 * (1.0 + direct.cwiseAbs().maxCoeff()))
        << "tet " << t;
  }
}
