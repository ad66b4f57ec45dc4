// overlap (src/narrow/overlap.cpp) for all 16 ordered pairs of 2D shapes, against brute force in
// double, Box2D 2.4's b2TestOverlap, GJK distance, and exact touching constructions.

#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include "support/gjk_oracle.hpp"
#include "support/test_util.hpp"

#include <array>
#include <string>

namespace collide {
namespace {

using test::kAllTypes2D;
using test::random_scene;
using test::Scene;
using test::uniform;

/// Cases closer than this to touching are not judged by the brute-force comparison (float
/// inputs vs a double truth): 1e-4 of a scene a few units across.
constexpr double kBand = 4e-4;

/// The brute-force answer in double: +1 overlap (touching included: overlap admits float
/// rounding), -1 apart, 0 too close to touching (but apart) to judge.
int truth(const Scene& s) {
  const test::WorldCore ca = test::world_core(s.a, s.xa);
  const test::WorldCore cb = test::world_core(s.b, s.xb);
  const double gap = test::brute_core_distance(ca.points, cb.points) - ca.radius - cb.radius;
  return gap <= 0.0 ? 1 : gap > kBand ? -1 : 0;
}

TEST(Overlap, EveryPairBothOrdersAgreesWithBruteForce) {
  std::mt19937 rng(424242);
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      const std::string pair = std::string(test::type_label(ta)) + "-" + test::type_label(tb);
      std::array<int, 2> outcomes{};
      const int trials = 500;
      for (int i = 0; i < trials; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const int t = truth(s);
        const bool ab = overlap(s.a, s.xa, s.b, s.xb);
        const bool ba = overlap(s.b, s.xb, s.a, s.xa);
        if (t != 0) {
          EXPECT_EQ(ab, t > 0) << pair << " trial " << i;
          ++outcomes[t > 0 ? 1 : 0];
        }
        EXPECT_EQ(ab, ba) << pair << " trial " << i << ": order changed the answer";
      }
      EXPECT_GT(outcomes[0], trials * 3 / 10) << pair << ": too few apart cases";
      EXPECT_GT(outcomes[1], trials * 3 / 10) << pair << ": too few overlapping cases";
    }
  }
}

TEST(Overlap, FarFromOriginAgreesWithBruteForce) {
  // Truth from the transforms as given (in double): at 1e4 they are rounded to ~1e-3.
  std::mt19937 rng(17);
  std::array<int, 2> outcomes{};
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 100; ++i) {
        Scene s = random_scene(rng, ta, tb);
        const Vec2 far = Vec2{1e4f, 1e4f} + test::random_point(rng, 100.0f);
        s.xa.p += far;
        s.xb.p += far;
        const int t = truth(s);
        if (t == 0) continue;
        ++outcomes[t > 0 ? 1 : 0];
        EXPECT_EQ(overlap(s.a, s.xa, s.b, s.xb), t > 0)
            << test::type_label(ta) << "-" << test::type_label(tb) << " trial " << i;
      }
    }
  }
  EXPECT_GT(outcomes[0], 1600 * 3 / 10);
  EXPECT_GT(outcomes[1], 1600 * 3 / 10);
}

TEST(Overlap, LargePolygonsAgreeWithBruteForce) {
  std::mt19937 rng(64);
  std::array<int, 2> outcomes{};
  for (int i = 0; i < 300; ++i) {
    Scene s{test::random_polygon(rng, 64, 0.5f, i % 3 == 0 ? 0.05f : 0.0f),
            i % 2 ? Shape2D{test::random_polygon(rng, 64, 0.5f)}
                  : test::random_shape(rng, kAllTypes2D[i % 4], 1.0f),
            test::random_transform(rng, 2.0f), {}};
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 1.0f), uniform(rng, -3.0f, 3.0f));
    const int t = truth(s);
    if (t == 0) continue;
    ++outcomes[t > 0 ? 1 : 0];
    EXPECT_EQ(overlap(s.a, s.xa, s.b, s.xb), t > 0) << "trial " << i;
  }
  EXPECT_GT(outcomes[0], 300 * 3 / 10);
  EXPECT_GT(outcomes[1], 300 * 3 / 10);
}

