// Exact Stokes fields around a spherical drop in a linear flow (radius 1, matrix viscosity 1),
// with or without Navier slip on its interface.
#pragma once

#include <Eigen/Core>

namespace softflow::analysis::theory {

/// Two exact solutions for a spherical drop of radius 1 at the origin in
/// u_inf = E.x + W.x (E symmetric traceless, W antisymmetric), matrix
/// viscosity 1, drop viscosity lambda, dimensionless Navier slip alpha >= 0
/// (alpha_dim eta_m / R, thesis §2.1; 0 = no slip); h = x.E.x, r = |x|,
/// n = x on r = 1 (outward, into the matrix). Both have the form
///   outside u = E.x + A h x/r^5 + B grad(h/r^5) + W.x,   p = 2A h/r^5
///   inside  u = K E.x + M (5 r^2 E.x - 2 h x) + W.x,     p = 21 lambda M h + 2 Gamma
/// with n.u continuous, tangential traction continuous,
/// (I - nn)(sigma_m - sigma_d) n = 0, and the Navier law (SPEC §9 sign)
///   (I - nn)(u_m - u_d) = alpha (I - nn)(sigma_m n),
/// which dissipates. On r = 1 the tangential traction is
/// (I - nn) sigma_m n = T (I - nn) E n and the slip velocity
/// (I - nn)(u_m - u_d) = S (I - nn) E n with S = alpha T. Coefficients
/// derived and checked identically (Stokes in both phases, every interface
/// condition, general E and W) by scripts/theory/derive_slip_drop.py.
///
/// `instantaneous`: the Stokes field at the instant the drop is a sphere,
/// with the full traction balance n.(sigma_m - sigma_d) n = 2 Gamma uniform.
/// This is what one Stokes solve on a spherical interface must reproduce.
/// By linearity it is the no-slip field plus S times the field a unit
/// tangential slip velocity (I - nn) E n drives (X = X0 + S X1, so alpha = 0
/// gives the no-slip numbers exactly). With d = 2 lambda + 3, e = 19 lambda + 16:
///   no slip  A0 = 5(1-lambda)/d, B0 = (1-lambda)/d, K0 = 5/d, M0 = 0, T0 = 10 lambda/d
///            (the interior is a uniform straining flow)
///   per unit slip velocity
///            A1 = 3 lambda/d, B1 = lambda(19 lambda+21)/(d e),
///            K1 = 3(11 lambda+24)/(d e), M1 = -8/e, T1 = -10 lambda(19 lambda+24)/(d e)
///   S = alpha T0 / (1 - alpha T1) = 10 alpha lambda e / Den,
///   T = T0 + S T1 = 10 lambda e / Den,  Den = d e + 10 alpha lambda (19 lambda + 24).
/// Written out: A = 5[(1-lambda) e - 2 alpha lambda (19 lambda-40)]/Den,
/// B = [(1-lambda) e + 80 alpha lambda]/Den, K = 5(e + 128 alpha lambda)/Den,
/// M = -80 alpha lambda/Den. With slip the interior is no longer a uniform
/// strain and its pressure not uniform.
///
/// `taylor_quasi_steady`: Taylor's (1932) field with u.n = 0 on r = 1, SPEC
/// §10, the leading order of the steady, slightly deformed drop; its
/// normal-stress jump is not uniform (that imbalance is what the O(Ca)
/// deformation carries: D/Ca = (19 lambda + 16 + 80 alpha lambda)/(16 L),
/// slip_taylor_deformation), so a Stokes solve on a sphere does not
/// reproduce it. With L = lambda + 1 + 5 alpha lambda:
///   A = -(5 lambda + 2 + 10 alpha lambda)/(2L), B = -lambda/(2L),
///   K = -3/(2L), M = 1/(2L), T = 5 lambda/L, S = 5 alpha lambda/L, i.e.
///   outside u = E.x - (5 lambda+2+10 alpha lambda)/(2L) h x/r^5 - lambda/(2L) grad(h/r^5) + W.x
///           p = -(5 lambda+2+10 alpha lambda)/L h/r^5
///   inside  u = [5 r^2 E.x - 2 h x - 3 E.x]/(2L) + W.x,  p = 21 lambda h/(2L) + 2 Gamma.
/// SPEC §10 prints the outer h x/r^5 coefficient as -(5 lambda+2+10 alpha
/// lambda)/L, without the factor 1/2 (also at alpha = 0); with it n.u is
/// continuous (and zero) at r = 1 (derived and tested). Every other
/// coefficient of SPEC §10, and its D/Ca, is right.
class DropInLinearFlow {
 public:
  enum class Kind { instantaneous, taylor_quasi_steady };

