// 3D ray casts against triangles, meshes and height fields, world space in and out, checked
// against brute force in double precision (every triangle placed in the world and crossed by a
// plane / edge-side test, tests/support/brute_triangle.hpp) on the shared level meshes and random
// height fields under random rigid transforms; closed-mesh edge cases; far-from-origin meshes;
// the rules for rays starting on a surface and inside a closed mesh.

#include <collide/ccd/raycast.hpp>
#include <collide/io/obj.hpp>

#include "support/brute_ray_mesh.hpp"
#include "support/brute_triangle.hpp"
#include "support/bitwise_equal.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <vector>

namespace collide {
namespace {

using test::uniform;

const std::string kMeshes = std::string(COLLIDE_DATA_DIR) + "/meshes/";

using test::place;
using test::world_triangles;
using test::WorldTriangle;
using Truth = test::RayTruth;

std::vector<WorldTriangle> world_triangles(const HeightField& f, const Transform3& xf) {
  std::vector<WorldTriangle> out(f.triangle_count());
  for (std::uint32_t t = 0; t < f.triangle_count(); ++t) {
    const std::array<Vec3, 3> g = f.grid_corners(t);
    for (int k = 0; k < 3; ++k) out[t][k] = place(xf, glm::dvec3(f.origin) + glm::dvec3(g[k]));
  }
  return out;
}

/// Distance from a point to a world triangle (double).
double distance_to(const WorldTriangle& t, Vec3 p) {
  const glm::dvec3 q(p);
  return glm::length(test::brute_closest_on_triangle(q, t[0], t[1], t[2]) - q);
}

/// Checks one hit against the truth and the hit's own consistency; returns whether it hit.
bool check(const RayHit3& hit, const Truth& truth, const std::vector<WorldTriangle>& tris, const Ray3& ray, double eps,
           const char* what, int i) {
  if (!hit.hit) {
    EXPECT_EQ(truth.clear, std::numeric_limits<double>::infinity()) << what << " ray " << i << ": missed a clear crossing at " << truth.clear;
    return false;
  }
  EXPECT_GE(hit.fraction, truth.possible) << what << " ray " << i;
  EXPECT_LE(hit.fraction, truth.clear) << what << " ray " << i;
  EXPECT_LT(hit.sub_shape, tris.size());
  EXPECT_NEAR(length(hit.normal), 1.0f, 1e-5f);
  EXPECT_LE(dot(hit.normal, ray.translation), 0.0f) << "the normal faces the ray's origin";
  EXPECT_VEC3_NEAR(hit.point, ray.at(hit.fraction), 0.0f);
  EXPECT_LT(distance_to(tris[hit.sub_shape], hit.point), 4.0 * eps) << what << " ray " << i << ": the point is on the triangle reported";
  // The normal is the triangle's (up to its side).
  const WorldTriangle& w = tris[hit.sub_shape];
  const glm::dvec3 n = glm::normalize(glm::cross(w[1] - w[0], w[2] - w[0]));
  EXPECT_NEAR(std::abs(glm::dot(n, glm::dvec3(hit.normal))), 1.0, 1e-4);
  return true;
}

/// A random ray around `box`: from anywhere near it, aimed at a random point of a random
/// triangle every other time.
Ray3 random_ray(std::mt19937& rng, const Aabb3& box, const std::vector<WorldTriangle>& tris) {
  const Vec3 size = box.size(), c = box.center();
  auto near_box = [&] { return c + Vec3(uniform(rng, -0.7f, 0.7f), uniform(rng, -0.7f, 0.7f), uniform(rng, -0.7f, 0.7f)) * size; };
  const Vec3 o = near_box();
  if (rng() % 2) {
    const WorldTriangle& t = tris[rng() % tris.size()];
    double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 target(t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]));
    return {o, (target - o) * uniform(rng, 0.5f, 1.5f)};
  }
  return {o, near_box() - o};
}

