// shape_cast (GJK ray cast into the Minkowski difference) against analytic answers and against
// the truth from Box2D distances sampled densely along the motion.

#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>

#include "ccd/ccd_oracle.hpp"
#include "support/brute_convex.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

/// The scene moved rigidly by `m`: positions and velocities of both shapes.
struct Scene {
  Transform xa;
  Vec2 va;
  Transform xb;
  Vec2 vb;

  [[nodiscard]] Scene moved(const Transform& m) const {
    return {mul(m, xa), rotate(m.q, va), mul(m, xb), rotate(m.q, vb)};
  }
};

/// Size of a proxy: reach of its core from its first point plus its radius.
float proxy_size(const ConvexProxy& p) {
  float size = 0.0f;
  for (int i = 0; i < p.count(); ++i) size = std::max(size, distance(p.point(0), p.point(i)));
  return size + p.radius();
}

/// How late a hit may look against the oracle: the oracle (Box2D) and collide round the
/// placed coordinates differently (and the oracle takes the offset between the shapes in
/// double), so they see geometry that differs by a few ulps of the coordinates' magnitude,
/// turned into time by the relative speed.
float late_tolerance(const ConvexProxy& a, const ConvexProxy& b, const Scene& s) {
  const float magnitude =
      length(s.xa.p) + length(s.xb.p) + proxy_size(a) + proxy_size(b);
  return 1e-5f + 4.8e-7f * magnitude / std::max(length(s.vb - s.va), 1e-6f);
}

/// Distance tolerance of a hit in these tests: the library's target separation with room for
/// the oracle's own rounding.
float hit_tolerance(const ConvexProxy& a, const ConvexProxy& b, const Scene& s) {
  const float size_a = proxy_size(a);
  const float size_b = proxy_size(b);
  const float magnitude =
      length(s.vb - s.va) + distance(s.xa.p, s.xb.p) + size_a + size_b;
  return 2.0f * (kShapeCastTolerance * std::max(std::min(size_a, size_b), 1e-3f) +
                 kShapeCastRounding * magnitude) +
         1e-5f * magnitude;
}

// 1. Two circles head on: A (r 0.5) at the origin moving +10 x, B (r 0.5) at x = 5 at rest.
// They touch when 10 t = 4: t = 0.4, at x = 4.5, normal +x. Re-run under random rigid motions,
// including far from the origin.
TEST(ShapeCast, CirclesHeadOnAnalytic) {
  const Circle a = make_circle({0.0f, 0.0f}, 0.5f);
  const Circle b = make_circle({0.0f, 0.0f}, 0.5f);
  const Scene base{Transform{}, {10.0f, 0.0f}, Transform{{5.0f, 0.0f}, {}}, {0.0f, 0.0f}};
  std::mt19937 rng(11);
  for (int k = 0; k < 200; ++k) {
    const float extent = k < 100 ? 10.0f : 1e4f;
    const Transform m = k == 0 ? Transform{} : test::random_transform(rng, extent);
    const Scene s = base.moved(m);
    const ShapeCastResult r = shape_cast(a, s.xa, s.va, b, s.xb, s.vb);
    ASSERT_EQ(r.status, QueryStatus::hit) << k;
    EXPECT_TRUE(r.hit);
    const float tol_t = k < 100 ? 2e-5f : 2e-3f;
    // Never late, up to the rounding of the inputs themselves (ulp 1e-3 at 1e4, over speed 10).
    EXPECT_LE(r.fraction, 0.4f + (k < 100 ? 1e-6f : 2e-4f)) << "never late";
    EXPECT_NEAR(r.fraction, 0.4f, tol_t) << k;
    EXPECT_VEC2_NEAR(r.normal, rotate(m.q, {1.0f, 0.0f}), 1e-3f);
    EXPECT_VEC2_NEAR(r.point, transform_point(m, {4.5f, 0.0f}), k < 100 ? 1e-3f : 2e-2f);
  }
}

