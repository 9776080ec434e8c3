#include "softflow/io/case_config.hpp"

#include "softflow/geometry/random_packing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <fmt/format.h>
#include <toml.hpp>

#include "softflow/common/error.hpp"
#include "softflow/io/case_keys.hpp"
#include "softflow/io/key_schema.hpp"
#include "softflow/physics/stokes/interface_slip.hpp"
#include "softflow/physics/viscoelastic/steady_shear.hpp"

namespace softflow::io {

namespace {

using physics::viscoelastic::Constitutive;
using physics::viscoelastic::ConstitutiveModel;
using physics::viscoelastic::ConstitutiveValues;
using schema::Diagnostics;
using schema::Read;
using schema::TableRead;
using schema::Value;

constexpr double kDefaultCapillaryNumber = 0.1;

// ---------------------------------------------------------------------------
// What involves several keys: checked after every key has been read on its
// own (case_keys.cpp declares those).

/// What the objects need from the rest of the file to resolve Gamma; a flag
/// is false when that key was bad (already reported), so no follow-up
/// message is made from a value the user never meant.
struct FlowState {
  bool matrix_viscosity_ok = true;
  bool shear_rate_ok = true;
};

// ---- constitutive models ----

/// The keys that make a phase's constitutive model (a table has some of
/// them): the model, its parameters (physics::viscoelastic::for_each_parameter)
/// and the dimensionless alternatives.
const std::vector<std::string_view>& model_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> k{"model", "viscosity_ratio", "elastic_capillary_number"};
    ConstitutiveValues values;
    physics::viscoelastic::for_each_parameter(
        values, [&](std::string_view key, std::string_view, auto&) { k.push_back(key); });
    return k;
  }();
  return keys;
}

/// Whether the model keys of a table were read without a problem: a bad
/// value or a missing required key is reported already, and a check built
/// on it would only repeat it or follow from a value the user never meant.
template <class Target>
bool model_keys_read(const schema::Table<Target>& declared, const TableRead& t,
                     const Target& target) {
  for (const std::string_view name : model_keys()) {
    const auto* key = declared.find(name);
    if (!key) continue;
    const Read r = t.status(name);
    if (r == Read::bad) return false;
    if (r == Read::absent && key->required && schema::applies(declared, *key, target)) return false;
  }
  return true;
}

/// Exactly one of two alternative keys, e.g. modulus or polymer_viscosity
/// (= G lambda), for a model that needs one of them.
bool one_of(const TableRead& t, std::string_view first, std::string_view second,
            ConstitutiveModel model, std::string_view relation, Diagnostics& diag) {
  const Value* a = t.value(first);
  const Value* b = t.value(second);
  if (a && b) {
    diag.error(fmt::format("{} gives both {} = {} and {} = {}: give only one ({})", t.prefix(),
                           first, schema::describe(*a), second, schema::describe(*b), relation));
    return false;
  }
  if (!a && !b) {
    diag.error(fmt::format("{}: missing: model = \"{}\" needs {} or {} ({})", t.path(first),
                           physics::viscoelastic::to_string(model), first, second, relation));
    return false;
  }
  return true;
}

/// The case-file key of each parameter Constitutive::create names in its
/// messages ("the solvent viscosity mu = 0 must be positive"), but the
/// Newtonian viscosity (its words are within "polymer viscosity eta_p").
struct ParameterKey {
  std::string_view words;
  std::string_view key;
};
const std::vector<ParameterKey>& parameter_keys() {
  static const std::vector<ParameterKey> keys = [] {
    std::vector<ParameterKey> k;
    ConstitutiveValues values;
    physics::viscoelastic::for_each_parameter(
        values, [&](std::string_view key, std::string_view words, auto&) {
          if (key != "viscosity") k.push_back({words, key});
        });
    return k;
  }();
  return keys;
}

/// The phase's model by Constitutive::create, where the rules of each model
/// live (the keys' ranges only repeat those that hold for every model). A
/// refusal is reported under the key whose parameter it names first
/// ("objects[1].solvent_viscosity = 0: constitutive model 'kelvin_voigt':
/// the solvent viscosity mu = 0 must be positive"), else under the table.
/// A model whose G or eta = mu + G lambda overflows or underflows (eta_p =
/// 1e300 with lambda = 1e-300) is refused too: no run could use it.
std::optional<Constitutive> make_model(const TableRead& t, ConstitutiveModel model,
                                       const ConstitutiveValues& values, Diagnostics& diag) {
  std::optional<Constitutive> m;
  try {
    m = Constitutive::create(model, values);
  } catch (const InputError& e) {
    const std::string what = e.what();
    std::size_t first = std::string::npos;
    std::string_view key;
    for (const auto& [words, k] : parameter_keys()) {
      const auto at = what.find(words);
      if (at < first && t.value(k)) {
        first = at;
        key = k;
      }
    }
    if (!key.empty())
      diag.error(t.path(key), *t.value(key), what);
    else
      diag.error(fmt::format("{}: {}", t.prefix(), what));
    return std::nullopt;
  }
  const double g = m->modulus(), eta = m->zero_shear_viscosity();
  if (!(std::isfinite(g) && g > 0.0) || (m->relaxes() && !(std::isfinite(eta) && eta > 0.0))) {
    diag.error(
        fmt::format("{}: model = \"{}\" with these parameters gives G = {} and eta = mu + "
                    "G lambda = {}, beyond the range of a double: state the case in "
                    "other units",
                    t.prefix(), physics::viscoelastic::to_string(model), g, eta));
    return std::nullopt;
  }
  return m;
}

/// [matrix]: a viscoelastic matrix's model, and eta_m, the viscosity of Ca,
/// Ca_e, lambda and p, its zero-shear viscosity mu + G lambda (thesis eq. 2.9).
/// False when eta_m is unknown (a bad key, reported).
bool resolve_matrix(const TableRead& t, CaseConfig& c, Diagnostics& diag) {
  if (!model_keys_read(*case_keys().table("matrix"), t, c)) return false;
  if (c.matrix_model == ConstitutiveModel::newtonian) return true;
  if (!one_of(t, "modulus", "polymer_viscosity", c.matrix_model, "eta_p = G lambda", diag))
    return false;
  const auto model = make_model(t, c.matrix_model, c.matrix_parameters, diag);
  if (!model) return false;
  c.matrix_viscosity = model->zero_shear_viscosity();
  return true;
}

/// The characteristic shear rate of each flow type (oscillatory: the
/// shear-rate amplitude gamma0 omega), and walls that start or stop must
/// move at all.
FlowState resolve_flow(bool matrix_ok, const TableRead& flow, CaseConfig& c, Diagnostics& diag) {
  FlowState state;
  state.matrix_viscosity_ok = matrix_ok;
  if (flow.status("type") == Read::bad) {
    state.shear_rate_ok = false;
    return state;
  }
  switch (c.flow.type) {
    case FlowType::oscillatory:
      state.shear_rate_ok =
          flow.status("strain_amplitude") == Read::ok && flow.status("frequency") == Read::ok;
      if (state.shear_rate_ok) c.shear_rate = c.flow.strain_amplitude * c.flow.frequency;
      break;
    case FlowType::start_up:
    case FlowType::cessation:
      state.shear_rate_ok = flow.status("shear_rate") != Read::bad;
      if (state.shear_rate_ok && c.shear_rate == 0.0) {
        // Only a given value can be 0 (the default is 1).
        diag.error(flow.path("shear_rate"), *flow.value("shear_rate"),
                   fmt::format("type = \"{}\" needs a shear rate > 0 (walls at rest have "
                               "nothing to {}; for a case at rest use type = \"steady\")",
                               c.flow.type == FlowType::start_up ? "start_up" : "cessation",
                               c.flow.type == FlowType::start_up ? "start" : "stop"));
        state.shear_rate_ok = false;
      }
      break;
    case FlowType::steady: state.shear_rate_ok = flow.status("shear_rate") != Read::bad; break;
  }
  return state;
}

