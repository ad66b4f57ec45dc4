// A fast body against a level shape: the world queries the triangles its sweep's box meets in
// order of a lower bound on their hit and skips those whose bound is past the earliest hit so
// far (world_dim.cpp). The answer must be the brute force's: a time of impact with every
// triangle of the level (the public time_of_impact), the earliest hit taken. Checked on a bumpy
// floor of 4608 triangles, straight down (a few triangles in the box), at a slant (dozens) and
// nearly level (over the 64 the world sorts on the stack).

#include <collide/ccd/time_of_impact.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr int kQuads = 48;        // per side
constexpr float kQuadSize = 0.25f;

struct Floor {
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
};

Floor bumpy_floor() {
  Floor f;
  for (int j = 0; j <= kQuads; ++j) {
    for (int i = 0; i <= kQuads; ++i) {
      const float x = kQuadSize * static_cast<float>(i), z = kQuadSize * static_cast<float>(j);
      f.vertices.push_back(Vec3(x, 0.1f * std::sin(1.3f * x) * std::cos(0.9f * z), z));
    }
  }
  const auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (kQuads + 1) + i); };
  for (int j = 0; j < kQuads; ++j) {
    for (int i = 0; i < kQuads; ++i) {
      f.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      f.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  return f;
}

TEST(LevelCcd, ABulletHitsTheFloorWhereEveryTriangleSaysItDoes) {
  const Floor floor = bumpy_floor();
  const auto mesh = std::make_shared<const TriangleMesh>(make_triangle_mesh(floor.vertices, floor.triangles));
  const Sphere sphere = make_sphere(Vec3(0.0f), 0.15f);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> place(3.0f, 9.0f), heading(0.0f, 2.0f * 3.14159265f);
  int checked = 0;
  // Horizontal speeds per frame: 0 (straight down), 1.5 (a slant), 4 (the box holds over 64).
  for (const float across : {0.0f, 1.5f, 4.0f}) {
    for (int trial = 0; trial < 20; ++trial) {
      const float angle = heading(rng);
      const Vec3 start(place(rng), 0.8f, place(rng));
      const Vec3 d(across * std::cos(angle), -1.2f, across * std::sin(angle));  // per frame
      // The brute force: the earliest hit over every triangle.
      const Sweep3 sweep = Sweep3::from_motion(Transform3{start}, Vec3(0.0f), d, Vec3(0.0f));
      const Sweep3 still = Sweep3::from_motion(Transform3{}, Vec3(0.0f), Vec3(0.0f), Vec3(0.0f));
      ToiResult3 best;
      for (const glm::uvec3& t : floor.triangles) {
        const Triangle tri{{floor.vertices[t.x], floor.vertices[t.y], floor.vertices[t.z]}};
        const ToiResult3 r = time_of_impact(ConvexProxy3(sphere), sweep, ConvexProxy3(tri), still);
        if (r.status == QueryStatus::hit && r.fraction < best.fraction) best = r;
      }
      ASSERT_EQ(best.status, QueryStatus::hit) << "trial " << trial;
      // The world: one step of a bullet; it stops at the hit, reflects, and goes on.
      World3D world;
      world.add_static({.shapes = {mesh}});
      const BodyId id = world.add_body({.shapes = {sphere}, .transform = Transform3{start}, .velocity = d / kDt, .bullet = true});
      world.step(kDt);
      EXPECT_EQ(world.last_step_stats().toi_hits, 1) << "across " << across << ", trial " << trial;
      const Vec3 n = best.normal;
      const Vec3 reflected = d - 2.0f * dot(d, n) * n;
      const Vec3 expected = start + best.fraction * d + (1.0f - best.fraction) * reflected;
      const Vec3 p = world.transform(id).p;
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(p[k], expected[k], 2e-3f) << "across " << across << ", trial " << trial << ", axis " << k;
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, 60);
}

}  // namespace
}  // namespace collide
