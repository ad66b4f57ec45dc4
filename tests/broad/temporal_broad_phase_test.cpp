// The temporal broad phase against brute force at every frame: objects within their speed
// bounds, objects bouncing, objects teleporting; and the count of skipped checks.

#include <collide/broad/brute_force.hpp>
#include <collide/broad/temporal_broad_phase.hpp>
#include <collide/core/error.hpp>

#include "support/broad_worlds.hpp"
#include "support/test_scheduler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::brute_pairs;

/// Speed bound of each object: its largest per-axis step per frame (the box moves by the
/// velocity each frame of one time unit), with 1% headroom plus the float rounding of a step
/// at the world's coordinates (half an ulp per corner: 6e-8 of the magnitude; 4e-7 to be safe).
template <int D>
std::vector<float> bounds_of_world(const test::MovingWorld<D>& world) {
  const float rounding = 4e-7f * (std::abs(world.offset) + world.extent + 2.0f);
  std::vector<float> speeds;
  for (const VecN<D>& v : world.velocity) {
    float m = 0.0f;
    for (int k = 0; k < D; ++k) m = std::max(m, std::abs(v[k]));
    speeds.push_back(1.01f * m + rounding);
  }
  return speeds;
}

/// How run_frames drives the candidate set's rebuilds.
enum class Rebuilds { in_find_pairs, ahead };

template <int D>
void run_frames(float offset, int teleport_every, std::int64_t& skipped, std::int64_t& violations,
                TaskScheduler* scheduler = nullptr, int objects = 500, int frames = 150,
                Rebuilds rebuilds = Rebuilds::in_find_pairs, std::int64_t* rebuild_count = nullptr,
                bool update_in_parts = false) {
  std::mt19937 rng(11 + D);
  auto world = test::moving_world<D>(
      rng, test::uniform_world<D>(rng, objects, D == 2 ? 25.0f : 10.0f, 0.2f, 1.0f, offset),
      D == 2 ? 25.0f : 10.0f, 0.05f, offset);
  world.velocity[0] = VecN<D>(0.0f);  // a resting object: speed bound 0
  TemporalBroadPhaseN<D> temporal;
  temporal.build(world.boxes, bounds_of_world(world), 0.0);
  PairList pairs;
  std::size_t total = 0;
  int ahead = 0;  // rebuilds made by rebuild_now before the frame's motion
  for (int frame = 1; frame <= frames; ++frame) {
    const bool rebuilt_ahead = rebuilds == Rebuilds::ahead && temporal.rebuild_due(static_cast<double>(frame));
    if (rebuilt_ahead) {
      temporal.rebuild_now(static_cast<double>(frame));
      ++ahead;
    }
    const std::int64_t rebuilds_before = temporal.stats().rebuilds;
    world.step();
    if (teleport_every > 0 && frame % teleport_every == 0) {
      // Objects 1 and objects - 2 jump onto others, breaking their bounds.
      for (const int jumper : {1, objects - 2}) {
        const int target = 2 + (frame + jumper) % 50;
        const VecN<D> shift = world.boxes[target].center() - world.boxes[jumper].center();
        world.boxes[jumper].min += shift;
        world.boxes[jumper].max += shift;
      }
    }
    if (update_in_parts) {
      // As the world's body pass does: ranges (object 0 alone, then 37 at a time), on the
      // workers when given, in any order (here last range first).
      temporal.begin_update(world.boxes.size(), static_cast<double>(frame));
      const int ranges = 1 + (objects - 1 + 36) / 37;
      parallel_for(scheduler, ranges, 1, [&](int begin, int end, int) {
        for (int r = end - 1; r >= begin; --r) {
          const int first = r == 0 ? 0 : 1 + (r - 1) * 37;
          temporal.update_range(first, r == 0 ? 1 : std::min(objects, first + 37), world.boxes);
        }
      });
      temporal.finish_update(world.boxes);
    } else {
      temporal.update(world.boxes, static_cast<double>(frame), scheduler);
    }
    temporal.find_pairs(pairs, scheduler);
    ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
    const PairList expected = brute_pairs<D>(world.boxes);
    total += expected.size();
    ASSERT_EQ(pairs, expected) << "frame " << frame;
    // A set built ahead holds through its frame: find_pairs rebuilds only for broken bounds.
    if (rebuilt_ahead && temporal.stats().bound_violations == 0) {
      EXPECT_EQ(temporal.stats().rebuilds, rebuilds_before) << "frame " << frame;
    }
  }
  if (rebuilds == Rebuilds::ahead) EXPECT_GT(ahead, 2);
  EXPECT_GT(total, 150u * 20u);
  skipped = temporal.stats().skipped_checks;
  violations = temporal.stats().bound_violations;
  if (rebuild_count != nullptr) *rebuild_count = temporal.stats().rebuilds;
  // The candidate set is rebuilt only every few frames, and most checks are skipped.
  EXPECT_LT(temporal.stats().rebuilds, 150 / 2 + 150 / std::max(teleport_every, 1));
  EXPECT_GT(temporal.stats().skipped_checks, temporal.stats().checks);
}