/// raycast_fraction's promise: raycast's hit and fraction, bit for bit.
void expect_fraction_is_raycasts(const RayFraction& f, const RayHit3& full, int ray) {
  EXPECT_TRUE(test::bitwise_equal(f, full)) << "ray " << ray << ": " << f.fraction << " against " << full.fraction;
}

TEST(MeshRaycast, SharedMeshesAgreeWithBruteForceUnderRandomTransforms) {
  std::mt19937 rng(100);
  for (const char* file : {"recast/dungeon.obj", "recast/undulating.obj", "fcl/env.obj", "fcl/rob.obj"}) {
    const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + file);
    for (int placement = 0; placement < 3; ++placement) {
      // Identity (undulating.obj stays at 5000), a random rigid motion, one far away.
      Transform3 xf;
      if (placement == 1) xf = {test::random_point3(rng, 100), test::random_rotation(rng)};
      if (placement == 2) xf = {Vec3(2e4f, -1e4f, 3e4f), test::random_rotation(rng)};
      const std::vector<WorldTriangle> tris = world_triangles(mesh, xf);
      const Aabb3 box = compute_aabb(mesh, xf);
      // Rounding of the world coordinates: float at the farthest coordinate, a few ulps.
      const double scale = std::max(max_abs(box.min), max_abs(box.max));
      const double eps = 1e-6 * scale, eps_fraction = 1e-5;
      int hits = 0, misses = 0;
      const int rays = mesh.triangle_count() > 5000 ? 300 : 600;
      for (int i = 0; i < rays; ++i) {
        const Ray3 ray = random_ray(rng, box, tris);
        const Truth truth = test::brute_ray_truth(tris, ray, eps, eps_fraction);
        (check(raycast(mesh, xf, ray), truth, tris, ray, eps, file, i) ? hits : misses)++;
        expect_fraction_is_raycasts(raycast_fraction(mesh, xf, ray), raycast(mesh, xf, ray), i);
        // Every crossing by the callback: at least the clear ones, at most the possible ones.
        std::size_t count = 0;
        float nearest = 2.0f;
        raycast(mesh, xf, ray, [&](const RayHit3& h) {
          EXPECT_TRUE(h.hit);
          EXPECT_LE(dot(h.normal, ray.translation), 0.0f);
          ++count;
          nearest = std::min(nearest, h.fraction);
          return 1.0f;
        });
        EXPECT_GE(count, truth.clear_count) << file << " ray " << i;
        EXPECT_LE(count, truth.possible_count) << file << " ray " << i;
        if (count > 0) EXPECT_EQ(nearest, raycast(mesh, xf, ray).fraction);
      }
      EXPECT_GT(hits, rays / 4) << file << " placement " << placement;
      EXPECT_GT(misses, rays / 20) << file << " placement " << placement;
    }
  }
}

