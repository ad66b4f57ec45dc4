// contact() properties and fixed scenarios: analytic answers (capsules, boxes), touching
// exactly, parallel faces, swapping A and B, rigid motions of the whole scene, far from the
// origin, and feature ids that stay put under tiny motions.

#include <algorithm>
#include <collide/core/tolerance.hpp>
#include <optional>

#include "narrow/contact_oracle.hpp"

namespace collide {
namespace {

constexpr float kTol = 1e-5f;

/// The point of `m` with id `id`, if any.
std::optional<ManifoldPoint> find_point(const Manifold& m, ContactId id) {
  for (int i = 0; i < m.count; ++i) {
    if (m.points[i].id == id) return m.points[i];
  }
  return std::nullopt;
}

/// `m` and `expected` have the same normal, and the same points (matched by id) within `tol`.
::testing::AssertionResult same_manifold(const Manifold& m, const Manifold& expected, float tol,
                                         float point_tol) {
  if (m.count != expected.count) {
    return ::testing::AssertionFailure() << "count " << m.count << " vs " << expected.count;
  }
  if (m.count == 0) return ::testing::AssertionSuccess();
  if (distance(m.normal, expected.normal) > tol) {
    return ::testing::AssertionFailure()
           << "normal (" << m.normal.x << ", " << m.normal.y << ") vs (" << expected.normal.x
           << ", " << expected.normal.y << ")";
  }
  for (int i = 0; i < expected.count; ++i) {
    const auto p = find_point(m, expected.points[i].id);
    if (!p) return ::testing::AssertionFailure() << "no point with id of expected point " << i;
    if (distance(p->point, expected.points[i].point) > point_tol ||
        std::fabs(p->depth - expected.points[i].depth) > tol) {
      return ::testing::AssertionFailure()
             << "point " << i << " (" << p->point.x << ", " << p->point.y << ") depth " << p->depth
             << " vs (" << expected.points[i].point.x << ", " << expected.points[i].point.y
             << ") depth " << expected.points[i].depth;
    }
  }
  return ::testing::AssertionSuccess();
}

Manifold transformed(Manifold m, const Transform& t) {
  m.normal = rotate(t.q, m.normal);
  for (int i = 0; i < m.count; ++i) m.points[i].point = transform_point(t, m.points[i].point);
  return m;
}

/// A random shape of any type, size about 1.
Shape2D random_shape(std::mt19937& rng) {
  switch (rng() % 4) {
    case 0:
      return make_circle(test::random_point(rng, 0.2f), test::uniform(rng, 0.1f, 0.7f));
    case 1:
      return make_capsule(test::random_point(rng, 0.8f), test::random_point(rng, 0.8f),
                          test::uniform(rng, 0.05f, 0.4f));
    case 2:
      return test::random_polygon(rng, 3 + static_cast<int>(rng() % 8), 0.8f,
                                  rng() % 2 ? 0.0f : 0.1f);
    default:
      return make_segment(test::random_point(rng, 0.8f), test::random_point(rng, 0.8f));
  }
}

contact_test::WorldCore world_core(const Shape2D& s, const Transform& xf) {
  return std::visit([&](const auto& shape) { return contact_test::world_core(shape, xf); }, s);
}

/// True when the answer may legitimately depend on rounding: near touching, or the two shapes'
/// best face axes nearly tied (the reference face is a choice then).
bool ambiguous(const Shape2D& a, const Transform& xa, const Shape2D& b, const Transform& xb) {
  const auto ca = world_core(a, xa), cb = world_core(b, xb);
  if (std::fabs(contact_test::true_depth(ca, cb)) < 1e-3f) return true;
  float sep_a = -1e30f, sep_b = -1e30f;
  for (Vec2 n : contact_test::core_axes(ca))
    sep_a = std::max(sep_a, contact_test::core_separation_along(n, ca, cb));
  for (Vec2 n : contact_test::core_axes(cb))
    sep_b = std::max(sep_b, contact_test::core_separation_along(n, cb, ca));
  return std::fabs(sep_a - sep_b) < 0.01f;
}

// ---- analytic scenarios ------------------------------------------------------------------

TEST(ContactAnalytic, BoxRestingOnBoxGivesTwoPointsOnTheFace) {
  // B (half 0.5) sinks 0.1 into the top face of A (half 1): bottom corners at x = -0.2, 0.8.
  const Polygon a = make_box({1.0f, 1.0f});
  const Polygon b = make_box({0.5f, 0.5f});
  const Manifold m = contact(a, Transform{}, b, Transform{{0.3f, 1.4f}, {}});
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.0f, 1.0f), kTol);
  std::array<float, 2> xs{m.points[0].point.x, m.points[1].point.x};
  std::sort(xs.begin(), xs.end());
  EXPECT_NEAR(xs[0], -0.2f, kTol);
  EXPECT_NEAR(xs[1], 0.8f, kTol);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(m.points[i].point.y, 0.95f, kTol);  // midway between y = 1 and y = 0.9
    EXPECT_NEAR(m.points[i].depth, 0.1f, kTol);
    EXPECT_EQ(m.points[i].id.type_a, FeatureType::edge);
    EXPECT_EQ(m.points[i].id.index_a, 2);  // A's top edge
    EXPECT_EQ(m.points[i].id.type_b, FeatureType::vertex);
  }
}

