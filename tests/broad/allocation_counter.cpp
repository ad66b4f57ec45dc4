// The global operator new of test_broad, counting the allocations of each thread (see
// support/allocation_counter.hpp); operator delete to match. Both forward to malloc/free
// (aligned_alloc for over-aligned types), so sanitizers still see every block.

#include "support/allocation_counter.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

namespace {

thread_local std::size_t allocations = 0;

void* counted(std::size_t size, std::size_t align) {
  ++allocations;
  if (size == 0) size = 1;
  void* p = align <= alignof(std::max_align_t)
                ? std::malloc(size)
                : std::aligned_alloc(align, (size + align - 1) / align * align);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

}  // namespace

namespace collide::test {

AllocationCounter::AllocationCounter() noexcept : start_(allocations) {}
AllocationCounter::~AllocationCounter() = default;
std::size_t AllocationCounter::count() const noexcept { return allocations - start_; }

}  // namespace collide::test

void* operator new(std::size_t size) { return counted(size, alignof(std::max_align_t)); }
void* operator new[](std::size_t size) { return counted(size, alignof(std::max_align_t)); }
void* operator new(std::size_t size, std::align_val_t align) { return counted(size, static_cast<std::size_t>(align)); }
void* operator new[](std::size_t size, std::align_val_t align) { return counted(size, static_cast<std::size_t>(align)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted(size, alignof(std::max_align_t));
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted(size, alignof(std::max_align_t));
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace collide::test {
namespace {

// The counting operator new is the one linked in (were it not, every "allocates nothing" test
// would pass with a count of 0 whatever the code did).
TEST(AllocationCounter, CountsEachAllocationWhileAlive) {
  AllocationCounter counter;
  const auto one = std::make_unique<int>(1);
  std::vector<float> many(100);
  EXPECT_EQ(counter.count(), 2u);
  {
    struct alignas(64) Line {
      char bytes[64];
    };
    AllocationCounter inner;
    const auto line = std::make_unique<Line>();  // operator new(size, align_val_t)
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(line.get()) % 64, 0u);
    EXPECT_EQ(inner.count(), 1u);
  }
  EXPECT_EQ(counter.count(), 3u);
}

}  // namespace
}  // namespace collide::test