TEST(MeshRaycast, HeightFieldsAgreeWithBruteForceUnderRandomTransforms) {
  std::mt19937 rng(101);
  for (int trial = 0; trial < 4; ++trial) {
    const int sx = 20 + static_cast<int>(rng() % 30), sz = 15 + static_cast<int>(rng() % 30);
    std::vector<float> h(static_cast<std::size_t>(sx) * sz);
    for (float& x : h) x = uniform(rng, -2, 2);
    std::vector<std::uint8_t> holes(static_cast<std::size_t>(sx - 1) * (sz - 1));
    for (auto& x : holes) x = rng() % 8 == 0;
    const Vec3 origin = trial == 3 ? Vec3(4000, 10, 5000) : Vec3(uniform(rng, -10, 0), 0, uniform(rng, -10, 0));
    const HeightField field = make_height_field(sx, sz, h, {uniform(rng, 0.5f, 2), uniform(rng, 0.5f, 2)}, origin, holes);
    const Transform3 xf = trial % 2 ? Transform3{test::random_point3(rng, 50), test::random_rotation(rng)} : Transform3{};
    const std::vector<WorldTriangle> tris = world_triangles(field, xf);
    std::vector<bool> hole(tris.size());
    for (std::uint32_t t = 0; t < tris.size(); ++t) hole[t] = field.is_hole(t / 2);
    const Aabb3 box = compute_aabb(field, xf);
    const double scale = std::max(max_abs(box.min), max_abs(box.max));
    const double eps = 1e-6 * scale, eps_fraction = 1e-5;
    int hits = 0, misses = 0;
    for (int i = 0; i < 1000; ++i) {
      const Ray3 ray = random_ray(rng, box, tris);
      const Truth truth = test::brute_ray_truth(tris, ray, eps, eps_fraction, &hole);
      (check(raycast(field, xf, ray), truth, tris, ray, eps, "height field", i) ? hits : misses)++;
      expect_fraction_is_raycasts(raycast_fraction(field, xf, ray), raycast(field, xf, ray), i);
      std::size_t count = 0;
      raycast(field, xf, ray, [&](const RayHit3& hit) {
        EXPECT_FALSE(field.is_hole(hit.sub_shape / 2));
        return ++count, 1.0f;
      });
      EXPECT_GE(count, truth.clear_count) << i;
      EXPECT_LE(count, truth.possible_count) << i;
    }
    EXPECT_GT(hits, 200) << trial;
    EXPECT_GT(misses, 100) << trial;
  }
}

TEST(MeshRaycast, TriangleAgreesWithBruteForce) {
  std::mt19937 rng(102);
  int hits = 0, misses = 0;
  for (int i = 0; i < 3000; ++i) {
    const Triangle tri = make_triangle(test::random_point3(rng, 2), test::random_point3(rng, 2), test::random_point3(rng, 2));
    const Transform3 xf{test::random_point3(rng, 20), test::random_rotation(rng)};
    WorldTriangle w;
    for (int k = 0; k < 3; ++k) w[k] = place(xf, glm::dvec3(tri.vertices[k]));
    const std::vector<WorldTriangle> tris{w};
    const Aabb3 box = compute_aabb(tri, xf);
    const Ray3 ray = random_ray(rng, fatten(box, 1.0f), tris);
    const double eps = 1e-5 * 25.0, eps_fraction = 1e-5;
    (check(raycast(tri, xf, ray), test::brute_ray_truth(tris, ray, eps, eps_fraction), tris, ray, eps, "triangle", i) ? hits : misses)++;
    expect_fraction_is_raycasts(raycast_fraction(tri, xf, ray), raycast(tri, xf, ray), i);
  }
  EXPECT_GT(hits, 600);
  EXPECT_GT(misses, 500);
}

/// The cube [-n, n]^3 as a closed mesh: each face an n x n grid of squares of side 2, split
/// along alternating diagonals, wound outwards. Integer corners.
TriangleMesh closed_cube(int n) {
  std::vector<Vec3> v;
  std::vector<glm::uvec3> tris;
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {-1, 1}) {
      const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
      const auto base = static_cast<unsigned>(v.size());
      for (int i = 0; i <= n; ++i) {
        for (int j = 0; j <= n; ++j) {
          Vec3 p(0.0f);
          p[axis] = static_cast<float>(side * n);
          p[u_axis] = static_cast<float>(2 * i - n);
          p[v_axis] = static_cast<float>(2 * j - n);
          v.push_back(p);
        }
      }
      auto id = [&](int i, int j) { return base + static_cast<unsigned>(i * (n + 1) + j); };
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
          const std::array<glm::uvec3, 2> two = (i + j) % 2 ? std::array<glm::uvec3, 2>{glm::uvec3{a, b, c}, glm::uvec3{a, c, d}}
                                                            : std::array<glm::uvec3, 2>{glm::uvec3{a, b, d}, glm::uvec3{b, c, d}};
          for (glm::uvec3 t : two) tris.push_back(side > 0 ? t : glm::uvec3{t.x, t.z, t.y});
        }
      }
    }
  }
  return make_triangle_mesh(v, tris);
}

