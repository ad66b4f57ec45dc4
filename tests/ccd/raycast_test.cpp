// Ray casts checked against Box2D 2.4 (circle, polygon, edge), and capsules and rounded
// polygons against a union of Box2D pieces: a convex union is first entered where its first
// piece is entered, so the truth is the smallest fraction over the pieces (when the origin is in
// no piece). Plus numbered edge cases and a laser bouncing between two mirrors (analytic).

#include <collide/ccd/raycast.hpp>
#include <collide/narrow/closest_point.hpp>

#include "clip_ray.hpp"
#include "support/brute_convex.hpp"
#include "support/bitwise_equal.hpp"
#include "support/test_util.hpp"

#include <box2d/box2d.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace collide {
namespace {

using test::uniform;

b2Vec2 b2(Vec2 v) { return {v.x, v.y}; }
Vec2 vec(b2Vec2 v) { return {v.x, v.y}; }
b2Transform b2(const Transform& xf) {
  b2Transform t;
  t.p = b2(xf.p);
  t.q.c = xf.q.c;
  t.q.s = xf.q.s;
  return t;
}

/// The truth for one ray: Box2D's answer, or the first entry over several Box2D pieces.
struct Truth {
  bool hit = false;
  float fraction = 0.0f;
  Vec2 normal{0.0f, 0.0f};
};

Truth box2d_cast(const std::vector<std::unique_ptr<b2Shape>>& pieces, const Transform& xf,
                 const Ray& ray) {
  b2RayCastInput in;
  in.p1 = b2(ray.origin);
  in.p2 = b2(ray.origin + ray.translation);
  in.maxFraction = 1.0f;
  Truth best;
  for (const auto& piece : pieces) {
    b2RayCastOutput out;
    if (piece->RayCast(&out, in, b2(xf), 0) && (!best.hit || out.fraction < best.fraction)) {
      best = {true, out.fraction, vec(out.normal)};
    }
  }
  return best;
}

std::unique_ptr<b2Shape> b2_circle(Vec2 c, float r) {
  auto s = std::make_unique<b2CircleShape>();
  s->m_p = b2(c);
  s->m_radius = r;
  return s;
}

std::unique_ptr<b2Shape> b2_polygon(const std::vector<Vec2>& pts) {
  std::vector<b2Vec2> v;
  for (Vec2 p : pts) v.push_back(b2(p));
  auto s = std::make_unique<b2PolygonShape>();
  s->Set(v.data(), static_cast<int32>(v.size()));
  s->m_radius = 0.0f;
  EXPECT_EQ(s->m_count, static_cast<int32>(pts.size())) << "Box2D welded a vertex";
  return s;
}

std::vector<Vec2> core_vertices(const Polygon& p) {
  return std::vector<Vec2>(p.vertices.begin(), p.vertices.begin() + p.count);
}

/// Pieces whose union is the shape, and a brute-force test of "local point in closed shape".
struct Oracle {
  std::vector<std::unique_ptr<b2Shape>> pieces;
  std::function<bool(Vec2)> contains;
};

Oracle oracle_for(const Circle& c) {
  Oracle o;
  o.pieces.push_back(b2_circle(c.center, c.radius));
  o.contains = [c](Vec2 p) { return distance(p, c.center) <= c.radius; };
  return o;
}

Oracle oracle_for(const Segment& s) {
  Oracle o;
  auto edge = std::make_unique<b2EdgeShape>();
  edge->SetTwoSided(b2(s.a), b2(s.b));
  o.pieces.push_back(std::move(edge));
  o.contains = [](Vec2) { return false; };  // measure zero: random origins are never on it
  return o;
}

Oracle oracle_for(const Capsule& c) {
  Oracle o;
  const Vec2 n = normalize_or_zero(right_perp(c.b - c.a)) * c.radius;
  o.pieces.push_back(b2_polygon({c.a + n, c.b + n, c.b - n, c.a - n}));
  o.pieces.push_back(b2_circle(c.a, c.radius));
  o.pieces.push_back(b2_circle(c.b, c.radius));
  o.contains = [c](Vec2 p) {
    return distance(p, test::closest_on_segment(c.a, c.b, p)) <= c.radius;
  };
  return o;
}

Oracle oracle_for(const Polygon& poly) {
  Oracle o;
  const std::vector<Vec2> core = core_vertices(poly);
  o.pieces.push_back(b2_polygon(core));
  const float r = poly.radius;
  if (r > 0.0f) {
    for (int i = 0; i < poly.count; ++i) {
      const Vec2 a = poly.vertex(i), b = poly.vertex(i + 1);
      const Vec2 n = normalize_or_zero(right_perp(b - a)) * r;
      o.pieces.push_back(b2_polygon({a, a + n, b + n, b}));
      o.pieces.push_back(b2_circle(a, r));
    }
  }
  o.contains = [core, r](Vec2 p) {
    const test::BruteDistance d = test::brute_distance(core, p);
    return d.inside || d.boundary <= r;
  };
  return o;
}

/// Where rays aim, local space: near the shape, so that hits and misses are both common.
template <class S>
Vec2 aim_point(const S&, std::mt19937& rng, float extent) {
  return test::random_point(rng, extent);
}
Vec2 aim_point(const Segment& s, std::mt19937& rng, float) {
  return s.a + uniform(rng, -0.2f, 1.2f) * (s.b - s.a) + test::random_point(rng, 0.5f);
}

struct Tolerances {
  float fraction;
  float point;
  float normal;
  float max_disagreement_rate;  ///< hit/miss disagreements allowed (grazing rays far out)
};

/// Random rays around a shape placed by random transforms, compared with the oracle. Rays
/// start and end in a disc of `reach` around the shape's placement; `far` offsets everything.
template <class S>
void compare_with_oracle(const std::vector<S>& shapes, std::mt19937& rng, float reach, Vec2 far,
                         const Tolerances& tol) {
  int hits = 0, misses = 0, disagreements = 0, total = 0;
  for (const S& shape : shapes) {
    const Oracle oracle = oracle_for(shape);
    for (int k = 0; k < 200; ++k) {
      const Transform xf{far + test::random_point(rng, 5.0f),
                         Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
      // Aim at a point near the shape, and stop short of it or overshoot.
      const Vec2 origin = xf.p + test::random_point(rng, reach);
      const Vec2 target = transform_point(xf, aim_point(shape, rng, 0.6f * reach));
      const Ray ray{origin, (target - origin) * uniform(rng, 0.5f, 2.0f)};
      const RayHit ours = raycast(shape, xf, ray);
      const bool starts_inside = oracle.contains(inv_transform_point(xf, ray.origin));
      // Box2D gets the same float inputs shifted exactly (Sterbenz) back near the origin, where
      // its own precision is good: the truth for the far inputs as given.
      const Transform shifted_xf{xf.p - far, xf.q};
      const Ray shifted{ray.origin - far, ray.translation};
      Truth truth = box2d_cast(oracle.pieces, shifted_xf, shifted);
      if (starts_inside) truth = {};
      ++total;
      if (ours.hit != truth.hit) {
        ++disagreements;
        continue;
      }
      if (!truth.hit) {
        ++misses;
        EXPECT_EQ(ours.fraction, 0.0f);
        EXPECT_EQ(ours.normal, Vec2(0.0f, 0.0f));
        continue;
      }
      ++hits;
      // A grazing hit is ill-conditioned: a surface error e moves the entry by
      // e / cos(incidence) along the ray. Scale the tolerances by that.
      const float incidence = std::fabs(dot(truth.normal, normalize_or_zero(ray.translation)));
      const float conditioning = 1.0f / std::max(incidence, 0.01f);
      EXPECT_NEAR(ours.fraction, truth.fraction, tol.fraction * conditioning);
      EXPECT_GE(ours.fraction, 0.0f);
      EXPECT_LE(ours.fraction, 1.0f);
      EXPECT_VEC2_NEAR(ours.point, ray.at(truth.fraction), tol.point * conditioning);
      EXPECT_VEC2_NEAR(ours.normal, truth.normal, tol.normal);
      EXPECT_NEAR(length(ours.normal), 1.0f, 1e-5f);
      // The hit point is on the surface.
      EXPECT_NEAR(closest_point(shape, xf, ours.point).distance, 0.0f, tol.point);
      // And the Shape2D overload agrees exactly.
      const RayHit any = raycast(Shape2D{shape}, xf, ray);
      EXPECT_EQ(any.fraction, ours.fraction);
    }
  }
  EXPECT_GT(hits, total * 3 / 10) << "hit rate too low to test hits";
  EXPECT_GT(misses, total * 3 / 10) << "miss rate too low to test misses";
  EXPECT_LE(disagreements, static_cast<int>(tol.max_disagreement_rate * total))
      << disagreements << " hit/miss disagreements of " << total;
  std::printf("[ rates    ] %d hits, %d misses, %d disagreements of %d rays\n", hits, misses,
              disagreements, total);
}

constexpr Tolerances kNear{2e-5f, 1e-4f, 1e-3f, 0.0f};
// At 1e4 a float has a spacing of ~1e-3, so a world point rounds by that much; fractions and
// normals are computed in the local frame and stay as exact as near the origin.
constexpr Tolerances kFar{2e-5f, 2e-3f, 1e-3f, 0.0f};
const Vec2 kFarAway{1.0e4f, -1.0e4f};

std::vector<Circle> random_circles(std::mt19937& rng) {
  std::vector<Circle> v;
  for (int i = 0; i < 20; ++i)
    v.push_back(make_circle(test::random_point(rng, 1.0f), uniform(rng, 0.3f, 3.0f)));
  return v;
}
std::vector<Capsule> random_capsules(std::mt19937& rng) {
  std::vector<Capsule> v;
  for (int i = 0; i < 20; ++i) {
    v.push_back(make_capsule(test::random_point(rng, 2.0f), test::random_point(rng, 2.0f),
                             uniform(rng, 0.1f, 1.5f)));
  }
  return v;
}
std::vector<Polygon> random_polygons(std::mt19937& rng, bool rounded) {
  std::vector<Polygon> v;
  for (int i = 0; i < 30; ++i) {
    v.push_back(test::random_polygon(rng, 3 + i % 6, uniform(rng, 0.5f, 3.0f),
                                     rounded ? uniform(rng, 0.1f, 1.0f) : 0.0f));
  }
  return v;
}
std::vector<Segment> random_segments(std::mt19937& rng) {
  std::vector<Segment> v;
  for (int i = 0; i < 20; ++i) {
    v.push_back(make_segment(test::random_point(rng, 3.0f), test::random_point(rng, 3.0f)));
  }
  return v;
}

TEST(Raycast, CircleMatchesBox2D) {
  std::mt19937 rng(1);
  compare_with_oracle(random_circles(rng), rng, 4.0f, {0.0f, 0.0f}, kNear);
  compare_with_oracle(random_circles(rng), rng, 4.0f, kFarAway, kFar);
}

TEST(Raycast, PolygonMatchesBox2D) {
  std::mt19937 rng(2);
  compare_with_oracle(random_polygons(rng, false), rng, 4.0f, {0.0f, 0.0f}, kNear);
  compare_with_oracle(random_polygons(rng, false), rng, 4.0f, kFarAway, kFar);
}

TEST(Raycast, SegmentMatchesBox2DEdge) {
  std::mt19937 rng(3);
  compare_with_oracle(random_segments(rng), rng, 2.0f, {0.0f, 0.0f}, kNear);
  compare_with_oracle(random_segments(rng), rng, 2.0f, kFarAway, kFar);
}

TEST(Raycast, CapsuleMatchesUnionOfBox2DPieces) {
  std::mt19937 rng(4);
  compare_with_oracle(random_capsules(rng), rng, 4.0f, {0.0f, 0.0f}, kNear);
  compare_with_oracle(random_capsules(rng), rng, 4.0f, kFarAway, kFar);
}

// Rays from 1e4 sizes away onto a capsule's flat side close to an end: the end disc is entered
// within rounding of the side there, and must not be named (its normal is turned by
// sqrt(2 (L - x) / r) from the side's).
TEST(Raycast, FarRaysOntoTheSideNearAnEndKeepTheSidesNormal) {
  std::mt19937 rng(43);
  const Capsule capsule = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f);
  int checked = 0;
  for (int i = 0; i < 4000; ++i) {
    const Transform xf = test::random_transform(rng, 10.0f);
    const float x = uniform(rng, 0.95f, 0.999f) * (i % 2 == 0 ? 1.0f : -1.0f);
    const float side = i % 4 < 2 ? 1.0f : -1.0f;
    const Vec2 target{x, 0.5f * side};
    const float angle = uniform(rng, 0.3f, 2.8f);  // from above (below) the side, not grazing
    const Vec2 from = target + 1.0e4f * Vec2{std::cos(angle), side * std::sin(angle)};
    const Ray ray{transform_point(xf, from), rotate(xf.q, 1.5f * (target - from))};
    const RayHit h = raycast(capsule, xf, ray);
    ASSERT_TRUE(h.hit) << i;
    EXPECT_NEAR(h.fraction, 1.0f / 1.5f, 1e-6f);
    // Within rounding of the end (the side's crossing is placed to about 1e4 L float epsilons
    // there: 1e-3) either piece may be named, as with the branches this replaced: only hits
    // measurably beside the core must carry the side's normal.
    const Vec2 local = inv_transform_point(xf, ray.at(h.fraction));
    if (std::fabs(local.x) > 0.995f) continue;
    ++checked;
    SCOPED_TRACE(testing::Message() << "ray " << i << " at x " << x);
    EXPECT_VEC2_NEAR(h.normal, rotate(xf.q, Vec2{0.0f, side}), 1e-5f);
  }
  EXPECT_GT(checked, 3000);
}

// Rays towards a capsule's flat side that end r (1 + delta) from the core's line, beside the
// core: ending inside (delta < 0) they hit the side where they cross y = r, at the fraction
// that crossing gives; ending short they miss, whether the cast's early out takes them (beyond
// its slack) or the full cast does (within it). Near the origin and 1e4 away (the rays' rounding
// there, about 6e-4, stays below delta r).
TEST(Raycast, CapsuleRaysEndingNearTheSideHitOnlyPastIt) {
  std::mt19937 rng(47);
  int hits = 0, misses = 0;
  const std::array<float, 10> near_deltas{-0.5f, -0.05f, -0.01f, -2e-3f, 2e-3f, 4e-3f, 0.01f, 0.05f, 0.5f, 5.0f};
  const std::array<float, 8> far_deltas{-0.5f, -0.05f, -0.02f, 0.02f, 0.05f, 0.2f, 0.5f, 5.0f};
  for (int i = 0; i < 400; ++i) {
    const bool far = i % 2 == 1;
    const float r = uniform(rng, 0.2f, 1.0f), half = uniform(rng, 0.5f, 2.0f);
    const Capsule capsule = make_capsule({-half, 0.0f}, {half, 0.0f}, r);
    const Transform xf = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const float delta = far ? far_deltas[static_cast<std::size_t>(i / 2) % far_deltas.size()]
                            : near_deltas[static_cast<std::size_t>(i / 2) % near_deltas.size()];
    const float side = i % 4 < 2 ? 1.0f : -1.0f;
    const Vec2 from{uniform(rng, -0.6f, 0.6f) * half, 3.0f * r * side};
    const Vec2 to{uniform(rng, -0.6f, 0.6f) * half, r * (1.0f + delta) * side};
    const Ray ray{transform_point(xf, from), rotate(xf.q, to - from)};
    const RayHit h = raycast(capsule, xf, ray);
    SCOPED_TRACE(testing::Message() << "ray " << i << " delta " << delta);
    if (delta < 0.0f) {
      ASSERT_TRUE(h.hit);
      EXPECT_NEAR(h.fraction, 2.0f / (2.0f - delta), far ? 2e-3f : 1e-5f);
      EXPECT_VEC2_NEAR(h.normal, rotate(xf.q, Vec2{0.0f, side}), far ? 1e-3f : 1e-5f);
      ++hits;
    } else {
      EXPECT_FALSE(h.hit);
      ++misses;
    }
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 100);
}

// A capsule of radius 0 is its core segment: the same hits as the segment's cast (the capsule's
// side lane crosses the core's line, its end discs have no area), normals facing the ray; and a
// ray along the core's line hits the nearer end head on, normal back along the ray.
TEST(Raycast, ZeroRadiusCapsuleIsItsSegment) {
  std::mt19937 rng(41);
  int hits = 0, total = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec2 a = test::random_point(rng, 2.0f), b = test::random_point(rng, 2.0f);
    const Capsule capsule = make_capsule(a, b, 0.0f);
    const Segment seg = make_segment(a, b);
    const Transform xf = test::random_transform(rng, 10.0f);
    for (int k = 0; k < 20; ++k) {
      const Vec2 origin = transform_point(xf, test::random_point(rng, 4.0f));
      const Ray ray{origin, (transform_point(xf, test::random_point(rng, 2.0f)) - origin) * uniform(rng, 0.5f, 2.0f)};
      const RayHit h = raycast(capsule, xf, ray);
      const RayHit s = raycast(seg, xf, ray);
      ++total;
      ASSERT_EQ(h.hit, s.hit) << i << " " << k;
      if (!h.hit) continue;
      ++hits;
      EXPECT_NEAR(h.fraction, s.fraction, 1e-5f);
      EXPECT_VEC2_NEAR(h.normal, s.normal, 1e-5f);
      EXPECT_LT(dot(h.normal, ray.translation), 0.0f);
    }
  }
  EXPECT_GT(hits, total / 5);
  EXPECT_LT(hits, total * 4 / 5);
  const Capsule capsule = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.0f);
  const RayHit head_on = raycast(capsule, Transform{}, Ray{{-3.0f, 0.0f}, {4.0f, 0.0f}});
  ASSERT_TRUE(head_on.hit);
  EXPECT_NEAR(head_on.fraction, 0.5f, 1e-6f);
  EXPECT_VEC2_NEAR(head_on.normal, Vec2(-1.0f, 0.0f), 1e-6f);
  EXPECT_FALSE(raycast(capsule, Transform{}, Ray{{0.5f, 0.0f}, {4.0f, 0.0f}}).hit);  // starts on it
  // A radius too small to square in float is the segment too, with a unit normal.
  const RayHit tiny = raycast(make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 1e-30f), Transform{},
                              Ray{{-3.0f, 0.0f}, {4.0f, 0.0f}});
  ASSERT_TRUE(tiny.hit);
  EXPECT_VEC2_NEAR(tiny.normal, Vec2(-1.0f, 0.0f), 1e-6f);
}

