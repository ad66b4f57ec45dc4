// GJK distance (src/narrow/distance.cpp) against brute force in double, Box2D 2.4's b2Distance
// and analytic answers, for every ordered pair of 2D shape types.

#include <collide/narrow/distance.hpp>

#include "support/gjk_oracle.hpp"
#include "support/test_util.hpp"

#include <array>
#include <cmath>
#include <string>
#include <variant>

namespace collide {
namespace {

using test::kAllTypes2D;
using test::uniform;

/// Shapes are about 1 unit across and placed within a few units: the scene is this big, and
/// answers must agree with exact geometry to 1e-4 of it.
constexpr float kSceneSize = 4.0f;
constexpr float kTol = 1e-4f * kSceneSize;

/// World-space precision of points 1e4 from the origin: a few float ulps at 1e4 (~1e-3).
constexpr float kFarPointTol = 4e-3f;

Transform compose(const Transform& g, const Transform& x) { return mul(g, x); }

using test::Scene;
using test::random_scene;

/// Checks one distance result against brute force; returns the kind of case it was
/// (0 apart, 1 radii overlap with cores apart, 2 cores overlap, 3 cores touch within kTol).
int check_against_brute_force(const Scene& s, const DistanceResult& r, const std::string& what) {
  const test::WorldCore ca = test::world_core(s.a, s.xa);
  const test::WorldCore cb = test::world_core(s.b, s.xb);
  const double core = test::brute_core_distance(ca.points, cb.points);
  const double truth = std::max(core - ca.radius - cb.radius, 0.0);
  EXPECT_NEAR(r.distance, truth, kTol) << what;
  EXPECT_NE(r.status, QueryStatus::max_iterations) << what;
  if (core > kTol) {
    // Cores apart: exact points on each surface, unit normal from A to B along them.
    EXPECT_EQ(r.status, QueryStatus::separated) << what;
    EXPECT_NEAR(length(r.normal), 1.0f, 1e-5f) << what;
    EXPECT_NEAR(test::brute_point_distance(ca.points, {r.point_a.x, r.point_a.y}), ca.radius, kTol)
        << what << ": point_a not on A's surface";
    EXPECT_NEAR(test::brute_point_distance(cb.points, {r.point_b.x, r.point_b.y}), cb.radius, kTol)
        << what << ": point_b not on B's surface";
    const Vec2 ab = r.point_b - r.point_a;
    EXPECT_NEAR(dot(ab, r.normal), truth > 0.0 ? truth : -(ca.radius + cb.radius - core), kTol)
        << what;
    EXPECT_NEAR(cross(ab, r.normal), 0.0f, kTol) << what;
    if (truth == 0.0) {
      // Radii overlap: each point is its shape's surface point along the normal, so they have
      // passed each other by the penetration depth (checked by the dot product above).
      EXPECT_EQ(r.distance, 0.0f) << what;
      return 1;
    }
    return 0;
  }
  if (core > 0.0) return 3;  // cores touch within kTol: only the distance is judged
  if (r.status == QueryStatus::overlapped) {
    // Cores overlap: one witness point, inside both cores.
    EXPECT_LE(distance(r.point_a, r.point_b), kTol) << what;
    EXPECT_LE(test::brute_point_distance(ca.points, {r.point_a.x, r.point_a.y}), kTol) << what;
    EXPECT_LE(test::brute_point_distance(cb.points, {r.point_a.x, r.point_a.y}), kTol) << what;
    EXPECT_EQ(r.normal, Vec2(0.0f, 0.0f)) << what;
  }
  return 2;
}

TEST(GjkDistance, EveryPairTypeAgreesWithBruteForce) {
  std::mt19937 rng(20261121);
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      std::array<int, 4> kinds{};
      int core_overlap_reported = 0;
      const int trials = 400;
      for (int i = 0; i < trials; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const DistanceResult r = distance(s.a, s.xa, s.b, s.xb);
        const std::string what = std::string(test::type_label(ta)) + "-" +
                                 test::type_label(tb) + " trial " + std::to_string(i);
        const int kind = check_against_brute_force(s, r, what);
        ++kinds[kind];
        if (kind == 2 && r.status == QueryStatus::overlapped) ++core_overlap_reported;
      }
      const std::string pair = std::string(test::type_label(ta)) + "-" + test::type_label(tb);
      // Both outcomes exercised: apart, and overlapping (radii or cores).
      EXPECT_GT(kinds[0], trials * 3 / 10) << pair;
      EXPECT_GT(kinds[1] + kinds[2], trials * 3 / 10) << pair;
      // Overlapping cores are reported as such; cores that merely touch (within rounding) may
      // come out as apart at a distance of ~0, which the distance check above accepts.
      EXPECT_LE(kinds[2] - core_overlap_reported, 1 + kinds[2] / 20) << pair;
      if (ta != ShapeType2D::segment || tb != ShapeType2D::segment) {
        if (ta != ShapeType2D::circle && tb != ShapeType2D::circle) EXPECT_GT(kinds[2], 0) << pair;
      }
    }
  }
}

