// The batched polygon-circle contact (four pairs side by side in lanes) against the single call
// it promises to equal bit for bit, and against an independent truth: the circle centre's
// signed distance to the polygon's core by brute force over its edges.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <collide/core/error.hpp>
#include <collide/narrow/contact.hpp>

#include "contact_routines.hpp"
#include "support/bitwise_equal.hpp"
#include "support/test_util.hpp"

namespace collide {
namespace {

using test::bitwise_equal;

/// Polygons of every size class the lanes see side by side: segments' two sides (2 vertices,
/// built by hand as inside collide), boxes, 3- to 8-gons inline, and 9- to 64-gons on the heap;
/// rounded one time in three.
Polygon random_polygon_any_size(std::mt19937& rng) {
  const float radius = rng() % 3 == 0 ? test::uniform(rng, 0.01f, 0.3f) : 0.0f;
  switch (rng() % 8) {
    case 0:
      return detail::two_vertex_polygon(test::random_point(rng, 0.6f), test::random_point(rng, 0.6f),
                                        radius);
    case 1:
      return make_box({test::uniform(rng, 0.1f, 0.6f), test::uniform(rng, 0.1f, 0.6f)}, radius);
    case 2:
      return test::random_polygon(rng, 9 + static_cast<int>(rng() % 56), 0.6f, radius);
    default:
      return test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 0.6f, radius);
  }
}

struct Cases {
  std::vector<Polygon> polygons;
  std::vector<Circle> circles;
  std::vector<PolygonCirclePair> pairs;
};

/// `count` pairs near the origin or (one in five) 1e4 from it; one circle in nine centred on a
/// polygon vertex exactly, one in seven of radius zero.
Cases random_cases(std::mt19937& rng, int count) {
  Cases c;
  c.polygons.reserve(static_cast<std::size_t>(count));
  c.circles.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    c.polygons.push_back(random_polygon_any_size(rng));
    const float r = i % 7 == 0 ? 0.0f : test::uniform(rng, 0.02f, 0.5f);
    c.circles.push_back(Circle{test::random_point(rng, 0.2f), r});
    const Vec2 base = i % 5 == 0 ? test::random_point(rng, 1e4f) : Vec2{0.0f, 0.0f};
    Transform xa = Transform::from(base + test::random_point(rng, 0.2f), test::uniform(rng, -3.0f, 3.0f));
    Transform xb = Transform::from(base + test::random_point(rng, 1.2f), test::uniform(rng, -3.0f, 3.0f));
    if (i % 9 == 0) {
      // B's centre exactly on one of A's vertices: both frames unturned, A's at the origin, the
      // circle's centre at B's (the single call's "centre on the vertex" case, which for a
      // segment's two sides takes the face normal).
      const Polygon& a = c.polygons.back();
      xa = Transform{};
      xb = Transform{a.vertices[static_cast<std::size_t>(rng() % static_cast<unsigned>(a.count))], Rot2{}};
      c.circles.back().center = Vec2{0.0f, 0.0f};
    }
    c.pairs.push_back({&c.polygons.back(), xa, &c.circles.back(), xb});  // (reserved: addresses stay)
  }
  return c;
}

TEST(ContactBatch, PolygonCircleMatchesTheSingleCallBitwise) {
  std::mt19937 rng(20261130);
  constexpr int kCases = 40003;  // not a multiple of four: the tail goes one by one
  const Cases c = random_cases(rng, kCases);
  std::vector<Manifold> batch(c.pairs.size());
  contact(c.pairs, batch);
  int touching = 0, vertex_points = 0, edge_points = 0, segments = 0, large = 0;
  for (std::size_t i = 0; i < c.pairs.size(); ++i) {
    const PolygonCirclePair& p = c.pairs[i];
    const Manifold single = contact(*p.polygon, p.polygon_xf, *p.circle, p.circle_xf);
    ASSERT_TRUE(bitwise_equal(batch[i], single))
        << "pair " << i << ": counts " << batch[i].count << " vs " << single.count << ", polygon of "
        << p.polygon->count << " vertices";
    if (single.count == 0) continue;
    ++touching;
    (single.points[0].id.type_a == FeatureType::vertex ? vertex_points : edge_points) += 1;
    segments += p.polygon->count == 2 ? 1 : 0;
    large += p.polygon->count > kInlinePolygonVertices ? 1 : 0;
  }
  // Both outcomes and every region are exercised, with segments and heap-held polygons.
  EXPECT_GT(touching, kCases / 4);
  EXPECT_LT(touching, kCases * 3 / 4);
  EXPECT_GT(vertex_points, kCases / 20);
  EXPECT_GT(edge_points, kCases / 20);
  EXPECT_GT(segments, kCases / 50);
  EXPECT_GT(large, kCases / 50);
}