  /// lambda >= 0 (0: a bubble), finite, and slip >= 0 (inf: free slip, the
  /// instantaneous kind only); throws
  /// softflow::InputError otherwise.
  DropInLinearFlow(Kind kind, double lambda, const Eigen::Matrix3d& velocity_gradient,
                   double tension = 0.0, double slip = 0.0);

  /// Simple shear u_inf = (shear_rate y, 0, 0).
  static DropInLinearFlow simple_shear(Kind kind, double lambda, double shear_rate,
                                       double tension = 0.0, double slip = 0.0);

  [[nodiscard]] Eigen::Vector3d velocity(const Eigen::Vector3d& x, bool inside) const;
  [[nodiscard]] double pressure(const Eigen::Vector3d& x, bool inside) const;

  /// The tangential velocity jump (I - nn)(u_m - u_d) = S (I - nn) E n at the
  /// point n = x/|x| of r = 1 (the normal velocity is continuous).
  [[nodiscard]] Eigen::Vector3d slip_velocity(const Eigen::Vector3d& x) const;
  /// The tangential traction (I - nn) sigma_m n = (I - nn) sigma_d n =
  /// T (I - nn) E n at n = x/|x| on r = 1.
  [[nodiscard]] Eigen::Vector3d tangential_traction(const Eigen::Vector3d& x) const;

  /// The rate of work the slip dissipates on r = 1:
  /// int (u_m - u_d).(sigma_m n) dS = alpha int |(I - nn) sigma_m n|^2 dS
  /// = (4 pi / 5) alpha T^2 E:E (int_S |(I - nn) E n|^2 = 4 pi/5 E:E), >= 0.
  [[nodiscard]] double slip_dissipation() const;
  /// The viscous dissipation inside the drop, int_{r<1} 2 lambda D:D dV
  /// = (8 pi / 15) lambda (5 K^2 + 42 K M + 111 M^2) E:E (the outside's is
  /// infinite in an unbounded matrix).
  [[nodiscard]] double interior_dissipation() const;

  /// The coefficients of the form above.
  struct Coefficients {
    double a = 0.0;  ///< A, of h x / r^5 outside (the pressure is 2A h / r^5)
    double b = 0.0;  ///< B, of grad(h / r^5) outside
    double k = 0.0;  ///< K, of E.x inside
    double m = 0.0;  ///< M, of 5 r^2 E.x - 2 h x inside (the pressure is 21 lambda M h)
    double t = 0.0;  ///< T, of the tangential traction (I - nn) E n on r = 1
    double s = 0.0;  ///< S = alpha T, of the slip velocity (I - nn) E n on r = 1
  };
  [[nodiscard]] const Coefficients& coefficients() const { return c_; }
  [[nodiscard]] double viscosity_ratio() const { return lambda_; }
  [[nodiscard]] double slip() const { return alpha_; }

 private:
  Kind kind_;
  double lambda_;
  double alpha_;
  Eigen::Matrix3d e_;  // rate of strain
  Eigen::Matrix3d w_;  // vorticity tensor
  double tension_;
  Coefficients c_;
};

}  // namespace softflow::analysis::theory