TEST(GjkDistance, SwappingShapesSwapsPointsAndFlipsNormal) {
  std::mt19937 rng(11);
  int separated = 0;
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 100; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const DistanceResult ab = distance(s.a, s.xa, s.b, s.xb);
        const DistanceResult ba = distance(s.b, s.xb, s.a, s.xa);
        EXPECT_NEAR(ab.distance, ba.distance, kTol);
        if (ab.distance > kTol) {
          ++separated;
          EXPECT_VEC2_NEAR(ab.point_a, ba.point_b, kTol);
          EXPECT_VEC2_NEAR(ab.point_b, ba.point_a, kTol);
          EXPECT_VEC2_NEAR(ab.normal, -ba.normal, 1e-3f);
        }
      }
    }
  }
  EXPECT_GT(separated, 1600 * 3 / 10);
}

TEST(GjkDistance, InvariantUnderRigidTransforms) {
  std::mt19937 rng(5);
  int separated = 0;
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 60; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const DistanceResult base = distance(s.a, s.xa, s.b, s.xb);
        const Transform g = test::random_transform(rng, 5.0f);
        const DistanceResult moved = distance(s.a, compose(g, s.xa), s.b, compose(g, s.xb));
        EXPECT_NEAR(moved.distance, base.distance, kTol);
        EXPECT_EQ(moved.status, base.status);
        if (base.distance > kTol) {
          ++separated;
          EXPECT_VEC2_NEAR(moved.point_a, transform_point(g, base.point_a), kTol);
          EXPECT_VEC2_NEAR(moved.point_b, transform_point(g, base.point_b), kTol);
          EXPECT_VEC2_NEAR(moved.normal, rotate(g.q, base.normal), 1e-3f);
        }
      }
    }
  }
  EXPECT_GT(separated, 960 * 3 / 10);
}

TEST(GjkDistance, FarFromOriginAgreesWithBruteForceInDouble) {
  // 1e4 from the origin the input transforms themselves are only exact to float spacing there
  // (~1e-3), so the truth is computed in double from the transforms as given. Distances stay
  // accurate to the scene's own size (B is moved into A's frame first); points are limited to
  // float spacing at 1e4.
  std::mt19937 rng(99);
  int apart = 0;
  int trials = 0;
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 60; ++i, ++trials) {
        Scene s = random_scene(rng, ta, tb);
        const Vec2 far = Vec2{-1e4f, 1e4f} + test::random_point(rng, 10.0f);
        s.xa.p += far;
        s.xb.p += far;
        const DistanceResult r = distance(s.a, s.xa, s.b, s.xb);
        const test::WorldCore ca = test::world_core(s.a, s.xa);
        const test::WorldCore cb = test::world_core(s.b, s.xb);
        const double core = test::brute_core_distance(ca.points, cb.points);
        const double truth = std::max(core - ca.radius - cb.radius, 0.0);
        EXPECT_NEAR(r.distance, truth, kTol) << test::type_label(ta) << "-" << test::type_label(tb);
        if (core > kTol) {
          EXPECT_NEAR(test::brute_point_distance(ca.points, {r.point_a.x, r.point_a.y}), ca.radius,
                      kFarPointTol);
          EXPECT_NEAR(test::brute_point_distance(cb.points, {r.point_b.x, r.point_b.y}), cb.radius,
                      kFarPointTol);
        }
        if (truth > kTol) ++apart;
      }
    }
  }
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_LT(apart, trials * 7 / 10);
}

TEST(GjkDistance, AgreesWithBox2DIncluding64VertexAndRoundedPolygons) {
  std::mt19937 rng(2024);
  int apart = 0;
  const int trials = 600;
  for (int i = 0; i < trials; ++i) {
    const int na = i % 3 == 0 ? 64 : 3 + static_cast<int>(rng() % 6);
    const int nb = i % 5 == 0 ? 64 : 3 + static_cast<int>(rng() % 6);
    const float ra = i % 4 == 0 ? uniform(rng, 0.02f, 0.2f) : 0.0f;
    const float rb = i % 7 == 0 ? uniform(rng, 0.02f, 0.2f) : 0.0f;
    Scene s{test::random_polygon(rng, na, 0.5f, ra), test::random_polygon(rng, nb, 0.5f, rb), {},
            {}};
    s.xa = test::random_transform(rng, 2.0f);
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 1.3f), uniform(rng, -3.0f, 3.0f));
    const DistanceResult r = distance(s.a, s.xa, s.b, s.xb);
    const double peer = std::max(
        test::box2d_core_distance(s.a, s.xa, s.b, s.xb) - double(ra) - double(rb), 0.0);
    EXPECT_NEAR(r.distance, peer, kTol) << "trial " << i << " (" << na << " vs " << nb << ")";
    check_against_brute_force(s, r, "trial " + std::to_string(i));
    if (peer > kTol) ++apart;
  }
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_LT(apart, trials * 7 / 10);
}