template <class T>
class TemporalTest : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(TemporalTest, Dims);

TYPED_TEST(TemporalTest, MatchesBruteForceEveryFrameWithinSpeedBounds) {
  for (const float offset : {0.0f, -3000.0f, 1.0e4f}) {
    std::int64_t skipped = 0, violations = 0;
    run_frames<TypeParam::value>(offset, 0, skipped, violations);
    EXPECT_GT(skipped, 1000) << offset;
    EXPECT_EQ(violations, 0) << offset;
  }
}

TYPED_TEST(TemporalTest, RebuildsAheadOfTheUpdateFindTheSamePairs) {
  // rebuild_now before the motion (as the world runs it beside the bodies' motion), with
  // objects within their bounds and with one teleporting.
  for (const int teleport_every : {0, 7}) {
    for (const float offset : {0.0f, 1.0e4f}) {
      std::int64_t skipped = 0, violations = 0, rebuilt = 0;
      run_frames<TypeParam::value>(offset, teleport_every, skipped, violations, nullptr, 500, 150,
                                   Rebuilds::ahead, &rebuilt);
      EXPECT_GT(skipped, 1000) << offset;
      EXPECT_EQ(violations > 0, teleport_every > 0) << offset;
      // A set built ahead covers a horizon from the update it was built for, so it is rebuilt
      // as often as one built in find_pairs (a set covering a horizon from its build would
      // expire a frame sooner each time).
      std::int64_t skipped_plain = 0, violations_plain = 0, rebuilt_plain = 0;
      run_frames<TypeParam::value>(offset, teleport_every, skipped_plain, violations_plain, nullptr, 500, 150,
                                   Rebuilds::in_find_pairs, &rebuilt_plain);
      EXPECT_LE(rebuilt, rebuilt_plain) << offset << ", teleport every " << teleport_every;
    }
  }
}

TYPED_TEST(TemporalTest, OnSeveralWorkersTheSamePairsAndCounters) {
  // 3000 objects: enough candidates for several ranges per worker; teleports demote objects.
  std::int64_t skipped = 0, violations = 0;
  run_frames<TypeParam::value>(0.0f, 5, skipped, violations, nullptr, 3000, 30);
  for (const int workers : {2, 3, 8}) {
    test::ThreadScheduler scheduler(workers);
    std::int64_t skipped_many = 0, violations_many = 0;
    run_frames<TypeParam::value>(0.0f, 5, skipped_many, violations_many, &scheduler, 3000, 30);
    EXPECT_EQ(skipped_many, skipped) << workers << " workers";
    EXPECT_EQ(violations_many, violations) << workers << " workers";
  }
}

