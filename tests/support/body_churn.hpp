#pragma once
// Bodies added, some removed, more added into the freed slots: what the world tests of slot and
// shape reuse share (2D and 3D).

#include <collide/world/world.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace collide::test {

/// The bodies of a churn: the live ones with the index of the definition each was made from,
/// and the removed ids.
struct BodyChurn {
  std::vector<std::pair<BodyId, int>> live;
  std::vector<BodyId> removed;
};

/// Adds def(0), ..., def(first - 1), removes every `stride`-th of them (the 0th first), then
/// adds def(first), ..., def(last - 1): the first of those take the freed slots.
template <class World, class Def>
BodyChurn churn_bodies(World& world, const Def& def, int first, int stride, int last) {
  BodyChurn churn;
  for (int i = 0; i < first; ++i) churn.live.emplace_back(world.add_body(def(i)), i);
  for (std::size_t k = 0; k < churn.live.size(); k += static_cast<std::size_t>(stride)) {
    world.remove_body(churn.live[k].first);
    churn.removed.push_back(churn.live[k].first);
  }
  std::erase_if(churn.live, [&](const auto& l) { return std::ranges::find(churn.removed, l.first) != churn.removed.end(); });
  for (int i = first; i < last; ++i) churn.live.emplace_back(world.add_body(def(i)), i);
  return churn;
}

/// Expects every live body of `churn` to read back the shapes of its definition (`same(a, b)`:
/// shape a equals shape b) and the removed ones to be gone.
template <class World, class Def, class Same>
void expect_churned_shapes(const World& world, const BodyChurn& churn, const Def& def, const Same& same) {
  for (const BodyId id : churn.removed) EXPECT_FALSE(world.contains(id));
  for (const auto& [id, i] : churn.live) {
    const auto d = def(i);
    const auto shapes = world.shapes(id);
    ASSERT_EQ(shapes.size(), d.shapes.size()) << "body of def " << i;
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      EXPECT_TRUE(same(shapes[k], d.shapes[k])) << "body of def " << i << " shape " << k;
    }
  }
}

}  // namespace collide::test
