// Point queries checked against brute force: the minimum over every edge segment computed
// naively (polygons), a dense sampling of the core (capsules, segments), and the analytic
// circle; Voronoi features checked on points built inside each region.

#include <collide/narrow/closest_point.hpp>

#include "support/brute_convex.hpp"
#include "support/test_util.hpp"

namespace collide {
namespace {

using test::uniform;

/// Distance from p to the segment a-b by sampling it densely (independent of the projection).
float sampled_segment_distance(Vec2 a, Vec2 b, Vec2 p) {
  constexpr int kSamples = 4000;
  float best = distance(a, p);
  for (int i = 1; i <= kSamples; ++i) {
    best = std::min(best, distance(a + (static_cast<float>(i) / kSamples) * (b - a), p));
  }
  return best;
}

/// Checks shared by every shape: the closest point is |distance| from the query point and lies
/// on the surface (its own query gives distance ~0), the sign matches `inside`.
template <class S>
void expect_consistent(const S& shape, const Transform& xf, Vec2 p, const PointQuery& q,
                       float tol) {
  EXPECT_NEAR(distance(q.closest, p), std::fabs(q.distance), tol);
  EXPECT_NEAR(closest_point(shape, xf, q.closest).distance, 0.0f, tol);
  EXPECT_EQ(q.inside, q.distance < 0.0f);
  const PointQuery any = closest_point(Shape2D{shape}, xf, p);
  EXPECT_EQ(any.distance, q.distance);
  EXPECT_EQ(any.feature, q.feature);
}

TEST(ClosestPoint, PolygonMatchesMinOverEdges) {
  std::mt19937 rng(11);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    // Far out, the brute force sees the same float inputs shifted exactly back to the origin
    // (Sterbenz), so it is the truth for them; our answers are then compared shifted too.
    const bool far_out = trial % 3 == 0;
    const Vec2 far = far_out ? Vec2{1.0e4f, 1.0e4f} : Vec2{0.0f, 0.0f};
    const float radius = trial % 2 ? uniform(rng, 0.05f, 0.8f) : 0.0f;
    const float size = uniform(rng, 0.5f, 4.0f);
    const Polygon poly = test::random_polygon(rng, 3 + trial % 10, size, radius);
    const Transform xf{far + test::random_point(rng, 10.0f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const std::vector<Vec2> world = test::world_vertices(poly, Transform{xf.p - far, xf.q});
    const float tol = far_out ? 4e-3f : 2e-4f;
    for (int k = 0; k < 30; ++k) {
      const Vec2 p_far = transform_point(xf, test::random_point(rng, 1.2f * size));
      const PointQuery q_far = closest_point(poly, xf, p_far);
      PointQuery q = q_far;
      q.closest -= far;
      const Vec2 p = p_far - far;
      const test::BruteDistance b = test::brute_distance(world, p);
      const float core = b.inside ? -b.boundary : b.boundary;
      EXPECT_NEAR(q.distance, core - radius, tol);
      (q.inside ? inside : outside)++;
      expect_consistent(poly, xf, p_far, q_far, tol);
      // Outside the core the closest core point is unique: compare it, and the feature. Near a
      // region boundary the brute force's choice between a vertex and its edge is decided by
      // distances equal to second order, so skip points within `margin` of a boundary.
      if (!b.inside && b.boundary > tol) {
        const Vec2 core_closest = q.closest - radius * normalize_or_zero(p - b.closest);
        // The brute-force feature: the segment's end when the clamped projection sits on it.
        const int m = poly.count;
        const float margin = 10.0f * tol;
        if (b.s == 0.0f || b.s == 1.0f) {
          const int v = b.s == 0.0f ? b.edge : (b.edge + 1) % m;
          const Vec2 wv = world[v];
          const Vec2 e_prev = normalize_or_zero(wv - world[(v + m - 1) % m]);
          const Vec2 e_next = normalize_or_zero(world[(v + 1) % m] - wv);
          if (dot(p - wv, e_prev) > margin && dot(p - wv, e_next) < -margin) {
            EXPECT_EQ(q.feature, (Feature{FeatureType::vertex, std::uint32_t(v)}));
            EXPECT_VEC2_NEAR(core_closest, b.closest, tol);
          }
        } else {
          const float len = distance(world[b.edge], world[(b.edge + 1) % m]);
          if (b.s * len > margin && (1.0f - b.s) * len > margin) {
            EXPECT_EQ(q.feature, (Feature{FeatureType::edge, std::uint32_t(b.edge)}));
            EXPECT_VEC2_NEAR(core_closest, b.closest, tol);
          }
        }
      }
    }
  }
  EXPECT_GT(inside, 9000 * 3 / 10);
  EXPECT_GT(outside, 9000 * 3 / 10);
}

TEST(ClosestPoint, PolygonFeatureOfEachVoronoiRegion) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 200; ++trial) {
    const bool far = trial % 2 == 0;
    const Polygon poly = test::random_polygon(rng, 3 + trial % 12, 2.0f, trial % 3 ? 0.0f : 0.3f);
    const Transform xf = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const float tol = far ? 4e-3f : 1e-4f;
    for (int i = 0; i < poly.count; ++i) {
      const Vec2 v = poly.vertex(i), w = poly.vertex(i + 1);
      const Vec2 n_prev = poly.normals[(i + poly.count - 1) % poly.count];
      const Vec2 n = poly.normals[i];
      // Vertex i's region: the wedge spanned by the normals of its two edges.
      const float a = uniform(rng, 0.05f, 1.0f), b = uniform(rng, 0.05f, 1.0f);
      const Vec2 in_wedge = v + 2.0f * (a * n_prev + b * n);
      const PointQuery qv = closest_point(poly, xf, transform_point(xf, in_wedge));
      EXPECT_EQ(qv.feature, (Feature{FeatureType::vertex, std::uint32_t(i)}));
      EXPECT_VEC2_NEAR(qv.closest,
                       transform_point(xf, v + poly.radius * normalize_or_zero(in_wedge - v)), tol);
      // Edge i's region: the slab over the edge, outside it.
      const float s = uniform(rng, 0.05f, 0.95f), h = uniform(rng, 0.01f, 3.0f);
      const Vec2 in_slab = v + s * (w - v) + h * n;
      const PointQuery qe = closest_point(poly, xf, transform_point(xf, in_slab));
      EXPECT_EQ(qe.feature, (Feature{FeatureType::edge, std::uint32_t(i)}));
      EXPECT_NEAR(qe.distance, h - poly.radius, tol);
      // Just inside edge i, near its middle: edge i is the edge of least penetration when the
      // depth is below the distance to every other edge line.
      const Vec2 mid = 0.5f * (v + w);
      float room = INFINITY;
      for (int j = 0; j < poly.count; ++j) {
        if (j != i) room = std::min(room, -dot(poly.normals[j], mid - poly.vertices[j]));
      }
      const float depth = 0.4f * room;
      const PointQuery qi = closest_point(poly, xf, transform_point(xf, mid - depth * n));
      EXPECT_TRUE(qi.inside);
      EXPECT_EQ(qi.feature, (Feature{FeatureType::edge, std::uint32_t(i)}));
      EXPECT_NEAR(qi.distance, -depth - poly.radius, tol);
      EXPECT_VEC2_NEAR(qi.closest, transform_point(xf, mid + poly.radius * n), tol);
    }
  }
}

TEST(ClosestPoint, CircleAnalytic) {
  std::mt19937 rng(13);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const bool far = trial % 2 == 0;
    const Circle c = make_circle(test::random_point(rng, 1.0f), uniform(rng, 0.1f, 3.0f));
    const Transform xf = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const float tol = far ? 4e-3f : 1e-5f;
    const Vec2 center = transform_point(xf, c.center);
    const Vec2 p = center + test::random_point(rng, 1.4f * c.radius);
    const PointQuery q = closest_point(c, xf, p);
    const float d = distance(p, center);
    EXPECT_NEAR(q.distance, d - c.radius, tol);
    EXPECT_VEC2_NEAR(q.closest, center + c.radius * normalize_or_zero(p - center), tol);
    EXPECT_EQ(q.feature, (Feature{FeatureType::face, 0}));
    expect_consistent(c, xf, p, q, tol);
    (q.inside ? inside : outside)++;
  }
  EXPECT_GT(inside, 600);
  EXPECT_GT(outside, 600);
  // The centre itself: distance -radius, some surface point.
  const PointQuery at_center =
      closest_point(make_circle({1.0f, 2.0f}, 0.5f), Transform{}, {1.0f, 2.0f});
  EXPECT_FLOAT_EQ(at_center.distance, -0.5f);
  EXPECT_NEAR(distance(at_center.closest, Vec2(1.0f, 2.0f)), 0.5f, 1e-6f);
}

