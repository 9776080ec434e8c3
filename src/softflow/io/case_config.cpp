#include "softflow/io/case_config.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include <fmt/format.h>
#include <toml.hpp>

#include "softflow/common/error.hpp"

namespace softflow::io {

namespace {

using Value = toml::value;

// ---------------------------------------------------------------------------
// The schema: every key a case file may hold. It drives the unknown-key check
// and the "did you mean" suggestions, so a new key is added here first.

struct Section {
  std::string_view name;
  std::vector<std::string_view> keys;
};

const std::vector<Section>& schema() {
  static const std::vector<Section> sections = {
      {"case", {"name"}},
      {"cell", {"length", "height", "width", "periodic_x", "periodic_z"}},
      {"matrix", {"viscosity"}},
      {"flow", {"shear_rate"}},
      {"objects",
       {"shape", "centre", "radius", "semi_axes", "rotation_deg", "viscosity_ratio",
        "capillary_number", "interfacial_tension"}},
      {"mesh", {"equator_nodes", "far_size", "growth", "optimize_high_order"}},
      {"solver", {"type", "rtol", "max_iterations", "petsc_options"}},
      {"output", {"directory", "fields"}},
      {"time",
       {"step", "end", "fields_interval", "min_quality", "max_volume_drift", "ale_rebuild_quality"}},
      {"checkpoint", {"interval_steps", "interval_minutes"}},
      {"interface", {"redistribution_factor", "supg_beta", "semi_implicit_tension"}},
  };
  return sections;
}

const Section* find_section(std::string_view name) {
  for (const auto& s : schema())
    if (s.name == name) return &s;
  return nullptr;
}

constexpr double kDefaultCapillaryNumber = 0.1;
constexpr std::size_t kMaxShownValueLength = 60;

// ---------------------------------------------------------------------------
// Spelling help.

/// Edit distance with adjacent transpositions (optimal string alignment):
/// "equator_ndoes" is one slip of the finger from "equator_nodes", not two.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

/// The candidate closest to `word` within edit distance 2, if any.
std::optional<std::string_view> closest(std::string_view word,
                                        const std::vector<std::string_view>& candidates) {
  std::optional<std::string_view> best;
  std::size_t best_distance = 3;
  for (const auto c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

/// A key that contains the unknown one or is contained in it ("viscosity" ->
/// "viscosity_ratio", "equator" -> "equator_nodes"): these are too far apart
/// for the edit distance yet plainly meant.
std::optional<std::string_view> containing(std::string_view word,
                                           const std::vector<std::string_view>& candidates) {
  if (word.size() < 4) return std::nullopt;
  for (const auto c : candidates)
    if (c.find(word) != std::string_view::npos || word.find(c) != std::string_view::npos) return c;
  return std::nullopt;
}

/// Symbols users write for a key, compared ignoring case.
struct Alias {
  std::string_view word;
  std::string_view section;
  std::string_view key;
};
constexpr std::array<Alias, 11> kAliases{{
    {"ca", "objects", "capillary_number"},
    {"capillary", "objects", "capillary_number"},
    {"gamma", "objects", "interfacial_tension"},
    {"sigma", "objects", "interfacial_tension"},
    {"surface_tension", "objects", "interfacial_tension"},
    {"lambda", "objects", "viscosity_ratio"},
    {"center", "objects", "centre"},
    {"axes", "objects", "semi_axes"},
    {"gamma_dot", "flow", "shear_rate"},
    {"eta", "matrix", "viscosity"},
    {"eta_m", "matrix", "viscosity"},
}};

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

/// What to suggest for an unknown key, as a full key path, or "" if nothing
/// fits. `section` is empty for a key at the top level; `prefix` is how keys
/// of this table are written in messages ("mesh", "objects[2]").
std::string suggestion(std::string_view section, std::string_view prefix, std::string_view key) {
  const auto qualified = [](std::string_view table, std::string_view k) {
    return table.empty() ? std::string(k) : fmt::format("{}.{}", table, k);
  };
  const auto in_other_table = [](std::string_view s) {
    return s == "objects" ? std::string("objects[k]") : std::string(s);
  };
  if (section.empty()) {
    std::vector<std::string_view> names;
    for (const auto& s : schema()) names.push_back(s.name);
    if (const auto c = closest(key, names))
      return *c == "objects" ? "[[objects]]" : std::string(*c);
  } else if (const auto* s = find_section(section)) {
    if (const auto c = closest(key, s->keys)) return qualified(prefix, *c);
    if (const auto c = containing(key, s->keys)) return qualified(prefix, *c);
  }
  // Names from the papers rather than from this file format.
  for (const auto& a : kAliases) {
    if (!equal_ignoring_case(a.word, key)) continue;
    return qualified(a.section == section ? prefix : in_other_table(a.section), a.key);
  }
  // A key put under the wrong table (or before any table header).
  for (const auto& s : schema())
    if (s.name != section && std::find(s.keys.begin(), s.keys.end(), key) != s.keys.end())
      return qualified(in_other_table(s.name), key);
  return "";
}

// ---------------------------------------------------------------------------
// Writing TOML values, for messages and for to_toml.

/// Shortest text that reads back to the same double, always recognisable as
/// a TOML float ("30.0", not "30").
std::string toml_float(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::string s = fmt::format("{}", x);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

std::string toml_string(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20 || c == 0x7f)
          out += fmt::format("\\u{:04X}", static_cast<unsigned>(c));
        else
          out += ch;
    }
  }
  return out + "\"";
}

std::string toml_vector(const Eigen::Vector3d& v) {
  return fmt::format("[{}, {}, {}]", toml_float(v.x()), toml_float(v.y()), toml_float(v.z()));
}

/// The value as the user wrote it (near enough), for error messages.
std::string describe(const Value& v) {
  std::string s;
  switch (v.type()) {
    case toml::value_t::boolean: s = v.as_boolean() ? "true" : "false"; break;
    case toml::value_t::integer: s = std::to_string(v.as_integer()); break;
    case toml::value_t::floating: s = toml_float(v.as_floating()); break;
    case toml::value_t::string: s = toml_string(v.as_string().str); break;
    case toml::value_t::array: {
      s = "[";
      for (std::size_t i = 0; i < v.as_array().size(); ++i)
        s += (i ? ", " : "") + describe(v.as_array()[i]);
      s += "]";
      break;
    }
    case toml::value_t::table: s = "(a table)"; break;
    default: {
      std::ostringstream os;
      os << v;
      s = os.str();
    }
  }
  if (s.size() > kMaxShownValueLength) s = s.substr(0, kMaxShownValueLength - 3) + "...";
  return s;
}

// ---------------------------------------------------------------------------
// Collecting problems: the whole file is checked and every problem reported
// at once, so a user fixes a case file in one round, not one per run.

class Diagnostics {
 public:
  explicit Diagnostics(std::string source) : source_(std::move(source)) {}