TYPED_TEST(TemporalTest, UpdateInPartsMatchesTheWholeUpdate) {
  // begin_update, update_range over ranges (on 1, 2 and 3 workers) and finish_update: brute
  // force's pairs every frame (run_frames asserts them) and the counters of update(), with
  // teleports breaking bounds and without.
  for (const int teleport_every : {0, 5}) {
    std::int64_t skipped = 0, violations = 0, rebuilt = 0;
    run_frames<TypeParam::value>(0.0f, teleport_every, skipped, violations, nullptr, 700, 60,
                                 Rebuilds::in_find_pairs, &rebuilt);
    EXPECT_EQ(violations > 0, teleport_every > 0);
    for (const int workers : {1, 2, 3}) {
      test::ThreadScheduler scheduler(workers);
      std::int64_t skipped_parts = 0, violations_parts = 0, rebuilt_parts = 0;
      run_frames<TypeParam::value>(0.0f, teleport_every, skipped_parts, violations_parts, &scheduler, 700, 60,
                                   Rebuilds::in_find_pairs, &rebuilt_parts, true);
      EXPECT_EQ(skipped_parts, skipped) << workers << " workers, teleport every " << teleport_every;
      EXPECT_EQ(violations_parts, violations) << workers << " workers";
      EXPECT_EQ(rebuilt_parts, rebuilt) << workers << " workers";
    }
  }
}

TYPED_TEST(TemporalTest, TeleportingObjectIsNotMissed) {
  std::int64_t skipped = 0, violations = 0;
  run_frames<TypeParam::value>(0.0f, 7, skipped, violations);
  EXPECT_GE(violations, 150 / 7);
}

// Objects that change speed (a game's collision response) announce it with set_speed_bounds
// after each frame: raised bounds wake their sleeping pairs, so nothing is missed and no
// rebuild is needed, and checks are still skipped.
TYPED_TEST(TemporalTest, ChangingSpeedsAreSafeWithoutRebuilds) {
  constexpr int D = TypeParam::value;
  std::mt19937 rng(21 + D);
  auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 400, 20.0f, 0.2f, 1.0f),
                                     20.0f, 0.02f);
  TemporalBroadPhaseN<D> temporal;
  temporal.build(world.boxes, bounds_of_world(world), 0.0);
  PairList pairs;
  std::uniform_int_distribution<int> pick(0, 399);
  for (int frame = 1; frame <= 120; ++frame) {
    world.step();
    temporal.update(world.boxes, static_cast<double>(frame));
    temporal.find_pairs(pairs);
    ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
    ASSERT_EQ(pairs, brute_pairs<D>(world.boxes)) << "frame " << frame;
    // Ten objects speed up fivefold, ten slow down, from this frame on.
    for (int k = 0; k < 10; ++k) {
      const std::size_t up = std::size_t(pick(rng)), down = std::size_t(pick(rng));
      if (std::abs(world.velocity[up][0]) < 0.2f) world.velocity[up] *= 5.0f;
      world.velocity[down] *= 0.5f;
    }
    temporal.set_speed_bounds(bounds_of_world(world));
  }
  EXPECT_EQ(temporal.stats().bound_violations, 0);
  EXPECT_GT(temporal.stats().skipped_checks, 0);
  EXPECT_THROW(temporal.set_speed_bounds(std::vector<float>(3, 1.0f)), InvalidInput);
  std::vector<float> bad = bounds_of_world(world);
  bad[7] = -1.0f;
  EXPECT_THROW(temporal.set_speed_bounds(bad), InvalidInput);
}