// Rays aimed at a vertex or an edge point of a closed mesh, from outside, going on into it: they
// must hit there, whatever the placement (the local ray is then only near the edge, and the
// watertight test still lets it through no gap).
TEST(MeshRaycast, RaysIntoAClosedMeshThroughEdgesAndVerticesHit) {
  std::mt19937 rng(103);
  const TriangleMesh cube = closed_cube(6);
  for (int placement = 0; placement < 3; ++placement) {
    const Transform3 xf = placement == 0 ? Transform3{} : Transform3{test::random_point3(rng, placement == 1 ? 10 : 5000), test::random_rotation(rng)};
    int tested = 0;
    for (int i = 0; i < 3000; ++i) {
      const std::uint32_t t = static_cast<std::uint32_t>(rng() % cube.triangle_count());
      const int k = static_cast<int>(rng() % 3);
      const Vec3 a = cube.origin + cube.corner(t, k), b = cube.origin + cube.corner(t, (k + 1) % 3);
      const Vec3 target_local = a + (b - a) * (0.25f * static_cast<float>(rng() % 4));
      Vec3 from_local(uniform(rng, -10, 10), uniform(rng, -10, 10), uniform(rng, -10, 10));
      from_local[rng() % 3] = rng() % 2 ? 15.0f : -15.0f;
      // Into the solid by a clear margin beyond the target (not along a face, not grazing).
      const glm::dvec3 beyond = glm::dvec3(target_local) + 0.05 * glm::dvec3(target_local - from_local);
      if (std::max({std::abs(beyond.x), std::abs(beyond.y), std::abs(beyond.z)}) > 6.0 - 1e-2) continue;
      ++tested;
      const Vec3 from = transform_point(xf, from_local), target = transform_point(xf, target_local);
      const Ray3 ray{from, 2.0f * (target - from)};
      const RayHit3 hit = raycast(cube, xf, ray);
      ASSERT_TRUE(hit.hit) << "placement " << placement << " ray " << i;
      EXPECT_NEAR(hit.fraction, 0.5f, placement == 2 ? 1e-3f : 1e-5f);
      EXPECT_LE(dot(hit.normal, ray.translation), 0.0f);
    }
    EXPECT_GT(tested, 500);
  }
}