// Round pieces hit from far away (relative to the radius): the normal is unit (it was the
// offset over the radius, 0.99945 long for r = 1e-3 hit from 1e5 radii away), and where the
// offset rounds to nothing (dead on, tiny radius: it was a zero normal) it faces the ray.
TEST(Raycast, FarAndDeadOnHitsOfRoundPiecesGiveUnitNormals) {
  const Ray ray{{-100.0f, 0.0f}, {200.0f, 0.0f}};
  const std::vector<Vec2> triangle{{0.0f, 0.0f}, {1.0f, 0.0f}, {0.0f, 1.0f}};
  for (const float r : {1e-3f, 1e-6f, 1e-10f, 1e-20f, 1e-30f}) {
    const Shape2D shapes[] = {make_circle({0.0f, 0.0f}, r), make_capsule(Vec2{0.0f, 0.0f}, Vec2{1.0f, 0.0f}, r),
                              make_capsule(Vec2{0.0f, 0.0f}, Vec2{0.0f, 1.0f}, r), make_polygon(triangle, r)};
    for (const Shape2D& shape : shapes) {
      SCOPED_TRACE(testing::Message() << "radius " << r << ", shape " << shape.index());
      const RayHit h = raycast(shape, Transform{}, ray);
      ASSERT_TRUE(h.hit) << r;
      EXPECT_NEAR(h.fraction, 0.5f, 1e-5f) << r;
      EXPECT_VEC2_NEAR(h.normal, Vec2(-1.0f, 0.0f), 1e-6f);
    }
  }
  std::mt19937 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const Vec2 centre = test::random_point(rng, 1.0f);
    const float r = 1e-3f;
    const float angle = uniform(rng, 0.0f, 6.3f);
    const Vec2 origin = centre + 1000.0f * Vec2(std::cos(angle), std::sin(angle));
    const Vec2 aim = centre + test::random_point(rng, 0.5f * r);
    const RayHit h = raycast(make_circle(centre, r), Transform{}, Ray{origin, 2.0f * (aim - origin)});
    ASSERT_TRUE(h.hit) << i;
    EXPECT_NEAR(length(h.normal), 1.0f, 1e-6f) << i;
  }
}