TEST(Overlap, PolygonPairsNearTouchingAgreeWithBruteForce) {
  // Polygon pairs of 3..10 vertices (up to 8 take the separating axis test in registers, then
  // GJK when it cannot decide; more take GJK), rounded or not, placed so that many are within
  // a fraction of their size of touching: both answers against the double-precision truth.
  std::mt19937 rng(1988);
  std::array<int, 2> outcomes{};
  const int trials = 4000;
  for (int i = 0; i < trials; ++i) {
    const int na = 3 + static_cast<int>(rng() % 8);
    const int nb = 3 + static_cast<int>(rng() % 8);
    const float ra = i % 3 == 0 ? uniform(rng, 0.02f, 0.2f) : 0.0f;
    const float rb = i % 4 == 0 ? uniform(rng, 0.02f, 0.2f) : 0.0f;
    Scene s{test::random_polygon(rng, na, 0.5f, ra), test::random_polygon(rng, nb, 0.5f, rb),
            test::random_transform(rng, 5.0f), {}};
    s.xb = Transform::from(s.xa.p + test::random_point(rng, 1.1f), uniform(rng, -3.0f, 3.0f));
    const int t = truth(s);
    if (t == 0) continue;
    ++outcomes[t > 0 ? 1 : 0];
    EXPECT_EQ(overlap(s.a, s.xa, s.b, s.xb), t > 0) << "trial " << i << ", " << na << "-" << nb;
    EXPECT_EQ(overlap(s.b, s.xb, s.a, s.xa), t > 0) << "trial " << i << ", " << nb << "-" << na;
  }
  EXPECT_GT(outcomes[0], trials * 3 / 10);
  EXPECT_GT(outcomes[1], trials * 3 / 10);
}

TEST(Overlap, AgreesWithBox2DTestOverlap) {
  std::mt19937 rng(2);
  std::array<int, 2> outcomes{};
  const int trials = 1000;
  for (int i = 0; i < trials; ++i) {
    const Polygon a = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 0.5f);
    const Polygon b = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 0.5f);
    const Circle c = make_circle({0.1f, -0.1f}, 0.3f);
    const Transform xa = test::random_transform(rng, 3.0f);
    const Transform xb =
        Transform::from(xa.p + test::random_point(rng, 1.0f), uniform(rng, -3.0f, 3.0f));
    b2PolygonShape pa;
    b2PolygonShape pb;
    std::array<b2Vec2, kMaxPolygonVertices> va;
    std::array<b2Vec2, kMaxPolygonVertices> vb;
    for (int k = 0; k < a.count; ++k) va[k].Set(a.vertices[k].x, a.vertices[k].y);
    for (int k = 0; k < b.count; ++k) vb[k].Set(b.vertices[k].x, b.vertices[k].y);
    pa.Set(va.data(), a.count);
    pb.Set(vb.data(), b.count);
    pa.m_radius = 0.0f;  // Box2D's default skin would make its polygons bigger than ours
    pb.m_radius = 0.0f;
    b2CircleShape pc;
    pc.m_p.Set(c.center.x, c.center.y);
    pc.m_radius = c.radius;
    b2Transform ta;
    b2Transform tb;
    ta.p.Set(xa.p.x, xa.p.y);
    ta.q.c = xa.q.c;
    ta.q.s = xa.q.s;
    tb.p.Set(xb.p.x, xb.p.y);
    tb.q.c = xb.q.c;
    tb.q.s = xb.q.s;
    // Judge only away from touching: Box2D decides at distance < 10 * FLT_EPSILON.
    const double gap = distance(a, xa, b, xb).distance;
    const double gap_c = distance(a, xa, c, xb).distance;
    if (gap > kBand || test::box2d_core_distance(a, xa, b, xb) == 0.0) {
      const bool peer = b2TestOverlap(&pa, 0, &pb, 0, ta, tb);
      EXPECT_EQ(overlap(a, xa, b, xb), peer) << "polygon-polygon trial " << i;
      ++outcomes[peer ? 1 : 0];
    }
    if (gap_c > kBand || gap_c == 0.0) {
      EXPECT_EQ(overlap(a, xa, c, xb), b2TestOverlap(&pa, 0, &pc, 0, ta, tb))
          << "polygon-circle trial " << i;
    }
  }
  EXPECT_GT(outcomes[0], trials * 3 / 10);
  EXPECT_GT(outcomes[1], trials * 3 / 10);
}