// A raised bound wakes the object's sleeping pairs at the next find_pairs only: resting boxes
// with small bounds sleep apart for a long time; raising a few bounds makes the next frame check
// their sleeping pairs (fewer checks skipped), the frame after skips as many as before (they
// sleep again), and lowered bounds wake nothing. The pairs are brute force's every frame.
TYPED_TEST(TemporalTest, RaisedBoundsWakeTheirPairsOnce) {
  constexpr int D = TypeParam::value;
  constexpr int kObjects = 400;
  std::mt19937 rng(29 + D);
  const test::Boxes<D> boxes = test::uniform_world<D>(rng, kObjects, D == 2 ? 20.0f : 8.0f, 0.2f, 1.0f);
  std::vector<float> bounds(kObjects, 1e-6f);
  TemporalBroadPhaseN<D> temporal;
  temporal.build(boxes, bounds, 0.0);
  PairList pairs;
  std::int64_t last_skipped = 0;
  // One frame: the bounds (as a game sets them after its response), then the boxes (unmoved),
  // then the pairs; returns the checks skipped in the frame.
  const auto frame = [&](int f) {
    temporal.set_speed_bounds(bounds);
    temporal.update(boxes, static_cast<double>(f));
    temporal.find_pairs(pairs);
    EXPECT_EQ(pairs, brute_pairs<D>(boxes)) << "frame " << f;
    const std::int64_t skipped = temporal.stats().skipped_checks - last_skipped;
    last_skipped = temporal.stats().skipped_checks;
    return skipped;
  };
  frame(1);  // (the rebuild: every candidate checked)
  const std::int64_t resting = frame(2);
  ASSERT_GT(resting, 0);
  ASSERT_EQ(frame(3), resting);
  for (int i = 0; i < kObjects; i += 20) bounds[std::size_t(i)] = 2e-6f;  // raised
  EXPECT_LT(frame(4), resting);
  EXPECT_EQ(frame(5), resting);
  for (int i = 1; i < kObjects; i += 20) bounds[std::size_t(i)] = 5e-7f;  // lowered
  EXPECT_EQ(frame(6), resting);
  EXPECT_EQ(temporal.stats().rebuilds, 1);
}

// The same speed changes on a world large enough for several ranges a worker (update's and
// set_speed_bounds' per-object loops, the wake-up of the raised objects' candidates): every
// frame's pairs and the counters as without workers, and at least one frame's pairs non-empty
// and one raise that woke a sleeping pair (the skipped checks differ from a run without raises).
TYPED_TEST(TemporalTest, SpeedChangesOnWorkersGiveTheSerialAnswer) {
  constexpr int D = TypeParam::value;
  constexpr int kObjects = 6000;
  struct Run {
    std::vector<PairList> pairs;
    std::int64_t skipped = 0, checks = 0, violations = 0;
  };
  const auto run = [](TaskScheduler* scheduler, bool raise) {
    std::mt19937 rng(23 + D);
    auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, kObjects, D == 2 ? 90.0f : 24.0f, 0.2f, 1.0f),
                                       D == 2 ? 90.0f : 24.0f, 0.02f);
    TemporalBroadPhaseN<D> temporal;
    temporal.build(world.boxes, bounds_of_world(world), 0.0);
    std::uniform_int_distribution<int> pick(0, kObjects - 1);
    Run out;
    for (int frame = 1; frame <= 20; ++frame) {
      world.step();
      temporal.update(world.boxes, static_cast<double>(frame), scheduler);
      PairList pairs;
      temporal.find_pairs(pairs, scheduler);
      EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
      out.pairs.push_back(pairs);
      for (int k = 0; k < 200 && raise; ++k) {
        const std::size_t up = std::size_t(pick(rng)), down = std::size_t(pick(rng));
        if (std::abs(world.velocity[up][0]) < 0.2f) world.velocity[up] *= 5.0f;
        world.velocity[down] *= 0.5f;
      }
      temporal.set_speed_bounds(bounds_of_world(world), scheduler);
    }
    out.skipped = temporal.stats().skipped_checks;
    out.checks = temporal.stats().checks;
    out.violations = temporal.stats().bound_violations;
    return out;
  };
  const Run serial = run(nullptr, true);
  ASSERT_GT(serial.pairs.back().size(), 100u);
  EXPECT_EQ(serial.violations, 0);
  EXPECT_NE(run(nullptr, false).skipped, serial.skipped);  // the raises woke pairs
  for (const int workers : {2, 3, 8}) {
    test::ThreadScheduler scheduler(workers);
    const Run many = run(&scheduler, true);
    EXPECT_EQ(many.pairs, serial.pairs) << workers << " workers";
    EXPECT_EQ(many.skipped, serial.skipped) << workers << " workers";
    EXPECT_EQ(many.checks, serial.checks) << workers << " workers";
    EXPECT_EQ(many.violations, serial.violations) << workers << " workers";
  }
}

