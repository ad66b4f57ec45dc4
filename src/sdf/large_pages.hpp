#pragma once
// Private to sdf/: the big arrays of a dense field on large pages. A query reads a node anywhere
// in tables of tens of MiB; with 4 KiB pages nearly every such read also misses the TLB (its
// 3072 entries reach 12 MiB on the machine measured), and in a virtual machine a page walk costs
// hundreds of cycles. On 2 MiB pages the whole table fits the TLB's reach.

#include <cstddef>
#include <vector>

namespace collide::detail {

/// Arrays smaller than this stay as they are (a large page would not pay).
inline constexpr std::size_t kLargePageMinBytes = std::size_t{4} << 20;

/// Asks the operating system to back the 2 MiB-aligned part of [data, data + bytes) with large
/// pages before it is first touched (Linux: madvise MADV_HUGEPAGE, used when transparent huge
/// pages are "always" or "madvise"; elsewhere nothing). Best effort: never fails.
void advise_large_pages(void* data, std::size_t bytes) noexcept;

/// A vector of `count` copies of `value`, its storage advised onto large pages (above) before
/// it is filled.
template <class T>
std::vector<T> large_page_vector(std::size_t count, const T& value) {
  std::vector<T> v;
  v.reserve(count);
  if (count * sizeof(T) >= kLargePageMinBytes) advise_large_pages(v.data(), count * sizeof(T));
  v.resize(count, value);
  return v;
}

}  // namespace collide::detail
