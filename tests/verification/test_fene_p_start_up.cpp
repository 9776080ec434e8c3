// FENE-P start-up of simple shear, homogeneous: the code's own time
// integration of the log-conformation (six components in a P1 field,
// the Fattal-Kupferman source with FENE-P's log-form relaxation
// extrapolated for BDF2, AleTransport) against an independent reference:
// the conformation ODE
//
//   dc/dt = L c + c L^T - (1/lambda) (f c - I),   f = (L^2 - 3) / (L^2 - tr c),
//
// (physics/viscoelastic/fene_p.cpp, the same convention) integrated in c,
// not in log c, by classical RK4 at a step 1000 times finer than the finest
// of the code. u = (gamma_dot y, 0, 0) in a periodic box, from c = I; the
// flow does not feel the stress (one-way), so the conformation stays
// uniform and the only error is the time integration's. Wi = lambda
// gamma_dot = 2 and L^2 = 10: at t = 2, tr c = 4.62 and f = 1.30, and
// c_xx = 2.79 where Oldroyd-B has 3.11, so f matters. The order fitted over
// dt = 0.2, 0.1, 0.05, 0.025 must be 2 (BDF2 with the extrapolated source).
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/fem/field.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

using namespace softflow;
using physics::viscoelastic::Constitutive;
using physics::viscoelastic::ConstitutiveModel;
using physics::viscoelastic::Mat3;

namespace {

constexpr double kShearRate = 1.0;
constexpr double kLambda = 2.0;
constexpr double kExtensibility = 10.0;  // L^2
constexpr double kEnd = 2.0;

Mat3 velocity_gradient() {
  Mat3 l = Mat3::Zero();
  l(0, 1) = kShearRate;  // L_ij = du_i/dx_j
  return l;
}

/// The right-hand side of the FENE-P conformation ODE, written out here.
Mat3 fene_p_rate(const Mat3& c) {
  const Mat3 l = velocity_gradient();
  const double f = (kExtensibility - 3.0) / (kExtensibility - c.trace());
  return l * c + c * l.transpose() - (f * c - Mat3::Identity()) / kLambda;
}

/// c(kEnd) by classical RK4 with n steps.
Mat3 reference(int n) {
  const double h = kEnd / n;
  Mat3 c = Mat3::Identity();
  for (int i = 0; i < n; ++i) {
    const Mat3 k1 = fene_p_rate(c);
    const Mat3 k2 = fene_p_rate(c + 0.5 * h * k1);
    const Mat3 k3 = fene_p_rate(c + 0.5 * h * k2);
    const Mat3 k4 = fene_p_rate(c + h * k3);
    c += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return c;
}

/// Max over owned vertices of |c_h(kEnd) - c_ref|, and the spread of c_xy.
std::pair<double, double> start_up_error(double dt, const Mat3& c_ref) {
  auto mesh = mesh::structured_box({2.0, 2.0, 2.0, true, true}, 3, 3, 3);
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  fem::Field u(mesh, "velocity", p2, 3);
  u.interpolate([](const Eigen::Vector3d& x, int) {
    return Eigen::VectorXd(Eigen::Vector3d(kShearRate * x.y(), 0.0, 0.0));
  });
  fem::Field s(mesh, "log_conformation", p1, 6);  // s = 0: c = I
  physics::AleTransport transport(s);
  const std::vector<Constitutive> models{Constitutive::create(
      ConstitutiveModel::fene_p, {.solvent_viscosity = 0.5,
                                  .modulus = 1.0,
                                  .relaxation_time = kLambda,
                                  .extensibility = kExtensibility})};
  const auto source = physics::viscoelastic::log_conformation_source(models, u, s, transport);
  const int steps = static_cast<int>(std::lround(kEnd / dt));
  for (int n = 1; n <= steps; ++n) transport.step(u, nullptr, source, dt, n * dt);

  const auto all = s.gather();
  double error = 0.0, lo = 1e300, hi = -1e300;
  for (std::size_t d = 0; d < all.size(); d += 6) {
    const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(all.data() + d, 6);
    const Mat3 c = physics::viscoelastic::matrix_exp(physics::viscoelastic::unpack_symmetric(v));
    error = std::max(error, (c - c_ref).cwiseAbs().maxCoeff());
    lo = std::min(lo, c(0, 1));
    hi = std::max(hi, c(0, 1));
  }
  return {error, hi - lo};
}

}  // namespace

TEST(FenePStartUp, MatchesTheConformationOdeAtSecondOrderInTime) {
  const Mat3 c_ref = reference(80000);  // h = 2.5e-5
  // The reference is converged far below the errors measured.
  EXPECT_LT((c_ref - reference(40000)).cwiseAbs().maxCoeff(), 1e-12);
  // f matters here: Oldroyd-B's c_xx(2) = 1 + 2 Wi^2 (1 - e^{-1} (1 + 1)) = 3.11 (Wi = 2).
  EXPECT_LT(c_ref(0, 0), 3.0);
  EXPECT_GT(c_ref.trace(), 4.0);

  const std::vector<double> dts{0.2, 0.1, 0.05, 0.025};
  std::vector<double> errors;
  for (const double dt : dts) {
    const auto [error, spread] = start_up_error(dt, c_ref);
    errors.push_back(error);
    EXPECT_LT(spread, 1e-10) << "dt = " << dt;  // a uniform conformation stays uniform
  }
  // Least-squares slope of log(error) against log(dt).
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < dts.size(); ++i) {
    mx += std::log(dts[i]) / dts.size();
    my += std::log(errors[i]) / dts.size();
  }
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < dts.size(); ++i) {
    sxy += (std::log(dts[i]) - mx) * (std::log(errors[i]) - my);
    sxx += (std::log(dts[i]) - mx) * (std::log(dts[i]) - mx);
  }
  const double order = sxy / sxx;
  if (la::mpi_rank() == 0) {
    std::printf("FENE-P start-up (Wi = 2, L^2 = 10), |c_h - c_ref| at t = 2:\n");
    for (std::size_t i = 0; i < dts.size(); ++i)
      std::printf("  dt = %.3f  error %.3e%s\n", dts[i], errors[i],
                  i > 0 ? (" ratio " + std::to_string(errors[i - 1] / errors[i])).c_str() : "");
    std::printf("  fitted order %.2f\n", order);
  }
  EXPECT_GT(order, 1.85);
  EXPECT_LT(order, 2.3);
  // The last halving alone: the ratio ~4.
  EXPECT_GT(errors[2] / errors[3], 3.4);
}
