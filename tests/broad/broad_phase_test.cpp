// Every broad phase against the brute-force reference: same pair set (each pair once, i < j),
// same answers to AABB, point and ray queries, on static and moving worlds in 2D and 3D.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/sweep_and_prune.hpp>
#include <collide/core/error.hpp>

#include "support/broad_worlds.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <set>
#include <string>

namespace collide {
namespace {

using test::Boxes;
using test::brute_pairs;
using test::static_worlds;

template <class BP, int Dim>
struct Case {
  using Type = BP;
  static constexpr int D = Dim;
};

/// Checks the structure's pairs against brute force: same set, each once, i < j.
template <int D, class BP>
void expect_same_pairs(BP& bp, std::span<const AabbN<D>> boxes, const PairList& expected,
                       const std::string& what) {
  PairList pairs;
  bp.find_pairs(pairs);
  for (const auto& [i, j] : pairs) {
    ASSERT_LT(i, j) << what;
    ASSERT_TRUE(overlap(boxes[i], boxes[j])) << what << " pair " << i << "," << j;
  }
  PairList sorted = pairs;
  sort_pairs(sorted);
  EXPECT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end())
      << what << ": a pair reported twice";
  EXPECT_EQ(sorted.size(), expected.size()) << what;
  EXPECT_TRUE(sorted == expected) << what << ": pair sets differ";
}

template <class C>
class BroadPhaseTest : public ::testing::Test {};

using Cases = ::testing::Types<
    Case<BruteForceN<2>, 2>, Case<BruteForceN<3>, 3>, Case<HashGridN<2>, 2>, Case<HashGridN<3>, 3>,
    Case<SortedGridN<2>, 2>, Case<SortedGridN<3>, 3>, Case<LooseGridN<2>, 2>, Case<LooseGridN<3>, 3>, Case<HierarchicalGridN<2>, 2>,
    Case<HierarchicalGridN<3>, 3>, Case<DynamicTreeN<2>, 2>, Case<DynamicTreeN<3>, 3>,
    Case<SweepAndPruneN<2>, 2>, Case<SweepAndPruneN<3>, 3>>;
TYPED_TEST_SUITE(BroadPhaseTest, Cases);

TYPED_TEST(BroadPhaseTest, ModelsTheBroadPhaseConcept) {
  static_assert(BroadPhase<typename TypeParam::Type, TypeParam::D>);
}

// Before the first build a structure is empty: no pairs, no query hits, and its counters (where
// it has them) at zero.
TYPED_TEST(BroadPhaseTest, EmptyBeforeTheFirstBuild) {
  constexpr int D = TypeParam::D;
  const typename TypeParam::Type bp;
  EXPECT_EQ(bp.size(), 0);
  int hits = 0;
  const AabbN<D> everything{VecN<D>(-1e30f), VecN<D>(1e30f)};
  bp.query(everything, [&](int) { return ++hits > 0; });
  bp.query_point(VecN<D>(0.0f), [&](int) { return ++hits > 0; });
  bp.ray_cast(RayN<D>{VecN<D>(-1.0f), VecN<D>(2.0f)}, [&](int, float f) { ++hits; return f; });
  EXPECT_EQ(hits, 0);
  typename TypeParam::Type fresh;
  PairList pairs{{0, 1}};
  fresh.find_pairs(pairs);
  EXPECT_TRUE(pairs.empty());
  if constexpr (requires { bp.cell_count(); }) EXPECT_EQ(bp.cell_count(), 0);
  if constexpr (requires { bp.oversized_count(); }) EXPECT_EQ(bp.oversized_count(), 0);
  if constexpr (requires { bp.level_count(); }) EXPECT_EQ(bp.level_count(), 0);
}

TYPED_TEST(BroadPhaseTest, PairsMatchBruteForceOnEveryStaticWorld) {
  constexpr int D = TypeParam::D;
  for (const auto& [name, boxes] : static_worlds<D>()) {
    const PairList expected = brute_pairs<D>(boxes);
    if (boxes.size() > 100) {
      // The world is neither empty of pairs nor all pairs: both outcomes are exercised.
      EXPECT_GT(expected.size(), boxes.size() / 20) << name;
      EXPECT_LT(expected.size(), boxes.size() * (boxes.size() - 1) / 4) << name;
    }
    typename TypeParam::Type bp;
    bp.build(boxes);
    EXPECT_EQ(bp.size(), static_cast<int>(boxes.size()));
    expect_same_pairs<D>(bp, boxes, expected, name);
    if (!boxes.empty()) EXPECT_GE(bp.memory_bytes(), boxes.size() * sizeof(AabbN<D>)) << name;
  }
}

TYPED_TEST(BroadPhaseTest, PairOrderIsDeterministic) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(5);
  const Boxes<D> boxes = test::clustered_world<D>(rng, 400, 20.0f);
  typename TypeParam::Type a, b;
  a.build(boxes);
  b.build(boxes);
  b.build(boxes);  // a second build of the same boxes must not change the order either
  PairList pa, pb;
  a.find_pairs(pa);
  b.find_pairs(pb);
  EXPECT_FALSE(pa.empty());
  EXPECT_TRUE(pa == pb);
}

