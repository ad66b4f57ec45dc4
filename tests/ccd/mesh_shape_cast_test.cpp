// Shape casts of convex shapes against TriangleMesh and HeightField: the BVH / cell sweep
// against the loop over every triangle with the convex-triangle cast, on random soups and on
// dungeon.obj; a height field against the equivalent mesh; a box dropped on flat ground.

#include <collide/ccd/shape_cast.hpp>
#include <collide/io/obj.hpp>

#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace collide {
namespace {

const std::string kMeshes = std::string(COLLIDE_DATA_DIR) + "/meshes/";

Triangle world_triangle(const TriangleMesh& mesh, std::uint32_t t) {
  return Triangle{{mesh.origin + mesh.corner(t, 0), mesh.origin + mesh.corner(t, 1), mesh.origin + mesh.corner(t, 2)}};
}

/// Earliest hit over all triangles by the convex-triangle cast.
ShapeCastResult3 brute_cast(const Shape3D& shape, const Transform3& xa, Vec3 va, const TriangleMesh& mesh,
                            const Transform3& xm, Vec3 vm) {
  ShapeCastResult3 best;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const ShapeCastResult3 r = std::visit(
        [&](const auto& a) { return shape_cast(a, xa, va, world_triangle(mesh, t), xm, vm); }, shape);
    if (r.hit && (!best.hit || r.fraction < best.fraction)) best = r;
  }
  return best;
}

void expect_same(const ShapeCastResult3& r, const ShapeCastResult3& b, int iter) {
  EXPECT_EQ(r.hit, b.hit) << iter;
  if (r.hit && b.hit) {
    EXPECT_NEAR(r.fraction, b.fraction, 1e-4f) << iter;
    EXPECT_TRUE(std::isfinite(r.point.x) && std::isfinite(r.normal.x));
  }
}

TEST(MeshShapeCast, RandomSoupAgainstBruteForce) {
  std::mt19937 rng(31);
  int hits = 0, misses = 0;
  for (int mesh_iter = 0; mesh_iter < 4; ++mesh_iter) {
    std::vector<Vec3> vertices;
    std::vector<glm::uvec3> triangles;
    for (unsigned t = 0; t < 250; ++t) {
      const Vec3 c = test::random_point3(rng, 6.0f);
      for (int k = 0; k < 3; ++k) vertices.push_back(c + test::random_point3(rng, 0.8f));
      triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
    const Transform3 xm = test::random_transform3(rng, 3.0f);
    for (int iter = 0; iter < 100; ++iter) {
      const Shape3D shape = test::random_shape3(rng, 0.4f);
      const Transform3 xa{transform_point(xm, test::random_point3(rng, 7.0f)), test::random_rotation(rng)};
      const Vec3 va = test::random_point3(rng, 6.0f);
      const Vec3 vm = test::random_point3(rng, 0.5f);
      std::uint32_t tri = 0;
      const ShapeCastResult3 r = shape_cast(shape, xa, va, mesh, xm, vm, &tri);
      expect_same(r, brute_cast(shape, xa, va, mesh, xm, vm), iter);
      if (r.hit) {
        EXPECT_LT(tri, mesh.triangle_count());
        ++hits;
      } else {
        EXPECT_EQ(tri, std::numeric_limits<std::uint32_t>::max());
        ++misses;
      }
    }
  }
  EXPECT_GT(hits, 80);
  EXPECT_GT(misses, 80);
}

TEST(MeshShapeCast, DungeonAgainstBruteForce) {
  const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + "recast/dungeon.obj");
  std::mt19937 rng(32);
  int hits = 0, misses = 0;
  for (int iter = 0; iter < 60; ++iter) {
    const std::uint32_t near = std::uniform_int_distribution<std::uint32_t>(0, mesh.triangle_count() - 1)(rng);
    const Triangle nt = world_triangle(mesh, near);
    const Vec3 centre = (nt.vertices[0] + nt.vertices[1] + nt.vertices[2]) / 3.0f;
    const Shape3D shape = test::random_shape3(rng, 0.3f);
    const Transform3 xa{centre + test::random_point3(rng, 2.0f), test::random_rotation(rng)};
    const Vec3 va = test::random_point3(rng, 3.0f);
    const ShapeCastResult3 r = shape_cast(shape, xa, va, mesh, Transform3{}, Vec3(0.0f));
    expect_same(r, brute_cast(shape, xa, va, mesh, Transform3{}, Vec3(0.0f)), iter);
    (r.hit ? hits : misses)++;
  }
  EXPECT_GT(hits, 10);
  EXPECT_GT(misses, 5);
}

