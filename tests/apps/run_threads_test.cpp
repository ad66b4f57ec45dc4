// The step on several threads (issue 20): the state hash and every contact event identical for
// 1, 2, 3 and 8 threads (oneTBB, more threads than this machine has cores included) on the
// default scene, a Tiled map and the bullets scene, and a default scene grown to several tiles;
// spawning that cannot fit stops with the count it placed.

#include "run.hpp"

#include <gtest/gtest.h>

#include <collide/core/error.hpp>

#include <chrono>
#include <cstdint>
#include <fstream>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

/// FNV-1a over the bytes of each event (type, colliders, user ids, manifold, sensor flag).
struct EventHash {
  std::uint64_t h = 1469598103934665603ull;
  std::int64_t count = 0;
  void mix(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      h ^= bytes[i];
      h *= 1099511628211ull;
    }
  }
  void add(const ContactEvent& e) {
    const std::uint64_t keys[] = {e.a.key(), e.b.key(), e.user_a, e.user_b};
    mix(keys, sizeof keys);
    const auto type = static_cast<std::uint8_t>(e.type);
    mix(&type, 1);
    mix(&e.manifold.normal, sizeof e.manifold.normal);
    for (int k = 0; k < e.manifold.count; ++k) {
      mix(&e.manifold.points[k].point, sizeof(Vec2));
      mix(&e.manifold.points[k].depth, sizeof(float));
    }
    ++count;
  }
};

struct Outcome {
  std::uint64_t state = 0;
  std::uint64_t events = 0;
  std::int64_t event_count = 0;
  std::int64_t tunnelled = 0;
  int bodies = 0;
};

Outcome run_frames(RunOptions o, int threads, int frames) {
  o.threads = threads;
  Scene scene = make_scene(o);
  EXPECT_EQ(scene.scheduler->worker_count(), threads);
  EventHash events;
  for (int f = 0; f < frames; ++f) {
    scene.world.step(o.dt);
    for (const ContactEvent& e : scene.world.events()) events.add(e);
  }
  return {scene.world.state_hash(), events.h, events.count, scene.world.total_stats().tunnelled,
          scene.world.body_count()};
}

void expect_same_for_every_thread_count(const RunOptions& o, int frames) {
  const Outcome one = run_frames(o, 1, frames);
  EXPECT_GT(one.event_count, 0) << o.input;
  EXPECT_EQ(one.tunnelled, 0) << o.input;
  for (const int threads : {2, 3, 8}) {
    const Outcome many = run_frames(o, threads, frames);
    EXPECT_EQ(many.state, one.state) << o.input << ", " << threads << " threads";
    EXPECT_EQ(many.events, one.events) << o.input << ", " << threads << " threads";
    EXPECT_EQ(many.event_count, one.event_count) << o.input << ", " << threads << " threads";
  }
}

RunOptions options(std::string input, int bodies) {
  RunOptions o;
  o.input = std::move(input);
  o.bodies = bodies;
  o.progress = false;
  return o;
}

TEST(RunThreads, DefaultSceneSameForEveryThreadCount) {
  expect_same_for_every_thread_count(options("default", -1), 60);
}

TEST(RunThreads, BulletsSceneSameForEveryThreadCount) {
  expect_same_for_every_thread_count(options("bullets", -1), 60);
}

TEST(RunThreads, MapSameForEveryThreadCount) {
  const fs::path map = fs::path(COLLIDE_DATA_DIR) / "tiled/mapeditor-tiled/sticker-knight/map/sandbox.tmx";
  expect_same_for_every_thread_count(options(map.string(), 2000), 60);
}

TEST(RunThreads, GrownDefaultSceneSameForEveryThreadCount) {
  // 4 tiles at density 2: 24000 bodies in a 640 x 360 world.
  RunOptions o = options("default", 24000);
  o.density = 2.0f;
  expect_same_for_every_thread_count(o, 20);
}

TEST(RunThreads, DefaultSceneGrowsWithBodiesAtItsDensity) {
  // Up to 3000 bodies: the one 320 x 180 tile it always was; beyond, tiles at the same density.
  const Scene one = make_scene(options("default", 3000));
  EXPECT_FLOAT_EQ(one.bounds.max.x - one.bounds.min.x, 320.0f);
  EXPECT_FLOAT_EQ(one.bounds.max.y - one.bounds.min.y, 180.0f);
  const Scene nine = make_scene(options("default", 27000));  // 9 tiles: 3 x 3
  EXPECT_FLOAT_EQ(nine.bounds.max.x - nine.bounds.min.x, 960.0f);
  EXPECT_FLOAT_EQ(nine.bounds.max.y - nine.bounds.min.y, 540.0f);
  EXPECT_EQ(nine.world.body_count(), 27000);
  EXPECT_EQ(nine.world.static_count(), 4 + 9 * 26);  // walls, then 15 obstacles, 8 thin walls, 3 sensors a tile
  RunOptions dense = options("default", 27000);
  dense.density = 9.0f;  // one tile
  EXPECT_FLOAT_EQ(make_scene(dense).bounds.max.x, 160.0f);
}

TEST(RunThreads, SpawningThatCannotFitStopsWithTheCountPlaced) {
  // A million bodies of radius 1 to 1.5 asked of a 20 x 20 box: a few dozen fit. Spawning gives
  // up after kSpawnMissesInARow tries in a row find no room, within a bounded time, and reports
  // what it placed (the summary says "N asked, no free space for more").
  const std::string path = ::testing::TempDir() + "crowded_scene.json";
  std::ofstream(path) << R"({"bounds": [-10, -10, 10, 10], "spawn": {"count": 1000000, "radius": [1, 1.5]}})";
  const auto start = std::chrono::steady_clock::now();
  const Scene s = make_scene(options(path, -1));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(s.requested_bodies, 1000000);
  EXPECT_GT(s.world.body_count(), 10);
  EXPECT_LT(s.world.body_count(), 200);
  // A watchdog, not a benchmark: the old rule (200 tries per body asked) took minutes here.
  EXPECT_LT(seconds, 20.0);
}

TEST(RunThreads, BadThreadsAndDensityAreRefused) {
  RunOptions o = options("default", 10);
  o.threads = -1;
  EXPECT_THROW((void)make_scene(o), InvalidInput);
  o.threads = 1;
  o.density = 0.0f;
  EXPECT_THROW((void)make_scene(o), InvalidInput);
}

}  // namespace
}  // namespace collide::cli
