// The embedded 3D scene grows with --bodies (issue 20): rooms of 40 x 12 x 40 on a grid, 500
// bodies each at --density 1, spawned room after room; one room up to 500 x density bodies. A
// grown scene steps to the same state and events on 1, 2, 3 and 8 threads; a request for more
// rooms than kMaxRooms is refused with a message naming the options.

#include "scene3d.hpp"

#include <gtest/gtest.h>

#include <collide/core/error.hpp>

#include <cmath>
#include <cstdint>
#include <string>

namespace collide::cli {
namespace {

RunOptions options3d(int bodies, float density = 1.0f) {
  RunOptions o;
  o.three_d = true;
  o.bodies = bodies;
  o.density = density;
  o.characters = 0;
  o.progress = false;
  return o;
}

TEST(Run3DRooms, TheSceneGrowsWithBodiesAtItsDensity) {
  const Scene3D one = make_scene3d(options3d(500));
  EXPECT_FLOAT_EQ(one.level.max.x - one.level.min.x, 40.0f);
  EXPECT_FLOAT_EQ(one.level.max.z - one.level.min.z, 40.0f);
  EXPECT_EQ(one.world.body_count(), 500);
  const int room_statics = one.world.static_count();
  // 2000 bodies: 4 rooms, 2 x 2, 2 apart.
  const Scene3D four = make_scene3d(options3d(2000));
  EXPECT_FLOAT_EQ(four.level.max.x - four.level.min.x, 82.0f);
  EXPECT_FLOAT_EQ(four.level.max.z - four.level.min.z, 82.0f);
  EXPECT_FLOAT_EQ(four.level.max.y - four.level.min.y, one.level.max.y - one.level.min.y);
  EXPECT_EQ(four.world.static_count(), 4 * room_statics);
  EXPECT_EQ(four.world.body_count(), 2000);
  // Every body in a room (none in the gaps between them).
  for (const BodyId id : four.world.body_ids()) {
    const Vec3 p = four.world.transform(id).p;
    const float gx = std::fmod(p.x + 20.0f, 42.0f), gz = std::fmod(p.z + 20.0f, 42.0f);
    EXPECT_LE(gx, 40.0f) << p.x;
    EXPECT_LE(gz, 40.0f) << p.z;
  }
  // At density 4 the same bodies fit one room.
  EXPECT_FLOAT_EQ(make_scene3d(options3d(2000, 4.0f)).level.max.x, one.level.max.x);
}

TEST(Run3DRooms, AGrownSceneIsTheSameForEveryThreadCount) {
  std::uint64_t state = 0, events = 0;
  std::int64_t event_count = 0;
  for (const int threads : {1, 2, 3, 8}) {
    RunOptions o = options3d(2000);
    o.threads = threads;
    Scene3D s = make_scene3d(o);
    ASSERT_EQ(s.scheduler->worker_count(), threads);
    std::uint64_t h = 1469598103934665603ull;
    std::int64_t count = 0;
    for (int f = 0; f < 20; ++f) {
      s.world.step(o.dt);
      for (const ContactEvent3& e : s.world.events()) {
        const std::uint64_t keys[] = {e.a.key(), e.b.key(), static_cast<std::uint64_t>(e.type)};
        for (const std::uint64_t k : keys) h = (h ^ k) * 1099511628211ull;
        ++count;
      }
    }
    EXPECT_EQ(s.world.total_stats().tunnelled, 0) << threads << " threads";
    EXPECT_EQ(s.world.total_stats().escaped, 0) << threads << " threads";
    if (threads == 1) {
      state = s.world.state_hash();
      events = h;
      event_count = count;
      EXPECT_GT(count, 0);
    } else {
      EXPECT_EQ(s.world.state_hash(), state) << threads << " threads";
      EXPECT_EQ(h, events) << threads << " threads";
      EXPECT_EQ(count, event_count) << threads << " threads";
    }
  }
}

TEST(Run3DRooms, MoreRoomsThanTheLimitAreRefusedNamingTheOptions) {
  try {
    (void)make_scene3d(options3d(1000000, 0.01f));  // 200000 rooms
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--bodies 1000000"), std::string::npos) << what;
    EXPECT_NE(what.find("rooms"), std::string::npos) << what;
    EXPECT_NE(what.find("raise --density"), std::string::npos) << what;
  }
  EXPECT_THROW((void)make_scene3d(options3d(10, 0.0f)), InvalidInput);
}

}  // namespace
}  // namespace collide::cli