TEST(Raycast, RoundedPolygonMatchesUnionOfBox2DPieces) {
  std::mt19937 rng(5);
  compare_with_oracle(random_polygons(rng, true), rng, 4.5f, {0.0f, 0.0f}, kNear);
  compare_with_oracle(random_polygons(rng, true), rng, 4.5f, kFarAway, kFar);
}

/// The first crossing of the ray with any edge segment, by brute force over all edges.
Truth edge_by_edge(const std::vector<Vec2>& world, const Ray& ray) {
  Truth best;
  for (size_t i = 0; i < world.size(); ++i) {
    const Vec2 a = world[i], b = world[(i + 1) % world.size()];
    const float den = cross(ray.translation, b - a);
    if (den == 0.0f) continue;
    const float t = cross(a - ray.origin, b - a) / den;
    const float s = cross(a - ray.origin, ray.translation) / den;
    if (t >= 0.0f && t <= 1.0f && s >= 0.0f && s <= 1.0f && (!best.hit || t < best.fraction)) {
      best = {true, t, normalize_or_zero(right_perp(b - a))};
    }
  }
  return best;
}

// Polygons beyond Box2D's 8 vertices, up to kMaxPolygonVertices (the side masks use all 64
// bits), against the first crossing over every edge.
TEST(Raycast, LargePolygonsMatchEdgeByEdge) {
  std::mt19937 rng(16);
  int hits = 0, misses = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = trial % 2 ? kMaxPolygonVertices : 9 + static_cast<int>(rng() % 55);
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) {
      const float a = 2.0f * test::kPi * (static_cast<float>(i) + uniform(rng, -0.2f, 0.2f)) / n;
      pts.push_back({2.0f * std::cos(a), 1.5f * std::sin(a)});
    }
    const Polygon poly = make_convex_polygon(pts);
    const Transform xf = test::random_transform(rng, 10.0f);
    const std::vector<Vec2> world = test::world_vertices(poly, xf);
    for (int k = 0; k < 20; ++k) {
      const Vec2 origin = xf.p + test::random_point(rng, 4.0f);
      const Ray ray{origin,
                    (xf.p + test::random_point(rng, 2.0f) - origin) * uniform(rng, 0.5f, 2.0f)};
      const test::BruteDistance start = test::brute_distance(world, origin);
      Truth truth = start.inside ? Truth{} : edge_by_edge(world, ray);
      const RayHit ours = raycast(poly, xf, ray);
      ASSERT_EQ(ours.hit, truth.hit) << "trial " << trial << " ray " << k;
      if (!truth.hit) {
        ++misses;
        continue;
      }
      ++hits;
      EXPECT_NEAR(ours.fraction, truth.fraction, 1e-5f);
      EXPECT_VEC2_NEAR(ours.normal, truth.normal, 1e-3f);
    }
  }
  EXPECT_GT(hits, 1200);
  EXPECT_GT(misses, 1200);
}

