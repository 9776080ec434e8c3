// Constitutive models of one phase (thesis §2.2.1-2.2.2, SPEC §1): their
// names, validated parameters, and the registry of the model families; the
// stress and the conformation equation written pointwise (no convection).
//
//   Newtonian            T = 2 eta D                                   eq. 2.4
//   viscoelastic liquid  T = 2 mu D + tau,  tau = G (c - I)            eqs. 2.5-2.6
//     Giesekus           lambda c_UC + (c - I) + alpha (c - I)^2 = 0   eq. 2.7
//     Oldroyd-B          alpha = 0;  UCM: alpha = 0 and mu = 0
//     FENE-P             tau = G (f c - I), lambda c_UC + (f c - I) = 0,
//                        f = (L^2 - 3) / (L^2 - tr c)                  (fene_p.cpp)
//   elastic solid        c_UC = 0 (lambda -> infinity): c is the Finger
//                        tensor B, tau = G (B - I)                     eqs. 2.21-2.22
//     neo-Hookean        mu = 0;  Kelvin-Voigt: mu > 0
//
// with D = (L + L^T)/2, L_ij = du_i/dx_j, and the upper-convected derivative
// (eq. 2.8, where (grad u)_ij = du_j/dx_i, so (grad u)^T = L)
//
//   c_UC = dc/dt - L c - c L^T        (dc/dt the material derivative).
//
// Solving the relaxation law for dc/dt gives the conformation equation of
// every model,
//
//   dc/dt = L c + c L^T + r(c),   r(c) = -(1/lambda) ((c - I) + alpha (c - I)^2)   (eq. 2.7)
//
// (r = -(1/lambda)(f c - I) for FENE-P, r = 0 for the solids, eq. 2.21). Every
// flow starts from c = I (eq. 2.20).
//
// Each model family is a ConstitutiveLaw (constitutive_law.hpp) in a file of
// its own: newtonian.cpp, giesekus.cpp (Oldroyd-B, Giesekus, UCM),
// elastic_solids.cpp (neo-Hookean, Kelvin-Voigt), fene_p.cpp. A run builds
// each phase's law once from the case (Constitutive::create) and hands the
// same immutable object to the Stokes kernel, the log-conformation source and
// the stress update. A new model is a new family file plus, here, its name
// in ConstitutiveModel, its parameters in ConstitutiveValues and its row in
// kConstitutiveModels; and its case keys (io/case_keys.cpp).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "softflow/physics/viscoelastic/symmetric_tensor.hpp"

