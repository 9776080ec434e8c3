// A heap scope whose small allocations land at addresses that depend only on
// what is allocated inside the scope, not on what the process did before.
//
// Why: gmsh 4.8's high-order optimiser keeps elements in containers ordered
// by pointer, so the order in which it relaxes them, and hence the last bits
// of the curved nodes it returns, followed the process's earlier allocations:
// the same case meshed to different fingerprints depending on the length of
// the case's path, on whether stdout was a terminal, or on the environment
// (measured: 1 to 4 of 4 paths differed for an ellipsoid). Inside a
// DeterministicHeapScope every `operator new` of up to kLargestSmallBlock
// bytes on the scope's thread is served from a fresh region of a private
// reservation by a size-class allocator, so the relative order of those
// addresses is a function of the allocation sequence alone and gmsh repeats
// itself to the bit in every process, `softflow mesh` or `run` alike.
//
// Larger blocks (arrays, whose addresses nobody orders) and allocations on
// other threads go to malloc as usual. A block may outlive its scope and be
// freed from any thread: memory of a closed scope is never handed out again,
// and its pages are returned to the system as soon as no live block is left
// on them.
#pragma once

#include <cstddef>

namespace softflow {

class DeterministicHeapScope {
 public:
  /// Blocks up to this size (bytes) come from the scope's region.
  static constexpr std::size_t kLargestSmallBlock = 4096;

  /// Opens a scope on the calling thread; a scope opened inside another on
  /// the same thread joins it.
  DeterministicHeapScope();
  ~DeterministicHeapScope();
  DeterministicHeapScope(const DeterministicHeapScope&) = delete;
  DeterministicHeapScope& operator=(const DeterministicHeapScope&) = delete;

  /// Bytes of the private reservation handed out since the process started
  /// (all scopes), and the pages of closed scopes that live blocks still hold.
  struct Usage {
    std::size_t reserved_used = 0;
    std::size_t resident_pages = 0;
  };
  [[nodiscard]] static Usage usage();

  /// True when `p` was served by a scope's region.
  [[nodiscard]] static bool owns(const void* p);

 private:
  bool joined_ = false;
};

}  // namespace softflow