// 2. A unit box sliding face-first into a wall segment at x = 3: its right face (x = 0.5 + 10 t)
// reaches the wall at t = 0.25; the contact lies on the wall within the box's height.
TEST(ShapeCast, BoxFaceIntoWallAnalytic) {
  const Polygon box = make_box({0.5f, 0.5f});
  const Segment wall = make_segment({3.0f, -5.0f}, {3.0f, 5.0f});
  std::mt19937 rng(12);
  for (int k = 0; k < 100; ++k) {
    const Transform m = k == 0 ? Transform{} : test::random_transform(rng, k < 50 ? 10.0f : 1e4f);
    const Scene s = Scene{Transform{}, {10.0f, 0.0f}, Transform{}, {0.0f, 0.0f}}.moved(m);
    const ShapeCastResult r = shape_cast(box, s.xa, s.va, wall, s.xb, s.vb);
    ASSERT_EQ(r.status, QueryStatus::hit);
    EXPECT_LE(r.fraction, 0.25f + (k < 50 ? 1e-6f : 2e-4f));
    EXPECT_NEAR(r.fraction, 0.25f, k < 50 ? 2e-5f : 2e-3f);
    EXPECT_VEC2_NEAR(r.normal, rotate(m.q, {1.0f, 0.0f}), 1e-3f);
    const Vec2 local = inv_transform_point(m, r.point);
    EXPECT_NEAR(local.x, 3.0f, k < 50 ? 1e-3f : 3e-2f);
    EXPECT_LE(std::fabs(local.y), 0.5f + 1e-3f);
  }
}

// 3. A circle (r 1) at (-5, 0) moving +10 x into the corner of a box turned 45 degrees (corner
// at (-sqrt 2, 0)): the centre reaches x = -sqrt(2) - 1 at t = (4 - sqrt 2) / 10.
TEST(ShapeCast, CircleIntoCornerAnalytic) {
  const Circle c = make_circle({0.0f, 0.0f}, 1.0f);
  const Polygon diamond = make_box({1.0f, 1.0f}, {0.0f, 0.0f}, 0.25f * kPi);
  const ShapeCastResult r =
      shape_cast(c, Transform{{-5.0f, 0.0f}, {}}, {10.0f, 0.0f}, diamond, Transform{}, {0, 0});
  ASSERT_EQ(r.status, QueryStatus::hit);
  EXPECT_NEAR(r.fraction, (4.0f - std::sqrt(2.0f)) / 10.0f, 1e-5f);
  EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-4f);
  EXPECT_VEC2_NEAR(r.point, Vec2(-std::sqrt(2.0f), 0.0f), 1e-4f);
  // The same seen from the other side: both move, B chases A.
  const ShapeCastResult s =
      shape_cast(diamond, Transform{}, {-4.0f, 0.0f}, c, Transform{{-5.0f, 0.0f}, {}}, {6.0f, 0.0f});
  ASSERT_EQ(s.status, QueryStatus::hit);
  EXPECT_NEAR(s.fraction, r.fraction, 1e-5f);
  EXPECT_VEC2_NEAR(s.normal, Vec2(-1.0f, 0.0f), 1e-4f);
}

// 4. Overlapping or touching at t = 0: t 0, status overlapped, whatever the motion.
TEST(ShapeCast, OverlapAtStartReportsOverlapped) {
  const Polygon box = make_box({1.0f, 1.0f});
  const Circle c = make_circle({0.0f, 0.0f}, 0.5f);
  for (const Vec2 v : {Vec2{0.0f, 0.0f}, Vec2{5.0f, 0.0f}, Vec2{-5.0f, 3.0f}}) {
    const ShapeCastResult deep = shape_cast(box, Transform{}, v, c, Transform{{0.5f, 0.2f}, {}}, {});
    EXPECT_EQ(deep.status, QueryStatus::overlapped);
    EXPECT_TRUE(deep.hit);
    EXPECT_EQ(deep.fraction, 0.0f);
    // Touching exactly (circle's left edge on the box's right face), even when moving apart.
    const ShapeCastResult touch = shape_cast(box, Transform{}, v, c, Transform{{1.5f, 0.0f}, {}}, {});
    EXPECT_EQ(touch.status, QueryStatus::overlapped);
    EXPECT_EQ(touch.fraction, 0.0f);
    EXPECT_VEC2_NEAR(touch.normal, Vec2(1.0f, 0.0f), 1e-4f);
  }
}

