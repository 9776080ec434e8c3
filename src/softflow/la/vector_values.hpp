// Moving values of distributed vectors between ranks: the whole vector (for
// output and checkpoints, counted), or only the entries a stage needs.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "softflow/common/state.hpp"
#include "softflow/la/petsc.hpp"

namespace softflow::la {

/// Every entry of a distributed vector, on every rank. Collective. For
/// output, checkpoints and small problems only: each call is counted
/// (full_gathers()), so that a test can check that no stage of a time step
/// needs one.
std::vector<double> gather_to_all(Vec v);

/// How many times gather_to_all has run in this process.
[[nodiscard]] long full_gathers();

/// Sets this rank's entries of `v` from a full vector (as gather_to_all returns).
void scatter_from_all(Vec v, std::span<const double> all);

/// This rank's entries of `v` (its ownership range), and setting them back:
/// a copy of a vector's state that never leaves the rank.
std::vector<double> owned_values(Vec v);
void set_owned_values(Vec v, std::span<const double> values);

/// A distributed vector as a record entry: every entry (gathered, in global
/// order) in a whole-run record, this rank's entries in a this-rank one
/// (StateRecord::Scope). Collective for a whole-run record.
void save_vector(StateRecord& record, const std::string& key, Vec v, int columns = 1);
/// Reads it back into `v` (laid out as when saved, for a this-rank record);
/// throws InputError naming `what` if the sizes differ.
void restore_vector(const StateRecord& record, const std::string& key, Vec v,
                    const std::string& what, int columns = 1);

/// The entries of chosen global indices of distributed vectors of one
/// layout, copied to this rank: e.g. the interface velocities the trackers
/// need out of a Stokes solution, instead of the whole solution. Each rank
/// asks for its own list (it may be empty); the copy is one PETSc scatter.
class SelectedEntries {
 public:
  SelectedEntries() = default;
  /// `layout`: any vector laid out as those to read. Collective.
  SelectedEntries(Vec layout, std::vector<PetscInt> indices);

  /// Copies the entries out of `v`. Collective.
  void read(Vec v);
  /// The value of global index `i` as of the last read(); throws if `i` was not selected.
  [[nodiscard]] double operator[](PetscInt i) const;
  [[nodiscard]] const std::vector<PetscInt>& indices() const { return indices_; }
  [[nodiscard]] bool empty() const { return indices_.empty(); }

 private:
  std::vector<PetscInt> indices_;  // sorted, unique
  std::vector<double> values_;
  Vector local_;
  Owned<VecScatter, VecScatterDestroy> scatter_;
};

/// Entry `i` of a distributed vector, on every rank. Collective (one
/// reduction: its owner contributes it, the others zero).
double entry(Vec v, PetscInt i);

/// The lowest global index whose entry is not finite, and that entry, or
/// nothing if every entry is finite. Collective (two reductions).
std::optional<std::pair<PetscInt, double>> first_non_finite(Vec v);

}  // namespace softflow::la
