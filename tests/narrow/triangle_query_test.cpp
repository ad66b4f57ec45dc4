// Every convex shape against a single Triangle: overlap, distance, contact, closest_point and
// shape_cast, checked against the analytic sphere-triangle answer (closest point of the
// triangle, independent of GJK and SAT), against each other, and by the depth property.

#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include "support/brute_triangle.hpp"
#include "support/hull_pairs.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <variant>
#include <vector>

namespace collide {
namespace {

Triangle random_triangle(std::mt19937& rng, float size) {
  for (;;) {
    const Vec3 a = test::random_point3(rng, size);
    const Vec3 b = test::random_point3(rng, size);
    const Vec3 c = test::random_point3(rng, size);
    try {
      return make_triangle(a, b, c);
    } catch (const InvalidInput&) {
    }
  }
}

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

TEST(TriangleQuery, SphereAgainstAnalyticClosestPoint) {
  std::mt19937 rng(11);
  int touching = 0, apart = 0;
  for (int iter = 0; iter < 2000; ++iter) {
    const Triangle tri = random_triangle(rng, 2.0f);
    const Sphere s = make_sphere(Vec3(0.0f), test::uniform(rng, 0.1f, 1.0f));
    const Transform3 xs{test::random_point3(rng, 1.5f), Quat{1, 0, 0, 0}};
    const Transform3 xt = test::random_transform3(rng, 1.0f);
    const Triangle world{{transform_point(xt, tri.vertices[0]), transform_point(xt, tri.vertices[1]),
                          transform_point(xt, tri.vertices[2])}};
    const glm::dvec3 q = test::brute_closest_on_triangle(glm::dvec3(xs.p), glm::dvec3(world.vertices[0]),
                                                         glm::dvec3(world.vertices[1]),
                                                         glm::dvec3(world.vertices[2]));
    const double gap = glm::length(q - glm::dvec3(xs.p)) - s.radius;
    const DistanceResult3 d = distance(s, xs, tri, xt);
    EXPECT_NEAR(d.distance, std::max(gap, 0.0), 1e-4) << iter;
    if (std::fabs(gap) < 1e-4) continue;  // the rounding band: either answer
    EXPECT_EQ(overlap(s, xs, tri, xt), gap < 0.0) << iter;
    const Manifold3 m = contact(s, xs, tri, xt);
    EXPECT_EQ(m.touching(), gap < 0.0) << iter;
    if (gap < 0.0) {
      ++touching;
      ASSERT_EQ(m.count, 1);
      EXPECT_NEAR(m.points[0].depth, -gap, 1e-4) << iter;
      // Normal from the sphere's centre towards the triangle's closest point (unless the centre
      // is on the triangle).
      if (glm::length(q - glm::dvec3(xs.p)) > 1e-3) {
        const Vec3 n = Vec3(glm::normalize(q - glm::dvec3(xs.p)));
        EXPECT_GT(dot(n, m.normal), 0.9999f) << iter;
      }
    } else {
      ++apart;
    }
  }
  EXPECT_GT(touching, 200);
  EXPECT_GT(apart, 200);
}

// Property: moving A back along the reported normal by depth + eps separates it from the
// triangle; by depth - eps it still overlaps. Every convex shape type.
TEST(TriangleQuery, DepthPropertyEveryShape) {
  std::mt19937 rng(12);
  int checked = 0;
  int short_depth = 0;
  int per_type[6] = {};
  for (int iter = 0; iter < 4000; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 1.0f);
    const Triangle tri = random_triangle(rng, 2.0f);
    const Transform3 xa = test::random_transform3(rng, 2.0f);
    const Transform3 xt = test::random_transform3(rng, 0.5f);
    const Manifold3 m = std::visit([&](const auto& a) { return contact(a, xa, tri, xt); }, shape);
    for (int i = 0; i < m.count; ++i) ASSERT_TRUE(finite(m.points[i].point) && std::isfinite(m.points[i].depth));
    if (!m.touching()) {
      const bool o = std::visit([&](const auto& a) { return overlap(a, xa, tri, xt); }, shape);
      const float dist = std::visit([&](const auto& a) { return distance(a, xa, tri, xt).distance; }, shape);
      if (o) EXPECT_LT(dist, 1e-3f) << iter;  // overlap only within rounding of touching
      continue;
    }
    const float depth = m.max_depth();
    if (depth < 1e-3f) continue;
    const float eps = 2e-3f;
    Transform3 out = xa;
    out.p -= (depth + eps) * m.normal;
    Transform3 in = xa;
    in.p -= std::max(depth - eps, 0.0f) * m.normal;
    const bool o_out = std::visit([&](const auto& a) { return overlap(a, out, tri, xt); }, shape);
    const bool o_in = std::visit([&](const auto& a) { return overlap(a, in, tri, xt); }, shape);
    // The clipped points' depth can fall short of the axis' penetration when the incident
    // triangle's deepest corner lies beyond the reference face's side planes (the clip keeps
    // the part over the face): counted, and held to a small share below.
    if (o_out) ++short_depth;
    EXPECT_TRUE(o_in) << iter << " type " << shape.index() << " depth " << depth;
    ++checked;
    ++per_type[std::min<std::size_t>(shape.index(), 5)];
  }
  EXPECT_GT(checked, 300);
  EXPECT_LE(short_depth * 100, checked) << short_depth << " of " << checked;
  for (int t = 0; t < 5; ++t) {
    if (t == 2) continue;  // segments rarely pierce deeper than the threshold
    EXPECT_GT(per_type[t], 10) << t;
  }
}

// A box or a hull against a triangle takes the separating axis test with the triangle's edges
// pruned on the Gauss map (each edge a half circle): a pruned-away axis that mattered would
// leave contact with a worse axis, deeper than the minimum translation. EPA (another route
// to the same minimum) is the check: contact's depth is EPA's to within the SAT's preference
// for a face axis (kEdgeContactTolerance, kReferenceFaceTolerance) and its normal's rounding.
TEST(TriangleQuery, SolidOnTriangleContactDepthIsTheMinimumTranslation) {
  std::mt19937 rng(27);
  int checked = 0, edge_axes = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    const bool box = iter % 2 == 0;
    const Shape3D shape = box ? Shape3D(make_box({test::uniform(rng, 0.1f, 1.0f), test::uniform(rng, 0.1f, 1.0f),
                                                  test::uniform(rng, 0.1f, 1.0f)}))
                              : test::random_shape3(rng, 1.0f);
    if (!box && !std::holds_alternative<ConvexHull>(shape)) continue;
    if (!box && std::get<ConvexHull>(shape).radius > 0.0f) continue;
    const Triangle tri = random_triangle(rng, 1.5f);
    const Transform3 xa = test::random_transform3(rng, 1.0f);
    const Transform3 xt = test::random_transform3(rng, 0.3f);
    const Manifold3 m = std::visit([&](const auto& a) { return contact(a, xa, tri, xt); }, shape);
    const PenetrationResult3 e = std::visit([&](const auto& a) { return penetration(a, xa, tri, xt); }, shape);
    if (!m.touching() || e.status != QueryStatus::overlapped || e.depth < 1e-3f) continue;
    ++checked;
    const float tol = (kEdgeContactTolerance + kReferenceFaceTolerance) * 2.0f + 1e-4f;
    EXPECT_NEAR(m.max_depth(), e.depth, tol) << iter << (box ? " box" : " hull");
    if (std::fabs(dot(m.normal, e.normal)) < 0.999f) ++edge_axes;
  }
  EXPECT_GT(checked, 600);
  std::printf("[ rates    ] %d overlapping solid-triangle pairs, %d with normals apart from EPA's\n", checked, edge_axes);
}