TEST(GjkDistance, TinyHugeAndSliverShapesScaleTheirAccuracy) {
  // Tolerances are relative: scenes 1e-3 and 1e3 across, and thin slivers (aspect 1:200), are
  // answered to 1e-4 of their own size, never at max_iterations.
  std::mt19937 rng(123);
  int apart = 0;
  int trials = 0;
  for (const float size : {1e-3f, 1.0f, 1e3f}) {
    for (int i = 0; i < 200; ++i, ++trials) {
      const float sliver = 0.005f * size;
      const std::vector<Vec2> thin = {{-size, -sliver}, {size, -sliver}, {size, sliver},
                                      {-size, sliver}};
      const Polygon a = i % 2 ? make_polygon(thin) : test::random_polygon(rng, 6, size);
      const Polygon b = i % 3 ? test::random_polygon(rng, 5, 0.5f * size, 0.05f * size)
                              : make_polygon(thin);
      const Transform xa = Transform::from(test::random_point(rng, size), uniform(rng, -3.0f, 3.0f));
      const Transform xb =
          Transform::from(xa.p + test::random_point(rng, 2.0f * size), uniform(rng, -3.0f, 3.0f));
      const DistanceResult r = distance(a, xa, b, xb);
      const test::WorldCore ca = test::world_core(a, xa);
      const test::WorldCore cb = test::world_core(b, xb);
      const double truth =
          std::max(test::brute_core_distance(ca.points, cb.points) - ca.radius - cb.radius, 0.0);
      EXPECT_NEAR(r.distance, truth, 1e-4 * 4.0 * size) << "size " << size << " trial " << i;
      EXPECT_NE(r.status, QueryStatus::max_iterations);
      if (truth > 1e-4 * size) ++apart;
    }
  }
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_LT(apart, trials * 9 / 10);
}

TEST(GjkDistance, ParallelFacesAtKnownGap) {
  // Two 2x2 boxes with parallel faces 0.5 apart, under random rigid transforms.
  std::mt19937 rng(3);
  const Polygon box = make_box({1.0f, 1.0f});
  for (int i = 0; i < 100; ++i) {
    // Near the origin any rotation; 1e4 away quarter turns and offsets on a 1/64 grid, so that
    // the placed boxes are exactly 0.5 apart in float.
    const float far_turns[] = {0.0f, 1.0f, 0.0f, -1.0f};
    const Transform g =
        i < 50 ? test::random_transform(rng, 10.0f)
               : Transform{{1e4f, -1e4f}, {far_turns[i % 4], far_turns[(i + 1) % 4]}};
    const float tol = i < 50 ? kTol : kFarPointTol;
    const float slide = std::round(uniform(rng, -1.5f, 1.5f) * 64.0f) / 64.0f;
    const Transform xa = mul(g, Transform{});
    const Transform xb = mul(g, Transform::from({2.5f, slide}, 0.0f));
    const DistanceResult r = distance(box, xa, box, xb);
    EXPECT_NEAR(r.distance, 0.5f, kTol);
    EXPECT_EQ(r.status, QueryStatus::separated);
    EXPECT_VEC2_NEAR(r.normal, rotate(g.q, {1.0f, 0.0f}), 1e-4f);
    const Vec2 la = inv_transform_point(g, r.point_a);
    const Vec2 lb = inv_transform_point(g, r.point_b);
    EXPECT_NEAR(la.x, 1.0f, tol);
    EXPECT_NEAR(lb.x, 1.5f, tol);
    EXPECT_NEAR(la.y, lb.y, tol);
    EXPECT_LE(std::abs(la.y), 1.0f + tol);  // on the shared span of both faces
  }
}

TEST(GjkDistance, TouchingExactlyIsDistanceZero) {
  std::mt19937 rng(4);
  const Polygon box = make_box({1.0f, 0.5f});
  const Circle circle = make_circle({0.0f, 0.0f}, 0.75f);
  for (int i = 0; i < 50; ++i) {
    const Transform g = test::random_transform(rng, 10.0f);
    // Face to face, corner to face, circle on a face.
    const DistanceResult ff =
        distance(box, g, box, mul(g, Transform::from({2.0f, 0.3f}, 0.0f)));
    const DistanceResult cf = distance(
        box, g, box, mul(g, Transform::from({1.0f + std::sqrt(1.25f), 0.0f}, std::atan2(0.5f, 1.0f))));
    const DistanceResult circ = distance(box, g, circle, mul(g, Transform::from({0.2f, 1.25f}, 0.0f)));
    EXPECT_NEAR(ff.distance, 0.0f, kTol);
    EXPECT_NEAR(cf.distance, 0.0f, kTol);
    EXPECT_NEAR(circ.distance, 0.0f, kTol);
    // And a hair apart is a positive distance.
    const DistanceResult gap =
        distance(box, g, box, mul(g, Transform::from({2.01f, 0.3f}, 0.0f)));
    EXPECT_NEAR(gap.distance, 0.01f, kTol);
  }
}

