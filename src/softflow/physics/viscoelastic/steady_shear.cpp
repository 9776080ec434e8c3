// Newton's method on the four conformation components that simple shear
// leaves free; the Jacobian by central differences (the residual is a
// polynomial or rational function of c of low degree, so the differences
// are accurate to ~1e-10 relative, and Newton's quadratic convergence only
// needs the Jacobian approximately).
#include "softflow/physics/viscoelastic/steady_shear.hpp"

#include <cmath>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::physics::viscoelastic {

namespace {

using Vec4 = Eigen::Vector4d;

Mat3 conformation_of(const Vec4& x) {
  Mat3 c = Mat3::Identity();
  c(0, 0) = x(0);
  c(1, 1) = x(1);
  c(2, 2) = x(2);
  c(0, 1) = c(1, 0) = x(3);
  return c;
}

Vec4 residual(const Constitutive& model, const Mat3& velocity_gradient, const Vec4& x) {
  const Mat3 rate = conformation_rate(model, velocity_gradient, conformation_of(x));
  return {rate(0, 0), rate(1, 1), rate(2, 2), rate(0, 1)};
}

/// Newton from x at the shear gradient L; false if it does not converge.
bool solve(const Constitutive& model, const Mat3& velocity_gradient, Vec4& x, int& steps) {
  constexpr int kMaxSteps = 40;
  for (int k = 0; k < kMaxSteps; ++k) {
    const Vec4 f = residual(model, velocity_gradient, x);
    Eigen::Matrix4d jacobian;
    for (int j = 0; j < 4; ++j) {
      const double h = 1e-6 * std::max(1.0, std::abs(x(j)));
      Vec4 plus = x, minus = x;
      plus(j) += h;
      minus(j) -= h;
      jacobian.col(j) =
          (residual(model, velocity_gradient, plus) - residual(model, velocity_gradient, minus)) /
          (2.0 * h);
    }
    const Vec4 dx = jacobian.fullPivLu().solve(-f);
    if (!dx.allFinite()) return false;
    x += dx;
    ++steps;
    if (dx.norm() <= 1e-14 * std::max(1.0, x.norm())) return true;
  }
  return false;
}

}  // namespace

SteadyShear steady_simple_shear(const Constitutive& model, double shear_rate) {
  if (!model.relaxes())
    throw Error(fmt::format("steady simple shear: the {} model has no steady state in shear "
                            "(only the liquids with a relaxation time have one)",
                            to_string(model.model())));
  if (!(shear_rate >= 0.0) || !std::isfinite(shear_rate))
    throw Error(fmt::format("steady simple shear: shear rate {} must be finite and >= 0", shear_rate));
  SteadyShear out;
  Vec4 x(1.0, 1.0, 1.0, 0.0);  // rest, c = I
  // Continuation in the Weissenberg number: from rest to lambda gamma_dot in
  // increments of at most 0.25, halved when a Newton solve fails.
  const double target = shear_rate;
  double reached = 0.0;
  double increment = std::min(target, 0.25 / model.relaxation_time());
  while (reached < target) {
    const double next = std::min(target, reached + increment);
    Mat3 gradient = Mat3::Zero();
    gradient(0, 1) = next;
    Vec4 trial = x;
    if (solve(model, gradient, trial, out.newton_steps)) {
      x = trial;
      reached = next;
    } else {
      increment /= 2.0;
      if (increment < 1e-8 * std::max(target, 1e-300))
        throw Error(fmt::format("steady simple shear of the {} model: no steady state found at "
                                "shear rate {} (continuation stalled at {})",
                                to_string(model.model()), target, reached));
    }
  }
  out.conformation = conformation_of(x);
  out.stress = polymer_stress(model, out.conformation);
  return out;
}

}  // namespace softflow::physics::viscoelastic
