// 3D ray casts checked against a double-precision brute force (tests/support/brute_query3.hpp:
// the first fraction at which the swept ray touches the shape, by bisection on point, segment
// and triangle distances; the normal as the distance's numerical gradient), on random shapes
// under random rigid transforms, near the origin, 1e4 away and at size ratios of 1e4; plus
// numbered edge cases (inside, on the surface, parallel to a face, through an edge and a
// vertex, NaN, zero length) and a laser in a corner-cube retroreflector (analytic).

#include <collide/ccd/raycast.hpp>
#include <collide/narrow/closest_point.hpp>

#include "clip_ray.hpp"
#include "support/brute_query3.hpp"
#include "support/random_shapes3.hpp"
#include "support/bitwise_equal.hpp"
#include "support/test_util.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

namespace collide {
namespace {

using test::DVec3;
using test::uniform;

/// How a random test is placed.
struct Setup {
  Vec3 far{0.0f};      ///< offset of everything from the world origin
  float size = 1.0f;   ///< scale of the shapes
  /// > 0: rays of about this length starting near a surface point (big shapes, short rays);
  /// 0: rays from up to `reach` sizes away aimed at the shape's neighbourhood.
  float short_rays = 0.0f;
  float reach = 4.0f;  ///< rays start within this many sizes of the shape
};

std::vector<Shape3D> random_shapes(std::mt19937& rng, ShapeType3D type, float size, bool rounded) {
  std::vector<Shape3D> v;
  for (int i = 0; i < 20; ++i) {
    const Vec3 c = test::random_point3(rng, 0.5f * size);
    switch (type) {
      case ShapeType3D::sphere:
        v.push_back(make_sphere(c, size * uniform(rng, 0.3f, 2.0f)));
        break;
      case ShapeType3D::capsule:
        v.push_back(make_capsule(test::random_point3(rng, 1.5f * size),
                                 test::random_point3(rng, 1.5f * size),
                                 size * uniform(rng, 0.1f, 1.2f)));
        break;
      case ShapeType3D::segment:
        v.push_back(make_segment(test::random_point3(rng, 2.0f * size),
                                 test::random_point3(rng, 2.0f * size)));
        break;
      case ShapeType3D::box:
        v.push_back(make_box(size * Vec3{uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f),
                                         uniform(rng, 0.2f, 2.0f)},
                             rounded ? size * uniform(rng, 0.05f, 1.0f) : 0.0f));
        break;
      case ShapeType3D::hull:
        v.push_back(test::random_hull(rng, 4 + i * 2, 3.0f * size,
                                      rounded ? size * uniform(rng, 0.05f, 1.0f) : 0.0f));
        break;
    }
  }
  return v;
}

DVec3 dvec(Vec3 v) { return DVec3(v); }

/// Entry and grazing tolerance, as a fraction of the local extent of a ray cast (the ray's
/// length plus its origin's distance from the shape's placement plus the shape's size): 8
/// float epsilons (2^-23 = 1.2e-7) gathered by the transform and the quadratics.
constexpr double kDecide = 1e-6;
/// World points round to float at the coordinates' size.
constexpr double kWorldRounding = 2e-7;
/// Unit normals agree within this plus the turn of a curved surface's normal by the hit
/// point's rounding (the brute force's numerical gradient is good to ~1e-6).
constexpr double kNormalBase = 1e-4;

/// The build tolerance of a hull (its faces are planar within it), 0 for other shapes.
double hull_tolerance(const Shape3D& shape) {
  const ConvexHull* hull = std::get_if<ConvexHull>(&shape);
  return hull ? hull->tolerance : 0.0;
}

/// Smallest radius of curvature of the shape's surface (infinite when flat).
double curvature_radius(const Shape3D& shape) {
  const double flat = std::numeric_limits<double>::infinity();
  switch (static_cast<ShapeType3D>(shape.index())) {
    case ShapeType3D::sphere: return std::get<Sphere>(shape).radius;
    case ShapeType3D::capsule: return std::get<Capsule3>(shape).radius;
    case ShapeType3D::segment: return flat;
    case ShapeType3D::box: {
      const float r = std::get<Box>(shape).radius;
      return r > 0.0f ? r : flat;
    }
    case ShapeType3D::hull: {
      const float r = std::get<ConvexHull>(shape).radius;
      return r > 0.0f ? r : flat;
    }
  }
  return flat;
}

struct Counts {
  int hits = 0, misses = 0, inside = 0, skipped = 0, total = 0;
  int either_face = 0;  ///< hits within rounding of an edge of a flat shape
};

/// Random rays at random placements of `shapes`, compared with the brute force. A ray whose
/// answer is decided within rounding (grazing: the ray's gap to the shape, the origin's
/// distance or the chord inside within the tolerance of zero) is skipped and counted; every
/// other ray must agree on hit or miss, and hits on the entry, point and normal.
Counts compare_with_brute_force(const std::vector<Shape3D>& shapes, std::mt19937& rng,
                                const Setup& s) {
  Counts n;
  double worst_along = 0.0, worst_normal = 0.0;
  for (const Shape3D& shape : shapes) {
    for (int k = 0; k < 60; ++k) {
      const Transform3 xf{s.far + test::random_point3(rng, 3.0f * s.size), test::random_rotation(rng)};
      Ray3 ray;
      if (s.short_rays > 0.0f) {
        // Placement only: a surface point near a random point (the truth is the brute force).
        const Vec3 surface =
            closest_point(shape, xf, xf.p + test::random_point3(rng, 2.0f * s.size)).closest;
        ray.origin = surface + test::random_point3(rng, s.short_rays);
        ray.translation = test::random_point3(rng, 2.0f * s.short_rays);
      } else {
        ray.origin = xf.p + test::random_point3(rng, s.reach * s.size);
        const Vec3 target = xf.p + test::random_point3(rng, 2.0f * s.size);
        ray.translation = (target - ray.origin) * uniform(rng, 0.5f, 2.0f);
      }
      const RayHit3 ours = raycast(shape, xf, ray);
      // The brute force works in double with everything shifted by -xf.p (exact: differences
      // of floats are doubles), so the truth for these float inputs is as precise far away.
      const DVec3 shift = dvec(xf.p);
      const test::BruteCore core = test::brute_core_of(shape, Transform3{Vec3(0.0f), xf.q});
      const double ray_length = glm::length(dvec(ray.translation));
      const test::BruteRay truth =
          test::brute_raycast(core, dvec(ray.origin) - shift, dvec(ray.translation), s.size);
      ++n.total;
      // Rounding of the local problem: float epsilons of the ray's extent around the shape and
      // of the shape's size (the world offset cancels when the ray is moved to local space).
      const double local = ray_length + glm::length(dvec(ray.origin - xf.p)) + s.size;
      // A hull's faces are planar only within its build tolerance: the planes the cast uses
      // and the corners the brute force triangulates differ by that much.
      const double decide = kDecide * local + hull_tolerance(shape);
      const bool grazing = truth.starts_inside ? false
                           : truth.hit         ? truth.depth < decide
                                               : truth.end_gap < decide;
      if (std::fabs(truth.start_distance) < decide || grazing) {
        ++n.skipped;
        continue;
      }
      SCOPED_TRACE(testing::Message() << type_name(shape) << " ray " << k);
      EXPECT_EQ(ours.hit, truth.hit) << "starts inside " << truth.starts_inside;
      if (ours.hit != truth.hit) continue;
      // The Shape3D overload and the typed one agree exactly.
      EXPECT_EQ(std::visit([&](const auto& x) { return raycast(x, xf, ray).fraction; }, shape),
                ours.fraction);
      if (!ours.hit) {
        (truth.starts_inside ? n.inside : n.misses)++;
        EXPECT_EQ(ours.fraction, 0.0f);
        EXPECT_EQ(ours.normal, Vec3(0.0f));
        EXPECT_EQ(ours.point, Vec3(0.0f));
        continue;
      }
      ++n.hits;
      // A grazing hit is ill-conditioned: a surface error e moves the entry by e / cos(incidence).
      const double incidence = std::fabs(glm::dot(truth.normal, dvec(ray.translation) / ray_length));
      const double conditioning = 1.0 / std::max(incidence, 0.01);
      EXPECT_GE(ours.fraction, 0.0f);
      EXPECT_LE(ours.fraction, 1.0f);
      const double along = std::fabs(ours.fraction - truth.fraction) * ray_length;
      worst_along = std::max(worst_along, along / (local * conditioning));
      EXPECT_LE(along, decide * conditioning) << ours.fraction << " vs " << truth.fraction;
      // The world point adds the rounding of world coordinates.
      const DVec3 truth_point = dvec(ray.origin) + truth.fraction * dvec(ray.translation);
      const double world = decide * conditioning + kWorldRounding * max_abs(s.far);
      EXPECT_LE(glm::length(dvec(ours.point) - truth_point), world);
      EXPECT_LE(std::fabs(test::brute_signed_distance(core, dvec(ours.point) - shift)), world);
      // On a curved surface of radius rc, an error e in the local hit point turns the normal
      // by e / rc; e is some float epsilons of the local extent.
      const double normal_error = glm::length(dvec(ours.normal) - truth.normal);
      const double rc = curvature_radius(shape);
      const double normal_tolerance = kNormalBase + kDecide * local / rc;
      if (normal_error > normal_tolerance && rc == std::numeric_limits<double>::infinity()) {
        // A hit within rounding of a flat shape's edge may name either face: then the plane
        // through the true entry with our normal must still support the shape.
        const double overhang = test::brute_support(core, dvec(ours.normal)) -
                                glm::dot(dvec(ours.normal), truth_point - shift);
        EXPECT_LE(overhang, decide * conditioning) << "normal off by " << normal_error;
        ++n.either_face;
        continue;
      }
      worst_normal = std::max(worst_normal, normal_error / normal_tolerance);
      EXPECT_LE(normal_error, normal_tolerance) << "incidence " << incidence;
      EXPECT_NEAR(length(ours.normal), 1.0f, 1e-5f);
    }
  }
  std::printf("[ rates    ] %d hits (%d on an edge within rounding), %d misses, %d starting inside,"
              " %d skipped as grazing, of %d; worst entry error %.2g of the extent, worst normal"
              " error %.2g of its tolerance\n",
              n.hits, n.either_face, n.misses, n.inside, n.skipped, n.total, worst_along, worst_normal);
  EXPECT_LE(n.either_face, n.hits / 100) << "hits on edges should be rare";
  return n;
}

void expect_rates(const Counts& n) {
  EXPECT_GT(n.hits, n.total * 20 / 100) << "hit rate too low to test hits";
  EXPECT_GT(n.misses, n.total * 15 / 100) << "miss rate too low to test misses";
  EXPECT_GT(n.inside, 0) << "no ray starting inside";
  EXPECT_LT(n.skipped, n.total * 2 / 100) << "too many grazing rays: the test decides little";
}

const Vec3 kFarAway{1.0e4f, -1.0e4f, 1.0e4f};

void run_random(ShapeType3D type, bool rounded, unsigned seed) {
  std::mt19937 rng(seed);
  {
    SCOPED_TRACE("near the origin");
    expect_rates(compare_with_brute_force(random_shapes(rng, type, 1.0f, rounded), rng, Setup{}));
  }
  {
    SCOPED_TRACE("1e4 away");
    Setup s;
    s.far = kFarAway;
    expect_rates(compare_with_brute_force(random_shapes(rng, type, 1.0f, rounded), rng, s));
  }
  {
    SCOPED_TRACE("small shapes, rays from 1e4 times their size away");
    Setup s;
    s.size = 1e-2f;
    s.reach = 1e4f;
    const Counts n = compare_with_brute_force(random_shapes(rng, type, s.size, rounded), rng, s);
    EXPECT_GT(n.hits, n.total / 20);
    EXPECT_GT(n.misses, n.total / 2);
    EXPECT_LT(n.skipped, n.total * 5 / 100);
  }
  {
    // The ray's position is known to float epsilons of the shape's coordinates (~1e2 here),
    // a few thousandths of its length: more of these rays are within rounding of grazing.
    // A hull of that size is planar only within its build tolerance (kHullRelativeTolerance of
    // its extent, ~6e-3), which the brute force's triangles and the cast's planes differ by:
    // its rays are 100 times longer (CubeHullMatchesBox checks 1e4 on an exactly planar hull).
    SCOPED_TRACE("big shapes, rays 1e4 (hulls: 200) times shorter near their surface");
    Setup s;
    s.size = 1e2f;
    s.short_rays = type == ShapeType3D::hull ? 1.0f : 1e-2f;
    const Counts n = compare_with_brute_force(random_shapes(rng, type, s.size, rounded), rng, s);
    EXPECT_GT(n.hits, n.total * 8 / 100);
    EXPECT_GT(n.misses, n.total * 15 / 100);
    EXPECT_GT(n.inside, n.total * 15 / 100);
    EXPECT_LT(n.skipped, n.total * 10 / 100);
  }
}

TEST(Raycast3, SphereMatchesBruteForce) { run_random(ShapeType3D::sphere, false, 1); }
TEST(Raycast3, CapsuleMatchesBruteForce) { run_random(ShapeType3D::capsule, false, 2); }
TEST(Raycast3, BoxMatchesBruteForce) { run_random(ShapeType3D::box, false, 3); }
TEST(Raycast3, RoundedBoxMatchesBruteForce) { run_random(ShapeType3D::box, true, 4); }
TEST(Raycast3, HullMatchesBruteForce) { run_random(ShapeType3D::hull, false, 12); }
TEST(Raycast3, RoundedHullMatchesBruteForce) { run_random(ShapeType3D::hull, true, 13); }

/// The box as a hull of its 8 corners.
ConvexHull cube_hull(const Box& box) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box.vertex(i));
  return make_convex_hull(corners, HullOptions{box.radius});
}