TEST(GjkDistance, CirclesAndCapsulesAnalytic) {
  std::mt19937 rng(8);
  for (int i = 0; i < 200; ++i) {
    const Circle a = make_circle(test::random_point(rng, 1.0f), uniform(rng, 0.1f, 1.0f));
    const Circle b = make_circle(test::random_point(rng, 1.0f), uniform(rng, 0.1f, 1.0f));
    const Transform xa = test::random_transform(rng, 3.0f);
    const Transform xb = test::random_transform(rng, 3.0f);
    const Vec2 ca = transform_point(xa, a.center);
    const Vec2 cb = transform_point(xb, b.center);
    const float centres = distance(ca, cb);
    const DistanceResult r = distance(a, xa, b, xb);
    EXPECT_NEAR(r.distance, std::max(centres - a.radius - b.radius, 0.0f), kTol);
    const Vec2 n = (cb - ca) / centres;
    EXPECT_VEC2_NEAR(r.normal, n, 1e-4f);
    EXPECT_VEC2_NEAR(r.point_a, ca + a.radius * n, kTol);
    EXPECT_VEC2_NEAR(r.point_b, cb - b.radius * n, kTol);
  }
  // Parallel capsules side by side: distance = gap between the axes minus the radii.
  const Capsule cap = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.25f);
  for (int i = 0; i < 50; ++i) {
    const Transform g = test::random_transform(rng, 10.0f);
    const float gap = uniform(rng, 0.1f, 2.0f);
    const DistanceResult r =
        distance(cap, g, cap, mul(g, Transform::from({uniform(rng, -1.5f, 1.5f), gap}, 0.0f)));
    EXPECT_NEAR(r.distance, std::max(gap - 0.5f, 0.0f), kTol);
    EXPECT_VEC2_NEAR(r.normal, rotate(g.q, {0.0f, 1.0f}), 1e-4f);
  }
}

TEST(GjkDistance, RoundedCoresApartButRadiiOverlap) {
  // Rounded boxes whose cores are 0.2 apart and radii sum to 0.3: touching through the radii.
  const Polygon a = make_box({1.0f, 1.0f}, 0.15f);
  const Polygon b = make_box({0.5f, 0.5f}, 0.15f);
  const Transform xb = Transform::from({1.7f, 0.0f}, 0.0f);
  const DistanceResult r = distance(a, Transform{}, b, xb);
  EXPECT_EQ(r.status, QueryStatus::separated);
  EXPECT_EQ(r.distance, 0.0f);
  EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-5f);
  // On the line between the core witnesses, each pushed out by its radius: past each other.
  EXPECT_NEAR(r.point_a.x, 1.15f, kTol);
  EXPECT_NEAR(r.point_b.x, 1.05f, kTol);
  EXPECT_NEAR(r.point_a.y, r.point_b.y, kTol);
}

TEST(GjkDistance, OverlappingCoresReportOverlapped) {
  std::mt19937 rng(12);
  const Polygon box = make_box({1.0f, 1.0f});
  for (int i = 0; i < 100; ++i) {
    const Polygon p = test::random_polygon(rng, 3 + i % 6, 1.0f, i % 2 ? 0.1f : 0.0f);
    const Transform xa = test::random_transform(rng, 5.0f);
    const Transform xb = mul(xa, Transform::from(test::random_point(rng, 0.5f), uniform(rng, -3.0f, 3.0f)));
    const DistanceResult r = distance(box, xa, p, xb);
    EXPECT_EQ(r.status, QueryStatus::overlapped);
    EXPECT_EQ(r.distance, 0.0f);
    EXPECT_EQ(r.normal, Vec2(0.0f, 0.0f));
    EXPECT_EQ(r.point_a, r.point_b);
    const test::WorldCore ca = test::world_core(box, xa);
    const test::WorldCore cb = test::world_core(p, xb);
    EXPECT_LE(test::brute_point_distance(ca.points, {r.point_a.x, r.point_a.y}), kTol);
    EXPECT_LE(test::brute_point_distance(cb.points, {r.point_b.x, r.point_b.y}), kTol);
  }
}

