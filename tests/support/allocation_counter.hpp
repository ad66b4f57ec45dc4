#pragma once
// Counts heap allocations (every global operator new) made on this thread while a counter is
// alive. The counting operator new lives in the test executable that uses this header
// (tests/broad/allocation_counter.cpp): link it there.

#include <cstddef>

namespace collide::test {

/// Allocations made on this thread while it is alive: count(). Counters may nest.
class AllocationCounter {
 public:
  AllocationCounter() noexcept;
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  /// Allocations since construction.
  [[nodiscard]] std::size_t count() const noexcept;

 private:
  std::size_t start_;
};

}  // namespace collide::test
