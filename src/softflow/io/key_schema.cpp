#include "softflow/io/key_schema.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::io::schema {

namespace {

constexpr std::size_t kMaxShownValueLength = 60;

std::string number_text(double x) { return fmt::format("{}", x); }

}  // namespace

// ---------------------------------------------------------------------------
// Ranges and allowed values.

bool Range::contains(double x) const {
  const bool above_lower = lower_open ? x > lower : x >= lower;
  const bool below_upper = upper_open ? x < upper : x <= upper;
  return above_lower && below_upper;
}

std::string Range::text() const {
  const bool has_lower = std::isfinite(lower), has_upper = std::isfinite(upper);
  if (has_lower && has_upper)
    return fmt::format("in {}{}, {}{}", lower_open ? "(" : "[", number_text(lower),
                       number_text(upper), upper_open ? ")" : "]");
  if (has_lower) return fmt::format("{} {}", lower_open ? ">" : ">=", number_text(lower));
  if (has_upper) return fmt::format("{} {}", upper_open ? "<" : "<=", number_text(upper));
  return "";
}

std::string allowed_text(const KeyInfo& key) {
  const std::string range = key.range.text();
  switch (key.type) {
    case KeyType::number: return range.empty() ? "a number" : "a number " + range;
    case KeyType::integer: return range.empty() ? "an integer" : "an integer " + range;
    case KeyType::boolean: return "true or false";
    case KeyType::string: return "a string";
    case KeyType::choice: {
      std::string words;
      for (const auto& c : key.choices) words += (words.empty() ? "" : ", ") + toml_string(c.word);
      return "one of " + words;
    }
    case KeyType::vector3: return range.empty() ? "[x, y, z]" : "[x, y, z], each " + range;
  }
  return "";
}

// ---------------------------------------------------------------------------
// TOML text.

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

void Diagnostics::error(std::string_view message) {
  messages_.push_back(fmt::format("{}: {}", source_, message));
}

void Diagnostics::error(std::string_view key_path, const Value& value, std::string_view what) {
  error(fmt::format("{} = {}: {}", key_path, describe(value), what));
}

void Diagnostics::unknown_key(std::string_view message) {
  if (!lists_next_unknown_key()) {
    ++unlisted_unknown_;
    return;
  }
  ++listed_unknown_;
  error(message);
}

void Diagnostics::throw_if_any() const {
  if (count() == 0) return;
  std::string all;
  for (const auto& m : messages_) all += (all.empty() ? "" : "\n") + m;
  if (unlisted_unknown_ > 0)
    all += fmt::format("\n{}: ... and {} more unknown key{} (only the first {} are listed)",
                       source_, unlisted_unknown_, unlisted_unknown_ == 1 ? "" : "s",
                       kMaxListedUnknownKeys);
  throw InputError(all);
}

// ---------------------------------------------------------------------------
// What toml11 changed silently.

std::string written(const Value& v) {
  const auto* region = dynamic_cast<const toml::detail::region*>(toml::detail::get_region(v));
  return region ? region->str() : std::string();
}

namespace {

/// The text of a TOML integer or float without '_' and a leading '+'.
std::string plain_number_text(std::string text) {
  std::erase(text, '_');
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  return text;
}

}  // namespace