TEST(GjkDistance, WarmStartSameAnswerAndNoMoreIterations) {
  std::mt19937 rng(77);
  int cold_total = 0;
  int warm_total = 0;
  for (int run = 0; run < 20; ++run) {
    const Polygon a = test::random_polygon(rng, 8 + run % 3 * 20, 1.0f);
    const Polygon b = test::random_polygon(rng, 5 + run % 4, 0.7f, run % 2 ? 0.05f : 0.0f);
    const Transform xa = test::random_transform(rng, 3.0f);
    SimplexCache cache;
    // B orbits A slowly (a small step per frame), staying apart.
    const float start = uniform(rng, -3.0f, 3.0f);
    for (int frame = 0; frame < 100; ++frame) {
      const float t = start + 0.01f * static_cast<float>(frame);
      const Transform xb =
          Transform::from(xa.p + 2.6f * Vec2{std::cos(t), std::sin(t)}, 0.5f * t);
      // GJK itself (the polygon overload of `distance` checks cached pairs without GJK: see
      // PolygonDistance.WarmPairsAgreeWithColdAndBruteForce).
      const DistanceResult cold = gjk_distance(ConvexProxy(a), xa, ConvexProxy(b), xb);
      const DistanceResult warm = gjk_distance(ConvexProxy(a), xa, ConvexProxy(b), xb, &cache);
      ASSERT_EQ(cold.status, QueryStatus::separated);
      EXPECT_EQ(warm.status, QueryStatus::separated);
      EXPECT_NEAR(warm.distance, cold.distance, 1e-5f);
      EXPECT_VEC2_NEAR(warm.point_a, cold.point_a, kTol);
      EXPECT_VEC2_NEAR(warm.point_b, cold.point_b, kTol);
      EXPECT_LE(warm.iterations, cold.iterations) << "run " << run << " frame " << frame;
      cold_total += cold.iterations;
      warm_total += warm.iterations;
    }
  }
  EXPECT_LT(warm_total, cold_total / 2) << "warm start should save most iterations";
}

TEST(GjkDistance, BadCacheFallsBackToColdStart) {
  const Polygon a = make_box({1.0f, 1.0f});
  const Circle b = make_circle({0.0f, 0.0f}, 0.5f);
  const Transform xb = Transform::from({3.0f, 0.5f}, 0.0f);
  const DistanceResult cold = distance(a, Transform{}, b, xb);
  // Indices out of range for these shapes, repeated vertices, an impossible count.
  SimplexCache out_of_range{2, {7, 200}, {0, 3}};
  SimplexCache repeated{3, {1, 1, 1}, {0, 0, 0}};
  SimplexCache bad_count{9, {}, {}};
  for (SimplexCache* c : {&out_of_range, &repeated, &bad_count}) {
    const DistanceResult r = distance(a, Transform{}, b, xb, c);
    EXPECT_NEAR(r.distance, cold.distance, 1e-6f);
    EXPECT_NEAR(r.distance, 1.5f, kTol);
    EXPECT_GE(c->count, 1);
    EXPECT_LE(c->count, 2);
    for (int i = 0; i < c->count; ++i) {
      EXPECT_LT(c->index_a[i], 4);
      EXPECT_LT(c->index_b[i], 1);
    }
  }
  // A cache from a different, larger pair: indices valid for A but meaning other vertices.
  SimplexCache stale{2, {2, 3}, {0, 0}};
  EXPECT_NEAR(distance(a, Transform{}, b, xb, &stale).distance, 1.5f, kTol);
}

/// A pair of polygons of 3..10 vertices (some rounded) placed so that every kind of closest
/// pair occurs: faces, corners facing each other, overlapping cores.
test::Scene random_polygon_scene(std::mt19937& rng) {
  const int na = 3 + static_cast<int>(rng() % 8);
  const int nb = 3 + static_cast<int>(rng() % 8);
  const float ra = rng() % 3 == 0 ? uniform(rng, 0.01f, 0.2f) : 0.0f;
  const float rb = rng() % 3 == 0 ? uniform(rng, 0.01f, 0.2f) : 0.0f;
  test::Scene s{test::random_polygon(rng, na, uniform(rng, 0.3f, 1.0f), ra),
                test::random_polygon(rng, nb, uniform(rng, 0.3f, 1.0f), rb), {}, {}};
  s.xa = test::random_transform(rng, 2.0f);
  const float angle = uniform(rng, -3.14f, 3.14f);
  s.xb = Transform::from(s.xa.p + uniform(rng, 0.3f, 3.0f) * Vec2{std::cos(angle), std::sin(angle)},
                         uniform(rng, -3.14f, 3.14f));
  return s;
}

