// Minkowski sums and differences checked against the convex hull (gift wrapping) of all n * m
// pairwise sums, and the difference's signed distance to the origin against the separating
// axis test and the pairwise vertex-edge distance, both brute force.

#include <collide/narrow/minkowski.hpp>

#include "support/brute_convex.hpp"
#include "support/test_util.hpp"

namespace collide {
namespace {

using test::uniform;

std::vector<Vec2> pairwise(const std::vector<Vec2>& a, const std::vector<Vec2>& b, float sign) {
  std::vector<Vec2> out;
  for (Vec2 p : a) {
    for (Vec2 q : b) out.push_back(p + sign * q);
  }
  return out;
}

/// The result equals the hull of `points` (gift wrapping) within `tol`: every hull vertex lies
/// on the result's boundary, every result vertex is a hull vertex, every point is inside, and
/// the outline turns left at every corner (within rounding). Vertex counts agree except that
/// nearly straight hull corners (two input edges within kParallelTolerance) may be merged.
void expect_hull_of(const MinkowskiPolygon& m, const std::vector<Vec2>& points, float tol) {
  const std::vector<Vec2> hull = test::gift_wrap(points, tol);
  const size_t n = m.vertices.size();
  ASSERT_GE(n, 3u);
  for (Vec2 h : hull) {
    const test::BruteDistance d = test::brute_distance(m.vertices, h);
    EXPECT_LE(d.boundary, tol) << "hull vertex (" << h.x << ", " << h.y << ") off the result";
  }
  for (Vec2 v : m.vertices) {
    float best = INFINITY;
    for (Vec2 h : hull) best = std::min(best, distance(v, h));
    EXPECT_LE(best, tol) << "result vertex (" << v.x << ", " << v.y << ") not on the hull";
  }
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = m.vertices[i], b = m.vertices[(i + 1) % n], c = m.vertices[(i + 2) % n];
    EXPECT_GT(cross(b - a, c - b), -tol * (distance(a, b) + distance(b, c)))
        << "corner " << (i + 1) % n << " turns right";
    const Vec2 normal = normalize_or_zero(right_perp(b - a));
    for (Vec2 p : points) EXPECT_LE(dot(normal, p - a), tol);
  }
  int nearly_straight = 0;
  for (size_t i = 0; i < hull.size(); ++i) {
    const Vec2 a = hull[i], b = hull[(i + 1) % hull.size()], c = hull[(i + 2) % hull.size()];
    if (cross(b - a, c - b) < 1e-3f * distance(a, b) * distance(b, c)) ++nearly_straight;
  }
  EXPECT_LE(n, hull.size());
  EXPECT_GE(n + static_cast<size_t>(nearly_straight), hull.size());
}

TEST(Minkowski, SumIsHullOfPairwiseSums) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 300; ++trial) {
    const bool far = trial % 4 == 0;
    const Polygon a = test::random_polygon(rng, 3 + trial % 12, uniform(rng, 0.5f, 3.0f));
    const Polygon b = test::random_polygon(rng, 3 + (trial / 12) % 12, uniform(rng, 0.5f, 3.0f));
    const Transform xa = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const Transform xb = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const MinkowskiPolygon sum = minkowski_sum(a, xa, b, xb);
    // Sums of coordinates near 2e4 carry ~2e-3 of rounding.
    expect_hull_of(sum, pairwise(test::world_vertices(a, xa), test::world_vertices(b, xb), 1.0f),
                   far ? 8e-3f : 1e-4f);
    EXPECT_EQ(sum.radius, 0.0f);
  }
}

