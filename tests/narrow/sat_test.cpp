// The separating axis test against brute force: the separation of B along each edge normal of A,
// computed in world space from world vertices.

#include <collide/narrow/sat.hpp>
#include <limits>
#include <span>
#include <vector>

#include "support/test_util.hpp"

namespace collide {
namespace {

/// Separation of B from A along A's edge i, brute force in world space.
float world_edge_separation(const Polygon& a, const Transform& xa, const Polygon& b,
                            const Transform& xb, int i) {
  const Vec2 v = transform_point(xa, a.vertices[i]);
  const Vec2 n = rotate(xa.q, a.normals[i]);
  float lowest = std::numeric_limits<float>::infinity();
  for (int j = 0; j < b.count; ++j) {
    lowest = std::min(lowest, dot(n, transform_point(xb, b.vertices[j]) - v));
  }
  return lowest;
}

TEST(SatFindMaxSeparation, MatchesBruteForceOverEveryEdge) {
  std::mt19937 rng(11);
  int apart = 0, overlapping = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    // Up to 64 vertices: many-sided polygons make the deepest-vertex walk go far.
    const int na =
        t % 4 == 0 ? 40 + static_cast<int>(rng() % 25) : 3 + static_cast<int>(rng() % 10);
    const int nb =
        t % 4 == 1 ? 40 + static_cast<int>(rng() % 25) : 3 + static_cast<int>(rng() % 10);
    const Polygon a = test::random_polygon(rng, na, 1.0f);
    const Polygon b = test::random_polygon(rng, nb, 1.0f);
    const Transform xa = test::random_transform(rng, 2.0f);
    const Transform xb = test::random_transform(rng, 2.0f);
    const EdgeSeparation s = find_max_separation(a, b, inv_mul(xa, xb));
    float best = -std::numeric_limits<float>::infinity();
    for (int i = 0; i < a.count; ++i) best = std::max(best, world_edge_separation(a, xa, b, xb, i));
    EXPECT_NEAR(s.separation, best, 1e-4f);
    EXPECT_NEAR(world_edge_separation(a, xa, b, xb, s.edge), best, 1e-4f) << "edge " << s.edge;
    // The support vertex is B's deepest along the chosen axis.
    const Vec2 n = rotate(xa.q, a.normals[s.edge]);
    EXPECT_NEAR(dot(n, transform_point(xb, b.vertices[s.support]) -
                           transform_point(xa, a.vertices[s.edge])),
                world_edge_separation(a, xa, b, xb, s.edge), 1e-4f);
    (s.separation > 0.0f ? apart : overlapping)++;
  }
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_GT(overlapping, trials * 3 / 10);
}

TEST(SatEdgeSeparations, EveryEdgeMatchesBruteForceAndTheMaximumMatchesFindMaxSeparation) {
  // 3..8 vertices take the register path (every combination of one and two groups of four),
  // 9..12 and 40-64 the scalar one; also far from the origin.
  std::mt19937 rng(12);
  int apart = 0;
  int overlapping = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    const int na = t % 8 == 0 ? 40 + static_cast<int>(rng() % 25) : 3 + static_cast<int>(rng() % 10);
    const int nb = t % 8 == 1 ? 40 + static_cast<int>(rng() % 25) : 3 + static_cast<int>(rng() % 10);
    const Polygon a = test::random_polygon(rng, na, 1.0f);
    const Polygon b = test::random_polygon(rng, nb, 1.0f);
    const Vec2 far = t % 5 == 0 ? Vec2{3e3f, -2e3f} : Vec2{0.0f};
    const Transform xa = test::random_transform(rng, 2.0f);
    const Transform xb = test::random_transform(rng, 2.0f);
    const Transform xa_far{xa.p + far, xa.q};
    const Transform xb_far{xb.p + far, xb.q};
    std::vector<float> out(static_cast<size_t>(a.count) + 1, 12345.0f);
    edge_separations(a, b, inv_mul(xa_far, xb_far), std::span(out).first(a.count));
    EXPECT_EQ(out.back(), 12345.0f) << "wrote past a.count";
    float best = -std::numeric_limits<float>::infinity();
    for (int i = 0; i < a.count; ++i) {
      // The brute force near the origin: the same relative placement, no far-away rounding.
      EXPECT_NEAR(out[i], world_edge_separation(a, xa, b, xb, i), 2e-3f)
          << "trial " << t << " edge " << i << " of " << a.count << "-" << b.count;
      best = std::max(best, out[i]);
    }
    if (t % 5 != 0) {
      EXPECT_NEAR(best, find_max_separation(a, b, inv_mul(xa, xb)).separation, 1e-5f) << "trial " << t;
    }
    (best > 0.0f ? apart : overlapping)++;
  }
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_GT(overlapping, trials * 3 / 10);
}

TEST(SatFindMaxSeparation, EarlyExitStopsAtASeparatingAxis) {
  // Unit box A; box B 3 units to the right: A's edge 1 (normal +x) separates by 2.
  const Polygon a = make_box({0.5f, 0.5f});
  const Polygon b = make_box({0.5f, 0.5f}, {3.0f, 0.0f}, 0.0f);
  const std::span<const Vec2> va(a.vertices.data(), 4), na(a.normals.data(), 4),
      vb(b.vertices.data(), 4);
  const EdgeSeparation full = find_max_separation(va, na, vb);
  EXPECT_EQ(full.edge, 1);
  EXPECT_FLOAT_EQ(full.separation, 2.0f);
  // With early exit at 0 it may stop at the first separating axis, which must separate.
  const EdgeSeparation early = find_max_separation(va, na, vb, 0.0f);
  EXPECT_GT(early.separation, 0.0f);
  EXPECT_EQ(early.edge, 1);  // edges 0 (-y) does not separate; edge 1 (+x) is the first that does
}

TEST(SatFindMaxSeparation, TouchingIsZeroAndTwoVertexPolygonsWork) {
  const Polygon a = make_box({1.0f, 1.0f});
  const Polygon b = make_box({1.0f, 1.0f}, {0.0f, 2.0f}, 0.0f);  // resting on top, touching
  EXPECT_EQ(find_max_separation(a, b, Transform{}).separation, 0.0f);
  // A segment seen as a 2-vertex polygon (edge 0 a->b, normal to its right) 0.5 above the box.
  Polygon seg;
  seg.count = 2;
  seg.vertices[0] = {-3.0f, 1.5f};
  seg.vertices[1] = {3.0f, 1.5f};
  seg.normals[0] = {0.0f, -1.0f};
  seg.normals[1] = {0.0f, 1.0f};
  const EdgeSeparation s = find_max_separation(seg, a, Transform{});
  EXPECT_EQ(s.edge, 0);
  EXPECT_FLOAT_EQ(s.separation, 0.5f);
}

}  // namespace
}  // namespace collide