TEST(PolygonDistance, EveryPathAgreesWithBruteForceAndGjk) {
  std::mt19937 rng(20261127);
  int by_pair = 0;    // answered without GJK (iterations 0)
  int corners = 0;    // ... with a corner of each (the cache names one vertex pair)
  int faces = 0;      // ... with an edge and a vertex
  int with_gjk = 0;
  const int trials = 6000;
  for (int i = 0; i < trials; ++i) {
    const test::Scene s = random_polygon_scene(rng);
    const Polygon& a = std::get<Polygon>(s.a);
    const Polygon& b = std::get<Polygon>(s.b);
    SimplexCache cache;
    const DistanceResult r = distance(a, s.xa, b, s.xb, &cache);
    const std::string what = std::to_string(a.count) + "-gon/" + std::to_string(b.count) +
                             "-gon trial " + std::to_string(i);
    SCOPED_TRACE(what);
    check_against_brute_force(s, r, what);
    const DistanceResult g = gjk_distance(ConvexProxy(a), s.xa, ConvexProxy(b), s.xb);
    EXPECT_EQ(r.status, g.status) << what;
    EXPECT_NEAR(r.distance, g.distance, 1e-5f) << what;
    if (r.status == QueryStatus::separated && g.distance > kTol) {
      EXPECT_VEC2_NEAR(r.point_a, g.point_a, kTol);
      EXPECT_VEC2_NEAR(r.point_b, g.point_b, kTol);
      EXPECT_VEC2_NEAR(r.normal, g.normal, 1e-4f);
    }
    // Swapped, the same pair seen from B.
    const DistanceResult w = distance(b, s.xb, a, s.xa);
    EXPECT_NEAR(w.distance, r.distance, 1e-5f) << what;
    if (r.status == QueryStatus::separated && r.distance > kTol) {
      EXPECT_VEC2_NEAR(w.point_a, r.point_b, kTol);
      EXPECT_VEC2_NEAR(w.normal, -r.normal, 1e-4f);
    }
    // The cache written names features valid for GJK, which then agrees at once.
    SimplexCache again = cache;
    const DistanceResult h = gjk_distance(ConvexProxy(a), s.xa, ConvexProxy(b), s.xb, &again);
    EXPECT_NEAR(h.distance, r.distance, 1e-5f) << what;
    if (r.iterations == 0) {
      ++by_pair;
      (cache.count == 1 ? corners : faces) += 1;
      EXPECT_LE(h.iterations, 1) << what << ": the cached pair was not GJK's answer";
    } else {
      ++with_gjk;
    }
  }
  // Every path exercised: face pairs, corner pairs, and GJK (overlaps, larger polygons).
  EXPECT_GT(faces, trials / 4);
  EXPECT_GT(corners, trials / 10);
  EXPECT_GT(with_gjk, trials / 10);
  EXPECT_EQ(by_pair + with_gjk, trials);
}

/// The polygon pair of `s` warm-started from `cache` (updated), checked against brute force
/// and against the same query without a cache: the same status and distance, and for cores
/// apart the same points. Returns the warm answer.
DistanceResult warm_agrees_with_cold(const test::Scene& s, SimplexCache& cache, const std::string& what) {
  const Polygon& a = std::get<Polygon>(s.a);
  const Polygon& b = std::get<Polygon>(s.b);
  const DistanceResult warm = distance(a, s.xa, b, s.xb, &cache);
  const DistanceResult cold = distance(a, s.xa, b, s.xb);
  SCOPED_TRACE(what);
  check_against_brute_force(s, warm, what);
  EXPECT_EQ(warm.status, cold.status) << what;
  EXPECT_NEAR(warm.distance, cold.distance, 1e-5f) << what;
  if (cold.status == QueryStatus::separated && cold.distance > kTol) {
    EXPECT_VEC2_NEAR(warm.point_a, cold.point_a, kTol);
    EXPECT_VEC2_NEAR(warm.point_b, cold.point_b, kTol);
  }
  return warm;
}

TEST(PolygonDistance, WarmPairsAgreeWithColdAndBruteForce) {
  std::mt19937 rng(1127);
  int checked_pairs = 0;
  for (int run = 0; run < 60; ++run) {
    test::Scene s = random_polygon_scene(rng);
    SimplexCache cache;
    const Vec2 offset = s.xb.p - s.xa.p;
    const float turn = s.xb.q.angle();
    for (int frame = 0; frame < 80; ++frame) {
      // B orbits A and turns, so the closest pair moves from feature to feature; every 20th
      // frame it jumps to the other side (the cached pair is then far from the answer).
      const float t = 0.02f * static_cast<float>(frame) + (frame % 20 == 19 ? 3.0f : 0.0f);
      s.xb = Transform::from(s.xa.p + rotate(Rot2::from_angle(t), offset), turn + 1.5f * t);
      const int cached_count = cache.count;
      const DistanceResult warm =
          warm_agrees_with_cold(s, cache, "run " + std::to_string(run) + " frame " + std::to_string(frame));
      if (cached_count > 0 && warm.iterations == 0) ++checked_pairs;
    }
  }
  EXPECT_GT(checked_pairs, 60 * 40);  // most frames answered from the warm pair or the axes
}

