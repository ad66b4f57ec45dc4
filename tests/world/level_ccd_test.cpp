// A fast body against a level shape: the world queries the triangles its sweep's box meets in
// order of a lower bound on their hit and skips those whose bound is past the earliest hit so
// far (world_dim.cpp). The answer must be the brute force's: a time of impact with every
// triangle of the level (the public time_of_impact), the earliest hit taken. Checked on a bumpy
// floor of 4608 triangles, straight down (a few triangles in the box), at a slant (dozens) and
// nearly level (over the 64 the world sorts on the stack); then turning boxes and capsules
// skimming a height field, passing beside its triangles (the cull's rounded-triangle test
// decides most of them) or through its plane, hitting it or not.

#include <collide/ccd/time_of_impact.hpp>
#include <collide/shape/height_field.hpp>
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

TEST(LevelCcd, TurningBulletsSkimmingAHeightFieldHitWhereEveryTriangleSaysTheyDo) {
  constexpr int kSamples = 49;
  std::vector<float> heights;
  for (int j = 0; j < kSamples; ++j) {
    for (int i = 0; i < kSamples; ++i) {
      heights.push_back(0.1f * std::sin(1.3f * kQuadSize * i) * std::cos(0.9f * kQuadSize * j));
    }
  }
  const auto field = std::make_shared<const HeightField>(
      make_height_field(kSamples, kSamples, heights, Vec2(kQuadSize), Vec3(0.0f)));
  const Box box = make_box(Vec3(0.2f, 0.05f, 0.1f));
  const Capsule3 capsule = make_capsule(Vec3(-0.15f, 0.0f, 0.0f), Vec3(0.15f, 0.0f, 0.0f), 0.05f);
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> place(3.0f, 9.0f), heading(0.0f, 2.0f * 3.14159265f),
      height(0.1f, 0.45f), sink(-0.3f, 0.05f), spin(-4.0f, 4.0f);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 80; ++trial) {
    const Shape3D shape = trial % 2 == 0 ? Shape3D(box) : Shape3D(capsule);
    const float angle = heading(rng);
    const Transform3 start{Vec3(place(rng), height(rng), place(rng)),
                           glm::angleAxis(heading(rng), glm::normalize(Vec3(0.3f, 1.0f, -0.5f)))};
    // Per frame; every third one steeply through the floor's plane (ending farther below it
    // than it started above).
    const Vec3 d(4.0f * std::cos(angle), trial % 3 == 2 ? -2.5f : sink(rng), 4.0f * std::sin(angle));
    const Vec3 spin_rate(spin(rng), spin(rng), spin(rng));                     // radians per second
    const Sweep3 sweep = Sweep3::from_motion(start, Vec3(0.0f), d, spin_rate * kDt);
    const Sweep3 still = Sweep3::from_motion(Transform3{}, Vec3(0.0f), Vec3(0.0f), Vec3(0.0f));
    ToiResult3 best;
    bool started_inside = false;
    for (std::uint32_t t = 0; t < 2u * (kSamples - 1) * (kSamples - 1); ++t) {
      const Triangle tri = field->triangle(t);
      const ToiResult3 r = time_of_impact(ConvexProxy3(shape), sweep, ConvexProxy3(tri), still);
      started_inside |= r.status == QueryStatus::overlapped;
      if (r.status == QueryStatus::hit && r.fraction < best.fraction) best = r;
    }
    if (started_inside) continue;  // not a sweep from free space
    World3D world;
    world.add_static({.shapes = {field}});
    const BodyId id = world.add_body(
        {.shapes = {shape}, .transform = start, .velocity = d / kDt, .angular_velocity = spin_rate, .bullet = true});
    world.step(kDt);
    const Vec3 p = world.transform(id).p;
    if (best.status != QueryStatus::hit) {
      ++misses;
      EXPECT_EQ(world.last_step_stats().toi_hits, 0) << "trial " << trial;
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], start.p[k] + d[k], 1e-4f) << "trial " << trial << ", axis " << k;
      continue;
    }
    ++hits;
    EXPECT_GE(world.last_step_stats().toi_hits, 1) << "trial " << trial;
    // Where the first hit stops it (its centre on the sweep's path: the body turns about it).
    ASSERT_FALSE(world.contacts().empty()) << "trial " << trial;
    const Vec3 n = best.normal;
    const Vec3 reflected = d - 2.0f * dot(d, n) * n;
    const Vec3 expected = start.p + best.fraction * d + (1.0f - best.fraction) * reflected;
    if (world.last_step_stats().toi_hits == 1) {
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], expected[k], 2e-3f) << "trial " << trial << ", axis " << k;
    }
  }
  // Both kinds happen, so the cull is asked both ways.
  EXPECT_GE(hits, 15);
  EXPECT_GE(misses, 15);
}

TEST(LevelCcd, ATurningBulletThroughALargeTriangleHitsItWhereItSays) {
  // A wall of two triangles 20 units wide, far larger than the bullet: a bullet crossing it in
  // the middle passes none of its edges, so only the face can say it comes near.
  const std::vector<Vec3> vertices{{-10.0f, -10.0f, 0.0f}, {10.0f, -10.0f, 0.0f}, {10.0f, 10.0f, 0.0f}, {-10.0f, 10.0f, 0.0f}};
  const std::vector<glm::uvec3> triangles{{0, 1, 2}, {0, 2, 3}};
  const auto mesh = std::make_shared<const TriangleMesh>(make_triangle_mesh(vertices, triangles));
  const ConvexHull hull = make_convex_hull(std::vector<Vec3>{{0.2f, 0.0f, 0.0f}, {-0.1f, 0.15f, 0.05f},
                                                             {-0.1f, -0.15f, 0.05f}, {0.0f, 0.0f, -0.2f}});
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> across(-5.0f, 5.0f), away(0.4f, 3.0f), spin(-4.0f, 4.0f), sideways(-2.0f, 2.0f);
  for (int trial = 0; trial < 40; ++trial) {
    const float side = trial % 2 == 0 ? 1.0f : -1.0f;  // from either side of the wall
    const Transform3 start{Vec3(across(rng), across(rng), side * away(rng))};
    const Vec3 d(sideways(rng), sideways(rng), -side * 7.0f);  // ends far beyond the wall
    const Vec3 spin_rate(spin(rng), spin(rng), spin(rng));
    const Sweep3 sweep = Sweep3::from_motion(start, hull.centroid, d, spin_rate * kDt);
    const Sweep3 still = Sweep3::from_motion(Transform3{}, Vec3(0.0f), Vec3(0.0f), Vec3(0.0f));
    ToiResult3 best;
    for (const glm::uvec3& t : triangles) {
      const Triangle tri{{vertices[t.x], vertices[t.y], vertices[t.z]}};
      const ToiResult3 r = time_of_impact(ConvexProxy3(hull), sweep, ConvexProxy3(tri), still);
      if (r.status == QueryStatus::hit && r.fraction < best.fraction) best = r;
    }
    ASSERT_EQ(best.status, QueryStatus::hit) << "trial " << trial;
    World3D world;
    world.add_static({.shapes = {mesh}});
    const BodyId id = world.add_body(
        {.shapes = {hull}, .transform = start, .velocity = d / kDt, .angular_velocity = spin_rate, .bullet = true});
    world.step(kDt);
    EXPECT_EQ(world.last_step_stats().toi_hits, 1) << "trial " << trial;
    // It bounces back: its centre ends on the side it came from.
    EXPECT_GT(side * transform_point(world.transform(id), hull.centroid).z, 0.0f) << "trial " << trial;
  }
}

}  // namespace
}  // namespace collide