  void error(std::string_view message) {
    messages_.push_back(fmt::format("{}: {}", source_, message));
  }
  void error(std::string_view key_path, const Value& value, std::string_view what) {
    error(fmt::format("{} = {}: {}", key_path, describe(value), what));
  }
  [[nodiscard]] std::size_t count() const { return messages_.size(); }

  void throw_if_any() const {
    if (messages_.empty()) return;
    std::string all;
    for (const auto& m : messages_) all += (all.empty() ? "" : "\n") + m;
    throw InputError(all);
  }

 private:
  std::string source_;
  std::vector<std::string> messages_;
};

// ---------------------------------------------------------------------------
// Reading typed, range-checked keys of one table.

enum class Read { absent, ok, bad };

enum class Bound { finite, positive, non_negative, open_unit, unit_from_zero };

bool satisfies(double x, Bound bound) {
  switch (bound) {
    case Bound::finite: return true;
    case Bound::positive: return x > 0.0;
    case Bound::non_negative: return x >= 0.0;
    case Bound::open_unit: return x > 0.0 && x < 1.0;
    case Bound::unit_from_zero: return x >= 0.0 && x < 1.0;
  }
  return false;
}

std::string_view rule(Bound bound) {
  switch (bound) {
    case Bound::finite: return "must be a finite number";
    case Bound::positive: return "must be > 0";
    case Bound::non_negative: return "must be >= 0";
    case Bound::open_unit: return "must be in (0, 1)";
    case Bound::unit_from_zero: return "must be in [0, 1)";
  }
  return "";
}

/// "must be a number", with a hint when the number was quoted.
std::string number_expected(const Value& v) {
  if (v.is_string()) {
    std::istringstream is(v.as_string().str);
    double x = 0.0;
    if (is >> x && is.peek() == std::char_traits<char>::eof())
      return "must be a number (remove the quotes)";
  }
  return "must be a number";
}

/// The entries of a table in file order, so that messages follow the file.
std::vector<std::pair<std::string, const Value*>> in_file_order(const toml::table& table) {
  std::vector<std::pair<std::string, const Value*>> entries;
  for (const auto& [key, value] : table) entries.emplace_back(key, &value);
  const auto position = [](const Value* v) {
    const auto loc = v->location();
    return std::make_pair(loc.line(), loc.column());
  };
  std::sort(entries.begin(), entries.end(), [&](const auto& a, const auto& b) {
    const auto pa = position(a.second), pb = position(b.second);
    return pa != pb ? pa < pb : a.first < b.first;
  });
  return entries;
}

class TableReader {
 public:
  /// `section` names the schema entry; `prefix` is how its keys are written
  /// in messages (they differ for objects: "objects" vs "objects[2]").
  TableReader(const toml::table& table, std::string section, std::string prefix, Diagnostics& diag)
      : table_(table), section_(std::move(section)), prefix_(std::move(prefix)), diag_(diag) {}

