#include "softflow/la/vector_values.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow::la {

namespace {
std::atomic<long> full_gather_count{0};
}  // namespace

std::vector<double> gather_to_all(Vec v) {
  ++full_gather_count;
  Owned<VecScatter, VecScatterDestroy> scatter;
  Vector all;
  check(VecScatterCreateToAll(v, scatter.out(), all.out()), "VecScatterCreateToAll");
  check(VecScatterBegin(scatter.get(), v, all.get(), INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterBegin");
  check(VecScatterEnd(scatter.get(), v, all.get(), INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterEnd");
  PetscInt n = 0;
  check(VecGetSize(all.get(), &n), "VecGetSize");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(all.get(), &a), "VecGetArrayRead");
  std::vector<double> out(a, a + n);
  check(VecRestoreArrayRead(all.get(), &a), "VecRestoreArrayRead");
  return out;
}

long full_gathers() { return full_gather_count.load(); }

void scatter_from_all(Vec v, std::span<const double> all) {
  PetscInt n = 0, begin = 0, end = 0;
  check(VecGetSize(v, &n), "VecGetSize");
  if (static_cast<PetscInt>(all.size()) != n)
    throw SolverError(fmt::format("scatter_from_all: {} values for a vector of {}", all.size(), n));
  check(VecGetOwnershipRange(v, &begin, &end), "VecGetOwnershipRange");
  PetscScalar* a = nullptr;
  check(VecGetArray(v, &a), "VecGetArray");
  std::copy(all.begin() + begin, all.begin() + end, a);
  check(VecRestoreArray(v, &a), "VecRestoreArray");
}

std::vector<double> owned_values(Vec v) {
  PetscInt n = 0;
  check(VecGetLocalSize(v, &n), "VecGetLocalSize");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(v, &a), "VecGetArrayRead");
  std::vector<double> out(a, a + n);
  check(VecRestoreArrayRead(v, &a), "VecRestoreArrayRead");
  return out;
}

void set_owned_values(Vec v, std::span<const double> values) {
  PetscInt n = 0;
  check(VecGetLocalSize(v, &n), "VecGetLocalSize");
  if (static_cast<PetscInt>(values.size()) != n)
    throw SolverError(fmt::format("set_owned_values: {} values for {} entries on this rank",
                                  values.size(), n));
  PetscScalar* a = nullptr;
  check(VecGetArray(v, &a), "VecGetArray");
  std::copy(values.begin(), values.end(), a);
  check(VecRestoreArray(v, &a), "VecRestoreArray");
}

void save_vector(StateRecord& record, const std::string& key, Vec v, int columns) {
  record.set(key,
             record.scope() == StateRecord::Scope::whole_run ? gather_to_all(v) : owned_values(v),
             columns);
}

void restore_vector(const StateRecord& record, const std::string& key, Vec v,
                    const std::string& what, int columns) {
  const auto& values = record.get_array(key, columns);
  PetscInt n = 0;
  const bool whole = record.scope() == StateRecord::Scope::whole_run;
  check(whole ? VecGetSize(v, &n) : VecGetLocalSize(v, &n), "VecGetSize");
  if (static_cast<PetscInt>(values.size()) != n)
    throw InputError(fmt::format("the saved {} has {} values, {} expected", what, values.size(), n));
  if (whole)
    scatter_from_all(v, values);
  else
    set_owned_values(v, values);
}

SelectedEntries::SelectedEntries(Vec layout, std::vector<PetscInt> indices)
    : indices_(std::move(indices)) {
  std::sort(indices_.begin(), indices_.end());
  indices_.erase(std::unique(indices_.begin(), indices_.end()), indices_.end());
  PetscInt n = 0;
  check(VecGetSize(layout, &n), "VecGetSize");
  if (!indices_.empty() && (indices_.front() < 0 || indices_.back() >= n))
    throw SolverError(fmt::format("SelectedEntries: index outside [0, {})", n));
  const auto count = static_cast<PetscInt>(indices_.size());
  check(VecCreateSeq(PETSC_COMM_SELF, count, local_.out()), "VecCreateSeq");
  IndexSet from, to;
  check(ISCreateGeneral(PETSC_COMM_SELF, count, indices_.data(), PETSC_COPY_VALUES, from.out()),
        "ISCreateGeneral");
  check(ISCreateStride(PETSC_COMM_SELF, count, 0, 1, to.out()), "ISCreateStride");
  check(VecScatterCreate(layout, from.get(), local_.get(), to.get(), scatter_.out()),
        "VecScatterCreate");
  values_.assign(indices_.size(), std::numeric_limits<double>::quiet_NaN());
}

void SelectedEntries::read(Vec v) {
  if (!scatter_) throw SolverError("SelectedEntries: read() before construction");
  check(VecScatterBegin(scatter_.get(), v, local_.get(), INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterBegin");
  check(VecScatterEnd(scatter_.get(), v, local_.get(), INSERT_VALUES, SCATTER_FORWARD),
        "VecScatterEnd");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(local_.get(), &a), "VecGetArrayRead");
  std::copy(a, a + values_.size(), values_.begin());
  check(VecRestoreArrayRead(local_.get(), &a), "VecRestoreArrayRead");
}

double SelectedEntries::operator[](PetscInt i) const {
  const auto it = std::lower_bound(indices_.begin(), indices_.end(), i);
  if (it == indices_.end() || *it != i)
    throw SolverError(fmt::format("SelectedEntries: entry {} was not selected", i));
  return values_[static_cast<std::size_t>(it - indices_.begin())];
}

namespace {
MPI_Comm communicator(Vec v) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  check(PetscObjectGetComm(reinterpret_cast<PetscObject>(v), &comm), "PetscObjectGetComm");
  return comm;
}
}  // namespace

double entry(Vec v, PetscInt i) {
  PetscInt begin = 0, end = 0;
  check(VecGetOwnershipRange(v, &begin, &end), "VecGetOwnershipRange");
  double value = 0.0;  // a NaN or Inf of the owner survives the sum
  if (i >= begin && i < end) {
    const PetscScalar* a = nullptr;
    check(VecGetArrayRead(v, &a), "VecGetArrayRead");
    value = a[i - begin];
    check(VecRestoreArrayRead(v, &a), "VecRestoreArrayRead");
  }
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_SUM, communicator(v));
  return value;
}

std::optional<std::pair<PetscInt, double>> first_non_finite(Vec v) {
  PetscInt begin = 0, end = 0;
  check(VecGetOwnershipRange(v, &begin, &end), "VecGetOwnershipRange");
  const PetscScalar* a = nullptr;
  check(VecGetArrayRead(v, &a), "VecGetArrayRead");
  PetscInt local = std::numeric_limits<PetscInt>::max();
  for (PetscInt i = begin; i < end; ++i)
    if (!std::isfinite(a[i - begin])) {
      local = i;
      break;
    }
  check(VecRestoreArrayRead(v, &a), "VecRestoreArrayRead");
  PetscInt first = 0;
  MPI_Allreduce(&local, &first, 1, MPIU_INT, MPI_MIN, communicator(v));
  if (first == std::numeric_limits<PetscInt>::max()) return std::nullopt;
  return std::pair{first, entry(v, first)};
}

}  // namespace softflow::la
