#include "softflow/physics/viscoelastic/constitutive.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::physics::viscoelastic {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

constexpr std::array<std::pair<ConstitutiveModel, std::string_view>, 6> kNames{{
    {ConstitutiveModel::newtonian, "newtonian"},
    {ConstitutiveModel::oldroyd_b, "oldroyd_b"},
    {ConstitutiveModel::giesekus, "giesekus"},
    {ConstitutiveModel::ucm, "ucm"},
    {ConstitutiveModel::neo_hookean, "neo_hookean"},
    {ConstitutiveModel::kelvin_voigt, "kelvin_voigt"},
}};

// One parameter of ConstitutiveValues with the words its messages use.
struct Parameter {
  const std::optional<double>& value;
  std::string_view name;  // e.g. "mobility alpha"
};

// Checks one model's parameters and builds every message, so that each
// names the model, the parameter with its symbol, and the offending value.
class Checker {
 public:
  explicit Checker(ConstitutiveModel model) : model_(model) {}

  [[noreturn]] void fail(std::string_view message) const {
    throw InputError(fmt::format("constitutive model '{}': {}", to_string(model_), message));
  }

  // A parameter the model needs: given and finite.
  double required(const Parameter& p) const {
    if (!p.value) fail(fmt::format("the {} is required", p.name));
    if (!std::isfinite(*p.value)) fail(fmt::format("the {} = {} is not finite", p.name, *p.value));
    return *p.value;
  }
  double positive(const Parameter& p) const {
    const double v = required(p);
    if (!(v > 0.0)) fail(fmt::format("the {} = {} must be positive", p.name, v));
    return v;
  }
  double non_negative(const Parameter& p) const {
    const double v = required(p);
    if (!(v >= 0.0)) fail(fmt::format("the {} = {} must not be negative", p.name, v));
    return v;
  }
  // A parameter the model does not have. `zero_allowed`: a zero is the
  // model's own value (e.g. mu = 0 for UCM) and may be stated.
  void absent(const Parameter& p, std::string_view why, bool zero_allowed = false) const {
    if (!p.value || (zero_allowed && *p.value == 0.0)) return;
    fail(fmt::format("the {} = {} is not a parameter of this model ({})", p.name, *p.value, why));
  }
  // G or eta_p = G lambda, exactly one of them.
  double modulus(const Parameter& g, const Parameter& eta_p, double lambda) const {
    if (g.value && eta_p.value)
      fail(fmt::format("give the {} or the {} (= G lambda), not both", g.name, eta_p.name));
    if (eta_p.value) return positive(eta_p) / lambda;
    if (!g.value)
      fail(fmt::format("the {} (or the {} = G lambda) is required", g.name, eta_p.name));
    return positive(g);
  }

 private:
  ConstitutiveModel model_;
};

}  // namespace

std::string_view to_string(ConstitutiveModel model) {
  for (const auto& [m, name] : kNames)
    if (m == model) return name;
  return "unknown";
}

ConstitutiveModel constitutive_model_from_string(std::string_view name) {
  for (const auto& [m, n] : kNames)
    if (n == name) return m;
  throw InputError(fmt::format(
      "unknown constitutive model '{}': use newtonian, oldroyd_b, giesekus, ucm, neo_hookean or "
      "kelvin_voigt",
      name));
}

Constitutive Constitutive::create(ConstitutiveModel model, const ConstitutiveValues& v) {
  const Checker check(model);
  const Parameter eta{v.viscosity, "viscosity eta"};
  const Parameter mu{v.solvent_viscosity, "solvent viscosity mu"};
  const Parameter g{v.modulus, "modulus G"};
  const Parameter eta_p{v.polymer_viscosity, "polymer viscosity eta_p"};
  const Parameter lambda{v.relaxation_time, "relaxation time lambda"};
  const Parameter alpha{v.mobility, "mobility alpha"};

  const bool newtonian = model == ConstitutiveModel::newtonian;
  if (!newtonian) check.absent(eta, "a viscoelastic phase has a solvent viscosity mu");
  if (model != ConstitutiveModel::giesekus)
    check.absent(alpha, "only the Giesekus model has one", true);

  switch (model) {
    case ConstitutiveModel::newtonian: {
      for (const auto& p : {mu, g, eta_p, lambda})
        check.absent(p, "a Newtonian phase has the viscosity eta only");
      return {model, check.positive(eta), 0.0, 0.0, 0.0};
    }
    case ConstitutiveModel::oldroyd_b:
    case ConstitutiveModel::giesekus:
    case ConstitutiveModel::ucm: {
      double solvent = 0.0;
      if (model == ConstitutiveModel::ucm)
        check.absent(mu, "UCM is the liquid without solvent, mu = 0; use oldroyd_b", true);
      else
        solvent = check.non_negative(mu);
      // lambda = 0 would make the relaxation term 1/lambda infinite: the
      // liquid is then Newtonian and should be declared so.
      const double time = check.positive(lambda);
      const double modulus = check.modulus(g, eta_p, time);
      double mobility = 0.0;
      if (model == ConstitutiveModel::giesekus) {
        mobility = check.required(alpha);
        if (!(mobility >= 0.0 && mobility <= 1.0))
          check.fail(fmt::format("the mobility alpha = {} must lie in [0, 1]", mobility));
      }
      return {model, solvent, modulus, time, mobility};
    }
    case ConstitutiveModel::neo_hookean:
    case ConstitutiveModel::kelvin_voigt: {
      const char* solid = "an elastic solid is the limit lambda -> infinity";
      check.absent(lambda, solid);
      check.absent(eta_p, "an elastic solid's G lambda is infinite; give the modulus G");
      double solvent = 0.0;
      if (model == ConstitutiveModel::neo_hookean)
        check.absent(mu, "the neo-Hookean solid has mu = 0; use kelvin_voigt", true);
      else
        solvent = check.positive(mu);  // mu = 0 is the neo-Hookean solid
      return {model, solvent, check.positive(g), kInfinity, 0.0};
    }
  }
  check.fail("unknown model");
}