// overlap, distance and contact agree for every shape type against a triangle.
TEST(TriangleQuery, OverlapDistanceContactAgree) {
  std::mt19937 rng(13);
  int hits = 0, misses = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 1.0f);
    const Triangle tri = random_triangle(rng, 2.0f);
    const Transform3 xa = test::random_transform3(rng, 2.5f);
    const Transform3 xt = test::random_transform3(rng, 0.5f);
    const DistanceResult3 d = std::visit([&](const auto& a) { return distance(a, xa, tri, xt); }, shape);
    ASSERT_TRUE(std::isfinite(d.distance) && finite(d.point_a) && finite(d.point_b));
    const bool o = std::visit([&](const auto& a) { return overlap(a, xa, tri, xt); }, shape);
    const Manifold3 m = std::visit([&](const auto& a) { return contact(a, xa, tri, xt); }, shape);
    if (d.distance > 1e-3f) {
      EXPECT_FALSE(o) << iter;
      EXPECT_FALSE(m.touching()) << iter;
      ++misses;
      // Speculative contact within a margin larger than the gap.
      const Manifold3 s =
          std::visit([&](const auto& a) { return contact(a, xa, tri, xt, d.distance + 1e-2f); }, shape);
      EXPECT_TRUE(s.touching()) << iter;
      float deepest = -1e30f;
      for (int i = 0; i < s.count; ++i) deepest = std::max(deepest, s.points[i].depth);
      // A face contact measures the gap along the face normal (within kFaceContactSine of the
      // closest points' direction), so its deepest point may lie a little farther.
      if (s.touching()) EXPECT_NEAR(deepest, -d.distance, 2e-3f + 0.05f * d.distance) << iter;
    } else if (d.distance == 0.0f) {
      // Distance 0: overlapping (or touching through the radii).
      EXPECT_TRUE(o) << iter;
      EXPECT_TRUE(m.touching()) << iter;
      ++hits;
    }
  }
  EXPECT_GT(hits, 200);
  EXPECT_GT(misses, 500);
}