// 5. Parallel motion: a box sliding along a wall 0.1 away never touches; moving away neither;
// no motion at all neither.
TEST(ShapeCast, ParallelAndReceding) {
  const Polygon box = make_box({0.5f, 0.5f});
  const Segment floor = make_segment({-100.0f, 0.0f}, {100.0f, 0.0f});
  const Transform above{{0.0f, 0.6f}, {}};
  for (const Vec2 v : {Vec2{50.0f, 0.0f}, Vec2{-50.0f, 0.0f}, Vec2{3.0f, 10.0f}, Vec2{0.0f, 0.0f}}) {
    const ShapeCastResult r = shape_cast(box, above, v, floor, Transform{}, {});
    EXPECT_EQ(r.status, QueryStatus::separated);
    EXPECT_FALSE(r.hit);
    EXPECT_EQ(r.fraction, 1.0f);
    EXPECT_EQ(r.normal, Vec2(0.0f, 0.0f));
  }
  // Sinking by exactly the gap: touches at t = 1; by a bit less: never.
  const ShapeCastResult at_end = shape_cast(box, above, {7.0f, -0.1f}, floor, Transform{}, {});
  EXPECT_EQ(at_end.status, QueryStatus::hit);
  EXPECT_NEAR(at_end.fraction, 1.0f, 1e-3f);
  const ShapeCastResult short_of =
      shape_cast(box, above, {7.0f, -0.09f}, floor, Transform{}, {});
  EXPECT_EQ(short_of.status, QueryStatus::separated);
}