  [[nodiscard]] std::string path(std::string_view key) const {
    return fmt::format("{}.{}", prefix_, key);
  }

  [[nodiscard]] const Value* find(std::string_view key) const {
    const auto it = table_.find(std::string(key));
    return it == table_.end() ? nullptr : &it->second;
  }

  void bad(std::string_view key, const Value& v, std::string_view what) {
    diag_.error(path(key), v, what);
  }
  void missing(std::string_view key, std::string_view what) {
    diag_.error(fmt::format("{}: {}", path(key), what));
  }

  /// A float; an integer is accepted too (users write `radius = 1`).
  Read number(std::string_view key, double& out, Bound bound = Bound::finite) {
    const Value* v = find(key);
    if (!v) return Read::absent;
    double x = 0.0;
    if (!as_number(*v, x)) return fail(key, *v, number_expected(*v));
    if (!std::isfinite(x)) return fail(key, *v, "must be a finite number");
    if (!satisfies(x, bound)) return fail(key, *v, rule(bound));
    out = x;
    return Read::ok;
  }

  /// An integer; a float is refused, even 40.0, because a count written as a
  /// float is usually a mistaken key, and silently truncating would hide it.
  Read integer(std::string_view key, int& out, int minimum) {
    const Value* v = find(key);
    if (!v) return Read::absent;
    if (!v->is_integer()) {
      if (v->is_floating() && std::trunc(v->as_floating()) == v->as_floating() &&
          std::abs(v->as_floating()) < 1e9)
        return fail(key, *v,
                    fmt::format("must be an integer (write {}, not {})",
                                static_cast<long long>(v->as_floating()), describe(*v)));
      return fail(key, *v, "must be an integer");
    }
    const auto x = v->as_integer();
    if (x < minimum || x > std::numeric_limits<int>::max())
      return fail(key, *v,
                  x < minimum ? fmt::format("must be an integer >= {}", minimum)
                              : fmt::format("must be an integer in [{}, {}]", minimum,
                                            std::numeric_limits<int>::max()));
    out = static_cast<int>(x);
    return Read::ok;
  }