std::string representation_problem(const Value& v) {
  if (!v.is_integer() && !v.is_floating()) return "";
  const std::string text = plain_number_text(written(v));
  if (text.empty()) return "";
  if (v.is_integer()) {
    // Only the clamped extremes can hide an overflow.
    const auto x = v.as_integer();
    if (x != std::numeric_limits<std::int64_t>::max() &&
        x != std::numeric_limits<std::int64_t>::min())
      return "";
    int base = 10;
    std::string_view digits = text;
    bool negative = false;
    if (digits.size() > 2 && digits[0] == '0' && std::isalpha(static_cast<unsigned char>(digits[1]))) {
      base = digits[1] == 'x' ? 16 : digits[1] == 'o' ? 8 : 2;
      digits.remove_prefix(2);
    } else if (!digits.empty() && digits.front() == '-') {
      negative = true;
      digits.remove_prefix(1);
    }
    std::uint64_t magnitude = 0;
    const auto [end, ec] =
        std::from_chars(digits.data(), digits.data() + digits.size(), magnitude, base);
    const std::uint64_t limit =
        static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()) + (negative ? 1 : 0);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && magnitude > limit))
      return "is outside the 64-bit integer range [-9223372036854775808, "
             "9223372036854775807]";
    return "";
  }
  const double x = v.as_floating();
  if (std::isnan(x) || text == "inf" || text == "-inf") return "";  // written as such
  // Underflow to 0 or overflow to +-max/inf: strtod says ERANGE; a subnormal
  // (also ERANGE) is kept, as it is the nearest double to what was written.
  errno = 0;
  const double reparsed = std::strtod(text.c_str(), nullptr);
  if (errno != ERANGE) return "";
  if (std::isinf(reparsed) || std::abs(reparsed) >= std::numeric_limits<double>::max())
    return "is too large for a double (its magnitude must be below 1.8e308)";
  if (reparsed == 0.0 && text.find_first_of("123456789") < text.find_first_of("eE"))
    return "is too small for a double (a number other than 0 must have a magnitude of at least "
           "5e-324)";
  return "";
}

// ---------------------------------------------------------------------------
// Spelling help.

