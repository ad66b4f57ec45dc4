// The explicit path (build A - B, cast a ray into it) against analytic answers, and the fast
// GJK ray cast against the explicit path on random polygon pairs.

#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>

#include "ccd/ccd_oracle.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

// 1. Two unit boxes, A sliding +x into B whose left face is 3 away: first touch at t = 0.3 with
// the whole faces touching, so the point is the middle of the shared part of the faces (B is
// shifted 0.5 up: faces share y in [0, 0.5] -> y = 0.25). Re-run under random rigid motions.
TEST(ShapeCastMinkowski, BoxFacesAnalytic) {
  const Polygon box = make_box({0.5f, 0.5f});
  std::mt19937 rng(31);
  for (int k = 0; k < 50; ++k) {
    const Transform m = k == 0 ? Transform{} : test::random_transform(rng, k < 25 ? 10.0f : 1e4f);
    const Transform xa = mul(m, Transform{});
    const Transform xb = mul(m, Transform{{4.0f, 0.5f}, {}});
    const ShapeCastResult r =
        shape_cast_minkowski(box, xa, rotate(m.q, {10.0f, 0.0f}), box, xb, {0.0f, 0.0f});
    ASSERT_EQ(r.status, QueryStatus::hit);
    EXPECT_NEAR(r.fraction, 0.3f, k < 25 ? 1e-5f : 2e-4f);
    EXPECT_VEC2_NEAR(r.normal, rotate(m.q, {1.0f, 0.0f}), 1e-4f);
    EXPECT_VEC2_NEAR(inv_transform_point(m, r.point), Vec2(3.5f, 0.25f), k < 25 ? 1e-4f : 3e-3f);
  }
}

// 2. A rounded triangle's vertex into a box face, and overlapping / receding cases.
TEST(ShapeCastMinkowski, VertexIntoFaceOverlapAndMiss) {
  const Polygon tri = make_polygon(std::vector<Vec2>{{-1, -1}, {1, 0}, {-1, 1}}, 0.25f);
  const Polygon box = make_box({1.0f, 1.0f});
  // Tip at x = 1.25 (radius included) moving +x toward the face at x = 4: t = 2.75 / 5.
  const ShapeCastResult r =
      shape_cast_minkowski(tri, Transform{}, {5.0f, 0.0f}, box, Transform{{5.0f, 0.0f}, {}}, {});
  ASSERT_EQ(r.status, QueryStatus::hit);
  EXPECT_NEAR(r.fraction, 2.75f / 5.0f, 1e-5f);
  EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-5f);
  EXPECT_VEC2_NEAR(r.point, Vec2(4.0f, 0.0f), 1e-4f);
  const ShapeCastResult over =
      shape_cast_minkowski(tri, Transform{}, {5.0f, 0.0f}, box, Transform{{1.5f, 0.0f}, {}}, {});
  EXPECT_EQ(over.status, QueryStatus::overlapped);
  EXPECT_EQ(over.fraction, 0.0f);
  const ShapeCastResult away =
      shape_cast_minkowski(tri, Transform{}, {-5.0f, 0.0f}, box, Transform{{5.0f, 0.0f}, {}}, {});
  EXPECT_EQ(away.status, QueryStatus::separated);
  EXPECT_EQ(away.fraction, 1.0f);
}

