// The world's independent end-of-step check (world_check.cpp) must see a body that ends a step
// inside static geometry: a check that finds nothing would pass every "tunnelled == 0" test in
// the suite. A body wedged in a gap narrower than itself cannot be pushed out (the jam rule puts
// it back where it started, still inside), so the check must count it: against convex pieces
// (2D and 3D) and against a level's triangles, many small ones (the check's grid holds each
// triangle) and one large (a triangle covering more cells than the grid bins).

#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;

TEST(WorldCheck, CountsABodyWedgedBetweenConvexStatics2D) {
  World2D world;
  for (const float side : {1.0f, -1.0f}) {
    world.add_static({.shapes = {make_box({1.0f, 2.0f})}, .transform = Transform::from({side * 1.3f, 0.0f}, 0.0f)});
  }
  world.add_body({.shapes = {make_circle({0.0f, 0.0f}, 0.5f)}});
  world.step(kDt);
  EXPECT_EQ(world.last_step_stats().tunnelled, 1);
  EXPECT_NEAR(world.last_step_stats().max_static_depth, 0.2f, 1e-3f);
}

TEST(WorldCheck, CountsABodyWedgedBetweenConvexStatics3D) {
  World3D world;
  for (const float side : {1.0f, -1.0f}) {
    world.add_static({.shapes = {make_box(Vec3(1.0f, 2.0f, 2.0f))}, .transform = Transform3{Vec3(side * 1.3f, 0.0f, 0.0f)}});
  }
  world.add_body({.shapes = {make_sphere(Vec3(0.0f), 0.5f)}});
  world.step(kDt);
  EXPECT_EQ(world.last_step_stats().tunnelled, 1);
  EXPECT_NEAR(world.last_step_stats().max_static_depth, 0.2f, 1e-3f);
}

/// Two parallel walls x = +-0.3, facing each other, each split into `cells` x `cells` quads
/// (two triangles each) over [-size, size] in y and z.
std::shared_ptr<const TriangleMesh> walls(int cells, float size) {
  std::vector<Vec3> v;
  std::vector<glm::uvec3> t;
  const float step = 2.0f * size / static_cast<float>(cells);
  for (const float x : {0.3f, -0.3f}) {
    for (int j = 0; j < cells; ++j) {
      for (int i = 0; i < cells; ++i) {
        const float y0 = -size + step * static_cast<float>(j), z0 = -size + step * static_cast<float>(i);
        const auto base = static_cast<std::uint32_t>(v.size());
        v.insert(v.end(), {Vec3(x, y0, z0), Vec3(x, y0 + step, z0), Vec3(x, y0 + step, z0 + step), Vec3(x, y0, z0 + step)});
        t.push_back({base, base + 1, base + 2});
        t.push_back({base, base + 2, base + 3});
      }
    }
  }
  return std::make_shared<const TriangleMesh>(make_triangle_mesh(v, t));
}

TEST(WorldCheck, CountsABodyWedgedBetweenLevelTriangles) {
  // 40 x 40 quads of 0.1 (the check's grid bins each triangle), then a single quad 2000 across
  // (beyond the grid's cells per item: tested against every body).
  for (const auto& [cells, size] : {std::pair{40, 2.0f}, std::pair{1, 1000.0f}}) {
    World3D world;
    world.add_static({.shapes = {walls(cells, size)}});
    world.add_body({.shapes = {make_sphere(Vec3(0.0f, 0.03f, 0.01f), 0.5f)}});
    world.step(kDt);
    EXPECT_EQ(world.last_step_stats().tunnelled, 1) << cells << " quads per side";
    EXPECT_NEAR(world.last_step_stats().max_static_depth, 0.2f, 1e-3f) << cells << " quads per side";
  }
}

}  // namespace
}  // namespace collide
