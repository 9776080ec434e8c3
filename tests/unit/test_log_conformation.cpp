// Pointwise constitutive numerics of the log-conformation method
// (physics/viscoelastic/): the tensor log/exp, the Fattal-Kupferman
// decomposition, ds/dt against the exact derivative of log c along the
// conformation equation, steady and elastic shear reached by integrating
// ds/dt, the D'Avino-Hulsen prediction, and the parameter checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include <Eigen/LU>
#include <Eigen/QR>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/conformation_prediction.hpp"
#include "softflow/physics/viscoelastic/constitutive.hpp"
#include "softflow/physics/viscoelastic/log_conformation.hpp"
#include "softflow/physics/viscoelastic/symmetric_tensor.hpp"
#include "softflow/time/bdf.hpp"

namespace ve = softflow::physics::viscoelastic;
using ve::Constitutive;
using ve::ConstitutiveModel;
using ve::Mat3;
using ve::Vec3;

namespace {

double max_abs(const Mat3& a) { return a.cwiseAbs().maxCoeff(); }

// Seeded, so that a failure reproduces.
class Random {
 public:
  explicit Random(unsigned seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(engine_); }
  Mat3 matrix(double scale) {
    Mat3 a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = uniform(-scale, scale);
    return a;
  }
  // A random orthogonal matrix: the Q of a random matrix.
  Mat3 rotation() { return Eigen::HouseholderQR<Mat3>(matrix(1.0)).householderQ(); }
  Mat3 symmetric(double scale) {
    const Mat3 a = matrix(scale);
    return 0.5 * (a + a.transpose());
  }

 private:
  std::mt19937 engine_;
};

// A conformation tensor built from its spectrum, so that tests know R and
// Lambda exactly, independently of the eigen-solver under test.
struct Spectral {
  Mat3 r;
  Vec3 lambda;
  [[nodiscard]] Mat3 c() const { return r * lambda.asDiagonal() * r.transpose(); }
  [[nodiscard]] Mat3 s() const {
    return r * lambda.array().log().matrix().asDiagonal() * r.transpose();
  }
};

// The Daleckii-Krein derivative of log at c = R Lambda R^T in the direction
// e: R (F o (R^T e R)) R^T with F_ij the divided difference of log,
// (log Lambda_j - log Lambda_i) / (Lambda_j - Lambda_i), and 1/Lambda_i when
// they are equal; log1p keeps its digits for nearly equal values. This is
// d/dt log c(t) for dc/dt = e, independent of the Fattal-Kupferman algebra.
Mat3 log_derivative(const Spectral& c, const Mat3& e) {
  const Mat3 m = c.r.transpose() * e * c.r;
  Mat3 f;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double a = c.lambda(i), b = c.lambda(j);
      f(i, j) = a == b ? 1.0 / a : std::log1p((b - a) / a) / (b - a);
    }
  return c.r * m.cwiseProduct(f) * c.r.transpose();
}

// Simple shear u = (gdot y, 0, 0): L = gdot e_x e_y^T.
Mat3 simple_shear(double gdot) {
  Mat3 l = Mat3::Zero();
  l(0, 1) = gdot;
  return l;
}