TEST(MeshShapeCast, HeightFieldMatchesEquivalentMeshAndFlatDrop) {
  const int n = 13;
  std::vector<float> heights;
  std::vector<Vec3> vertices;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x = 0.8f * float(i), z = 0.8f * float(j);
      heights.push_back(0.6f * std::sin(0.7f * x) * std::cos(0.4f * z));
      vertices.push_back({x, heights.back(), z});
    }
  }
  std::vector<glm::uvec3> triangles;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const unsigned p00 = unsigned(j * n + i), p10 = p00 + 1, p01 = p00 + unsigned(n), p11 = p01 + 1;
      triangles.push_back({p00, p01, p11});
      triangles.push_back({p00, p11, p10});
    }
  }
  const HeightField field = make_height_field(n, n, heights, {0.8f, 0.8f});
  const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
  std::mt19937 rng(33);
  const Transform3 xl = test::random_transform3(rng, 4.0f);
  int hits = 0;
  for (int iter = 0; iter < 300; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 0.4f);
    const Vec3 local{test::uniform(rng, 0.0f, 9.6f), test::uniform(rng, 0.5f, 2.5f), test::uniform(rng, 0.0f, 9.6f)};
    const Transform3 xa{transform_point(xl, local), test::random_rotation(rng)};
    const Vec3 va = rotate(xl.q, Vec3(test::uniform(rng, -3, 3), test::uniform(rng, -4, 0.5f), test::uniform(rng, -3, 3)));
    const ShapeCastResult3 rm = shape_cast(shape, xa, va, mesh, xl, Vec3(0.0f));
    const ShapeCastResult3 rf = shape_cast(shape, xa, va, field, xl, Vec3(0.0f));
    expect_same(rm, rf, iter);
    hits += rm.hit;
  }
  EXPECT_GT(hits, 60);
  EXPECT_LT(hits, 290);
  // A box dropped flat onto level ground (the field lifted to 0): touches after falling 1.5.
  std::vector<float> zero(static_cast<std::size_t>(n * n), 0.0f);
  const HeightField ground = make_height_field(n, n, zero, {0.8f, 0.8f});
  const Box box = make_box({0.5f, 0.5f, 0.5f});
  const ShapeCastResult3 r = shape_cast(box, Transform3{{4.0f, 2.0f, 4.0f}, Quat{1, 0, 0, 0}}, Vec3(0, -3, 0),
                                        ground, Transform3{}, Vec3(0.0f));
  ASSERT_TRUE(r.hit);
  EXPECT_NEAR(r.fraction, 0.5f, 1e-3f);
  EXPECT_NEAR(r.normal.y, -1.0f, 1e-3f);
}

TEST(MeshShapeCast, PrismEarlyOutKeepsTouchesWithinTheTargetSeparation) {
  // A sphere passing beside edge 0 of a triangle (y = 0 in the plane z = 0), a little more
  // than its radius away: within the cast's target separation it is a touch (as the GJK cast of
  // the triangle alone says), beyond it a miss; the early out of spheres and capsules must
  // not turn the first into the second.
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  const TriangleMesh mesh = make_triangle_mesh(std::vector<Vec3>{a, b, c}, std::vector<glm::uvec3>{{0, 1, 2}});
  const Triangle tri = make_triangle(a, b, c);
  const float r = 0.25f;
  const Sphere ball = make_sphere(Vec3(0.0f), r);
  // gjk_shape_cast's target separation for this pair (sizes r and |a - c| = 2).
  const float tolerance = kShapeCastTolerance * r + kShapeCastRounding * (4.0f + r + 2.0f);
  for (const float gap : {0.3f * tolerance, 3.0f * tolerance}) {
    const Transform3 xa = Transform3::from({-1.0f, -(r + gap), 0.0f}, Quat{1, 0, 0, 0});
    const ShapeCastResult3 got = shape_cast(ball, xa, Vec3(4, 0, 0), mesh, Transform3{}, Vec3(0.0f));
    const ShapeCastResult3 gjk = shape_cast(ball, xa, Vec3(4, 0, 0), tri, Transform3{}, Vec3(0.0f));
    EXPECT_EQ(got.hit, gjk.hit) << gap;
    EXPECT_EQ(got.hit, gap < tolerance) << gap;
  }
}

}  // namespace
}  // namespace collide
