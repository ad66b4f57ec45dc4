// DynamicTreeN::insert: objects added one by one (as a spawner places bodies, each checked against
// those already placed) give the same answers as brute force, and the tree stays usable by update.

#include <collide/broad/dynamic_tree.hpp>
#include <collide/core/error.hpp>

#include "support/broad_worlds.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace collide {
namespace {

template <int D>
std::vector<int> query_ids(const DynamicTreeN<D>& tree, const AabbN<D>& box) {
  std::vector<int> ids;
  tree.query(box, [&](int id) {
    ids.push_back(id);
    return true;
  });
  std::sort(ids.begin(), ids.end());
  return ids;
}

template <int D>
std::vector<int> brute_ids(std::span<const AabbN<D>> boxes, const AabbN<D>& box) {
  std::vector<int> ids;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) {
    if (overlap(boxes[static_cast<std::size_t>(i)], box)) ids.push_back(i);
  }
  return ids;
}

template <int D>
void check_inserts() {
  for (const auto& [name, boxes] : test::static_worlds<D>()) {
    DynamicTreeN<D> tree;
    std::vector<AabbN<D>> placed;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      // Before inserting box i, the query over it sees exactly the boxes placed so far that it
      // overlaps: what a spawner asks.
      ASSERT_EQ(query_ids(tree, boxes[i]), brute_ids<D>(placed, boxes[i])) << name << " box " << i;
      ASSERT_EQ(tree.insert(boxes[i]), static_cast<int>(i)) << name;
      placed.push_back(boxes[i]);
    }
    EXPECT_EQ(tree.size(), static_cast<int>(boxes.size())) << name;
    // Balanced enough for O(log n) queries: the rotations keep the height near log2(n) (an empty
    // world's tree has height -1).
    const double log_n = std::log2(static_cast<double>(std::max<std::size_t>(boxes.size(), 2)));
    EXPECT_LE(tree.height(), 4 * static_cast<int>(std::ceil(log_n))) << name;
    PairList pairs;
    tree.find_pairs(pairs);
    sort_pairs(pairs);
    EXPECT_TRUE(pairs == test::brute_pairs<D>(boxes)) << name << ": pairs after inserts";
    // update() after inserts moves objects as usual (the same count: no rebuild).
    std::vector<AabbN<D>> moved = boxes;
    for (AabbN<D>& b : moved) {
      b.min += VecN<D>(3.0f);
      b.max += VecN<D>(3.0f);
    }
    tree.update(moved);
    tree.find_pairs(pairs);
    sort_pairs(pairs);
    EXPECT_TRUE(pairs == test::brute_pairs<D>(moved)) << name << ": pairs after update";
  }
}

TEST(DynamicTreeInsert, MatchesBruteForce2D) { check_inserts<2>(); }
TEST(DynamicTreeInsert, MatchesBruteForce3D) { check_inserts<3>(); }

TEST(DynamicTreeInsert, InsertsPastTheLargePageSizeKeepEveryBox) {
  // 300 x 250 boxes of size 1.2 on a lattice of spacing 1, inserted one at a time: the node
  // array (two nodes an object) grows past 4 MiB, where each growth moves the nodes into a block
  // advised onto large pages. Each box overlaps exactly its eight lattice neighbours, so the
  // pairs are known without a brute-force pass over 75,000 boxes.
  constexpr int kColumns = 300, kRows = 250;
  const auto box_at = [](int column, int row) {
    const Vec2 corner{static_cast<float>(column), static_cast<float>(row)};
    return Aabb{corner, corner + Vec2{1.2f, 1.2f}};
  };
  DynamicTreeN<2> tree;
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      ASSERT_EQ(tree.insert(box_at(column, row)), row * kColumns + column);
    }
  }
  PairList expected;
  for (int row = 0; row < kRows; ++row) {
    for (int column = 0; column < kColumns; ++column) {
      const int id = row * kColumns + column;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int c = column + dx, r = row + dy;
          if (c < 0 || c >= kColumns || r < 0 || r >= kRows) continue;
          const int other = r * kColumns + c;
          if (other > id) expected.push_back({id, other});
        }
      }
    }
  }
  sort_pairs(expected);
  PairList pairs;
  tree.find_pairs(pairs);
  sort_pairs(pairs);
  EXPECT_EQ(pairs.size(), expected.size());
  EXPECT_TRUE(pairs == expected);
  // A small box near the lattice point (150, 120) lies in the boxes of columns 149 and 150 of
  // rows 119 and 120, and in no other.
  const std::vector<int> ids = query_ids(tree, Aabb{{150.1f, 120.1f}, {150.15f, 120.15f}});
  const std::vector<int> four{119 * kColumns + 149, 119 * kColumns + 150, 120 * kColumns + 149,
                              120 * kColumns + 150};
  EXPECT_EQ(ids, four);
}

TEST(DynamicTreeInsert, RejectsBadBoxes) {
  DynamicTreeN<2> tree;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(tree.insert(Aabb{{nan, 0.0f}, {1.0f, 1.0f}}), InvalidInput);
  EXPECT_THROW(tree.insert(Aabb{{2.0f, 0.0f}, {1.0f, 1.0f}}), InvalidInput);
  EXPECT_EQ(tree.size(), 0);
}

}  // namespace
}  // namespace collide