  Read boolean(std::string_view key, bool& out) {
    const Value* v = find(key);
    if (!v) return Read::absent;
    if (!v->is_boolean()) return fail(key, *v, "must be true or false");
    out = v->as_boolean();
    return Read::ok;
  }

  Read string(std::string_view key, std::string& out) {
    const Value* v = find(key);
    if (!v) return Read::absent;
    if (!v->is_string()) return fail(key, *v, "must be a string (in double quotes)");
    out = v->as_string().str;
    return Read::ok;
  }

  /// One of a few words; `choices` in the order they are listed to the user.
  template <class Enum>
  Read choice(std::string_view key, Enum& out,
              const std::vector<std::pair<std::string_view, Enum>>& choices) {
    std::string word;
    const Read r = string(key, word);
    if (r != Read::ok) return r;
    std::vector<std::string_view> words;
    for (const auto& [w, e] : choices) {
      if (w == word) {
        out = e;
        return Read::ok;
      }
      words.push_back(w);
    }
    std::string allowed;
    for (const auto w : words) allowed += (allowed.empty() ? "" : ", ") + toml_string(w);
    std::string what = fmt::format("must be one of {}", allowed);
    if (const auto c = closest(word, words))
      what += fmt::format(" (did you mean {}?)", toml_string(*c));
    return fail(key, *find(key), what);
  }

  /// Exactly three numbers, each satisfying `bound`; element i is named
  /// key[i] (1-based) in messages.
  Read vector3(std::string_view key, Eigen::Vector3d& out, Bound bound = Bound::finite) {
    const Value* v = find(key);
    if (!v) return Read::absent;
    if (!v->is_array() || v->as_array().size() != 3)
      return fail(key, *v,
                  v->is_array() ? fmt::format("must be an array of exactly 3 numbers (got {})",
                                              v->as_array().size())
                                : std::string("must be an array of exactly 3 numbers"));
    Eigen::Vector3d x;
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
      const Value& e = v->as_array()[static_cast<std::size_t>(i)];
      const std::string element = fmt::format("{}[{}]", path(key), i + 1);
      if (!as_number(e, x[i])) {
        diag_.error(element, e, number_expected(e));
        ok = false;
      } else if (!std::isfinite(x[i]) || !satisfies(x[i], bound)) {
        diag_.error(element, e, std::isfinite(x[i]) ? rule(bound) : "must be a finite number");
        ok = false;
      }
    }
    if (!ok) return Read::bad;
    out = x;
    return Read::ok;
  }

  /// Reports every key the schema does not know, with a suggestion.
  void check_keys() const {
    const Section* s = find_section(section_);
    for (const auto& [key, value] : in_file_order(table_)) {
      if (s && std::find(s->keys.begin(), s->keys.end(), key) != s->keys.end()) continue;
      std::string message = fmt::format("unknown key '{}'", path(key));
      if (const auto hint = suggestion(section_, prefix_, key); !hint.empty())
        message += fmt::format(" (did you mean '{}'?)", hint);
      diag_.error(message);
    }
  }

 private:
  static bool as_number(const Value& v, double& x) {
    if (v.is_floating())
      x = v.as_floating();
    else if (v.is_integer())
      x = static_cast<double>(v.as_integer());
    else
      return false;
    return true;
  }

  Read fail(std::string_view key, const Value& v, std::string_view what) {
    bad(key, v, what);
    return Read::bad;
  }

