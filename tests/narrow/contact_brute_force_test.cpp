// contact() for all 16 ordered pairs of shape types (capsules and rounded polygons included, which
// Box2D 2.4 lacks) against brute force on the world-space cores:
//  - touching iff the true depth (radii sum minus the signed core distance) is >= 0;
//  - the deepest point's depth equals the true depth;
//  - the normal is unit and realises that depth: the cores' separation along it plus the depth
//    is the radii sum (for apart cores: the normal runs along the closest points);
//  - each point's two surface points lie in their shapes, and every depth is within [0, true].

#include <collide/core/tolerance.hpp>
#include <collide/shape/shape2d.hpp>

#include "narrow/contact_oracle.hpp"

namespace collide {
namespace {

constexpr float kTol = 3e-4f;
/// The reference face prefers A unless B's axis separates more by kReferenceFaceTolerance of the
/// shapes' size (about 2 here): within that band the reported axis, and so the depth, may
/// exceed the minimum by that much. Never less than the minimum.
constexpr float kHysteresis = kReferenceFaceTolerance * 2.0f + kTol;

/// A random shape of the given type, size about 1, centred near its local origin.
Shape2D random_shape(std::mt19937& rng, ShapeType2D type) {
  switch (type) {
    case ShapeType2D::circle:
      return make_circle(test::random_point(rng, 0.2f), test::uniform(rng, 0.1f, 0.7f));
    case ShapeType2D::capsule: {
      const Vec2 half{test::uniform(rng, 0.2f, 0.8f), 0.0f};
      const Transform xf = test::random_transform(rng, 0.2f);  // any direction, off-centre
      return make_capsule(transform_point(xf, -half), transform_point(xf, half),
                          test::uniform(rng, 0.05f, 0.5f));
    }
    case ShapeType2D::polygon: {
      const float radius = rng() % 2 == 0 ? 0.0f : test::uniform(rng, 0.05f, 0.3f);
      return test::random_polygon(rng, 3 + static_cast<int>(rng() % 8),
                                  test::uniform(rng, 0.4f, 0.9f), radius);
    }
    case ShapeType2D::segment: {
      const Vec2 half{test::uniform(rng, 0.2f, 0.9f), 0.0f};
      const Transform xf = test::random_transform(rng, 0.2f);
      return make_segment(transform_point(xf, -half), transform_point(xf, half));
    }
  }
  return Circle{};
}

contact_test::WorldCore world_core(const Shape2D& s, const Transform& xf) {
  return std::visit([&](const auto& shape) { return contact_test::world_core(shape, xf); }, s);
}

struct Outcome {
  bool touching = false;
  bool ambiguous = false;
};

/// Checks one manifold against brute force; returns whether the pair touches.
Outcome check_brute_force(const Manifold& m, const contact_test::WorldCore& a,
                          const contact_test::WorldCore& b) {
  const float depth = contact_test::true_depth(a, b);
  if (std::fabs(depth) < 1e-3f) return {depth >= 0.0f, true};  // either answer is fair
  if (depth < 0.0f) {
    EXPECT_EQ(m.count, 0) << "apart by " << -depth << " but touching";
    return {false, false};
  }
  EXPECT_GT(m.count, 0) << "overlap " << depth << " missed";
  if (m.count == 0) return {true, false};
  EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f);
  EXPECT_GE(m.max_depth(), depth - kTol);
  EXPECT_LE(m.max_depth(), depth + kHysteresis);
  const float radius = a.radius + b.radius;
  const float along_normal = radius - contact_test::core_separation_along(m.normal, a, b);
  EXPECT_GE(along_normal, depth - kTol);
  EXPECT_LE(along_normal, depth + kHysteresis)
      << "normal (" << m.normal.x << ", " << m.normal.y << ") does not realise the depth";
  for (int i = 0; i < m.count; ++i) {
    const ManifoldPoint& p = m.points[i];
    EXPECT_GE(p.depth, 0.0f);
    EXPECT_LE(p.depth, depth + kHysteresis);
    const Vec2 on_a = p.point + 0.5f * p.depth * m.normal;
    const Vec2 on_b = p.point - 0.5f * p.depth * m.normal;
    EXPECT_LE(contact_test::point_core_distance(on_a, a), a.radius + kTol) << "point " << i;
    EXPECT_LE(contact_test::point_core_distance(on_b, b), b.radius + kTol) << "point " << i;
  }
  return {true, false};
}

/// Places B (rotated by `angle`) along the ray from A's origin in direction `u` so that the true
/// depth is about `target` (bisection; depth decreases as B moves out along the ray). If even
/// B at A's origin is shallower than `target`, B stays there.
template <class ShapeB>
Transform place_at_depth(const contact_test::WorldCore& a, const ShapeB& b, Vec2 origin, Vec2 u,
                         float angle, float target) {
  const auto placed = [&](float s) { return Transform::from(origin + s * u, angle); };
  float lo = 0.0f, hi = 10.0f;
  for (int k = 0; k < 40; ++k) {
    const float mid = 0.5f * (lo + hi);
    const float d = contact_test::true_depth(a, world_core(b, placed(mid)));
    (d > target ? lo : hi) = mid;
  }
  return placed(lo);
}

Vec2 random_direction(std::mt19937& rng) {
  const float heading = test::uniform(rng, -test::kPi, test::kPi);
  return {std::cos(heading), std::sin(heading)};
}

/// On failure: the inputs and the answer, to turn into a regression test.
void dump(const Manifold& m, const contact_test::WorldCore& a, const contact_test::WorldCore& b) {
  for (const contact_test::WorldCore* w : {&a, &b}) {
    std::printf("core:");
    for (Vec2 p : w->points) std::printf(" (%.9g, %.9g)", p.x, p.y);
    std::printf(" radius %.9g\n", w->radius);
  }
  std::printf("normal (%.9g, %.9g), %d points\n", m.normal.x, m.normal.y, m.count);
  for (int i = 0; i < m.count; ++i) {
    const ManifoldPoint& p = m.points[i];
    std::printf("  (%.9g, %.9g) depth %.9g id %d/%d %d/%d\n", p.point.x, p.point.y, p.depth,
                p.id.index_a, static_cast<int>(p.id.type_a), p.id.index_b,
                static_cast<int>(p.id.type_b));
  }
}

constexpr ShapeType2D kTypes[] = {ShapeType2D::circle, ShapeType2D::capsule, ShapeType2D::polygon,
                                  ShapeType2D::segment};

TEST(ContactBruteForce, EveryOrderedPairOfShapeTypes) {
  std::mt19937 rng(201);
  for (ShapeType2D ta : kTypes) {
    for (ShapeType2D tb : kTypes) {
      int touching = 0, apart = 0;
      const int trials = 1500;
      for (int t = 0; t < trials; ++t) {
        const Shape2D a = random_shape(rng, ta);
        const Shape2D b = random_shape(rng, tb);
        const Transform xa = test::random_transform(rng, 1.0f);
        const Transform xb = place_at_depth(world_core(a, xa), b, xa.p, random_direction(rng),
                                            test::uniform(rng, -test::kPi, test::kPi),
                                            test::uniform(rng, -0.4f, 0.6f));
        SCOPED_TRACE(::testing::Message() << type_name(a) << "-" << type_name(b) << " #" << t);
        const Manifold m = contact(a, xa, b, xb);
        const auto ca = world_core(a, xa), cb = world_core(b, xb);
        const Outcome o = check_brute_force(m, ca, cb);
        if (!o.ambiguous) (o.touching ? touching : apart)++;
        if (::testing::Test::HasFailure()) {  // one clear report, not thousands
          dump(m, ca, cb);
          return;
        }
      }
      EXPECT_GT(touching, trials * 3 / 10)
          << type_name(random_shape(rng, ta)) << "-" << type_name(random_shape(rng, tb));
      EXPECT_GT(apart, trials * 3 / 10);
    }
  }
}

/// Rounded shapes placed so that their surfaces nearly touch (true depth in [-0.02, 0.02]) while
/// their cores are apart: the case where the closest core features decide the contact.
TEST(ContactBruteForce, RoundedShapesNearlyTouching) {
  std::mt19937 rng(202);
  int touching = 0, apart = 0, vertex_vertex = 0;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    const Shape2D a = random_shape(rng, rng() % 2 ? ShapeType2D::capsule : ShapeType2D::polygon);
    Shape2D b = random_shape(rng, rng() % 2 ? ShapeType2D::capsule : ShapeType2D::polygon);
    if (auto* p = std::get_if<Polygon>(&b)) p->radius = test::uniform(rng, 0.05f, 0.3f);
    const Transform xa = test::random_transform(rng, 0.5f);
    const Transform xb = place_at_depth(world_core(a, xa), b, xa.p, random_direction(rng),
                                        test::uniform(rng, -test::kPi, test::kPi),
                                        test::uniform(rng, -0.02f, 0.02f));
    const auto ca = world_core(a, xa), cb = world_core(b, xb);
    if (contact_test::signed_core_distance(ca, cb) <= 0.0f)
      continue;  // cores overlap: not this test
    SCOPED_TRACE(::testing::Message() << type_name(a) << "-" << type_name(b) << " #" << t);
    const Manifold m = contact(a, xa, b, xb);
    const Outcome o = check_brute_force(m, ca, cb);
    if (o.ambiguous) {
      // Still exact in the ambiguous band when it reports contact.
      if (m.touching()) EXPECT_NEAR(m.max_depth(), contact_test::true_depth(ca, cb), kHysteresis);
      (m.touching() ? touching : apart)++;
    } else {
      (o.touching ? touching : apart)++;
    }
    if (m.count == 1 && m.points[0].id.type_a == FeatureType::vertex &&
        m.points[0].id.type_b == FeatureType::vertex) {
      ++vertex_vertex;
    }
    if (::testing::Test::HasFailure()) {
      dump(m, ca, cb);
      return;
    }
  }
  EXPECT_GT(touching, trials * 3 / 10);
  EXPECT_GT(apart, trials * 3 / 10);
  EXPECT_GT(vertex_vertex, trials / 20) << "corner-against-corner contacts not exercised";
}