// A few bullets among slow walkers: the bullets are handled every frame instead of being grown
// into candidates with everything, and the answer stays brute force's.
TYPED_TEST(TemporalTest, FastObjectsAmongSlowOnesAreFoundEveryFrame) {
  constexpr int D = TypeParam::value;
  std::mt19937 rng(31 + D);
  auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 600, 30.0f, 0.2f, 1.0f),
                                     30.0f, 0.02f);
  for (std::size_t i = 0; i < 8; ++i) world.velocity[i * 50] *= 200.0f;  // 4 units per frame
  TemporalBroadPhaseN<D> temporal;
  temporal.build(world.boxes, bounds_of_world(world), 0.0);
  PairList pairs;
  std::size_t fast_pairs = 0;
  for (int frame = 1; frame <= 100; ++frame) {
    world.step();
    temporal.update(world.boxes, static_cast<double>(frame));
    temporal.find_pairs(pairs);
    ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
    const PairList expected = brute_pairs<D>(world.boxes);
    ASSERT_EQ(pairs, expected) << "frame " << frame;
    for (const auto& [a, b] : expected) fast_pairs += (a % 50 == 0 && a < 400) || (b % 50 == 0 && b < 400);
    // Queries see the fast objects too.
    std::vector<int> got;
    temporal.query(world.boxes[100], [&](int id) { got.push_back(id); return true; });
    EXPECT_NE(std::find(got.begin(), got.end(), 100), got.end());
  }
  EXPECT_GT(fast_pairs, 20u);
  EXPECT_EQ(temporal.stats().fast_objects, 8);
  EXPECT_EQ(temporal.stats().bound_violations, 0);
  EXPECT_GT(temporal.stats().skipped_checks, temporal.stats().checks);
  EXPECT_LT(temporal.stats().candidate_pairs, 5000);  // grown bullets would pair with most
}

// Hundreds of fast objects (a third of the world): their pairs among themselves come from a
// grid of their own rather than a sweep along x. Brute force's pairs every frame, on one
// worker and on several.
TYPED_TEST(TemporalTest, ManyFastObjectsFindTheirPairsAmongThemselvesEveryFrame) {
  constexpr int D = TypeParam::value;
  for (const int workers : {1, 3}) {
    std::mt19937 rng(41 + D);
    auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 1800, 30.0f, 0.2f, 1.0f),
                                       30.0f, 0.02f);
    for (std::size_t i = 0; i < world.velocity.size(); i += 3) world.velocity[i] *= 100.0f;
    test::ThreadScheduler scheduler(workers);
    TemporalBroadPhaseN<D> temporal;
    temporal.build(world.boxes, bounds_of_world(world), 0.0);
    PairList pairs;
    std::size_t fast_fast = 0;
    for (int frame = 1; frame <= 40; ++frame) {
      world.step();
      temporal.update(world.boxes, static_cast<double>(frame), &scheduler);
      temporal.find_pairs(pairs, &scheduler);
      ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
      const PairList expected = brute_pairs<D>(world.boxes);
      ASSERT_EQ(pairs, expected) << "frame " << frame << ", " << workers << " workers";
      for (const auto& [a, b] : expected) fast_fast += a % 3 == 0 && b % 3 == 0;
    }
    EXPECT_GT(fast_fast, 400u) << workers << " workers";
    EXPECT_GE(temporal.stats().fast_objects, 256) << workers << " workers";
  }
}

