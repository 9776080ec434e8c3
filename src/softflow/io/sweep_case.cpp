#include "softflow/io/sweep_case.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include <fmt/format.h>
#include <toml.hpp>

#include "softflow/common/error.hpp"
#include "softflow/io/case_keys.hpp"
#include "softflow/io/key_schema.hpp"

namespace softflow::io {

namespace {

/// Keys whose single value is itself a list of three numbers (as declared):
/// varied, they are lists of such lists.
bool is_vector_key(const std::string& section, const std::string& key) {
  const schema::KeyInfo* k = case_keys().schema.find(section, key);
  return k && k->type == schema::KeyType::vector3;
}

toml::value parse(const std::string& text, const std::string& source) {
  check_toml_nesting(text, source);
  try {
    std::istringstream stream(text);
    return toml::parse(stream, source);
  } catch (const std::exception&) {
    parse_case(text, source);  // throws the case reader's message for the same syntax error
    throw InputError(fmt::format("{}: cannot parse", source));
  }
}

/// Where a varied value lives in the parsed file.
struct Location {
  std::string section;  ///< top-level table ("time", "objects", ...)
  int object = -1;      ///< index into [[objects]], or -1
  std::string key;
};

/// A value as it appears in directory names: plain characters only.
std::string label_of(const toml::value& v) {
  std::string s;
  if (v.is_integer()) {
    s = std::to_string(v.as_integer());
  } else if (v.is_floating()) {
    s = fmt::format("{}", v.as_floating());
  } else if (v.is_boolean()) {
    s = v.as_boolean() ? "true" : "false";
  } else if (v.is_string()) {
    s = v.as_string().str;
  } else if (v.is_array()) {
    for (const auto& e : v.as_array()) s += (s.empty() ? "" : "x") + label_of(e);
  } else {
    s = "value";
  }
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+')) c = '_';
  return s;
}

double number_of(const toml::value& v) {
  if (v.is_floating()) return v.as_floating();
  if (v.is_integer()) return static_cast<double>(v.as_integer());
  return std::numeric_limits<double>::quiet_NaN();
}

/// The same value, reading 1 and 1.0 (and vectors of them) as one.
bool same_value(const toml::value& a, const toml::value& b) {
  if (a.is_array() && b.is_array()) {
    const auto &x = a.as_array(), &y = b.as_array();
    if (x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!same_value(x[i], y[i])) return false;
    return true;
  }
  const double p = number_of(a), q = number_of(b);
  if (!std::isnan(p) || !std::isnan(q)) return p == q;
  return a == b;
}

/// Whether `value` of `section`.`key` is a list of values rather than one value.
bool is_varied(const std::string& section, const std::string& key, const toml::value& value) {
  if (!value.is_array()) return false;
  if (!is_vector_key(section, key)) return true;
  const auto& a = value.as_array();
  return !a.empty() && a.front().is_array();
}

struct Found {
  std::vector<SweepParameter> parameters;
  std::vector<Location> locations;
  std::vector<std::vector<toml::value>> values;
};

Found find_varied(const toml::value& root, const std::string& source) {
  Found found;
  if (!root.is_table()) return found;
  const auto& table = root.as_table();
  const auto objects = table.find("objects");
  const std::size_t n_objects =
      objects != table.end() && objects->second.is_array() ? objects->second.as_array().size() : 0;
  auto add = [&](const Location& where, const toml::value& list) {
    SweepParameter p;
    if (where.object >= 0) {
      p.path = fmt::format("objects[{}].{}", where.object + 1, where.key);
      p.name = n_objects > 1 ? fmt::format("objects{}.{}", where.object + 1, where.key) : where.key;
    } else {
      p.path = fmt::format("{}.{}", where.section, where.key);
      p.name = where.key;
    }
    if (list.as_array().empty())
      throw InputError(fmt::format("{}: {} = []: a swept parameter must list at least one value",
                                   source, p.path));
    for (const auto& v : list.as_array()) {
      p.labels.push_back(label_of(v));
      p.numbers.push_back(number_of(v));
    }
    found.parameters.push_back(std::move(p));
    found.locations.push_back(where);
    found.values.emplace_back(list.as_array().begin(), list.as_array().end());
  };
  // Sorted for a stable order whatever the hash map does: sections by name,
  // objects by index, keys by name.
  std::vector<std::string> sections;
  for (const auto& [name, value] : table) sections.push_back(name);
  std::sort(sections.begin(), sections.end());
  for (const auto& section : sections) {
    const auto& value = table.at(section);
    auto scan = [&](const toml::table& t, int object) {
      std::vector<std::string> keys;
      for (const auto& [key, v] : t) keys.push_back(key);
      std::sort(keys.begin(), keys.end());
      for (const auto& key : keys)
        if (is_varied(section, key, t.at(key))) add({section, object, key}, t.at(key));
    };
    if (section == "objects" && value.is_array()) {
      for (std::size_t i = 0; i < value.as_array().size(); ++i)
        if (value.as_array()[i].is_table())
          scan(value.as_array()[i].as_table(), static_cast<int>(i));
    } else if (value.is_table()) {
      scan(value.as_table(), -1);
    }
  }
  return found;
}

/// What a sweep's lists must not do (issue 33): vary the names the sweep
/// gives its cases, or list a value twice (it ran once and filled two
/// identical rows) or two values that make one directory label. Checked by
/// expand_sweep only: sweep_parameters merely tells a sweep file.
void check_varied(const Found& found, const std::string& source) {
  for (std::size_t k = 0; k < found.parameters.size(); ++k) {
    const SweepParameter& p = found.parameters[k];
    const Location& where = found.locations[k];
    const auto& values = found.values[k];
    const toml::value list(toml::array(values.begin(), values.end()));
    if ((where.section == "case" && where.key == "name") ||
        (where.section == "output" && where.key == "directory"))
      throw InputError(fmt::format(
          "{}: {} = {}: cannot be varied: the sweep names its cases itself, "
          "<case.name>_<label> in <output.directory>/<label>; give one value",
          source, p.path, schema::describe(list)));
    for (std::size_t i = 0; i < values.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        if (p.labels[j] != p.labels[i]) continue;
        if (same_value(values[j], values[i]))
          throw InputError(fmt::format(
              "{}: {} = {}: lists {} twice (values {} and {}): each value of a sweep must "
              "differ (the same case would run once and fill two identical rows); remove one",
              source, p.path, schema::describe(list), schema::describe(values[i]), j + 1, i + 1));
        throw InputError(fmt::format(
            "{}: {} = {}: values {} and {} ({} and {}) both make the directory label '{}': give "
            "values that differ in letters, digits, '.', '-' or '+'",
            source, p.path, schema::describe(list), j + 1, i + 1, schema::describe(values[j]),
            schema::describe(values[i]), p.labels[i]));
      }
  }
}

toml::value& at(toml::value& root, const Location& where) {
  toml::value& section = root.as_table().at(where.section);
  if (where.object >= 0) return section.as_array()[where.object].as_table().at(where.key);
  return section.as_table().at(where.key);
}

/// root[section][key], or nullptr.
const toml::value* find_key(const toml::value& root, const char* section, const char* key) {
  const auto& table = root.as_table();
  const auto s = table.find(section);
  if (s == table.end() || !s->second.is_table()) return nullptr;
  const auto k = s->second.as_table().find(key);
  return k == s->second.as_table().end() ? nullptr : &k->second;
}

/// The sweep's [case] name or [output] directory, checked as a single case
/// checks it (each generated case gets its own, so without this a name of
/// "", true or 5 passed, and "" wrote into output/ itself); `fallback` when
/// not given.
std::string sweep_text(const toml::value& root, const char* section, const char* key,
                       const std::string& fallback, const std::string& source) {
  const toml::value* v = find_key(root, section, key);
  if (!v) return fallback;
  const auto* declared = case_keys().table(section)->find(key);
  schema::Diagnostics diag(source);
  CaseConfig scratch;
  declared->read(scratch, *v, fmt::format("{}.{}", section, key), diag);
  diag.throw_if_any();
  return v->as_string().str;
}

}  // namespace

std::vector<SweepParameter> sweep_parameters(const std::string& toml_text,
                                             const std::string& source_name) {
  return find_varied(parse(toml_text, source_name), source_name).parameters;
}

Sweep expand_sweep(const std::string& toml_text, const std::string& source_name) {
  const toml::value root = parse(toml_text, source_name);
  const Found found = find_varied(root, source_name);
  check_varied(found, source_name);
  Sweep sweep;
  sweep.parameters = found.parameters;
  const std::string stem = std::filesystem::path(source_name).stem().string();
  const std::string default_name =
      is_plain_name(stem) && stem.size() <= kMaxDirectoryNameBytes ? stem : "sweep";
  sweep.name = sweep_text(root, "case", "name", default_name, source_name);
  sweep.directory = sweep_text(root, "output", "directory", "output/" + sweep.name, source_name);
  if (const auto what = output_directory_problem(sweep.directory); !what.empty()) {
    const bool given = find_key(root, "output", "directory") != nullptr;
    throw InputError(fmt::format(
        "{}: {} = {}: {}{}", source_name, given ? "output.directory" : "case.name",
        schema::toml_string(given ? sweep.directory : sweep.name),
        given ? what : "names the sweep's directory output/<name>, which " + what,
        given ? "" : ", or give output.directory"));
  }

  std::size_t n_cases = 1;
  for (const auto& v : found.values) n_cases *= v.size();
  std::vector<int> choice(found.values.size(), 0);
  for (std::size_t n = 0; n < n_cases; ++n) {
    // choice = the digits of n, the last parameter varying fastest.
    std::size_t rest = n;
    for (std::size_t p = found.values.size(); p-- > 0;) {
      choice[p] = static_cast<int>(rest % found.values[p].size());
      rest /= found.values[p].size();
    }
    toml::value value = root;
    std::string label;
    for (std::size_t p = 0; p < choice.size(); ++p) {
      at(value, found.locations[p]) = found.values[p][choice[p]];
      label += (label.empty() ? "" : "__") + sweep.parameters[p].name + "_" +
               sweep.parameters[p].labels[choice[p]];
    }
    if (label.empty()) label = "case";
    // The label names the case's directory (staged as <label>.partial-<pid>)
    // and its file cases/<label>.toml (written as <label>.toml.tmp-<pid>).
    constexpr std::size_t kMaxLabelBytes = 255 - std::string_view(".toml.tmp-").size() - 7;
    if (label.size() > kMaxLabelBytes) {
      std::string varied;
      for (const auto& p : sweep.parameters) varied += (varied.empty() ? "" : ", ") + p.path;
      throw InputError(fmt::format(
          "{}: the sweep case '{}...' has a label of {} bytes (<key>_<value> of each varied key, "
          "joined by '__'): it names the case's directory and cases/<label>.toml, at most {} "
          "bytes (NAME_MAX, 255, less the 17 of '.toml.tmp-<pid>'); vary fewer keys or give "
          "shorter values (varied: {})",
          source_name, label.substr(0, 40), label.size(), kMaxLabelBytes, varied));
    }
    auto& table = value.as_table();
    if (!table.count("case") || !table.at("case").is_table()) table["case"] = toml::table{};
    if (!table.count("output") || !table.at("output").is_table()) table["output"] = toml::table{};
    table["case"].as_table()["name"] = sweep.name + "_" + label;
    table["output"].as_table()["directory"] =
        (std::filesystem::path(sweep.directory) / label).string();
    SweepCase c;
    c.label = label;
    c.choice = choice;
    c.toml_text = "# generated by softflow sweep from " + source_name + "\n" + toml::format(value);
    // The first combination with a problem is reported: most problems are
    // shared by every combination, and one message per case would bury them.
    c.config = parse_case(c.toml_text, fmt::format("{} [sweep case {}]", source_name, label));
    sweep.cases.push_back(std::move(c));
  }
  return sweep;
}

}  // namespace softflow::io