// 3. The fast path agrees with the explicit one on random polygon pairs (sharp and rounded,
// near and far from the origin): same outcome, same time (both within tolerance of touching,
// the fast one never after the explicit one), and mostly the same normal (at vertex-vertex
// contacts several normals are right; both are checked to separate the shapes).
TEST(ShapeCastMinkowski, FastPathAgreesWithExplicit) {
  std::mt19937 rng(99);
  int hits = 0;
  int normals_agree = 0;
  int overlaps = 0;
  const int total = 600;
  for (int k = 0; k < total; ++k) {
    const float ra = k % 3 == 0 ? uniform(rng, 0.05f, 0.3f) : 0.0f;
    const float rb = k % 5 == 0 ? uniform(rng, 0.05f, 0.3f) : 0.0f;
    const Polygon a = test::random_polygon(rng, 3 + int(rng() % 6), uniform(rng, 0.3f, 2.0f), ra);
    const Polygon b = test::random_polygon(rng, 3 + int(rng() % 6), uniform(rng, 0.3f, 2.0f), rb);
    const Transform xa = test::random_transform(rng, k % 4 == 3 ? 1e4f : 5.0f);
    const Transform xb = Transform::from(xa.p + test::random_point(rng, 6.0f), uniform(rng, -kPi, kPi));
    const Vec2 va = test::random_point(rng, 8.0f);
    const Vec2 vb = k % 2 == 0 ? (xa.p - xb.p) * uniform(rng, 0.5f, 2.0f) + va
                               : test::random_point(rng, 8.0f);
    const ShapeCastResult fast = shape_cast(a, xa, va, b, xb, vb);
    const ShapeCastResult slow = shape_cast_minkowski(a, xa, va, b, xb, vb);
    const ConvexProxy pa(a);
    const ConvexProxy pb(b);
    const test::TranslationTruth truth = test::translation_truth(pa, xa, va, pb, xb, vb);
    const test::B2Proxy ba(pa);
    const test::B2Proxy bb(pb);
    const float magnitude = length(vb - va) + distance(xa.p, xb.p) + 4.0f;
    const float tol = 2e-4f + 2e-6f * magnitude;
    SCOPED_TRACE(testing::Message() << "case " << k << " fast t " << fast.fraction << " slow t "
                                    << slow.fraction << " min d " << truth.min_distance);
    if (fast.hit != slow.hit) {
      // Only a graze within tolerance may split them.
      EXPECT_LE(truth.min_distance, tol);
      continue;
    }
    if (!fast.hit) continue;
    ++hits;
    EXPECT_EQ(fast.status, slow.status);
    if (slow.status == QueryStatus::overlapped) {
      ++overlaps;
      EXPECT_EQ(fast.fraction, 0.0f);
      continue;
    }
    EXPECT_LE(truth.distance_at(ba, bb, fast.fraction), tol);
    EXPECT_LE(truth.distance_at(ba, bb, slow.fraction), tol);
    const float late = 1e-5f + 1e-6f * magnitude / std::max(length(vb - va), 1e-6f);
    EXPECT_LE(fast.fraction, slow.fraction + late) << "fast path later than the explicit one";
    if (distance(fast.normal, slow.normal) <= 1e-3f) ++normals_agree;
    for (const Vec2 n : {fast.normal, slow.normal}) {
      const float sep = test::separation_along(pa, Transform{truth.xa.p + fast.fraction * va, xa.q}, pb,
                                               Transform{truth.xb.p + fast.fraction * vb, xb.q}, n);
      EXPECT_LE(std::fabs(sep), 2.0f * tol);
    }
  }
  EXPECT_GT(hits, total * 3 / 10);
  EXPECT_LT(hits, total * 8 / 10);
  EXPECT_GT(overlaps, 5);
  EXPECT_GE(normals_agree, (hits - overlaps) * 9 / 10);
}

// 4. A difference with more vertices than a Polygon holds is refused by name.
TEST(ShapeCastMinkowski, RejectsTooManyVertices) {
  std::vector<Vec2> ring;
  for (int i = 0; i < 40; ++i) {
    const float angle = 2.0f * kPi * float(i) / 40.0f;
    ring.push_back({std::cos(angle), std::sin(angle)});
  }
  const Polygon a = make_polygon(ring);
  const Polygon b = make_polygon(ring);
  EXPECT_THROW((void)shape_cast_minkowski(a, Transform{}, {1.0f, 0.0f}, b,
                                          Transform::from({5.0f, 0.0f}, 0.01f), {}),
               InvalidInput);
}

}  // namespace
}  // namespace collide
