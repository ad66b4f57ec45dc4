// The small-polygon front end of contact_polygons (pairs of at most eight vertices each, in
// registers, one or two groups of four) against the general front end (4-wide arrays) that
// every pair took before: the manifolds must be bitwise equal, for boxes, triangles, quads,
// 5- to 8-gons, capsules and segments (2-vertex polygons), rounded or not, overlapping,
// touching, apart, and far from the origin. Larger polygons take the general path only.
// Capsules and segments as B skip their polygon (contact_polygon_segment): the same check.

#include <gtest/gtest.h>

#include <random>
#include <utility>

#include <collide/narrow/contact.hpp>
#include <collide/shape/capsule.hpp>
#include <collide/shape/segment.hpp>

#include "contact_routines.hpp"
#include "support/bitwise_equal.hpp"
#include "support/test_util.hpp"

namespace collide {
namespace {

using test::bitwise_equal;
using detail::two_vertex_polygon;  // a capsule or segment as contact() sees it

/// A polygon of 2..8 vertices, size about 1, rounded one time in three: every combination of
/// one and two register groups.
Polygon random_small_polygon(std::mt19937& rng) {
  const float radius = rng() % 3 == 0 ? test::uniform(rng, 0.01f, 0.3f) : 0.0f;
  switch (rng() % 6) {
    case 0:
      return two_vertex_polygon(test::random_point(rng, 0.6f), test::random_point(rng, 0.6f),
                                radius);
    case 1:
      return make_box({test::uniform(rng, 0.1f, 0.6f), test::uniform(rng, 0.1f, 0.6f)}, radius);
    case 2:
    case 3:
      return test::random_polygon(rng, 3 + static_cast<int>(rng() % 2), 0.6f, radius);
    default:
      return test::random_polygon(rng, 5 + static_cast<int>(rng() % 4), 0.6f, radius);
  }
}

/// The frames of case `i`: A near the origin or (one case in five) 1e4 from it, B within 1.2;
/// one case in seven turned as A (parallel edges, tied axes), one in eleven A's frame itself.
std::pair<Transform, Transform> random_frames(std::mt19937& rng, int i) {
  const Vec2 base = i % 5 == 0 ? test::random_point(rng, 1e4f) : Vec2{0.0f, 0.0f};
  const Transform xa =
      Transform::from(base + test::random_point(rng, 0.2f), test::uniform(rng, -3.0f, 3.0f));
  Transform xb =
      Transform::from(base + test::random_point(rng, 1.2f), test::uniform(rng, -3.0f, 3.0f));
  if (i % 7 == 0) xb.q = xa.q;
  if (i % 11 == 0) xb = xa;
  return {xa, xb};
}

TEST(PolygonContactPaths, SmallPolygonPathMatchesGeneralPathBitwise) {
  std::mt19937 rng(20241122);
  int touching = 0;
  int two_points = 0;
  constexpr int kCases = 40000;
  for (int i = 0; i < kCases; ++i) {
    const Polygon a = random_small_polygon(rng);
    const Polygon b = random_small_polygon(rng);
    const auto [xa, xb] = random_frames(rng, i);
    const Manifold fast = detail::contact_polygons(a, xa, b, xb);
    const Manifold general = detail::contact_polygons_general_path(a, xa, b, xb);
    ASSERT_TRUE(bitwise_equal(fast, general))
        << "case " << i << ": counts " << fast.count << " vs " << general.count;
    touching += fast.count > 0 ? 1 : 0;
    two_points += fast.count == 2 ? 1 : 0;
  }
  // Both outcomes, and two-point manifolds, are exercised.
  EXPECT_GT(touching, kCases / 4);
  EXPECT_LT(touching, kCases * 3 / 4);
  EXPECT_GT(two_points, kCases / 10);
}

TEST(PolygonContactPaths, SegmentFrontEndMatchesGeneralPathBitwise) {
  std::mt19937 rng(20261129);
  int touching = 0;
  int two_points = 0;
  int apart_cores = 0;
  constexpr int kCases = 40000;
  for (int i = 0; i < kCases; ++i) {
    // A: 2..8 vertices (one and two register groups) or larger (the general path).
    const Polygon a = i % 13 == 0 ? test::random_polygon(rng, 9 + static_cast<int>(rng() % 8),
                                                         0.6f, 0.0f)
                                  : random_small_polygon(rng);
    const Vec2 b0 = test::random_point(rng, 0.6f);
    // Now and then a core a millionth long: its normal from a difference of nearby points.
    const Vec2 b1 = i % 17 == 0 ? b0 + Vec2{1e-6f, -2e-6f} : test::random_point(rng, 0.6f);
    const float radius = i % 3 == 0 ? 0.0f : test::uniform(rng, 0.01f, 0.3f);
    const auto [xa, xb] = random_frames(rng, i);
    const Polygon b = two_vertex_polygon(b0, b1, radius);
    const Manifold general = detail::contact_polygons_general_path(a, xa, b, xb);
    const Manifold fast = radius > 0.0f ? contact(a, xa, make_capsule(b0, b1, radius), xb)
                                        : contact(a, xa, Segment{b0, b1}, xb);
    ASSERT_TRUE(bitwise_equal(fast, general))
        << "case " << i << ": counts " << fast.count << " vs " << general.count;
    touching += fast.count > 0 ? 1 : 0;
    two_points += fast.count == 2 ? 1 : 0;
    apart_cores += fast.count > 0 && radius > 0.0f &&
                           !(contact(a, xa, Segment{b0, b1}, xb).count > 0)
                       ? 1
                       : 0;
  }
  EXPECT_GT(touching, kCases / 4);
  EXPECT_LT(touching, kCases * 3 / 4);
  EXPECT_GT(two_points, kCases / 10);
  // Rounded pairs whose cores are apart (the closest-feature walk) are exercised too.
  EXPECT_GT(apart_cores, kCases / 20);
}

}  // namespace
}  // namespace collide
