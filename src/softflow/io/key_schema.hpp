// Keys of a TOML input file, each declared once (name, type, default, allowed values, one-line
// doc); reading with its messages, the printout of the resolved values and the key reference
// are all derived from the declarations.
//
// A declaration binds a key to a value of the struct its table fills (a Field), e.g.
//
//   number("length", field(&CaseConfig::box, &mesh::Box::length), 30.0, Range::above(0),
//          "L along x, the flow direction")
//
// and read_table / write_table / markdown do the rest. What involves several keys (one value
// computed from others, two keys that exclude each other) stays explicit code after
// read_table, which reports for each key whether it was absent, read, or bad.
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <toml.hpp>

namespace softflow::io::schema {

using Value = toml::value;

// ---------------------------------------------------------------------------
// What a key allows.

/// The interval a number, an integer or each element of a vector must lie in.
struct Range {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool lower_open = false;  ///< the bound itself is excluded
  bool upper_open = false;

  static Range any() { return {}; }
  static Range above(double x) { return {x, std::numeric_limits<double>::infinity(), true, false}; }
  static Range at_least(double x) {
    return {x, std::numeric_limits<double>::infinity(), false, false};
  }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }          ///< (lo, hi)
  static Range right_open(double lo, double hi) { return {lo, hi, false, true}; }  ///< [lo, hi)

  [[nodiscard]] bool contains(double x) const;
  /// "> 0", ">= 8", "in (0, 1)", "in [0, 1)"; empty for any value.
  [[nodiscard]] std::string text() const;
};

enum class KeyType { number, integer, boolean, string, choice, vector3 };

/// One word a choice key accepts, with what it means (for the key reference).
struct Choice {
  std::string word;
  std::string doc;
};

/// A key that belongs to some values of another key of its table (a choice
/// declared before it): `radius` only with shape = "sphere". Given with any
/// other value it is an error rather than ignored, since the user then
/// expects something they did not ask for.
struct Condition {
  std::string selector;             ///< empty: the key always applies
  std::vector<std::string> values;
  /// Why the key belongs to those values only, added to the message when it
  /// is given with another ("an elastic particle has no interfacial
  /// tension"); may be empty.
  std::string why;
};

/// What every declaration says, whatever struct its table fills.
struct KeyInfo {
  std::string name;
  KeyType type = KeyType::number;
  Range range;                  ///< number, integer, each element of a vector
  std::vector<Choice> choices;  ///< choice keys, in the order they are listed to users
  /// The default as TOML ("30.0"), or in words when code computes it after
  /// reading ("the file name without .toml"); empty for a required key.
  std::string default_text;
  bool default_in_words = false;  ///< default_text is prose, not a TOML value
  bool required = false;          ///< must be given wherever it applies
  Condition condition;
  std::string doc;  ///< one line: meaning, symbol, unit
};

/// "a number > 0", "an integer >= 8", "true or false", "one of "a", "b"",
/// "[x, y, z], each > 0": the type and allowed values, as messages and the
/// key reference word them.
std::string allowed_text(const KeyInfo& key);

// ---------------------------------------------------------------------------
// Writing TOML values, for messages and printouts.

/// Shortest text that reads back to the same double, always recognisable as
/// a TOML float ("30.0", not "30").
std::string toml_float(double x);
std::string toml_string(std::string_view s);
std::string toml_vector(const Eigen::Vector3d& v);
/// The value as the user wrote it (near enough, shortened), for messages.
std::string describe(const Value& v);

// ---------------------------------------------------------------------------
// Collecting problems: the whole file is checked and every problem reported
// at once, so a user fixes a file in one round, not one per run.