// Distance of segment [p, q] to the triangle in double, independent of the library: the
// distance of a point on the segment to the triangle is convex along it, so a golden-section
// search over the fraction finds its minimum (to about 1e-12 of the segment).
double brute_segment_triangle_distance(glm::dvec3 p, glm::dvec3 q, const std::array<glm::dvec3, 3>& t) {
  const auto f = [&](double s) {
    const glm::dvec3 x = p + s * (q - p);
    return glm::length(test::brute_closest_on_triangle(x, t[0], t[1], t[2]) - x);
  };
  double lo = 0.0, hi = 1.0;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int i = 0; i < 80; ++i) {
    const double m1 = hi - g * (hi - lo);
    const double m2 = lo + g * (hi - lo);
    if (f(m1) < f(m2)) {
      hi = m2;
    } else {
      lo = m1;
    }
  }
  return std::min({f(0.0), f(1.0), f(0.5 * (lo + hi))});
}

// Capsules and segments against a triangle take a closed form for their cores' closest points
// (not GJK): touching with and without a margin, and the speculative depth, against the brute
// distance above. Placements over the triangle (both ends above it), lying along an edge and
// crossing it are drawn on purpose, besides random ones.
TEST(TriangleQuery, CapsuleAndSegmentAgainstBruteSegmentTriangleDistance) {
  std::mt19937 rng(29);
  int apart = 0, touching = 0, over = 0, crossing = 0;
  for (int iter = 0; iter < 6000; ++iter) {
    const Triangle tri = random_triangle(rng, 2.0f);
    const std::array<Vec3, 3>& v = tri.vertices;
    Vec3 p, q;
    const Vec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
    const auto inner = [&]() {  // a random point of the triangle
      float u = test::uniform(rng, 0.0f, 1.0f), w = test::uniform(rng, 0.0f, 1.0f);
      if (u + w > 1.0f) u = 1.0f - u, w = 1.0f - w;
      return v[0] + u * (v[1] - v[0]) + w * (v[2] - v[0]);
    };
    switch (iter % 4) {
      case 0:  // both ends over the triangle, one side
        p = inner() + test::uniform(rng, 0.01f, 0.8f) * n;
        q = inner() + test::uniform(rng, 0.01f, 0.8f) * n;
        ++over;
        break;
      case 1: {  // along an edge, off to its outside or above it
        const int k = static_cast<int>(rng() % 3);
        const Vec3 e0 = v[static_cast<std::size_t>(k)], e1 = v[static_cast<std::size_t>((k + 1) % 3)];
        const Vec3 off = test::random_point3(rng, 0.5f);
        p = e0 + test::uniform(rng, -0.3f, 0.6f) * (e1 - e0) + off;
        q = e0 + test::uniform(rng, 0.4f, 1.3f) * (e1 - e0) + off;
        break;
      }
      case 2: {  // through the plane, near the triangle
        const Vec3 x = inner() + test::random_point3(rng, 0.3f);
        const Vec3 d = test::random_unit3(rng) * test::uniform(rng, 0.1f, 1.0f);
        p = x + d;
        q = x - d;
        ++crossing;
        break;
      }
      default:
        p = test::random_point3(rng, 2.0f);
        q = test::random_point3(rng, 2.0f);
    }
    const float radius = iter % 5 == 0 ? 0.0f : test::uniform(rng, 0.05f, 0.5f);
    const double core = brute_segment_triangle_distance(
        glm::dvec3(p), glm::dvec3(q), {glm::dvec3(v[0]), glm::dvec3(v[1]), glm::dvec3(v[2])});
    const double gap = core - radius;
    const auto contact_with = [&](float margin) {
      return radius > 0.0f ? contact(make_capsule(p, q, radius), Transform3{}, tri, Transform3{}, margin)
                           : contact(make_segment(p, q), Transform3{}, tri, Transform3{}, margin);
    };
    const Manifold3 m = contact_with(0.0f);
    if (gap > 1e-4) {
      EXPECT_FALSE(m.touching()) << iter << " gap " << gap;
      ++apart;
      const Manifold3 s = contact_with(static_cast<float>(gap) + 0.05f);
      ASSERT_TRUE(s.touching()) << iter << " gap " << gap;
      float deepest = -1e30f;
      for (int i = 0; i < s.count; ++i) deepest = std::max(deepest, s.points[i].depth);
      // A face contact measures along the face normal (within kFaceContactSine of the closest
      // points' direction): its deepest point lies no nearer than the gap, a little farther.
      EXPECT_LE(deepest, -gap + 1e-4) << iter;
      EXPECT_GE(deepest, -gap * (1.0 + kFaceContactSine) - 1e-4) << iter;
      const Manifold3 short_margin = contact_with(static_cast<float>(gap) * 0.9f - 1e-4f);
      EXPECT_FALSE(short_margin.touching()) << iter << " gap " << gap;
    } else if (gap < -1e-4) {
      EXPECT_TRUE(m.touching()) << iter << " gap " << gap;
      ++touching;
    }
  }
  EXPECT_GT(apart, 1500);
  EXPECT_GT(touching, 1000);
  EXPECT_GT(over, 1000);
  EXPECT_GT(crossing, 1000);
}

