// TriangleBvh against brute force: the nearest triangle of random soups (with degenerate
// triangles, which the BVH takes as given) and the box query.
#include "support/brute_triangle.hpp"
#include "support/test_util.hpp"

#include <collide/shape/triangle_bvh.hpp>

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace collide {
namespace {

using test::brute_closest_on_triangle;
using test::uniform;

float uniform01(std::mt19937& rng) { return uniform(rng, 0.0f, 1.0f); }

/// Triangles as indices into positions.
struct TriangleSoup {
  std::vector<Vec3> positions;
  std::vector<glm::uvec3> triangles;
};

/// `n` random triangles in a cube of side `extent` at `center`, of sizes up to `size`; every
/// seventh one degenerate in turn: a repeated corner, three collinear corners (on integer
/// coordinates, so exactly collinear in float), one point. (Not slivers, nearly collinear
/// triangles: their plane is ill-conditioned in float, and neither closest_point_on_triangle nor
/// the BVH's region test is exact on them; walk meshes drop them.)
TriangleSoup random_soup(std::mt19937& rng, int n, Vec3 center, float extent, float size) {
  TriangleSoup s;
  for (int i = 0; i < n; ++i) {
    Vec3 a = center + Vec3(uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent)) * 0.5f;
    auto near_a = [&] { return a + Vec3(uniform(rng, -size, size), uniform(rng, -size, size), uniform(rng, -size, size)); };
    Vec3 b = near_a(), c = near_a();
    switch (i % 21) {
      case 7: c = b; break;                              // repeated corner
      case 14: {                                         // collinear
        const Vec3 start = glm::round(a), half = glm::round(0.5f * (b - a));
        a = start, b = start + 2.0f * half, c = start + half;
        break;
      }
      case 20: b = c = a; break;                         // a point
      default: break;
    }
    const auto base = static_cast<unsigned>(s.positions.size());
    s.positions.insert(s.positions.end(), {a, b, c});
    s.triangles.push_back({base, base + 1, base + 2});
  }
  return s;
}

glm::dvec3 corner(const TriangleSoup& s, std::uint32_t t, int k) { return glm::dvec3(s.positions[s.triangles[t][k]]); }

/// Nearest distance to the soup by scanning every triangle, in double precision.
double brute_distance(const TriangleSoup& s, Vec3 q) {
  const glm::dvec3 p(q);
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t t = 0; t < s.triangles.size(); ++t) {
    best = std::min(best, glm::length(brute_closest_on_triangle(p, corner(s, t, 0), corner(s, t, 1), corner(s, t, 2)) - p));
  }
  return best;
}

TEST(TriangleBvh, NearestEqualsBruteForceWithDegenerateTriangles) {
  std::mt19937 rng(61);
  for (int trial = 0; trial < 4; ++trial) {
    const float extent = trial % 2 ? 40.0f : 4.0f;
    const TriangleSoup soup = random_soup(rng, 50 + 150 * trial, Vec3(0.0f), extent, trial < 2 ? 1.0f : 3.0f);
    const TriangleBvh bvh(soup.positions, soup.triangles);
    ASSERT_EQ(bvh.triangle_count(), soup.triangles.size());
    int near = 0, far = 0;
    for (int i = 0; i < 1000; ++i) {
      Vec3 q;
      if (i % 2) {  // near (or exactly on) a random triangle: many candidates at close distances
        const auto t = static_cast<std::uint32_t>(rng() % soup.triangles.size());
        float u = uniform01(rng), v = uniform01(rng);
        if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
        const Vec3 on = glm::vec3(corner(soup, t, 0) * double(1.0f - u - v) + corner(soup, t, 1) * double(u) +
                                  corner(soup, t, 2) * double(v));
        const float offset = i % 4 == 1 ? 0.0f : 0.2f;
        q = on + offset * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      } else {
        q = Vec3(uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent));
      }
      const BvhNearest hit = bvh.nearest(q);
      ASSERT_LT(hit.triangle, soup.triangles.size());
      const double truth = brute_distance(soup, q);
      const double tol = 1e-5 * (1.0 + extent);
      EXPECT_NEAR(std::sqrt(double(hit.distance_squared)), truth, tol) << "trial " << trial << " query " << i;
      // The point is on the reported triangle, at its weights, at the reported distance.
      const Vec3 w = hit.closest.weights;
      EXPECT_GE(std::min({w.x, w.y, w.z}), 0.0f);
      EXPECT_NEAR(w.x + w.y + w.z, 1.0f, 1e-5f);
      const glm::dvec3 at = corner(soup, hit.triangle, 0) * double(w.x) + corner(soup, hit.triangle, 1) * double(w.y) +
                            corner(soup, hit.triangle, 2) * double(w.z);
      EXPECT_LT(glm::length(at - glm::dvec3(hit.closest.point)), tol);
      EXPECT_NEAR(glm::length(glm::dvec3(hit.closest.point) - glm::dvec3(q)), truth, tol);
      (truth < 0.3 ? near : far)++;
    }
    EXPECT_GT(near, 300);  // both kinds of query really happen
    EXPECT_GT(far, 100);
  }
}