namespace softflow::physics::viscoelastic {

/// The models a case file names. Values are saved in checkpoints: append,
/// never reorder.
enum class ConstitutiveModel { newtonian, oldroyd_b, giesekus, ucm, neo_hookean, kelvin_voigt, fene_p };

/// "newtonian", "oldroyd_b", "giesekus", "ucm", "neo_hookean", "kelvin_voigt",
/// "fene_p": the names a case file uses.
[[nodiscard]] std::string_view to_string(ConstitutiveModel model);
/// The inverse of to_string. Throws softflow::InputError listing the names.
[[nodiscard]] ConstitutiveModel constitutive_model_from_string(std::string_view name);

/// The parameters a user gives for one phase, as read (units of the case:
/// viscosities in stress * time, G in stress, lambda in time). Unset means
/// not given; Constitutive::create decides what each model needs.
struct ConstitutiveValues {
  std::optional<double> viscosity = std::nullopt;          ///< eta: Newtonian only
  std::optional<double> solvent_viscosity = std::nullopt;  ///< mu
  std::optional<double> modulus = std::nullopt;            ///< G
  std::optional<double> polymer_viscosity = std::nullopt;  ///< eta_p = G lambda, instead of G
  std::optional<double> relaxation_time = std::nullopt;    ///< lambda: liquids only
  std::optional<double> mobility = std::nullopt;           ///< alpha: Giesekus only
  std::optional<double> extensibility = std::nullopt;      ///< L^2 = max tr c: FENE-P only
};

/// Calls f(key, words, value) for every parameter of ConstitutiveValues:
/// its case-file key, the words messages use, and the value (a reference
/// into `values`). Checkpoints save a model by these keys.
template <class Values, class F>
void for_each_parameter(Values& values, F&& f) {
  f("viscosity", "viscosity eta", values.viscosity);
  f("solvent_viscosity", "solvent viscosity mu", values.solvent_viscosity);
  f("modulus", "modulus G", values.modulus);
  f("polymer_viscosity", "polymer viscosity eta_p", values.polymer_viscosity);
  f("relaxation_time", "relaxation time lambda", values.relaxation_time);
  f("mobility", "mobility alpha", values.mobility);
  f("extensibility", "extensibility L^2", values.extensibility);
}

class ConstitutiveLaw;  // constitutive_law.hpp
using ConstitutiveLawPtr = std::shared_ptr<const ConstitutiveLaw>;

/// A family's factory: the validated law of `model` (one of the family's)
/// from `values`; throws softflow::InputError naming the parameter.
using ConstitutiveLawFactory = ConstitutiveLawPtr (*)(ConstitutiveModel model,
                                                     const ConstitutiveValues& values);

// The model families, one file each.
[[nodiscard]] ConstitutiveLawPtr make_newtonian_law(ConstitutiveModel, const ConstitutiveValues&);
[[nodiscard]] ConstitutiveLawPtr make_giesekus_law(ConstitutiveModel, const ConstitutiveValues&);
[[nodiscard]] ConstitutiveLawPtr make_elastic_solid_law(ConstitutiveModel,
                                                        const ConstitutiveValues&);
[[nodiscard]] ConstitutiveLawPtr make_fene_p_law(ConstitutiveModel, const ConstitutiveValues&);

/// One row of the registry: a model, its case-file name, its family's
/// factory, and the parameter only this model has (a key of
/// for_each_parameter; empty if none) with the value that is the same as
/// leaving it out (stated for another model, it is then accepted), if any.
struct ConstitutiveModelEntry {
  ConstitutiveModel model;
  std::string_view name;
  ConstitutiveLawFactory make;
  std::string_view own_parameter = {};
  std::optional<double> neutral_value = std::nullopt;
};

inline constexpr std::array<ConstitutiveModelEntry, 7> kConstitutiveModels{{
    {ConstitutiveModel::newtonian, "newtonian", make_newtonian_law},
    {ConstitutiveModel::oldroyd_b, "oldroyd_b", make_giesekus_law},
    {ConstitutiveModel::giesekus, "giesekus", make_giesekus_law, "mobility", 0.0},
    {ConstitutiveModel::ucm, "ucm", make_giesekus_law},
    {ConstitutiveModel::neo_hookean, "neo_hookean", make_elastic_solid_law},
    {ConstitutiveModel::kelvin_voigt, "kelvin_voigt", make_elastic_solid_law},
    {ConstitutiveModel::fene_p, "fene_p", make_fene_p_law, "extensibility"},
}};

/// A phase's validated constitutive model: a handle to its immutable
/// ConstitutiveLaw, cheap to copy (copies share the law). Made only by the
/// factories, which throw softflow::InputError naming the parameter (e.g.
/// "the mobility alpha = 1.5 must lie in [0, 1]") for a value that is
/// missing, not finite, out of range, or not a parameter of the model.
///
/// Every model has mu (the whole viscosity eta of a Newtonian phase, so
/// T = 2 mu D + tau holds throughout), G and lambda. A Newtonian phase has
/// G = 0 and no conformation; a solid has lambda = +infinity.
class Constitutive {
 public:
  /// The general factory (for case files): checks that `values` gives
  /// exactly the parameters `model` needs and that each is admissible:
  ///   newtonian      viscosity > 0
  ///   oldroyd_b      solvent_viscosity >= 0, G > 0 or eta_p > 0, lambda > 0
  ///   giesekus       as oldroyd_b, and mobility in [0, 1]
  ///   ucm            G > 0 or eta_p > 0, lambda > 0 (solvent viscosity 0 if given)
  ///   fene_p         as oldroyd_b, and extensibility L^2 > 3
  ///   neo_hookean    G > 0 (solvent viscosity 0 if given)
  ///   kelvin_voigt   solvent_viscosity > 0, G > 0
  /// G and eta_p are alternatives (G = eta_p / lambda); a parameter the model
  /// does not have is refused rather than ignored, so that a typo in the
  /// model name cannot silently drop a parameter.
  [[nodiscard]] static Constitutive create(ConstitutiveModel model,
                                           const ConstitutiveValues& values);