TEST(MeshRaycast, RaysStartingOnOrInsideASurface) {
  const TriangleMesh cube = closed_cube(2);  // [-2, 2]^3
  const Transform3 id;
  // 1. From the centre: the inside of the closed mesh is hit (two-sided), normal facing back.
  const RayHit3 inside = raycast(cube, id, Ray3{Vec3(0.3f, 0.1f, 0.2f), Vec3(10, 0, 0)});
  ASSERT_TRUE(inside.hit);
  EXPECT_NEAR(inside.fraction, 0.17f, 1e-6f);
  EXPECT_EQ(inside.normal, Vec3(-1, 0, 0));
  // 2. From exactly on a face, outwards: nothing (the surface it starts on does not count).
  EXPECT_FALSE(raycast(cube, id, Ray3{Vec3(2, 0.5f, 0.5f), Vec3(5, 0, 0)}).hit);
  // 3. From exactly on a face, inwards: the opposite face, not the one it starts on.
  const RayHit3 across = raycast(cube, id, Ray3{Vec3(2, 0.5f, 0.5f), Vec3(-8, 0, 0)});
  ASSERT_TRUE(across.hit);
  EXPECT_EQ(across.fraction, 0.5f);
  EXPECT_EQ(across.normal, Vec3(1, 0, 0));
  // 4. A reflected laser: cast again from the hit point, it does not find the face it left.
  const Ray3 in{Vec3(5, 0.5f, 0.5f), Vec3(-6, 0, 0)};
  const RayHit3 first = raycast(cube, id, in);
  ASSERT_TRUE(first.hit);
  EXPECT_EQ(first.point, Vec3(2, 0.5f, 0.5f));
  EXPECT_FALSE(raycast(cube, id, Ray3{first.point, Vec3(6, 0, 0)}).hit);
  // 5. Ending exactly on a face: a hit at fraction 1.
  EXPECT_EQ(raycast(cube, id, Ray3{Vec3(5, 0.5f, 0.5f), Vec3(-3, 0, 0)}).fraction, 1.0f);
  // 6. Zero length, NaN: nothing.
  EXPECT_FALSE(raycast(cube, id, Ray3{Vec3(5, 0, 0), Vec3(0.0f)}).hit);
  EXPECT_FALSE(raycast(cube, id, Ray3{Vec3(std::numeric_limits<float>::quiet_NaN()), Vec3(1.0f)}).hit);
  // 7. The same for a single triangle and a height field: starting on them, no hit.
  const Triangle tri = make_triangle({-1, 0, -1}, {0, 0, 1}, {1, 0, -1});
  EXPECT_FALSE(raycast(tri, id, Ray3{Vec3(0, 0, 0), Vec3(0, 1, 0)}).hit);
  EXPECT_FALSE(raycast(tri, id, Ray3{Vec3(0, 0, 0), Vec3(0, -1, 0)}).hit);
  EXPECT_EQ(raycast(tri, id, Ray3{Vec3(0, 1, 0), Vec3(0, -2, 0)}).normal, Vec3(0, 1, 0));  // facing the ray
  EXPECT_EQ(raycast(tri, id, Ray3{Vec3(0, -1, 0), Vec3(0, 2, 0)}).normal, Vec3(0, -1, 0));
  const std::vector<float> flat(9, 0.0f);
  const HeightField field = make_height_field(3, 3, flat, {1, 1});
  EXPECT_FALSE(raycast(field, id, Ray3{Vec3(0.5f, 0, 0.5f), Vec3(0, 1, 0)}).hit);
  const RayHit3 down = raycast(field, id, Ray3{Vec3(0.5f, 1, 0.5f), Vec3(0, -2, 0)});
  ASSERT_TRUE(down.hit);
  EXPECT_EQ(down.normal, Vec3(0, 1, 0));
  EXPECT_EQ(down.fraction, 0.5f);
}

TEST(MeshRaycast, CallbacksClipAndStopInWorldSpace) {
  const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + "recast/dungeon.obj");
  std::mt19937 rng(104);
  const Transform3 xf{Vec3(100, -5, 30), test::random_rotation(rng)};
  const Aabb3 box = compute_aabb(mesh, xf);
  int several = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 o = box.center() + Vec3(uniform(rng, -40, 40), uniform(rng, -20, 20), uniform(rng, -40, 40));
    const Ray3 ray{o, Vec3(uniform(rng, -80, 80), uniform(rng, -40, 40), uniform(rng, -80, 80))};
    std::vector<float> all;
    raycast(mesh, xf, ray, [&](const RayHit3& h) { return all.push_back(h.fraction), 1.0f; });
    if (all.size() < 2) continue;
    ++several;
    int calls = 0;
    raycast(mesh, xf, ray, [&](const RayHit3&) { return ++calls, 0.0f; });
    EXPECT_EQ(calls, 1);
    float clipped = 1.0f;
    RayHit3 last;
    raycast(mesh, xf, ray, [&](const RayHit3& h) {
      EXPECT_LE(h.fraction, clipped);
      last = h;
      return clipped = h.fraction;
    });
    const RayHit3 closest = raycast(mesh, xf, ray);
    EXPECT_EQ(clipped, closest.fraction);
    EXPECT_EQ(*std::min_element(all.begin(), all.end()), closest.fraction);
  }
  EXPECT_GT(several, 20);
}

}  // namespace
}  // namespace collide