// Spheres and lying capsules over slivers 2 units long and 2^-3 to 2^-21 wide (wider than the
// float spacing of their coordinates, below which rounding a corner makes another triangle):
// a single Triangle (down to make_triangle's limit) and a one-triangle mesh, the depth against
// the nearest point found in double. With the normals made in float, a sliver's plane turned
// by FLT_EPSILON times its length over width: depths were 0.003 off at 2^-17, and the mesh's
// early out dropped contacts up to 0.05 deep at 2^-19 and 2^-21.
TEST(TriangleQuery, SpheresAndCapsulesOverSliversTouchAtTheirNearestPoint) {
  std::mt19937 rng(104);
  constexpr double kTolerance = 2e-6;  // a few float spacings at coordinates up to 4
  int triangles = 0, meshes = 0;
  for (int i = 0; i < 8000; ++i) {
    const int e = 3 + static_cast<int>(rng() % 19);
    const float width = std::ldexp(1.0f, -e);
    const std::array<Vec3, 3> t = test::random_sliver(rng, 2.0f, 2.0f, width, i % 2 == 1);
    const float radius = test::uniform(rng, 0.1f, 1.0f);
    const double height = test::uniform(rng, -0.9f, 0.9f) * radius;
    if (std::fabs(height) < 0.01) continue;
    const bool capsule = i % 3 == 2;
    const Vec3 p = test::random_point_over(rng, t, height);
    const Vec3 q = capsule ? test::random_point_over(rng, t, height) : p;
    // Over the face on one side: the nearest point of the triangle is an end's.
    const std::array<glm::dvec3, 3> dt{glm::dvec3(t[0]), glm::dvec3(t[1]), glm::dvec3(t[2])};
    const auto nearest = [&](Vec3 x) { return test::brute_closest_on_triangle(glm::dvec3(x), dt[0], dt[1], dt[2]); };
    const glm::dvec3 np = nearest(p), nq = nearest(q);
    const double dp = glm::length(np - glm::dvec3(p)), dq = glm::length(nq - glm::dvec3(q));
    const double gap = std::min(dp, dq);
    const glm::dvec3 direction = dp <= dq ? (np - glm::dvec3(p)) / dp : (nq - glm::dvec3(q)) / dq;
    const auto check = [&](const Manifold3& m, double normal_slack, const char* what) {
      ASSERT_GT(m.count, 0) << what << " " << i << " width 2^-" << e;
      float deepest = -1e30f;
      for (int k = 0; k < m.count; ++k) deepest = std::max(deepest, m.points[k].depth);
      ASSERT_NEAR(deepest, radius - gap, kTolerance) << what << " " << i << " width 2^-" << e;
      // The normal's sideways error times the distance: how far off the nearest point it aims.
      const double off = glm::length(glm::cross(glm::normalize(glm::dvec3(m.normal)), direction)) * gap;
      ASSERT_LE(off, kTolerance + normal_slack) << what << " " << i << " width 2^-" << e;
    };
    const auto contact_with = [&](const auto& b, const Transform3& xb) {
      return capsule ? contact(make_capsule(p, q, radius), Transform3{}, b, xb)
                     : contact(make_sphere(Vec3(0.0f), radius), Transform3{p, Quat{1, 0, 0, 0}}, b, xb);
    };
    const std::vector<Vec3> corners{t[0], t[1], t[2]};
    const std::vector<glm::uvec3> one{{0, 1, 2}};
    const TriangleMesh mesh = make_triangle_mesh(corners, one);
    // The mesh holds its corners about a vertex of its own: rounded there, a sliver turns about
    // its long edge by up to a float spacing over its width, and so does its face normal.
    check(contact_with(mesh, Transform3{}), 2.0 * width, "mesh");
    ++meshes;
    // make_triangle's limit: twice the area (length times width) above 2 kDegenerateAreaTolerance
    // times the length squared.
    if (width > 2.0f * kDegenerateAreaTolerance * 2.0f * 1.1f) {
      check(contact_with(make_triangle(t[0], t[1], t[2]), Transform3{}), 0.0, "triangle");
      ++triangles;
    }
  }
  EXPECT_GT(meshes, 7000);
  EXPECT_GT(triangles, 3500);
}