namespace {

/// Edit distance with adjacent transpositions (optimal string alignment):
/// "equator_ndoes" is one slip of the finger from "equator_nodes", not two.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  // At least the difference in length: past 2 nothing is suggested anyway,
  // and a huge key costs nothing.
  if (n > m + 2 || m > n + 2) return std::max(n, m) - std::min(n, m);
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
std::optional<std::string> closest(std::string_view word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = 3;
  for (const auto& c : candidates) {
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
std::optional<std::string> containing(std::string_view word,
                                      const std::vector<std::string>& candidates) {
  if (word.size() < 4) return std::nullopt;
  for (const auto& c : candidates)
    if (c.find(word) != std::string::npos || word.find(c) != std::string_view::npos) return c;
  return std::nullopt;
}

bool equal_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::vector<std::string> key_names(const TableInfo& t) {
  std::vector<std::string> names;
  for (const auto* k : t.keys) names.push_back(k->name);
  return names;
}

/// What to suggest for an unknown key, as a full key path, or "" if nothing
/// fits. `table` is empty for a key at the top level; `prefix` is how keys
/// of this table are written in messages ("mesh", "objects[2]").
std::string suggestion(const Schema& schema, std::string_view table, std::string_view prefix,
                       std::string_view key) {
  const auto qualified = [](std::string_view t, std::string_view k) {
    return t.empty() ? std::string(k) : fmt::format("{}.{}", t, k);
  };
  // Keys of an array table elsewhere are written with a placeholder index.
  const auto in_other_table = [&schema](const std::string& t) {
    const TableInfo* info = schema.find(t);
    return info && info->array ? t + "[k]" : t;
  };
  if (table.empty()) {
    std::vector<std::string> names;
    for (const auto& t : schema.tables) names.push_back(t.name);
    if (const auto c = closest(key, names))
      return schema.find(*c)->array ? "[[" + *c + "]]" : *c;
  } else if (const TableInfo* t = schema.find(table)) {
    const auto names = key_names(*t);
    if (const auto c = closest(key, names)) return qualified(prefix, *c);
    if (const auto c = containing(key, names)) return qualified(prefix, *c);
  }
  // Names from the papers rather than from this file format; a symbol may
  // mean a different key in each table ("G": [matrix] or an object's
  // modulus), so this table's own meaning comes first.
  for (const auto& a : schema.aliases)
    if (a.table == table && equal_ignoring_case(a.word, key)) return qualified(prefix, a.key);
  for (const auto& a : schema.aliases)
    if (equal_ignoring_case(a.word, key)) return qualified(in_other_table(a.table), a.key);
  // A key put under the wrong table (or before any table header).
  for (const auto& t : schema.tables)
    if (t.name != table && t.find(key)) return qualified(in_other_table(t.name), key);
  return "";
}

void report_unknown(const Schema& schema, std::string_view table, std::string_view prefix,
                    std::string_view key, const std::string& path, Diagnostics& diag) {
  if (!diag.lists_next_unknown_key()) {  // only counted: no suggestion to search for
    diag.unknown_key("");
    return;
  }
  std::string message = fmt::format("unknown key '{}'", path);
  if (const auto hint = suggestion(schema, table, prefix, key); !hint.empty())
    message += fmt::format(" (did you mean '{}'?)", hint);
  diag.unknown_key(message);
}

}  // namespace

// ---------------------------------------------------------------------------
// Typed readers.

namespace detail {

namespace {

bool as_number(const Value& v, double& x) {
  if (v.is_floating())
    x = v.as_floating();
  else if (v.is_integer())
    x = static_cast<double>(v.as_integer());
  else
    return false;
  return true;
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

/// "path = value: what", the value as written when toml11 changed it.
void report_number(const std::string& path, const Value& v, std::string_view what,
                   Diagnostics& diag) {
  if (!representation_problem(v).empty())
    diag.error(fmt::format("{} = {}: {}", path, written(v).substr(0, 60), what));
  else
    diag.error(path, v, what);
}

/// What is wrong with one number of a key, or "".
std::string number_problem(const Value& v, const Range& range, double& x) {
  if (!as_number(v, x)) return number_expected(v);
  if (std::string what = representation_problem(v); !what.empty()) return what;
  if (!std::isfinite(x)) return "must be a finite number";
  if (!range.contains(x)) return "must be " + range.text();
  return "";
}

}  // namespace

Read read_number(const Value& v, const std::string& path, const Range& range, double& out,
                 Diagnostics& diag) {
  double x = 0.0;
  if (const std::string what = number_problem(v, range, x); !what.empty()) {
    report_number(path, v, what, diag);
    return Read::bad;
  }
  out = x;
  return Read::ok;
}

Read read_integer(const Value& v, const std::string& path, const Range& range, int& out,
                  Diagnostics& diag) {
  if (!v.is_integer()) {
    if (v.is_floating() && std::trunc(v.as_floating()) == v.as_floating() &&
        std::abs(v.as_floating()) < 1e9)
      diag.error(path, v,
                 fmt::format("must be an integer (write {}, not {})",
                             static_cast<long long>(v.as_floating()), describe(v)));
    else
      diag.error(path, v, "must be an integer");
    return Read::bad;
  }
  if (const std::string what = representation_problem(v); !what.empty()) {
    report_number(path, v, fmt::format("{}; must be an integer {}", what, range.text()), diag);
    return Read::bad;
  }
  const auto x = v.as_integer();
  constexpr auto kMax = std::numeric_limits<int>::max();
  constexpr auto kMin = std::numeric_limits<int>::min();
  if (!range.contains(static_cast<double>(x)) || x > kMax || x < kMin) {
    // An int's own limits are stated only when they are what was passed.
    if (range.contains(static_cast<double>(x)) && !std::isfinite(range.upper)) {
      const double lower = std::isfinite(range.lower) ? range.lower : kMin;
      diag.error(path, v, fmt::format("must be an integer in [{}, {}]", number_text(lower), kMax));
    } else {
      diag.error(path, v, "must be an integer " + range.text());
    }
    return Read::bad;
  }
  out = static_cast<int>(x);
  return Read::ok;
}

Read read_boolean(const Value& v, const std::string& path, bool& out, Diagnostics& diag) {
  if (!v.is_boolean()) {
    diag.error(path, v, "must be true or false");
    return Read::bad;
  }
  out = v.as_boolean();
  return Read::ok;
}

Read read_string(const Value& v, const std::string& path, std::string& out, Diagnostics& diag) {
  if (!v.is_string()) {
    diag.error(path, v, "must be a string (in double quotes)");
    return Read::bad;
  }
  out = v.as_string().str;
  return Read::ok;
}

Read read_choice(const Value& v, const std::string& path, const std::vector<Choice>& words,
                 std::size_t& out, Diagnostics& diag) {
  std::string word;
  if (const Read r = read_string(v, path, word, diag); r != Read::ok) return r;
  std::vector<std::string> candidates;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (words[i].word == word) {
      out = i;
      return Read::ok;
    }
    candidates.push_back(words[i].word);
  }
  std::string allowed;
  for (const auto& w : candidates) allowed += (allowed.empty() ? "" : ", ") + toml_string(w);
  std::string what = fmt::format("must be one of {}", allowed);
  if (const auto c = closest(word, candidates))
    what += fmt::format(" (did you mean {}?)", toml_string(*c));
  diag.error(path, v, what);
  return Read::bad;
}

Read read_vector3(const Value& v, const std::string& path, const Range& range,
                  Eigen::Vector3d& out, Diagnostics& diag) {
  if (!v.is_array() || v.as_array().size() != 3) {
    diag.error(path, v,
               v.is_array() ? fmt::format("must be an array of exactly 3 numbers (got {})",
                                          v.as_array().size())
                            : std::string("must be an array of exactly 3 numbers"));
    return Read::bad;
  }
  Eigen::Vector3d x;
  bool ok = true;
  for (int i = 0; i < 3; ++i) {
    const Value& e = v.as_array()[static_cast<std::size_t>(i)];
    if (const std::string what = number_problem(e, range, x[i]); !what.empty()) {
      report_number(fmt::format("{}[{}]", path, i + 1), e, what, diag);
      ok = false;
    }
  }
  if (!ok) return Read::bad;
  out = x;
  return Read::ok;
}

}  // namespace detail

// ---------------------------------------------------------------------------
// Tables.

const KeyInfo* TableInfo::find(std::string_view key) const {
  for (const auto* k : keys)
    if (k->name == key) return k;
  return nullptr;
}

const TableInfo* Schema::find(std::string_view table) const {
  for (const auto& t : tables)
    if (t.name == table) return &t;
  return nullptr;
}

const KeyInfo* Schema::find(std::string_view table, std::string_view key) const {
  const TableInfo* t = find(table);
  return t ? t->find(key) : nullptr;
}

const Value* TableRead::value(std::string_view key) const {
  if (!table_) return nullptr;
  const auto it = table_->find(std::string(key));
  return it == table_->end() ? nullptr : &it->second;
}

std::string TableRead::path(std::string_view key) const {
  return fmt::format("{}.{}", prefix_, key);
}

std::vector<std::pair<std::string, const Value*>> in_file_order(const toml::table& table) {
  std::vector<std::pair<std::string, const Value*>> entries;
  for (const auto& [key, value] : table) entries.emplace_back(key, &value);
  // The offset in the file, not toml11's location(): that counts the lines
  // from the start of the file on each call, which made sorting thousands of
  // keys quadratic (seconds to minutes).
  const auto position = [](const Value* v) -> std::size_t {
    const auto* region = dynamic_cast<const toml::detail::region*>(toml::detail::get_region(*v));
    if (!region) return std::numeric_limits<std::size_t>::max();
    return static_cast<std::size_t>(region->first() - region->begin());
  };
  std::vector<std::pair<std::size_t, std::size_t>> order;  // (position, index)
  order.reserve(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i)
    order.emplace_back(position(entries[i].second), i);
  std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first
                              : entries[a.second].first < entries[b.second].first;
  });
  std::vector<std::pair<std::string, const Value*>> sorted;
  sorted.reserve(entries.size());
  for (const auto& [pos, i] : order) sorted.push_back(std::move(entries[i]));
  return sorted;
}

