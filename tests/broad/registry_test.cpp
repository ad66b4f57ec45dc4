// The registry behind `collide query`'s `pairs` op: every name gives the brute-force pairs,
// sorted; unknown names and bad boxes are rejected with messages that say what to do.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/registry.hpp>
#include <collide/core/error.hpp>

#include "support/broad_worlds.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace collide {
namespace {

TEST(Registry, NamesAreUniqueDescribedAndDefaultFirst) {
  const auto names = broadphase_names();
  ASSERT_GE(names.size(), 6u);
  EXPECT_EQ(names[0], "hierarchical_grid");
  std::set<std::string_view> unique(names.begin(), names.end());
  EXPECT_EQ(unique.size(), names.size());
  ASSERT_EQ(broadphases().size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(broadphases()[i].name, names[i]);
    EXPECT_GT(broadphases()[i].description.size(), 10u);
  }
}

template <int D>
void expect_every_name_matches_brute_force() {
  std::mt19937 rng(21 + D);
  test::Boxes<D> boxes = test::mixed_size_world<D>(rng, 300, D == 2 ? 60.0f : 25.0f);
  const test::Boxes<D> touching = test::touching_world<D>(rng, 200, 6);
  boxes.insert(boxes.end(), touching.begin(), touching.end());
  BruteForceN<D> brute;
  brute.build(boxes);
  PairList expected;
  brute.find_pairs(expected);
  ASSERT_GT(expected.size(), 100u);
  for (const std::string_view name : broadphase_names()) {
    EXPECT_EQ(find_pairs(name, std::span<const AabbN<D>>(boxes)), expected) << name;
  }
  EXPECT_EQ(find_pairs("", std::span<const AabbN<D>>(boxes)), expected) << "default";
}

TEST(Registry, EveryNameGivesTheBruteForcePairsSorted2D) { expect_every_name_matches_brute_force<2>(); }
TEST(Registry, EveryNameGivesTheBruteForcePairsSorted3D) { expect_every_name_matches_brute_force<3>(); }

TEST(Registry, UnknownNameListsTheValidOnes) {
  const std::vector<Aabb> boxes(3);
  try {
    (void)find_pairs("octree", boxes);
    FAIL() << "unknown name accepted";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("octree"), std::string::npos) << what;
    for (const std::string_view name : broadphase_names()) {
      EXPECT_NE(what.find(name), std::string::npos) << what;
    }
  }
}

TEST(Registry, BadBoxIsNamed) {
  std::vector<Aabb3> boxes(4);
  boxes[2].min.z = 1.0f;
  for (const std::string_view name : broadphase_names()) {
    try {
      (void)find_pairs(name, boxes);
      FAIL() << name << " accepted min > max";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("box 2"), std::string::npos) << name << ": " << e.what();
    }
  }
}

}  // namespace
}  // namespace collide
