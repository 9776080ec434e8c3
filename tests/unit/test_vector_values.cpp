// la/vector_values: what crosses ranks. A whole vector (counted), this
// rank's part (never leaves it), chosen entries (one scatter), one entry
// (one reduction), and the first entry that is not finite.
//
// Runs on 1 rank and, as part of mpi_fem_layer, on 2.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/common/error.hpp"
#include "softflow/la/vector_values.hpp"

using namespace softflow;

namespace {

constexpr PetscInt kSize = 11;  // odd: the ranks own different counts

/// v_i = 10 i + 1 on every owned entry.
la::Vector numbered_vector() {
  const PetscInt size = la::mpi_size(), rank = la::mpi_rank();
  const PetscInt begin = rank * kSize / size, end = (rank + 1) * kSize / size;
  la::Vector v = la::make_vector(end - begin, kSize);
  std::vector<double> values;
  for (PetscInt i = begin; i < end; ++i) values.push_back(10.0 * static_cast<double>(i) + 1.0);
  la::set_owned_values(v.get(), values);
  return v;
}

}  // namespace

TEST(VectorValues, GatherToAllReturnsEveryEntryAndIsCounted) {
  const la::Vector v = numbered_vector();
  const long before = la::full_gathers();
  const auto all = la::gather_to_all(v.get());
  EXPECT_EQ(la::full_gathers(), before + 1);
  ASSERT_EQ(static_cast<PetscInt>(all.size()), kSize);
  for (PetscInt i = 0; i < kSize; ++i) EXPECT_EQ(all[i], 10.0 * static_cast<double>(i) + 1.0);
}

TEST(VectorValues, OwnedValuesAndScatterFromAllRoundTrip) {
  const la::Vector v = numbered_vector();
  const auto owned = la::owned_values(v.get());
  la::Vector w = la::make_vector(static_cast<PetscInt>(owned.size()), kSize);
  la::scatter_from_all(w.get(), la::gather_to_all(v.get()));
  EXPECT_EQ(la::owned_values(w.get()), owned);
  EXPECT_THROW(la::set_owned_values(w.get(), std::vector<double>(owned.size() + 1)), SolverError);
  EXPECT_THROW(la::scatter_from_all(w.get(), std::vector<double>(kSize - 1)), SolverError);
}

TEST(VectorValues, SelectedEntriesCopyOnlyWhatEachRankAsksFor) {
  la::Vector v = numbered_vector();
  // Each rank asks for other entries, with repeats and in any order; the
  // last entry lives on the last rank, the first on the first.
  const PetscInt rank = la::mpi_rank();
  const std::vector<PetscInt> wanted{kSize - 1, rank, 0, kSize - 1};
  const long before = la::full_gathers();
  la::SelectedEntries entries(v.get(), wanted);
  entries.read(v.get());
  EXPECT_EQ(la::full_gathers(), before);
  EXPECT_EQ(entries.indices().size(), rank == 0 ? 2u : 3u);
  for (PetscInt i : wanted) EXPECT_EQ(entries[i], 10.0 * static_cast<double>(i) + 1.0);
  EXPECT_THROW((void)entries[kSize / 2 + 1], SolverError);  // not asked for

  VecScale(v.get(), 2.0);  // a new read sees new values
  entries.read(v.get());
  EXPECT_EQ(entries[kSize - 1], 2.0 * (10.0 * (kSize - 1) + 1.0));
  EXPECT_THROW(la::SelectedEntries(v.get(), {kSize}), SolverError);
}

TEST(VectorValues, EntryIsReadOnEveryRankWhoeverOwnsIt) {
  const la::Vector v = numbered_vector();
  for (PetscInt i = 0; i < kSize; ++i) EXPECT_EQ(la::entry(v.get(), i), 10.0 * static_cast<double>(i) + 1.0);
}

TEST(VectorValues, FirstNonFiniteFindsTheLowestBadEntryOnAnyRank) {
  la::Vector v = numbered_vector();
  EXPECT_FALSE(la::first_non_finite(v.get()).has_value());
  // Bad entries at 9 and 4 (on different ranks with 2): 4 is reported, with its value.
  for (const auto& [i, value] : {std::pair<PetscInt, double>{9, std::numeric_limits<double>::infinity()},
                                 {4, std::nan("")}})
    VecSetValue(v.get(), i, value, INSERT_VALUES);
  VecAssemblyBegin(v.get());
  VecAssemblyEnd(v.get());
  const auto bad = la::first_non_finite(v.get());
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(bad->first, 4);
  EXPECT_TRUE(std::isnan(bad->second));
}
