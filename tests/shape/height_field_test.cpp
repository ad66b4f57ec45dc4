// HeightField: validation named by field, the documented sample / cell / triangle mapping, and
// its box query and ray casts against brute force (every triangle of every non-hole cell
// tested, with the same crossing test) on random fields with holes.
#include "support/test_util.hpp"

#include <collide/core/error.hpp>
#include <collide/shape/height_field.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::uniform;

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

std::string error_of(int sx, int sz, std::span<const float> h, Vec2 spacing, Vec3 origin = Vec3(0.0f),
                     std::span<const std::uint8_t> holes = {}) {
  try {
    (void)make_height_field(sx, sz, h, spacing, origin, holes);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(HeightField, InvalidInputIsNamedByField) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> h(12, 0.0f);
  EXPECT_EQ(error_of(4, 3, h, {1, 1}), "no error");
  EXPECT_EQ(error_of(1, 12, h, {1, 1}), "height field: samples_x 1 and samples_z 12: need at least 2 x 2");
  EXPECT_EQ(error_of(12, 1, h, {1, 1}), "height field: samples_x 12 and samples_z 1: need at least 2 x 2");
  EXPECT_EQ(error_of(4, 4, h, {1, 1}), "height field heights: 12 given, expected 16 (samples_x 4 * samples_z 4)");
  h[4 * 2 + 3] = nan;
  EXPECT_EQ(error_of(4, 3, h, {1, 1}), "height field height at row 2, column 3: not finite");
  h[4 * 2 + 3] = 0.0f;
  EXPECT_EQ(error_of(4, 3, h, {0, 1}), "height field spacing.x: must be finite and > 0 (got 0.000000)");
  EXPECT_EQ(error_of(4, 3, h, {1, -2}), "height field spacing.y: must be finite and > 0 (got -2.000000)");
  EXPECT_EQ(error_of(4, 3, h, {1, nan}), "height field spacing.y: must be finite and > 0 (got nan)");
  EXPECT_EQ(error_of(4, 3, h, {1, 1}, Vec3(0, nan, 0)), "height field origin: not finite");
  const std::vector<std::uint8_t> holes(5, 0);
  EXPECT_EQ(error_of(4, 3, h, {1, 1}, Vec3(0.0f), holes),
            "height field holes: 5 given, expected 0 or 6 (one per cell: (samples_x - 1) * (samples_z - 1))");
  EXPECT_EQ(error_of(4, 3, h, {3e38f, 1}), "height field: extent beyond float range (samples times spacing)");
  h[0] = -3e38f, h[1] = 3e38f;
  EXPECT_EQ(error_of(4, 3, h, {1, 1}), "height field: heights span more than float range");
  // More triangles than feature ids can name: refused from the counts, before any height is read.
  EXPECT_EQ(error_of(20000, 20000, h, {1, 1}).substr(0, 45), "height field: 799920002 triangles, more than ");
}

TEST(HeightField, SamplesCellsAndTrianglesAreNumberedAsDocumented) {
  // 3 x 2 samples: heights 10 * column + row.
  const std::vector<float> h{0, 10, 20, 1, 11, 21};
  const HeightField f = make_height_field(3, 2, h, {2.0f, 3.0f}, Vec3(100, 5, -7));
  EXPECT_EQ(f.triangle_count(), 4u);
  EXPECT_EQ(f.height(2, 1), 21.0f);
  // Sample (i, j) at origin + (i * spacing.x, h, j * spacing.y).
  EXPECT_EQ(f.origin + f.grid_point(2, 1), Vec3(104, 26, -4));
  // Cell 1 (i = 1, j = 0): triangle 2 = (p00, p01, p11), triangle 3 = (p00, p11, p10).
  const Triangle t2 = f.triangle(2), t3 = f.triangle(3);
  EXPECT_EQ(t2.vertices[0], Vec3(102, 15, -7));
  EXPECT_EQ(t2.vertices[1], Vec3(102, 16, -4));
  EXPECT_EQ(t2.vertices[2], Vec3(104, 26, -4));
  EXPECT_EQ(t3.vertices[0], Vec3(102, 15, -7));
  EXPECT_EQ(t3.vertices[1], Vec3(104, 26, -4));
  EXPECT_EQ(t3.vertices[2], Vec3(104, 25, -7));
  // Both wound counter-clockwise seen from above: normals up.
  for (std::uint32_t t = 0; t < 4; ++t) {
    const Triangle tri = f.triangle(t);
    EXPECT_GT(triangle_normal(tri.vertices[0], tri.vertices[1], tri.vertices[2]).y, 0.0f) << t;
  }
  // Bounds.
  const Aabb3 box = compute_aabb(f, Transform3{});
  EXPECT_EQ(box.min, Vec3(100, 5, -7));
  EXPECT_EQ(box.max, Vec3(104, 26, -4));
}

/// A random field: samples_x by samples_z heights from a few waves plus noise (some steep), a
/// fraction `hole_rate` of cells holes.
HeightField random_field(std::mt19937& rng, int sx, int sz, Vec2 spacing, Vec3 origin, float hole_rate) {
  std::vector<float> h(static_cast<std::size_t>(sx) * sz);
  const float phase = uniform(rng, 0, 6);
  for (int j = 0; j < sz; ++j) {
    for (int i = 0; i < sx; ++i) {
      h[static_cast<std::size_t>(j) * sx + i] =
          3.0f * std::sin(0.3f * i + phase) * std::cos(0.2f * j) + uniform(rng, -0.5f, 0.5f) + (i % 13 == 0 ? 4.0f : 0.0f);
    }
  }
  std::vector<std::uint8_t> holes(static_cast<std::size_t>(sx - 1) * (sz - 1));
  for (auto& x : holes) x = uniform(rng, 0, 1) < hole_rate ? 1 : 0;
  return make_height_field(sx, sz, h, spacing, origin, holes);
}

/// Every crossing by testing each triangle of each non-hole cell, in grid space (as the field).
std::map<std::uint32_t, float> every_crossing(const HeightField& f, const Ray3& local, float max_fraction = 1.0f) {
  const Ray3 grid{local.origin - f.origin, local.translation};
  std::map<std::uint32_t, float> out;
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
    if (f.is_hole(t / 2)) continue;
    const std::array<Vec3, 3> p = f.grid_corners(t);
    const float x = ray_triangle_fraction(grid, p[0], p[1], p[2], max_fraction);
    if (x >= 0.0f) out[t] = x;
  }
  return out;
}

