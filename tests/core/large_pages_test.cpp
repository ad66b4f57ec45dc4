// LargePageAllocator and reserve_on_large_pages (core/large_pages.hpp): big arrays land on
// 2 MiB boundaries (where the large-page advice applies), small ones keep the alignment asked
// for, and growth by push_back, resize and reserve keeps every element.

#include <collide/core/large_pages.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <utility>
#include <vector>

namespace collide {
namespace {

bool aligned_to(const void* p, std::size_t alignment) {
  return reinterpret_cast<std::uintptr_t>(p) % alignment == 0;
}

TEST(LargePages, VectorGrownOneByOnePastTheThresholdKeepsItsElements) {
  // 1.5M ints (6 MB) pushed one at a time: the growths below 4 MiB are plain blocks, those above
  // are on 2 MiB boundaries; the values survive every move.
  LargePageVector<int> v;
  constexpr int kCount = 1'500'000;
  for (int i = 0; i < kCount; ++i) {
    v.push_back(3 * i + 1);
    if (v.size() == v.capacity() && v.capacity() * sizeof(int) >= kLargePageMinBytes) {
      EXPECT_TRUE(aligned_to(v.data(), kLargePageBytes)) << "capacity " << v.capacity();
    }
  }
  ASSERT_EQ(v.size(), static_cast<std::size_t>(kCount));
  EXPECT_TRUE(aligned_to(v.data(), kLargePageBytes));
  for (int i = 0; i < kCount; i += 7919) EXPECT_EQ(v[static_cast<std::size_t>(i)], 3 * i + 1) << i;
  EXPECT_EQ(v.back(), 3 * (kCount - 1) + 1);
}

TEST(LargePages, SmallBlocksKeepTheAlignmentAskedFor) {
  LargePageVector<float, 64> lines(5, 2.0f);
  EXPECT_TRUE(aligned_to(lines.data(), 64));
  lines.resize(1000, 1.0f);  // 4 KB: still small
  EXPECT_TRUE(aligned_to(lines.data(), 64));
  EXPECT_EQ(lines[4], 2.0f);
  EXPECT_EQ(lines[999], 1.0f);
  lines.reserve(kLargePageMinBytes / sizeof(float));  // exactly the threshold: large
  EXPECT_TRUE(aligned_to(lines.data(), kLargePageBytes));
  EXPECT_EQ(lines[4], 2.0f);
  EXPECT_EQ(lines.size(), 1000u);
}

TEST(LargePages, CopiesAndSwapsBetweenVectorsWork) {
  // Stateless allocators: copies, moves and swaps need no allocator bookkeeping.
  LargePageVector<double> a(kLargePageMinBytes / sizeof(double) + 1, 0.5);
  LargePageVector<double> b = a;
  EXPECT_EQ(a, b);
  LargePageVector<double> c(3, 1.5);
  c.swap(b);
  EXPECT_EQ(c.size(), a.size());
  EXPECT_EQ(b.size(), 3u);
  EXPECT_TRUE(aligned_to(c.data(), kLargePageBytes));
  b = std::move(c);
  EXPECT_EQ(b, a);
}

TEST(LargePages, ReserveOnLargePagesMovesStdVectorsThere) {
  // reserve_on_large_pages serves std::vector (public types such as a field's node array): the
  // elements move into a fresh block; nothing happens when the room is there.
  std::vector<int> v{1, 2, 3};
  reserve_on_large_pages(v, kLargePageMinBytes / sizeof(int) + 10);
  EXPECT_GE(v.capacity(), kLargePageMinBytes / sizeof(int) + 10);
  EXPECT_EQ(v, (std::vector<int>{1, 2, 3}));
  const int* before = v.data();
  reserve_on_large_pages(v, 100);
  EXPECT_EQ(v.data(), before);
  const std::vector<float> filled = large_page_vector(1000, 4.0f);
  EXPECT_EQ(filled.size(), 1000u);
  EXPECT_EQ(filled[999], 4.0f);
}

TEST(LargePages, ImpossibleCountsThrowInsteadOfWrapping) {
  LargePageAllocator<double> allocator;
  EXPECT_THROW((void)allocator.allocate(static_cast<std::size_t>(-1) / 4), std::bad_array_new_length);
}

}  // namespace
}  // namespace collide