TEST(Overlap, MatchesGjkDistanceBeingZero) {
  std::mt19937 rng(6);
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 100; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const DistanceResult d = distance(s.a, s.xa, s.b, s.xb);
        const bool o = overlap(s.a, s.xa, s.b, s.xb);
        if (d.distance > kBand) EXPECT_FALSE(o);
        if (d.distance == 0.0f && truth(s) > 0) EXPECT_TRUE(o);
      }
    }
  }
}

/// Exactly touching constructions, in a local frame g (random rigid transform near the origin):
/// overlap is true when touching and false once moved apart by `gap`.
struct TouchCase {
  const char* name;
  Shape2D a;
  Shape2D b;
  Transform xb;  ///< B in the frame of A when touching
  Vec2 away;     ///< unit direction that separates B from A
};

std::vector<TouchCase> touch_cases() {
  const Polygon box = make_box({1.0f, 0.5f});
  const Polygon tri = make_polygon(std::vector<Vec2>{{0.0f, 0.0f}, {1.0f, -0.5f}, {1.0f, 0.5f}});
  const Circle circle = make_circle({0.0f, 0.0f}, 0.5f);
  const Circle small = make_circle({0.25f, 0.0f}, 0.25f);
  const Capsule capsule = make_capsule({-0.5f, 0.0f}, {0.5f, 0.0f}, 0.25f);
  const Segment seg = make_segment({-1.0f, 0.0f}, {1.0f, 0.0f});
  const Segment vertical = make_segment({0.0f, 0.0f}, {0.0f, 1.0f});
  const Polygon rounded = make_box({0.5f, 0.5f}, 0.25f);
  return {
      {"circle-circle", circle, small, Transform::from({0.5f, 0.0f}, 0.0f), {1, 0}},
      {"circle-capsule", circle, capsule, Transform::from({0.0f, 0.75f}, 0.0f), {0, 1}},
      {"capsule-capsule end to end", capsule, capsule, Transform::from({1.5f, 0.0f}, 0.0f), {1, 0}},
      {"capsule-segment side", capsule, seg, Transform::from({0.0f, -0.25f}, 0.0f), {0, -1}},
      {"segment-segment T", seg, vertical, Transform::from({0.25f, 0.0f}, 0.0f), {0, 1}},
      {"segment-segment shared end", seg, seg, Transform::from({2.0f, 0.0f}, 0.0f), {1, 0}},
      {"circle-segment", circle, seg, Transform::from({0.0f, 0.5f}, 0.0f), {0, 1}},
      {"box-box face", box, box, Transform::from({2.0f, 0.25f}, 0.0f), {1, 0}},
      {"box-box corner on face", box, tri, Transform::from({1.0f, 0.0f}, 0.0f), {1, 0}},
      {"box-circle face", box, circle, Transform::from({0.3f, 1.0f}, 0.0f), {0, 1}},
      {"box-capsule face", box, capsule, Transform::from({0.0f, -0.75f}, 0.0f), {0, -1}},
      {"box-segment edge on face", box, seg, Transform::from({0.5f, 0.5f}, 0.0f), {0, 1}},
      {"box-segment end on face", box, vertical, Transform::from({0.2f, 0.5f}, 0.0f), {0, 1}},
      {"rounded-box face", rounded, box, Transform::from({0.75f, 1.25f}, 0.0f), {0, 1}},
      {"rounded-circle corner", rounded, circle,
       Transform::from(Vec2{0.5f, 0.5f} + 0.75f * Vec2{0.6f, 0.8f}, 0.0f), {0.6f, 0.8f}},
      // Core corners 0.5 apart on the diagonal: the face axes separate the cores by only
      // 0.35, less than the radii; the rounded corners just touch.
      {"rounded-rounded corner", rounded, rounded,
       Transform::from(Vec2{1.0f, 1.0f} + 0.5f * Vec2{0.70710678f, 0.70710678f}, 0.0f),
       {0.70710678f, 0.70710678f}},
  };
}