TYPED_TEST(BroadPhaseTest, MovingWorldMatchesBruteForceEveryFrame) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(77);
  for (const float offset : {0.0f, -5000.0f, 1.0e4f}) {
    auto world = test::moving_world<D>(
        rng, test::uniform_world<D>(rng, 400, 15.0f, 0.2f, 1.2f, offset), 15.0f, 0.3f, offset);
    // A few big and tiny boxes among them, moving too.
    world.boxes[3] = test::box_at<D>(VecN<D>(offset), VecN<D>(12.0f));
    world.boxes[7] = test::box_at<D>(VecN<D>(offset + 1.0f), VecN<D>(0.0f));
    typename TypeParam::Type bp;
    bp.build(world.boxes);
    std::size_t total = 0;
    for (int frame = 0; frame < 25; ++frame) {
      world.step();
      bp.update(world.boxes);
      const PairList expected = brute_pairs<D>(world.boxes);
      total += expected.size();
      expect_same_pairs<D>(bp, world.boxes, expected,
                           "offset " + std::to_string(offset) + " frame " + std::to_string(frame));
      if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(total, 25u * 100u);
  }
}

/// True when every corner of every box is a whole number.
template <int D>
bool on_integer_lattice(std::span<const AabbN<D>> boxes) {
  for (const AabbN<D>& b : boxes) {
    for (int k = 0; k < D; ++k) {
      if (b.min[k] != std::floor(b.min[k]) || b.max[k] != std::floor(b.max[k])) return false;
    }
  }
  return true;
}

/// Pairs that touch exactly: on some axis the overlap has zero width.
template <int D>
std::size_t exact_touches(std::span<const AabbN<D>> boxes, const PairList& pairs) {
  std::size_t touches = 0;
  for (const auto& [i, j] : pairs) {
    for (int k = 0; k < D; ++k) {
      if (std::max(boxes[i].min[k], boxes[j].min[k]) == std::min(boxes[i].max[k], boxes[j].max[k])) {
        ++touches;
        break;
      }
    }
  }
  return touches;
}

// The named worlds moving for 100 frames: clusters drifting through the cells, 0.1- and
// 100-unit boxes, huge boxes, boxes touching exactly on cell boundaries (every other frame all
// on the integer lattice), negative coordinates and coordinates near 1e6. Each frame's update
// must give exactly brute force's pairs, however far the boxes moved since the build.
TYPED_TEST(BroadPhaseTest, MovingNamedWorldsMatchBruteForceEveryFrame) {
  constexpr int D = TypeParam::D;
  constexpr std::size_t kFrames = 100;
  for (auto& [name, world] : test::moving_worlds<D>(300)) {
    typename TypeParam::Type bp;
    bp.build(world.boxes);
    std::size_t total = 0, lattice_frames = 0, touches = 0;
    for (std::size_t frame = 1; frame <= kFrames; ++frame) {
      world.step();
      bp.update(world.boxes);
      const PairList expected = brute_pairs<D>(world.boxes);
      total += expected.size();
      expect_same_pairs<D>(bp, world.boxes, expected, name + " frame " + std::to_string(frame));
      if (::testing::Test::HasFailure()) return;
      if (name == "touching" && on_integer_lattice<D>(world.boxes)) {
        ++lattice_frames;
        touches += exact_touches<D>(world.boxes, expected);
      }
    }
    // Neither empty of pairs nor all pairs, in every world.
    const std::size_t n = world.boxes.size();
    EXPECT_GT(total, kFrames * n / 20) << name;
    EXPECT_LT(total, kFrames * n * (n - 1) / 4) << name;
    if (name == "touching") {
      EXPECT_EQ(lattice_frames, kFrames / 2);
      EXPECT_GT(touches, lattice_frames * 50) << "boxes touching exactly on the lattice";
    }
  }
}

