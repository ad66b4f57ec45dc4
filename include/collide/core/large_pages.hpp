#pragma once
/// @file
/// Big arrays read at random, on large pages: a dense distance field's tables, the world's
/// bodies. A query reads a node anywhere in tables of tens of MiB, a body pair two bodies
/// anywhere in hundreds; with 4 KiB pages nearly every such read also misses the TLB (its 3072
/// entries reach 12 MiB on the machine measured), and in a virtual machine a page walk costs
/// hundreds of cycles. On 2 MiB pages the whole table fits the TLB's reach, and filling it takes
/// a page fault per 2 MiB instead of one per 4 KiB. The one place the library asks the
/// operating system for anything.

#include <cstddef>
#include <iterator>
#include <vector>

namespace collide {

/// Arrays smaller than this stay as they are (a large page would not pay).
inline constexpr std::size_t kLargePageMinBytes = std::size_t{4} << 20;

/// Asks the operating system to back the 2 MiB-aligned part of [data, data + bytes) with large
/// pages before it is first touched (Linux: madvise MADV_HUGEPAGE, used when transparent huge
/// pages are "always" or "madvise"; elsewhere nothing). Best effort: never fails.
void advise_large_pages(void* data, std::size_t bytes) noexcept;

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