// 6. Every pair of shape kinds (circle, capsule, polygon, segment, rounded polygon) at random
// poses and motions, checked against the densely sampled Box2D truth: a hit is never later than
// the first touch, the shapes are within tolerance of each other at the reported time, the
// normal separates them there, the point lies on both; a miss means the truth never touches.
// Swapping A and B gives the same time and the flipped normal.
TEST(ShapeCast, RandomPairsAgainstDenseSampling) {
  std::mt19937 rng(2024);
  int hits = 0;
  int total = 0;
  for (int ka = 0; ka < test::kShapeKinds; ++ka) {
    for (int kb = 0; kb < test::kShapeKinds; ++kb) {
      for (int k = 0; k < 40; ++k) {
        const Shape2D sa = test::random_shape(rng, ka, uniform(rng, 0.2f, 2.0f));
        const Shape2D sb = test::random_shape(rng, kb, uniform(rng, 0.2f, 2.0f));
        const float extent = k % 4 == 3 ? 1e4f : 5.0f;
        Scene s{test::random_transform(rng, extent), test::random_point(rng, 10.0f), {}, {}};
        s.xb = Transform::from(s.xa.p + test::random_point(rng, 6.0f), uniform(rng, -kPi, kPi));
        // Aim roughly at each other half the time.
        s.vb = k % 2 == 0 ? (s.xa.p - s.xb.p) * uniform(rng, 0.5f, 2.0f) + s.va
                          : test::random_point(rng, 10.0f);
        const ConvexProxy pa(sa);
        const ConvexProxy pb(sb);
        const ShapeCastResult r = shape_cast(sa, s.xa, s.va, sb, s.xb, s.vb);
        const test::TranslationTruth truth =
            test::translation_truth(pa, s.xa, s.va, pb, s.xb, s.vb);
        const float tol = hit_tolerance(pa, pb, s);
        ++total;
        ASSERT_NE(r.status, QueryStatus::max_iterations) << ka << kb << " " << k;
        SCOPED_TRACE(testing::Message() << "kinds " << ka << "," << kb << " case " << k
                                        << " t " << r.fraction << " truth " << truth.t_first
                                        << " min d " << truth.min_distance);
        if (truth.touches) {
          ASSERT_TRUE(r.hit);
          EXPECT_LE(r.fraction, truth.t_first + late_tolerance(pa, pb, s)) << "late";
        } else if (truth.min_distance > tol) {
          EXPECT_FALSE(r.hit);
          EXPECT_EQ(r.fraction, 1.0f);
        }
        if (!r.hit) continue;
        ++hits;
        const test::B2Proxy ba(pa);
        const test::B2Proxy bb(pb);
        EXPECT_LE(truth.distance_at(ba, bb, r.fraction), tol) << "too early";
        if (r.status == QueryStatus::overlapped) {
          EXPECT_EQ(r.fraction, 0.0f);
          continue;
        }
        // At the reported time the normal is a separating axis with ~zero gap. Checked in the
        // oracle's frame where A starts at the origin, so far-away cases keep their precision.
        const Transform xa_t{truth.xa.p + r.fraction * s.va, s.xa.q};
        const Transform xb_t{truth.xb.p + r.fraction * s.vb, s.xb.q};
        EXPECT_NEAR(length(r.normal), 1.0f, 1e-4f);
        const float sep = test::separation_along(pa, xa_t, pb, xb_t, r.normal);
        EXPECT_GE(sep, -tol);
        EXPECT_LE(sep, tol);
        // The point is on both surfaces (within tolerance).
        const Circle dot_shape = make_circle({0.0f, 0.0f}, 0.0f);
        const test::B2Proxy bp{ConvexProxy(dot_shape)};
        const Transform at_point{
            Vec2{static_cast<float>(double(r.point.x) - double(s.xa.p.x)),
                 static_cast<float>(double(r.point.y) - double(s.xa.p.y))},
            {}};
        EXPECT_LE(test::b2_distance(ba, xa_t, bp, at_point), 2.0f * tol);
        EXPECT_LE(test::b2_distance(bb, xb_t, bp, at_point), 2.0f * tol);
        // Swapped: same time, flipped normal.
        const ShapeCastResult w = shape_cast(sb, s.xb, s.vb, sa, s.xa, s.va);
        EXPECT_EQ(w.status, r.status);
        EXPECT_NEAR(w.fraction, r.fraction, 1e-3f);
      }
    }
  }
  // Both outcomes exercised.
  EXPECT_GT(hits, total * 3 / 10);
  EXPECT_LT(hits, total * 8 / 10);
}

