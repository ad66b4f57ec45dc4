// The single 3D triangle: validation, bounds, the closest point and the watertight ray crossing
// against double-precision answers by other methods (tests/support/brute_triangle.hpp).
#include "support/brute_triangle.hpp"
#include "support/test_util.hpp"

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/shape/triangle.hpp>

#include <gtest/gtest.h>

#include <array>
#include <limits>
#include <algorithm>
#include <random>
#include <string>

namespace collide {
namespace {

using test::uniform;

std::string error_of(Vec3 a, Vec3 b, Vec3 c) {
  try {
    (void)make_triangle(a, b, c);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(Triangle, MakeTriangleNamesTheBadVertexAndRefusesNoArea) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(error_of({nan, 0, 0}, {1, 0, 0}, {0, 1, 0}), "triangle vertex 0: not finite");
  EXPECT_EQ(error_of({0, 0, 0}, {1, inf, 0}, {0, 1, 0}), "triangle vertex 1: not finite");
  EXPECT_EQ(error_of({0, 0, 0}, {1, 0, 0}, {0, 1, -inf}), "triangle vertex 2: not finite");
  const std::string degenerate = "triangle: degenerate (repeated or collinear vertices, no area)";
  EXPECT_EQ(error_of({0, 0, 0}, {0, 0, 0}, {0, 1, 0}), degenerate);
  EXPECT_EQ(error_of({0, 0, 0}, {1, 1, 1}, {3, 3, 3}), degenerate);
  // A sliver: area 2.5e-7 of its longest edge squared, below kDegenerateAreaTolerance.
  EXPECT_EQ(error_of({0, 0, 0}, {1000, 0, 0}, {500, 0.0005f, 0}), degenerate);
  // Just above the tolerance, far from the origin and huge: accepted as given.
  const Triangle t = make_triangle({0, 0, 0}, {1000, 0, 0}, {500, 0.01f, 0});
  EXPECT_EQ(t.vertices[2], Vec3(500, 0.01f, 0));
  EXPECT_NO_THROW((void)make_triangle({1e30f, 0, 0}, {-1e30f, 0, 0}, {0, 1e30f, 1e30f}));
}

TEST(Triangle, BoundsHoldTheCornersPlaced) {
  std::mt19937 rng(70);
  for (int i = 0; i < 100; ++i) {
    const Triangle t = make_triangle(test::random_point3(rng, 5), test::random_point3(rng, 5), test::random_point3(rng, 5));
    const Transform3 xf{test::random_point3(rng, 100), test::random_rotation(rng)};
    const Aabb3 box = compute_aabb(t, xf);
    Vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const Vec3& v : t.vertices) {
      const Vec3 w = transform_point(xf, v);
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
    EXPECT_VEC3_NEAR(box.min, lo, 1e-4f);
    EXPECT_VEC3_NEAR(box.max, hi, 1e-4f);
  }
}

TEST(Triangle, ClosestPointEqualsBruteForce) {
  std::mt19937 rng(71);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 a = test::random_point3(rng, 3), b = test::random_point3(rng, 3), c = test::random_point3(rng, 3);
    const Vec3 p = test::random_point3(rng, 6);
    const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
    const glm::dvec3 truth = test::brute_closest_on_triangle(glm::dvec3(p), glm::dvec3(a), glm::dvec3(b), glm::dvec3(c));
    EXPECT_NEAR(glm::length(glm::dvec3(q.point) - glm::dvec3(p)), glm::length(truth - glm::dvec3(p)), 1e-4);
    EXPECT_VEC3_NEAR(q.weights.x * a + q.weights.y * b + q.weights.z * c, q.point, 1e-4f);
  }
}

// Slivers 2 units long and 2^-3 to 2^-29 wide, caps and needles in turn, in any direction,
// with points about the middle of the long edge and anywhere near. Made in float, the plane of
// such a triangle turns by about FLT_EPSILON times its length over width, and Ericson's region
// tests cancel: the nearest point was off by more than a unit (2026-12-07, 1.75 units at a
// width of 1.5e-8). Against the double brute force: the distance within float rounding of the
// coordinates (up to about 6), the point on the triangle, the weights giving the point back.
TEST(Triangle, ClosestPointOnSliversIsWithinRounding) {
  std::mt19937 rng(74);
  constexpr double kTolerance = 2e-6;  // a few float spacings at coordinates up to 8
  for (int i = 0; i < 20000; ++i) {
    const float width = std::ldexp(1.0f, -3 - static_cast<int>(rng() % 27));
    const auto [a, b, c] = test::random_sliver(rng, 2.0f, 2.0f, width, i % 2 == 1);
    const Vec3 p = i % 4 < 2 ? 0.5f * (a + b) + test::random_point3(rng, 0.01f) : test::random_point3(rng, 4.0f);
    const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
    const glm::dvec3 da(a), db(b), dc(c), dp(p), dq(q.point);
    const glm::dvec3 truth = test::brute_closest_on_triangle(dp, da, db, dc);
    ASSERT_NEAR(glm::length(dq - dp), glm::length(truth - dp), kTolerance) << i << " width " << width;
    ASSERT_LE(glm::length(test::brute_closest_on_triangle(dq, da, db, dc) - dq), kTolerance) << i << " off the triangle";
    const glm::dvec3 w(q.weights);
    ASSERT_GE(std::min({w.x, w.y, w.z}), 0.0) << i;
    ASSERT_NEAR(w.x + w.y + w.z, 1.0, 1e-6) << i;
    ASSERT_LE(glm::length(w.x * da + w.y * db + w.z * dc - dq), kTolerance) << i << " weights";
  }
}

// Needles narrower than 2^-40 of their length, beyond what double resolves (a corner 1e-20
// beside another, 4.5 from the third, as a height field with spacing 1e-20 makes): their edge
// vectors round the width away and the face tests read 0, so a point beyond the tip was "over
// the face" at distance 0 (found by the fuzzer's height field contact check, stop 105). Now such
// a needle is its edges: the distance is the nearest edge point's, in double (segments are
// exact there), within the needle's width.
TEST(Triangle, ClosestPointOnNeedlesBeyondDoubleIsOnTheirEdges) {
  const Vec3 a(4.5f, -5.74394217e-21f, -8.0f), b(4.5f, 4.5f, -3.5f), c(4.5f, 4.25605751e-21f, -8.0f);
  const TrianglePoint tip = closest_point_on_triangle({4.5f, 5.625f, -2.375f}, a, b, c);
  EXPECT_EQ(tip.point, b);
  std::mt19937 rng(105);
  const auto segment_distance = [](glm::dvec3 p, glm::dvec3 u, glm::dvec3 v) {
    const glm::dvec3 e = v - u;
    const double t = std::clamp(glm::dot(p - u, e) / glm::dot(e, e), 0.0, 1.0);
    return glm::length(p - (u + t * e));
  };
  for (int i = 0; i < 4000; ++i) {
    // Two corners a tiny step apart either side of the origin (where float holds it), the third
    // up to 4 away: widths 2^-44 to 2^-120 of the length.
    const int e = 45 + static_cast<int>(rng() % 75);
    const Vec3 step = std::ldexp(1.0f, -e) * test::random_unit3(rng);
    const Vec3 x = -0.5f * step, y = test::random_point3(rng, 4.0f), z = 0.5f * step;
    const Vec3 p = i % 2 == 0 ? y + 0.5f * test::random_point3(rng, 1.0f) : test::random_point3(rng, 4.0f);
    const TrianglePoint q = closest_point_on_triangle(p, x, y, z);
    const glm::dvec3 dp(p), dx(x), dy(y), dz(z);
    const double edges = std::min({segment_distance(dp, dx, dy), segment_distance(dp, dy, dz), segment_distance(dp, dz, dx)});
    ASSERT_NEAR(glm::length(glm::dvec3(q.point) - dp), edges, 2e-6) << i << " step 2^-" << e;
  }
}

// A needle whose short side lies near the origin, its tip far away: taken from the tip, the
// short side comes out of the difference of two long edge vectors, which double rounds (a side
// 2^-51 beside a tip 8 away: the normal was along (1, 0, 2), not (1, 1, 1)). Found by the
// fuzzer's mesh contact check (finding 23: a capsule and a box at such a side had no contact).
// The truth is exact: corners 0, s d and a (small integers, s a power of two) have the normal
// s (d x a), in every order of the corners that keeps the winding.
TEST(Triangle, AreaNormalOfANeedleIsExactFromEveryCorner) {
  const std::array<glm::ivec3, 3> tips{glm::ivec3(8, -4, -4), glm::ivec3(-6, 3, 9), glm::ivec3(1, 7, -5)};
  const std::array<glm::ivec3, 3> sides{glm::ivec3(1, -1, 0), glm::ivec3(2, 1, -3), glm::ivec3(0, 1, 1)};
  int checked = 0;
  for (const glm::ivec3& tip : tips) {
    for (const glm::ivec3& side : sides) {
      const glm::dvec3 truth = glm::normalize(glm::cross(glm::dvec3(side), glm::dvec3(tip)));  // exact: small integers
      for (int e = 0; e <= 12; e += 4) {
        for (int k = 20; k <= 90; k += 5) {
          const Vec3 a = std::ldexp(1.0f, e) * Vec3(tip), b(0.0f), c = std::ldexp(1.0f, -k) * Vec3(side);
          const std::array<Vec3, 3> v{a, b, c};
          for (int first = 0; first < 3; ++first) {
            const Vec3 p = v[std::size_t(first)], q = v[std::size_t((first + 1) % 3)], r = v[std::size_t((first + 2) % 3)];
            const glm::dvec3 n = glm::normalize(triangle_area_normal(p, q, r));
            ASSERT_GT(glm::dot(n, truth), 1.0 - 1e-12) << "tip 2^" << e << " side 2^-" << k << " from corner " << first;
            const Vec3 unit = triangle_normal(p, q, r);
            EXPECT_LE(length(unit - Vec3(truth)), 4e-7f) << "tip 2^" << e << " side 2^-" << k << " from corner " << first;
            ++checked;
          }
        }
      }
    }
  }
  EXPECT_EQ(checked, 3 * 3 * 4 * 15 * 3);
}

TEST(Triangle, NormalIsUnitRightHandedAndSurvivesTinyTriangles) {
  EXPECT_EQ(triangle_normal({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), Vec3(0, 0, 1));
  EXPECT_EQ(triangle_normal({0, 0, 0}, {0, 1, 0}, {1, 0, 0}), Vec3(0, 0, -1));
  // Edges of 1e-20: the cross product (1e-40) is below what a plain normalisation accepts.
  EXPECT_VEC3_NEAR(triangle_normal({0, 0, 0}, {1e-20f, 0, 0}, {0, 0, 1e-20f}), Vec3(0, -1, 0), 1e-6f);
  EXPECT_EQ(triangle_normal({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), Vec3(0.0f));
}

TEST(Triangle, RayCrossingEqualsBruteForceFromBothSides) {
  std::mt19937 rng(72);
  int hits = 0, misses = 0, back = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = test::random_point3(rng, 3), b = test::random_point3(rng, 3), c = test::random_point3(rng, 3);
    Ray3 ray{test::random_point3(rng, 6), test::random_point3(rng, 8)};
    if (i % 2) {  // aimed at a point of the triangle (or near it), from either side
      const float u = uniform(rng, -0.1f, 1.0f), v = uniform(rng, -0.1f, 1.0f - u);
      ray.translation = (a + u * (b - a) + v * (c - a) - ray.origin) * uniform(rng, 0.8f, 3.0f);
    }
    const float f = ray_triangle_fraction(ray, a, b, c);
    const auto truth = test::brute_ray_triangle(glm::dvec3(ray.origin), glm::dvec3(ray.translation), glm::dvec3(a),
                                                glm::dvec3(b), glm::dvec3(c));
    // Near an edge, or ending near the plane, either answer is right within rounding: skip those.
    const glm::dvec3 n = glm::cross(glm::dvec3(b - a), glm::dvec3(c - a));
    const double len = glm::length(n);
    if (truth) {
      const glm::dvec3 q = glm::dvec3(ray.origin) + *truth * glm::dvec3(ray.translation);
      const double margin = std::min({glm::dot(n, glm::cross(glm::dvec3(c - b), q - glm::dvec3(b))),
                                      glm::dot(n, glm::cross(glm::dvec3(a - c), q - glm::dvec3(c))),
                                      glm::dot(n, glm::cross(glm::dvec3(b - a), q - glm::dvec3(a)))}) / len;
      if (margin < 1e-4 || *truth > 1.0 - 1e-5 || *truth < 1e-5) continue;
      ASSERT_GE(f, 0.0f) << i;
      EXPECT_NEAR(f, *truth, 1e-5 * (1.0 + 1.0 / std::abs(glm::dot(n / len, glm::normalize(glm::dvec3(ray.translation))))));
      ++hits;
      back += glm::dot(n, glm::dvec3(ray.translation)) > 0.0;
    } else {
      // A miss by a clear margin: the segment's distance to the triangle is not tiny.
      bool close = false;
      for (int k = 0; k <= 100 && !close; ++k) {
        const glm::dvec3 p = glm::dvec3(ray.origin) + (k / 100.0) * glm::dvec3(ray.translation);
        const glm::dvec3 q = test::brute_closest_on_triangle(p, glm::dvec3(a), glm::dvec3(b), glm::dvec3(c));
        close = glm::length(q - p) < 0.02 * glm::length(glm::dvec3(ray.translation));
      }
      if (close) continue;
      EXPECT_LT(f, 0.0f) << i;
      ++misses;
    }
  }
  EXPECT_GT(hits, 2000);
  EXPECT_GT(back, 800);  // two-sided: back faces hit too
  EXPECT_GT(misses, 5000);
}

// A sliver (a wall strip 6000 long and 9 wide, as FCL's env.obj has, 3000 units from the
// origin, turned at random): the watertight test's own fraction interpolates the corners'
// distances along the ray by edge functions whose rounding grows with length over width (it
// was 0.04 units off along a ray of env.obj); slivers are measured from their plane. Crossings
// clearly inside the strip, against the exact crossing in double, in world units along the ray.
TEST(Triangle, SliverCrossingIsWithinRoundingOfThePlane) {
  std::mt19937 rng(73);
  double worst = 0.0;
  int hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::quat q = test::random_rotation(rng);
    const Vec3 centre = glm::normalize(test::random_point3(rng, 1.0f) + Vec3(0.0f, 0.0f, 1e-3f)) * 3000.0f;
    const float length = 6000.0f, width = uniform(rng, 5.0f, 20.0f);
    const Vec3 a = centre + q * Vec3(-0.5f * length, 0.0f, 0.0f), b = centre + q * Vec3(0.5f * length, 0.0f, 0.0f);
    const Vec3 c = centre + q * Vec3(uniform(rng, -0.5f, 0.5f) * length, width, 0.0f);
    const float u = uniform(rng, 0.1f, 0.8f), v = uniform(rng, 0.1f, 0.9f - u);
    const Vec3 target = a + u * (b - a) + v * (c - a);
    const Vec3 origin = target + q * Vec3(uniform(rng, -1500.0f, 1500.0f), uniform(rng, -1500.0f, 1500.0f),
                                          uniform(rng, 200.0f, 1500.0f) * (i % 2 ? 1.0f : -1.0f));
    const Ray3 ray{origin, (target - origin) * uniform(rng, 1.05f, 1.5f)};
    const auto truth = test::brute_ray_triangle(glm::dvec3(ray.origin), glm::dvec3(ray.translation), glm::dvec3(a),
                                                glm::dvec3(b), glm::dvec3(c));
    ASSERT_TRUE(truth) << i;
    const float f = ray_triangle_fraction(ray, a, b, c);
    ASSERT_GT(f, 0.0f) << i;
    worst = std::max(worst, std::abs(f - *truth) * glm::length(glm::dvec3(ray.translation)));
    ++hits;
  }
  EXPECT_LT(worst, 1e-3);  // a few float spacings at 3000 (2.4e-4); it was 0.13 before slivers used the plane
}

TEST(Triangle, RayCrossingEdgeCases) {
  const Vec3 a(-1, 0, -1), b(1, 0, -1), c(0, 0, 1);  // in y = 0, normal -y
  const auto cast = [&](Vec3 o, Vec3 d, float max = 1.0f) { return ray_triangle_fraction(Ray3{o, d}, a, b, c, max); };
  // 1. Straight down onto the middle, from above and from below (two-sided).
  EXPECT_EQ(cast({0, 1, 0}, {0, -2, 0}), 0.5f);
  EXPECT_EQ(cast({0, -1, 0}, {0, 2, 0}), 0.5f);
  // 2. Ends exactly on the triangle: counts (fraction 1).
  EXPECT_EQ(cast({0, 1, 0}, {0, -1, 0}), 1.0f);
  // 3. Starts exactly on it, either way: no hit (the ray must leave the surface to hit).
  EXPECT_LT(cast({0, 0, 0}, {0, -1, 0}), 0.0f);
  EXPECT_LT(cast({0, 0, 0}, {0, 1, 0}), 0.0f);
  // 4. In the plane (through the triangle): no hit.
  EXPECT_LT(cast({-5, 0, 0}, {10, 0, 0}), 0.0f);
  // 5. Exactly through a corner and through an edge: hits (closed triangle).
  EXPECT_EQ(cast({1, 1, -1}, {0, -2, 0}), 0.5f);
  EXPECT_EQ(cast({0, 1, -1}, {0, -2, 0}), 0.5f);
  EXPECT_EQ(cast({0.5f, 1, 0}, {0, -2, 0}), 0.5f);  // on edge b -> c
  // 6. Just outside an edge: miss.
  EXPECT_LT(cast({0, 1, -1.0001f}, {0, -2, 0}), 0.0f);
  // 7. Beyond max_fraction: miss; max_fraction is inclusive.
  EXPECT_LT(cast({0, 1, 0}, {0, -2, 0}, 0.4f), 0.0f);
  EXPECT_EQ(cast({0, 1, 0}, {0, -2, 0}, 0.5f), 0.5f);
  // 8. Zero length, NaN, infinite: no hit.
  EXPECT_LT(cast({0, 1, 0}, {0, 0, 0}), 0.0f);
  EXPECT_LT(cast({0, std::numeric_limits<float>::quiet_NaN(), 0}, {0, -2, 0}), 0.0f);
  EXPECT_LT(cast({0, 1, 0}, {0, -std::numeric_limits<float>::infinity(), 0}), 0.0f);
  // 9. A ray running down every axis direction sign (the watertight axis permutation).
  for (int axis = 0; axis < 3; ++axis) {
    for (float s : {-1.0f, 1.0f}) {
      Vec3 d(0.0f);
      d[axis] = s;
      const Vec3 p0(0.1f, 0.2f, 0.3f);
      Vec3 o = p0 - 2.0f * d;
      const Vec3 e1 = axis == 0 ? Vec3(0, 1, 0) : Vec3(1, 0, 0), e2 = cross(d, e1);
      EXPECT_NEAR(ray_triangle_fraction(Ray3{o, 4.0f * d}, p0 - e1 - e2, p0 + e1 - e2, p0 + e2), 0.5f, 1e-6f) << axis << s;
    }
  }
}

}  // namespace
}  // namespace collide