void check_top_level(const toml::table& root, const Schema& schema, Diagnostics& diag) {
  for (const auto& [key, value] : in_file_order(root))
    if (!schema.find(key)) report_unknown(schema, "", "", key, key, diag);
}

void check_unknown_keys(const Schema& schema, const std::string& name, const toml::table& table,
                        const std::string& prefix, Diagnostics& diag) {
  const TableInfo* info = schema.find(name);
  for (const auto& [key, value] : in_file_order(table))
    if (!info || !info->find(key))
      report_unknown(schema, name, prefix, key, fmt::format("{}.{}", prefix, key), diag);
}

const toml::table& section(const toml::table& root, const TableInfo& table, Diagnostics& diag) {
  static const toml::table empty;
  const auto it = root.find(table.name);
  if (it == root.end()) return empty;
  if (!it->second.is_table()) {
    diag.error(table.name, it->second,
               fmt::format("must be a table (write [{}] above its keys)", table.name));
    return empty;
  }
  return it->second.as_table();
}

std::vector<const toml::table*> array_sections(const toml::table& root, const TableInfo& table,
                                               Diagnostics& diag) {
  const auto it = root.find(table.name);
  if (it == root.end()) return {};
  const Value& v = it->second;
  const bool array_of_tables =
      v.is_array() && std::all_of(v.as_array().begin(), v.as_array().end(),
                                  [](const Value& e) { return e.is_table(); });
  if (!array_of_tables) {
    diag.error(table.name, v,
               fmt::format("must be a list of tables: write [[{}]] (double brackets) above each "
                           "entry",
                           table.name));
    return {};
  }
  std::vector<const toml::table*> tables;
  for (const auto& e : v.as_array()) tables.push_back(&e.as_table());
  return tables;
}