// Boxes and hulls through slivers 2 units long and 2^-3 to 2^-21 wide (stop 104 made the
// triangle's face normal in double for them too), a single Triangle and a one-triangle mesh,
// against the exact Minkowski difference in double (hull_pairs.hpp: the separating axes of a
// hull and a triangle): never shallower than the penetration depth, and the reported normal
// within the face preference (kEdgeContactTolerance, kReferenceFaceTolerance of the smaller
// shape's size) of the best axis, and no point deeper than that normal says. (Between the
// penetration depth and that normal's: a face preferred within the tolerance clips away the
// deepest vertex when it lies beyond the face's sides.)
TEST(TriangleQuery, BoxesAndHullsThroughSliversMatchTheSeparatingAxes) {
  std::mt19937 rng(105);
  constexpr double kTolerance = 4e-6;  // float spacings at coordinates up to about 4
  int triangles = 0, meshes = 0;
  for (int i = 0; i < 6000; ++i) {
    const int e = 3 + static_cast<int>(rng() % 19);
    const float width = std::ldexp(1.0f, -e);
    const std::array<Vec3, 3> t = test::random_sliver(rng, 2.0f, 2.0f, width, i % 2 == 1);
    const std::array<test::DVec3, 3> dt{test::DVec3(t[0]), test::DVec3(t[1]), test::DVec3(t[2])};
    const bool box = i % 2 == 0;
    const Vec3 half(test::uniform(rng, 0.1f, 1.0f), test::uniform(rng, 0.1f, 1.0f), test::uniform(rng, 0.1f, 1.0f));
    std::vector<Vec3> box_corners;
    for (int k = 0; k < 8; ++k) box_corners.emplace_back(k & 1 ? half.x : -half.x, k & 2 ? half.y : -half.y, k & 4 ? half.z : -half.z);
    const ConvexHull hull = box ? make_convex_hull(box_corners) : test::random_hull(rng, 12, 0.6f);
    float reach = 0.0f;
    for (const Vec3& v : hull.vertices) reach = std::max(reach, length(v));
    const Transform3 xa{test::random_point_over(rng, t, test::uniform(rng, -1.0f, 1.0f) * reach), test::random_rotation(rng)};
    const test::MinkowskiReference k = test::minkowski_reference(hull, xa, dt);
    const double depth = k.depth();
    if (depth < 1e-3) continue;
    // The smaller shape's size as the tolerances take it (twice the farthest vertex from the
    // centroid), a bound on both preferences.
    const test::DVec3 centroid = (dt[0] + dt[1] + dt[2]) / 3.0;
    double triangle_size = 0.0;
    for (const test::DVec3& c : dt) triangle_size = std::max(triangle_size, 2.0 * glm::length(c - centroid));
    const double preference =
        std::max(kEdgeContactTolerance, kReferenceFaceTolerance) * std::min(2.0 * double(reach), triangle_size);
    const auto check = [&](const Manifold3& m, const char* what) {
      ASSERT_GT(m.count, 0) << what << " " << i << " width 2^-" << e;
      double deepest = -1e30;
      for (int p = 0; p < m.count; ++p) deepest = std::max(deepest, double(m.points[p].depth));
      const test::DVec3 n = glm::normalize(test::DVec3(m.normal));
      ASSERT_GE(deepest, depth - kTolerance) << what << " " << i << " width 2^-" << e;
      ASSERT_LE(k.depth_along(n), depth + preference + kTolerance) << what << " " << i << " width 2^-" << e;
      ASSERT_LE(deepest, k.depth_along(n) + kTolerance) << what << " " << i << " width 2^-" << e;
    };
    const auto contact_with = [&](const auto& b) {
      return box ? contact(make_box(half), xa, b, Transform3{}) : contact(hull, xa, b, Transform3{});
    };
    const std::vector<Vec3> corners{t[0], t[1], t[2]};
    const std::vector<glm::uvec3> one{{0, 1, 2}};
    check(contact_with(make_triangle_mesh(corners, one)), "mesh");
    ++meshes;
    if (width > 2.0f * kDegenerateAreaTolerance * 2.0f * 1.1f) {  // make_triangle's limit, as above
      check(contact_with(make_triangle(t[0], t[1], t[2])), "triangle");
      ++triangles;
    }
  }
  EXPECT_GT(meshes, 3000);
  EXPECT_GT(triangles, 1500);
}