// Edge case 0: a ray with a NaN coordinate reports no hit rather than garbage.
TEST(Raycast, NonFiniteRayMisses) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Shape2D> shapes = {make_circle({0.0f, 0.0f}, 1.0f),
                                       make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f),
                                       make_box({1.0f, 1.0f}), make_box({1.0f, 1.0f}, 0.5f),
                                       make_segment({-1.0f, 0.0f}, {1.0f, 0.0f})};
  for (const Shape2D& s : shapes) {
    EXPECT_FALSE(raycast(s, Transform{}, Ray{{nan, 0.0f}, {6.0f, 0.0f}}).hit) << type_name(s);
    EXPECT_FALSE(raycast(s, Transform{}, Ray{{-3.0f, 0.0f}, {6.0f, nan}}).hit) << type_name(s);
  }
}

// Edge case 1: a ray that starts inside never enters, however it is aimed and however long.
TEST(Raycast, RayStartingInsideMisses) {
  std::mt19937 rng(6);
  const std::vector<Shape2D> shapes = {make_circle({0.5f, 0.0f}, 1.0f),
                                       make_capsule({-1.0f, 0.0f}, {1.0f, 0.5f}, 0.5f),
                                       make_box({1.0f, 0.5f}), make_box({1.0f, 0.5f}, 0.3f),
                                       test::random_polygon(rng, 7, 1.0f, 0.2f)};
  int tested = 0;
  for (const Shape2D& shape : shapes) {
    for (int k = 0; k < 300; ++k) {
      const Transform xf = test::random_transform(rng, k % 2 == 0 ? 10.0f : 1.0e4f);
      const Vec2 origin = transform_point(xf, test::random_point(rng, 1.5f));
      if (!(closest_point(shape, xf, origin).distance < -1e-3f)) continue;
      ++tested;
      const Ray ray{origin, test::random_point(rng, 10.0f)};
      EXPECT_FALSE(raycast(shape, xf, ray).hit) << type_name(shape);
    }
  }
  EXPECT_GT(tested, 400);
}