/// The signed distance from `c` (A's frame) to polygon `a`'s core: the distance to the nearest
/// edge, negative inside (every edge's separation negative); for a segment's two sides, the
/// distance to the segment.
float core_signed_distance(const Polygon& a, Vec2 c) {
  float nearest = std::numeric_limits<float>::infinity();
  bool inside = a.count > 2;
  for (int i = 0; i < a.count; ++i) {
    const Vec2 v1 = a.vertices[static_cast<std::size_t>(i)];
    const Vec2 v2 = a.vertices[static_cast<std::size_t>(next_vertex(i, a.count))];
    const Vec2 e = v2 - v1;
    const float t = std::clamp(dot(c - v1, e) / dot(e, e), 0.0f, 1.0f);
    nearest = std::min(nearest, length(c - (v1 + t * e)));
    if (dot(a.normals[static_cast<std::size_t>(i)], c - v1) > 0.0f) inside = false;
  }
  return inside ? -nearest : nearest;
}

TEST(ContactBatch, PolygonCircleDepthsAgreeWithBruteForceDistance) {
  std::mt19937 rng(7);
  constexpr int kCases = 20000;
  Cases c = random_cases(rng, kCases);
  std::vector<Manifold> batch(c.pairs.size());
  contact(c.pairs, batch);
  int checked = 0;
  for (std::size_t i = 0; i < c.pairs.size(); ++i) {
    const PolygonCirclePair& p = c.pairs[i];
    // The centre in A's frame by an independent route (double precision).
    const Vec2 world = transform_point(p.circle_xf, p.circle->center);
    const double dx = double(world.x) - double(p.polygon_xf.p.x), dy = double(world.y) - double(p.polygon_xf.p.y);
    const Vec2 local{float(double(p.polygon_xf.q.c) * dx + double(p.polygon_xf.q.s) * dy),
                     float(-double(p.polygon_xf.q.s) * dx + double(p.polygon_xf.q.c) * dy)};
    const float gap = core_signed_distance(*p.polygon, local) - p.polygon->radius - p.circle->radius;
    // Coordinates up to 1e4: a few ulps of them apart.
    const float tolerance = 1e-5f * (1.0f + std::abs(p.polygon_xf.p.x) + std::abs(p.polygon_xf.p.y));
    if (std::abs(gap) <= tolerance) continue;  // touching within rounding: either answer
    ASSERT_EQ(batch[i].count > 0, gap < 0.0f) << "pair " << i << ", gap " << gap;
    if (batch[i].count == 0) continue;
    EXPECT_NEAR(batch[i].points[0].depth, -gap, 2.0f * tolerance) << "pair " << i;
    EXPECT_NEAR(length(batch[i].normal), 1.0f, 1e-5f) << "pair " << i;
    ++checked;
  }
  EXPECT_GT(checked, kCases / 4);
}

TEST(ContactBatch, WritesOnlyAsManyManifoldsAsBothSpansHold) {
  std::mt19937 rng(11);
  const Cases c = random_cases(rng, 10);
  // A shorter output is a caller's error (COLLIDE_ASSERT in debug builds, told to go on here):
  // the pairs beyond it are left alone, nothing is written past the span.
  const AssertHandler before = set_assert_handler([](const char*, const char*, const char*, int) { return true; });
  Manifold sentinel;
  sentinel.count = 7;
  std::vector<Manifold> out(10, sentinel);
  contact(c.pairs, std::span<Manifold>(out.data(), 6));
  set_assert_handler(before);
  for (std::size_t i = 0; i < 6; ++i) {
    const PolygonCirclePair& p = c.pairs[i];
    EXPECT_TRUE(bitwise_equal(out[i], contact(*p.polygon, p.polygon_xf, *p.circle, p.circle_xf))) << i;
  }
  for (std::size_t i = 6; i < 10; ++i) EXPECT_EQ(out[i].count, 7) << i;
  // No pairs: nothing written.
  contact(std::span<const PolygonCirclePair>{}, out);
  EXPECT_EQ(out[9].count, 7);
}

}  // namespace
}  // namespace collide