// Steady state allocates nothing: once the vectors have grown, the same world moving on keeps
// the memory of the structure and of the pair list unchanged.
TYPED_TEST(BroadPhaseTest, SteadyStateFramesAllocateNothing) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(13);
  auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 300, 10.0f, 0.2f, 1.0f),
                                     10.0f, 0.0f);  // velocity 0: the same boxes every frame
  typename TypeParam::Type bp;
  bp.build(world.boxes);
  PairList pairs;
  bp.update(world.boxes);
  bp.find_pairs(pairs);
  const std::size_t memory = bp.memory_bytes();
  const std::size_t capacity = pairs.capacity();
  const BroadPair* data = pairs.data();
  for (int frame = 0; frame < 5; ++frame) {
    bp.update(world.boxes);
    bp.find_pairs(pairs);
  }
  EXPECT_EQ(bp.memory_bytes(), memory);
  EXPECT_EQ(pairs.capacity(), capacity);
  EXPECT_EQ(pairs.data(), data);
  EXPECT_FALSE(pairs.empty());
}

TYPED_TEST(BroadPhaseTest, QueriesMatchBruteForce) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(99);
  for (const auto& [name, boxes] : static_worlds<D>()) {
    typename TypeParam::Type bp;
    bp.build(boxes);
    BruteForceN<D> brute;
    brute.build(boxes);
    const AabbN<D> world = bounds_of<D>(boxes);
    const VecN<D> lo = world.min - 0.1f * world.size() - VecN<D>(1.0f);
    const VecN<D> hi = world.max + 0.1f * world.size() + VecN<D>(1.0f);
    int box_hits = 0, point_hits = 0, ray_hits = 0;
    for (int q = 0; q < 60; ++q) {
      VecN<D> a, b;
      for (int k = 0; k < D; ++k) {
        a[k] = test::uniform_f(rng, lo[k], hi[k]);
        b[k] = test::uniform_f(rng, lo[k], hi[k]);
      }
      // Half the queries start at a box: the hit rate stays high in sparse worlds.
      if (!boxes.empty() && q % 2 == 1) a = boxes[rng() % boxes.size()].center();
      // AABB query: a box from a towards b, up to 1/8 of the way.
      const AabbN<D> qbox{glm::min(a, a + (b - a) * 0.125f), glm::max(a, a + (b - a) * 0.125f)};
      std::vector<int> got, want;
      bp.query(qbox, [&](int id) { got.push_back(id); return true; });
      brute.query(qbox, [&](int id) { want.push_back(id); return true; });
      std::sort(got.begin(), got.end());
      EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << name << " query dup";
      EXPECT_EQ(got, want) << name << " query " << q;
      box_hits += !want.empty();

      // Point query at a box corner or a random point.
      const VecN<D> p = (!boxes.empty() && q % 2 == 0) ? boxes[rng() % boxes.size()].max : a;
      got.clear();
      want.clear();
      bp.query_point(p, [&](int id) { got.push_back(id); return true; });
      brute.query_point(p, [&](int id) { want.push_back(id); return true; });
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, want) << name << " point " << q;
      point_hits += !want.empty();

      // Ray cast without clipping: every box the segment meets, once.
      const RayN<D> ray{a, b - a};
      got.clear();
      want.clear();
      bp.ray_cast(ray, [&](int id, float f) { got.push_back(id); return f; });
      brute.ray_cast(ray, [&](int id, float f) { want.push_back(id); return f; });
      std::sort(got.begin(), got.end());
      EXPECT_TRUE(std::adjacent_find(got.begin(), got.end()) == got.end()) << name << " ray dup";
      EXPECT_EQ(got, want) << name << " ray " << q;
      ray_hits += !want.empty();

      // Ray cast clipped to each box's entry: the closest box entry is found.
      float best = 2.0f, want_best = 2.0f;
      const auto clip = [&](float& out) {
        return [&](int id, float limit) {
          const float f = ray_box_fraction(ray, boxes[id], limit);
          if (f >= 0.0f && f < out) out = f;
          return f >= 0.0f ? f : limit;
        };
      };
      bp.ray_cast(ray, clip(best));
      brute.ray_cast(ray, clip(want_best));
      EXPECT_EQ(best, want_best) << name << " closest ray " << q;
    }
    if (boxes.size() > 100) {
      EXPECT_GT(box_hits, 10) << name;
      EXPECT_LT(box_hits, 60) << name;
      EXPECT_GT(point_hits, 10) << name;
      if (name != "points") EXPECT_GT(ray_hits, 10) << name;
    }
  }
}

