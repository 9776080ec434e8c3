#include "softflow/physics/viscoelastic/constitutive.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <fmt/format.h>

#include "softflow/common/error.hpp"
#include "softflow/physics/viscoelastic/constitutive_law.hpp"

namespace softflow::physics::viscoelastic {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

const ConstitutiveModelEntry& entry(ConstitutiveModel model) {
  for (const auto& e : kConstitutiveModels)
    if (e.model == model) return e;
  throw Error(fmt::format("constitutive model {}: not registered", static_cast<int>(model)));
}

// "a, b or c" of the registered names, for messages.
std::string registered_names() {
  std::string out;
  for (std::size_t i = 0; i < kConstitutiveModels.size(); ++i) {
    if (i > 0) out += i + 1 == kConstitutiveModels.size() ? " or " : ", ";
    out += kConstitutiveModels[i].name;
  }
  return out;
}

}  // namespace

// ---- names ----

std::string_view to_string(ConstitutiveModel model) {
  for (const auto& e : kConstitutiveModels)
    if (e.model == model) return e.name;
  return "unknown";
}

ConstitutiveModel constitutive_model_from_string(std::string_view name) {
  for (const auto& e : kConstitutiveModels)
    if (e.name == name) return e.model;
  throw InputError(
      fmt::format("unknown constitutive model '{}': use {}", name, registered_names()));
}

// ---- ParameterCheck ----

void ParameterCheck::fail(std::string_view message) const {
  throw InputError(fmt::format("constitutive model '{}': {}", to_string(model_), message));
}

double ParameterCheck::required(const Parameter& p) const {
  if (!p.value) fail(fmt::format("the {} is required", p.name));
  if (!std::isfinite(*p.value)) fail(fmt::format("the {} = {} is not finite", p.name, *p.value));
  return *p.value;
}

double ParameterCheck::positive(const Parameter& p) const {
  const double v = required(p);
  if (!(v > 0.0)) fail(fmt::format("the {} = {} must be positive", p.name, v));
  return v;
}

double ParameterCheck::non_negative(const Parameter& p) const {
  const double v = required(p);
  if (!(v >= 0.0)) fail(fmt::format("the {} = {} must not be negative", p.name, v));
  return v;
}

void ParameterCheck::absent(const Parameter& p, std::string_view why, bool zero_allowed) const {
  if (!p.value || (zero_allowed && *p.value == 0.0)) return;
  fail(fmt::format("the {} = {} is not a parameter of this model ({})", p.name, *p.value, why));
}

double ParameterCheck::modulus(const Parameter& g, const Parameter& eta_p, double lambda) const {
  if (g.value && eta_p.value)
    fail(fmt::format("give the {} or the {} (= G lambda), not both", g.name, eta_p.name));
  if (eta_p.value) return positive(eta_p) / lambda;
  if (!g.value) fail(fmt::format("the {} (or the {} = G lambda) is required", g.name, eta_p.name));
  return positive(g);
}

// ---- ConstitutiveLaw defaults ----

double ConstitutiveLaw::polymer_viscosity() const {
  if (!has_conformation()) return 0.0;
  return relaxes() ? modulus() * relaxation_time() : kInfinity;
}

Mat3 ConstitutiveLaw::linearized_stress(const Mat3& /*c_n*/, const Mat3& c) const {
  return polymer_stress(c);
}

StressDerivative ConstitutiveLaw::stress_derivative(const Mat3& /*c_n*/) const {
  return {modulus(), Mat3::Zero(), false};
}

// ---- Constitutive ----

Constitutive Constitutive::create(ConstitutiveModel model, const ConstitutiveValues& values) {
  const ParameterCheck check(model);
  if (model != ConstitutiveModel::newtonian)
    check.absent({values.viscosity, "viscosity eta"},
                 "a viscoelastic phase has a solvent viscosity mu");
  // A parameter only some other model has (the Giesekus mobility, the
  // FENE-P extensibility) is refused here, so that the families need not
  // know of each other; its neutral value (alpha = 0) may be stated.
  for (const auto& owner : kConstitutiveModels) {
    if (owner.own_parameter.empty() || owner.model == model) continue;
    for_each_parameter(values, [&](std::string_view key, std::string_view words,
                                   const std::optional<double>& value) {
      if (key != owner.own_parameter || !value) return;
      if (owner.neutral_value && *value == *owner.neutral_value) return;
      check.absent({value, words}, fmt::format("only the {} model has one", owner.name));
    });
  }
  return Constitutive(entry(model).make(model, values));
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
    default: break;  // later models were saved by values()
  }
  throw Error(fmt::format("Constitutive::from_parameters: model '{}' needs its values()",
                          to_string(model)));
}

ConstitutiveModel Constitutive::model() const { return law_->model(); }
ConstitutiveValues Constitutive::values() const { return law_->values(); }
double Constitutive::solvent_viscosity() const { return law_->solvent_viscosity(); }
double Constitutive::modulus() const { return law_->modulus(); }
double Constitutive::relaxation_time() const { return law_->relaxation_time(); }
double Constitutive::mobility() const { return law_->values().mobility.value_or(0.0); }
double Constitutive::polymer_viscosity() const { return law_->polymer_viscosity(); }
double Constitutive::zero_shear_viscosity() const {
  return law_->solvent_viscosity() + law_->polymer_viscosity();
}
bool Constitutive::has_conformation() const { return law_->has_conformation(); }
bool Constitutive::relaxes() const { return law_->relaxes(); }

// ---- pointwise ----

Mat3 polymer_stress(const Constitutive& model, const Mat3& c) {
  return model.law().polymer_stress(c);
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
  return model.law().relaxation(c);
}

Mat3 conformation_rate(const Constitutive& model, const Mat3& velocity_gradient, const Mat3& c) {
  return upper_convected_terms(velocity_gradient, c) + conformation_relaxation(model, c);
}

}  // namespace softflow::physics::viscoelastic