// 6b. Sharp polygons of up to 8 vertices take the separating-axis cast into A - B: exact (the
// gap at the reported time is rounding, not the GJK cast's tolerance), never late, without
// GJK iterations for almost every hit; 9- and 10-gons still take GJK.
TEST(ShapeCast, SharpPolygonsCastExactlyAlongTheAxes) {
  std::mt19937 rng(1978);
  int hits = 0;
  int axis_hits = 0;
  int large_hits = 0;
  const int total = 1500;
  for (int k = 0; k < total; ++k) {
    const int na = 3 + static_cast<int>(rng() % 8);
    const int nb = 3 + static_cast<int>(rng() % 8);
    const Polygon a = test::random_polygon(rng, na, uniform(rng, 0.3f, 2.0f));
    const Polygon b = test::random_polygon(rng, nb, uniform(rng, 0.3f, 2.0f));
    Scene s{test::random_transform(rng, k % 4 == 3 ? 1e4f : 5.0f), test::random_point(rng, 10.0f),
            {}, {}};
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 6.0f), uniform(rng, -kPi, kPi));
    s.vb = k % 2 == 0 ? (s.xa.p - s.xb.p) * uniform(rng, 0.5f, 2.0f) + s.va
                      : test::random_point(rng, 10.0f);
    const ShapeCastResult r = shape_cast(a, s.xa, s.va, b, s.xb, s.vb);
    const ConvexProxy pa(a);
    const ConvexProxy pb(b);
    const test::TranslationTruth truth = test::translation_truth(pa, s.xa, s.va, pb, s.xb, s.vb);
    const float tol = hit_tolerance(pa, pb, s);
    SCOPED_TRACE(testing::Message() << "case " << k << " " << na << "-" << nb << " t "
                                    << r.fraction << " truth " << truth.t_first);
    if (truth.touches) {
      ASSERT_TRUE(r.hit);
      EXPECT_LE(r.fraction, truth.t_first + late_tolerance(pa, pb, s)) << "late";
    } else if (truth.min_distance > tol) {
      EXPECT_FALSE(r.hit);
    }
    if (r.status != QueryStatus::hit) continue;
    ++hits;
    if (a.count > 8 || b.count > 8) {  // (the hull of the jittered points may drop a vertex)
      EXPECT_GT(r.iterations, 0) << "a 9- or 10-gon takes GJK";
      ++large_hits;
      continue;
    }
    if (r.iterations != 0) continue;  // touching at the start or grazing: GJK's
    ++axis_hits;
    // Exact: at the reported time the shapes touch to within the rounding of the coordinates
    // (the GJK cast stops anywhere within kShapeCastTolerance of the smaller size).
    const float magnitude = length(s.vb - s.va) + distance(s.xa.p, s.xb.p) + 4.0f;
    const test::B2Proxy ba(pa);
    const test::B2Proxy bb(pb);
    EXPECT_LE(truth.distance_at(ba, bb, r.fraction), 2e-6f * magnitude);
    const Transform xa_t{truth.xa.p + r.fraction * s.va, s.xa.q};
    const Transform xb_t{truth.xb.p + r.fraction * s.vb, s.xb.q};
    const float sep = test::separation_along(pa, xa_t, pb, xb_t, r.normal);
    EXPECT_NEAR(sep, 0.0f, 2e-6f * magnitude) << "the normal is the touching axis";
  }
  EXPECT_GT(hits, total * 3 / 10);
  EXPECT_GT(axis_hits, hits * 5 / 10);
  EXPECT_GT(large_hits, 20);
}

// 6c. A circle and a polygon (sharp or rounded) take the ray from the centre into the polygon
// grown by the circle: exact, never late, no GJK iterations for almost every hit; both orders
// give the same time and point and opposite normals.
/// Counts of one exact-cast test: hits, and hits the exact path answered (iterations 0).
struct ExactCastCounts {
  int hits = 0;
  int exact_hits = 0;
};

/// Checks one cast of a round shape A (core segment core0 -> core1 in A's frame: a circle's
/// centre twice, a capsule's segment) against polygon `p` by the exact path: against dense
/// sampling and Box2D's distance at the hit, the reverse order bit-equal, and the point on A's
/// surface at the hit.
template <class Round>
void check_exact_cast(const Round& a, Vec2 core0, Vec2 core1, const Polygon& p, const Scene& s,
                      ExactCastCounts& counts) {
  const ShapeCastResult r = shape_cast(a, s.xa, s.va, p, s.xb, s.vb);
  const ConvexProxy pa(a);
  const ConvexProxy pb(p);
  const test::TranslationTruth truth = test::translation_truth(pa, s.xa, s.va, pb, s.xb, s.vb);
  const float tol = hit_tolerance(pa, pb, s);
  SCOPED_TRACE(testing::Message() << "t " << r.fraction << " truth " << truth.t_first
                                  << " iterations " << r.iterations);
  if (truth.touches) {
    ASSERT_TRUE(r.hit);
    EXPECT_LE(r.fraction, truth.t_first + late_tolerance(pa, pb, s)) << "late";
  } else if (truth.min_distance > tol) {
    EXPECT_FALSE(r.hit);
  }
  const ShapeCastResult w = shape_cast(p, s.xb, s.vb, a, s.xa, s.va);
  EXPECT_EQ(w.status, r.status);
  EXPECT_EQ(w.fraction, r.fraction);
  if (r.status != QueryStatus::hit) return;
  ++counts.hits;
  EXPECT_EQ(w.normal, -r.normal);
  EXPECT_EQ(w.point, r.point);
  if (r.iterations != 0) return;  // near touching at the start: GJK's
  ++counts.exact_hits;
  const float magnitude = length(s.vb - s.va) + distance(s.xa.p, s.xb.p) + 4.0f;
  const test::B2Proxy ba(pa);
  const test::B2Proxy bb(pb);
  EXPECT_LE(truth.distance_at(ba, bb, r.fraction), 2e-6f * magnitude);
  const Transform xa_t{truth.xa.p + r.fraction * s.va, s.xa.q};
  const Transform xb_t{truth.xb.p + r.fraction * s.vb, s.xb.q};
  EXPECT_NEAR(test::separation_along(pa, xa_t, pb, xb_t, r.normal), 0.0f, 2e-6f * magnitude);
  // The point is on A's surface: one radius from its core at t (world coordinates: within
  // their rounding far from the origin).
  const Vec2 c0 = transform_point(s.xa, core0) + r.fraction * s.va;
  const Vec2 c1 = transform_point(s.xa, core1) + r.fraction * s.va;
  EXPECT_NEAR(distance(r.point, test::closest_on_segment(c0, c1, r.point)), a.radius,
              2e-6f * magnitude + 4e-7f * length(s.xa.p));
}