TEST(TriangleQuery, ClosestPointVoronoiFeatures) {
  const Triangle tri = make_triangle({0, 0, 0}, {2, 0, 0}, {0, 0, 2});  // normal -y
  const Transform3 xf{{100, 5, -3}, Quat{1, 0, 0, 0}};
  const auto at = [&](Vec3 p) { return closest_point(tri, xf, xf.p + p); };
  PointQuery3 q = at({0.5f, 1.0f, 0.5f});
  EXPECT_EQ(q.feature, (Feature{FeatureType::face, 0}));
  EXPECT_NEAR(q.distance, 1.0f, 1e-5f);
  EXPECT_FALSE(q.inside);
  q = at({-1, 0.5f, -1});
  EXPECT_EQ(q.feature, (Feature{FeatureType::vertex, 0}));
  q = at({3, 0, -0.5f});
  EXPECT_EQ(q.feature, (Feature{FeatureType::vertex, 1}));
  q = at({1, 0, -1});
  EXPECT_EQ(q.feature, (Feature{FeatureType::edge, 0}));
  q = at({1.5f, 0, 1.5f});
  EXPECT_EQ(q.feature, (Feature{FeatureType::edge, 1}));
  q = at({-1, 2, 1});
  EXPECT_EQ(q.feature, (Feature{FeatureType::edge, 2}));
  EXPECT_NEAR(q.distance, std::sqrt(5.0f), 1e-4f);
  q = at({0.5f, 0, 0.5f});  // on the face
  EXPECT_EQ(q.distance, 0.0f);
}

