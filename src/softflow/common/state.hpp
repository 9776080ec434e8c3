// The state of a run as named entries, and the registry of the parts that own them.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace softflow {

/// A run's state as named, typed entries: what a checkpoint stores and a
/// restart reads back. Keys are paths ("stokes/refactor_next",
/// "objects/1/x"); values are integers, reals, or real arrays of
/// `columns` columns (points: 3). No file format here: io::Checkpoint
/// writes every entry, whatever its owner, without per-entry code.
class StateRecord {
 public:
  /// Whose values the record holds. A checkpoint's are the whole run's:
  /// distributed data is gathered, so a run on any number of ranks reads it
  /// back. A snapshot that never leaves the process (a step taken back) holds
  /// this rank's own part of distributed data: nothing crosses ranks.
  enum class Scope { whole_run, this_rank };
  explicit StateRecord(Scope scope = Scope::whole_run) : scope_(scope) {}
  [[nodiscard]] Scope scope() const { return scope_; }

  enum class Kind { integer, real, array };
  struct Entry {
    Kind kind = Kind::real;
    std::vector<double> values;  ///< integers are stored exactly (|n| < 2^53)
    int columns = 1;
  };

  void set(const std::string& key, int value);
  void set(const std::string& key, bool value) { set(key, value ? 1 : 0); }
  void set(const std::string& key, double value);
  void set(const std::string& key, std::vector<double> values, int columns = 1);
  void set(const std::string& key, const std::vector<Eigen::Vector3d>& points);
  /// Stores an entry as read from a file.
  void insert(const std::string& key, Entry entry) { entries_[key] = std::move(entry); }

  [[nodiscard]] bool contains(const std::string& key) const { return entries_.count(key) > 0; }
  /// Each getter throws InputError naming the key if it is missing or of
  /// another kind or shape (a checkpoint of another build, or damaged).
  [[nodiscard]] int get_int(const std::string& key) const;
  [[nodiscard]] bool get_bool(const std::string& key) const { return get_int(key) != 0; }
  [[nodiscard]] double get_double(const std::string& key) const;
  [[nodiscard]] const std::vector<double>& get_array(const std::string& key, int columns = 1) const;
  [[nodiscard]] std::vector<Eigen::Vector3d> get_points(const std::string& key) const;

  [[nodiscard]] const std::map<std::string, Entry>& entries() const { return entries_; }

 private:
  [[nodiscard]] const Entry& find(const std::string& key, Kind kind) const;
  std::map<std::string, Entry> entries_;
  Scope scope_ = Scope::whole_run;
};

/// One part of a run that saves and restores its own state under a prefix
/// ("stokes/", "objects/1/", "fields/tracer/").
struct StatePart {
  std::string name;
  std::function<void(StateRecord&, const std::string& prefix)> save;
  std::function<void(const StateRecord&, const std::string& prefix)> restore;
};

/// The parts of a run whose state a checkpoint carries, in the order they
/// are restored. A new field or history registers itself here: no edits
/// to the checkpoint format, the time loop or the restart code.
class StateRegistry {
 public:
  /// Adds a part; its entries live under "<name>/". Names are unique.
  void add(StatePart part);
  void save(StateRecord& record) const;
  void restore(const StateRecord& record) const;
  /// The same for every part but those named in `skip`.
  void save(StateRecord& record, const std::vector<std::string>& skip) const;
  void restore(const StateRecord& record, const std::vector<std::string>& skip) const;
  [[nodiscard]] std::vector<std::string> names() const;

 private:
  std::vector<StatePart> parts_;
};

}  // namespace softflow