// Classical fourth-order Runge-Kutta for y' = f(y), n steps of dt.
Mat3 rk4(const std::function<Mat3(const Mat3&)>& f, Mat3 y, double dt, int n) {
  for (int k = 0; k < n; ++k) {
    const Mat3 k1 = f(y);
    const Mat3 k2 = f(y + 0.5 * dt * k1);
    const Mat3 k3 = f(y + 0.5 * dt * k2);
    const Mat3 k4 = f(y + dt * k3);
    y += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return y;
}

// The models whose c-equation the log form must reproduce.
std::vector<Constitutive> conformation_models() {
  return {Constitutive::oldroyd_b(0.5, 2.0, 0.7), Constitutive::giesekus(0.5, 2.0, 0.7, 0.3),
          Constitutive::ucm(1.0, 1.3), Constitutive::neo_hookean(3.0)};
}

// The spectra of the rate tests: generic, c = I, double eigenvalue, nearly
// equal eigenvalues at gaps on both sides of kDegenerateLogGap, nearly I.
std::vector<Spectral> test_conformations(Random& random) {
  std::vector<Spectral> out;
  for (int k = 0; k < 5; ++k)
    out.push_back(
        {random.rotation(), Vec3(std::exp(random.uniform(-2, 2)), std::exp(random.uniform(-2, 2)),
                                 std::exp(random.uniform(-2, 2)))});
  out.push_back({Mat3::Identity(), Vec3(1, 1, 1)});  // c = I exactly
  out.push_back({random.rotation(), Vec3(1, 1, 1)});
  out.push_back({random.rotation(), Vec3(0.5, 2.0, 2.0)});  // double eigenvalue
  out.push_back({random.rotation(), Vec3(3.0, 3.0, 3.0)});  // triple, not I
  for (double gap : {1e-3, 1e-5, 2e-6, 1e-6, 5e-7, 1e-8, 1e-11, 1e-14})
    out.push_back({random.rotation(), Vec3(0.5, 2.0, 2.0 * (1.0 + gap))});
  for (double eps : {1e-4, 1e-7, 1e-10})
    out.push_back({random.rotation(), Vec3(1.0 - eps, 1.0 + 0.5 * eps, 1.0 + 2.0 * eps)});
  return out;
}

// Expects an InputError whose message contains every fragment.
void expect_input_error(const std::function<void()>& make,
                        std::initializer_list<std::string> fragments) {
  try {
    make();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const softflow::InputError& e) {
    const std::string message = e.what();
    for (const auto& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "message \"" << message << "\" lacks \"" << fragment << "\"";
  }
}

}  // namespace

// ---- symmetric tensor functions ----

TEST(ViscoelasticTensorFunctions, ExpOfLogIsIdentityIncludingRepeatedEigenvalues) {
  Random random(20240611);
  std::vector<Spectral> cases;
  for (int k = 0; k < 200; ++k)
    cases.push_back(
        {random.rotation(), Vec3(std::exp(random.uniform(-3, 3)), std::exp(random.uniform(-3, 3)),
                                 std::exp(random.uniform(-3, 3)))});
  for (double gap : {1e-4, 1e-8, 1e-12, 1e-15, 0.0}) {
    const double a = std::exp(random.uniform(-2, 2)), b = std::exp(random.uniform(-2, 2));
    cases.push_back({random.rotation(), Vec3(a, a * (1.0 + gap), b)});
    cases.push_back({random.rotation(), Vec3(a, a * (1.0 + gap), a * (1.0 - gap))});
  }
  cases.push_back({Mat3::Identity(), Vec3(1, 1, 1)});
  for (const auto& sc : cases) {
    const Mat3 c = sc.c();
    const Mat3 s = ve::matrix_log(c);
    EXPECT_LE(max_abs(ve::matrix_exp(s) - c), 1e-13 * max_abs(c))
        << "Lambda = " << sc.lambda.transpose();
    EXPECT_LE(max_abs(s - sc.s()), 1e-13 * std::max(1.0, max_abs(sc.s())));
    EXPECT_EQ(s, s.transpose());  // exactly symmetric, as an s unknown must be
  }
  EXPECT_EQ(ve::matrix_log(Mat3::Identity()), Mat3::Zero());
}

TEST(ViscoelasticTensorFunctions, LogAndExpOfADiagonalTensorAreEntrywise) {
  const Mat3 c = Vec3(std::exp(1.0), 1.0, std::exp(-2.0)).asDiagonal();
  EXPECT_LE(max_abs(ve::matrix_log(c) - Mat3(Vec3(1.0, 0.0, -2.0).asDiagonal())), 1e-15);
  EXPECT_LE(max_abs(ve::matrix_exp(Vec3(1.0, 0.0, -2.0).asDiagonal()) - c), 1e-15);
  const auto eig = ve::symmetric_eigen(c);
  EXPECT_DOUBLE_EQ(eig.values(0), std::exp(-2.0));  // ascending
  EXPECT_DOUBLE_EQ(eig.values(2), std::exp(1.0));
}

TEST(ViscoelasticTensorFunctions, LogRefusesATensorThatIsNotSpd) {
  const auto expect_error = [](const Mat3& c, const std::string& fragment) {
    try {
      (void)ve::matrix_log(c);
      ADD_FAILURE() << "no error for\n" << c;
    } catch (const softflow::Error& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error(Vec3(2.0, 1.0, -0.5).asDiagonal(), "not positive definite");
  expect_error(Vec3(2.0, 0.0, 1.0).asDiagonal(), "not positive definite");
  Mat3 asymmetric = Mat3::Identity();
  asymmetric(0, 1) = 0.1;
  expect_error(asymmetric, "not symmetric");
  Mat3 nan = Mat3::Identity();
  nan(2, 2) = std::nan("");
  expect_error(nan, "non-finite");
  // Round-off asymmetry, as sums of products leave it, is accepted.
  Mat3 nearly = Mat3::Identity();
  nearly(0, 1) = 1e-17;
  EXPECT_NO_THROW((void)ve::matrix_log(nearly));
}

// ---- the Fattal-Kupferman decomposition ----

TEST(ViscoelasticDecomposition, SplitsLIntoRotationStretchAndAnAntisymmetricRemainder) {
  Random random(7);
  for (const auto& sc : test_conformations(random)) {
    const Mat3 l = random.matrix(1.5), c = sc.c();
    const auto fk = ve::fattal_kupferman(l, sc.s());
    const double scale = max_abs(l) * max_abs(c);
    EXPECT_LE(max_abs(fk.omega + fk.omega.transpose()), 1e-14 * max_abs(fk.omega) + 1e-300);
    EXPECT_LE(max_abs(fk.n + fk.n.transpose()), 1e-14 * (max_abs(fk.n) + 1.0));
    EXPECT_LE(max_abs(fk.b - fk.b.transpose()), 1e-14 * max_abs(fk.b));
    // L = Omega + B + N c^{-1}: relative to Omega, which grows as the gap
    // closes down to kDegenerateLogGap.
    EXPECT_LE(max_abs(fk.omega + fk.b + fk.n * c.inverse() - l),
              1e-13 * (max_abs(fk.omega) + scale))
        << "Lambda = " << sc.lambda.transpose();
    // The property that matters: L c + c L^T = (Omega c - c Omega) + B c + c B.
    EXPECT_LE(
        max_abs(fk.omega * c - c * fk.omega + fk.b * c + c * fk.b - (l * c + c * l.transpose())),
        1e-13 * (max_abs(fk.omega) * max_abs(c) + scale));
    // B commutes with c: exactly above the threshold, to gap * |M| |c| below.
    const double gap = std::min({std::abs(std::log(sc.lambda(1) / sc.lambda(0))),
                                 std::abs(std::log(sc.lambda(2) / sc.lambda(1))),
                                 std::abs(std::log(sc.lambda(2) / sc.lambda(0)))});
    const double commute_tolerance =
        gap <= ve::kDegenerateLogGap ? 4.0 * ve::kDegenerateLogGap : 1e-13;
    EXPECT_LE(max_abs(fk.b * c - c * fk.b), commute_tolerance * scale)
        << "Lambda = " << sc.lambda.transpose();
  }
}

TEST(ViscoelasticDecomposition, AtTheIdentityIsVorticityAndRateOfStrain) {
  // c = I: every pair of eigenvalues is equal, so Omega is the vorticity
  // tensor and B the rate of strain, N = 0; the rate is 2D.
  Random random(11);
  const Mat3 l = random.matrix(2.0);
  const auto fk = ve::fattal_kupferman(l, Mat3::Zero());
  EXPECT_LE(max_abs(fk.omega - 0.5 * (l - l.transpose())), 1e-15);
  EXPECT_LE(max_abs(fk.b - 0.5 * (l + l.transpose())), 1e-15);
  EXPECT_EQ(max_abs(fk.n), 0.0);
  for (const auto& model : conformation_models())
    EXPECT_LE(max_abs(ve::log_conformation_rate(model, l, Mat3::Zero()) - (l + l.transpose())),
              1e-15);
}

// ---- ds/dt against the exact derivative of log c ----

TEST(ViscoelasticLogRate, EqualsTheDerivativeOfLogAlongTheConformationEquation) {
  // d/dt log c(t) with dc/dt = L c + c L^T - (1/lambda)((c - I) + alpha (c - I)^2),
  // by the Daleckii-Krein formula, against ds/dt = (Omega s - s Omega) + 2B + g/lambda
  // formed (a) in the eigenbasis by log_conformation_rate and (b) from the
  // global-frame Omega, B and g of the decomposition.
  Random random(2025);
  for (const auto& model : conformation_models()) {
    for (const auto& sc : test_conformations(random)) {
      const Mat3 l = random.matrix(1.5), c = sc.c(), s = sc.s();
      const Mat3 exact = log_derivative(sc, ve::conformation_rate(model, l, c));
      const double scale = std::max(1.0, max_abs(exact)) * std::max(1.0, max_abs(s));
      const Mat3 rate = ve::log_conformation_rate(model, l, s);
      EXPECT_LE(max_abs(rate - exact), 1e-13 * scale)
          << ve::to_string(model.model()) << ", Lambda = " << sc.lambda.transpose();
      EXPECT_LE(max_abs(rate - rate.transpose()), 1e-15 * scale);

      const auto eig = ve::symmetric_eigen(s);
      const auto fk = ve::fattal_kupferman(l, eig);
      Mat3 global = fk.omega * s - s * fk.omega + 2.0 * fk.b;
      if (model.relaxes())
        global += ve::relaxation_function(model.mobility(), eig) / model.relaxation_time();
      // The global-frame product loses a few eps |s| |Omega| (header comment),
      // |Omega| growing as the gap closes down to kDegenerateLogGap.
      EXPECT_LE(max_abs(global - exact), 1e-13 * scale + 4e-15 * max_abs(fk.omega) * max_abs(s))
          << ve::to_string(model.model()) << ", Lambda = " << sc.lambda.transpose();
    }
  }
}

TEST(ViscoelasticLogRate, EqualsAFiniteDifferenceOfLog) {
  // Independent of any divided-difference algebra: the central difference
  // (log(c + h e) - log(c - h e)) / 2h, e = dc/dt, at a generic c, at c = I
  // and at a double eigenvalue.
  Random random(99);
  const std::vector<Spectral> cases{
      {random.rotation(), Vec3(0.3, 1.7, 4.0)},
      {Mat3::Identity(), Vec3(1, 1, 1)},
      {random.rotation(), Vec3(0.5, 2.0, 2.0)},
  };
  const double h = 1e-5;
  for (const auto& model :
       {Constitutive::oldroyd_b(0.1, 1.0, 0.8), Constitutive::giesekus(0.1, 1.0, 0.8, 0.3)})
    for (const auto& sc : cases) {
      const Mat3 l = random.matrix(1.0), c = sc.c();
      const Mat3 e = ve::conformation_rate(model, l, c);
      const Mat3 fd = (ve::matrix_log(c + h * e) - ve::matrix_log(c - h * e)) / (2.0 * h);
      EXPECT_LE(max_abs(ve::log_conformation_rate(model, l, sc.s()) - fd),
                1e-8 * std::max(1.0, max_abs(fd)))
          << ve::to_string(model.model()) << ", Lambda = " << sc.lambda.transpose();
    }
}

TEST(ViscoelasticLogRate, RelaxationSignDecaysTowardsTheIdentity) {
  // No flow, c = diag(4, 1, 1/4): log c must shrink, at rate g/lambda with
  // g_i = (1 - Lambda_i - alpha (Lambda_i - 1)^2)/Lambda_i (hand values).
  const auto model = Constitutive::giesekus(0.0, 1.0, 2.0, 0.5);
  const Mat3 s = Vec3(std::log(4.0), 0.0, std::log(0.25)).asDiagonal();
  const Mat3 rate = ve::log_conformation_rate(model, Mat3::Zero(), s);
  EXPECT_NEAR(rate(0, 0), (1.0 - 4.0 - 0.5 * 9.0) / 4.0 / 2.0, 1e-15);  // -0.9375
  EXPECT_NEAR(rate(1, 1), 0.0, 1e-15);
  EXPECT_NEAR(rate(2, 2), (1.0 - 0.25 - 0.5 * 0.5625) / 0.25 / 2.0, 1e-15);  // +0.9375
  EXPECT_EQ(max_abs(ve::log_conformation_rate(Constitutive::neo_hookean(1.0), Mat3::Zero(), s)),
            0.0);
  EXPECT_THROW((void)ve::log_conformation_rate(Constitutive::newtonian(1.0), Mat3::Zero(), s),
               softflow::Error);
}

// ---- shear flows by integrating ds/dt ----

TEST(ViscoelasticShear, OldroydBAndUcmReachTheAnalyticSteadyConformation) {
  // Steady shear of Oldroyd-B/UCM (eq. 2.7 with alpha = 0): c_xx = 1 + 2 Wi^2,
  // c_xy = Wi, the rest of c the identity, Wi = lambda gdot.
  for (const auto& model : {Constitutive::oldroyd_b(0.3, 1.0, 0.8), Constitutive::ucm(2.0, 0.8)}) {
    const double gdot = 1.5, wi = model.relaxation_time() * gdot;
    const Mat3 l = simple_shear(gdot);
    const auto rate = [&](const Mat3& s) { return ve::log_conformation_rate(model, l, s); };
    // From rest (s = 0, the c = I branch) to 40 lambda: transients ~ t e^{-t/lambda}.
    const Mat3 s = rk4(rate, Mat3::Zero(), 0.01 * model.relaxation_time(), 4000);
    Mat3 expected = Mat3::Identity();
    expected(0, 0) = 1.0 + 2.0 * wi * wi;
    expected(0, 1) = expected(1, 0) = wi;
    EXPECT_LE(max_abs(ve::matrix_exp(s) - expected), 1e-11) << "\n" << ve::matrix_exp(s);
  }
}

TEST(ViscoelasticShear, GiesekusReachesTheAnalyticSteadyConformation) {
  // Steady shear of Giesekus, Wi = lambda gdot, in closed form (Giesekus 1982;
  // Bird, Armstrong & Hassager vol. 1): with
  //   chi^2 = (sqrt(1 + 16 alpha (1 - alpha) Wi^2) - 1) / (8 alpha (1 - alpha) Wi^2),
  //   f = (1 - chi) / (1 + (1 - 2 alpha) chi),
  // c - I has  yy = -f,  xy = Wi (1 - f)^2 / (1 + (1 - 2 alpha) f),
  // xx - yy = 2 f (1 - alpha f) / (alpha (1 - f)) (= N1 / G), zz = 0.
  // The test does not take the closed form on trust: it first checks that it
  // solves the steady conformation equation, then that integrating ds/dt
  // reaches it.
  const double alpha = 0.3;
  const auto model = Constitutive::giesekus(0.2, 1.0, 1.0, alpha);
  for (double gdot : {0.4, 1.2, 5.0}) {
    const double wi = model.relaxation_time() * gdot;
    const double k = 8.0 * alpha * (1.0 - alpha) * wi * wi;
    const double chi = std::sqrt((std::sqrt(1.0 + 2.0 * k) - 1.0) / k);
    const double f = (1.0 - chi) / (1.0 + (1.0 - 2.0 * alpha) * chi);
    Mat3 expected = Mat3::Identity();
    expected(1, 1) = 1.0 - f;
    expected(0, 1) = expected(1, 0) = wi * (1.0 - f) * (1.0 - f) / (1.0 + (1.0 - 2.0 * alpha) * f);
    expected(0, 0) = 1.0 - f + 2.0 * f * (1.0 - alpha * f) / (alpha * (1.0 - f));
    const Mat3 l = simple_shear(gdot);
    EXPECT_LE(max_abs(ve::conformation_rate(model, l, expected)), 1e-13 * max_abs(expected))
        << "Wi = " << wi;

    const auto rate = [&](const Mat3& s) { return ve::log_conformation_rate(model, l, s); };
    const double dt = 0.01 / std::max(1.0, wi);
    const Mat3 s = rk4(rate, Mat3::Zero(), dt, static_cast<int>(40.0 / dt));
    EXPECT_LE(max_abs(ve::matrix_exp(s) - expected), 1e-11 * max_abs(expected))
        << "Wi = " << wi << "\n"
        << ve::matrix_exp(s) << "\nexpected\n"
        << expected;
  }
}

TEST(ViscoelasticShear, ElasticSolidFollowsTheFingerTensor) {
  // g = 0: from c = I, shear by gamma gives c = B = F F^T with
  // F = I + gamma e_x e_y^T: c_xx = 1 + gamma^2, c_xy = gamma (eqs. 2.21-2.22).
  for (const auto& model : {Constitutive::neo_hookean(2.0), Constitutive::kelvin_voigt(0.5, 2.0)}) {
    const double gdot = 1.0;
    const auto rate = [&](const Mat3& s) {
      return ve::log_conformation_rate(model, simple_shear(gdot), s);
    };
    for (double gamma : {0.5, 2.0}) {
      const int n = static_cast<int>(std::lround(2000 * gamma));
      const Mat3 c = ve::matrix_exp(rk4(rate, Mat3::Zero(), gamma / gdot / n, n));
      Mat3 f = Mat3::Identity();
      f(0, 1) = gamma;
      EXPECT_LE(max_abs(c - f * f.transpose()), 1e-11) << "gamma = " << gamma << "\n" << c;
    }
  }
}

// ---- the D'Avino-Hulsen prediction ----

TEST(ViscoelasticPrediction, IsOneExplicitEulerStepOfTheConformationEquation) {
  Random random(5);
  for (const auto& model : conformation_models()) {
    const Mat3 c_n = Spectral{random.rotation(), Vec3(0.4, 1.3, 3.1)}.c();
    const Mat3 l = random.matrix(1.0), convection = random.symmetric(0.5);
    const double dt = 0.01;
    const ve::ConformationPrediction prediction(model, c_n, convection, dt);
    const Mat3 euler = c_n + dt * (ve::conformation_rate(model, l, c_n) - convection);
    EXPECT_LE(max_abs(prediction(l) - euler), 1e-15 * max_abs(euler));
    // The L-linear part is dt (L c_n + c_n L^T), linear, and the rest does not see L.
    EXPECT_LE(max_abs(prediction.linear(l) - dt * (l * c_n + c_n * l.transpose())), 1e-15);
    const Mat3 l2 = random.matrix(1.0);
    EXPECT_LE(max_abs(prediction.linear(2.0 * l - 3.0 * l2) -
                      (2.0 * prediction.linear(l) - 3.0 * prediction.linear(l2))),
              1e-15);
    EXPECT_EQ(prediction(Mat3::Zero()), prediction.constant());
  }
}

TEST(ViscoelasticPrediction, AgreesWithTheExactStepToSecondOrderInDt) {
  // One step from c_n against the c-equation integrated accurately over dt
  // (L constant, no convection): a consistent first-order step, local error
  // O(dt^2), so halving dt quarters it.
  Random random(8);
  const auto model = Constitutive::giesekus(0.1, 1.0, 0.5, 0.3);
  const Mat3 c_n = Spectral{random.rotation(), Vec3(0.6, 1.1, 2.5)}.c();
  const Mat3 l = random.matrix(1.0);
  const auto exact_step = [&](double dt) {
    return rk4([&](const Mat3& c) { return ve::conformation_rate(model, l, c); }, c_n, dt / 200,
               200);
  };
  double previous = 0.0;
  for (double dt : {1e-2, 5e-3, 2.5e-3}) {
    const double error =
        max_abs(ve::ConformationPrediction(model, c_n, Mat3::Zero(), dt)(l) - exact_step(dt));
    EXPECT_LT(error, 10.0 * dt * dt);
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 4.0, 0.2) << "dt = " << dt;
    }
    previous = error;
  }
}

TEST(ViscoelasticPrediction, TheBdf2StepAgreesWithTheExactStepToThirdOrderInDt) {
  // The consistent prediction takes the transport's BDF2 step: from c_{n-1}
  // and c_n on the exact trajectory, h = (4 c_n - c_{n-1}) / 3 plus 2 dt / 3
  // times the rate at c* = 2 c_n - c_{n-1}: local error O(dt^3), so halving
  // dt divides it by 8. With a2 = 0 and c* = c_n it is the Euler step.
  Random random(9);
  const auto model = Constitutive::giesekus(0.1, 1.0, 0.5, 0.3);
  const Mat3 c0 = Spectral{random.rotation(), Vec3(0.6, 1.1, 2.5)}.c();
  const Mat3 l = random.matrix(1.0);
  const auto exact = [&](double t) {
    return rk4([&](const Mat3& c) { return ve::conformation_rate(model, l, c); }, c0, t / 400, 400);
  };
  const auto bdf = softflow::time::bdf(2);
  const auto e = softflow::time::extrapolation(2);
  double previous = 0.0;
  for (double dt : {2e-2, 1e-2, 5e-3}) {
    const Mat3 c_previous = c0, c_n = exact(dt);
    const Mat3 history = -(bdf.a1 * c_n + bdf.a2 * c_previous) / bdf.a0;
    const Mat3 extrapolated = e.current * c_n + e.previous * c_previous;
    const ve::ConformationPrediction prediction(model, history, extrapolated, Mat3::Zero(),
                                                bdf.theta_dt(dt));
    const double error = max_abs(prediction(l) - exact(2.0 * dt));
    if (previous > 0.0) {
      EXPECT_NEAR(previous / error, 8.0, 1.2) << "dt = " << dt;
    }
    previous = error;
  }
  const Mat3 c_n = c0;
  const ve::ConformationPrediction euler(model, c_n, Mat3::Zero(), 0.01);
  const ve::ConformationPrediction bdf1(model, c_n, c_n, Mat3::Zero(), softflow::time::bdf(1).theta_dt(0.01));
  EXPECT_EQ(euler(l), bdf1(l));
}

TEST(ViscoelasticPrediction, RelaxationEntersWithMinusSignAndOneOverLambda) {
  // SPEC §9 (thesis eq. 2.37 misprint): at rest, Oldroyd-B with lambda = 2,
  // c_n = diag(3, 1, 1) relaxes: c_xx = 3 - dt (3 - 1)/lambda.
  const auto model = Constitutive::oldroyd_b(0.0, 1.0, 2.0);
  const Mat3 c_n = Vec3(3.0, 1.0, 1.0).asDiagonal();
  const ve::ConformationPrediction prediction(model, c_n, Mat3::Zero(), 0.1);
  EXPECT_DOUBLE_EQ(prediction.constant()(0, 0), 3.0 - 0.1 * 2.0 / 2.0);
  EXPECT_DOUBLE_EQ(prediction.constant()(1, 1), 1.0);
  // Giesekus adds alpha (c - I)^2: 3 - dt (2 + 0.5 * 4) / 2.
  const ve::ConformationPrediction giesekus(Constitutive::giesekus(0.0, 1.0, 2.0, 0.5), c_n,
                                            Mat3::Zero(), 0.1);
  EXPECT_DOUBLE_EQ(giesekus.constant()(0, 0), 3.0 - 0.1 * 4.0 / 2.0);
  // A solid does not relax; shear adds dt gdot (e_x e_y + e_y e_x) at c = I.
  const ve::ConformationPrediction solid(Constitutive::neo_hookean(1.0), Mat3::Identity(),
                                         Mat3::Zero(), 0.1);
  EXPECT_EQ(solid.constant(), Mat3::Identity());
  Mat3 sheared = Mat3::Identity();
  sheared(0, 1) = sheared(1, 0) = 0.1 * 2.0;
  EXPECT_EQ(solid(simple_shear(2.0)), sheared);
  EXPECT_THROW(ve::ConformationPrediction(Constitutive::newtonian(1.0), c_n, Mat3::Zero(), 0.1),
               softflow::Error);
  EXPECT_THROW(ve::ConformationPrediction(model, c_n, Mat3::Zero(), 0.0), softflow::Error);
}

TEST(ViscoelasticPrediction, ConvectiveDerivativeIsLinearInTheVelocity) {
  // c(x) = c0 + x_k C_k: (w . grad) c = w_k C_k.
  Random random(3);
  const std::array<Mat3, 3> grad_c{random.symmetric(1.0), random.symmetric(1.0),
                                   random.symmetric(1.0)};
  const Vec3 w(0.3, -1.2, 2.0);
  EXPECT_LE(max_abs(ve::convective_derivative(w, grad_c) -
                    (0.3 * grad_c[0] - 1.2 * grad_c[1] + 2.0 * grad_c[2])),
            1e-15);
}

// ---- stresses and parameters ----

TEST(ViscoelasticParameters, StressesAndDerivedViscosities) {
  Random random(1);
  const Mat3 d = random.symmetric(1.0), c = Spectral{random.rotation(), Vec3(0.5, 1.0, 2.0)}.c();
  const auto ob = Constitutive::oldroyd_b(0.3, 2.0, 0.5);
  EXPECT_LE(max_abs(ve::extra_stress(ob, d, c) - (0.6 * d + 2.0 * (c - Mat3::Identity()))), 1e-15);
  EXPECT_DOUBLE_EQ(ob.polymer_viscosity(), 1.0);
  EXPECT_DOUBLE_EQ(ob.zero_shear_viscosity(), 1.3);  // eq. 2.9
  const auto newtonian = Constitutive::newtonian(1.7);
  EXPECT_EQ(ve::extra_stress(newtonian, d, c), 3.4 * d);
  EXPECT_FALSE(newtonian.has_conformation());
  EXPECT_DOUBLE_EQ(newtonian.zero_shear_viscosity(), 1.7);
  const auto solid = Constitutive::neo_hookean(4.0);
  EXPECT_TRUE(solid.has_conformation());
  EXPECT_FALSE(solid.relaxes());
  EXPECT_TRUE(std::isinf(solid.relaxation_time()));
  EXPECT_EQ(ve::polymer_stress(solid, c), 4.0 * (c - Mat3::Identity()));
  // eta_p instead of G: G = eta_p / lambda.
  const auto by_eta_p = Constitutive::create(ConstitutiveModel::giesekus, {.solvent_viscosity = 0.1,
                                                                           .polymer_viscosity = 0.9,
                                                                           .relaxation_time = 3.0,
                                                                           .mobility = 0.2});
  EXPECT_DOUBLE_EQ(by_eta_p.modulus(), 0.3);
  EXPECT_DOUBLE_EQ(by_eta_p.zero_shear_viscosity(), 1.0);
  for (auto model :
       {ConstitutiveModel::newtonian, ConstitutiveModel::oldroyd_b, ConstitutiveModel::giesekus,
        ConstitutiveModel::ucm, ConstitutiveModel::neo_hookean, ConstitutiveModel::kelvin_voigt})
    EXPECT_EQ(ve::constitutive_model_from_string(ve::to_string(model)), model);
}

TEST(ViscoelasticParameters, MessagesNameTheParameter) {
  using M = ConstitutiveModel;
  expect_input_error([] { (void)Constitutive::giesekus(0.1, 1.0, 1.0, 1.5); },
                     {"'giesekus'", "mobility alpha", "1.5", "[0, 1]"});
  expect_input_error([] { (void)Constitutive::giesekus(0.1, 1.0, 1.0, -0.1); },
                     {"mobility alpha", "[0, 1]"});
  expect_input_error([] { (void)Constitutive::oldroyd_b(0.1, 1.0, 0.0); },
                     {"'oldroyd_b'", "relaxation time lambda", "positive"});
  expect_input_error([] { (void)Constitutive::ucm(1.0, -2.0); }, {"relaxation time lambda", "-2"});
  expect_input_error([] { (void)Constitutive::oldroyd_b(-1.0, 1.0, 1.0); },
                     {"solvent viscosity mu", "negative"});
  expect_input_error([] { (void)Constitutive::oldroyd_b(0.1, -2.0, 1.0); },
                     {"modulus G", "positive"});
  expect_input_error([] { (void)Constitutive::neo_hookean(0.0); }, {"'neo_hookean'", "modulus G"});
  expect_input_error([] { (void)Constitutive::newtonian(0.0); }, {"'newtonian'", "viscosity eta"});
  expect_input_error([] { (void)Constitutive::kelvin_voigt(0.0, 1.0); },
                     {"solvent viscosity mu", "positive"});
  expect_input_error([] { (void)Constitutive::oldroyd_b(0.1, std::nan(""), 1.0); },
                     {"modulus G", "not finite"});
  expect_input_error([] { (void)Constitutive::giesekus(0.1, 1.0, INFINITY, 0.2); },
                     {"relaxation time lambda", "not finite"});
  expect_input_error(
      [] {
        (void)Constitutive::create(
            M::giesekus, {.solvent_viscosity = 0.1, .modulus = 1.0, .relaxation_time = 1.0});
      },
      {"mobility alpha", "required"});
  expect_input_error(
      [] {
        (void)Constitutive::create(M::oldroyd_b,
                                   {.solvent_viscosity = 0.1, .relaxation_time = 1.0});
      },
      {"modulus G", "polymer viscosity eta_p", "required"});
  expect_input_error(
      [] {
        (void)Constitutive::create(M::oldroyd_b, {.solvent_viscosity = 0.1,
                                                  .modulus = 1.0,
                                                  .polymer_viscosity = 1.0,
                                                  .relaxation_time = 1.0});
      },
      {"modulus G", "polymer viscosity eta_p", "not both"});
  expect_input_error(
      [] {
        (void)Constitutive::create(
            M::oldroyd_b,
            {.solvent_viscosity = 0.1, .modulus = 1.0, .relaxation_time = 1.0, .mobility = 0.2});
      },
      {"mobility alpha", "not a parameter"});
  expect_input_error(
      [] {
        (void)Constitutive::create(
            M::ucm, {.solvent_viscosity = 0.5, .modulus = 1.0, .relaxation_time = 1.0});
      },
      {"'ucm'", "solvent viscosity mu", "not a parameter"});
  expect_input_error(
      [] { (void)Constitutive::create(M::neo_hookean, {.modulus = 1.0, .relaxation_time = 1.0}); },
      {"relaxation time lambda", "not a parameter", "infinity"});
  expect_input_error(
      [] { (void)Constitutive::create(M::newtonian, {.viscosity = 1.0, .modulus = 1.0}); },
      {"'newtonian'", "modulus G", "not a parameter"});
  expect_input_error(
      [] {
        (void)Constitutive::create(M::oldroyd_b,
                                   {.viscosity = 1.0, .modulus = 1.0, .relaxation_time = 1.0});
      },
      {"viscosity eta", "not a parameter"});
  expect_input_error([] { (void)ve::constitutive_model_from_string("maxwell"); },
                     {"'maxwell'", "giesekus", "neo_hookean"});
  // The models' own zero values may be stated.
  EXPECT_NO_THROW((void)Constitutive::create(
      M::ucm, {.solvent_viscosity = 0.0, .modulus = 1.0, .relaxation_time = 1.0}));
  EXPECT_NO_THROW((void)Constitutive::create(
      M::oldroyd_b,
      {.solvent_viscosity = 0.0, .modulus = 1.0, .relaxation_time = 1.0, .mobility = 0.0}));
  EXPECT_NO_THROW((void)Constitutive::giesekus(0.0, 1.0, 1.0, 0.0));
}