/// An elastic particle's G = eta_m gamma_dot / Ca_e (thesis §2.2.2), into
/// o.parameters.modulus. False when it cannot be had: gamma_dot = 0
/// (reported), or eta_m or gamma_dot unknown (a bad key, reported).
bool modulus_from_elastic_capillary_number(const TableRead& t, const CaseConfig& c,
                                           const FlowState& flow, ObjectConfig& o,
                                           Diagnostics& diag) {
  if (!flow.shear_rate_ok || !flow.matrix_viscosity_ok) return false;
  const Value& given = *t.value("elastic_capillary_number");
  if (c.shear_rate == 0.0) {
    diag.error(t.path("elastic_capillary_number"), given,
               "needs flow.shear_rate > 0 (it is 0) to set the modulus G = eta_m gamma_dot / "
               "Ca_e; give modulus instead");
    return false;
  }
  const double g = c.matrix_viscosity * c.shear_rate / *o.elastic_capillary_number;
  if (!(std::isfinite(g) && g > 0.0)) {
    diag.error(t.path("elastic_capillary_number"), given,
               fmt::format("gives the modulus G = eta_m gamma_dot / Ca_e = {}, beyond the range "
                           "of a double: state the case in other units",
                           g));
    return false;
  }
  o.parameters.modulus = g;
  return true;
}

/// An object's constitutive model (thesis §2.2.1-2.2.2): a non-Newtonian
/// object's parameters through Constitutive::create, an elastic particle's
/// modulus G = eta_m gamma_dot / Ca_e when it gives Ca_e, and lambda =
/// eta_d / eta_m with eta_d the zero-shear viscosity mu + G lambda (+inf for
/// a solid). False when the model itself is unknown (a bad key, reported).
bool resolve_object_model(const TableRead& t, const CaseConfig& c, const FlowState& flow,
                          ObjectConfig& o, Diagnostics& diag) {
  if (t.status("model") == Read::bad) return false;
  if (o.model == ConstitutiveModel::newtonian) return true;
  if (!model_keys_read(case_keys().objects, t, o)) return true;
  if (is_elastic_solid(o.model)) {
    if (!one_of(t, "modulus", "elastic_capillary_number", o.model, "Ca_e = eta_m gamma_dot / G",
                diag))
      return true;
    if (o.elastic_capillary_number && !modulus_from_elastic_capillary_number(t, c, flow, o, diag)) {
      // G unknown: the other parameters are still checked, with a stand-in G
      // (any G > 0 passes), so that one run of `check` reports every problem.
      ConstitutiveValues others = o.parameters;
      others.modulus = 1.0;
      make_model(t, o.model, others, diag);
      return true;
    }
  } else if (!one_of(t, "modulus", "polymer_viscosity", o.model, "eta_p = G lambda", diag)) {
    return true;
  }
  const auto model = make_model(t, o.model, o.parameters, diag);
  if (model && flow.matrix_viscosity_ok)
    o.viscosity_ratio = model->zero_shear_viscosity() / c.matrix_viscosity;
  return true;
}

/// Gamma from exactly one of capillary_number (Gamma = eta_m gamma_dot R/Ca)
/// or interfacial_tension; neither means Ca = 0.1.
void resolve_tension(const TableRead& t, const CaseConfig& c, const FlowState& flow,
                     ObjectConfig& o, Diagnostics& diag) {
  const Read ca_read = t.status("capillary_number");
  const Read gamma_read = t.status("interfacial_tension");
  if (ca_read != Read::absent && gamma_read != Read::absent) {
    diag.error(fmt::format(
        "{} gives both capillary_number = {} and interfacial_tension = {}: give "
        "only one (Gamma = eta_m gamma_dot R / Ca)",
        t.prefix(), schema::describe(*t.value("capillary_number")),
        schema::describe(*t.value("interfacial_tension"))));
    return;
  }
  if (gamma_read == Read::ok) return;  // Gamma as given
  if (ca_read == Read::bad || gamma_read == Read::bad) return;
  if (!flow.shear_rate_ok || !flow.matrix_viscosity_ok) return;
  if (c.shear_rate == 0.0) {
    if (ca_read == Read::ok)
      diag.error(t.path("capillary_number"), *t.value("capillary_number"),
                 "needs flow.shear_rate > 0 (it is 0); give interfacial_tension instead");
    else
      diag.error(
          fmt::format("{}: flow.shear_rate = 0, so the default capillary_number = {} cannot "
                      "set the interfacial tension; give {}.interfacial_tension",
                      t.prefix(), kDefaultCapillaryNumber, t.prefix()));
    return;
  }
  if (!o.capillary_number) o.capillary_number = kDefaultCapillaryNumber;
  o.interfacial_tension = c.matrix_viscosity * c.shear_rate * mean_radius(o.geometry) /
                          *o.capillary_number;
}

/// Navier slip is a property of a liquid interface here: an elastic
/// particle (no interfacial tension either) takes slip = 0 only.
///
/// A slip beyond what the mesh resolves is refused (issue 33): the inside of
/// a near-spherical drop then turns at a rate the mesh decides, not the
/// physics (physics::largest_resolved_slip). Such a slip is free slip for
/// the drop's shape already: Taylor's law with slip puts D within
/// 3 lambda / (16 (1 + lambda + 5 alpha lambda)) of its free-slip value.
void check_slip(const TableRead& t, const CaseConfig& c, const ObjectConfig& o,
                Diagnostics& diag) {
  if (t.status("slip") != Read::ok || o.slip == 0.0) return;
  if (!is_elastic_solid(o.model)) {
    const double largest = physics::largest_resolved_slip(c.sizing.equator_nodes);
    if (o.slip <= largest) return;
    const double lambda = o.viscosity_ratio;
    const double off_free_slip = 3.0 * lambda / (16.0 * (1.0 + lambda + 5.0 * largest * lambda));
    const int needed = static_cast<int>(std::ceil(16.0 * std::pow(o.slip / 100.0, 0.25)));
    diag.error(
        t.path("slip"), *t.value("slip"),
        fmt::format("above {:g}, the largest slip that mesh.equator_nodes = {} resolves: the "
                    "inside of a nearly spherical drop turns rigidly at no viscous cost, and "
                    "beyond that slip the mesh's own asphericity, not the slip law, sets how fast "
                    "(docs/slip.md). Lower slip (at {:g}, Taylor's law puts D within {:.2g} % of "
                    "free slip), or mesh finer (mesh.equator_nodes >= {} for this slip)",
                    largest, c.sizing.equator_nodes, largest, 100.0 * off_free_slip, needed));
    return;
  }
  diag.error(t.path("slip"), *t.value("slip"),
             fmt::format("model = \"{}\" is an elastic particle, which takes only slip = 0 (no "
                         "slip); slip > 0 is for drops (model = \"newtonian\", \"oldroyd_b\", "
                         "\"giesekus\" or \"ucm\")",
                         physics::viscoelastic::to_string(o.model)));
}