TEST(Minkowski, DifferenceIsHullOfPairwiseDifferences) {
  std::mt19937 rng(22);
  for (int trial = 0; trial < 300; ++trial) {
    const bool far = trial % 4 == 0;
    const float ra = trial % 3 == 0 ? uniform(rng, 0.1f, 0.5f) : 0.0f;
    const Polygon a = test::random_polygon(rng, 3 + trial % 12, uniform(rng, 0.5f, 3.0f), ra);
    const Polygon b =
        test::random_polygon(rng, 3 + (trial / 12) % 12, uniform(rng, 0.5f, 3.0f), 0.25f);
    const Transform xa = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const Transform xb{xa.p + test::random_point(rng, 5.0f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const MinkowskiPolygon diff = minkowski_difference(a, xa, b, xb);
    expect_hull_of(diff, pairwise(test::world_vertices(a, xa), test::world_vertices(b, xb), -1.0f),
                   far ? 4e-3f : 1e-4f);
    EXPECT_FLOAT_EQ(diff.radius, ra + 0.25f);
  }
}

// Two boxes: the parallel edges merge, so the sum is a box of summed extents with 4 vertices.
TEST(Minkowski, ParallelEdgesMerge) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 50; ++trial) {
    const Transform xf =
        trial == 0 ? Transform{} : test::random_transform(rng, trial % 2 ? 1.0e4f : 10.0f);
    const float tol = trial % 2 ? 8e-3f : 1e-5f;
    const Polygon a = make_box({1.0f, 2.0f});
    const Polygon b = make_box({0.5f, 0.25f}, {3.0f, 1.0f}, 0.0f);
    const Transform xb{transform_point(xf, {10.0f, 0.0f}), xf.q};
    const MinkowskiPolygon sum = minkowski_sum(a, xf, b, xb);
    ASSERT_EQ(sum.vertices.size(), 4u);
    const Vec2 center = transform_point(xf, {0.0f, 0.0f}) + transform_point(xb, {3.0f, 1.0f});
    for (Vec2 corner :
         {Vec2{-1.5f, -2.25f}, Vec2{1.5f, -2.25f}, Vec2{1.5f, 2.25f}, Vec2{-1.5f, 2.25f}}) {
      const Vec2 expected = center + rotate(xf.q, corner);
      float best = INFINITY;
      for (Vec2 v : sum.vertices) best = std::min(best, distance(v, expected));
      EXPECT_LE(best, tol);
    }
  }
}

// A - B contains the origin iff A and B overlap (separating axis test over every edge normal),
// and its signed distance to the origin is the distance between A and B (vertex-edge brute
// force) when apart, minus the smallest overlap over the axes when overlapping; radii subtract.
TEST(Minkowski, SignedDistanceToOriginMatchesBruteForce) {
  std::mt19937 rng(24);
  int overlapping = 0, apart = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const bool far = trial % 4 == 0;
    const float ra = trial % 2 ? uniform(rng, 0.05f, 0.5f) : 0.0f;
    const float rb = trial % 3 ? uniform(rng, 0.05f, 0.5f) : 0.0f;
    const Polygon a = test::random_polygon(rng, 3 + trial % 8, uniform(rng, 0.5f, 2.0f), ra);
    const Polygon b = test::random_polygon(rng, 3 + trial % 7, uniform(rng, 0.5f, 2.0f), rb);
    // Place both near a common far point; the brute force works on the same inputs shifted
    // exactly back to the origin.
    const Vec2 base = far ? Vec2{1.0e4f, -1.0e4f} : Vec2{0.0f, 0.0f};
    const Transform xa{base + test::random_point(rng, 2.0f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const Transform xb{base + test::random_point(rng, 2.0f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const MinkowskiPolygon diff = minkowski_difference(a, xa, b, xb);
    const std::vector<Vec2> wa = test::world_vertices(a, {xa.p - base, xa.q});
    const std::vector<Vec2> wb = test::world_vertices(b, {xb.p - base, xb.q});
    const float sat = test::sat_separation(wa, wb);
    const float core = sat > 0.0f ? test::brute_polygon_distance(wa, wb) : sat;
    // World vertices far out are rounded to ~1e-3 before the difference is formed.
    const float tol = far ? 4e-3f : 2e-5f;
    const float d = diff.signed_distance_to_origin();
    EXPECT_NEAR(d, core - ra - rb, tol);
    if (std::fabs(core - ra - rb) > tol) {
      EXPECT_EQ(diff.contains_origin(), core - ra - rb < 0.0f);
    }
    (d <= 0.0f ? overlapping : apart)++;
  }
  EXPECT_GT(overlapping, 600);
  EXPECT_GT(apart, 600);
}

}  // namespace
}  // namespace collide