TEST(PolygonDistance, OverlapsStartedFromTheCachedTriangleAgreeWithColdAndBruteForce) {
  // B slides through A and out the other side, warm-started every frame: while the cores
  // overlap the cache holds GJK's triangle around the origin, which the next frame checks
  // first (cached_triangle_holds_origin); as B leaves, the triangle no longer holds the origin
  // and the answer comes from the walk or GJK as on a cold start. Every frame against the cold
  // answer and brute force.
  std::mt19937 rng(20261130);
  int from_triangle = 0;  // frames that began with a cached triangle and overlapped
  int left_triangle = 0;  // frames that began with a cached triangle and came out apart
  for (int run = 0; run < 80; ++run) {
    test::Scene s = random_polygon_scene(rng);
    const float angle = uniform(rng, -3.14f, 3.14f);
    const Vec2 dir{std::cos(angle), std::sin(angle)};
    const float turn = s.xb.q.angle();
    SimplexCache cache;
    for (int frame = 0; frame <= 60; ++frame) {
      const float t = -3.0f + 0.1f * static_cast<float>(frame);  // from 3 units away to 3 beyond
      s.xb = Transform::from(s.xa.p + t * dir, turn + 0.05f * t);
      const bool had_triangle = cache.count == 3;
      const DistanceResult warm =
          warm_agrees_with_cold(s, cache, "run " + std::to_string(run) + " frame " + std::to_string(frame));
      if (had_triangle) (warm.status == QueryStatus::overlapped ? from_triangle : left_triangle) += 1;
    }
  }
  EXPECT_GT(from_triangle, 80 * 5);
  EXPECT_GT(left_triangle, 40);
}

TEST(PolygonDistance, ZeroLengthEdgesGiveFiniteAnswers) {
  // A box 2e-9 high, 5 units from the origin: its corners round onto each other in pairs, so
  // two of its edges have no length (fuzz_shapes found the walk dividing 0 by 0 on one). Cold
  // and warm-started, around it at several distances, against brute force.
  const Polygon thin = make_box({0.5f, 1e-9f}, {5.0f, 1.0f}, 0.2877f, 5.0f);
  ASSERT_EQ(thin.vertices[1], thin.vertices[2]) << "the test needs coinciding corners";
  const Polygon box = make_box({0.75f, 0.5f});
  for (int k = 0; k < 120; ++k) {
    const float angle = 0.0523599f * static_cast<float>(k);  // every 3 degrees
    for (const float reach : {1.0f, 3.0f, 4.5f, 6.0f}) {
      for (const float turn : {0.0f, 0.3f, 1.0f}) {
        const Transform xb = Transform::from(Vec2{5.0f, 1.0f} + reach * Vec2{std::cos(angle), std::sin(angle)}, turn);
        const test::Scene s{thin, box, Transform{}, xb};
        SimplexCache cache;
        const std::string what = "angle step " + std::to_string(k) + " reach " + std::to_string(reach) +
                                 " turn " + std::to_string(turn);
        warm_agrees_with_cold(s, cache, what + " (cold start)");
        warm_agrees_with_cold(s, cache, what + " (warm)");
      }
    }
  }
}

TEST(PolygonDistance, WrongCachesAreCheckedNotTrusted) {
  // Two unit boxes 3 apart along x: the closest pair is A's right edge (1 -> 2) and B's left
  // edge. Caches naming other features, or indices these boxes do not have, must not change
  // the answer (2 apart).
  const Polygon a = make_box({0.5f, 0.5f});
  const Polygon b = make_box({0.5f, 0.5f});
  const Transform xb = Transform::from({3.0f, 0.2f}, 0.0f);
  const std::array<SimplexCache, 7> caches = {
      SimplexCache{2, {3, 0}, {1, 1}},    // A's left edge: an edge, but on the far side
      SimplexCache{1, {0}, {2}},          // corners on the far sides
      SimplexCache{1, {1}, {3}},          // a corner of each, near but not the closest pair
      SimplexCache{2, {2, 2}, {0, 2}},    // B's "edge" 0 -> 2 is a diagonal
      SimplexCache{2, {1, 2}, {9, 9}},    // B has no vertex 9
      SimplexCache{2, {200, 201}, {0, 0}},
      SimplexCache{7, {}, {}}};
  for (SimplexCache c : caches) {
    const DistanceResult r = distance(a, Transform{}, b, xb, &c);
    EXPECT_EQ(r.status, QueryStatus::separated);
    EXPECT_NEAR(r.distance, 2.0f, 1e-6f);
    EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-6f);
    EXPECT_NEAR(r.point_a.x, 0.5f, 1e-6f);
    EXPECT_NEAR(r.point_b.x, 2.5f, 1e-6f);
    ASSERT_GE(c.count, 1);
    ASSERT_LE(c.count, 3);
    for (int i = 0; i < c.count; ++i) {
      EXPECT_LT(c.index_a[i], 4);
      EXPECT_LT(c.index_b[i], 4);
    }
  }
}