/// initial_deformation = "taylor" needs what small-deformation theory
/// describes: a Newtonian drop with a tension in steady (or started-up) shear,
/// without slip (whose own theory is not the start's).
void check_initial_deformation(const TableRead& t, const CaseConfig& c, const ObjectConfig& o,
                               Diagnostics& diag) {
  if (t.status("initial_deformation") != Read::ok ||
      o.initial_deformation == InitialDeformation::none)
    return;
  const auto refuse = [&](const std::string& why) {
    diag.error(t.path("initial_deformation"), *t.value("initial_deformation"), why);
  };
  if (o.model != ConstitutiveModel::newtonian)
    refuse(fmt::format("the theory's ellipsoid is a Newtonian drop's; model = \"{}\" takes "
                       "initial_deformation = \"none\"",
                       physics::viscoelastic::to_string(o.model)));
  else if (!(o.interfacial_tension > 0.0))
    refuse("the theory's ellipsoid needs an interfacial tension (capillary_number, or "
           "interfacial_tension > 0)");
  else if (o.slip > 0.0)
    refuse("with slip > 0 the start would be the no-slip drop's ellipsoid: use "
           "initial_deformation = \"none\"");
  else if ((c.flow.type != FlowType::steady && c.flow.type != FlowType::start_up) ||
           !(c.shear_rate > 0.0) || c.matrix_model != ConstitutiveModel::newtonian)
    refuse("the theory's ellipsoid is the steady shape in steady shear of a Newtonian matrix "
           "(flow.type \"steady\" or \"start_up\", flow.shear_rate > 0, matrix.model "
           "\"newtonian\")");
}

/// The height from [cell] blockage_ratio beta = 2R/H (thesis ch. 3), R the
/// equivalent radius (abc)^(1/3) of objects[1]: H = 2R / beta. It replaces
/// the height, so the two together are ambiguous and refused.
void resolve_height(const TableRead& cell, const std::vector<TableRead>& objects, CaseConfig& c,
                    Diagnostics& diag) {
  const Read beta_read = cell.status("blockage_ratio");
  if (beta_read != Read::ok) {
    c.blockage_ratio.reset();  // absent, or bad (reported)
    return;
  }
  const Value& beta = *cell.value("blockage_ratio");
  if (cell.status("height") != Read::absent) {
    diag.error(fmt::format(
        "cell gives both height = {} and blockage_ratio = {}: give only one (blockage_ratio sets "
        "the height, H = 2R / beta with R = (abc)^(1/3) of objects[1])",
        schema::describe(*cell.value("height")), schema::describe(beta)));
    return;
  }
  if (c.objects.empty()) {
    diag.error(cell.path("blockage_ratio"), beta,
               "needs an [[objects]] entry: beta = 2R / H with R = (abc)^(1/3), the equivalent "
               "radius of objects[1]; without objects give cell.height");
    return;
  }
  for (const char* key : {"shape", "radius", "semi_axes"})
    if (objects[0].status(key) == Read::bad) return;  // R unknown (reported)
  const double height = 2.0 * mean_radius(c.objects[0].geometry) / *c.blockage_ratio;
  if (!(std::isfinite(height) && height > 0.0)) {
    diag.error(cell.path("blockage_ratio"), beta,
               fmt::format("gives the height H = 2R / beta = {}, beyond the range of a double: "
                           "state the case in other units",
                           height));
    return;
  }
  c.box.height = height;
}

/// The bulk stress's cube must fit in the cell, and eq. 4.1 is written here
/// for Newtonian phases: the polymer and elastic stresses are not in its
/// volume term yet.
void check_bulk_stress(const TableRead& bulk, const CaseConfig& c, Diagnostics& diag) {
  if (bulk.status("box_side") != Read::ok || c.bulk_stress.box_side == 0.0) return;
  const Value& side = *bulk.value("box_side");
  const double largest = std::min({c.box.length, c.box.height, c.box.width});
  if (c.bulk_stress.box_side > largest)
    diag.error(bulk.path("box_side"), side,
               fmt::format("the cube must fit in the cell: allowed 0 < box_side <= {:g}, the "
                           "smallest of cell.length = {:g}, height = {:g}, width = {:g}",
                           largest, c.box.length, c.box.height, c.box.width));
  if (c.matrix_model != physics::viscoelastic::ConstitutiveModel::newtonian)
    diag.error(bulk.path("box_side"), side,
               fmt::format("the bulk stress is computed for a Newtonian matrix only (matrix.model "
                           "= \"{}\"): give bulk_stress.box_side = 0 or a Newtonian matrix",
                           physics::viscoelastic::to_string(c.matrix_model)));
  for (std::size_t k = 0; k < c.objects.size(); ++k) {
    const ObjectConfig& o = c.objects[k];
    if (o.model != physics::viscoelastic::ConstitutiveModel::newtonian)
      diag.error(bulk.path("box_side"), side,
                 fmt::format("the bulk stress is computed for Newtonian drops only (objects[{}] "
                             "model = \"{}\"): give bulk_stress.box_side = 0",
                             k + 1, physics::viscoelastic::to_string(o.model)));
  }
}

/// Stopping at steady state (time.steady_tolerance > 0) needs objects to
/// watch, a latest time, a flow that can become steady, and a window the
/// run can cover.
void check_steady(const TableRead& time, const CaseConfig& c, Diagnostics& diag) {
  if (time.status("steady_tolerance") != Read::ok || c.time.steady_tolerance == 0.0) return;
  const Value* tolerance = time.value("steady_tolerance");
  if (c.objects.empty())
    diag.error(time.path("steady_tolerance"), *tolerance,
               "a steady state is detected from the objects' shapes and velocities: it needs at "
               "least one [[objects]] entry (or time.steady_tolerance = 0)");
  if (c.flow.type == FlowType::oscillatory)
    diag.error(time.path("steady_tolerance"), *tolerance,
               "an oscillatory flow has no steady state: use time.steady_tolerance = 0 and a "
               "time.end of whole periods");
  if (!(c.time.end > 0.0)) {
    diag.error(time.path("steady_tolerance"), *tolerance,
               "stopping at steady state needs a run in time: time.end > 0, the latest time");
    return;
  }
  if (time.status("steady_window") == Read::bad) return;
  if (c.time.steady_window < c.time.step || c.time.steady_window > c.time.end)
    diag.error(fmt::format("time.steady_window = {:g} must lie between time.step = {:g} and "
                           "time.end = {:g} (the latest time of a run that stops at steady state)",
                           c.time.steady_window, c.time.step, c.time.end));
}

}  // namespace

bool carries_conformation(const CaseConfig& c) {
  return c.matrix_model != ConstitutiveModel::newtonian ||
         std::any_of(c.objects.begin(), c.objects.end(),
                     [](const ObjectConfig& o) { return o.model != ConstitutiveModel::newtonian; });
}

bool has_relaxing_phase(const CaseConfig& c) {
  return matrix_constitutive(c).relaxes() ||
         std::any_of(c.objects.begin(), c.objects.end(),
                     [&](const ObjectConfig& o) { return object_constitutive(c, o).relaxes(); });
}

std::vector<physics::SupgTau> conformation_supg_taus(const CaseConfig& c) {
  using Choice = ConformationConfig::SupgTau;
  const auto kind = [&](const physics::viscoelastic::Constitutive& model) {
    switch (c.conformation.supg_tau) {
      case Choice::transient: return physics::SupgTau::transient;
      case Choice::steady: return physics::SupgTau::steady;
      case Choice::automatic: break;
    }
    return model.relaxes() ? physics::SupgTau::steady : physics::SupgTau::transient;
  };
  std::vector<physics::SupgTau> taus{kind(matrix_constitutive(c))};
  for (const auto& o : c.objects) taus.push_back(kind(object_constitutive(c, o)));
  return taus;
}

bool has_interface_slip(const CaseConfig& c) {
  return std::any_of(c.objects.begin(), c.objects.end(),
                     [](const ObjectConfig& o) { return o.slip > 0.0; });
}