class Diagnostics {
 public:
  explicit Diagnostics(std::string source) : source_(std::move(source)) {}
  void error(std::string_view message);
  /// "<path> = <value as written>: <what>".
  void error(std::string_view key_path, const Value& value, std::string_view what);
  /// An unknown key: the first kMaxListedUnknownKeys are listed, the rest
  /// only counted ("... and 990 more unknown keys"), so that a file of
  /// thousands of stray keys gives a readable answer.
  static constexpr std::size_t kMaxListedUnknownKeys = 10;
  /// Whether the next unknown key would still be listed (worth a suggestion).
  [[nodiscard]] bool lists_next_unknown_key() const {
    return listed_unknown_ < kMaxListedUnknownKeys;
  }
  void unknown_key(std::string_view message);
  [[nodiscard]] std::size_t count() const { return messages_.size() + unlisted_unknown_; }
  /// Throws InputError with one line per problem.
  void throw_if_any() const;

 private:
  std::string source_;
  std::vector<std::string> messages_;
  std::size_t listed_unknown_ = 0;
  std::size_t unlisted_unknown_ = 0;
};

/// The value's text as written in the file (e.g. "1e400", which toml11
/// stores as 1.8e308), or "" when the value has no source text.
std::string written(const Value& v);

/// What is wrong with a number's text that its stored value hides: "" when
/// the stored value is what was written (up to rounding), else why not
/// ("is too large for a double ..."). toml11 clamps out-of-range integers
/// and floats silently.
std::string representation_problem(const Value& v);

enum class Read { absent, ok, bad };

/// Typed readers: check one value and report what is wrong under `path`.
namespace detail {
Read read_number(const Value& v, const std::string& path, const Range& range, double& out,
                 Diagnostics& diag);
Read read_integer(const Value& v, const std::string& path, const Range& range, int& out,
                  Diagnostics& diag);
Read read_boolean(const Value& v, const std::string& path, bool& out, Diagnostics& diag);
Read read_string(const Value& v, const std::string& path, std::string& out, Diagnostics& diag);
/// Index of the word in `words`.
Read read_choice(const Value& v, const std::string& path, const std::vector<Choice>& words,
                 std::size_t& out, Diagnostics& diag);
/// Exactly three numbers; element i is named path[i] (1-based) in messages.
Read read_vector3(const Value& v, const std::string& path, const Range& range,
                  Eigen::Vector3d& out, Diagnostics& diag);

/// The read function of a key checked by one of the ranged readers above:
/// the field is set only when the value reads.
template <class Target, class X, class Set>
auto ranged_reader(Set set, Range range,
                   Read (*parse)(const Value&, const std::string&, const Range&, X&, Diagnostics&)) {
  return [set = std::move(set), range, parse](Target& t, const Value& v, const std::string& path,
                                              Diagnostics& diag) {
    X x{};
    const Read r = parse(v, path, range, x, diag);
    if (r == Read::ok) set(t, x);
    return r;
  };
}
}  // namespace detail

// ---------------------------------------------------------------------------
// Binding keys to structs.

/// Where a key's value lives in the struct `Target` its table fills.
template <class Target, class T>
struct Field {
  std::function<T(const Target&)> get;
  std::function<void(Target&, const T&)> set;
};

/// A member: field(&CaseConfig::shear_rate).
template <class Target, class T>
Field<Target, T> field(T Target::*member) {
  return {[member](const Target& t) { return t.*member; },
          [member](Target& t, const T& v) { t.*member = v; }};
}

/// A member of a member: field(&CaseConfig::box, &mesh::Box::length).
template <class Target, class Inner, class T>
Field<Target, T> field(Inner Target::*outer, T Inner::*member) {
  return {[outer, member](const Target& t) { return (t.*outer).*member; },
          [outer, member](Target& t, const T& v) { (t.*outer).*member = v; }};
}

/// A default that code fills in after reading (it depends on other keys or
/// on the file name), described in words for the key reference.
struct Computed {
  std::string how;
};
/// A key without a default: it must be given where it applies.
struct Required {};
inline constexpr Required required{};

template <class T>
struct Default {
  std::optional<T> value;
  std::string text;  ///< for Computed
  bool required = false;