/// Rays of several kinds over a field spanning `size` from `origin`.
Ray3 random_ray(std::mt19937& rng, const HeightField& f, int kind) {
  const Vec3 size(static_cast<float>(f.cells_x()) * f.spacing.x, 0, static_cast<float>(f.cells_z()) * f.spacing.y);
  auto over = [&](float margin) {
    return f.origin + Vec3(uniform(rng, -margin, size.x + margin), 0, uniform(rng, -margin, size.z + margin));
  };
  switch (kind) {
    case 0: {  // from above, down at an angle
      const Vec3 o = over(5) + Vec3(0, uniform(rng, 8, 20), 0);
      return {o, over(5) + Vec3(0, uniform(rng, -10, 0), 0) - o};
    }
    case 1: {  // nearly horizontal, long, grazing the hills
      const Vec3 o = over(10) + Vec3(0, uniform(rng, -4, 6), 0);
      return {o, over(10) + Vec3(0, uniform(rng, -4, 6), 0) - o};
    }
    case 2: {  // straight down, sometimes exactly over a grid line
      Vec3 o = over(1) + Vec3(0, 15, 0);
      if (rng() % 3 == 0) o.x = f.origin.x + f.spacing.x * static_cast<float>(rng() % f.samples_x);
      return {o, Vec3(0, -30, 0)};
    }
    case 3: {  // exactly along a row or a column (no movement on one axis)
      Vec3 o = over(2) + Vec3(0, uniform(rng, -2, 4), 0);
      Vec3 d(uniform(rng, -30, 30), uniform(rng, -3, 3), 0);
      if (rng() % 2) std::swap(d.x, d.z);
      return {o, d};
    }
    default: {  // short, from anywhere (often starting under the surface, or ending before it)
      const Vec3 o = over(3) + Vec3(0, uniform(rng, -6, 10), 0);
      return {o, Vec3(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3))};
    }
  }
}