namespace {

/// Adaptive steps estimate their error from the interfaces: they need
/// objects, and a flow whose period the steps would otherwise skip over is
/// refused. max_step and max_growth mean something only with them.
void check_adaptive(const TableRead& time, const CaseConfig& c, Diagnostics& diag) {
  if (time.status("adaptive_tolerance") != Read::ok || c.time.adaptive_tolerance == 0.0) {
    for (const char* key : {"max_step", "max_growth"})
      if (time.status(key) == Read::ok)
        diag.error(time.path(key), *time.value(key),
                   "this bounds adaptive steps: it needs time.adaptive_tolerance > 0 (the steps "
                   "are constant, time.step, without)");
    return;
  }
  const Value* tolerance = time.value("adaptive_tolerance");
  if (!(c.time.end > 0.0))
    diag.error(time.path("adaptive_tolerance"), *tolerance,
               "adaptive steps need a run in time: time.end > 0");
  if (c.objects.empty())
    diag.error(time.path("adaptive_tolerance"), *tolerance,
               "adaptive steps estimate the error from the objects' interfaces: they need at "
               "least one [[objects]] entry (or time.adaptive_tolerance = 0)");
  if (c.flow.type == FlowType::oscillatory)
    diag.error(time.path("adaptive_tolerance"), *tolerance,
               "adaptive steps are not available for oscillatory flow, whose period the "
               "interface estimate does not see: use time.adaptive_tolerance = 0 and a "
               "time.step that resolves the period");
  // The estimate sees the interfaces only. A conformation's time error it
  // does not see, and an elastic particle's steady state moves with dt at
  // first order (the decoupled elastic stress, G dt): measured, a particle
  // at Ca_e = 0.1 (20 equator nodes) settled 0.8 % higher in D with steps
  // growing to 0.22 than at a constant 0.02. A bound must be chosen.
  const bool conformation = carries_conformation(c);
  if (conformation && !(c.time.max_step > 0.0))
    diag.error(time.path("adaptive_tolerance"), *tolerance,
               "with a viscoelastic phase or an elastic particle, adaptive steps need a "
               "time.max_step > 0: the estimate watches the interfaces, not the conformation's "
               "time error, and an elastic particle's steady state depends on the step size "
               "(docs/time_stepping.md)");
  if (time.status("max_step") == Read::ok && c.time.max_step > 0.0 && c.time.max_step < c.time.step)
    diag.error(time.path("max_step"), *time.value("max_step"),
               fmt::format("the largest adaptive step must be at least the first one, time.step = "
                           "{:g} (or 0: no bound)",
                           c.time.step));
}

/// flow.periods > 0 sets time.end to that many periods of the oscillation
/// (before check_time, which then judges the steps as for a given end).
void resolve_periods(const TableRead& time, const TableRead& flow, CaseConfig& c,
                     Diagnostics& diag) {
  if (flow.status("periods") != Read::ok || !(c.flow.periods > 0.0)) return;
  if (time.status("end") != Read::absent) {
    diag.error(fmt::format("{} = {} and {} = {} both say when the run ends: give only one",
                           flow.path("periods"), schema::describe(*flow.value("periods")),
                           time.path("end"),
                           time.value("end") ? schema::describe(*time.value("end")) : "?"));
    return;
  }
  if (flow.status("frequency") != Read::ok || time.status("step") == Read::bad) return;
  const double period = 2.0 * M_PI / c.flow.frequency;
  c.time.end = c.flow.periods * period;
  // Constant steps: a whole number per period, so the run ends on the period
  // and the moduli's fit samples every phase alike.
  if (c.time.adaptive_tolerance > 0.0 || !(c.time.step > 0.0)) return;
  const double per_period = std::ceil(period / c.time.step * (1.0 - 1e-12));
  if (per_period <= static_cast<double>(std::numeric_limits<int>::max()))
    c.time.step = period / per_period;
}

/// A run in time (end > 0) takes n = round(end / step) steps: at least one,
/// and as many as an int counts. A step beyond end would run past t_end (or,
/// below end / 2, round to no step at all); a step so small that n overflows
/// (step = 5e-324) made the run end at once, reported as completed.
void check_time(const TableRead& time, const CaseConfig& c, Diagnostics& diag) {
  if (time.status("step") == Read::bad || time.status("end") == Read::bad) return;
  const double step = c.time.step, end = c.time.end;
  check_steady(time, c, diag);
  check_adaptive(time, c, diag);
  if (!(end > 0.0)) return;  // one Stokes solve: the step is not used
  const auto shown = [&time](std::string_view key, double x) {
    const Value* v = time.value(key);
    return v ? schema::describe(*v) : schema::toml_float(x);
  };
  if (step > end) {
    diag.error(fmt::format("time.step = {} is larger than time.end = {}: a run in time needs "
                           "time.step <= time.end (or time.end = 0 for one Stokes solve)",
                           shown("step", step), shown("end", end)));
    return;
  }
  constexpr double kMaxSteps = std::numeric_limits<int>::max();
  if (!(end / step <= kMaxSteps))
    diag.error(fmt::format("time.step = {} with time.end = {} makes {:.3g} steps: at most {} "
                           "are allowed (time.step >= time.end / {})",
                           shown("step", step), shown("end", end), end / step,
                           static_cast<long long>(kMaxSteps), static_cast<long long>(kMaxSteps)));
}

/// A remesh threshold at or below time.min_quality would never act: the run
/// stops at min_quality first.
/// [emulsion]: the one [[objects]] entry copied at random centres.
void expand_emulsion(const TableRead& emulsion, CaseConfig& c, Diagnostics& diag) {
  if (emulsion.status("volume_fraction") != Read::ok || c.emulsion.volume_fraction == 0.0) return;
  const Value& phi = *emulsion.value("volume_fraction");
  if (c.objects.size() != 1 || c.objects[0].geometry.shape != geometry::ObjectShape::sphere ||
      c.objects[0].geometry.centre != Eigen::Vector3d::Zero()) {
    diag.error(emulsion.path("volume_fraction"), phi,
               fmt::format("an emulsion copies one [[objects]] entry, a sphere centred at the origin (its "
                           "template); the case has {} [[objects]] entr{}{}",
                           c.objects.size(), c.objects.size() == 1 ? "y" : "ies",
                           c.objects.size() == 1 ? " that is not a sphere at the origin" : ""));
    return;
  }
  geometry::RandomPacking packing;
  packing.radius = c.objects[0].geometry.semi_axes.x();
  packing.region = c.emulsion.core_side > 0.0 ? Eigen::Vector3d::Constant(c.emulsion.core_side)
                                              : Eigen::Vector3d(c.box.length, c.box.height, c.box.width);
  packing.volume_fraction = c.emulsion.volume_fraction;
  packing.seed = static_cast<std::uint64_t>(c.emulsion.seed);
  const double element = geometry::interface_element_size(c.objects[0].geometry, c.sizing);
  packing.min_gap = c.emulsion.min_gap > 0.0 ? c.emulsion.min_gap * packing.radius : element;
  // Between drops the mesh refines narrow gaps (geometry::object_gap_element_size);
  // a cell's periodic faces need one interface element.
  const double narrowest = geometry::smallest_wall_gap(c.objects[0].geometry, c.sizing);
  if (packing.min_gap < narrowest) {
    diag.error(emulsion.path("min_gap"), *emulsion.value("min_gap"),
               fmt::format("the narrowest gap between drops the mesh resolves is {:.3g} R (mesh.gap_elements = "
                           "{} elements across, at most {:g} times smaller than the interface elements of "
                           "mesh.equator_nodes = {}): min_gap >= {:.3g}, or 0 for one interface element",
                           narrowest / packing.radius, c.sizing.elements_across_gaps(),
                           geometry::kMaxGapRefinement, c.sizing.equator_nodes, narrowest / packing.radius));
    return;
  }
  const bool centres_in_core = c.emulsion.core_layout == EmulsionConfig::CoreLayout::centres;
  if (centres_in_core && !(c.emulsion.core_side > 0.0)) {
    diag.error(
        emulsion.path("core_layout"), *emulsion.value("core_layout"),
        "the centres' layout of a core cube needs emulsion.core_side > 0 (without it the drops "
        "fill the whole cell)");
    return;
  }
  if (centres_in_core) packing.container = Eigen::Vector3d(c.box.length, c.box.height, c.box.width);
  if (!(c.emulsion.core_side > 0.0) || centres_in_core)
    packing.face_gap = std::max(packing.min_gap, element);  // the cell's faces
  if (c.emulsion.core_side > std::min({c.box.length, c.box.height, c.box.width})) {
    diag.error(emulsion.path("core_side"), *emulsion.value("core_side"),
               "the core cube must fit in the cell: at most its length, height and width");
    return;
  }
  std::vector<Eigen::Vector3d> centres;
  try {
    centres = geometry::random_sequential_addition(packing);
  } catch (const InputError& e) {
    diag.error(emulsion.path("volume_fraction"), phi, e.what());
    return;
  }
  const ObjectConfig drop = c.objects[0];
  c.objects.clear();
  for (const auto& centre : centres) {
    c.objects.push_back(drop);
    c.objects.back().geometry.centre = centre;
  }
}

void check_remesh(const TableRead& remesh, const TableRead& time, const CaseConfig& c, Diagnostics& diag) {
  // A remesh makes gap_elements elements across a narrow gap (the mesher's
  // count): a trigger at or above that would remesh before every step.
  if (remesh.status("gap_elements") == Read::ok && c.remesh.gap_elements > 0.0 &&
      c.remesh.gap_elements >= c.sizing.elements_across_gaps())
    diag.error(remesh.path("gap_elements"), *remesh.value("gap_elements"),
               fmt::format("must be below mesh.gap_elements = {}, the elements a remesh puts "
                           "across a narrow gap (allowed: 0 <= remesh.gap_elements < "
                           "mesh.gap_elements; raise mesh.gap_elements to remesh at more)",
                           c.sizing.elements_across_gaps()));
  // Slip lives on the interface nodes (its multipliers): a new interface
  // has nothing to carry it over from yet.
  if (has_interface_slip(c) && remesh.status("interfaces") == Read::ok &&
      c.remesh.interfaces == geometry::InterfaceRemeshing::resample)
    diag.error(remesh.path("interfaces"), *remesh.value("interfaces"),
               "cannot resample interfaces with slip (objects.slip > 0): the slip multipliers "
               "live on the interface nodes and are carried over only node for node (allowed "
               "with slip: \"keep\", or \"auto\", which then keeps them)");
  if (remesh.status("quality") != Read::ok || c.remesh.quality == 0.0) return;
  if (time.status("min_quality") == Read::bad) return;
  if (c.remesh.quality <= c.time.min_quality)
    diag.error(remesh.path("quality"), *remesh.value("quality"),
               fmt::format("must be above time.min_quality = {:g}, which stops the run before a "
                           "remesh at this quality could act (allowed: time.min_quality < "
                           "remesh.quality < 1, or 0 for never)",
                           c.time.min_quality));
}

/// The phases' relaxation is taken explicitly: the predicted stress uses
/// c_n's relaxation, and the log-conformation's source g(s)/lambda is
/// evaluated at s extrapolated to t_{n+1} (docs/viscoelastic.md). For
/// ds/dt = -s/lambda that is 3 s_{n+1} - 4 s_n + s_{n-1} = -2 (dt/lambda)
/// (2 s_n - s_{n-1}), whose roots stay inside the unit circle only for
/// dt < 4/3 lambda (BDF1, the first step: dt < 2 lambda); near the bound
/// the stress rings, an oscillation that
/// decays slowly (dt = 1.25 lambda: by 11 % a step) or grows (1.4 lambda:
/// measured, an Oldroyd-B matrix's tau_xy 0.52, 0.58, 0.40, 0.81 at t = 2
/// for 0.5). relaxation_time = 1e-300 passed `check` and the run stopped at
/// step 1 with NaN in the Stokes system. So a step (and an adaptive run's
/// largest step) must not exceed the shortest relaxation time: there the
/// mode decays by 42 % a step.
/// The shortest relaxation time of the case's viscoelastic phases and the key
/// that sets it (infinity and "" without one; elastic particles relax no
/// conformation of their own: their Finger tensor has no relaxation time).
struct ShortestRelaxation {
  double time = std::numeric_limits<double>::infinity();
  std::string key;
};

ShortestRelaxation shortest_relaxation(const TableRead& matrix,
                                       const std::vector<TableRead>& objects,
                                       const CaseConfig& c) {
  ShortestRelaxation shortest;
  const auto consider = [&](const TableRead& t, const ConstitutiveValues& values) {
    if (t.status("relaxation_time") != Read::ok || !values.relaxation_time) return;
    if (*values.relaxation_time < shortest.time) {
      shortest.time = *values.relaxation_time;
      shortest.key = t.path("relaxation_time");
    }
  };
  if (c.matrix_model != ConstitutiveModel::newtonian) consider(matrix, c.matrix_parameters);
  for (std::size_t k = 0; k < c.objects.size() && k < objects.size(); ++k)
    if (!is_elastic_solid(c.objects[k].model) &&
        c.objects[k].model != ConstitutiveModel::newtonian)
      consider(objects[k], c.objects[k].parameters);
  return shortest;
}

void check_relaxation_steps(const TableRead& time, const TableRead& matrix,
                            const std::vector<TableRead>& objects, const CaseConfig& c,
                            Diagnostics& diag) {
  if (time.status("step") == Read::bad || time.status("end") == Read::bad) return;
  if (!(c.time.end > 0.0)) return;  // one Stokes solve: no step is taken
  const auto [lambda, key] = shortest_relaxation(matrix, objects, c);
  if (key.empty()) return;
  const auto refuse = [&](std::string_view step_key, double step) {
    const Value* given = time.value(step_key);
    diag.error(fmt::format(
        "{} = {} is longer than the shortest relaxation time, {} = {}: the relaxation of the "
        "conformation is taken explicitly, which is stable only for steps below 4/3 of it and "
        "rings near that; allowed: {} <= {} (or a longer relaxation time)",
        time.path(step_key), given ? schema::describe(*given) : schema::toml_float(step), key,
        schema::toml_float(lambda), time.path(step_key), schema::toml_float(lambda)));
  };
  if (c.time.step > lambda) refuse("step", c.time.step);
  const bool adaptive = time.status("adaptive_tolerance") == Read::ok && c.time.adaptive_tolerance > 0.0;
  if (adaptive && time.status("max_step") == Read::ok && c.time.max_step > lambda)
    refuse("max_step", c.time.max_step);
}

/// Constant steps must resolve an oscillatory flow's period 2 pi / omega:
/// at least kStepsPerPeriod of them. Fewer sample the wall motion too coarsely
/// (at 2 per period every step sees the same phase) and BDF2 itself damps
/// a free oscillation resolved by 10 steps by 18 % per period (by 51 % at 4).
/// frequency = 1000 with step = 0.05 (0.13 steps per period) passed `check`.
/// (Adaptive steps are refused for oscillatory flow, check_adaptive.)
constexpr double kStepsPerPeriod = 10.0;

void check_oscillatory_steps(const TableRead& time, const TableRead& flow, const CaseConfig& c,
                             Diagnostics& diag) {
  if (c.flow.type != FlowType::oscillatory || flow.status("type") != Read::ok ||
      flow.status("frequency") != Read::ok)
    return;
  if (time.status("step") == Read::bad || time.status("end") == Read::bad) return;
  if (!(c.time.end > 0.0)) return;
  if (time.status("adaptive_tolerance") == Read::ok && c.time.adaptive_tolerance > 0.0) return;
  const double period = 2.0 * M_PI / c.flow.frequency;
  const double largest = period / kStepsPerPeriod;
  if (c.time.step <= largest) return;
  const Value* step = time.value("step");
  diag.error(fmt::format(
      "{} = {} with {} = {} takes {:.3g} steps per period (2 pi / frequency = {:.4g}): at least "
      "{:g} are needed, time.step <= {:.4g}; fewer sample the wall motion too coarsely and BDF2 "
      "damps the oscillation (by 18 % per period at 10 steps)",
      time.path("step"), step ? schema::describe(*step) : schema::toml_float(c.time.step),
      flow.path("frequency"), schema::describe(*flow.value("frequency")), period / c.time.step,
      period, kStepsPerPeriod, largest));
}

/// A case that gives neither time.step nor time.adaptive_tolerance runs with
/// adaptive steps wherever they are available and verified: a run in time
/// with objects (the estimate watches their interfaces), a flow without a
/// period to resolve, and no remeshing (a remesh between an accepted step
/// and a retried one is not verified). The first step is time.step's
/// default (0.005: no rejections from rest, docs/time_stepping.md); the
/// largest is bounded by the tangential redistribution's 1 / (k gamma_dot)
/// alone for Newtonian phases, and with a conformation to carry by
/// kDefaultConformationMaxStep (an elastic particle's steady D moved by
/// 0.2 % between max_step 0.04 and constant 0.02, docs/time_stepping.md)
/// and the shortest relaxation time (check_relaxation_steps). Any case
/// outside these keeps constant steps of time.step.
constexpr double kDefaultAdaptiveTolerance = 1e-3;
constexpr double kDefaultConformationMaxStep = 0.04;

void resolve_default_steps(const TableRead& time, const TableRead& matrix,
                           const std::vector<TableRead>& objects, CaseConfig& c) {
  const bool step_given = time.status("step") != Read::absent;
  const bool tolerance_given = time.status("adaptive_tolerance") != Read::absent;
  if (step_given || tolerance_given) {
    c.time.steps_chosen_by = tolerance_given ? "time.adaptive_tolerance" : "time.step";
    return;
  }
  c.time.steps_chosen_by = "default";
  if (!(c.time.end > 0.0) || c.objects.empty() || c.flow.type == FlowType::oscillatory ||
      c.remesh.enabled() || time.status("max_step") != Read::absent ||
      time.status("max_growth") != Read::absent)
    return;
  c.time.adaptive_tolerance = kDefaultAdaptiveTolerance;
  const bool conformation = carries_conformation(c);
  if (conformation)
    c.time.max_step = std::max(
        c.time.step, std::min(kDefaultConformationMaxStep, shortest_relaxation(matrix, objects, c).time));
}

/// The output directory, given or output/<name>, must be one softflow can
/// make (output_directory_problem); a long name is refused only when it
/// names the directory.
void check_output_directory(const TableRead& name_table, const TableRead& output, CaseConfig& c,
                            Diagnostics& diag) {
  if (output.status("directory") == Read::ok) {
    if (const auto what = output_directory_problem(c.output_directory); !what.empty())
      diag.error(output.path("directory"), *output.value("directory"), what);
    return;
  }
  c.output_directory = "output/" + c.name;
  if (name_table.status("name") != Read::ok) return;  // the default name fits (default_case_name)
  if (const auto what = output_directory_problem(c.output_directory); !what.empty())
    diag.error(name_table.path("name"), *name_table.value("name"),
               fmt::format("names the output directory output/<name>, which {}, or give "
                           "output.directory",
                           what));
}

// ---------------------------------------------------------------------------
// TOML syntax errors: toml11's message carries a source excerpt; keep it, but
// lead with "file:line:" like a compiler, so editors can jump to it.

std::string syntax_message(const toml::syntax_error& e, const std::string& source) {
  std::string what = e.what();
  const auto strip = [&what](std::string_view prefix) {
    if (what.rfind(prefix, 0) == 0) what.erase(0, prefix.size());
  };
  strip("[error] ");
  if (what.rfind("toml::", 0) == 0) {  // e.g. "toml::parse_array: " names toml11's internals
    const auto colon = what.find(": ");
    const auto newline = what.find('\n');
    if (colon != std::string::npos && colon < newline) what.erase(0, colon + 2);
  }
  // Drop the " --> file" line: the file is already in front.
  std::istringstream lines(what);
  std::string line, headline, excerpt;
  std::getline(lines, headline);
  while (std::getline(lines, line))
    if (line.rfind(" --> ", 0) != 0) excerpt += "\n" + line;
  return fmt::format("{}:{}: TOML syntax error: {}{}", source, e.location().line(), headline,
                     excerpt);
}

constexpr std::size_t kMaxNesting = 64;

// ---------------------------------------------------------------------------
// Nesting depth: toml11 parses nested arrays and inline tables recursively,
// so `a = [[[[...` thousands deep overflows the stack (a segmentation fault).
// The text is scanned first; brackets in strings and comments do not count.

}  // namespace