  Default(T v) : value(std::move(v)) {}  // NOLINT: a plain value is the usual default
  Default(const char* s)
    requires std::is_same_v<T, std::string>
      : value(std::string(s)) {}
  Default(Computed c) : text(std::move(c.how)) {}
  Default(Required) : required(true) {}
};

/// One declared key of a table whose values go into a `Target`.
template <class Target>
struct Key : KeyInfo {
  /// Stores the declared default; empty for required and computed defaults.
  std::function<void(Target&)> apply_default;
  /// Checks a given value and stores it.
  std::function<Read(Target&, const Value&, const std::string& path, Diagnostics&)> read;
  /// The value as TOML for the printout; nullopt: not written.
  std::function<std::optional<std::string>(const Target&)> print;
  /// Choice keys: the current word (what conditions on this key test).
  std::function<std::string(const Target&)> word;
  /// Optional: a note written after the value in the printout ("# u_w = 15.0").
  std::function<std::string(const Target&)> comment;

  /// The key applies only while `selector` has one of `values`; `why`, if
  /// given, explains it to a user who gave the key with another value.
  Key only_when(std::string selector, std::vector<std::string> values, std::string why = "") && {
    condition = {std::move(selector), std::move(values), std::move(why)};
    return std::move(*this);
  }
  Key with_comment(std::function<std::string(const Target&)> note) && {
    comment = std::move(note);
    return std::move(*this);
  }
  /// Written in the printout only when `shown` holds (e.g. one of two
  /// alternative keys: the one the user gave).
  Key printed_if(std::function<bool(const Target&)> shown) && {
    print = [shown = std::move(shown), inner = std::move(print)](const Target& t) {
      return shown(t) ? inner(t) : std::nullopt;
    };
    return std::move(*this);
  }
};

namespace detail {

template <class Target, class T>
Key<Target> declare(std::string name, KeyType type, Range range, const Field<Target, T>& f,
                    const Default<T>& d, std::string doc,
                    std::function<std::string(const T&)> as_toml) {
  Key<Target> k;
  k.name = std::move(name);
  k.type = type;
  k.range = range;
  k.doc = std::move(doc);
  k.required = d.required;
  if (d.value) {
    k.default_text = as_toml(*d.value);
    k.apply_default = [set = f.set, v = *d.value](Target& t) { set(t, v); };
  } else {
    k.default_text = d.text;
    k.default_in_words = !d.required;
  }
  k.print = [get = f.get, as_toml](const Target& t) -> std::optional<std::string> {
    return as_toml(get(t));
  };
  return k;
}

}  // namespace detail

/// A finite float; an integer is accepted too (users write `radius = 1`).
template <class Target>
Key<Target> number(std::string name, Field<Target, double> f,
                   std::type_identity_t<Default<double>> d, Range range, std::string doc) {
  auto k = detail::declare<Target, double>(std::move(name), KeyType::number, range, f, d,
                                           std::move(doc), toml_float);
  k.read = detail::ranged_reader<Target>(f.set, range, &detail::read_number);
  return k;
}

/// A number that may stay unset (its default is computed from other keys).
template <class Target>
Key<Target> optional_number(std::string name, Field<Target, std::optional<double>> f,
                            Computed d, Range range, std::string doc) {
  Key<Target> k;
  k.name = std::move(name);
  k.type = KeyType::number;
  k.range = range;
  k.default_text = std::move(d.how);
  k.default_in_words = true;
  k.doc = std::move(doc);
  k.read = detail::ranged_reader<Target>(f.set, range, &detail::read_number);
  k.print = [get = f.get](const Target& t) -> std::optional<std::string> {
    const auto x = get(t);
    return x ? std::optional<std::string>(toml_float(*x)) : std::nullopt;
  };
  return k;
}

