#include "softflow/common/deterministic_heap.hpp"

#include <sys/mman.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <new>

namespace softflow {
namespace {

// Address space only: pages are committed when touched and given back when
// no live block is left on them (MAP_NORESERVE; 256 GiB of the 128 TiB a
// process may map). A scope that exhausts it falls back to malloc.
constexpr std::size_t kReservation = std::size_t{256} << 30;
constexpr std::size_t kPage = 4096;
constexpr std::size_t kGranule = 16;  // __STDCPP_DEFAULT_NEW_ALIGNMENT__
constexpr std::size_t kHeader = 16;   // keeps the payload 16-byte aligned
constexpr std::size_t kClasses = (DeterministicHeapScope::kLargestSmallBlock + kHeader) / kGranule + 1;

struct BlockHeader {
  std::uint32_t bytes;  // whole block, header included: the region is walkable
  std::uint32_t scope;  // the scope that allocated it
  std::uint32_t free;   // 1 once freed (on the free list or freed by another thread)
  std::uint32_t unused;
};
static_assert(sizeof(BlockHeader) == kHeader);

// All state is constant-initialised: operator new may run before any
// dynamic initialiser. While a scope is open, its thread alone allocates
// from the region and keeps the free lists, without a lock (the hot path of
// gmsh's meshing); other threads only flag blocks they free, under the mutex.
// Live blocks are counted per page when the scope closes, to give back
// pages as the closed scope's survivors die.
struct Heap {
  std::mutex mutex;        // guards the page counts, scope changes and frees by other threads
  std::mutex scope_mutex;  // one scope at a time in the process
  std::atomic<char*> begin{nullptr};
  std::atomic<char*> end{nullptr};
  std::uint32_t* page_live = nullptr;  // live blocks touching each page of closed scopes
  char* bump = nullptr;
  char* scope_begin = nullptr;
  std::atomic<std::uint32_t> open_scope{0};  // 0: none open
  std::uint32_t next_scope = 1;
  std::array<void*, kClasses> free_lists{};  // the open scope's, owned by its thread
};

constinit Heap heap;
constinit thread_local bool in_scope = false;  // this thread owns the open scope

BlockHeader& header_of(char* block) { return *reinterpret_cast<BlockHeader*>(block); }

std::size_t page_of(const char* p) { return static_cast<std::size_t>(p - heap.begin.load()) / kPage; }

// Adds `delta` to the live count of every page that [first, last] touches.
void count_pages(const char* first, const char* last, std::int32_t delta) {
  for (std::size_t page = page_of(first); page <= page_of(last); ++page)
    heap.page_live[page] = static_cast<std::uint32_t>(static_cast<std::int64_t>(heap.page_live[page]) + delta);
}

// Gives back to the system every page of [first_page, end_page) no live block touches.
void release_empty_pages(std::size_t first_page, std::size_t end_page) {
  char* base = heap.begin.load();
  std::size_t run = first_page;
  for (std::size_t page = first_page; page <= end_page; ++page) {
    const bool empty = page < end_page && heap.page_live[page] == 0;
    if (empty) continue;
    if (page > run) madvise(base + run * kPage, (page - run) * kPage, MADV_DONTNEED);
    run = page + 1;
  }
}

bool reserve() {
  if (heap.begin.load()) return true;
  const std::size_t count_bytes = kReservation / kPage * sizeof(std::uint32_t);
  void* region = mmap(nullptr, kReservation, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  void* counts = mmap(nullptr, count_bytes, PROT_READ | PROT_WRITE,
                      MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  if (region == MAP_FAILED || counts == MAP_FAILED) {
    if (region != MAP_FAILED) munmap(region, kReservation);
    if (counts != MAP_FAILED) munmap(counts, count_bytes);
    return false;
  }
  heap.page_live = static_cast<std::uint32_t*>(counts);
  heap.bump = static_cast<char*>(region);
  heap.end.store(static_cast<char*>(region) + kReservation);
  heap.begin.store(static_cast<char*>(region));
  return true;
}

// On the scope's thread only.
void* allocate_small(std::size_t n) {
  const std::size_t bytes = (n + kHeader + kGranule - 1) / kGranule * kGranule;
  const std::size_t size_class = bytes / kGranule;
  char* block = static_cast<char*>(heap.free_lists[size_class]);
  if (block) {
    heap.free_lists[size_class] = *reinterpret_cast<void**>(block + kHeader);
    header_of(block).free = 0;
    return block + kHeader;
  }
  const std::uint32_t scope = heap.open_scope.load(std::memory_order_relaxed);
  if (scope == 0 || bytes > static_cast<std::size_t>(heap.end.load() - heap.bump)) return nullptr;
  block = heap.bump;
  heap.bump += bytes;
  header_of(block) = {static_cast<std::uint32_t>(bytes), scope, 0, 0};
  return block + kHeader;
}

void free_small(void* p) {
  char* block = static_cast<char*>(p) - kHeader;
  BlockHeader& header = header_of(block);
  if (in_scope && header.scope == heap.open_scope.load(std::memory_order_relaxed)) {
    header.free = 1;  // reused by this scope, last in first out
    *reinterpret_cast<void**>(p) = heap.free_lists[header.bytes / kGranule];
    heap.free_lists[header.bytes / kGranule] = block;
    return;
  }
  std::lock_guard lock(heap.mutex);
  header.free = 1;
  // Another thread's block of the open scope: counted when the scope closes.
  if (header.scope == heap.open_scope.load()) return;
  // A closed scope's memory is never handed out again: its pages go back to
  // the system once empty.
  count_pages(block, block + header.bytes - 1, -1);
  release_empty_pages(page_of(block), page_of(block + header.bytes - 1) + 1);
}

void* allocate(std::size_t n) {
  if (in_scope && n <= DeterministicHeapScope::kLargestSmallBlock)
    if (void* p = allocate_small(n)) return p;
  return std::malloc(n == 0 ? 1 : n);
}

void* allocate_or_throw(std::size_t n) {
  for (;;) {
    if (void* p = allocate(n)) return p;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

void release(void* p) noexcept {
  if (!p) return;
  const char* c = static_cast<const char*>(p);
  if (c >= heap.begin.load(std::memory_order_relaxed) && c < heap.end.load(std::memory_order_relaxed))
    free_small(p);
  else
    std::free(p);
}

}  // namespace

DeterministicHeapScope::DeterministicHeapScope() {
  if (in_scope) {
    joined_ = true;
    return;
  }
  heap.scope_mutex.lock();
  {
    std::lock_guard lock(heap.mutex);
    if (reserve()) {
      // Each scope starts on a fresh page: its blocks' relative addresses
      // depend on its own allocations only.
      const auto offset = static_cast<std::size_t>(heap.bump - heap.begin.load());
      heap.bump = heap.begin.load() + (offset + kPage - 1) / kPage * kPage;
      heap.scope_begin = heap.bump;
      heap.free_lists.fill(nullptr);
      heap.open_scope.store(heap.next_scope++);
    }
  }
  in_scope = true;
}

DeterministicHeapScope::~DeterministicHeapScope() {
  if (joined_) return;
  in_scope = false;
  {
    std::lock_guard lock(heap.mutex);
    if (heap.open_scope.load() != 0) {
      heap.open_scope.store(0);
      heap.free_lists.fill(nullptr);
      for (char* block = heap.scope_begin; block < heap.bump; block += header_of(block).bytes)
        if (!header_of(block).free) count_pages(block, block + header_of(block).bytes - 1, +1);
      const auto used = static_cast<std::size_t>(heap.bump - heap.begin.load());
      release_empty_pages(page_of(heap.scope_begin), (used + kPage - 1) / kPage);
    }
  }
  heap.scope_mutex.unlock();
}

DeterministicHeapScope::Usage DeterministicHeapScope::usage() {
  std::lock_guard lock(heap.mutex);
  Usage u;
  if (!heap.begin.load()) return u;
  u.reserved_used = static_cast<std::size_t>(heap.bump - heap.begin.load());
  for (std::size_t page = 0; page * kPage < u.reserved_used; ++page)
    u.resident_pages += heap.page_live[page] > 0 ? 1 : 0;
  return u;
}

bool DeterministicHeapScope::owns(const void* p) {
  const char* c = static_cast<const char*>(p);
  return c && c >= heap.begin.load() && c < heap.end.load();
}

}  // namespace softflow

// The replaceable global allocation functions (C++ [new.delete]): every
// `new` of the program goes through softflow::allocate, which serves the
// open scope's thread from its region and everything else from malloc.
void* operator new(std::size_t n) { return softflow::allocate_or_throw(n); }
void* operator new[](std::size_t n) { return softflow::allocate_or_throw(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return softflow::allocate_or_throw(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t& tag) noexcept { return operator new(n, tag); }
void operator delete(void* p) noexcept { softflow::release(p); }
void operator delete[](void* p) noexcept { softflow::release(p); }
void operator delete(void* p, std::size_t) noexcept { softflow::release(p); }
void operator delete[](void* p, std::size_t) noexcept { softflow::release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { softflow::release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { softflow::release(p); }