void check_toml_nesting(std::string_view text, const std::string& source) {
  std::size_t depth = 0, line = 1;
  const auto at = [&text](std::size_t i) { return i < text.size() ? text[i] : '\0'; };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
    } else if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
    } else if (c == '"' || c == '\'') {
      const bool basic = c == '"';
      const bool multi_line = at(i + 1) == c && at(i + 2) == c;
      i += multi_line ? 3 : 1;
      for (; i < text.size(); ++i) {
        if (text[i] == '\n') {
          ++line;
          if (!multi_line) break;  // unterminated: toml11 reports it
        } else if (basic && text[i] == '\\') {
          if (at(i + 1) == '\n') ++line;
          ++i;
        } else if (text[i] == c && (!multi_line || (at(i + 1) == c && at(i + 2) == c))) {
          if (multi_line) {
            i += 2;
            while (at(i + 1) == c) ++i;  // up to two quotes end the content
          }
          break;
        }
      }
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        throw InputError(fmt::format(
            "{}:{}: arrays or inline tables nested more than {} deep: at most {} levels of "
            "[ ] and {{ }} are allowed",
            source, line, kMaxNesting, kMaxNesting));
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

namespace {

toml::value parse_toml(const std::string& text, const std::string& source) {
  check_toml_nesting(text, source);
  std::istringstream stream(text);
  try {
    return toml::parse(stream, source);
  } catch (const toml::syntax_error& e) {
    throw InputError(syntax_message(e, source));
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: cannot parse: {}", source, e.what()));
  }
}

std::string default_case_name(const std::string& source) {
  const std::string stem = std::filesystem::path(source).stem().string();
  return is_plain_name(stem) && stem.size() <= kMaxDirectoryNameBytes ? stem : "case";
}

/// At most `bytes` bytes of `s`, not cutting a UTF-8 sequence, with "..." if cut.
std::string shortened(const std::string& s, std::size_t bytes = 40) {
  if (s.size() <= bytes) return s;
  std::size_t n = bytes;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;
  return s.substr(0, n) + "...";
}

}  // namespace

// ---------------------------------------------------------------------------

std::string output_directory_problem(const std::string& directory) {
  if (directory.size() > kMaxDirectoryPathBytes)
    return fmt::format("is {} bytes long: an output directory's path has at most {} (PATH_MAX, "
                       "4096 bytes, less room for the names written in it); shorten it",
                       directory.size(), kMaxDirectoryPathBytes);
  std::filesystem::path path(directory);
  // "out/a/" names "out/a", as OutputDirectory takes it.
  if (!path.has_filename() && path.has_parent_path()) path = path.parent_path();
  for (const auto& part : path) {
    const std::string name = part.string();
    if (name.size() > 255)
      return fmt::format("has a part '{}' of {} bytes: a directory name has at most 255 "
                         "(NAME_MAX); shorten it",
                         shortened(name), name.size());
  }
  const std::string last = path.filename().string();
  if (last.empty() || last == "." || last == "..")
    return "names no directory to create (it ends in '.' or '..'); name the directory itself";
  if (last.size() > kMaxDirectoryNameBytes)
    return fmt::format("makes a directory name '{}' of {} bytes: at most {} are allowed "
                       "(NAME_MAX, 255 bytes, less the 16 of the suffix '.partial-<pid>' of the "
                       "directory a run is staged in); shorten it",
                       shortened(last), last.size(), kMaxDirectoryNameBytes);
  return "";
}

double mean_radius(const geometry::ObjectSpec& object) {
  const auto& a = object.semi_axes;
  return std::cbrt(a.x() * a.y() * a.z());
}

double navier_slip_coefficient(const CaseConfig& c, const ObjectConfig& o) {
  // slip = alpha_dim eta_m / R (thesis §2.1), eta_m zero-shear.
  return o.slip * mean_radius(o.geometry) / c.matrix_viscosity;
}

geometry::ShearCellSpec CaseConfig::shear_cell_spec() const {
  geometry::ShearCellSpec spec;
  spec.box = box;
  for (const auto& o : objects) spec.objects.push_back(o.geometry);
  spec.sizing = sizing;
  return spec;
}

bool is_elastic_solid(ConstitutiveModel model) {
  return model == ConstitutiveModel::neo_hookean || model == ConstitutiveModel::kelvin_voigt;
}

Constitutive matrix_constitutive(const CaseConfig& c) {
  if (c.matrix_model == ConstitutiveModel::newtonian)
    return Constitutive::newtonian(c.matrix_viscosity);
  return Constitutive::create(c.matrix_model, c.matrix_parameters);
}

Constitutive object_constitutive(const CaseConfig& c, const ObjectConfig& o) {
  // lambda = eta_d / eta_m with eta_m the zero-shear viscosity (thesis §2.2.1).
  if (o.model == ConstitutiveModel::newtonian)
    return Constitutive::newtonian(o.viscosity_ratio * c.matrix_viscosity);
  return Constitutive::create(o.model, o.parameters);
}

physics::WallMotion wall_motion(const CaseConfig& config) {
  const double h = config.box.height;
  const auto& flow = config.flow;
  switch (flow.type) {
    case FlowType::steady: return physics::WallMotion::steady(h, config.shear_rate);
    case FlowType::start_up: return physics::WallMotion::start_up(h, config.shear_rate);
    case FlowType::cessation: return physics::WallMotion::cessation(h, config.shear_rate, flow.stop_time);
    case FlowType::oscillatory: return physics::WallMotion::oscillatory(h, flow.strain_amplitude, flow.frequency);
  }
  return physics::WallMotion::steady(h, config.shear_rate);  // not reached: every type above
}

std::vector<Constitutive> constitutive_models(const CaseConfig& c) {
  std::vector<Constitutive> models{matrix_constitutive(c)};
  for (const auto& o : c.objects) models.push_back(object_constitutive(c, o));
  return models;
}

std::optional<double> elastic_capillary_number(const CaseConfig& c, const ObjectConfig& o) {
  if (!is_elastic_solid(o.model)) return std::nullopt;
  // The Ca_e the user gave is reported as given, not re-derived through G.
  if (o.elastic_capillary_number) return o.elastic_capillary_number;
  return c.matrix_viscosity * c.shear_rate / object_constitutive(c, o).modulus();
}

double capillary_number(const CaseConfig& c, const ObjectConfig& o) {
  // The Ca the user gave is reported as given, not re-derived through Gamma.
  if (o.capillary_number) return *o.capillary_number;
  if (o.interfacial_tension > 0.0)
    return c.matrix_viscosity * c.shear_rate * mean_radius(o.geometry) / o.interfacial_tension;
  return std::numeric_limits<double>::infinity();
}

CaseConfig parse_case(const std::string& toml_text, const std::string& source_name) {
  const toml::value root_value = parse_toml(toml_text, source_name);
  const toml::table& root = root_value.as_table();
  const CaseKeys& keys = case_keys();
  Diagnostics diag(source_name);
  schema::check_top_level(root, keys.schema, diag);

  // 1. Every key on its own: type, range, applicability, defaults.
  CaseConfig c;
  c.name = default_case_name(source_name);
  std::map<std::string, TableRead> read;
  std::vector<TableRead> objects_read;
  for (const auto& table : keys.schema.tables) {
    if (table.name == keys.objects.name) {
      const auto entries = schema::array_sections(root, table, diag);
      for (std::size_t i = 0; i < entries.size(); ++i) {
        ObjectConfig o;
        objects_read.push_back(schema::read_table(keys.objects, *entries[i],
                                                  fmt::format("objects[{}]", i + 1), keys.schema,
                                                  o, diag));
        c.objects.push_back(std::move(o));
      }
    } else {
      read[table.name] = schema::read_table(*keys.table(table.name),
                                            schema::section(root, table, diag), table.name,
                                            keys.schema, c, diag);
    }
  }

  // 2. What several keys decide together.
  resolve_height(read["cell"], objects_read, c, diag);
  check_output_directory(read["case"], read["output"], c, diag);
  resolve_periods(read["time"], read["flow"], c, diag);
  check_time(read["time"], c, diag);
  check_remesh(read["remesh"], read["time"], c, diag);
  const bool matrix_ok = resolve_matrix(read["matrix"], c, diag);
  const FlowState flow = resolve_flow(matrix_ok, read["flow"], c, diag);
  for (std::size_t k = 0; k < c.objects.size(); ++k) {
    ObjectConfig& o = c.objects[k];
    const bool model_known = resolve_object_model(objects_read[k], c, flow, o, diag);
    // An elastic particle has no interfacial tension (Gamma = 0, SPEC §1).
    if (model_known && !is_elastic_solid(o.model))
      resolve_tension(objects_read[k], c, flow, o, diag);
    if (model_known) check_slip(objects_read[k], c, o, diag);
    if (model_known) check_initial_deformation(objects_read[k], c, o, diag);
  }
  check_relaxation_steps(read["time"], read["matrix"], objects_read, c, diag);
  check_oscillatory_steps(read["time"], read["flow"], c, diag);
  resolve_default_steps(read["time"], read["matrix"], objects_read, c);
  check_bulk_stress(read["bulk_stress"], c, diag);
  // Node relocation's search does not keep a carried mesh the image of its
  // mirror case's (docs/confinement.md): off unless the file asks for it.
  if (c.sizing.point_symmetric_start && read["time"].status("relocation_quality") == schema::Read::absent)
    c.time.relocation_quality = 0.0;
  diag.throw_if_any();
  expand_emulsion(read["emulsion"], c, diag);
  diag.throw_if_any();
  return c;
}

CaseConfig read_case_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(fmt::format("{}: is a directory, not a case file", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot open the case file (does it exist?)", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: cannot read the case file", path.string()));
  return parse_case(text.str(), path.string());
}