TEST(HeightField, RayCastEqualsEveryTriangleTested) {
  std::mt19937 rng(90);
  for (int trial = 0; trial < 3; ++trial) {
    // Sizes that are not multiples of the block size; far from the origin in trial 2.
    const int sx = trial == 0 ? 2 + static_cast<int>(rng() % 3) : 37 + trial * 11, sz = trial == 0 ? 2 : 23 + trial * 17;
    const Vec3 origin = trial == 2 ? Vec3(5000, -20, -3000) : Vec3(-3, 1, 2);
    const HeightField f = random_field(rng, sx, sz, {uniform(rng, 0.5f, 1.5f), uniform(rng, 0.5f, 1.5f)}, origin, trial == 0 ? 0.0f : 0.1f);
    std::array<int, 5> hits{}, misses{};
    int multiple = 0;
    for (int i = 0; i < 5000; ++i) {
      const int kind = i % 5;
      const Ray3 ray = random_ray(rng, f, kind);
      const std::map<std::uint32_t, float> truth = every_crossing(f, ray);
      std::map<std::uint32_t, float> all;
      f.ray_cast(ray, [&](std::uint32_t t, float x) {
        EXPECT_TRUE(all.emplace(t, x).second) << "triangle " << t << " reported twice";
        return 1.0f;
      });
      ASSERT_EQ(all, truth) << "trial " << trial << " ray " << i << " kind " << kind;
      const TriangleRayHit hit = f.ray_cast(ray);
      if (truth.empty()) {
        EXPECT_EQ(hit.triangle, kNone);
        ++misses[kind];
        continue;
      }
      float nearest = 1.0f;
      for (const auto& [t, x] : truth) nearest = std::min(nearest, x);
      ASSERT_NE(hit.triangle, kNone);
      EXPECT_EQ(hit.fraction, nearest);
      EXPECT_EQ(truth.at(hit.triangle), nearest);
      EXPECT_GT(hit.normal.y, 0.0f);  // the geometric normal of a height field triangle is up
      // The closest hit by clipping in the callback, too.
      float clipped = 1.0f;
      f.ray_cast(ray, [&](std::uint32_t, float x) {
        EXPECT_LE(x, clipped);
        return clipped = x;
      });
      EXPECT_EQ(clipped, nearest);
      ++hits[kind];
      multiple += truth.size() > 1;
    }
    for (int kind = 0; kind < 5; ++kind) {
      if (trial > 0) EXPECT_GT(hits[kind], 40) << trial << " kind " << kind;
      if (kind != 0 || trial == 0) EXPECT_GT(misses[kind], 50) << trial << " kind " << kind;
    }
    if (trial > 0) EXPECT_GT(multiple, 300) << trial;
  }
}

// Rays whose xz path runs exactly along a grid line, or crosses grid vertices exactly: the
// triangles on both sides touch the path, and each crossing (at an edge or vertex) is reported.
TEST(HeightField, RaysAlongGridLinesAndThroughGridVerticesFindEveryTriangleTouched) {
  std::mt19937 rng(93);
  const HeightField f = random_field(rng, 26, 21, {1.0f, 1.0f}, Vec3(-7, 0, 4), 0.15f);
  int along = 0, diagonal = 0, vertical = 0, hits = 0, several = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 at(static_cast<float>(static_cast<int>(rng() % 26)), 0, static_cast<float>(static_cast<int>(rng() % 21)));
    Ray3 ray;
    if (i % 3 == 0) {  // along a row or a column line
      ray = {f.origin + at + Vec3(0, uniform(rng, -3, 5), 0), Vec3(uniform(rng, -25, 25), uniform(rng, -2, 2), 0)};
      if (rng() % 2) std::swap(ray.translation.x, ray.translation.z);
      ++along;
    } else if (i % 3 == 1) {  // diagonally through grid vertices (integer steps)
      const float sx = rng() % 2 ? 1.0f : -1.0f, sz = rng() % 2 ? 1.0f : -1.0f, n = static_cast<float>(4 + rng() % 12);
      ray = {f.origin + at + Vec3(0, uniform(rng, -3, 5), 0), Vec3(sx * n, uniform(rng, -3, 3), sz * n)};
      ++diagonal;
    } else {  // straight down onto a grid vertex
      ray = {f.origin + at + Vec3(0, 10, 0), Vec3(0, -20, 0)};
      ++vertical;
    }
    std::map<std::uint32_t, float> all;
    f.ray_cast(ray, [&](std::uint32_t t, float x) { return all.emplace(t, x), 1.0f; });
    ASSERT_EQ(all, every_crossing(f, ray)) << i;
    hits += !all.empty();
    several += all.size() > 2;  // an edge or vertex crossing is several triangles at once
  }
  EXPECT_EQ(along + diagonal + vertical, 3000);
  EXPECT_GT(hits, 1500);
  EXPECT_GT(several, 500);
}

TEST(HeightField, RayCastRespectsMaxFractionAndStop) {
  std::mt19937 rng(91);
  const HeightField f = random_field(rng, 30, 30, {1, 1}, Vec3(0.0f), 0.05f);
  int tested = 0;
  for (int i = 0; i < 2000; ++i) {
    const Ray3 ray = random_ray(rng, f, 1);
    const std::map<std::uint32_t, float> truth = every_crossing(f, ray);
    if (truth.size() < 2) continue;
    ++tested;
    int calls = 0;
    f.ray_cast(ray, [&](std::uint32_t, float) { return ++calls, 0.0f; });
    EXPECT_EQ(calls, 1);
    std::map<std::uint32_t, float> within;
    f.ray_cast(ray, [&](std::uint32_t t, float x) { return within.emplace(t, x), 1.0f; }, 0.5f);
    EXPECT_EQ(within, every_crossing(f, ray, 0.5f));
  }
  EXPECT_GT(tested, 200);
  // Degenerate rays: nothing.
  for (const Ray3& ray : {Ray3{Vec3(5, 10, 5), Vec3(0.0f)}, Ray3{Vec3(5, std::numeric_limits<float>::quiet_NaN(), 5), Vec3(0, -20, 0)}}) {
    EXPECT_EQ(f.ray_cast(ray).triangle, kNone);
  }
}