/// A number that must be given wherever it applies but has no place in the
/// struct until then (e.g. a relaxation time, needed by some models only).
template <class Target>
Key<Target> optional_number(std::string name, Field<Target, std::optional<double>> f, Required,
                            Range range, std::string doc) {
  auto k = optional_number(std::move(name), std::move(f), Computed{""}, range, std::move(doc));
  k.default_in_words = false;
  k.required = true;
  return k;
}

/// An integer that may stay unset (its meaning unset is described in words).
template <class Target>
Key<Target> optional_integer(std::string name, Field<Target, std::optional<int>> f, Computed d,
                             Range range, std::string doc) {
  Key<Target> k;
  k.name = std::move(name);
  k.type = KeyType::integer;
  k.range = range;
  k.default_text = std::move(d.how);
  k.default_in_words = true;
  k.doc = std::move(doc);
  k.read = detail::ranged_reader<Target>(f.set, range, &detail::read_integer);
  k.print = [get = f.get](const Target& t) -> std::optional<std::string> {
    const auto x = get(t);
    return x ? std::optional<std::string>(std::to_string(*x)) : std::nullopt;
  };
  return k;
}

/// An integer; a float is refused, even 40.0 (a count written as a float is
/// usually a mistaken key, and truncating it would hide that).
template <class Target>
Key<Target> integer(std::string name, Field<Target, int> f, std::type_identity_t<Default<int>> d,
                    Range range, std::string doc) {
  auto k = detail::declare<Target, int>(std::move(name), KeyType::integer, range, f, d,
                                        std::move(doc),
                                        [](const int& x) { return std::to_string(x); });
  k.read = detail::ranged_reader<Target>(f.set, range, &detail::read_integer);
  return k;
}

template <class Target>
Key<Target> boolean(std::string name, Field<Target, bool> f,
                    std::type_identity_t<Default<bool>> d, std::string doc) {
  auto k = detail::declare<Target, bool>(std::move(name), KeyType::boolean, Range::any(), f, d,
                                         std::move(doc), [](const bool& x) {
                                           return std::string(x ? "true" : "false");
                                         });
  k.read = [set = f.set](Target& t, const Value& v, const std::string& path, Diagnostics& diag) {
    bool x = false;
    const Read r = detail::read_boolean(v, path, x, diag);
    if (r == Read::ok) set(t, x);
    return r;
  };
  return k;
}

/// A string; `check` returns what is wrong with a value ("" if nothing).
template <class Target>
Key<Target> text(std::string name, Field<Target, std::string> f,
                 std::type_identity_t<Default<std::string>> d, std::string doc,
                 std::function<std::string(const std::string&)> check = {}) {
  auto k = detail::declare<Target, std::string>(
      std::move(name), KeyType::string, Range::any(), f, d, std::move(doc),
      [](const std::string& s) { return toml_string(s); });
  k.read = [set = f.set, check](Target& t, const Value& v, const std::string& path,
                                Diagnostics& diag) {
    std::string x;
    Read r = detail::read_string(v, path, x, diag);
    if (r == Read::ok && check) {
      if (const std::string what = check(x); !what.empty()) {
        diag.error(path, v, what);
        r = Read::bad;
      }
    }
    if (r == Read::ok) set(t, x);
    return r;
  };
  return k;
}

/// One word of an enumeration as a choice key accepts it.
template <class Enum>
struct Option {
  std::string word;
  Enum value;
  std::string doc;
};

/// One of a few words, each standing for a value of `Enum`.
template <class Target, class Enum>
Key<Target> choice(std::string name, Field<Target, Enum> f,
                   std::type_identity_t<Default<Enum>> d, std::vector<Option<Enum>> options,
                   std::string doc) {
  const auto word_of = [options](const Enum& e) {
    for (const auto& o : options)
      if (o.value == e) return o.word;
    return std::string("?");
  };
  auto k = detail::declare<Target, Enum>(
      std::move(name), KeyType::choice, Range::any(), f, d, std::move(doc),
      [word_of](const Enum& e) { return toml_string(word_of(e)); });
  for (const auto& o : options) k.choices.push_back({o.word, o.doc});
  k.read = [set = f.set, options, choices = k.choices](
               Target& t, const Value& v, const std::string& path, Diagnostics& diag) {
    std::size_t i = 0;
    const Read r = detail::read_choice(v, path, choices, i, diag);
    if (r == Read::ok) set(t, options[i].value);
    return r;
  };
  k.word = [get = f.get, word_of](const Target& t) { return word_of(get(t)); };
  return k;
}