// A box and the hull of its corners are the same solid (rounded or not, its faces exactly
// planar): every ray agrees, near unit size and for boxes of 1e2 with rays 1e4 times shorter
// near their surface (the box being checked against the brute force there).
TEST(Raycast3, CubeHullMatchesBox) {
  std::mt19937 rng(14);
  for (const float size : {1.0f, 1e2f}) {
    int hits = 0, total = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const Box box = make_box(size * Vec3{uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f),
                                           uniform(rng, 0.2f, 2.0f)},
                               trial % 2 ? size * uniform(rng, 0.05f, 0.8f) : 0.0f);
      const ConvexHull hull = cube_hull(box);
      ASSERT_EQ(hull.faces.size(), 6u);
      for (int k = 0; k < 100; ++k) {
        const Transform3 xf = test::random_transform3(rng, 10.0f * size);
        Ray3 ray;
        if (size == 1.0f) {
          ray.origin = xf.p + test::random_point3(rng, 5.0f);
          ray.translation = (xf.p + test::random_point3(rng, 2.0f) - ray.origin) * 1.5f;
        } else {
          const Vec3 surface = closest_point(box, xf, xf.p + test::random_point3(rng, 3.0f * size)).closest;
          ray.origin = surface + test::random_point3(rng, 1e-2f);
          ray.translation = test::random_point3(rng, 2e-2f);
        }
        const float extent = length(ray.origin - xf.p) + length(ray.translation);
        const float rounding = 1e-6f * extent;  // 8 float epsilons
        const float start = std::fabs(closest_point(box, xf, ray.origin).distance);
        const float end = std::fabs(closest_point(box, xf, ray.at(1.0f)).distance);
        if (start < rounding || end < rounding) continue;
        const RayHit3 a = raycast(box, xf, ray);
        const RayHit3 b = raycast(hull, xf, ray);
        ++total;
        if (a.hit != b.hit) {
          // Only a ray grazing within rounding may differ: its deepest point is that shallow.
          const RayHit3& h = a.hit ? a : b;
          const Vec3 mid = ray.at(0.5f * (h.fraction + 1.0f));
          EXPECT_LT(-closest_point(box, xf, mid).distance, 4.0f * rounding);
          continue;
        }
        if (!a.hit) continue;
        ++hits;
        EXPECT_LE(std::fabs(a.fraction - b.fraction) * length(ray.translation), rounding);
        if (distance(a.normal, b.normal) > 1e-4f) {
          // Within rounding of an edge either face may be named (the box's rounded edges are
          // no exception: there the normals turn quickly); the hit points agree anyway.
          EXPECT_LT(closest_point(box, xf, a.point).distance, rounding);
        }
      }
    }
    EXPECT_GT(hits, total / 10) << "size " << size;
    EXPECT_GT(total, 3000);
  }
}

