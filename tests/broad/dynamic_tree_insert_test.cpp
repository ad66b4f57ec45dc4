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

TEST(DynamicTreeInsert, RejectsBadBoxes) {
  DynamicTreeN<2> tree;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(tree.insert(Aabb{{nan, 0.0f}, {1.0f, 1.0f}}), InvalidInput);
  EXPECT_THROW(tree.insert(Aabb{{2.0f, 0.0f}, {1.0f, 1.0f}}), InvalidInput);
  EXPECT_EQ(tree.size(), 0);
}

}  // namespace
}  // namespace collide