/// Three numbers [x, y, z], each in `range`.
template <class Target>
Key<Target> vector3(std::string name, Field<Target, Eigen::Vector3d> f,
                    std::type_identity_t<Default<Eigen::Vector3d>> d, Range range,
                    std::string doc) {
  auto k = detail::declare<Target, Eigen::Vector3d>(std::move(name), KeyType::vector3, range, f,
                                                    d, std::move(doc), toml_vector);
  k.read = detail::ranged_reader<Target>(f.set, range, &detail::read_vector3);
  return k;
}

// ---------------------------------------------------------------------------
// Tables and the whole schema.

/// A table as users and messages see it, whatever struct it fills.
struct TableInfo {
  std::string name;
  std::string doc;
  bool array = false;  ///< [[name]]: a list of tables
  std::vector<const KeyInfo*> keys;

  [[nodiscard]] const KeyInfo* find(std::string_view key) const;
};

/// The keys of one table, filling a `Target` (for [[name]], one per entry).
template <class Target>
struct Table {
  std::string name;
  std::string doc;
  bool array = false;
  std::vector<Key<Target>> keys;

  [[nodiscard]] const Key<Target>* find(std::string_view key) const {
    for (const auto& k : keys)
      if (k.name == key) return &k;
    return nullptr;
  }
  /// Points into `keys`: the Table must outlive it.
  [[nodiscard]] TableInfo info() const {
    TableInfo t{name, doc, array, {}};
    for (const auto& k : keys) t.keys.push_back(&k);
    return t;
  }
};

/// A word users write for a key (a symbol from the papers), compared
/// ignoring case: "Ca" -> objects.capillary_number.
struct Alias {
  std::string word;
  std::string table;
  std::string key;
};

/// Every table of a file, in the order they are printed and documented.
struct Schema {
  std::vector<TableInfo> tables;
  std::vector<Alias> aliases;

  [[nodiscard]] const TableInfo* find(std::string_view table) const;
  [[nodiscard]] const KeyInfo* find(std::string_view table, std::string_view key) const;
};

// ---------------------------------------------------------------------------
// Reading.

/// What reading one table found, key by key.
class TableRead {
 public:
  TableRead() = default;
  TableRead(const toml::table* table, std::string prefix)
      : table_(table), prefix_(std::move(prefix)) {}

  [[nodiscard]] Read status(std::string_view key) const {
    const auto it = status_.find(std::string(key));
    return it == status_.end() ? Read::absent : it->second;
  }
  /// The value as given, or nullptr.
  [[nodiscard]] const Value* value(std::string_view key) const;
  /// How the key is written in messages: "mesh.far_size", "objects[2].radius".
  [[nodiscard]] std::string path(std::string_view key) const;
  [[nodiscard]] const std::string& prefix() const { return prefix_; }
  void set_status(const std::string& key, Read r) { status_[key] = r; }

 private:
  const toml::table* table_ = nullptr;
  std::string prefix_;
  std::map<std::string, Read> status_;
};

/// The entries of a table in file order, so that messages follow the file.
std::vector<std::pair<std::string, const Value*>> in_file_order(const toml::table& table);

/// Reports each top-level entry that is no table of the schema, with a suggestion.
void check_top_level(const toml::table& root, const Schema& schema, Diagnostics& diag);