/// Capsule (radius r) and segment (r = 0) against dense sampling of the core, plus features by
/// construction: before a, past b, right and left of a -> b.
template <class S>
void check_segment_like(const S& shape, Vec2 a, Vec2 b, float r, std::mt19937& rng, int& inside,
                        int& outside) {
  const bool far = rng() % 2 == 0;
  const Transform xf = test::random_transform(rng, far ? 1.0e4f : 10.0f);
  const float length_ab = distance(a, b);
  // Sampling resolution bounds the brute force error: half a step, squared over the distance.
  const float tol = (far ? 4e-3f : 1e-5f) + length_ab / 4000.0f;
  for (int k = 0; k < 20; ++k) {
    const Vec2 local = 0.5f * (a + b) + test::random_point(rng, 0.5f * length_ab + r);
    const Vec2 p = transform_point(xf, local);
    const PointQuery q = closest_point(shape, xf, p);
    EXPECT_NEAR(q.distance, sampled_segment_distance(a, b, local) - r, tol);
    expect_consistent(shape, xf, p, q, tol);
    (q.inside ? inside : outside)++;
  }
  const Vec2 u = (b - a) / length_ab;
  const Vec2 right = right_perp(u);
  const float ftol = far ? 4e-3f : 1e-5f;
  const float h = uniform(rng, 0.01f, 2.0f);
  const Vec2 cases[4] = {a - h * u + uniform(rng, -1.0f, 1.0f) * h * right,
                         b + h * u + uniform(rng, -1.0f, 1.0f) * h * right,
                         a + uniform(rng, 0.05f, 0.95f) * (b - a) + h * right,
                         a + uniform(rng, 0.05f, 0.95f) * (b - a) - h * right};
  const Feature expected[4] = {{FeatureType::vertex, 0},
                               {FeatureType::vertex, 1},
                               {FeatureType::edge, 0},
                               {FeatureType::edge, 1}};
  for (int c = 0; c < 4; ++c) {
    const PointQuery q = closest_point(shape, xf, transform_point(xf, cases[c]));
    EXPECT_EQ(q.feature, expected[c]) << "case " << c;
    if (c >= 2) EXPECT_NEAR(q.distance, h - r, ftol);
  }
}

