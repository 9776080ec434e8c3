// DeterministicHeapScope: addresses that depend only on the scope's own
// allocations, blocks that outlive their scope, other threads untouched.
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "softflow/common/deterministic_heap.hpp"

using softflow::DeterministicHeapScope;

namespace {

// A mixed sequence of allocations and frees, like a mesher's: returns the
// offset of every allocation from the first one.
std::vector<std::ptrdiff_t> allocation_offsets() {
  std::vector<std::ptrdiff_t> offsets;
  std::vector<std::unique_ptr<char[]>> live;
  std::mt19937 rng(7);
  const char* first = nullptr;
  for (int i = 0; i < 2000; ++i) {
    const std::size_t bytes = 1 + rng() % 300;
    live.push_back(std::make_unique<char[]>(bytes));
    if (!first) first = live.back().get();
    offsets.push_back(live.back().get() - first);
    if (rng() % 3 == 0) live.erase(live.begin() + static_cast<std::ptrdiff_t>(rng() % live.size()));
  }
  return offsets;
}

// Leaves the ordinary heap in a different state each time it is called.
std::vector<std::unique_ptr<std::string>> scramble_heap(int seed) {
  std::vector<std::unique_ptr<std::string>> kept;
  std::mt19937 rng(seed);
  for (int i = 0; i < 500; ++i) {
    auto s = std::make_unique<std::string>(rng() % 200, 'x');
    if (rng() % 2) kept.push_back(std::move(s));
  }
  return kept;
}

}  // namespace

TEST(DeterministicHeap, AddressesInsideAScopeDoNotDependOnTheHeapBefore) {
  std::vector<std::vector<std::ptrdiff_t>> runs;
  std::vector<std::vector<std::unique_ptr<std::string>>> scrambles;
  for (int seed : {1, 2, 3}) {
    scrambles.push_back(scramble_heap(seed));
    DeterministicHeapScope scope;
    runs.push_back(allocation_offsets());
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(runs[0], runs[2]);

  // Outside a scope the same sequence follows the heap's history: the test
  // above would tell the scope from no scope.
  std::vector<std::vector<std::ptrdiff_t>> ordinary;
  for (int seed : {4, 5, 6}) {
    scrambles.push_back(scramble_heap(seed));
    ordinary.push_back(allocation_offsets());
  }
  EXPECT_FALSE(ordinary[0] == ordinary[1] && ordinary[1] == ordinary[2]);
}

TEST(DeterministicHeap, SmallBlocksComeFromTheScopeLargeOnesAndOtherThreadsFromMalloc) {
  std::unique_ptr<int> before = std::make_unique<int>(1);
  EXPECT_FALSE(DeterministicHeapScope::owns(before.get()));
  DeterministicHeapScope scope;
  auto small = std::make_unique<char[]>(DeterministicHeapScope::kLargestSmallBlock);
  auto large = std::make_unique<char[]>(DeterministicHeapScope::kLargestSmallBlock + 1);
  EXPECT_TRUE(DeterministicHeapScope::owns(small.get()));
  EXPECT_FALSE(DeterministicHeapScope::owns(large.get()));
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(small.get()) % 16, 0u);  // new's alignment
  bool other_thread_owned = true;
  std::thread([&] { other_thread_owned = DeterministicHeapScope::owns(std::make_unique<int>(2).get()); }).join();
  EXPECT_FALSE(other_thread_owned);
  {
    DeterministicHeapScope nested;  // joins the open scope
    auto inner = std::make_unique<int>(3);
    EXPECT_TRUE(DeterministicHeapScope::owns(inner.get()));
  }
  auto after_nested = std::make_unique<int>(4);
  EXPECT_TRUE(DeterministicHeapScope::owns(after_nested.get()));
}

TEST(DeterministicHeap, BlocksOutliveTheirScopeAndTheirPagesGoBackWhenFreed) {
  std::vector<std::unique_ptr<std::vector<double>>> survivors;
  {
    DeterministicHeapScope scope;
    for (int i = 0; i < 20000; ++i) {
      survivors.push_back(std::make_unique<std::vector<double>>(8, double(i)));  // 64-byte arrays
      if (i % 2) survivors.pop_back();
    }
  }
  ASSERT_EQ(survivors.size(), 10000u);
  const auto held = DeterministicHeapScope::usage().resident_pages;
  EXPECT_GT(held, 0u);
  // Freed from another thread, after the scope closed, their contents intact.
  std::thread([&] {
    for (std::size_t i = 0; i < survivors.size(); ++i) {
      EXPECT_EQ((*survivors[i])[7], double(2 * i));
      survivors[i].reset();
    }
  }).join();
  EXPECT_LT(DeterministicHeapScope::usage().resident_pages, held);
}