// Edge case 2: starting exactly on the surface, heading in or out, is not an entry.
TEST(Raycast, RayStartingOnSurfaceMisses) {
  const Transform id{};
  const Polygon box = make_box({1.0f, 1.0f});
  EXPECT_FALSE(raycast(box, id, Ray{{1.0f, 0.0f}, {-3.0f, 0.0f}}).hit);
  EXPECT_FALSE(raycast(box, id, Ray{{1.0f, 0.0f}, {3.0f, 0.0f}}).hit);
  const Circle circle = make_circle({0.0f, 0.0f}, 2.0f);
  EXPECT_FALSE(raycast(circle, id, Ray{{0.0f, 2.0f}, {0.0f, -1.0f}}).hit);
  const Capsule capsule = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f);
  EXPECT_FALSE(raycast(capsule, id, Ray{{0.0f, 0.5f}, {0.0f, -1.0f}}).hit);
  EXPECT_FALSE(raycast(capsule, id, Ray{{-1.5f, 0.0f}, {1.0f, 0.0f}}).hit);
  const Segment segment = make_segment({-1.0f, 0.0f}, {1.0f, 0.0f});
  EXPECT_FALSE(raycast(segment, id, Ray{{0.0f, 0.0f}, {0.0f, 1.0f}}).hit);
}