  [[nodiscard]] static Constitutive newtonian(double viscosity);
  [[nodiscard]] static Constitutive oldroyd_b(double solvent_viscosity, double modulus,
                                              double relaxation_time);
  [[nodiscard]] static Constitutive giesekus(double solvent_viscosity, double modulus,
                                             double relaxation_time, double mobility);
  [[nodiscard]] static Constitutive ucm(double modulus, double relaxation_time);
  [[nodiscard]] static Constitutive neo_hookean(double modulus);
  [[nodiscard]] static Constitutive kelvin_voigt(double solvent_viscosity, double modulus);
  /// The model with the parameters the accessors return (solvent_viscosity,
  /// modulus, relaxation_time, mobility), those it does not have ignored:
  /// checkpoints written before values() was saved. Validated as the
  /// factories are.
  [[nodiscard]] static Constitutive from_parameters(ConstitutiveModel model, double mu, double g,
                                                    double lambda, double alpha);

  /// The law: stress, relaxation, viscosities (constitutive_law.hpp).
  [[nodiscard]] const ConstitutiveLaw& law() const { return *law_; }

  // Its identity: create(model(), values()) makes the same model.
  [[nodiscard]] ConstitutiveModel model() const;
  [[nodiscard]] ConstitutiveValues values() const;

  /// mu; the viscosity eta for a Newtonian phase.
  [[nodiscard]] double solvent_viscosity() const;
  /// G (0 for a Newtonian phase).
  [[nodiscard]] double modulus() const;
  /// lambda (+infinity for a solid, 0 for a Newtonian phase).
  [[nodiscard]] double relaxation_time() const;
  /// alpha (0 except for Giesekus).
  [[nodiscard]] double mobility() const;
  /// The zero-shear polymer viscosity eta_p (G lambda for the liquids of
  /// this file), +infinity for a solid, 0 for a Newtonian phase.
  [[nodiscard]] double polymer_viscosity() const;
  /// eta = mu + eta_p (eq. 2.9): the zero-shear viscosity of a liquid,
  /// the viscosity of a Newtonian phase, +infinity for a solid.
  [[nodiscard]] double zero_shear_viscosity() const;

  /// True unless Newtonian: the phase carries a conformation tensor c.
  [[nodiscard]] bool has_conformation() const;
  /// True for the liquids with a finite relaxation time; false for the
  /// solids (no relaxation, r = 0) and Newtonian.
  [[nodiscard]] bool relaxes() const;

 private:
  explicit Constitutive(ConstitutiveLawPtr law) : law_(std::move(law)) {}

  ConstitutiveLawPtr law_;
};

/// tau(c): G (c - I) (eq. 2.6; eq. 2.22 for a solid), G (f c - I) for
/// FENE-P; zero for a Newtonian phase.
[[nodiscard]] Mat3 polymer_stress(const Constitutive& model, const Mat3& c);

/// T = 2 mu D + tau (eqs. 2.4-2.5), D the rate of strain; c is not read for
/// a Newtonian phase.
[[nodiscard]] Mat3 extra_stress(const Constitutive& model, const Mat3& rate_of_strain,
                                const Mat3& c);

/// L c + c L^T: the upper-convected terms of eq. 2.8 moved to the right-hand
/// side; linear in L.
[[nodiscard]] Mat3 upper_convected_terms(const Mat3& velocity_gradient, const Mat3& c);

/// r(c): the relaxation of the model's conformation equation (eq. 2.7:
/// -(1/lambda) ((c - I) + alpha (c - I)^2)); zero for a solid. Throws
/// softflow::Error for a Newtonian phase.
[[nodiscard]] Mat3 conformation_relaxation(const Constitutive& model, const Mat3& c);

/// dc/dt = L c + c L^T + r(c): the conformation equation without
/// convection, L_ij = du_i/dx_j. Throws softflow::Error for a Newtonian phase.
[[nodiscard]] Mat3 conformation_rate(const Constitutive& model, const Mat3& velocity_gradient,
                                     const Mat3& c);

}  // namespace softflow::physics::viscoelastic