/// Reports each key of `table` (the entries of schema table `name`, written
/// `prefix` in messages) that the schema does not know, with a suggestion.
void check_unknown_keys(const Schema& schema, const std::string& name, const toml::table& table,
                        const std::string& prefix, Diagnostics& diag);

/// The table [name] of a file, or an empty one when the file omits it (every
/// key then takes its default); a value that is not a table is reported.
const toml::table& section(const toml::table& root, const TableInfo& table, Diagnostics& diag);

/// The entries of [[name]] in file order (none if absent); anything but a
/// list of tables is reported.
std::vector<const toml::table*> array_sections(const toml::table& root, const TableInfo& table,
                                               Diagnostics& diag);

/// "must be one of ... / only for ..." for a key given where it does not
/// apply, and "missing: ..." for a required one not given.
std::string not_applicable_message(const TableInfo& table, const KeyInfo& key,
                                   const std::string& selector_word);
std::string missing_message(const KeyInfo& key, const std::string& selector_word);

/// Reads `table` into `target` key by key, in declaration order: unknown
/// keys, each value's type and range, keys given where they do not apply,
/// required keys missing; every declared default of a key that applies is
/// stored first. Keys that depend on a bad selector are skipped (their
/// meaning is unknown, and a follow-up message would only confuse).
template <class Target>
TableRead read_table(const Table<Target>& declared, const toml::table& table,
                     const std::string& prefix, const Schema& schema, Target& target,
                     Diagnostics& diag) {
  check_unknown_keys(schema, declared.name, table, prefix, diag);
  TableRead result(&table, prefix);
  const TableInfo info = declared.info();
  for (const auto& key : declared.keys) {
    const Value* v = result.value(key.name);
    std::string selector_word;
    if (!key.condition.selector.empty()) {
      const Key<Target>* selector = declared.find(key.condition.selector);
      if (!selector || result.status(selector->name) == Read::bad) {
        result.set_status(key.name, v ? Read::bad : Read::absent);
        continue;
      }
      selector_word = selector->word(target);
      const auto& when = key.condition.values;
      if (std::find(when.begin(), when.end(), selector_word) == when.end()) {
        if (v) diag.error(result.path(key.name), *v, not_applicable_message(info, key, selector_word));
        result.set_status(key.name, v ? Read::bad : Read::absent);
        continue;
      }
    }
    if (key.apply_default) key.apply_default(target);
    if (!v) {
      if (key.required)
        diag.error(result.path(key.name) + ": " + missing_message(key, selector_word));
      result.set_status(key.name, Read::absent);
      continue;
    }
    result.set_status(key.name, key.read(target, *v, result.path(key.name), diag));
  }
  return result;
}

// ---------------------------------------------------------------------------
// Writing.

/// Whether `key` applies to `target` (its condition's selector has one of its values).
template <class Target>
bool applies(const Table<Target>& declared, const Key<Target>& key, const Target& target) {
  if (key.condition.selector.empty()) return true;
  const Key<Target>* selector = declared.find(key.condition.selector);
  if (!selector) return false;
  const auto& when = key.condition.values;
  return std::find(when.begin(), when.end(), selector->word(target)) != when.end();
}

/// The table as TOML: its header, then every key that applies, with its value
/// and comment. Reading the text back gives the same values.
template <class Target>
std::string write_table(const Table<Target>& declared, const Target& target) {
  std::string s = declared.array ? "[[" + declared.name + "]]\n" : "[" + declared.name + "]\n";
  for (const auto& key : declared.keys) {
    if (!applies(declared, key, target)) continue;
    const auto value = key.print(target);
    if (!value) continue;
    s += key.name + " = " + *value;
    if (key.comment)
      if (const std::string note = key.comment(target); !note.empty()) s += "  # " + note;
    s += "\n";
  }
  return s;
}

/// The key reference of one table as Markdown: a heading, the table's doc,
/// and one row per key (value, default, meaning, when it applies).
std::string markdown(const TableInfo& table);

}  // namespace softflow::io::schema