TEST(ContactAnalytic, WideBoxOnNarrowBoxIsClippedToTheReferenceFace) {
  // B (half 2 x 0.5) sinks 0.2 into A (half 1): B's bottom edge is cut at A's top corners.
  const Manifold m = contact(make_box({1.0f, 1.0f}), Transform{}, make_box({2.0f, 0.5f}),
                             Transform{{0.5f, 1.3f}, {}});
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.0f, 1.0f), kTol);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(std::fabs(m.points[i].point.x), 1.0f, kTol);
    EXPECT_NEAR(m.points[i].point.y, 0.9f, kTol);
    EXPECT_NEAR(m.points[i].depth, 0.2f, kTol);
  }
}

TEST(ContactAnalytic, Capsules) {
  const Transform id{};
  // Crossing at right angles through each other's middle: cores overlap by 1 on every axis.
  const Capsule h = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.25f);
  const Capsule v = make_capsule({0.0f, -1.0f}, {0.0f, 1.0f}, 0.25f);
  Manifold m = contact(h, id, v, id);
  ASSERT_GT(m.count, 0);
  EXPECT_NEAR(m.max_depth(), 1.5f, kTol);
  // End to end on one line: corner against corner, one point.
  const Capsule left = make_capsule({-1.0f, 0.0f}, {0.0f, 0.0f}, 0.5f);
  const Capsule right = make_capsule({0.8f, 0.0f}, {2.0f, 0.0f}, 0.5f);
  m = contact(left, id, right, id);
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC2_NEAR(m.normal, Vec2(1.0f, 0.0f), kTol);
  EXPECT_NEAR(m.points[0].depth, 0.2f, kTol);
  EXPECT_VEC2_NEAR(m.points[0].point, Vec2(0.4f, 0.0f), kTol);  // between x = 0.5 and 0.3
  EXPECT_EQ(m.points[0].id, (ContactId{1, 0, FeatureType::vertex, FeatureType::vertex}));
  // Side by side, overlapping on x in [0, 1]: two points.
  const Capsule above = make_capsule({0.0f, 0.9f}, {2.0f, 0.9f}, 0.5f);
  const Capsule below = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.5f);
  m = contact(below, id, above, id);
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.0f, 1.0f), kTol);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(m.points[i].depth, 0.1f, kTol);
    EXPECT_NEAR(m.points[i].point.y, 0.45f, kTol);
  }
  EXPECT_NEAR(std::min(m.points[0].point.x, m.points[1].point.x), 0.0f, kTol);
  EXPECT_NEAR(std::max(m.points[0].point.x, m.points[1].point.x), 1.0f, kTol);
  // Capsule against a circle beside its middle, and beyond its end.
  m = contact(below, id, make_circle({0.3f, -0.9f}, 0.5f), id);
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.0f, -1.0f), kTol);
  EXPECT_NEAR(m.points[0].depth, 0.1f, kTol);
  m = contact(below, id, make_circle({1.6f, 0.8f}, 0.5f), id);  // 1 from end (1, 0)
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.6f, 0.8f), kTol);
  EXPECT_NEAR(m.points[0].depth, 0.0f, kTol);
  // A capsule lying on a box: two points, depth 0.05.
  m = contact(make_box({1.0f, 1.0f}), id, make_capsule({-0.5f, 1.2f}, {0.5f, 1.2f}, 0.25f), id);
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.0f, 1.0f), kTol);
  EXPECT_NEAR(m.points[0].depth, 0.05f, kTol);
  EXPECT_NEAR(m.points[1].depth, 0.05f, kTol);
}

