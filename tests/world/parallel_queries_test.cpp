// World queries on the workers: raycast_batch gives, ray for ray, what raycast gives, on one
// thread and on several (tests/support/test_scheduler.hpp), and refuses bad input up front.

#include <collide/core/error.hpp>
#include <collide/world/world2d.hpp>

#include "support/random.hpp"
#include "support/test_scheduler.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <vector>

namespace collide {
namespace {

World2D random_world(std::mt19937& rng, TaskScheduler* scheduler) {
  WorldOptions options;
  options.scheduler = scheduler;
  World2D world(options);
  for (int i = 0; i < 40; ++i) {
    StaticDef def;
    def.shapes = {make_box({test::uniform(rng, 0.5f, 3.0f), test::uniform(rng, 0.1f, 1.0f)})};
    def.transform = Transform::from(test::random_point(rng, 40.0f), test::uniform(rng, -3.0f, 3.0f));
    def.user_id = static_cast<std::uint64_t>(i);
    world.add_static(def);
  }
  for (int i = 0; i < 300; ++i) {
    BodyDef def;
    def.shapes = {make_circle({0.0f, 0.0f}, test::uniform(rng, 0.2f, 0.8f))};
    def.transform = Transform::from(test::random_point(rng, 40.0f), 0.0f);
    def.velocity = test::random_point(rng, 5.0f);
    world.add_body(def);
  }
  return world;
}

bool same_hit(const std::optional<WorldRayHit>& a, const std::optional<WorldRayHit>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  return a->collider.key() == b->collider.key() && std::memcmp(&a->hit.fraction, &b->hit.fraction, sizeof(float)) == 0 &&
         std::memcmp(&a->hit.point, &b->hit.point, sizeof(Vec2)) == 0;
}

TEST(WorldQueriesParallel, RaycastBatchMatchesRaycastOnAnyWorkerCount) {
  for (const int workers : {1, 2, 3, 8}) {
    std::mt19937 rng(77);
    test::ThreadScheduler scheduler(workers);
    World2D world = random_world(rng, &scheduler);
    world.step(1.0f / 60.0f);  // bodies in the broad phase, as in a game's frame
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i) rays.push_back(Ray{test::random_point(rng, 45.0f), test::random_point(rng, 60.0f)});
    std::vector<std::optional<WorldRayHit>> hits(rays.size());
    world.raycast_batch(rays, hits);
    int hit_count = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      ASSERT_TRUE(same_hit(hits[i], world.raycast(rays[i]))) << workers << " workers, ray " << i;
      hit_count += hits[i].has_value() ? 1 : 0;
    }
    EXPECT_GT(hit_count, 500) << workers << " workers";
  }
}

TEST(WorldQueriesParallel, RaycastBatchRefusesBadInputBeforeCasting) {
  std::mt19937 rng(5);
  World2D world = random_world(rng, nullptr);
  std::vector<Ray> rays(3, Ray{{0.0f, 0.0f}, {1.0f, 0.0f}});
  std::vector<std::optional<WorldRayHit>> hits(2);
  EXPECT_THROW(world.raycast_batch(rays, hits), InvalidInput);
  hits.resize(3);
  rays[2].translation.x = std::numeric_limits<float>::quiet_NaN();
  try {
    world.raycast_batch(rays, hits);
    FAIL() << "a NaN ray was cast";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("ray 2"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(hits[0].has_value());  // nothing cast
}

}  // namespace
}  // namespace collide