// A segment has no area: random rays never hit it; rays built to cross it (origin and
// direction chosen, the segment's point between) hit at the crossing, the normal across the
// segment in the common plane, facing the origin.
TEST(Raycast3, SegmentHitOnlyByCrossingRays) {
  std::mt19937 rng(5);
  int crossing_hits = 0, random_hits = 0, random_total = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Segment3 seg = make_segment(test::random_point3(rng, 2.0f), test::random_point3(rng, 2.0f));
    const Transform3 xf = test::random_transform3(rng, 10.0f);
    // Random rays near the segment: general position, never on it.
    const Vec3 o = transform_point(xf, test::random_point3(rng, 3.0f));
    const Ray3 random_ray{o, transform_point(xf, test::random_point3(rng, 2.0f)) - o};
    ++random_total;
    random_hits += raycast(seg, xf, random_ray).hit;
    // Crossing rays: through the point at s, from a random direction, ending beyond it.
    const float s = uniform(rng, 0.02f, 0.98f);
    const Vec3 x = seg.a + s * (seg.b - seg.a);
    const Vec3 dir = test::random_point3(rng, 1.0f);
    const float before = uniform(rng, 0.5f, 3.0f);
    const Vec3 local_origin = x - before * dir;
    const Ray3 ray{transform_point(xf, local_origin), rotate(xf.q, 2.0f * before * dir)};
    const RayHit3 h = raycast(seg, xf, ray);
    ASSERT_TRUE(h.hit) << "trial " << trial;
    ++crossing_hits;
    EXPECT_NEAR(h.fraction, 0.5f, 1e-4f);
    EXPECT_VEC3_NEAR(h.point, transform_point(xf, x), 1e-4f);
    const Vec3 n = inv_rotate(xf.q, h.normal);
    const Vec3 e = normalize_or_zero(seg.b - seg.a);
    EXPECT_NEAR(length(n), 1.0f, 1e-5f);
    EXPECT_NEAR(dot(n, e), 0.0f, 1e-4f);                  // across the segment
    EXPECT_NEAR(dot(n, cross(e, dir)), 0.0f, 1e-4f);      // in the common plane
    EXPECT_LT(dot(n, dir), 0.0f);                         // facing the origin
    // Too short, or starting past the crossing: no hit.
    EXPECT_FALSE(raycast(seg, xf, Ray3{ray.origin, 0.45f * ray.translation}).hit);
    EXPECT_FALSE(raycast(seg, xf, Ray3{transform_point(xf, x + 0.1f * dir), ray.translation}).hit);
    // Moved off the segment's line by 1e-3 of its length (far beyond the tolerance): misses.
    const Vec3 off = 1e-3f * length(seg.b - seg.a) * normalize_or_zero(cross(e, dir));
    EXPECT_FALSE(raycast(seg, xf, Ray3{transform_point(xf, local_origin + off), ray.translation}).hit);
  }
  EXPECT_EQ(random_hits, 0);
  EXPECT_EQ(crossing_hits, 400);
  // Far from the world origin with exactly representable inputs: the ray crosses exactly.
  const Segment3 seg = make_segment({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
  const Transform3 far{{1.0e4f, 1.0e4f, -1.0e4f}, Quat{1.0f, 0.0f, 0.0f, 0.0f}};
  const RayHit3 h = raycast(seg, far, Ray3{{1.0e4f + 0.5f, 1.0e4f - 3.0f, -1.0e4f}, {0.0f, 6.0f, 0.0f}});
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.fraction, 0.5f);
  EXPECT_VEC3_NEAR(h.normal, Vec3(0.0f, -1.0f, 0.0f), 0.0f);
}

// Edge case: a ray along a segment's line hits the nearer end, normal back along the ray; one
// starting on the segment, heading away, or too short, misses.
TEST(Raycast3, RayCollinearWithSegment) {
  std::mt19937 rng(6);
  const Segment3 seg = make_segment({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f});
  for (int k = 0; k < 50; ++k) {
    const Transform3 xf = k == 0 ? Transform3{} : test::random_transform3(rng, 10.0f);
    auto cast = [&](Vec3 o, Vec3 d) {
      return raycast(seg, xf, Ray3{transform_point(xf, o), rotate(xf.q, d)});
    };
    const RayHit3 from_left = cast({-3.0f, 0.0f, 0.0f}, {4.0f, 0.0f, 0.0f});
    ASSERT_TRUE(from_left.hit);
    EXPECT_NEAR(from_left.fraction, 0.5f, 1e-5f);
    EXPECT_VEC3_NEAR(from_left.normal, rotate(xf.q, {-1.0f, 0.0f, 0.0f}), 1e-5f);
    const RayHit3 from_right = cast({2.0f, 0.0f, 0.0f}, {-4.0f, 0.0f, 0.0f});
    ASSERT_TRUE(from_right.hit);
    EXPECT_NEAR(from_right.fraction, 0.25f, 1e-5f);
    EXPECT_VEC3_NEAR(from_right.normal, rotate(xf.q, {1.0f, 0.0f, 0.0f}), 1e-5f);
    EXPECT_FALSE(cast({-3.0f, 0.0f, 0.0f}, {-4.0f, 0.0f, 0.0f}).hit);  // heading away
    EXPECT_FALSE(cast({-3.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}).hit);   // too short
    EXPECT_FALSE(cast({0.5f, 0.0f, 0.0f}, {4.0f, 0.0f, 0.0f}).hit);    // starts on it
    EXPECT_FALSE(cast({0.5f, 0.0f, 0.0f}, {0.0f, 4.0f, 1.0f}).hit);    // starts on it, leaves
    EXPECT_FALSE(cast({-3.0f, 0.01f, 0.0f}, {4.0f, 0.0f, 0.0f}).hit);  // parallel, off the line
  }
}