/// A strictly convex polygon with exactly `n` vertices on an ellipse with semi-axes `rx`, `ry`
/// (angles jittered), rotated at random.
Polygon ellipse_polygon(std::mt19937& rng, int n, float rx, float ry, float radius = 0.0f) {
  std::vector<Vec2> pts;
  const Rot2 q = Rot2::from_angle(test::uniform(rng, -test::kPi, test::kPi));
  for (int i = 0; i < n; ++i) {
    const float angle = 2.0f * test::kPi *
                        (static_cast<float>(i) + test::uniform(rng, -0.3f, 0.3f)) /
                        static_cast<float>(n);
    pts.push_back(rotate(q, {rx * std::cos(angle), ry * std::sin(angle)}));
  }
  return make_convex_polygon(pts, radius);
}

TEST(ContactBruteForce, SixtyFourVertexPolygons) {
  std::mt19937 rng(203);
  int touching = 0, apart = 0, big = 0;
  const int trials = 300;
  for (int t = 0; t < trials; ++t) {
    const Polygon a =
        ellipse_polygon(rng, kMaxPolygonVertices, 1.0f, 0.6f, rng() % 2 ? 0.0f : 0.1f);
    const Polygon b = t % 2 == 0 ? ellipse_polygon(rng, kMaxPolygonVertices, 0.8f, 0.5f)
                                 : make_box({0.5f, 0.3f}, 0.0f);
    big += a.count == kMaxPolygonVertices ? 1 : 0;
    const Transform xa = test::random_transform(rng, 1.0f);
    const Transform xb =
        place_at_depth(contact_test::world_core(a, xa), b, xa.p, random_direction(rng),
                       test::uniform(rng, -test::kPi, test::kPi), test::uniform(rng, -0.5f, 0.6f));
    SCOPED_TRACE(t);
    const Manifold m = contact(a, xa, b, xb);
    const auto ca = contact_test::world_core(a, xa), cb = contact_test::world_core(b, xb);
    const Outcome o = check_brute_force(m, ca, cb);
    if (!o.ambiguous) (o.touching ? touching : apart)++;
    if (::testing::Test::HasFailure()) {
      dump(m, ca, cb);
      return;
    }
  }
  EXPECT_EQ(big, trials);
  EXPECT_GT(touching, trials * 3 / 10);
  EXPECT_GT(apart, trials * 3 / 10);
}

}  // namespace
}  // namespace collide