TEST(ShapeCast, CirclePolygonCastsIntoTheGrownPolygon) {
  std::mt19937 rng(1979);
  ExactCastCounts counts;
  const int total = 1500;
  for (int k = 0; k < total; ++k) {
    const Circle c = make_circle(test::random_point(rng, 0.3f), uniform(rng, 0.1f, 1.0f));
    const Polygon p = test::random_polygon(rng, 3 + static_cast<int>(rng() % 10),
                                           uniform(rng, 0.3f, 2.0f),
                                           k % 3 == 0 ? uniform(rng, 0.05f, 0.3f) : 0.0f);
    Scene s{test::random_transform(rng, k % 4 == 3 ? 1e4f : 5.0f), test::random_point(rng, 10.0f),
            {}, {}};
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 6.0f), uniform(rng, -kPi, kPi));
    s.vb = k % 2 == 0 ? (s.xa.p - s.xb.p) * uniform(rng, 0.5f, 2.0f) + s.va
                      : test::random_point(rng, 10.0f);
    SCOPED_TRACE(testing::Message() << "case " << k);
    check_exact_cast(c, c.center, c.center, p, s, counts);
  }
  EXPECT_GT(counts.hits, total * 3 / 10);
  EXPECT_GT(counts.exact_hits, counts.hits * 9 / 10);
}

TEST(ShapeCast, CapsulePolygonCastsIntoThePolygonMinusTheSegment) {
  std::mt19937 rng(2711);
  ExactCastCounts counts;
  const int total = 1500;
  for (int k = 0; k < total; ++k) {
    const Vec2 c = test::random_point(rng, 0.3f);
    // Every fifth an upright capsule beside a box turned as it is: the segment exactly parallel
    // to two sides (B - S then has collinear edges, as a game's character against level
    // boxes); now and then a capsule with almost no segment (a circle).
    const Vec2 half =
        k % 5 == 0 ? Vec2{0.0f, uniform(rng, 0.2f, 1.0f)} : test::random_point(rng, 1.0f);
    const float stretch = k % 7 == 0 ? 1e-4f : 1.0f;
    const Capsule cap = make_capsule(c - stretch * half, c + stretch * half,
                                     uniform(rng, 0.05f, 0.6f));
    const float rounding = k % 3 == 0 ? uniform(rng, 0.05f, 0.3f) : 0.0f;
    const Polygon p = k % 5 == 0 ? make_box({uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f)})
                                 : test::random_polygon(rng, 3 + static_cast<int>(rng() % 10),
                                                        uniform(rng, 0.3f, 2.0f), rounding);
    Scene s{test::random_transform(rng, k % 4 == 3 ? 1e4f : 5.0f), test::random_point(rng, 10.0f),
            {}, {}};
    s.xb = k % 5 == 0 ? Transform{s.xa.p + test::random_point(rng, 6.0f), s.xa.q}
                      : Transform::from(s.xa.p + test::random_point(rng, 6.0f),
                                        uniform(rng, -kPi, kPi));
    s.vb = k % 2 == 0 ? (s.xa.p - s.xb.p) * uniform(rng, 0.5f, 2.0f) + s.va
                      : test::random_point(rng, 10.0f);
    SCOPED_TRACE(testing::Message() << "case " << k);
    check_exact_cast(cap, cap.a, cap.b, p, s, counts);
  }
  EXPECT_GT(counts.hits, total * 3 / 10);
  EXPECT_GT(counts.exact_hits, counts.hits * 9 / 10);
}

