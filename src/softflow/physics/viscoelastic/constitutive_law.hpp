// The interface every constitutive model implements (ConstitutiveLaw), and
// the parameter checks the families' factories share.
//
// What the numerics need from a model, and where they ask for it:
//
//   polymer_stress(c)         tau(c): the stress update after the transport
//                             (simulation::ViscoelasticPhases), eqs. 2.6, 2.22
//   linearized_stress(c_n, c),
//   stress_derivative(c_n)    tau at the D'Avino-Hulsen prediction
//                             c = c_n + dt(...) (eq. 2.37), affine in the
//                             unknown velocity: tau(c_n) + tau'(c_n)[c - c_n],
//                             the load and the matrix of the Stokes kernel
//                             (physics/stokes/viscoelastic_terms)
//   relaxation(c)             r(c) of dc/dt = L c + c L^T + r(c) (eq. 2.7):
//                             the prediction's explicit part
//   log_relaxation(sigma)     the same in log form, g(s)/lambda = c^{-1} r(c)
//                             (r commutes with c), as eigenvalues in the
//                             eigenbasis of s = log c: the source of the
//                             log-conformation transport (eqs. 2.10, 2.38-2.41)
//   inadmissible(c)           a state outside the model's domain (FENE-P:
//                             tr c >= L^2), so that a run stops with a
//                             diagnosis instead of evaluating nonsense
//   solvent_viscosity, modulus, relaxation_time, polymer_viscosity
//                             the Stokes viscosity, the DEVSS-G theta, the
//                             pressure-mass scaling, the case's viscosity ratio
//   model(), values()         its identity, saved with the Stokes factors
//
// Every relaxation here is an isotropic function of c, so it shares c's
// eigenvectors; log_relaxation therefore takes and returns eigenvalues. A
// law is immutable and built once per run (Constitutive::create).
#pragma once

#include <string>
#include <string_view>

#include "softflow/physics/viscoelastic/constitutive.hpp"

namespace softflow::physics::viscoelastic {

/// The derivative of tau at c_n along dc, in the form every model here has:
///   tau'(c_n)[dc] = scale dc + tr(dc) trace_part.
/// A stress affine in c (G (c - I)) has scale = G and no trace part.
struct StressDerivative {
  double scale = 0.0;
  Mat3 trace_part = Mat3::Zero();
  bool has_trace_part = false;
};

/// One phase's constitutive law (header comment). Implementations live one
/// family per file and are made through kConstitutiveModels.
class ConstitutiveLaw {
 public:
  virtual ~ConstitutiveLaw() = default;

  /// The model, as the case names it.
  [[nodiscard]] virtual ConstitutiveModel model() const = 0;
  /// The parameters that rebuild this law: Constitutive::create(model(), values()).
  [[nodiscard]] virtual ConstitutiveValues values() const = 0;

  /// mu (eq. 2.5); the viscosity eta of a Newtonian phase.
  [[nodiscard]] virtual double solvent_viscosity() const = 0;
  /// G (eq. 2.6); 0 for a Newtonian phase.
  [[nodiscard]] virtual double modulus() const = 0;
  /// lambda; +infinity for a solid, 0 for a Newtonian phase.
  [[nodiscard]] virtual double relaxation_time() const = 0;
  /// The zero-shear polymer viscosity eta_p; G lambda unless overridden,
  /// +infinity for a solid (relaxes() false), 0 without a conformation.
  [[nodiscard]] virtual double polymer_viscosity() const;
  /// True unless Newtonian: the phase carries a conformation tensor c.
  [[nodiscard]] virtual bool has_conformation() const { return true; }
  /// True for a liquid with a finite relaxation time.
  [[nodiscard]] virtual bool relaxes() const = 0;

  /// tau(c).
  [[nodiscard]] virtual Mat3 polymer_stress(const Mat3& c) const = 0;
  /// tau(c_n) + tau'(c_n)[c - c_n]: tau(c) itself (the default) for a
  /// stress affine in c.
  [[nodiscard]] virtual Mat3 linearized_stress(const Mat3& c_n, const Mat3& c) const;
  /// tau'(c_n); the default: modulus() times the identity map.
  [[nodiscard]] virtual StressDerivative stress_derivative(const Mat3& c_n) const;

  /// r(c), the relaxation of dc/dt (0 for a solid).
  [[nodiscard]] virtual Mat3 relaxation(const Mat3& c) const = 0;
  /// The eigenvalues of c^{-1} r(c) (= g(s)/lambda, the relaxation part of
  /// ds/dt) at the s = log c with eigenvalues `sigma`.
  [[nodiscard]] virtual Vec3 log_relaxation(const Vec3& sigma) const = 0;
  /// Empty if the conformation c (positive definite) lies in the model's
  /// domain; otherwise what is wrong, in words. Every c by default.
  [[nodiscard]] virtual std::string inadmissible(const Mat3& /*c*/) const { return {}; }
};

/// A parameter of ConstitutiveValues with the words its messages use.
struct Parameter {
  const std::optional<double>& value;
  std::string_view name;  // e.g. "mobility alpha"
};

/// The checks of one model's parameters, each message naming the model,
/// the parameter with its symbol and the offending value; all throw
/// softflow::InputError.
class ParameterCheck {
 public:
  explicit ParameterCheck(ConstitutiveModel model) : model_(model) {}

  [[noreturn]] void fail(std::string_view message) const;
  /// A parameter the model needs: given and finite.
  double required(const Parameter& p) const;
  double positive(const Parameter& p) const;
  double non_negative(const Parameter& p) const;
  /// A parameter the model does not have. `zero_allowed`: a zero is the
  /// model's own value (e.g. mu = 0 for UCM) and may be stated.
  void absent(const Parameter& p, std::string_view why, bool zero_allowed = false) const;
  /// G or eta_p = G lambda, exactly one of them.
  double modulus(const Parameter& g, const Parameter& eta_p, double lambda) const;

 private:
  ConstitutiveModel model_;
};

}  // namespace softflow::physics::viscoelastic