// The named static worlds (uniform, clustered, mixed sizes, huge objects, touching on cell
// boundaries, negative, far from the origin, points, one box, empty) held still for a few
// frames under small speed bounds: every frame brute force's pairs, and the separated
// candidates asleep (their checks skipped) in every world with more than a hundred boxes.
TYPED_TEST(TemporalTest, NamedStaticWorldsMatchBruteForceEveryFrame) {
  constexpr int D = TypeParam::value;
  for (const auto& [name, boxes] : test::static_worlds<D>()) {
    const PairList expected = brute_pairs<D>(boxes);
    TemporalBroadPhaseN<D> temporal;
    temporal.build(boxes, std::vector<float>(boxes.size(), 0.01f), 0.0);
    PairList pairs;
    for (int frame = 0; frame <= 10; ++frame) {
      if (frame > 0) temporal.update(boxes, static_cast<double>(frame));
      temporal.find_pairs(pairs);
      ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
      ASSERT_EQ(pairs, expected) << name << " frame " << frame;
    }
    EXPECT_EQ(temporal.stats().bound_violations, 0) << name;
    // (In "points" every candidate is a pair of coincident points: none can sleep.)
    if (boxes.size() > 100 && name != "points") {
      EXPECT_GT(temporal.stats().skipped_checks, 0) << name;
    }
  }
}

// The same worlds moving for 100 frames (test::moving_worlds: clusters drifting, 0.1- and
// 100-unit boxes, huge boxes, touching on the lattice every other frame, negative, near 1e6),
// each object within its speed bound: every frame brute force's pairs and no bound violation.
// Where the speeds are small against the boxes (the automatic horizon spans more than a frame
// and a half: all but the drifting clusters and the mixed sizes' fast 0.1-unit boxes, which
// rebuild every frame) separated candidates sleep, so checks are skipped.
TYPED_TEST(TemporalTest, NamedMovingWorldsMatchBruteForceEveryFrame) {
  constexpr int D = TypeParam::value;
  int slow_worlds = 0;
  for (auto& [name, world] : test::moving_worlds<D>(300)) {
    TemporalBroadPhaseN<D> temporal;
    temporal.build(world.boxes, bounds_of_world(world), 0.0);
    PairList pairs;
    std::size_t total = 0;
    for (int frame = 1; frame <= 100; ++frame) {
      world.step();
      temporal.update(world.boxes, static_cast<double>(frame));
      temporal.find_pairs(pairs);
      ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
      const PairList expected = brute_pairs<D>(world.boxes);
      total += expected.size();
      ASSERT_EQ(pairs, expected) << name << " frame " << frame;
    }
    EXPECT_GT(total, 100u * 50u) << name;
    EXPECT_EQ(temporal.stats().bound_violations, 0) << name;
    if (temporal.horizon() > 1.5) {
      ++slow_worlds;
      EXPECT_GT(temporal.stats().skipped_checks, 0) << name;
    }
  }
  EXPECT_GE(slow_worlds, 4);
}

TYPED_TEST(TemporalTest, QueriesSeeCurrentBoxes) {
  constexpr int D = TypeParam::value;
  std::mt19937 rng(4);
  auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, 300, 15.0f, 0.2f, 1.0f),
                                     15.0f, 0.1f);
  TemporalBroadPhaseN<D> temporal;
  temporal.build(world.boxes, bounds_of_world(world), 0.0);
  BruteForceN<D> brute;
  PairList pairs;
  int hits = 0;
  for (int frame = 1; frame <= 20; ++frame) {
    world.step();
    if (frame == 10) world.boxes[5].min[0] += 100.0f, world.boxes[5].max[0] += 100.0f;  // teleport
    temporal.update(world.boxes, frame);
    if (frame % 2 == 0) temporal.find_pairs(pairs);  // queries also right between rebuilds
    brute.build(world.boxes);
    const AabbN<D> q = test::box_at<D>(world.boxes[frame].center(), VecN<D>(2.0f));
    std::vector<int> got, want;
    temporal.query(q, [&](int id) { got.push_back(id); return true; });
    brute.query(q, [&](int id) { want.push_back(id); return true; });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << frame;
    got.clear();
    want.clear();
    const RayN<D> ray{world.boxes[frame].center(), VecN<D>(10.0f)};
    temporal.ray_cast(ray, [&](int id, float f) { got.push_back(id); return f; });
    brute.ray_cast(ray, [&](int id, float f) { want.push_back(id); return f; });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << frame;
    hits += !want.empty();
    got.clear();
    want.clear();
    temporal.query_point(world.boxes[frame].max, [&](int id) { got.push_back(id); return true; });
    brute.query_point(world.boxes[frame].max, [&](int id) { want.push_back(id); return true; });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want) << frame;
  }
  EXPECT_EQ(hits, 20);
}