std::string to_toml(const CaseConfig& c) {
  const CaseKeys& keys = case_keys();
  std::string s = "# softflow case, resolved: every key with the value the run uses.\n";
  for (const auto& table : keys.schema.tables) {
    // (Appended piece by piece: GCC 12 warns falsely about "\n" + a temporary.)
    if (table.name != keys.objects.name) {
      // A run that never remeshes prints as before the key: the case.toml
      // of its checkpoints and stored runs compares with the printout.
      if (table.name == "remesh" && !c.remesh.enabled()) continue;
      if (table.name == "emulsion" && c.emulsion.volume_fraction == 0.0) continue;
      if (table.name == "conformation" && !carries_conformation(c)) continue;
      s += '\n';
      s += schema::write_table(*keys.table(table.name), c);
      continue;
    }
    if (c.objects.empty()) s += "\n# no [[objects]]: the undisturbed shear flow\n";
    if (c.emulsion.volume_fraction > 0.0 && !c.objects.empty()) {
      // The template the drops were copied from ([emulsion] places them again).
      ObjectConfig drop = c.objects.front();
      drop.geometry.centre = Eigen::Vector3d::Zero();
      s += fmt::format("\n# the template of the emulsion's {} drops\n", c.objects.size());
      s += schema::write_table(keys.objects, drop);
      continue;
    }
    for (const auto& o : c.objects) {
      s += '\n';
      s += schema::write_table(keys.objects, o);
    }
  }
  return s;
}

