// Exact Stokes fields around a spherical drop in a linear flow (radius 1, matrix viscosity 1).
#pragma once

#include <Eigen/Core>

namespace softflow::analysis::theory {

/// Two exact solutions for a spherical drop of radius 1 at the origin in
/// u_inf = E.x + W.x (E symmetric traceless, W antisymmetric), matrix
/// viscosity 1, drop viscosity lambda, no slip; h = x.E.x, r = |x|.
///
/// `instantaneous`: the Stokes field at the instant the drop is a sphere,
/// with continuous velocity and the full traction balance
/// (sigma_m - sigma_d) n = 2 Gamma n. This is what one Stokes solve on a
/// spherical interface must reproduce (derived with the ansatz below; the
/// interior is a uniform straining flow, the classical start of deformation):
///   outside u = E.x + 5(1-lambda)/(2 lambda+3) h x/r^5 + (1-lambda)/(2 lambda+3) grad(h/r^5) + W.x
///           p = 10(1-lambda)/(2 lambda+3) h/r^5
///   inside  u = 5/(2 lambda+3) E.x + W.x,   p = 2 Gamma.
///
/// `taylor_quasi_steady`: Taylor's (1932) field with u.n = 0 on r = 1 (SPEC
/// §10 at alpha = 0), the leading order of the steady, slightly deformed
/// drop; its normal-stress jump is not uniform (that imbalance is what the
/// O(Ca) deformation carries), so a Stokes solve on a sphere does not
/// reproduce it. With L = lambda + 1:
///   outside u = E.x - (5 lambda+2)/(2L) h x/r^5 - lambda/(2L) grad(h/r^5) + W.x
///           p = -(5 lambda+2)/L h/r^5
///   inside  u = [5 r^2 E.x - 2 h x - 3 E.x]/(2L) + W.x,  p = 21 lambda h/(2L) + 2 Gamma.
/// SPEC §10 prints the outer h x/r^5 coefficient without the factor 1/2;
/// with it the velocity is continuous at r = 1 (tested).
class DropInLinearFlow {
 public:
  enum class Kind { instantaneous, taylor_quasi_steady };

  DropInLinearFlow(Kind kind, double lambda, const Eigen::Matrix3d& velocity_gradient,
                   double tension = 0.0);

  /// Simple shear u_inf = (shear_rate y, 0, 0).
  static DropInLinearFlow simple_shear(Kind kind, double lambda, double shear_rate,
                                       double tension = 0.0);

  [[nodiscard]] Eigen::Vector3d velocity(const Eigen::Vector3d& x, bool inside) const;
  [[nodiscard]] double pressure(const Eigen::Vector3d& x, bool inside) const;

 private:
  Kind kind_;
  double lambda_;
  Eigen::Matrix3d e_;  // rate of strain
  Eigen::Matrix3d w_;  // vorticity tensor
  double tension_;
};

}  // namespace softflow::analysis::theory