// The queries take the fast objects from the index the last find_pairs left (a grid of their
// own from 256 on, else their order by min x) and test each one after an update drops it:
// every query's ids are brute force's, with a few fast objects and with hundreds, on rays
// along an axis, diagonal and long, and on boxes and points at fast objects.
TYPED_TEST(TemporalTest, QueriesFindFastObjectsWithAndWithoutTheirIndex) {
  constexpr int D = TypeParam::value;
  for (const int every : {60, 3}) {  // 10 fast objects of 600, or 200 of 600 (x 3 for the grid)
    const int objects = every == 60 ? 600 : 1800;
    std::mt19937 rng(53 + D + every);
    auto world = test::moving_world<D>(rng, test::uniform_world<D>(rng, objects, 30.0f, 0.2f, 1.0f),
                                       30.0f, 0.02f);
    for (std::size_t i = 0; i < world.velocity.size(); i += static_cast<std::size_t>(every)) {
      world.velocity[i] *= 200.0f;
    }
    TemporalBroadPhaseN<D> temporal;
    temporal.build(world.boxes, bounds_of_world(world), 0.0);
    BruteForceN<D> brute;
    PairList pairs;
    int fast_hits = 0;
    const auto same = [&](auto&& ours, auto&& theirs, const std::string& what) {
      std::vector<int> got, want;
      ours(got);
      theirs(want);
      std::sort(got.begin(), got.end());
      std::sort(want.begin(), want.end());
      EXPECT_EQ(got, want) << what;
      for (const int id : want) fast_hits += id % every == 0;
    };
    for (int frame = 1; frame <= 12; ++frame) {
      world.step();
      temporal.update(world.boxes, static_cast<double>(frame));
      if (frame % 3 != 0) temporal.find_pairs(pairs);  // every third frame: no index
      brute.build(world.boxes);
      for (int probe = 0; probe < 40; ++probe) {
        const int at = ((probe + frame) * every) % objects;  // a fast object
        const std::string what = std::to_string(every) + " frame " + std::to_string(frame) + " probe " +
                                 std::to_string(probe);
        VecN<D> d(0.0f);
        d[probe % D] = probe % 2 == 0 ? 12.0f : -12.0f;  // along an axis
        if (probe % 3 == 0) d = VecN<D>(probe % 4 == 0 ? 40.0f : -7.0f);  // diagonal
        const RayN<D> ray{world.boxes[static_cast<std::size_t>(at)].center() - 0.5f * d, d};
        same([&](std::vector<int>& out) { temporal.ray_cast(ray, [&](int id, float f) { out.push_back(id); return f; }); },
             [&](std::vector<int>& out) { brute.ray_cast(ray, [&](int id, float f) { out.push_back(id); return f; }); },
             "ray " + what);
        const AabbN<D> q = test::box_at<D>(world.boxes[static_cast<std::size_t>(at)].center(), VecN<D>(1.5f));
        same([&](std::vector<int>& out) { temporal.query(q, [&](int id) { out.push_back(id); return true; }); },
             [&](std::vector<int>& out) { brute.query(q, [&](int id) { out.push_back(id); return true; }); },
             "box " + what);
        const VecN<D> p = world.boxes[static_cast<std::size_t>(at)].min;
        same([&](std::vector<int>& out) { temporal.query_point(p, [&](int id) { out.push_back(id); return true; }); },
             [&](std::vector<int>& out) { brute.query_point(p, [&](int id) { out.push_back(id); return true; }); },
             "point " + what);
      }
    }
    EXPECT_GE(fast_hits, 3 * 12 * 40) << every;  // each query found the fast object it was made at
    if (every == 3) {
      EXPECT_GE(temporal.stats().fast_objects, 256);
    } else {
      EXPECT_GE(temporal.stats().fast_objects, 10);
    }
  }
}