TEST(Overlap, TouchingExactlyCountsAndAHairApartDoesNot) {
  std::mt19937 rng(9);
  for (const TouchCase& c : touch_cases()) {
    for (int i = 0; i < 40; ++i) {
      const Transform g = i == 0 ? Transform{} : test::random_transform(rng, 10.0f);
      const Transform xb = mul(g, c.xb);
      const Transform apart =
          mul(g, Transform{c.xb.p + 1e-3f * c.away, c.xb.q});
      const Transform into = mul(g, Transform{c.xb.p - 1e-3f * c.away, c.xb.q});
      EXPECT_TRUE(overlap(c.a, g, c.b, xb)) << c.name << " touching, frame " << i;
      EXPECT_TRUE(overlap(c.b, xb, c.a, g)) << c.name << " touching reversed, frame " << i;
      EXPECT_TRUE(overlap(c.a, g, c.b, into)) << c.name << " pushed in, frame " << i;
      EXPECT_FALSE(overlap(c.a, g, c.b, apart)) << c.name << " apart, frame " << i;
      EXPECT_FALSE(overlap(c.b, apart, c.a, g)) << c.name << " apart reversed, frame " << i;
    }
  }
}

TEST(Overlap, CrossingAndParallelSegments) {
  const Segment a = make_segment({-1.0f, -1.0f}, {1.0f, 1.0f});
  const Segment b = make_segment({-1.0f, 1.0f}, {1.0f, -1.0f});
  EXPECT_TRUE(overlap(a, Transform{}, b, Transform{}));  // an X
  EXPECT_TRUE(overlap(a, Transform::from({5.0f, 5.0f}, 0.3f), b,
                      Transform::from({5.0f, 5.0f}, 0.3f)));
  const Segment h = make_segment({0.0f, 0.0f}, {2.0f, 0.0f});
  EXPECT_FALSE(overlap(h, Transform{}, h, Transform::from({0.5f, 0.01f}, 0.0f)));  // parallel
  EXPECT_FALSE(overlap(h, Transform{}, h, Transform::from({2.01f, 0.0f}, 0.0f)));  // collinear
  EXPECT_TRUE(overlap(h, Transform{}, h, Transform::from({1.0f, 0.0f}, 0.0f)));    // collinear
}

TEST(Overlap, Shape2DOverloadMatchesTypedCall) {
  std::mt19937 rng(10);
  for (ShapeType2D ta : kAllTypes2D) {
    for (ShapeType2D tb : kAllTypes2D) {
      for (int i = 0; i < 20; ++i) {
        const Scene s = random_scene(rng, ta, tb);
        const bool typed = std::visit(
            [&](const auto& sa, const auto& sb) { return overlap(sa, s.xa, sb, s.xb); }, s.a, s.b);
        EXPECT_EQ(overlap(s.a, s.xa, s.b, s.xb), typed);
      }
    }
  }
}

}  // namespace
}  // namespace collide