  const toml::table& table_;
  std::string section_;
  std::string prefix_;
  Diagnostics& diag_;
};

// ---------------------------------------------------------------------------
// Sections.

const toml::table& empty_table() {
  static const toml::table table;
  return table;
}

/// The table of a top-level section, or an empty one if the file omits it
/// (every key then takes its default).
const toml::table& section_table(const toml::table& root, std::string_view name,
                                 Diagnostics& diag) {
  const auto it = root.find(std::string(name));
  if (it == root.end()) return empty_table();
  if (!it->second.is_table()) {
    diag.error(std::string(name), it->second,
               fmt::format("must be a table (write [{}] above its keys)", name));
    return empty_table();
  }
  return it->second.as_table();
}

/// A plain file-name component: the name becomes the output directory.
bool is_plain_name(std::string_view name) {
  if (name.empty() || name == "." || name == "..") return false;
  return std::none_of(name.begin(), name.end(), [](char c) {
    return c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20;
  });
}

void read_case_section(const toml::table& root, const std::string& default_name, CaseConfig& c,
                       Diagnostics& diag) {
  TableReader t(section_table(root, "case", diag), "case", "case", diag);
  t.check_keys();
  c.name = default_name;
  if (t.string("name", c.name) == Read::ok && !is_plain_name(c.name)) {
    t.bad("name", *t.find("name"),
          "must be a non-empty name without '/' or '\\' (it names the output directory)");
    c.name = default_name;
  }
}

void read_cell(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  TableReader t(section_table(root, "cell", diag), "cell", "cell", diag);
  t.check_keys();
  t.number("length", c.box.length, Bound::positive);
  t.number("height", c.box.height, Bound::positive);
  t.number("width", c.box.width, Bound::positive);
  t.boolean("periodic_x", c.box.periodic_x);
  t.boolean("periodic_z", c.box.periodic_z);
}

/// What the objects need from the rest of the file to resolve Gamma; a flag
/// is false when that key was bad (already reported), so no follow-up
/// message is made from a value the user never meant.
struct FlowState {
  bool matrix_viscosity_ok = true;
  bool shear_rate_ok = true;
};

FlowState read_matrix_and_flow(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  FlowState state;
  TableReader matrix(section_table(root, "matrix", diag), "matrix", "matrix", diag);
  matrix.check_keys();
  state.matrix_viscosity_ok =
      matrix.number("viscosity", c.matrix_viscosity, Bound::positive) != Read::bad;
  TableReader flow(section_table(root, "flow", diag), "flow", "flow", diag);
  flow.check_keys();
  state.shear_rate_ok = flow.number("shear_rate", c.shear_rate, Bound::non_negative) != Read::bad;
  return state;
}

void read_mesh(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  TableReader t(section_table(root, "mesh", diag), "mesh", "mesh", diag);
  t.check_keys();
  // Fewer than 8 nodes on the equator (4 P2 edges) no longer describes a sphere.
  t.integer("equator_nodes", c.sizing.equator_nodes, 8);
  t.number("far_size", c.sizing.far_size, Bound::positive);
  t.number("growth", c.sizing.growth, Bound::positive);
  t.boolean("optimize_high_order", c.sizing.optimize_high_order);
}

void read_solver(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  TableReader t(section_table(root, "solver", diag), "solver", "solver", diag);
  t.check_keys();
  t.choice<SolverType>("type", c.solver,
                       {{"direct", SolverType::direct}, {"iterative", SolverType::iterative}});
  t.number("rtol", c.rtol, Bound::open_unit);
  t.integer("max_iterations", c.max_iterations, 1);
  t.string("petsc_options", c.petsc_options);
}

void read_output(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  TableReader t(section_table(root, "output", diag), "output", "output", diag);
  t.check_keys();
  c.output_directory = "output/" + c.name;
  if (t.string("directory", c.output_directory) == Read::ok && c.output_directory.empty()) {
    t.bad("directory", *t.find("directory"), "must not be empty");
    c.output_directory = "output/" + c.name;
  }
  t.boolean("fields", c.write_fields);
}

void read_time_and_interface(const toml::table& root, CaseConfig& c, Diagnostics& diag) {
  TableReader t(section_table(root, "time", diag), "time", "time", diag);
  t.check_keys();
  t.number("step", c.time.step, Bound::positive);
  t.number("end", c.time.end, Bound::non_negative);
  t.integer("fields_interval", c.time.fields_interval, 0);
  t.number("min_quality", c.time.min_quality, Bound::open_unit);
  t.number("max_volume_drift", c.time.max_volume_drift, Bound::open_unit);
  t.number("ale_rebuild_quality", c.time.ale_rebuild_quality, Bound::unit_from_zero);
  TableReader k(section_table(root, "checkpoint", diag), "checkpoint", "checkpoint", diag);
  k.check_keys();
  k.integer("interval_steps", c.checkpoint.interval_steps, 0);
  k.number("interval_minutes", c.checkpoint.interval_minutes, Bound::non_negative);
  TableReader i(section_table(root, "interface", diag), "interface", "interface", diag);
  i.check_keys();
  i.number("redistribution_factor", c.interface.redistribution_factor, Bound::non_negative);
  i.number("supg_beta", c.interface.supg_beta, Bound::non_negative);
  i.boolean("semi_implicit_tension", c.interface.semi_implicit_tension);
}

// ---- one object ----

/// Sphere: `radius`; ellipsoid: `semi_axes` (required) and `rotation_deg`.
/// A key of the other shape is an error rather than ignored, since it means
/// the user expects a shape they did not ask for.
void read_object_shape(TableReader& t, geometry::ObjectSpec& g) {
  const Read shape = t.choice<geometry::ObjectShape>(
      "shape", g.shape,
      {{"sphere", geometry::ObjectShape::sphere}, {"ellipsoid", geometry::ObjectShape::ellipsoid}});
  t.vector3("centre", g.centre);
  if (shape == Read::bad) return;  // which size keys belong is unknown

  if (g.shape == geometry::ObjectShape::sphere) {
    double radius = 1.0;
    t.number("radius", radius, Bound::positive);
    g.semi_axes = Eigen::Vector3d::Constant(radius);
    for (const std::string_view key : {"semi_axes", "rotation_deg"})
      if (const Value* v = t.find(key))
        t.bad(key, *v, "only for shape = \"ellipsoid\" (a sphere takes 'radius')");
    return;
  }
  if (t.vector3("semi_axes", g.semi_axes, Bound::positive) == Read::absent)
    t.missing("semi_axes", "missing: an ellipsoid needs semi_axes = [a, b, c]");
  t.vector3("rotation_deg", g.rotation_deg);
  if (const Value* v = t.find("radius"))
    t.bad("radius", *v, "only for shape = \"sphere\" (an ellipsoid takes 'semi_axes')");
}

/// Gamma from exactly one of capillary_number (Gamma = eta_m gamma_dot R/Ca)
/// or interfacial_tension; neither means Ca = 0.1.
void read_object_tension(TableReader& t, const CaseConfig& c, const FlowState& flow,
                         ObjectConfig& o, Diagnostics& diag, const std::string& prefix) {
  double ca = kDefaultCapillaryNumber;
  double gamma = 0.0;
  const Read ca_read = t.number("capillary_number", ca, Bound::positive);
  const Read gamma_read = t.number("interfacial_tension", gamma, Bound::non_negative);
  if (ca_read != Read::absent && gamma_read != Read::absent) {
    diag.error(fmt::format(
        "{} gives both capillary_number = {} and interfacial_tension = {}: give "
        "only one (Gamma = eta_m gamma_dot R / Ca)",
        prefix, describe(*t.find("capillary_number")), describe(*t.find("interfacial_tension"))));
    return;
  }
  if (gamma_read == Read::ok) {
    o.interfacial_tension = gamma;
    return;
  }
  if (ca_read == Read::bad || gamma_read == Read::bad) return;
  if (!flow.shear_rate_ok || !flow.matrix_viscosity_ok) return;
  if (c.shear_rate == 0.0) {
    if (ca_read == Read::ok)
      t.bad("capillary_number", *t.find("capillary_number"),
            "needs flow.shear_rate > 0 (it is 0); give interfacial_tension instead");
    else
      diag.error(
          fmt::format("{}: flow.shear_rate = 0, so the default capillary_number = {} cannot "
                      "set the interfacial tension; give {}.interfacial_tension",
                      prefix, kDefaultCapillaryNumber, prefix));
    return;
  }
  o.capillary_number = ca;
  o.interfacial_tension = c.matrix_viscosity * c.shear_rate * mean_radius(o.geometry) / ca;
}

ObjectConfig read_object(const toml::table& table, const std::string& prefix, const CaseConfig& c,
                         const FlowState& flow, Diagnostics& diag) {
  ObjectConfig o;
  TableReader t(table, "objects", prefix, diag);
  t.check_keys();
  read_object_shape(t, o.geometry);
  t.number("viscosity_ratio", o.viscosity_ratio, Bound::positive);
  read_object_tension(t, c, flow, o, diag, prefix);
  return o;
}

void read_objects(const toml::table& root, const FlowState& flow, CaseConfig& c,
                  Diagnostics& diag) {
  const auto it = root.find("objects");
  if (it == root.end()) return;  // no objects: the undisturbed shear flow
  const Value& objects = it->second;
  const bool array_of_tables =
      objects.is_array() && std::all_of(objects.as_array().begin(), objects.as_array().end(),
                                        [](const Value& v) { return v.is_table(); });
  if (!array_of_tables) {
    diag.error("objects", objects,
               "must be a list of tables: write [[objects]] (double brackets) above each object");
    return;
  }
  for (std::size_t i = 0; i < objects.as_array().size(); ++i) {
    const std::string prefix = fmt::format("objects[{}]", i + 1);
    c.objects.push_back(read_object(objects.as_array()[i].as_table(), prefix, c, flow, diag));
  }
}

/// Top-level keys that are not sections, and sections that do not exist.
void check_top_level(const toml::table& root, Diagnostics& diag) {
  for (const auto& [key, value] : in_file_order(root)) {
    if (find_section(key)) continue;
    std::string message = fmt::format("unknown key '{}'", key);
    if (const auto hint = suggestion("", "", key); !hint.empty())
      message += fmt::format(" (did you mean '{}'?)", hint);
    diag.error(message);
  }
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

toml::value parse_toml(const std::string& text, const std::string& source) {
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

CaseConfig parse_case(const std::string& toml_text, const std::string& source_name) {
  const toml::value root_value = parse_toml(toml_text, source_name);
  const toml::table& root = root_value.as_table();
  Diagnostics diag(source_name);
  CaseConfig c;
  check_top_level(root, diag);
  read_case_section(root, default_case_name(source_name), c, diag);
  read_cell(root, c, diag);
  const FlowState flow = read_matrix_and_flow(root, c, diag);
  read_objects(root, flow, c, diag);
  read_mesh(root, c, diag);
  read_solver(root, c, diag);
  read_output(root, c, diag);
  read_time_and_interface(root, c, diag);
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

// ---------------------------------------------------------------------------

namespace {

std::string object_toml(const ObjectConfig& o) {
  const auto& g = o.geometry;
  std::string s = "[[objects]]\n";
  if (g.shape == geometry::ObjectShape::sphere) {
    s += "shape = \"sphere\"\n";
    s += fmt::format("centre = {}\n", toml_vector(g.centre));
    s += fmt::format("radius = {}\n", toml_float(g.semi_axes.x()));
  } else {
    s += "shape = \"ellipsoid\"\n";
    s += fmt::format("centre = {}\n", toml_vector(g.centre));
    s += fmt::format("semi_axes = {}\n", toml_vector(g.semi_axes));
    s += fmt::format("rotation_deg = {}\n", toml_vector(g.rotation_deg));
  }
  s += fmt::format("viscosity_ratio = {}\n", toml_float(o.viscosity_ratio));
  // Ca is written when it was given, so that re-reading recomputes the very
  // same Gamma; the resolved Gamma goes in a comment for the reader.
  if (o.capillary_number)
    s += fmt::format("capillary_number = {}  # interfacial_tension = {}\n",
                     toml_float(*o.capillary_number), toml_float(o.interfacial_tension));
  else
    s += fmt::format("interfacial_tension = {}\n", toml_float(o.interfacial_tension));
  return s;
}

}  // namespace

std::string to_toml(const CaseConfig& c) {
  std::string s = "# softflow case, resolved: every key with the value the run uses.\n\n";
  s += fmt::format("[case]\nname = {}\n\n", toml_string(c.name));
  s += fmt::format(
      "[cell]\nlength = {}\nheight = {}\nwidth = {}\nperiodic_x = {}\nperiodic_z = {}\n\n",
      toml_float(c.box.length), toml_float(c.box.height), toml_float(c.box.width), c.box.periodic_x,
      c.box.periodic_z);
  s += fmt::format("[matrix]\nviscosity = {}\n\n", toml_float(c.matrix_viscosity));
  s +=
      fmt::format("[flow]\nshear_rate = {}  # wall velocity u_w = shear_rate * height / 2 = {}\n\n",
                  toml_float(c.shear_rate), toml_float(c.wall_velocity()));
  if (c.objects.empty()) s += "# no [[objects]]: the undisturbed shear flow\n\n";
  for (const auto& o : c.objects) s += object_toml(o) + "\n";
  s += fmt::format(
      "[mesh]\nequator_nodes = {}\nfar_size = {}\ngrowth = {}\noptimize_high_order = {}\n\n",
      c.sizing.equator_nodes, toml_float(c.sizing.far_size), toml_float(c.sizing.growth),
      c.sizing.optimize_high_order);
  s +=
      fmt::format("[solver]\ntype = \"{}\"\nrtol = {}\nmax_iterations = {}\npetsc_options = {}\n\n",
                  c.solver == SolverType::direct ? "direct" : "iterative", toml_float(c.rtol),
                  c.max_iterations, toml_string(c.petsc_options));
  s += fmt::format("[output]\ndirectory = {}\nfields = {}\n\n", toml_string(c.output_directory),
                   c.write_fields);
  s += fmt::format(
      "[time]\nstep = {}\nend = {}\nfields_interval = {}\nmin_quality = {}\nmax_volume_drift = "
      "{}\nale_rebuild_quality = {}\n\n",
      toml_float(c.time.step), toml_float(c.time.end), c.time.fields_interval,
      toml_float(c.time.min_quality), toml_float(c.time.max_volume_drift),
      toml_float(c.time.ale_rebuild_quality));
  s += fmt::format("[checkpoint]\ninterval_steps = {}\ninterval_minutes = {}\n\n",
                   c.checkpoint.interval_steps, toml_float(c.checkpoint.interval_minutes));
  s += fmt::format(
      "[interface]\nredistribution_factor = {}\nsupg_beta = {}\nsemi_implicit_tension = {}\n",
      toml_float(c.interface.redistribution_factor), toml_float(c.interface.supg_beta),
      c.interface.semi_implicit_tension);
  return s;
}

// ---------------------------------------------------------------------------

std::vector<DimensionlessGroup> dimensionless_groups(const CaseConfig& c) {
  std::vector<DimensionlessGroup> groups;
  // Case-wide groups (Deborah/Weissenberg numbers of a viscoelastic matrix)
  // go here, before the per-object ones, with object = 0.
  for (std::size_t k = 0; k < c.objects.size(); ++k) {
    const ObjectConfig& o = c.objects[k];
    const int object = static_cast<int>(k) + 1;
    const double r = mean_radius(o.geometry);
    const double d = 2.0 * r;
    // The Ca the user gave is reported as given, not re-derived through Gamma.
    const double ca = o.capillary_number ? *o.capillary_number
                      : o.interfacial_tension > 0.0
                          ? c.matrix_viscosity * c.shear_rate * r / o.interfacial_tension
                          : std::numeric_limits<double>::infinity();
    const auto add = [&](std::string symbol, std::string name, double value,
                         std::string definition) {
      groups.push_back({std::move(symbol), std::move(name), value, std::move(definition), object});
    };
    add("Ca", "capillary number", ca, "eta_m gamma_dot R / Gamma, R = (abc)^(1/3)");
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
