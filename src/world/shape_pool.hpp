#pragma once
// The world's pool of body shapes (world_impl.hpp): each body's shapes are a span of slots in
// blocks that never move, the big blocks on large pages.

#include <collide/core/large_pages.hpp>

#include <algorithm>
#include <cstddef>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace collide::detail {

/// Storage for the shapes of a world's bodies. A body's `count` shapes are `count` adjacent
/// slots of one block; blocks never move, so the body keeps a span into its block for its life.
/// Blocks double from kFirstBlockSlots slots up to kMaxBlockBytes, from LargePageAllocator: a
/// block of kLargePageMinBytes or more is on large pages before its first touch.
/// A removed body's slots go to a free list for their count and serve the next body with as many
/// shapes. Every slot ever handed out holds a constructed T (a released one a default T, which
/// frees what the shape held), so the pool's destructor destroys them all.
///
/// Why (issue 20): with a heap block of its own for each body's shapes, a 1e6-body spawn took
/// about 66k page faults for them (a 4 KiB page per 15 bodies), and the narrow phase read the
/// shapes through 4 KiB pages scattered over the heap.
template <class T>
class ShapePool {
 public:
  ShapePool() = default;
  ShapePool(const ShapePool&) = delete;
  ShapePool& operator=(const ShapePool&) = delete;
  ~ShapePool() {
    for (const Block& b : blocks_) {
      std::destroy_n(b.data, b.used);
      Allocator{}.deallocate(b.data, b.capacity);
    }
  }

  /// Copies of `shapes` in adjacent slots (empty for none). Throws what T's copy or the
  /// allocation throws: fresh slots are then given back unconstructed, and released slots stay
  /// released (some of them holding copies).
  std::span<T> allocate(std::span<const T> shapes) {
    const std::size_t n = shapes.size();
    if (n == 0) return {};
    if (auto it = free_.find(n); it != free_.end() && !it->second.empty()) {
      T* slots = it->second.back();
      std::copy(shapes.begin(), shapes.end(), slots);  // into the constructed default Ts
      it->second.pop_back();
      return {slots, n};
    }
    if (blocks_.empty() || blocks_.back().capacity - blocks_.back().used < n) add_block(n);
    Block& b = blocks_.back();
    T* slots = b.data + b.used;
    std::uninitialized_copy(shapes.begin(), shapes.end(), slots);
    b.used += n;
    return {slots, n};
  }

  /// Gives back slots from allocate: each becomes a default T (releasing what it held) and the
  /// span waits for the next allocate of as many. Nothing for an empty span.
  void release(std::span<T> slots) {
    if (slots.empty()) return;
    std::fill(slots.begin(), slots.end(), T{});
    free_[slots.size()].push_back(slots.data());
  }

 private:
  static constexpr std::size_t kFirstBlockSlots = 16;
  static constexpr std::size_t kMaxBlockBytes = std::size_t{16} << 20;
  /// Big blocks on large pages, small ones aligned for T.
  using Allocator = LargePageAllocator<T>;

  struct Block {
    T* data = nullptr;
    std::size_t capacity = 0;  ///< slots
    std::size_t used = 0;      ///< slots constructed, from the front
  };

  /// A new block of at least `n` slots, twice the last one's up to kMaxBlockBytes.
  void add_block(std::size_t n) {
    std::size_t slots = blocks_.empty() ? kFirstBlockSlots : 2 * blocks_.back().capacity;
    slots = std::min(slots, std::max<std::size_t>(kMaxBlockBytes / sizeof(T), 1));
    slots = std::max(slots, n);
    blocks_.reserve(blocks_.size() + 1);  // so that the push_back below cannot throw
    blocks_.push_back(Block{Allocator{}.allocate(slots), slots, 0});
  }

  std::vector<Block> blocks_;
  std::map<std::size_t, std::vector<T*>> free_;  ///< released spans by their count
};

}  // namespace collide::detail
