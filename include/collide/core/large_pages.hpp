#pragma once
/// @file
/// Big arrays read at random, on large pages: a dense distance field's tables (std::vector, by
/// reserve_on_large_pages), the world's bodies and a broad phase's arrays (LargePageVector). A query reads a node anywhere in tables of tens of MiB, a body pair two bodies
/// anywhere in hundreds; with 4 KiB pages nearly every such read also misses the TLB (its 3072
/// entries reach 12 MiB on the machine measured), and in a virtual machine a page walk costs
/// hundreds of cycles. On 2 MiB pages the whole table fits the TLB's reach, and filling it takes
/// a page fault per 2 MiB instead of one per 4 KiB. The one place the library asks the
/// operating system for anything.

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <new>
#include <vector>

namespace collide {

/// Arrays smaller than this stay as they are (a large page would not pay).
inline constexpr std::size_t kLargePageMinBytes = std::size_t{4} << 20;

/// The size of a large page where `advise_large_pages` asks for them (x86-64 Linux: 2 MiB).
inline constexpr std::size_t kLargePageBytes = std::size_t{2} << 20;

/// Asks the operating system to back the 2 MiB-aligned part of [data, data + bytes) with large
/// pages before it is first touched (Linux: madvise MADV_HUGEPAGE, used when transparent huge
/// pages are "always" or "madvise"; elsewhere nothing). Best effort: never fails.
void advise_large_pages(void* data, std::size_t bytes) noexcept;

/// An allocator for arrays that may grow big and are read at random (a broad phase's boxes, a
/// world's bodies and shapes): a block of kLargePageMinBytes or more is aligned to
/// kLargePageBytes and advised onto large pages before its owner writes it, whichever way the
/// vector grows (reserve, resize, push_back); smaller blocks are aligned to `Align` bytes (64:
/// a cache line) and left as they are. Stateless: all instances are equal.
template <class T, std::size_t Align = alignof(T)>
struct LargePageAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = LargePageAllocator<U, Align>;
  };
  LargePageAllocator() = default;
  template <class U>
  LargePageAllocator(const LargePageAllocator<U, Align>&) noexcept {}  // NOLINT: as std::allocator

  [[nodiscard]] T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    void* p = ::operator new(bytes, alignment(bytes));
    if (bytes >= kLargePageMinBytes) advise_large_pages(p, bytes);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept { ::operator delete(p, alignment(n * sizeof(T))); }

  template <class U>
  bool operator==(const LargePageAllocator<U, Align>&) const noexcept {
    return true;
  }

 private:
  static std::align_val_t alignment(std::size_t bytes) noexcept {
    constexpr std::size_t small = std::max(Align, alignof(T));
    return std::align_val_t{bytes >= kLargePageMinBytes ? std::max(kLargePageBytes, small) : small};
  }
};

/// A vector on LargePageAllocator (above).
template <class T, std::size_t Align = alignof(T)>
using LargePageVector = std::vector<T, LargePageAllocator<T, Align>>;

/// Makes room for `count` elements in `v` (nothing when it has it), its new storage advised onto
/// large pages (above) before anything is written there: the elements are moved into a fresh
/// block rather than reallocated by `reserve`, which would touch the block's first pages before
/// the advice. References into `v` are invalidated as by `reserve`.
template <class T>
void reserve_on_large_pages(std::vector<T>& v, std::size_t count) {
  if (count <= v.capacity()) return;
  if (count * sizeof(T) < kLargePageMinBytes) {
    v.reserve(count);
    return;
  }
  std::vector<T> grown;
  grown.reserve(count);
  advise_large_pages(grown.data(), count * sizeof(T));
  grown.insert(grown.end(), std::make_move_iterator(v.begin()), std::make_move_iterator(v.end()));
  v.swap(grown);
}

/// A vector of `count` copies of `value`, its storage advised onto large pages (above) before
/// it is filled.
template <class T>
std::vector<T> large_page_vector(std::size_t count, const T& value) {
  std::vector<T> v;
  reserve_on_large_pages(v, count);
  v.resize(count, value);
  return v;
}

}  // namespace collide