TEST(TriangleQuery, ShapeCastSphereOntoTriangle) {
  const Triangle tri = make_triangle({-5, 0, -5}, {-5, 0, 5}, {5, 0, 0});
  const Sphere s = make_sphere(Vec3(0.0f), 0.5f);
  const Transform3 xs{{0.5f, 3.0f, 0.2f}, Quat{1, 0, 0, 0}};
  const ShapeCastResult3 r = shape_cast(s, xs, Vec3(0, -5, 0), tri, Transform3{}, Vec3(0.0f));
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.fraction, 2.5f / 5.0f, 1e-3f);
  EXPECT_NEAR(r.normal.y, -1.0f, 1e-4f);
  const ShapeCastResult3 miss = shape_cast(s, xs, Vec3(20, 0, 0), tri, Transform3{}, Vec3(0.0f));
  EXPECT_FALSE(miss.hit);
}

TEST(TriangleQuery, BoxOnTriangleFace) {
  const Triangle tri = make_triangle({-10, 0, -10}, {-10, 0, 10}, {10, 0, 0});
  const Box box = make_box({0.5f, 0.5f, 0.5f});
  const Transform3 xb{{0.1f, 0.49f, 0.2f}, Quat{1, 0, 0, 0}};
  const Manifold3 m = contact(box, xb, tri, Transform3{});
  ASSERT_EQ(m.count, 4);
  EXPECT_NEAR(m.normal.y, -1.0f, 1e-5f);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(m.points[i].depth, 0.01f, 1e-4f);
  // And the reverse order: the reversed manifold.
  const Manifold3 r = contact(tri, Transform3{}, box, xb);
  ASSERT_EQ(r.count, 4);
  EXPECT_NEAR(r.normal.y, 1.0f, 1e-5f);
}