TEST(TriangleBvh, BoundedNearestFindsExactlyTheTrianglesWithinTheBound) {
  std::mt19937 rng(64);
  const TriangleSoup soup = random_soup(rng, 400, Vec3(0.0f), 30.0f, 2.0f);
  const TriangleBvh bvh(soup.positions, soup.triangles);
  int found = 0, none = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 q(uniform(rng, -20, 20), uniform(rng, -20, 20), uniform(rng, -20, 20));
    const float bound = uniform(rng, 0.0f, 4.0f);
    const double truth = brute_distance(soup, q);
    if (std::abs(truth - bound) < 1e-4) continue;  // too close to call in float
    const BvhNearest hit = bvh.nearest(q, bound * bound);
    if (truth < bound) {
      ASSERT_LT(hit.triangle, soup.triangles.size()) << i;
      EXPECT_NEAR(std::sqrt(double(hit.distance_squared)), truth, 1e-4) << i;
      EXPECT_EQ(hit.triangle, bvh.nearest(q).triangle) << i;  // the unbounded answer, when in reach
      ++found;
    } else {
      EXPECT_EQ(hit.triangle, std::numeric_limits<std::uint32_t>::max()) << i;
      ++none;
    }
  }
  EXPECT_GT(found, 300);
  EXPECT_GT(none, 300);
  // The bound is inclusive: a query exactly on a triangle is found with a zero bound.
  const Vec3 corner_point = soup.positions[soup.triangles[5].x];
  EXPECT_EQ(bvh.nearest(corner_point, 0.0f).distance_squared, 0.0f);
}

TEST(TriangleBvh, NearestOfAnEmptyTreeIsEmpty) {
  const TriangleBvh bvh;
  EXPECT_EQ(bvh.nearest(Vec3(1.0f)).triangle, std::numeric_limits<std::uint32_t>::max());
  const TriangleBvh built(std::span<const Vec3>{}, std::span<const glm::uvec3>{});
  EXPECT_EQ(built.nearest(Vec3(1.0f)).triangle, std::numeric_limits<std::uint32_t>::max());
  EXPECT_EQ(built.triangle_count(), 0u);
}

TEST(TriangleBvh, OneTriangleAndFewTrianglesAreFound) {
  // Trees that are a single leaf, or a root with fewer than four children.
  std::mt19937 rng(62);
  for (int n : {1, 2, 3, 4, 5, 7, 9}) {
    const TriangleSoup soup = random_soup(rng, n, Vec3(3.0f), 5.0f, 1.0f);
    const TriangleBvh bvh(soup.positions, soup.triangles);
    for (int i = 0; i < 100; ++i) {
      const Vec3 q(uniform(rng, -5, 10), uniform(rng, -5, 10), uniform(rng, -5, 10));
      EXPECT_NEAR(std::sqrt(double(bvh.nearest(q).distance_squared)), brute_distance(soup, q), 1e-4) << n;
    }
  }
}

TEST(TriangleBvh, BoxQueryEqualsBruteForce) {
  std::mt19937 rng(63);
  const TriangleSoup soup = random_soup(rng, 700, Vec3(0.0f), 30.0f, 2.0f);
  const TriangleBvh bvh(soup.positions, soup.triangles);
  int hits = 0, misses = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 c(uniform(rng, -20, 20), uniform(rng, -20, 20), uniform(rng, -20, 20));
    const Vec3 h(uniform(rng, 0, 4), uniform(rng, 0, 4), uniform(rng, 0, 4));
    const Aabb3 box{c - h, c + h};
    std::set<std::uint32_t> found, truth;
    bvh.query(box, [&](std::uint32_t t) { EXPECT_TRUE(found.insert(t).second) << "reported twice"; });
    for (std::uint32_t t = 0; t < soup.triangles.size(); ++t) {
      const Vec3 a = soup.positions[soup.triangles[t].x], b = soup.positions[soup.triangles[t].y],
                 d = soup.positions[soup.triangles[t].z];
      if (overlap(Aabb3{glm::min(glm::min(a, b), d), glm::max(glm::max(a, b), d)}, box)) truth.insert(t);
    }
    EXPECT_EQ(found, truth);
    (truth.empty() ? misses : hits)++;
  }
  EXPECT_GT(hits, 100);
  EXPECT_GT(misses, 30);
}

}  // namespace
}  // namespace collide