// ---------------------------------------------------------------------------

std::vector<DimensionlessGroup> dimensionless_groups(const CaseConfig& c) {
  std::vector<DimensionlessGroup> groups;
  const bool oscillatory = c.flow.type == FlowType::oscillatory;
  const double inf = std::numeric_limits<double>::infinity();
  const double eta_m = c.matrix_viscosity;  // zero-shear for a viscoelastic matrix
  const Constitutive matrix = matrix_constitutive(c);
  // Psi_1 = N1 / gamma_dot^2 = 2 eta_p lambda: the first normal-stress
  // coefficient of Oldroyd-B and UCM, and Giesekus's at zero shear rate
  // (where the second-order theory of p and p_d, thesis eq. 2.60, holds).
  const auto psi1 = [](const Constitutive& m) {
    return 2.0 * m.polymer_viscosity() * m.relaxation_time();
  };
  const std::string rate = oscillatory ? "gamma0 omega" : "gamma_dot";
  // Thesis ch. 3 writes a particle's p = N / Ca_e^2 with N = N_1 / (2 G) and
  // N_1 the matrix's first normal stress difference at the flow's shear rate:
  // the same as p for Oldroyd-B and UCM, smaller for a shear-thinning matrix
  // (Giesekus: 0.84 of it at Wi = 0.5, alpha = 0.2). Once for all particles;
  // only in steady shear.
  std::optional<double> matrix_n1;
  if (matrix.relaxes() && !oscillatory && c.shear_rate > 0.0)
    matrix_n1 =
        physics::viscoelastic::steady_simple_shear(matrix, c.shear_rate).first_normal_stress_difference();
  // Case-wide groups first (object = 0).
  if (oscillatory)
    groups.push_back({"gamma0", "strain amplitude", c.flow.strain_amplitude,
                      "flow.strain_amplitude", 0});
  if (matrix.relaxes()) {
    groups.push_back({"Wi", "Weissenberg number of the matrix",
                      matrix.relaxation_time() * c.shear_rate, "lambda_m " + rate, 0});
    if (oscillatory)
      groups.push_back({"De", "Deborah number of the matrix",
                        matrix.relaxation_time() * c.flow.frequency, "lambda_m omega", 0});
  }
  for (std::size_t k = 0; k < c.objects.size(); ++k) {
    const ObjectConfig& o = c.objects[k];
    const int object = static_cast<int>(k) + 1;
    const double r = mean_radius(o.geometry);
    const double d = 2.0 * r;
    const auto add = [&](std::string symbol, std::string name, double value,
                         std::string definition) {
      groups.push_back({std::move(symbol), std::move(name), value, std::move(definition), object});
    };
    const Constitutive model = object_constitutive(c, o);
    if (is_elastic_solid(o.model)) {
      // No interfacial tension: no Ca, omega* or lambda; Ca_e and p of thesis §2.2.2.
      add("Ca_e", "elastic capillary number", *elastic_capillary_number(c, o),
          "eta_m " + rate + " / G");
      if (matrix.relaxes())
        add("p", "matrix elasticity parameter",
            psi1(matrix) * model.modulus() / (2.0 * eta_m * eta_m),
            "Psi_1m G / (2 eta_m^2), Psi_1m = 2 eta_pm lambda_m");
      if (matrix_n1)
        add("p_N1", "matrix elasticity parameter from N_1 at the shear rate",
            *matrix_n1 * model.modulus() / (2.0 * eta_m * eta_m * c.shear_rate * c.shear_rate),
            "N / Ca_e^2, N = N_1(gamma_dot) / (2 G), Ca_e = eta_m gamma_dot / G (thesis ch. 3)");
      if (o.model == ConstitutiveModel::kelvin_voigt)
        add("mu_d/eta_m", "particle solvent viscosity ratio", model.solvent_viscosity() / eta_m,
            "mu_d / eta_m");
    } else {
      const double gamma = o.interfacial_tension;
      add("Ca", "capillary number", capillary_number(c, o),
          "eta_m " + rate + " R / Gamma, R = (abc)^(1/3)");
      if (oscillatory)
        add("omega*", "dimensionless frequency",
            gamma > 0.0 ? c.flow.frequency * eta_m * r / gamma : inf, "omega eta_m R / Gamma");
      add("lambda", "viscosity ratio", o.viscosity_ratio,
          model.relaxes() ? "eta_d / eta_m, eta_d = mu_d + eta_pd (zero-shear)" : "eta_d / eta_m");
      // thesis §2.2.1 and eq. 2.60: p of the matrix, p_d of the drop, each
      // with its own zero-shear viscosity squared in the denominator.
      if (matrix.relaxes())
        add("p", "matrix elasticity parameter", psi1(matrix) * gamma / (2.0 * r * eta_m * eta_m),
            "Psi_1m Gamma / (2 R eta_m^2), Psi_1m = 2 eta_pm lambda_m");
      if (model.relaxes()) {
        const double eta_d = model.zero_shear_viscosity();
        add("p_d", "drop elasticity parameter", psi1(model) * gamma / (2.0 * r * eta_d * eta_d),
            "Psi_1d Gamma / (2 R eta_d^2), Psi_1d = 2 eta_pd lambda_d");
        add("Wi_d", "Weissenberg number of the drop", model.relaxation_time() * c.shear_rate,
            "lambda_d " + rate);
        if (oscillatory)
          add("De_d", "Deborah number of the drop", model.relaxation_time() * c.flow.frequency,
              "lambda_d omega");
      }
    }
    // SPEC §1: the slip alpha of an interface that has slip.
    if (o.slip > 0.0)
      add("alpha", "Navier slip coefficient", o.slip,
          "alpha_dim eta_m / R, alpha_dim the dimensional coefficient of (I - nn)(u_m - u_d) = "
          "alpha_dim (I - nn)(sigma_m n)");
    add("beta", "blockage ratio", d / c.box.height, "2R / H");
    add("L/D", "box length in diameters", c.box.length / d, "L / 2R");
    add("H/D", "box height in diameters", c.box.height / d, "H / 2R");
    add("W/D", "box width in diameters", c.box.width / d, "W / 2R");
  }
  return groups;
}

nlohmann::json to_json(const std::vector<DimensionlessGroup>& groups) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& g : groups) {
    nlohmann::json j = {{"symbol", g.symbol}, {"name", g.name}};
    if (g.object > 0) j["object"] = g.object;
    // JSON has no infinity; null reads as "unbounded" beside the definition.
    j["value"] = std::isfinite(g.value) ? nlohmann::json(g.value) : nlohmann::json(nullptr);
    j["definition"] = g.definition;
    out.push_back(std::move(j));
  }
  return out;
}

}  // namespace softflow::io