// Edge case: a ray with a NaN coordinate, or of zero length, reports no hit.
TEST(Raycast3, NonFiniteOrZeroLengthRayMisses) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Shape3D> shapes = {
      make_sphere({0.0f, 0.0f, 0.0f}, 1.0f), make_capsule({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.5f),
      make_segment({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}), make_box({1.0f, 1.0f, 1.0f}),
      make_box({1.0f, 1.0f, 1.0f}, 0.5f), cube_hull(make_box({1.0f, 1.0f, 1.0f})),
      cube_hull(make_box({1.0f, 1.0f, 1.0f}, 0.5f))};
  const Transform3 id{};
  for (const Shape3D& s : shapes) {
    SCOPED_TRACE(type_name(s));
    // The same rays without the NaN hit (so the NaN is what makes them miss).
    EXPECT_TRUE(raycast(s, id, Ray3{{0.0f, -3.0f, 0.0f}, {0.0f, 6.0f, 0.0f}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{nan, -3.0f, 0.0f}, {0.0f, 6.0f, 0.0f}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{0.0f, -3.0f, nan}, {0.0f, 6.0f, 0.0f}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{0.0f, -3.0f, 0.0f}, {0.0f, 6.0f, nan}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{0.0f, -3.0f, 0.0f}, {nan, 6.0f, 0.0f}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{0.0f, -3.0f, 0.0f}, {0.0f, 0.0f, 0.0f}}).hit);
    EXPECT_FALSE(raycast(s, id, Ray3{{0.0f, -1.5f, 0.0f}, {0.0f, 0.0f, 0.0f}}).hit);
  }
}

// Edge case: a ray that starts inside never enters, however it is aimed and however long.
TEST(Raycast3, RayStartingInsideMisses) {
  std::mt19937 rng(7);
  const std::vector<Shape3D> shapes = {
      make_sphere({0.5f, 0.0f, 0.0f}, 1.0f), make_capsule({-1.0f, 0.0f, 0.0f}, {1.0f, 0.5f, 0.2f}, 0.5f),
      make_box({1.0f, 0.5f, 0.7f}), make_box({1.0f, 0.5f, 0.7f}, 0.3f), test::random_hull(rng, 30, 1.5f),
      test::random_hull(rng, 20, 1.2f, 0.3f)};
  int tested = 0;
  for (const Shape3D& shape : shapes) {
    for (int k = 0; k < 500; ++k) {
      const Transform3 xf = test::random_transform3(rng, k % 2 == 0 ? 10.0f : 1.0e4f);
      const Vec3 origin = transform_point(xf, test::random_point3(rng, 1.2f));
      if (!(closest_point(shape, xf, origin).distance < -1e-2f)) continue;
      ++tested;
      EXPECT_FALSE(raycast(shape, xf, Ray3{origin, test::random_point3(rng, 10.0f)}).hit)
          << type_name(shape);
    }
  }
  EXPECT_GT(tested, 500);
}