TEST(ClosestPoint, CapsuleMatchesSampledCore) {
  std::mt19937 rng(14);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Capsule c = make_capsule(test::random_point(rng, 2.0f), test::random_point(rng, 2.0f),
                                   uniform(rng, 0.2f, 1.5f));
    check_segment_like(c, c.a, c.b, c.radius, rng, inside, outside);
  }
  EXPECT_GT(inside, 4000 * 3 / 10);
  EXPECT_GT(outside, 4000 * 3 / 10);
}

TEST(ClosestPoint, SegmentMatchesSampledSegment) {
  std::mt19937 rng(15);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Segment s = make_segment(test::random_point(rng, 2.0f), test::random_point(rng, 2.0f));
    check_segment_like(s, s.a, s.b, 0.0f, rng, inside, outside);
  }
  EXPECT_EQ(inside, 0);  // a segment has no inside
  EXPECT_EQ(outside, 4000);
  // On the segment: distance 0, the point itself, edge 0 by convention.
  const PointQuery on =
      closest_point(make_segment({-1.0f, 0.0f}, {1.0f, 0.0f}), Transform{}, {0.25f, 0.0f});
  EXPECT_EQ(on.distance, 0.0f);
  EXPECT_VEC2_NEAR(on.closest, Vec2(0.25f, 0.0f), 0.0f);
  EXPECT_EQ(on.feature, (Feature{FeatureType::edge, 0}));
}

// Touching: a point exactly on a box's edge and corner has distance 0 and is not inside.
TEST(ClosestPoint, PointOnBoundary) {
  const Polygon box = make_box({1.0f, 2.0f});
  const PointQuery edge = closest_point(box, Transform{}, {1.0f, 0.5f});
  EXPECT_EQ(edge.distance, 0.0f);
  EXPECT_FALSE(edge.inside);
  EXPECT_EQ(edge.feature, (Feature{FeatureType::edge, 1}));
  const PointQuery corner = closest_point(box, Transform{}, {1.0f, 2.0f});
  EXPECT_EQ(corner.distance, 0.0f);
  EXPECT_VEC2_NEAR(corner.closest, Vec2(1.0f, 2.0f), 0.0f);
  const PointQuery rounded = closest_point(make_box({1.0f, 2.0f}, 0.5f), Transform{}, {1.5f, 2.0f});
  EXPECT_NEAR(rounded.distance, 0.0f, 1e-6f);
  EXPECT_EQ(rounded.feature, (Feature{FeatureType::edge, 1}));
}

}  // namespace
}  // namespace collide