TEST(PolygonDistance, CornersFacingEachOtherAreExact) {
  // Two unit squares turned 45 degrees, corner to corner along x at a known gap: no edge normal
  // of either is the closest direction, so the separating axes alone would under-estimate it.
  const float h = 0.5f * std::sqrt(2.0f);  // corner distance from the centre
  const Polygon a = make_box({0.5f, 0.5f}, {0.0f, 0.0f}, 0.25f * test::kPi);
  const Polygon b = make_box({0.5f, 0.5f}, {0.0f, 0.0f}, 0.25f * test::kPi);
  for (float gap : {1e-3f, 0.1f, 1.0f, 7.5f}) {
    SCOPED_TRACE(gap);
    const Transform xa = Transform::from({-40.0f, 12.0f}, 0.0f);
    const Transform xb = Transform::from(xa.p + Vec2{2.0f * h + gap, 0.0f}, 0.0f);
    SimplexCache cache;
    const DistanceResult r = distance(a, xa, b, xb, &cache);
    EXPECT_NEAR(r.distance, gap, 1e-5f + 1e-6f * gap) << gap;
    EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-5f);
    EXPECT_VEC2_NEAR(r.point_a, (xa.p + Vec2{h, 0.0f}), 1e-5f);
    EXPECT_EQ(r.iterations, 0) << gap << ": a corner pair needs no GJK";
    EXPECT_EQ(cache.count, 1) << gap;
    const DistanceResult warm = distance(a, xa, b, xb, &cache);
    EXPECT_EQ(warm.distance, r.distance) << gap;
  }
}

TEST(PolygonDistance, CirclesAgreeWithBruteForceAndGjkInBothOrders) {
  std::mt19937 rng(271127);
  int edges = 0;     // centre in an edge's region (the cache names an edge)
  int corners = 0;   // ... in a vertex's region
  int with_gjk = 0;  // centre on or inside the core
  const int trials = 4000;
  for (int i = 0; i < trials; ++i) {
    const int n = 3 + static_cast<int>(rng() % 12);  // past 8: the scalar scan
    const float ra = rng() % 3 == 0 ? uniform(rng, 0.01f, 0.2f) : 0.0f;
    const Polygon a = test::random_polygon(rng, n, uniform(rng, 0.3f, 1.0f), ra);
    const Circle b = make_circle(test::random_point(rng, 0.3f), uniform(rng, 0.05f, 0.5f));
    test::Scene s{a, b, test::random_transform(rng, 2.0f), {}};
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 2.5f), uniform(rng, -3.0f, 3.0f));
    const std::string what = std::to_string(n) + "-gon trial " + std::to_string(i);
    SCOPED_TRACE(what);
    SimplexCache cache;
    const DistanceResult r = distance(a, s.xa, b, s.xb, &cache);
    check_against_brute_force(s, r, what);
    const DistanceResult g = gjk_distance(ConvexProxy(a), s.xa, ConvexProxy(b), s.xb);
    EXPECT_EQ(r.status, g.status);
    EXPECT_NEAR(r.distance, g.distance, 1e-5f);
    if (r.status == QueryStatus::separated && g.distance > kTol) {
      EXPECT_VEC2_NEAR(r.point_a, g.point_a, kTol);
      EXPECT_VEC2_NEAR(r.point_b, g.point_b, kTol);
    }
    // The circle first: the same pair, points swapped, normal flipped, cache exchanged.
    SimplexCache flipped;
    const DistanceResult w = distance(b, s.xb, a, s.xa, &flipped);
    EXPECT_NEAR(w.distance, r.distance, 1e-5f);
    EXPECT_EQ(w.status, r.status);
    if (r.status == QueryStatus::separated && r.distance > kTol) {
      EXPECT_VEC2_NEAR(w.point_a, r.point_b, kTol);
      EXPECT_VEC2_NEAR(w.normal, -r.normal, 1e-4f);
    }
    EXPECT_EQ(flipped.count, cache.count);
    EXPECT_EQ(flipped.index_a[0], cache.index_b[0]);
    EXPECT_EQ(flipped.index_b[0], cache.index_a[0]);
    // The cache names GJK's answer.
    const DistanceResult h = gjk_distance(ConvexProxy(a), s.xa, ConvexProxy(b), s.xb, &cache);
    EXPECT_NEAR(h.distance, r.distance, 1e-5f);
    if (r.iterations > 0) {
      ++with_gjk;
    } else {
      EXPECT_LE(h.iterations, 1) << "the cached feature was not GJK's answer";
      (cache.count == 1 ? corners : edges) += 1;
    }
  }
  EXPECT_GT(edges, trials / 5);
  EXPECT_GT(corners, trials / 5);
  EXPECT_GT(with_gjk, trials / 50);
}

TEST(GjkDistance, Shape2DOverloadMatchesTypedCall) {
  std::mt19937 rng(31);
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      const Scene s = random_scene(rng, ta, tb);
      const DistanceResult r = distance(s.a, s.xa, s.b, s.xb);
      const DistanceResult g = std::visit(
          [&](const auto& a, const auto& b) { return distance(a, s.xa, b, s.xb); }, s.a, s.b);
      EXPECT_EQ(r.distance, g.distance);
      EXPECT_EQ(r.point_a, g.point_a);
      EXPECT_EQ(r.point_b, g.point_b);
    }
  }
}

}  // namespace
}  // namespace collide