// 7. No tunnelling: small fast circles, capsules and boxes fired at thin walls (segments and
// 0.01-thick boxes) at up to 1e4 times their own size per step, from many angles and positions,
// also far from the origin. Every shot that crosses the wall is caught, never late.
TEST(ShapeCast, NoTunnellingThroughThinWalls) {
  std::mt19937 rng(7);
  const Segment seg_wall = make_segment({0.0f, -50.0f}, {0.0f, 50.0f});
  const Polygon thin_wall = make_box({0.005f, 50.0f});
  int shots = 0;
  for (int kind = 0; kind < 3; ++kind) {
    const float size = 0.05f;
    Shape2D bullet;
    if (kind == 0) bullet = make_circle({0.0f, 0.0f}, size);
    if (kind == 1) bullet = make_capsule({-size, 0.0f}, {size, 0.0f}, 0.3f * size);
    if (kind == 2) bullet = make_box({size, 0.5f * size});
    for (int w = 0; w < 2; ++w) {
      const Shape2D wall = w == 0 ? Shape2D(seg_wall) : Shape2D(thin_wall);
      for (int k = 0; k < 300; ++k) {
        const float speed = size * std::pow(10.0f, uniform(rng, 1.0f, 4.0f));  // up to 1e4 sizes
        const float angle = uniform(rng, -1.4f, 1.4f);  // from many angles, all crossing x = 0
        const Vec2 dir{std::cos(angle), std::sin(angle)};
        // Start left of the wall, so that the path crosses x = 0 at a random height within it.
        const float cross_y = uniform(rng, -40.0f, 40.0f);
        const float before = uniform(rng, 0.05f, 0.95f) * speed;  // distance to the crossing
        const Vec2 start = Vec2{0.0f, cross_y} - before * dir;
        const Transform world = test::random_transform(rng, k % 3 == 0 ? 1e4f : 10.0f);
        Scene s{Transform::from(start, uniform(rng, -kPi, kPi)), speed * dir, Transform{}, {}};
        s = s.moved(world);
        const ShapeCastResult r = shape_cast(bullet, s.xa, s.va, wall, s.xb, s.vb);
        const ConvexProxy pa(bullet);
        const ConvexProxy pb(wall);
        const test::TranslationTruth truth =
            test::translation_truth(pa, s.xa, s.va, pb, s.xb, s.vb);
        ++shots;
        ASSERT_TRUE(truth.touches) << "test setup: the path must cross the wall";
        ASSERT_TRUE(r.hit) << "tunnelled: kind " << kind << " wall " << w << " shot " << k;
        EXPECT_LE(r.fraction, truth.t_first + late_tolerance(pa, pb, s)) << "late";
        // Early by at most the tolerance, in distance.
        const test::B2Proxy ba(pa);
        const test::B2Proxy bb(pb);
        EXPECT_LE(truth.distance_at(ba, bb, r.fraction), hit_tolerance(pa, pb, s))
            << "kind " << kind << " wall " << w << " shot " << k << " t " << r.fraction << " truth "
            << truth.t_first << " it " << r.iterations << " speed " << speed << " status "
            << int(r.status);
      }
    }
  }
  EXPECT_EQ(shots, 3 * 2 * 300);
}