TYPED_TEST(BroadPhaseTest, QueriesStopWhenTheCallbackSaysSo) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(3);
  const Boxes<D> boxes = test::clustered_world<D>(rng, 300, 10.0f);
  typename TypeParam::Type bp;
  bp.build(boxes);
  int calls = 0;
  bp.query(bounds_of<D>(boxes), [&](int) { return ++calls < 3; });
  EXPECT_EQ(calls, 3);
  calls = 0;
  // A ray from inside box 0 meets at least box 0.
  const AabbN<D> world = bounds_of<D>(boxes);
  bp.ray_cast(RayN<D>{boxes[0].center(), world.max - boxes[0].center()},
              [&](int, float) { ++calls; return 0.0f; });
  EXPECT_EQ(calls, 1);
}

TYPED_TEST(BroadPhaseTest, RejectsNonFiniteAndInvertedBoxesNamingTheIndex) {
  constexpr int D = TypeParam::D;
  Boxes<D> boxes(5, test::box_at<D>(VecN<D>(0.0f), VecN<D>(1.0f)));
  typename TypeParam::Type bp;
  boxes[3].min[1] = std::numeric_limits<float>::quiet_NaN();
  try {
    bp.build(boxes);
    FAIL() << "NaN accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("box 3"), std::string::npos) << e.what();
  }
  boxes[3] = test::box_at<D>(VecN<D>(0.0f), VecN<D>(1.0f));
  boxes[2].min[D - 1] = 5.0f;
  try {
    bp.build(boxes);
    FAIL() << "min > max accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("box 2"), std::string::npos) << e.what();
  }
  boxes[2].min[D - 1] = std::numeric_limits<float>::infinity();
  EXPECT_THROW(bp.build(boxes), InvalidInput);
}

// update validates as build does: a NaN, an infinity or min > max anywhere (first, middle and
// last box, min or max corner) is rejected naming the box, and the structure is not left
// broken: the next update with good boxes gives brute force's pairs.
TYPED_TEST(BroadPhaseTest, UpdateRejectsNonFiniteAndInvertedBoxesNamingTheIndex) {
  constexpr int D = TypeParam::D;
  std::mt19937 rng(41);
  const Boxes<D> good = test::uniform_world<D>(rng, 200, 8.0f, 0.2f, 1.0f);
  const PairList expected = brute_pairs<D>(good);
  ASSERT_GT(expected.size(), 50u);
  typename TypeParam::Type bp;
  bp.build(good);
  for (const test::BadBox<D>& c : test::bad_boxes<D>(static_cast<int>(good.size()))) {
    Boxes<D> boxes = good;
    c.spoil(boxes[std::size_t(c.index)]);
    test::expect_rejects_naming_the_box(c, [&] { bp.update(boxes); });
    bp.update(good);
    expect_same_pairs<D>(bp, good, expected, std::string("update after ") + c.what);
  }
}

}  // namespace
}  // namespace collide