// Edge case: starting exactly on the surface, heading in or out, is not an entry; on a box face,
// edge and corner, a sphere, a capsule's side and cap, a rounded box's face, edge and corner.
TEST(Raycast3, RayStartingOnSurfaceMisses) {
  const Transform3 id{};
  const Box box = make_box({1.0f, 2.0f, 3.0f});
  for (const Vec3 o : {Vec3{1.0f, 0.0f, 0.0f}, Vec3{1.0f, 2.0f, 0.0f}, Vec3{1.0f, 2.0f, 3.0f}}) {
    EXPECT_FALSE(raycast(box, id, Ray3{o, -3.0f * o}).hit);
    EXPECT_FALSE(raycast(box, id, Ray3{o, 3.0f * o}).hit);
    EXPECT_FALSE(raycast(box, id, Ray3{o, {0.0f, 0.0f, -1.0f}}).hit);
  }
  const Sphere sphere = make_sphere({0.0f, 0.0f, 0.0f}, 2.0f);
  EXPECT_FALSE(raycast(sphere, id, Ray3{{0.0f, 2.0f, 0.0f}, {0.0f, -1.0f, 0.0f}}).hit);
  EXPECT_FALSE(raycast(sphere, id, Ray3{{0.0f, 2.0f, 0.0f}, {0.0f, 1.0f, 0.0f}}).hit);
  const Capsule3 capsule = make_capsule({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.5f);
  EXPECT_FALSE(raycast(capsule, id, Ray3{{0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, -1.0f}}).hit);
  EXPECT_FALSE(raycast(capsule, id, Ray3{{-1.5f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}}).hit);
  EXPECT_FALSE(raycast(capsule, id, Ray3{{1.5f, 0.0f, 0.0f}, {1.0f, 1.0f, 0.0f}}).hit);
  // Rounded boxes, with radii and offsets exact in binary so the points are exactly on them:
  // 0.375^2 + 0.5^2 = 0.625^2 (an edge), 0.125^2 + 0.5^2 + 1^2 = 1.125^2 (a corner).
  const Box rounded = make_box({1.0f, 1.0f, 1.0f}, 0.625f);
  for (const Vec3 o : {Vec3{1.625f, 0.0f, 0.0f}, Vec3{1.375f, 1.5f, 0.0f}}) {
    EXPECT_FALSE(raycast(rounded, id, Ray3{o, -o}).hit);
    EXPECT_FALSE(raycast(rounded, id, Ray3{o, o}).hit);
    EXPECT_FALSE(raycast(rounded, id, Ray3{o, {0.0f, 0.0f, 1.0f}}).hit);
  }
  const Box round_corner = make_box({1.0f, 1.0f, 1.0f}, 1.125f);
  const Vec3 corner{1.125f, 1.5f, 2.0f};
  EXPECT_FALSE(raycast(round_corner, id, Ray3{corner, -corner}).hit);
  EXPECT_FALSE(raycast(round_corner, id, Ray3{corner, corner}).hit);
  // The same points on the hulls of those boxes' corners.
  const ConvexHull hull = cube_hull(box);
  for (const Vec3 o : {Vec3{1.0f, 0.0f, 0.0f}, Vec3{1.0f, 2.0f, 0.0f}, Vec3{1.0f, 2.0f, 3.0f}}) {
    EXPECT_FALSE(raycast(hull, id, Ray3{o, -3.0f * o}).hit);
    EXPECT_FALSE(raycast(hull, id, Ray3{o, 3.0f * o}).hit);
  }
  const ConvexHull rounded_hull = cube_hull(rounded);
  for (const Vec3 o : {Vec3{1.625f, 0.0f, 0.0f}, Vec3{1.375f, 1.5f, 0.0f}}) {
    EXPECT_FALSE(raycast(rounded_hull, id, Ray3{o, -o}).hit);
    EXPECT_FALSE(raycast(rounded_hull, id, Ray3{o, o}).hit);
  }
  const ConvexHull round_corner_hull = cube_hull(round_corner);
  EXPECT_FALSE(raycast(round_corner_hull, id, Ray3{corner, -corner}).hit);
  EXPECT_FALSE(raycast(round_corner_hull, id, Ray3{corner, corner}).hit);
}

// Edge case: rays parallel to a box face, on its plane, touch the face (touching counts); just
// outside they miss, just inside they enter through the side face. Through an edge and a
// vertex exactly: the entry is there, the normal one of the faces that meet there.
template <class S>
void parallel_edge_and_vertex_rays(const S& box) {
  const Transform3 id{};
  const RayHit3 along = raycast(box, id, Ray3{{-3.0f, 1.0f, 0.2f}, {6.0f, 0.0f, 0.0f}});
  ASSERT_TRUE(along.hit);
  EXPECT_NEAR(along.fraction, 1.0f / 3.0f, 1e-6f);
  EXPECT_VEC3_NEAR(along.normal, Vec3(-1.0f, 0.0f, 0.0f), 1e-6f);
  // Through the edge x = -1, y = 1 (at 45 degrees in the xy plane) and the corner (-1, 1, 1).
  const RayHit3 edge = raycast(box, id, Ray3{{-2.0f, 2.0f, 0.3f}, {2.0f, -2.0f, 0.0f}});
  ASSERT_TRUE(edge.hit);
  EXPECT_NEAR(edge.fraction, 0.5f, 1e-6f);
  EXPECT_VEC3_NEAR(edge.point, Vec3(-1.0f, 1.0f, 0.3f), 1e-6f);
  EXPECT_TRUE(distance(edge.normal, Vec3(-1.0f, 0.0f, 0.0f)) < 1e-6f ||
              distance(edge.normal, Vec3(0.0f, 1.0f, 0.0f)) < 1e-6f);
  const RayHit3 vertex = raycast(box, id, Ray3{{-3.0f, 3.0f, 3.0f}, {4.0f, -4.0f, -4.0f}});
  ASSERT_TRUE(vertex.hit);
  EXPECT_NEAR(vertex.fraction, 0.5f, 1e-6f);
  EXPECT_VEC3_NEAR(vertex.point, Vec3(-1.0f, 1.0f, 1.0f), 1e-6f);
  EXPECT_NEAR(std::fabs(vertex.normal.x) + std::fabs(vertex.normal.y) + std::fabs(vertex.normal.z), 1.0f, 1e-6f);
  // Grazing the edge from outside (tangent to the corner in the plane y = 1) still touches.
  EXPECT_TRUE(raycast(box, id, Ray3{{-1.0f, 1.0f, 5.0f}, {0.0f, 0.0f, -8.0f}}).hit);
  // Under rigid motions the exact plane is lost to rounding; a margin decides.
  std::mt19937 rng(8);
  for (int k = 0; k < 200; ++k) {
    const Transform3 xf = test::random_transform3(rng, k % 2 ? 1.0e4f : 20.0f);
    const float margin = k % 2 ? 1e-2f : 1e-4f;
    const Vec3 d{6.0f, 0.0f, 0.0f};
    const Ray3 outside{transform_point(xf, {-3.0f, 1.0f + margin, 0.5f}), rotate(xf.q, d)};
    const Ray3 inside{transform_point(xf, {-3.0f, 1.0f - margin, 0.5f}), rotate(xf.q, d)};
    EXPECT_FALSE(raycast(box, xf, outside).hit);
    const RayHit3 h = raycast(box, xf, inside);
    ASSERT_TRUE(h.hit);
    EXPECT_VEC3_NEAR(h.normal, rotate(xf.q, {-1.0f, 0.0f, 0.0f}), 1e-5f);
    EXPECT_NEAR(h.fraction, 1.0f / 3.0f, k % 2 ? 1e-3f : 1e-5f);
  }
}

TEST(Raycast3, BoxParallelEdgeAndVertexRays) { parallel_edge_and_vertex_rays(make_box({1.0f, 1.0f, 1.0f})); }
TEST(Raycast3, HullParallelEdgeAndVertexRays) {
  parallel_edge_and_vertex_rays(cube_hull(make_box({1.0f, 1.0f, 1.0f})));
}

// Rounded box: a ray tangent to the flat top touches where the top meets the rounded edge; a
// ray along the diagonal hits the corner sphere at its pole; a ray parallel to an edge, outside
// the core's faces, is decided by the edge's cylinder alone, wherever it runs along it.
TEST(Raycast3, RoundedBoxAnalytic) {
  const Box box = make_box({1.0f, 2.0f, 3.0f}, 0.5f);
  const Transform3 id{};
  const RayHit3 tangent = raycast(box, id, Ray3{{-3.0f, 2.5f, 0.0f}, {6.0f, 0.0f, 0.0f}});
  ASSERT_TRUE(tangent.hit);
  EXPECT_NEAR(tangent.fraction, 2.0f / 6.0f, 1e-6f);
  EXPECT_VEC3_NEAR(tangent.normal, Vec3(0.0f, 1.0f, 0.0f), 1e-5f);
  const Vec3 corner{1.0f, 2.0f, 3.0f};
  const Vec3 u = normalize_or_zero(corner);
  const RayHit3 diagonal = raycast(box, id, Ray3{corner + 4.0f * u, -8.0f * u});
  ASSERT_TRUE(diagonal.hit);
  EXPECT_NEAR(diagonal.fraction, 3.5f / 8.0f, 1e-6f);
  EXPECT_VEC3_NEAR(diagonal.normal, u, 1e-6f);
  // Parallel to the z edge at x = 1, y = 2, at distance 0.4 (hits) or 0.6 (misses) from it in
  // the diagonal direction, from beyond the box's end: the cap corner first.
  const Vec3 w = normalize_or_zero(Vec3{1.0f, 1.0f, 0.0f});
  for (const float z0 : {10.0f, 0.0f}) {
    const Vec3 start = Vec3{1.0f, 2.0f, z0} + 0.4f * w;
    const RayHit3 near = raycast(box, id, Ray3{start, {0.0f, 0.0f, -20.0f}});
    if (z0 > 3.5f) {
      ASSERT_TRUE(near.hit);
      // Enters the corner sphere of radius 0.5 about (1, 2, 3) at z = 3 + sqrt(0.25 - 0.16).
      EXPECT_NEAR(near.fraction * 20.0f, z0 - 3.0f - 0.3f, 1e-5f);
      EXPECT_VEC3_NEAR(near.normal, (0.4f * w + Vec3{0.0f, 0.0f, 0.3f}) / 0.5f, 1e-5f);
    } else {
      EXPECT_FALSE(near.hit);  // starts inside the rounded edge
    }
    EXPECT_FALSE(raycast(box, id, Ray3{Vec3{1.0f, 2.0f, z0} + 0.6f * w, {0.0f, 0.0f, -20.0f}}).hit);
  }
}

// Capsule: along its axis, the cap's pole; parallel to the axis outside the radius, a miss;
// tangent to the side, a touch; beyond an end, that end's sphere.
TEST(Raycast3, CapsuleAnalytic) {
  std::mt19937 rng(9);
  const Capsule3 c = make_capsule({0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 0.5f);
  for (int k = 0; k < 40; ++k) {
    const Transform3 xf = k == 0 ? Transform3{} : test::random_transform3(rng, k % 2 ? 1.0e4f : 10.0f);
    // 1e4 away the ray's origin rounds to ~5e-4 when placed, which turns a normal on the 0.5
    // radius by ~1e-3.
    const float tol = k % 2 ? 2e-3f : 1e-5f;
    const float ntol = k % 2 ? 4e-3f : 1e-5f;
    auto cast = [&](Vec3 o, Vec3 d) { return raycast(c, xf, Ray3{transform_point(xf, o), rotate(xf.q, d)}); };
    const RayHit3 pole = cast({0.0f, 4.0f, 0.0f}, {0.0f, -5.0f, 0.0f});
    ASSERT_TRUE(pole.hit);
    EXPECT_NEAR(pole.fraction * 5.0f, 2.5f, tol);
    EXPECT_VEC3_NEAR(pole.normal, rotate(xf.q, {0.0f, 1.0f, 0.0f}), ntol);
    EXPECT_FALSE(cast({0.0f, 4.0f, 0.501f}, {0.0f, -10.0f, 0.0f}).hit);
    if (k == 0) {
      // Exactly tangent to the cylinder (exact in float at the origin): touches at x = 0.
      const RayHit3 tangent = cast({-3.0f, 0.3f, 0.5f}, {6.0f, 0.0f, 0.0f});
      ASSERT_TRUE(tangent.hit);
      EXPECT_NEAR(tangent.fraction, 0.5f, 1e-6f);
      EXPECT_VEC3_NEAR(tangent.normal, Vec3(0.0f, 0.0f, 1.0f), 1e-6f);
    }
    // Just inside tangent to the side (0.49 from the axis): enters 0.0995 before the axis.
    const RayHit3 side = cast({-3.0f, 0.3f, 0.49f}, {6.0f, 0.0f, 0.0f});
    ASSERT_TRUE(side.hit);
    EXPECT_NEAR(side.fraction * 6.0f, 3.0f - std::sqrt(0.25f - 0.49f * 0.49f), k % 2 ? 0.05f : 1e-4f);
    // Across the axis beyond end b: the cylinder is entered past b, so b's sphere decides.
    const RayHit3 cap = cast({0.0f, 1.3f, -2.0f}, {0.0f, 0.0f, 4.0f});
    ASSERT_TRUE(cap.hit);
    EXPECT_NEAR(cap.fraction * 4.0f, 2.0f - 0.4f, tol);
    EXPECT_VEC3_NEAR(cap.normal, rotate(xf.q, {0.0f, 0.6f, -0.8f}), ntol);
    // From inside the cylinder beyond end b, along the axis: b's sphere at y = 1 + 0.4.
    const RayHit3 inside_cylinder = cast({0.0f, 3.0f, 0.3f}, {0.0f, -4.0f, 0.0f});
    ASSERT_TRUE(inside_cylinder.hit);
    EXPECT_NEAR(inside_cylinder.fraction * 4.0f, 1.6f, tol);
    EXPECT_VEC3_NEAR(inside_cylinder.normal, rotate(xf.q, {0.0f, 0.8f, 0.6f}), ntol);
    EXPECT_FALSE(cast({0.0f, 1.6f, -2.0f}, {0.0f, 0.0f, 4.0f}).hit);
  }
}

// Rays across a capsule's side whose line passes r (1 + delta) from the core's line, at a point
// beside the core and at any tilt towards the axis: inside (delta < 0) they hit before that
// point, on the surface; outside they miss, whether the cast's early out on the line's distance
// takes them (delta well above its slack) or the full cast does (grazing, within it). Placed
// near the origin and 1e4 away, where the rays' rounding (about 6e-4) stays below delta r.
TEST(Raycast3, CapsuleSideRaysHitInsideTheRadiusAndMissOutside) {
  std::mt19937 rng(31);
  int hits = 0, misses = 0;
  // Grazing within the early out's slack only near the origin (1e4 away the rays round by more).
  const std::array<float, 10> near_deltas{-0.5f, -0.05f, -0.01f, -2e-3f, 2e-3f, 4e-3f, 0.01f, 0.05f, 0.5f, 5.0f};
  const std::array<float, 8> far_deltas{-0.5f, -0.05f, -0.01f, 0.01f, 0.02f, 0.05f, 0.5f, 5.0f};
  for (int trial = 0; trial < 400; ++trial) {
    const bool far = trial % 2 == 1;
    const float r = uniform(rng, 0.3f, 1.0f);
    const Capsule3 c =
        make_capsule(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f) + Vec3(2.0f, 0.0f, 0.0f), r);
    const Transform3 xf = test::random_transform3(rng, far ? 1.0e4f : 10.0f);
    const Vec3 axis = normalize(c.b - c.a);
    // u across the axis, v across both: a line through q along v (tilted towards the axis)
    // keeps its distance to the core's line along u.
    Vec3 u = cross(axis, test::random_point3(rng, 1.0f));
    if (length(u) < 1e-3f) u = cross(axis, Vec3(0.0f, 0.0f, 1.0f));
    u = normalize(u);
    const float tilt = uniform(rng, -1.0f, 1.0f);
    const Vec3 v = normalize(cross(axis, u) + tilt * axis);
    const float delta = far ? far_deltas[static_cast<std::size_t>(trial / 2) % far_deltas.size()]
                            : near_deltas[static_cast<std::size_t>(trial / 2) % near_deltas.size()];
    const Vec3 q = c.a + uniform(rng, 0.35f, 0.65f) * (c.b - c.a) + (r * (1.0f + delta)) * u;
    const Ray3 local{q - 4.0f * v, 8.0f * v};
    const Ray3 ray{transform_point(xf, local.origin), rotate(xf.q, local.translation)};
    const RayHit3 hit = raycast(c, xf, ray);
    if (delta < 0.0f) {
      ASSERT_TRUE(hit.hit) << "trial " << trial << " delta " << delta;
      EXPECT_LT(hit.fraction, 0.5f);
      // The hit point lies on the surface: r from the core.
      const float rounding = far ? 2e-3f : 1e-4f;
      EXPECT_NEAR(closest_point(c, xf, hit.point).distance, 0.0f, rounding) << "trial " << trial;
      ++hits;
    } else {
      EXPECT_FALSE(hit.hit) << "trial " << trial << " delta " << delta;
      ++misses;
    }
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 100);
}

// A capsule of radius 0, or one too thin to square in float, is its core segment: head on along
// the axis it is hit at the nearer end, the normal facing the ray; a ray through the core's
// middle, across it, hits with the normal facing the ray across the axis.
TEST(Raycast3, ZeroRadiusCapsuleFacesTheRay) {
  for (const float r : {0.0f, 1e-30f}) {
    const Capsule3 c = make_capsule({0.0f, -1.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, r);
    const RayHit3 head_on = raycast(c, Transform3{}, Ray3{{0.0f, 3.0f, 0.0f}, {0.0f, -4.0f, 0.0f}});
    ASSERT_TRUE(head_on.hit) << r;
    EXPECT_NEAR(head_on.fraction, 0.5f, 1e-6f);
    EXPECT_VEC3_NEAR(head_on.normal, Vec3(0.0f, 1.0f, 0.0f), 1e-6f);
    const RayHit3 across = raycast(c, Transform3{}, Ray3{{-2.0f, 0.5f, 0.0f}, {4.0f, 0.0f, 0.0f}});
    ASSERT_TRUE(across.hit) << r;
    EXPECT_NEAR(across.fraction, 0.5f, 1e-6f);
    EXPECT_VEC3_NEAR(across.normal, Vec3(-1.0f, 0.0f, 0.0f), 1e-6f);
    EXPECT_FALSE(raycast(c, Transform3{}, Ray3{{-2.0f, 0.5f, 0.1f}, {4.0f, 0.0f, 0.0f}}).hit);
  }
}

// A round piece hit dead on from far away (relative to its radius): the hit point's offset from
// the centre rounds to nothing (or to denormals), so it gives no direction; the normal faces the
// ray. fuzz_shapes found a rounded hull of radius 1e-20 whose edge capsule made it NaN
// (fuzz/regressions/shapes/rounded_hull_edge_radius_1e-20_normal_nan.bin); a sphere gave a zero
// normal. Radii where the offset keeps its digits give the unit normal from the centre.
TEST(Raycast3, DeadOnHitsOfTinyRoundPiecesFaceTheRay) {
  const Vec3 x{1.0f, 0.0f, 0.0f};
  const Ray3 ray{{-100.0f, 0.0f, 0.0f}, {200.0f, 0.0f, 0.0f}};
  std::vector<Vec3> corners{{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  for (const float r : {1e-3f, 1e-6f, 1e-10f, 1e-20f, 1e-30f}) {
    HullOptions rounded;
    rounded.radius = r;
    const Shape3D shapes[] = {make_sphere({0.0f, 0.0f, 0.0f}, r),
                              make_capsule({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, r),
                              make_capsule({0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, r),
                              make_convex_hull(corners, rounded)};
    for (const Shape3D& shape : shapes) {
      SCOPED_TRACE(testing::Message() << "radius " << r << ", shape " << shape.index());
      const RayHit3 h = raycast(shape, Transform3{}, ray);
      ASSERT_TRUE(h.hit) << r;
      EXPECT_NEAR(h.fraction, 0.5f, 1e-5f) << r;
      EXPECT_VEC3_NEAR(h.normal, -x, 1e-6f);
    }
  }
  // The NaN the fuzzer found: a hull of 8 points with radius 1e-20 hit near an edge.
  const std::vector<Vec3> points{{-1.0f, 5.16524007e-22f, 1e-20f}, {1e-20f, 1e-20f, 5.0f}, {5.0f, 5.0f, 1.75f},
                                 {1.0f, -2.0f, 2.0f}, {5.0f, 5.0f, 5.0f}, {4.25f, 1.0f, 1.0f},
                                 {-1.40129846e-45f, 1.0f, 2.0f}, {0.0f, 0.5f, 1e-20f}};
  HullOptions tiny;
  tiny.radius = 1e-20f;
  const RayHit3 h = raycast(make_convex_hull(points, tiny), Transform3{},
                            Ray3{{-100.0f, 0.1f, 0.2f}, {200.0f, 0.0f, 0.0f}});
  ASSERT_TRUE(h.hit);
  EXPECT_TRUE(is_finite(h.normal));
  EXPECT_NEAR(length(h.normal), 1.0f, 1e-6f);
  EXPECT_LT(dot(h.normal, x), 0.0f);
}

TEST(Raycast3, SphereTangentAndCentreRays) {
  const Sphere s = make_sphere({1.0f, 2.0f, 3.0f}, 1.0f);
  const Transform3 id{};
  const RayHit3 tangent = raycast(s, id, Ray3{{-1.0f, 3.0f, 3.0f}, {4.0f, 0.0f, 0.0f}});
  ASSERT_TRUE(tangent.hit);
  EXPECT_NEAR(tangent.fraction, 0.5f, 1e-6f);
  EXPECT_VEC3_NEAR(tangent.normal, Vec3(0.0f, 1.0f, 0.0f), 1e-6f);
  EXPECT_FALSE(raycast(s, id, Ray3{{-1.0f, 3.001f, 3.0f}, {4.0f, 0.0f, 0.0f}}).hit);
  const RayHit3 centre = raycast(s, id, Ray3{{1.0f, 2.0f, 10.0f}, {0.0f, 0.0f, -10.0f}});
  ASSERT_TRUE(centre.hit);
  EXPECT_NEAR(centre.fraction, 0.6f, 1e-6f);
  EXPECT_VEC3_NEAR(centre.point, Vec3(1.0f, 2.0f, 4.0f), 1e-6f);
  EXPECT_VEC3_NEAR(centre.normal, Vec3(0.0f, 0.0f, 1.0f), 1e-7f);
  // Ends exactly on the surface: touching counts.
  EXPECT_TRUE(raycast(s, id, Ray3{{1.0f, 2.0f, 10.0f}, {0.0f, 0.0f, -6.0f}}).hit);
  EXPECT_FALSE(raycast(s, id, Ray3{{1.0f, 2.0f, 10.0f}, {0.0f, 0.0f, -5.99f}}).hit);
}

TEST(Raycast3, ReflectMirrorsAboutTheNormal) {
  EXPECT_EQ(reflect(Vec3{1.0f, -2.0f, 3.0f}, Vec3{0.0f, 1.0f, 0.0f}), Vec3(1.0f, 2.0f, 3.0f));
  std::mt19937 rng(10);
  for (int k = 0; k < 100; ++k) {
    const Vec3 d = test::random_point3(rng, 3.0f);
    const Vec3 n = normalize_or_zero(test::random_point3(rng, 1.0f));
    const Vec3 r = reflect(d, n);
    EXPECT_NEAR(length(r), length(d), 1e-5f);                 // length kept
    EXPECT_NEAR(dot(r, n), -dot(d, n), 1e-5f);                // normal part flipped
    EXPECT_VEC3_NEAR(cross(r, n), cross(d, n), 1e-5f);        // tangent part kept
  }
}

/// A corner-cube retroreflector: three mirrors (thin boxes) whose inner faces are the planes
/// x = 0, y = 0, z = 0. A laser entering the corner reflects once off each and leaves exactly
/// reversed, having travelled (in total, unfolded) a straight line: its endpoint after the
/// three reflections is the start point with every coordinate of the unreflected endpoint
/// negated... run under random rigid motions of the whole scene.
TEST(Raycast3, LaserInCornerCube) {
  std::mt19937 rng(11);
  const Box mirror = make_box({0.5f, 50.0f, 50.0f});  // thin along local x
  for (int trial = 0; trial < 40; ++trial) {
    const Transform3 xf = trial == 0 ? Transform3{} : test::random_transform3(rng, trial % 2 ? 1.0e4f : 50.0f);
    const float tol = trial % 2 ? 2e-2f : 1e-3f;
    // Mirrors: boxes centred half a thickness behind each plane, on the positive side 50 wide.
    const Quat to_y = glm::angleAxis(0.5f * test::kPi, Vec3{0.0f, 0.0f, 1.0f});   // x -> y
    const Quat to_z = glm::angleAxis(-0.5f * test::kPi, Vec3{0.0f, 1.0f, 0.0f});  // x -> z
    const Transform3 mirrors[3] = {mul(xf, Transform3{{-0.5f, 50.0f, 50.0f}, Quat{1, 0, 0, 0}}),
                                   mul(xf, Transform3{{50.0f, -0.5f, 50.0f}, to_y}),
                                   mul(xf, Transform3{{50.0f, 50.0f, -0.5f}, to_z})};
    const Vec3 start{5.0f, 7.0f, 6.0f};
    const Vec3 dir = normalize_or_zero(Vec3{-1.0f, -1.3f, -0.8f});
    const float total = 40.0f;
    Ray3 ray{transform_point(xf, start), rotate(xf.q, total * dir)};
    int bounces = 0;
    for (int k = 0; k < 4; ++k) {
      int first = -1;
      RayHit3 best;
      for (int m = 0; m < 3; ++m) {
        const RayHit3 h = raycast(mirror, mirrors[m], ray);
        // Skip the mirror just left (rounding may re-hit it at ~0).
        if (h.hit && h.fraction * length(ray.translation) > tol && (first < 0 || h.fraction < best.fraction)) {
          first = m;
          best = h;
        }
      }
      if (first < 0) break;
      ++bounces;
      ray = reflect(ray, best);
    }
    ASSERT_EQ(bounces, 3) << "trial " << trial;
    // Unfolded: the three reflections negate every coordinate of the path in the corner's
    // frame, so the end is -(start + total dir) and the direction is -dir.
    EXPECT_VEC3_NEAR(ray.at(1.0f), transform_point(xf, -(start + total * dir)), tol);
    EXPECT_VEC3_NEAR(normalize_or_zero(ray.translation), rotate(xf.q, -dir), 1e-4f);
  }
}

#if defined(__SSE2__) || defined(_M_X64)
/// The hull ray cast clips four faces at a time (clip_ray_blocks over face_blocks); the scalar
/// Cyrus-Beck loop (clip_ray over faces) is what it replaced. On random rays, including rays
/// from inside, parallel to faces, through the planes' own points and NaN, both must agree on miss,
/// inside and hit, on the entry fraction to rounding, and on the entered face unless another face
/// is entered at the same fraction within rounding (an edge or a corner): then the hit point
/// must lie on both faces' planes.
TEST(Raycast3, HullLaneClipIsTheScalarClip) {
  std::mt19937 rng(77);
  int hits = 0, inside = 0, other_face = 0;
  for (int h = 0; h < 40; ++h) {
    const ConvexHull hull = test::random_hull(rng, 4 + h, 2.0f, 0.0f);
    const float offset = h % 3 == 0 ? 0.25f : 0.0f;  // as the rounded hull's pushed faces
    for (int i = 0; i < 500; ++i) {
      Vec3 p = test::random_point3(rng, 4.0f);
      Vec3 d = (test::random_point3(rng, 1.0f) - p) * uniform(rng, 0.3f, 2.0f);  // at the hull
      if (i % 7 == 0) p = 0.2f * p;                        // often inside
      if (i % 11 == 0) d -= dot(d, hull.faces[i % hull.faces.size()].normal) *
                              hull.faces[i % hull.faces.size()].normal;  // parallel to a face
      if (i % 13 == 0) p = hull.vertices[i % hull.vertices.size()];      // on the surface
      if (i % 17 == 0) p.y = std::numeric_limits<float>::quiet_NaN();    // no bound moves
      const detail::ClipResult lanes = detail::clip_ray_blocks(hull.face_blocks.data(), hull.face_blocks.size() / 16,
                                                               p.x, p.y, p.z, d.x, d.y, d.z, offset);
      const detail::ClipResult scalar = detail::clip_ray(static_cast<int>(hull.faces.size()), [&](int k) {
        const HullFace& f = hull.faces[k];
        return detail::PlaneCrossing{f.offset + offset - dot(f.normal, p), dot(f.normal, d)};
      });
      ASSERT_EQ(lanes.plane >= 0, scalar.plane >= 0) << "hull " << h << " ray " << i;
      ASSERT_EQ(lanes.inside, scalar.inside) << "hull " << h << " ray " << i;
      if (scalar.inside) ++inside;
      if (scalar.plane < 0) continue;
      ++hits;
      ASSERT_NEAR(lanes.fraction, scalar.fraction, 1e-6f * (1.0f + scalar.fraction)) << "hull " << h << " ray " << i;
      if (lanes.plane != scalar.plane) {
        ++other_face;
        const Vec3 x = p + lanes.fraction * d;
        for (const int k : {lanes.plane, scalar.plane}) {
          const HullFace& f = hull.faces[k];
          EXPECT_NEAR(dot(f.normal, x), f.offset + offset, 1e-4f) << "hull " << h << " ray " << i;
        }
      }
    }
  }
  EXPECT_GT(hits, 5000);
  EXPECT_GT(inside, 500);
  EXPECT_LT(other_face, hits / 100);
}
#endif

/// raycast_fraction against raycast (3D) on the same shape, placement and ray: the same hit, the
/// same fraction bit for bit, fraction 0 on a miss; through the template and through Shape3D.
/// Returns whether it hit.
bool expect_fraction_is_raycasts(const Shape3D& shape, const Transform3& xf, const Ray3& ray) {
  const RayHit3 full = raycast(shape, xf, ray);
  const RayFraction typed = std::visit([&](const auto& s) { return raycast_fraction(s, xf, ray); }, shape);
  for (const RayFraction f : {typed, raycast_fraction(shape, xf, ray)}) {
    EXPECT_TRUE(test::bitwise_equal(f, full)) << f.hit << " " << f.fraction << " against " << full.hit << " " << full.fraction;
    if (!f.hit) EXPECT_EQ(f.fraction, 0.0f);
  }
  return full.hit;
}

// Every 3D convex shape kind (spheres, capsules, segments, boxes and hulls sharp and rounded),
// near the origin and 1e4 away, rays from outside, inside and of zero length.
TEST(Raycast3, FractionIsRaycastsBitForBit) {
  std::mt19937 rng(43);
  int hits = 0, casts = 0;
  for (const Vec3 far : {Vec3{0.0f}, kFarAway}) {
    for (const ShapeType3D type : {ShapeType3D::sphere, ShapeType3D::capsule, ShapeType3D::segment,
                                   ShapeType3D::box, ShapeType3D::hull}) {
      for (const bool rounded : {false, true}) {
        for (const Shape3D& shape : random_shapes(rng, type, 1.0f, rounded)) {
          for (int i = 0; i < 100; ++i) {
            const Transform3 xf{far + test::random_point3(rng, 2.0f), test::random_rotation(rng)};
            const Vec3 origin = xf.p + test::random_point3(rng, 5.0f);
            const Vec3 target = xf.p + test::random_point3(rng, 1.5f);
            const float scale = i % 50 == 0 ? 0.0f : uniform(rng, 0.3f, 2.0f);  // some of zero length
            hits += expect_fraction_is_raycasts(shape, xf, Ray3{origin, scale * (target - origin)});
            ++casts;
          }
        }
      }
    }
  }
  EXPECT_GT(hits, casts / 5);
  EXPECT_LT(hits, casts * 4 / 5);
  // A segment hit: only a crossing ray meets it.
  EXPECT_TRUE(expect_fraction_is_raycasts(make_segment(Vec3{-1.0f, 0.0f, 0.0f}, Vec3{1.0f, 0.0f, 0.0f}),
                                          Transform3{}, Ray3{{0.25f, 2.0f, 0.0f}, {0.0f, -4.0f, 0.0f}}));
}

}  // namespace
}  // namespace collide