Constitutive Constitutive::newtonian(double viscosity) {
  return create(ConstitutiveModel::newtonian, {.viscosity = viscosity});
}

Constitutive Constitutive::oldroyd_b(double solvent_viscosity, double modulus,
                                     double relaxation_time) {
  return create(ConstitutiveModel::oldroyd_b, {.solvent_viscosity = solvent_viscosity,
                                               .modulus = modulus,
                                               .relaxation_time = relaxation_time});
}

Constitutive Constitutive::giesekus(double solvent_viscosity, double modulus,
                                    double relaxation_time, double mobility) {
  return create(ConstitutiveModel::giesekus, {.solvent_viscosity = solvent_viscosity,
                                              .modulus = modulus,
                                              .relaxation_time = relaxation_time,
                                              .mobility = mobility});
}

Constitutive Constitutive::ucm(double modulus, double relaxation_time) {
  return create(ConstitutiveModel::ucm, {.modulus = modulus, .relaxation_time = relaxation_time});
}

Constitutive Constitutive::neo_hookean(double modulus) {
  return create(ConstitutiveModel::neo_hookean, {.modulus = modulus});
}

Constitutive Constitutive::kelvin_voigt(double solvent_viscosity, double modulus) {
  return create(ConstitutiveModel::kelvin_voigt,
                {.solvent_viscosity = solvent_viscosity, .modulus = modulus});
}

Constitutive Constitutive::from_parameters(ConstitutiveModel model, double mu, double g,
                                           double lambda, double alpha) {
  switch (model) {
    case ConstitutiveModel::newtonian: return newtonian(mu);
    case ConstitutiveModel::oldroyd_b: return oldroyd_b(mu, g, lambda);
    case ConstitutiveModel::giesekus: return giesekus(mu, g, lambda, alpha);
    case ConstitutiveModel::ucm: return ucm(g, lambda);
    case ConstitutiveModel::neo_hookean: return neo_hookean(g);
    case ConstitutiveModel::kelvin_voigt: return kelvin_voigt(mu, g);
  }
  throw Error("Constitutive::from_parameters: unknown model");
}

double Constitutive::polymer_viscosity() const {
  if (!has_conformation()) return 0.0;
  return relaxes() ? modulus_ * relaxation_time_ : kInfinity;
}

double Constitutive::zero_shear_viscosity() const {
  return solvent_viscosity_ + polymer_viscosity();
}

bool Constitutive::relaxes() const {
  return model_ == ConstitutiveModel::oldroyd_b || model_ == ConstitutiveModel::giesekus ||
         model_ == ConstitutiveModel::ucm;
}

Mat3 polymer_stress(const Constitutive& model, const Mat3& c) {
  if (!model.has_conformation()) return Mat3::Zero();
  return model.modulus() * (c - Mat3::Identity());
}

Mat3 extra_stress(const Constitutive& model, const Mat3& rate_of_strain, const Mat3& c) {
  return 2.0 * model.solvent_viscosity() * rate_of_strain + polymer_stress(model, c);
}

Mat3 upper_convected_terms(const Mat3& velocity_gradient, const Mat3& c) {
  const Mat3 lc = velocity_gradient * c;
  return lc + lc.transpose();  // c symmetric: c L^T = (L c)^T
}

Mat3 conformation_relaxation(const Constitutive& model, const Mat3& c) {
  if (!model.has_conformation())
    throw Error("conformation_relaxation: a Newtonian phase has no conformation tensor");
  if (!model.relaxes()) return Mat3::Zero();  // eq. 2.21: the solid does not relax
  const Mat3 a = c - Mat3::Identity();
  return -(a + model.mobility() * a * a) / model.relaxation_time();  // eq. 2.7
}

Mat3 conformation_rate(const Constitutive& model, const Mat3& velocity_gradient, const Mat3& c) {
  return upper_convected_terms(velocity_gradient, c) + conformation_relaxation(model, c);
}

}  // namespace softflow::physics::viscoelastic