TEST(HeightField, QueryFindsExactlyTheTrianglesWhoseBoxesOverlap) {
  std::mt19937 rng(92);
  const HeightField f = random_field(rng, 41, 29, {0.8f, 1.2f}, Vec3(100, 0, -50), 0.1f);
  int nonempty = 0, empty = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 c = f.origin + Vec3(uniform(rng, -3, 35), uniform(rng, -6, 8), uniform(rng, -3, 37));
    const Vec3 h(uniform(rng, 0, 3), uniform(rng, 0, 2), uniform(rng, 0, 3));
    Aabb3 box{c - h, c + h};
    if (i % 10 == 0) {  // on grid lines exactly
      box.min.x = f.origin.x + 0.8f * 5.0f;
      box.max.z = f.origin.z + 1.2f * 7.0f;
    }
    if (i % 10 == 5) {  // the other sides on grid lines, anywhere in the grid
      box.max.x = f.origin.x + 0.8f * static_cast<float>(i % 41);
      box.min.z = f.origin.z + 1.2f * static_cast<float>(i % 29);
      box.min.x = std::min(box.min.x, box.max.x);
      box.max.z = std::max(box.max.z, box.min.z);
    }
    std::set<std::uint32_t> found, truth;
    f.query(box, [&](std::uint32_t t) {
      EXPECT_TRUE(found.insert(t).second);
      return true;
    });
    for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
      if (f.is_hole(t / 2)) continue;
      // In grid space, as the field decides (local and grid space differ by the origin's rounding).
      const std::array<Vec3, 3> g = f.grid_corners(t);
      const Aabb3 gb{glm::min(glm::min(g[0], g[1]), g[2]), glm::max(glm::max(g[0], g[1]), g[2])};
      if (overlap(gb, Aabb3{box.min - f.origin, box.max - f.origin})) truth.insert(t);
    }
    EXPECT_EQ(found, truth) << i;
    (truth.empty() ? empty : nonempty)++;
  }
  EXPECT_GT(nonempty, 100);
  EXPECT_GT(empty, 50);
  // Stopping: false ends the query.
  int calls = 0;
  f.query(Aabb3{f.origin - Vec3(1.0f), f.origin + Vec3(40.0f)}, [&](std::uint32_t) { return ++calls < 3; });
  EXPECT_EQ(calls, 3);
}

TEST(HeightField, ForEachTriangleGivesQuerysTrianglesPlacedInTheWorld) {
  // for_each_triangle on a turned and moved field: the triangles the field's own query finds
  // for the box taken into the field's frame, each once, in the query's order, with its
  // corners placed by the transform (a cell's two triangles share two transformed corners; the
  // boxes cut between them too, so one of a cell's triangles is often visited alone).
  std::mt19937 rng(93);
  const HeightField f = random_field(rng, 23, 19, {0.7f, 1.1f}, Vec3(-4, 1, 3), 0.1f);
  const Transform3 xf = Transform3::from_axis_angle({30.0f, -2.0f, 12.0f}, glm::normalize(Vec3{0.3f, 1.0f, -0.2f}), 0.8f);
  int odd_alone = 0, pairs = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 c = transform_point(xf, f.origin + Vec3(uniform(rng, -2, 17), uniform(rng, -5, 6), uniform(rng, -2, 21)));
    const Vec3 h(uniform(rng, 0, 2.5f), uniform(rng, 0, 2), uniform(rng, 0, 2.5f));
    const Aabb3 box{c - h, c + h};
    std::vector<std::uint32_t> expected;
    f.query(transform_aabb(box, inv_mul(xf, Transform3{})), [&](std::uint32_t t) {
      expected.push_back(t);
      return true;
    });
    std::vector<std::uint32_t> visited;
    for_each_triangle(f, xf, box, [&](std::uint32_t t, const std::array<Vec3, 3>& w) {
      visited.push_back(t);
      const Triangle local = f.triangle(t);
      for (int k = 0; k < 3; ++k) {
        const Vec3 want = transform_point(xf, local.vertices[k]);
        EXPECT_LT(glm::length(w[k] - want), 1e-4f) << "triangle " << t << " corner " << k;
      }
      return true;
    });
    EXPECT_EQ(visited, expected) << i;
    for (std::size_t k = 0; k < visited.size(); ++k) {
      if (visited[k] % 2 == 0) continue;
      (k > 0 && visited[k - 1] + 1 == visited[k] ? pairs : odd_alone)++;
    }
  }
  EXPECT_GT(pairs, 100);
  EXPECT_GT(odd_alone, 10);
}

}  // namespace
}  // namespace collide