TEST(ContactAnalytic, TouchingExactlyReportsDepthZero) {
  const Transform id{};
  const Polygon box = make_box({1.0f, 1.0f});
  // Box on box, faces touching.
  Manifold m = contact(box, id, make_box({0.5f, 0.5f}), Transform{{0.25f, 1.5f}, {}});
  EXPECT_EQ(m.count, 2);
  for (int i = 0; i < m.count; ++i) EXPECT_EQ(m.points[i].depth, 0.0f);
  // Circles.
  m = contact(make_circle({0.0f, 0.0f}, 0.5f), id, make_circle({0.75f, 0.0f}, 0.25f), id);
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].depth, 0.0f);
  EXPECT_VEC2_NEAR(m.points[0].point, Vec2(0.5f, 0.0f), kTol);
  // Circle on a box face and on a box corner (3-4-5 triangle: distance exactly 0.5).
  m = contact(box, id, make_circle({0.0f, 1.5f}, 0.5f), id);
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].depth, 0.0f);
  m = contact(box, id, make_circle({1.3f, 1.4f}, 0.5f), id);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].depth, 0.0f, kTol);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.6f, 0.8f), kTol);
  // Segment lying on a box, and a rounded box touching a segment.
  m = contact(make_segment({-0.5f, 1.0f}, {0.5f, 1.0f}), id, box, id);
  EXPECT_EQ(m.count, 2);
  for (int i = 0; i < m.count; ++i) EXPECT_EQ(m.points[i].depth, 0.0f);
  m = contact(make_box({1.0f, 1.0f}, 0.5f), id, make_segment({-3.0f, 1.5f}, {3.0f, 1.5f}), id);
  EXPECT_EQ(m.count, 2);
  for (int i = 0; i < m.count; ++i) EXPECT_EQ(m.points[i].depth, 0.0f);
  // Rounded corners meeting on the diagonal: one point, depth 0 (corners (1, 1) and
  // (1.75, 2) are 1.25 = 0.625 + 0.625 apart, exactly in float).
  m = contact(make_box({1.0f, 1.0f}, 0.625f), id, make_box({1.0f, 1.0f}, 0.625f),
              Transform{{2.75f, 3.0f}, {}});
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].depth, 0.0f);
  EXPECT_VEC2_NEAR(m.normal, Vec2(0.6f, 0.8f), kTol);
  // Collinear segments end to end.
  m = contact(make_segment({-1.0f, 0.0f}, {0.0f, 0.0f}), id,
              make_segment({0.0f, 0.0f}, {1.0f, 0.0f}), id);
  ASSERT_EQ(m.count, 1);
  EXPECT_EQ(m.points[0].depth, 0.0f);
}

TEST(ContactAnalytic, SeparatedGivesNothing) {
  const Transform id{};
  const Polygon box = make_box({1.0f, 1.0f});
  EXPECT_EQ(contact(box, id, box, Transform{{2.001f, 0.0f}, {}}).count, 0);
  EXPECT_EQ(contact(box, id, make_circle({1.5f, 1.5f}, 0.7f), id).count, 0);  // corner region
  EXPECT_EQ(contact(make_capsule({-1, 0}, {1, 0}, 0.5f), id,
                    make_capsule({1.8f, 0.6f}, {3.0f, 0.6f}, 0.4f), id)
                .count,
            0);
  EXPECT_EQ(
      contact(make_segment({-1, 0}, {1, 0}), id, make_segment({1.01f, -1}, {1.01f, 1}), id).count,
      0);
  // Collinear segments and capsules with a gap (only the segments' direction separates them).
  EXPECT_EQ(contact(make_segment({-1, 0}, {0, 0}), id, make_segment({0.1f, 0}, {1, 0}), id).count,
            0);
  EXPECT_EQ(
      contact(make_capsule({-1, 0}, {0, 0}, 0.2f), id, make_capsule({0.5f, 0}, {1, 0}, 0.2f), id)
          .count,
      0);
  // Rounded corners just apart on the diagonal (face axes alone would say they overlap).
  EXPECT_EQ(contact(make_box({1.0f, 1.0f}, 0.25f), id, make_box({1.0f, 1.0f}, 0.25f),
                    Transform{{2.31f, 2.41f}, {}})
                .count,
            0);
}

// ---- properties on random pairs ------------------------------------------------------------

TEST(ContactProperties, SwappingShapesGivesTheReversedManifold) {
  std::mt19937 rng(301);
  int touching = 0, apart = 0, skipped = 0;
  const int trials = 4000;
  for (int t = 0; t < trials; ++t) {
    const Shape2D a = random_shape(rng), b = random_shape(rng);
    const Transform xa = test::random_transform(rng, 0.7f), xb = test::random_transform(rng, 0.7f);
    if (ambiguous(a, xa, b, xb)) {
      ++skipped;
      continue;
    }
    SCOPED_TRACE(::testing::Message() << type_name(a) << "-" << type_name(b) << " #" << t);
    const Manifold ab = contact(a, xa, b, xb);
    EXPECT_TRUE(same_manifold(contact(b, xb, a, xa), reversed(ab), 1e-4f, 1e-4f));
    (ab.touching() ? touching : apart)++;
  }
  EXPECT_GT(touching, trials * 3 / 10);
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_LT(skipped, trials / 4);
}