namespace {

/// "a", "a" or "b", "a", "b" or "c" (or with "and").
std::string either(const std::vector<std::string>& words, bool quoted,
                   std::string_view conjunction = "or") {
  std::string s;
  for (std::size_t i = 0; i < words.size(); ++i) {
    if (i > 0) s += i + 1 == words.size() ? fmt::format(" {} ", conjunction) : ", ";
    s += quoted ? toml_string(words[i]) : words[i];
  }
  return s;
}

}  // namespace

std::string not_applicable_message(const TableInfo& table, const KeyInfo& key,
                                   const std::string& selector_word) {
  const std::string& selector = key.condition.selector;
  std::vector<std::string> taken;  // what the current word does take
  for (const auto* k : table.keys) {
    const auto& when = k->condition.values;
    if (k->condition.selector == selector &&
        std::find(when.begin(), when.end(), selector_word) != when.end())
      taken.push_back(k->name);
  }
  std::string s = fmt::format("only for {} = {}", selector, either(key.condition.values, true));
  if (taken.empty()) {
    s += fmt::format(" (with {} = {} leave it out)", selector, toml_string(selector_word));
  } else {
    std::vector<std::string> quoted;
    for (const auto& t : taken) quoted.push_back("'" + t + "'");
    s += fmt::format(" ({} = {} takes {})", selector, toml_string(selector_word),
                     either(quoted, false, "and"));
  }
  if (!key.condition.why.empty()) s += "; " + key.condition.why;
  return s;
}

std::string missing_message(const KeyInfo& key, const std::string& selector_word) {
  const std::string what = key.type == KeyType::vector3
                               ? fmt::format("{} = {}", key.name, allowed_text(key))
                               : fmt::format("{}, {}", key.name, allowed_text(key));
  if (key.condition.selector.empty()) return "missing: give " + what;
  return fmt::format("missing: {} = {} needs {}", key.condition.selector,
                     toml_string(selector_word), what);
}

// ---------------------------------------------------------------------------
// The key reference.

namespace {

std::string cell(std::string s) {
  std::string out;
  for (const char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string code(const std::string& s) { return "`" + s + "`"; }

}  // namespace

std::string markdown(const TableInfo& table) {
  std::string s = table.array ? fmt::format("## `[[{}]]`\n\n", table.name)
                              : fmt::format("## `[{}]`\n\n", table.name);
  if (!table.doc.empty()) s += table.doc + "\n\n";
  s += "| key | value | default | meaning |\n|---|---|---|---|\n";
  for (const auto* k : table.keys) {
    std::string value;
    if (k->type == KeyType::choice) {
      std::vector<std::string> words;
      for (const auto& c : k->choices) words.push_back(code(toml_string(c.word)));
      value = either(words, false);
    } else {
      value = allowed_text(*k);
    }
    const std::string fallback = k->required         ? "required"
                                 : k->default_in_words ? k->default_text
                                                       : code(k->default_text);
    std::string meaning = k->doc;
    for (const auto& c : k->choices)
      if (!c.doc.empty()) meaning += fmt::format("<br>{}: {}", code(toml_string(c.word)), c.doc);
    if (!k->condition.selector.empty()) {
      std::vector<std::string> when;
      for (const auto& w : k->condition.values)
        when.push_back(code(fmt::format("{} = {}", k->condition.selector, toml_string(w))));
      meaning += fmt::format("<br>Only with {}{}.", either(when, false),
                             k->required ? ", and required there" : "");
    }
    s += fmt::format("| {} | {} | {} | {} |\n", code(k->name), cell(value), cell(fallback),
                     cell(meaning));
  }
  return s;
}

}  // namespace softflow::io::schema