// A box above, touching or sunk into a large flat triangle, with a speculative margin: the
// lowest corner's height h is the analytic signed distance. Cores apart within the margin
// (0 < h <= margin) take GJK's closest points, overlapping ones the separating axis test; both
// must give depth -h along the triangle's normal, and a box beyond the margin nothing.
TEST(TriangleQuery, BoxOnTriangleWithMarginAgreesWithTheLowestCorner) {
  const Triangle tri = make_triangle({-50, 0, -50}, {-50, 0, 50}, {50, 0, 0});
  const Box box = make_box({0.5f, 0.3f, 0.2f});
  constexpr float kMargin = 0.1f;
  std::mt19937 rng(2611);
  int apart = 0, sunk = 0, beyond = 0;
  for (int iter = 0; iter < 2000; ++iter) {
    const Quat q = test::random_rotation(rng);
    // Lowest corner below the centre by the box's support along -y.
    float reach_down = 0.0f;
    for (int c = 0; c < 8; ++c) {
      const Vec3 corner{(c & 1) ? 0.5f : -0.5f, (c & 2) ? 0.3f : -0.3f, (c & 4) ? 0.2f : -0.2f};
      reach_down = std::max(reach_down, -rotate(q, corner).y);
    }
    const float h = std::uniform_real_distribution<float>(-0.2f, 0.2f)(rng);
    const Transform3 xb{{std::uniform_real_distribution<float>(-5.0f, 5.0f)(rng), h + reach_down, 0.3f}, q};
    const Manifold3 m = contact(box, xb, tri, Transform3{}, kMargin);
    if (h > kMargin + 1e-4f) {
      ++beyond;
      EXPECT_EQ(m.count, 0) << "h " << h;
      continue;
    }
    if (h > 1e-4f && h < kMargin - 1e-4f) ++apart;
    if (h < -1e-4f) ++sunk;
    if (h < kMargin - 1e-4f) {
      ASSERT_GE(m.count, 1) << "h " << h;
      EXPECT_NEAR(std::fabs(m.normal.y), 1.0f, 1e-4f) << "h " << h;
      float deepest = -INFINITY;  // max_depth() clamps at 0: speculative points are negative
      for (int i = 0; i < m.count; ++i) deepest = std::max(deepest, m.points[i].depth);
      EXPECT_NEAR(deepest, -h, 2e-5f) << "h " << h;
    }
  }
  EXPECT_GT(apart, 300);
  EXPECT_GT(sunk, 700);
  EXPECT_GT(beyond, 300);
}

// make_triangle refuses degenerate triangles; a collinear one built by hand still yields no NaN.
TEST(TriangleQuery, DegenerateTriangleNoNaN) {
  EXPECT_THROW((void)make_triangle({0, 0, 0}, {1, 0, 0}, {2, 0, 0}), InvalidInput);
  EXPECT_THROW((void)make_triangle({0, 0, 0}, {0, 0, 0}, {0, 1, 0}), InvalidInput);
  const Triangle flat{{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{2, 0, 0}}};
  std::mt19937 rng(14);
  for (int iter = 0; iter < 500; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 1.0f);
    const Transform3 xa = test::random_transform3(rng, 2.0f);
    std::visit(
        [&](const auto& a) {
          const DistanceResult3 d = distance(a, xa, flat, Transform3{});
          EXPECT_TRUE(std::isfinite(d.distance) && finite(d.point_a) && finite(d.point_b));
          const Manifold3 m = contact(a, xa, flat, Transform3{}, 0.1f);
          EXPECT_TRUE(finite(m.normal));
          for (int i = 0; i < m.count; ++i) {
            EXPECT_TRUE(finite(m.points[i].point) && std::isfinite(m.points[i].depth));
          }
          (void)overlap(a, xa, flat, Transform3{});
          const ShapeCastResult3 c = shape_cast(a, xa, Vec3(1, 2, 3), flat, Transform3{}, Vec3(0.0f));
          EXPECT_TRUE(std::isfinite(c.fraction) && finite(c.point) && finite(c.normal));
        },
        shape);
    const PointQuery3 q = closest_point(flat, Transform3{}, xa.p);
    EXPECT_TRUE(std::isfinite(q.distance) && finite(q.closest));
  }
}

}  // namespace
}  // namespace collide