namespace collide {
namespace {

// sort_pairs radix-sorts lists of 512 or more non-negative pairs: its order must be std::sort's
// lexicographic one for every id range (the key's width follows the largest id), duplicates,
// pairs with first > second, a scratch reused across calls, and lists with a negative id (which
// take std::sort).
TEST(SortPairs, SameOrderAsStdSortForEverySizeAndIdRange) {
  std::mt19937 rng(7);
  PairList scratch;
  for (const std::size_t n : {0u, 1u, 2u, 511u, 512u, 513u, 3000u, 100000u}) {
    for (const int largest : {1, 10, 10000, 1000000, std::numeric_limits<int>::max()}) {
      for (const bool with_negative : {false, true}) {
        std::uniform_int_distribution<int> id(0, largest);
        PairList pairs(n);
        for (BroadPair& p : pairs) p = {id(rng), id(rng)};
        if (with_negative && n > 0) pairs[n / 2].second = -3;
        if (n >= 4) pairs[1] = pairs[3];  // a duplicate
        PairList want = pairs;
        std::sort(want.begin(), want.end());
        sort_pairs(pairs, scratch);
        ASSERT_EQ(pairs, want) << n << " pairs, ids up to " << largest << (with_negative ? ", one negative" : "");
      }
    }
  }
  PairList one_call{{5, 2}, {1, 9}, {1, 3}};
  sort_pairs(one_call);
  EXPECT_EQ(one_call, (PairList{{1, 3}, {1, 9}, {5, 2}}));
}

// SlabRayN::touches4 (four boxes in SSE2 lanes, from boxes or from a structure of arrays)
// decides as fraction() >= 0 box by box, and for_each_touched (both stores) visits what a loop
// of fraction() tests visits, while the visits
// shrink the fraction: random rays (some along an axis, some with a tiny translation whose
// reciprocal overflows), boxes that are points, that touch the origin exactly, that hold it.
template <int D>
void check_four_box_slab_test() {
  std::mt19937 rng(31 + D);
  std::uniform_real_distribution<float> coordinate(-4.0f, 4.0f), size(0.0f, 2.0f), unit(0.0f, 1.0f);
  for (int trial = 0; trial < 4000; ++trial) {
    RayN<D> ray;
    for (int k = 0; k < D; ++k) {
      ray.origin[k] = trial % 7 == 0 ? 0.0f : coordinate(rng);
      ray.translation[k] = 3.0f * coordinate(rng);
    }
    if (trial % 5 == 1) ray.translation[trial % D] = 0.0f;       // along the other axes
    if (trial % 11 == 2) ray.translation[0] = 1e-40f;             // 1 / t overflows
    std::vector<AabbN<D>> boxes(1 + trial % 9);
    for (AabbN<D>& b : boxes) {
      for (int k = 0; k < D; ++k) {
        b.min[k] = trial % 13 == 3 ? ray.origin[k] : coordinate(rng);  // the origin on a corner
        b.max[k] = b.min[k] + (trial % 17 == 4 ? 0.0f : size(rng));     // a point
      }
    }
    const SlabRayN<D> slab(ray);
    const float start = trial % 3 == 0 ? 1.0f : unit(rng);
    for (std::size_t g = 0; g + 4 <= boxes.size(); ++g) {
      unsigned want = 0;
      for (unsigned i = 0; i < 4; ++i) want |= unsigned{slab.fraction(boxes[g + i], start) >= 0.0f} << i;
      ASSERT_EQ(slab.touches4({&boxes[g], &boxes[g + 1], &boxes[g + 2], &boxes[g + 3]}, start), want) << trial;
    }
    // Each visit shrinks the fraction to the box's entry fraction (as a hit would).
    std::vector<std::size_t> want, got;
    float limit = start;
    for (std::size_t i = 0; i < boxes.size() && limit > 0.0f; ++i) {
      const float f = slab.fraction(boxes[i], limit);
      if (f < 0.0f) continue;
      want.push_back(i);
      limit = std::min(limit, 0.5f * (f + limit));
    }
    const float end = for_each_touched<D>(
        slab, boxes.size(), start, [&](std::size_t i) -> const AabbN<D>& { return boxes[i]; },
        [&](std::size_t i, float fraction) {
          got.push_back(i);
          return 0.5f * (slab.fraction(boxes[i], fraction) + fraction);
        });
    ASSERT_EQ(got, want) << trial;
    EXPECT_EQ(end, limit) << trial;

    // The same boxes as a structure of arrays (a loose grid's store: coordinate k of the min
    // corner at coords[k * stride + e], of the max at coords[(D + k) * stride + e], three
    // readable entries past the last): the same decisions, and the same visits from any first box.
    const std::size_t stride = boxes.size() + 3;
    std::vector<float> coords(2 * D * stride, std::numeric_limits<float>::quiet_NaN());
    for (std::size_t e = 0; e < boxes.size(); ++e) {
      for (int k = 0; k < D; ++k) {
        coords[std::size_t(k) * stride + e] = boxes[e].min[k];
        coords[std::size_t(D + k) * stride + e] = boxes[e].max[k];
      }
    }
    for (std::size_t g = 0; g + 4 <= boxes.size(); ++g) {
      ASSERT_EQ(slab.touches4(coords.data() + g, stride, start),
                slab.touches4({&boxes[g], &boxes[g + 1], &boxes[g + 2], &boxes[g + 3]}, start))
          << trial;
    }
    const std::size_t first = std::size_t(trial) % boxes.size();
    std::vector<std::size_t> want_from, got_from;
    limit = start;
    for (std::size_t i = first; i < boxes.size() && limit > 0.0f; ++i) {
      const float f = slab.fraction(boxes[i], limit);
      if (f < 0.0f) continue;
      want_from.push_back(i);
      limit = std::min(limit, 0.5f * (f + limit));
    }
    const float end_from = for_each_touched<D>(slab, coords.data(), stride, first, boxes.size(), start,
                                               [&](std::size_t e, float fraction) {
                                                 got_from.push_back(e);
                                                 return 0.5f * (slab.fraction(boxes[e], fraction) + fraction);
                                               });
    ASSERT_EQ(got_from, want_from) << trial;
    EXPECT_EQ(end_from, limit) << trial;
  }
}

TEST(SlabRay, FourBoxTestDecidesAsOneAtATime) {
  check_four_box_slab_test<2>();
  check_four_box_slab_test<3>();
}

}  // namespace
}  // namespace collide