// Edge case 3: a zero-length ray never hits, even from outside touching distance.
TEST(Raycast, ZeroLengthRayMisses) {
  const std::vector<Shape2D> shapes = {make_circle({0.0f, 0.0f}, 1.0f),
                                       make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f),
                                       make_box({1.0f, 1.0f}), make_box({1.0f, 1.0f}, 0.5f),
                                       make_segment({-1.0f, 0.0f}, {1.0f, 0.0f})};
  for (const Shape2D& s : shapes) {
    EXPECT_FALSE(raycast(s, Transform{}, Ray{{3.0f, 0.0f}, {0.0f, 0.0f}}).hit) << type_name(s);
  }
}

// Edge case 4: rays parallel to an edge, on its line, touch the corner (touching counts);
// just outside they miss, just inside they enter through the side.
TEST(Raycast, RayParallelToEdgeOnBoundary) {
  const Polygon box = make_box({1.0f, 1.0f});
  const RayHit along = raycast(box, Transform{}, Ray{{-3.0f, 1.0f}, {6.0f, 0.0f}});
  ASSERT_TRUE(along.hit);
  EXPECT_NEAR(along.fraction, 1.0f / 3.0f, 1e-6f);
  EXPECT_VEC2_NEAR(along.point, Vec2(-1.0f, 1.0f), 1e-6f);
  EXPECT_VEC2_NEAR(along.normal, Vec2(-1.0f, 0.0f), 1e-6f);
  // Box2D agrees on the exact case.
  Oracle o = oracle_for(box);
  const Truth t = box2d_cast(o.pieces, Transform{}, Ray{{-3.0f, 1.0f}, {6.0f, 0.0f}});
  EXPECT_TRUE(t.hit);
  // Under rigid motions the exact line is lost to rounding; a margin decides.
  std::mt19937 rng(8);
  for (int k = 0; k < 100; ++k) {
    const Transform xf = test::random_transform(rng, k % 2 ? 1.0e4f : 20.0f);
    const float margin = k % 2 ? 1e-2f : 1e-4f;
    const Ray outside{transform_point(xf, {-3.0f, 1.0f + margin}), rotate(xf.q, {6.0f, 0.0f})};
    const Ray inside{transform_point(xf, {-3.0f, 1.0f - margin}), rotate(xf.q, {6.0f, 0.0f})};
    EXPECT_FALSE(raycast(box, xf, outside).hit);
    const RayHit h = raycast(box, xf, inside);
    ASSERT_TRUE(h.hit);
    EXPECT_VEC2_NEAR(h.normal, rotate(xf.q, {-1.0f, 0.0f}), 1e-4f);
    EXPECT_NEAR(h.fraction, 1.0f / 3.0f, k % 2 ? 1e-3f : 1e-5f);
  }
  // A rounded box: the ray tangent to the flat top touches the top-left corner disc.
  const Polygon rounded = make_box({1.0f, 1.0f}, 0.5f);
  const RayHit tangent = raycast(rounded, Transform{}, Ray{{-3.0f, 1.5f}, {6.0f, 0.0f}});
  ASSERT_TRUE(tangent.hit);
  EXPECT_NEAR(tangent.fraction, 1.0f / 3.0f, 1e-5f);
  EXPECT_VEC2_NEAR(tangent.normal, Vec2(0.0f, 1.0f), 1e-5f);
  // A capsule's flat side, grazed along its line, is touched at the end disc's top.
  const Capsule capsule = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f);
  const RayHit grazing = raycast(capsule, Transform{}, Ray{{-3.0f, 0.5f}, {6.0f, 0.0f}});
  ASSERT_TRUE(grazing.hit);
  EXPECT_NEAR(grazing.fraction, 1.0f / 3.0f, 1e-5f);
}

