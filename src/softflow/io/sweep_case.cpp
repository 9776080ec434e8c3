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

toml::value& at(toml::value& root, const Location& where) {
  toml::value& section = root.as_table().at(where.section);
  if (where.object >= 0) return section.as_array()[where.object].as_table().at(where.key);
  return section.as_table().at(where.key);
}

std::string string_or(const toml::value& root, const char* section, const char* key,
                      const std::string& fallback) {
  const auto& table = root.as_table();
  const auto s = table.find(section);
  if (s == table.end() || !s->second.is_table()) return fallback;
  const auto k = s->second.as_table().find(key);
  return k != s->second.as_table().end() && k->second.is_string() ? k->second.as_string().str
                                                                  : fallback;
}

}  // namespace

std::vector<SweepParameter> sweep_parameters(const std::string& toml_text,
                                             const std::string& source_name) {
  return find_varied(parse(toml_text, source_name), source_name).parameters;
}

Sweep expand_sweep(const std::string& toml_text, const std::string& source_name) {
  const toml::value root = parse(toml_text, source_name);
  const Found found = find_varied(root, source_name);
  Sweep sweep;
  sweep.parameters = found.parameters;
  const std::string stem = std::filesystem::path(source_name).stem().string();
  sweep.name = string_or(root, "case", "name", stem.empty() ? "sweep" : stem);
  sweep.directory = string_or(root, "output", "directory", "output/" + sweep.name);

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