// 7b. Polygons of kMaxPolygonVertices vertices (near-circles: many nearly parallel edges, the
// hard case for a simplex method) converge well within the iteration cap and stay exact.
TEST(ShapeCast, LargePolygonsConverge) {
  std::mt19937 rng(64);
  int hits = 0;
  for (int k = 0; k < 100; ++k) {
    const Polygon a = test::random_polygon(rng, kMaxPolygonVertices, uniform(rng, 0.5f, 2.0f));
    const Polygon b = test::random_polygon(rng, kMaxPolygonVertices, uniform(rng, 0.5f, 2.0f));
    Scene s{test::random_transform(rng, 5.0f), test::random_point(rng, 10.0f),
            test::random_transform(rng, 5.0f), test::random_point(rng, 10.0f)};
    if (k % 2 == 0) s.vb = s.va + (s.xa.p - s.xb.p) * uniform(rng, 0.5f, 2.0f);  // aimed
    const ShapeCastResult r = shape_cast(a, s.xa, s.va, b, s.xb, s.vb);
    ASSERT_NE(r.status, QueryStatus::max_iterations) << k;
    EXPECT_LT(r.iterations, kShapeCastMaxIterations / 2);
    const ConvexProxy pa(a);
    const ConvexProxy pb(b);
    const test::TranslationTruth truth = test::translation_truth(pa, s.xa, s.va, pb, s.xb, s.vb);
    if (truth.touches) {
      ASSERT_TRUE(r.hit) << k;
      EXPECT_LE(r.fraction, truth.t_first + late_tolerance(pa, pb, s));
    }
    if (r.status != QueryStatus::hit) continue;
    ++hits;
    const test::B2Proxy ba(pa);
    const test::B2Proxy bb(pb);
    EXPECT_LE(truth.distance_at(ba, bb, r.fraction), hit_tolerance(pa, pb, s));
  }
  EXPECT_GT(hits, 30);
  EXPECT_LT(hits, 80);
}

// 8. The Shape2D overload (used by the query tool) gives the same answer as the typed one.
TEST(ShapeCast, VariantMatchesTyped) {
  const Capsule cap = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.25f);
  const Polygon tri = make_polygon(std::vector<Vec2>{{0, 0}, {2, 0}, {0, 2}});
  const Transform xa = Transform::from({-6.0f, 0.3f}, 0.4f);
  const Transform xb = Transform::from({3.0f, -0.5f}, -1.0f);
  const ShapeCastResult typed = shape_cast(cap, xa, {12.0f, 0.0f}, tri, xb, {-1.0f, 0.0f});
  const ShapeCastResult variant =
      shape_cast(Shape2D(cap), xa, {12.0f, 0.0f}, Shape2D(tri), xb, {-1.0f, 0.0f});
  ASSERT_EQ(typed.status, QueryStatus::hit);
  EXPECT_EQ(variant.status, typed.status);
  EXPECT_EQ(variant.fraction, typed.fraction);
  EXPECT_EQ(variant.point, typed.point);
  EXPECT_EQ(variant.normal, typed.normal);
}

// 9. Bad input is rejected with a message naming the field.
TEST(ShapeCast, RejectsNonFiniteInput) {
  const Circle c = make_circle({0.0f, 0.0f}, 1.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  try {
    (void)shape_cast(c, Transform{}, {nan, 0.0f}, c, Transform{}, {});
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("va"), std::string::npos);
  }
  EXPECT_THROW((void)shape_cast(c, Transform{}, {}, c, Transform{}, {0.0f, inf}), InvalidInput);
  EXPECT_THROW((void)shape_cast(c, Transform{{inf, 0.0f}, {}}, {}, c, Transform{}, {}),
               InvalidInput);
  EXPECT_THROW((void)shape_cast(Shape2D(c), Transform{}, {}, Shape2D(c), Transform{{0.0f, 0.0f}, {2.0f, 0.0f}}, {}),
               InvalidInput);
}

}  // namespace
}  // namespace collide
