#pragma once
/// @file
/// Uninitialised fixed-capacity storage for the narrow phase's scratch buffers. Internal.

#include <cstddef>
#include <type_traits>

namespace collide::detail {

/// Storage for up to N values of T, left uninitialised: the buffers that use it are filled
/// before they are read, and value-initialising them (T's members have default initialisers)
/// cost a quarter of a face contact (the clip buffers' 5 KB) and a few percent of a capsule's
/// level contact (its point lists' 4 KB). The bytes implicitly create the T objects that are
/// assigned (T is an implicit-lifetime type).
template <class T, int N>
struct ScratchArray {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  alignas(T) std::byte bytes[N * sizeof(T)];
  [[nodiscard]] T& operator[](int i) noexcept { return reinterpret_cast<T*>(bytes)[i]; }
  [[nodiscard]] const T& operator[](int i) const noexcept {
    return reinterpret_cast<const T*>(bytes)[i];
  }
  [[nodiscard]] const T* data() const noexcept { return reinterpret_cast<const T*>(bytes); }
};

}  // namespace collide::detail
