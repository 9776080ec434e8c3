#include "softflow/io/case_config.hpp"

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

namespace softflow::io {

namespace {

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

/// The characteristic shear rate of each flow type (oscillatory: the
/// shear-rate amplitude gamma0 omega), and walls that start or stop must
/// move at all.
FlowState resolve_flow(const TableRead& matrix, const TableRead& flow, CaseConfig& c,
                       Diagnostics& diag) {
  FlowState state;
  state.matrix_viscosity_ok = matrix.status("viscosity") != Read::bad;
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

/// A run in time (end > 0) takes n = round(end / step) steps: at least one,
/// and as many as an int counts. A step beyond end would run past t_end (or,
/// below end / 2, round to no step at all); a step so small that n overflows
/// (step = 5e-324) made the run end at once, reported as completed.
void check_time(const TableRead& time, const CaseConfig& c, Diagnostics& diag) {
  if (time.status("step") == Read::bad || time.status("end") == Read::bad) return;
  const double step = c.time.step, end = c.time.end;
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
  return is_plain_name(stem) ? stem : "case";
}

}  // namespace

// ---------------------------------------------------------------------------

double mean_radius(const geometry::ObjectSpec& object) {
  const auto& a = object.semi_axes;
  return std::cbrt(a.x() * a.y() * a.z());
}

geometry::ShearCellSpec CaseConfig::shear_cell_spec() const {
  geometry::ShearCellSpec spec;
  spec.box = box;
  for (const auto& o : objects) spec.objects.push_back(o.geometry);
  spec.sizing = sizing;
  return spec;
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
  if (read["output"].status("directory") != Read::ok) c.output_directory = "output/" + c.name;
  check_time(read["time"], c, diag);
  const FlowState flow = resolve_flow(read["matrix"], read["flow"], c, diag);
  for (std::size_t k = 0; k < c.objects.size(); ++k)
    resolve_tension(objects_read[k], c, flow, c.objects[k], diag);
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
      s += '\n';
      s += schema::write_table(*keys.table(table.name), c);
      continue;
    }
    if (c.objects.empty()) s += "\n# no [[objects]]: the undisturbed shear flow\n";
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
  // Case-wide groups first (object = 0); the Deborah/Weissenberg numbers of a
  // viscoelastic matrix will go here too.
  if (oscillatory)
    groups.push_back({"gamma0", "strain amplitude", c.flow.strain_amplitude,
                      "flow.strain_amplitude", 0});
  for (std::size_t k = 0; k < c.objects.size(); ++k) {
    const ObjectConfig& o = c.objects[k];
    const int object = static_cast<int>(k) + 1;
    const double r = mean_radius(o.geometry);
    const double d = 2.0 * r;
    const auto add = [&](std::string symbol, std::string name, double value,
                         std::string definition) {
      groups.push_back({std::move(symbol), std::move(name), value, std::move(definition), object});
    };
    add("Ca", "capillary number", capillary_number(c, o),
        oscillatory ? "eta_m gamma0 omega R / Gamma, R = (abc)^(1/3)"
                    : "eta_m gamma_dot R / Gamma, R = (abc)^(1/3)");
    if (oscillatory)
      add("omega*", "dimensionless frequency",
          o.interfacial_tension > 0.0
              ? c.flow.frequency * c.matrix_viscosity * r / o.interfacial_tension
              : std::numeric_limits<double>::infinity(),
          "omega eta_m R / Gamma");
    add("lambda", "viscosity ratio", o.viscosity_ratio, "eta_d / eta_m");
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