// Edge case 5: a ray along a segment's line hits the nearer end, normal back along the ray; one
// starting on the segment, or heading away, or too short, misses.
TEST(Raycast, RayCollinearWithSegment) {
  std::mt19937 rng(9);
  const Segment seg = make_segment({-1.0f, 0.0f}, {1.0f, 0.0f});
  // Near the origin only: at 1e4 the inputs cannot place a ray on the segment's line closer than
  // ~1e-3, outside the collinearity tolerance (kRelativeTolerance of the length).
  for (int k = 0; k < 50; ++k) {
    const Transform xf = k == 0 ? Transform{} : test::random_transform(rng, 10.0f);
    const float tol = 1e-5f;
    const RayHit from_left =
        raycast(seg, xf, Ray{transform_point(xf, {-3.0f, 0.0f}), rotate(xf.q, {4.0f, 0.0f})});
    ASSERT_TRUE(from_left.hit);
    EXPECT_NEAR(from_left.fraction, 0.5f, tol);
    EXPECT_VEC2_NEAR(from_left.point, transform_point(xf, {-1.0f, 0.0f}), 2.0f * tol);
    EXPECT_VEC2_NEAR(from_left.normal, rotate(xf.q, {-1.0f, 0.0f}), 1e-5f);
    const RayHit from_right =
        raycast(seg, xf, Ray{transform_point(xf, {2.0f, 0.0f}), rotate(xf.q, {-4.0f, 0.0f})});
    ASSERT_TRUE(from_right.hit);
    EXPECT_NEAR(from_right.fraction, 0.25f, tol);
    EXPECT_VEC2_NEAR(from_right.normal, rotate(xf.q, {1.0f, 0.0f}), 1e-5f);
    EXPECT_FALSE(
        raycast(seg, xf, Ray{transform_point(xf, {-3.0f, 0.0f}), rotate(xf.q, {-4.0f, 0.0f})}).hit);
    EXPECT_FALSE(
        raycast(seg, xf, Ray{transform_point(xf, {-3.0f, 0.0f}), rotate(xf.q, {1.0f, 0.0f})}).hit);
    EXPECT_FALSE(
        raycast(seg, xf, Ray{transform_point(xf, {0.5f, 0.0f}), rotate(xf.q, {4.0f, 0.0f})}).hit);
  }
}

// Edge case 6: a ray tangent to a circle touches it.
TEST(Raycast, TangentRayTouchesCircle) {
  const Circle c = make_circle({0.0f, 0.0f}, 1.0f);
  const RayHit h = raycast(c, Transform{}, Ray{{-2.0f, 1.0f}, {4.0f, 0.0f}});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, 0.5f, 1e-6f);
  EXPECT_VEC2_NEAR(h.normal, Vec2(0.0f, 1.0f), 1e-6f);
  EXPECT_FALSE(raycast(c, Transform{}, Ray{{-2.0f, 1.001f}, {4.0f, 0.0f}}).hit);
}

/// A laser bouncing between two parallel mirrors y = 0 and y = H, started at (0, H/2) at angle
/// theta: unfolded, it is a straight line, so bounce k lands at x = (H/2 + k H) cot(theta), on
/// the top mirror for even k. Run under random rigid motions of the whole scene.
template <class Mirror>
void bounce_between(const Mirror& bottom, const Mirror& top, float bottom_face, float top_face) {
  constexpr float kH = 2.0f;
  const float theta = 0.7f;
  std::mt19937 rng(10);
  for (int trial = 0; trial < 20; ++trial) {
    const Transform xf =
        trial == 0 ? Transform{} : test::random_transform(rng, trial % 2 ? 1.0e4f : 50.0f);
    const float tol = trial % 2 ? 2e-2f : 1e-3f;
    const Transform xb{transform_point(xf, {0.0f, bottom_face}), xf.q};
    const Transform xt{transform_point(xf, {0.0f, top_face}), xf.q};
    const float total = 40.0f;
    Ray ray{transform_point(xf, {0.0f, kH / 2}),
            rotate(xf.q, total * Vec2{std::cos(theta), std::sin(theta)})};
    float travelled = 0.0f;
    for (int k = 0; k < 8; ++k) {
      const bool top_next = k % 2 == 0;
      const RayHit h = raycast(top_next ? top : bottom, top_next ? xt : xb, ray);
      const RayHit other = raycast(top_next ? bottom : top, top_next ? xb : xt, ray);
      ASSERT_TRUE(h.hit) << "bounce " << k;
      // The mirror just left: the reflected ray starts on it, and rounding may put that start
      // a hair behind it, so it can be re-hit at fraction ~0. A laser loop skips it.
      if (other.hit) EXPECT_LE(other.fraction * length(ray.translation), tol) << "bounce " << k;
      const Vec2 expected{(kH / 2 + static_cast<float>(k) * kH) / std::tan(theta),
                          top_next ? kH : 0.0f};
      SCOPED_TRACE(k);
      EXPECT_VEC2_NEAR(h.point, transform_point(xf, expected), tol);
      EXPECT_VEC2_NEAR(h.normal, rotate(xf.q, {0.0f, top_next ? -1.0f : 1.0f}), 1e-4f);
      travelled += h.fraction * length(ray.translation);
      ray = reflect(ray, h);
    }
    // Unfolded path length to the 8th bounce: (H/2 + 7 H) / sin(theta).
    EXPECT_NEAR(travelled, (kH / 2 + 7 * kH) / std::sin(theta), 10.0f * tol);
    EXPECT_NEAR(length(ray.translation), total - travelled, 10.0f * tol);
  }
}

TEST(Raycast, LaserBetweenSegmentMirrors) {
  const Segment mirror = make_segment({-100.0f, 0.0f}, {100.0f, 0.0f});
  bounce_between(mirror, mirror, 0.0f, 2.0f);
}

TEST(Raycast, LaserBetweenBoxMirrors) {
  // Thick mirrors: boxes of half height 0.5 whose inner faces are y = 0 and y = 2.
  const Polygon mirror = make_box({100.0f, 0.5f});
  bounce_between(mirror, mirror, -0.5f, 2.5f);
}