TEST(ContactProperties, RigidMotionOfTheSceneMovesTheManifold) {
  std::mt19937 rng(302);
  int touching = 0, apart = 0;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    const Shape2D a = random_shape(rng), b = random_shape(rng);
    const Transform xa = test::random_transform(rng, 0.7f), xb = test::random_transform(rng, 0.7f);
    if (ambiguous(a, xa, b, xb)) continue;
    const Transform motion = test::random_transform(rng, 50.0f);
    SCOPED_TRACE(::testing::Message() << type_name(a) << "-" << type_name(b) << " #" << t);
    const Manifold m = contact(a, xa, b, xb);
    const Manifold moved = contact(a, mul(motion, xa), b, mul(motion, xb));
    EXPECT_TRUE(same_manifold(moved, transformed(m, motion), 1e-4f, 1e-4f * 50.0f));
    (m.touching() ? touching : apart)++;
  }
  EXPECT_GT(touching, trials * 3 / 10);
  EXPECT_GT(apart, trials * 3 / 10);
}

/// Far from the origin, float world coordinates have steps of about 1e-3; contact must still
/// be exact in depth and normal. Positions are kept to multiples of 2^-10 so that moving the
/// scene by (1e4, -1e4) is exact and the expected answer is the near one, shifted.
TEST(ContactProperties, TenThousandUnitsFromTheOrigin) {
  std::mt19937 rng(303);
  int touching = 0;
  const int trials = 2000;
  const auto quantized = [&](float extent) {
    Transform xf = test::random_transform(rng, extent);
    xf.p = glm::round(xf.p * 1024.0f) / 1024.0f;
    return xf;
  };
  const Transform shift{{1e4f, -1e4f}, {}};
  for (int t = 0; t < trials; ++t) {
    const Shape2D a = random_shape(rng), b = random_shape(rng);
    const Transform xa = quantized(0.7f), xb = quantized(0.7f);
    if (ambiguous(a, xa, b, xb)) continue;
    SCOPED_TRACE(::testing::Message() << type_name(a) << "-" << type_name(b) << " #" << t);
    const Manifold near = contact(a, xa, b, xb);
    const Manifold far = contact(a, mul(shift, xa), b, mul(shift, xb));
    // Depth and normal as precise as near the origin; points to the float step at 1e4.
    EXPECT_TRUE(same_manifold(far, transformed(near, shift), 1e-5f, 2e-3f));
    touching += near.touching() ? 1 : 0;
  }
  EXPECT_GT(touching, trials * 3 / 10);
}

TEST(ContactProperties, FeatureIdsStayPutUnderTinyMotion) {
  struct Scene {
    const char* name;
    Shape2D a, b;
    Transform xb;
    int count;
  };
  const Scene scenes[] = {
      {"box on box", make_box({1.0f, 1.0f}), make_box({0.5f, 0.5f}), {{0.3f, 1.45f}, {}}, 2},
      {"wide box on box", make_box({1.0f, 1.0f}), make_box({2.0f, 0.5f}), {{0.2f, 1.45f}, {}}, 2},
      {"box corner in box", make_box({1.0f, 1.0f}), make_box({0.5f, 0.5f}),
       Transform::from({0.1f, 1.65f}, 0.7f), 1},
      {"capsule on box",
       make_box({1.0f, 1.0f}),
       make_capsule({-0.5f, 0.0f}, {0.5f, 0.0f}, 0.2f),
       {{0.1f, 1.15f}, {}},
       2},
      {"rounded corners",
       make_box({1.0f, 1.0f}, 0.25f),
       make_box({1.0f, 1.0f}, 0.25f),
       {{2.25f, 2.3f}, {}},
       1},
      {"circle on polygon corner",
       make_box({1.0f, 1.0f}),
       make_circle({0.0f, 0.0f}, 0.5f),
       {{1.3f, 1.3f}, {}},
       1},
      {"segment across capsule", make_segment({-2.0f, 0.0f}, {2.0f, 0.0f}),
       make_capsule({0.0f, 0.0f}, {0.0f, 1.0f}, 0.3f), Transform::from({0.1f, 0.2f}, 0.1f), 1},
  };
  std::mt19937 rng(304);
  for (const Scene& s : scenes) {
    SCOPED_TRACE(s.name);
    const Manifold base = contact(s.a, Transform{}, s.b, s.xb);
    ASSERT_EQ(base.count, s.count);
    for (int k = 0; k < 200; ++k) {
      const Transform nudge =
          Transform::from(test::random_point(rng, 1e-3f), test::uniform(rng, -1e-3f, 1e-3f));
      const Manifold m = contact(s.a, Transform{}, s.b, mul(nudge, s.xb));
      ASSERT_EQ(m.count, base.count);
      for (int i = 0; i < base.count; ++i) {
        EXPECT_TRUE(find_point(m, base.points[i].id).has_value()) << "id of point " << i;
      }
    }
  }
}

}  // namespace
}  // namespace collide