// build and update reject a NaN, an infinity or min > max naming the box, and a rejected
// update leaves the set as it was: the next good update gives brute force's pairs.
TYPED_TEST(TemporalTest, RejectsBadBoxesNamingTheIndex) {
  constexpr int D = TypeParam::value;
  std::mt19937 rng(43);
  const test::Boxes<D> good = test::uniform_world<D>(rng, 150, 6.0f, 0.2f, 1.0f);
  const std::vector<float> speeds(good.size(), 0.1f);
  const PairList expected = brute_pairs<D>(good);
  ASSERT_GT(expected.size(), 50u);
  TemporalBroadPhaseN<D> temporal;
  double time = 0.0;
  PairList pairs;
  for (const test::BadBox<D>& c : test::bad_boxes<D>(static_cast<int>(good.size()))) {
    test::Boxes<D> boxes = good;
    c.spoil(boxes[std::size_t(c.index)]);
    test::expect_rejects_naming_the_box(c, [&] { temporal.build(boxes, speeds, time); });
    temporal.build(good, speeds, time);
    time += 1.0;
    test::expect_rejects_naming_the_box(c, [&] { temporal.update(boxes, time); });
    // The same in parts: finish_update names the box, and nothing has changed.
    test::expect_rejects_naming_the_box(c, [&] {
      temporal.begin_update(boxes.size(), time);
      temporal.update_range(0, static_cast<int>(boxes.size()) / 2, boxes);
      temporal.update_range(static_cast<int>(boxes.size()) / 2, static_cast<int>(boxes.size()), boxes);
      temporal.finish_update(boxes);
    });
    temporal.update(good, time);
    temporal.find_pairs(pairs);
    ASSERT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));  // (find_pairs sorts them)
    EXPECT_EQ(pairs, expected) << "after " << c.what;
    EXPECT_EQ(temporal.stats().bound_violations, 0) << c.what;
  }
}

TYPED_TEST(TemporalTest, RejectsBadSpeedsTimesAndCounts) {
  constexpr int D = TypeParam::value;
  const test::Boxes<D> boxes(4, test::box_at<D>(VecN<D>(0.0f), VecN<D>(1.0f)));
  TemporalBroadPhaseN<D> temporal;
  try {
    temporal.build(boxes, std::vector<float>{1.0f, 1.0f, -1.0f, 1.0f});
    FAIL() << "negative speed accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("speed bound 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(temporal.build(boxes, std::vector<float>{1.0f}), InvalidInput);
  temporal.build(boxes, std::vector<float>(4, 1.0f), 5.0);
  EXPECT_THROW(temporal.update(boxes, 4.0), InvalidInput);
  EXPECT_THROW(temporal.begin_update(boxes.size(), 4.0), InvalidInput);
  EXPECT_THROW(temporal.begin_update(3, 6.0), InvalidInput);
  EXPECT_THROW(temporal.rebuild_now(4.0), InvalidInput);
  EXPECT_THROW(temporal.rebuild_now(std::numeric_limits<double>::quiet_NaN()), InvalidInput);
  EXPECT_FALSE(temporal.rebuild_due(std::numeric_limits<double>::quiet_NaN()));
  // A different count is a new set of objects (each needs a speed bound): update says so.
  try {
    temporal.update(test::Boxes<D>(3, boxes[0]), 6.0);
    FAIL() << "a different count accepted";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("3 given, 4 built"), std::string::npos) << what;
    EXPECT_NE(what.find("call build"), std::string::npos) << what;
  }
  // ... and leaves the set as it was.
  temporal.update(boxes, 6.0);
  EXPECT_EQ(temporal.size(), 4);
  PairList pairs;
  temporal.find_pairs(pairs);
  EXPECT_EQ(pairs.size(), 6u);
  EXPECT_THROW(TemporalBroadPhaseN<D>({.horizon = -1.0}), InvalidInput);
}

}  // namespace
}  // namespace collide