#if defined(__SSE2__) || defined(_M_X64)
/// The rounded polygon ray casts (and the circle and capsule shape casts through them) clip an
/// outline four edges at a time (clip_ray_outline_lanes); the scalar Cyrus-Beck loop is what it
/// replaced. As for hulls (Raycast3.HullLaneClipIsTheScalarClip): the same miss, inside and
/// hit, the fraction to rounding, another edge only where the entry lies on both edges' lines.
TEST(Raycast, OutlineLaneClipIsTheScalarClip) {
  std::mt19937 rng(78);
  int hits = 0, inside = 0, other_edge = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const int n = 3 + trial % 14;
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) {
      const float a = 2.0f * test::kPi * (static_cast<float>(i) + uniform(rng, -0.3f, 0.3f)) / n;
      pts.push_back({2.0f * std::cos(a), 1.2f * std::sin(a)});
    }
    const Polygon poly = make_convex_polygon(pts);
    const float offset = trial % 2 ? 0.3f : 0.0f;
    for (int i = 0; i < 300; ++i) {
      Vec2 p = test::random_point(rng, 4.0f);
      Vec2 d = (test::random_point(rng, 1.0f) - p) * uniform(rng, 0.3f, 2.0f);
      if (i % 7 == 0) p = 0.2f * p;                                  // often inside
      if (i % 11 == 0) d = 2.0f * left_perp(poly.normals[i % poly.count]);  // along an edge
      if (i % 13 == 0) p = poly.vertices[i % poly.count];             // on the outline
      if (i % 17 == 0) p.y = std::numeric_limits<float>::quiet_NaN();  // no bound moves
      const detail::ClipResult lanes =
          detail::clip_ray_outline_lanes(poly.vertices.data(), poly.normals.data(), poly.count, p, d, offset);
      const detail::ClipResult scalar = detail::clip_ray(poly.count, [&](int k) {
        return detail::PlaneCrossing{offset - dot(poly.normals[k], p - poly.vertices[k]), dot(poly.normals[k], d)};
      });
      ASSERT_EQ(lanes.plane >= 0, scalar.plane >= 0) << "polygon " << trial << " ray " << i;
      ASSERT_EQ(lanes.inside, scalar.inside) << "polygon " << trial << " ray " << i;
      if (scalar.inside) ++inside;
      if (scalar.plane < 0) continue;
      ++hits;
      ASSERT_NEAR(lanes.fraction, scalar.fraction, 1e-6f * (1.0f + scalar.fraction)) << "polygon " << trial;
      if (lanes.plane != scalar.plane) {
        ++other_edge;
        const Vec2 x = p + lanes.fraction * d;
        for (const int k : {lanes.plane, scalar.plane}) {
          EXPECT_NEAR(dot(poly.normals[k], x - poly.vertices[k]), offset, 1e-4f) << "polygon " << trial;
        }
      }
    }
  }
  EXPECT_GT(hits, 5000);
  EXPECT_GT(inside, 1000);
  EXPECT_LT(other_edge, hits / 100);
}
#endif

/// raycast_fraction against raycast on the same shape, placement and ray: the same hit, the
/// same fraction bit for bit, fraction 0 on a miss; through the template and through Shape2D.
/// Returns whether it hit.
template <class S>
bool expect_fraction_is_raycasts(const S& shape, const Transform& xf, const Ray& ray) {
  const RayHit full = raycast(shape, xf, ray);
  for (const RayFraction f : {raycast_fraction(shape, xf, ray), raycast_fraction(Shape2D(shape), xf, ray)}) {
    EXPECT_TRUE(test::bitwise_equal(f, full)) << f.hit << " " << f.fraction << " against " << full.hit << " " << full.fraction;
    if (!f.hit) EXPECT_EQ(f.fraction, 0.0f);
  }
  return full.hit;
}

// Every 2D shape kind (polygons sharp and rounded, capsules, circles, segments hit only by
// crossing rays), near the origin and 1e4 away, rays from outside, inside and of zero length.
TEST(Raycast, FractionIsRaycastsBitForBit) {
  std::mt19937 rng(41);
  int hits = 0, casts = 0;
  const auto check_all = [&](const auto& shapes, Vec2 far) {
    for (const auto& shape : shapes) {
      for (int i = 0; i < 200; ++i) {
        const Transform xf = Transform::from(far + test::random_point(rng, 2.0f), uniform(rng, -3.2f, 3.2f));
        const Vec2 origin = xf.p + test::random_point(rng, 5.0f);
        const Vec2 target = xf.p + test::random_point(rng, 1.5f);
        const float scale = i % 50 == 0 ? 0.0f : uniform(rng, 0.3f, 2.0f);  // some of zero length
        hits += expect_fraction_is_raycasts(shape, xf, Ray{origin, scale * (target - origin)});
        ++casts;
      }
    }
  };
  for (const Vec2 far : {Vec2{0.0f}, kFarAway}) {
    check_all(random_circles(rng), far);
    check_all(random_capsules(rng), far);
    check_all(random_polygons(rng, false), far);
    check_all(random_polygons(rng, true), far);
    check_all(random_segments(rng), far);
  }
  EXPECT_GT(hits, casts / 5);
  EXPECT_LT(hits, casts * 4 / 5);
  // A segment hit: only a crossing ray meets it.
  EXPECT_TRUE(expect_fraction_is_raycasts(make_segment({-1.0f, 0.0f}, {1.0f, 0.0f}), Transform{},
                                          Ray{{0.25f, 2.0f}, {0.0f, -4.0f}}));
}

}  // namespace
}  // namespace collide
