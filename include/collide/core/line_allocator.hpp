#pragma once
/// @file
/// `LineAllocator`: a standard allocator whose blocks start on 64-byte boundaries (a cache
/// line), for arrays whose records must not straddle two lines (a distance field's cells, the
/// broad phase's streamed rows).

#include <cstddef>
#include <new>

namespace collide {

/// Size of the cache line the layouts in this library are shaped for, bytes.
inline constexpr std::size_t kCacheLineBytes = 64;

/// Allocates through aligned operator new on kCacheLineBytes boundaries; stateless (every
/// instance equal). Throws std::bad_alloc as operator new does.
template <class T>
struct LineAllocator {
  using value_type = T;
  static constexpr std::align_val_t kAlign{kCacheLineBytes};
  LineAllocator() = default;
  template <class U>
  LineAllocator(const LineAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), kAlign)); }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, kAlign); }
  template <class U>
  bool operator==(const LineAllocator<U>&) const noexcept { return true; }
};

}  // namespace collide
