// The log-conformation tensor carried by a given flow (one-way: the stress
// does not act back on the flow yet): start-up of simple shear in a periodic
// box, u = (gamma_dot y, 0, 0), from c = I. The conformation stays uniform,
// so this checks the whole pointwise-plus-transport path (six components in
// a P1 per-region field, grad u through the curved-map machinery, the
// Fattal-Kupferman source extrapolated for BDF2, AleTransport) against the
// closed-form start-up solutions, and its order in time:
//   Oldroyd-B (Wi = lambda gamma_dot):  c_xy = Wi (1 - e^(-t/lambda)),
//                                       c_xx = 1 + 2 Wi^2 (1 - e^(-t/lambda) (1 + t/lambda));
//   neo-Hookean (no relaxation):        c = F F^T, F = I + gamma_dot t e_x e_y:
//                                       c_xx = 1 + (gamma_dot t)^2, c_xy = gamma_dot t.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "softflow/fem/field.hpp"
#include "support/verification/structured_box.hpp"
#include "softflow/physics/transport/ale_transport.hpp"
#include "softflow/physics/viscoelastic/conformation_transport.hpp"

using namespace softflow;
using physics::viscoelastic::Constitutive;
using physics::viscoelastic::Mat3;

namespace {

constexpr double kShearRate = 1.0;
constexpr double kEnd = 2.0;

/// Max over owned vertices of |c_h - c_exact| at t = kEnd, and the spread of
/// c_xy over the vertices (uniformity).
std::pair<double, double> start_up_error(const Constitutive& model, double dt,
                                         const std::function<Mat3(double)>& exact) {
  auto mesh = mesh::structured_box({2.0, 2.0, 2.0, true, true}, 3, 3, 3);
  auto p1 = std::make_shared<fem::Space>(mesh, 1, fem::Continuity::per_region);
  auto p2 = std::make_shared<fem::Space>(mesh, 2, fem::Continuity::continuous);
  fem::Field u(mesh, "velocity", p2, 3);
  u.interpolate([](const Eigen::Vector3d& x, int) {
    return Eigen::VectorXd(Eigen::Vector3d(kShearRate * x.y(), 0.0, 0.0));
  });
  fem::Field s(mesh, "log_conformation", p1, 6);  // s = log c = 0: c = I
  physics::AleTransport transport(s);
  const std::vector<Constitutive> models{model};
  const auto source = physics::viscoelastic::log_conformation_source(models, u, s, transport);
  const int steps = static_cast<int>(std::lround(kEnd / dt));
  for (int n = 1; n <= steps; ++n) transport.step(u, nullptr, source, dt, n * dt);

  const auto all = s.gather();
  const Mat3 c_exact = exact(kEnd);
  double error = 0.0, lo = 1e300, hi = -1e300;
  for (std::size_t d = 0; d < all.size(); d += 6) {
    const Eigen::VectorXd v = Eigen::Map<const Eigen::VectorXd>(all.data() + d, 6);
    const Mat3 c = physics::viscoelastic::matrix_exp(physics::viscoelastic::unpack_symmetric(v));
    error = std::max(error, (c - c_exact).cwiseAbs().maxCoeff());
    lo = std::min(lo, c(0, 1));
    hi = std::max(hi, c(0, 1));
  }
  return {error, hi - lo};
}

void expect_second_order(const Constitutive& model, const std::function<Mat3(double)>& exact,
                         const char* name) {
  const auto [e1, spread] = start_up_error(model, 0.2, exact);
  const auto [e2, spread2] = start_up_error(model, 0.1, exact);
  const auto [e3, spread3] = start_up_error(model, 0.05, exact);
  if (la::mpi_rank() == 0)
    std::printf("%s: errors %.3e %.3e %.3e, orders %.2f %.2f\n", name, e1, e2, e3,
                std::log2(e1 / e2), std::log2(e2 / e3));
  EXPECT_GT(std::log2(e2 / e3), 1.8) << name;
  EXPECT_LT(spread3, 1e-10) << name;  // a uniform conformation stays uniform
}

}  // namespace

TEST(ConformationTransport, OldroydBStartUpOfShearIsSecondOrderInTime) {
  const double lambda = 1.0, wi = lambda * kShearRate;
  expect_second_order(
      Constitutive::oldroyd_b(0.5, 1.0, lambda),
      [=](double t) {
        const double e = std::exp(-t / lambda);
        Mat3 c = Mat3::Identity();
        c(0, 0) = 1.0 + 2.0 * wi * wi * (1.0 - e * (1.0 + t / lambda));
        c(0, 1) = c(1, 0) = wi * (1.0 - e);
        return c;
      },
      "Oldroyd-B");
}

TEST(ConformationTransport, NeoHookeanShearGivesTheFingerTensor) {
  expect_second_order(
      Constitutive::neo_hookean(1.0),
      [](double t) {
        const double gamma = kShearRate * t;
        Mat3 c = Mat3::Identity();
        c(0, 0) = 1.0 + gamma * gamma;
        c(0, 1) = c(1, 0) = gamma;
        return c;
      },
      "neo-Hookean");
}

TEST(ConformationTransport, SymmetricPackingRoundTrips) {
  Mat3 a;
  a << 1, 4, 6, 4, 2, 5, 6, 5, 3;
  const auto v = physics::viscoelastic::pack_symmetric(a);
  EXPECT_EQ(v(3), 4.0);  // xy
  EXPECT_EQ(v(4), 5.0);  // yz
  EXPECT_EQ(v(5), 6.0);  // xz
  EXPECT_EQ(physics::viscoelastic::unpack_symmetric(v), a);
}
