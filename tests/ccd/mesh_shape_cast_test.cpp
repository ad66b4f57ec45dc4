// Shape casts of convex shapes against TriangleMesh and HeightField: the BVH / cell sweep
// against the loop over every triangle with the convex-triangle cast, on random soups and on
// dungeon.obj; a height field against the equivalent mesh; a box dropped on flat ground; the
// closed form that spheres and capsules take when they first reach a triangle's plane inside it
// (LevelCast::plane_test) against a brute-force first touch in double precision, against the
// GJK cast, and on analytic cases.

#include <collide/ccd/shape_cast.hpp>
#include <collide/io/obj.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include "support/brute_convex3.hpp"
#include "support/brute_triangle.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
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

/// A floor y = 0 of `n` x `n` quads of side `side` centred on the origin, two triangles each,
/// leaving out the quads whose centre is within `hole` of the origin.
TriangleMesh fine_floor(int n, float side, float hole) {
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  const float half = 0.5f * float(n) * side;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const float x = -half + float(i) * side, z = -half + float(j) * side;
      if (length(Vec2(x + 0.5f * side, z + 0.5f * side)) < hole) continue;
      const auto v = static_cast<unsigned>(vertices.size());
      vertices.insert(vertices.end(), {{x, 0, z}, {x, 0, z + side}, {x + side, 0, z + side}, {x + side, 0, z}});
      triangles.push_back({v, v + 1, v + 2});
      triangles.push_back({v, v + 2, v + 3});
    }
  }
  return make_triangle_mesh(vertices, triangles);
}

TEST(MeshShapeCast, WideRoundedShapesOverManySmallTriangles) {
  // A sphere and a lying capsule of radius 0.5 dropped onto a floor of 0.05 quads: hundreds of
  // triangles lie within the radius of the foot, reached first outside themselves, more than
  // the cast puts off for later. Whole, the floor is met face on under the foot; with a hole
  // of radius 0.2 under it, the sphere on the hole's rim, later (only the triangles put off
  // can give that touch).
  for (const float hole : {0.0f, 0.2f}) {
    const TriangleMesh floor = fine_floor(40, 0.05f, hole);
    const float r = 0.5f;
    const Shape3D shapes[] = {make_sphere(Vec3(0.0f), r), make_capsule(Vec3(-0.3f, 0, 0), Vec3(0.3f, 0, 0), r)};
    for (const Shape3D& shape : shapes) {
      const Transform3 xa{Vec3(0.013f, 1.0f, -0.007f)};
      const Vec3 va(0.0f, -1.0f, 0.0f);
      const ShapeCastResult3 got = shape_cast(shape, xa, va, floor, Transform3{}, Vec3(0.0f));
      const ShapeCastResult3 truth = brute_cast(shape, xa, va, floor, Transform3{}, Vec3(0.0f));
      SCOPED_TRACE(testing::Message() << "hole " << hole << " shape " << shape.index());
      ASSERT_TRUE(got.hit);
      expect_same(got, truth, 0);
      const bool sphere = std::holds_alternative<Sphere>(shape);
      if (hole == 0.0f || !sphere) {
        // The capsule (core x in [-0.3, 0.3]) lies across the hole onto the floor beyond it.
        EXPECT_NEAR(got.fraction, 1.0f - r, 1e-5f);
        // The sphere's touch is the face under its foot, in closed form (the capsule's is a
        // segment of the floor, which GJK may find first, on a triangle beside the foot).
        if (hole == 0.0f && sphere) EXPECT_EQ(got.iterations, 0);
      } else {
        // The lowest ring of the sphere resting on a rim of radius about the hole's: lower
        // than the face by r - sqrt(r^2 - rim^2), rim in [0.2 - 0.05, 0.2 + 0.05] (quads are
        // left out by their centres).
        const auto drop = [&](float rim) { return r - std::sqrt(r * r - rim * rim); };
        EXPECT_GT(got.fraction, 1.0f - r + drop(0.14f));
        EXPECT_LT(got.fraction, 1.0f - r + drop(0.26f));
        EXPECT_NEAR(got.normal.y, -1.0f, 0.3f);
      }
    }
  }
}

TEST(MeshShapeCast, RoundedShapesBesideALedgeMeetItsEdgeOnly) {
  // The wall below a ledge: the plane x = 0 for y in [-5, 0] (its top edge along z at y = 0).
  // A sphere of radius 0.5 beside it, centre at x = 0.35 (inside the wall's plane's reach),
  // above the edge, moving down: it touches the edge when its centre is 0.5 from it.
  const TriangleMesh wall = make_triangle_mesh(std::vector<Vec3>{{0, -5, -5}, {0, 0, -5}, {0, 0, 5}, {0, -5, 5}},
                                               std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}});
  const float r = 0.5f;
  const Sphere ball = make_sphere(Vec3(0.0f), r);
  const Capsule3 upright = make_capsule(Vec3(0, -0.2f, 0), Vec3(0, 0.2f, 0), r);
  const float touch_y = std::sqrt(r * r - 0.35f * 0.35f);  // of the lower core end
  for (const bool capsule : {false, true}) {
    const float below = capsule ? 0.2f : 0.0f;  // the lower core end under the centre
    const auto cast = [&](Vec3 v) {
      const Transform3 xa{Vec3(0.35f, 0.4f + below, 0.1f)};
      return capsule ? shape_cast(upright, xa, v, wall, Transform3{}, Vec3(0.0f))
                     : shape_cast(ball, xa, v, wall, Transform3{}, Vec3(0.0f));
    };
    SCOPED_TRACE(capsule ? "capsule" : "sphere");
    // Down by 0.05: the edge is met after (0.4 - touch_y) / 0.05.
    const ShapeCastResult3 down = cast(Vec3(0, -0.05f, 0));
    ASSERT_TRUE(down.hit);
    EXPECT_NEAR(down.fraction, (0.4f - touch_y) / 0.05f, 2e-3f);
    EXPECT_VEC3_NEAR(down.point, Vec3(0, 0, 0.1f), 1e-3f);
    EXPECT_VEC3_NEAR(down.normal, normalize(Vec3(-0.35f, -touch_y, 0)), 1e-3f);
    // Down by 0.02 it ends 0.017 short of the edge; along the edge it never nears it.
    EXPECT_FALSE(cast(Vec3(0, -0.02f, 0)).hit);
    EXPECT_FALSE(cast(Vec3(0, 0, 2.0f)).hit);
  }
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

/// A mesh of one triangle.
TriangleMesh one_triangle(Vec3 a, Vec3 b, Vec3 c) {
  return make_triangle_mesh(std::vector<Vec3>{a, b, c}, std::vector<glm::uvec3>{{0, 1, 2}});
}

/// Distance between capsule core p0-p1 (radius r) moved by t * v and triangle (a, b, c), in
/// double, by the brute-force element pairs (no GJK, no Voronoi regions).
double capsule_triangle_distance(Vec3 p0, Vec3 p1, float r, Vec3 v, double t, const Triangle& tri) {
  using test::DVec3;
  const DVec3 q0 = DVec3(p0) + t * DVec3(v);
  const DVec3 q1 = DVec3(p1) + t * DVec3(v);
  const DVec3 a(tri.vertices[0]), b(tri.vertices[1]), c(tri.vertices[2]);
  if (test::segment_crosses_triangle(q0, q1, a, b, c)) return 0.0;
  double d2 = std::min(test::point_triangle_d2(q0, a, b, c), test::point_triangle_d2(q1, a, b, c));
  for (const auto& [x, y] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
    d2 = std::min(d2, test::segment_segment_d2(q0, q1, x, y));
  }
  return std::max(std::sqrt(d2) - double(r), 0.0);
}

/// The cast of a capsule core p0-p1 (p0 == p1: a sphere) moving by v against one triangle at
/// rest, checked against the brute-force first touch and against the GJK cast of the triangle
/// alone. Returns 1 for a hit of the closed form (no GJK iterations), 0 otherwise.
int check_rounded_cast(Vec3 p0, Vec3 p1, float r, Vec3 v, const Triangle& tri, const std::string& what) {
  const TriangleMesh mesh = one_triangle(tri.vertices[0], tri.vertices[1], tri.vertices[2]);
  const bool sphere = p0 == p1;
  const Vec3 centre = 0.5f * (p0 + p1);
  const Transform3 xa = Transform3::from(centre, Quat{1, 0, 0, 0});
  const Capsule3 capsule = sphere ? Capsule3{} : make_capsule(p0 - centre, p1 - centre, r);
  const Sphere ball = make_sphere(Vec3(0.0f), r);
  const ShapeCastResult3 got = sphere ? shape_cast(ball, xa, v, mesh, Transform3{}, Vec3(0.0f))
                                      : shape_cast(capsule, xa, v, mesh, Transform3{}, Vec3(0.0f));
  const ShapeCastResult3 gjk = sphere ? shape_cast(ball, xa, v, tri, Transform3{}, Vec3(0.0f))
                                      : shape_cast(capsule, xa, v, tri, Transform3{}, Vec3(0.0f));
  const auto distance_at = [&](double t) { return capsule_triangle_distance(p0, p1, r, v, t, tri); };
  double min_distance = 0.0;
  const double truth = test::brute_first_touch(distance_at, min_distance);
  // The target separation of the cast (kShapeCastTolerance of the smaller size, at most the
  // capsule's) and rounding.
  const float tol = kShapeCastTolerance * (distance(p0, p1) + 2.0f * r) + 1e-5f;
  SCOPED_TRACE(testing::Message() << what << " truth " << truth << " min d " << min_distance << " got "
                                  << got.fraction << " " << to_string(got.status) << " gjk " << gjk.fraction << " "
                                  << to_string(gjk.status));
  if (truth < 0.0) {
    if (min_distance > tol) EXPECT_FALSE(got.hit);
    return 0;
  }
  if (truth == 0.0) {
    EXPECT_EQ(got.status, QueryStatus::overlapped);
    return 0;
  }
  EXPECT_TRUE(got.hit);
  if (!got.hit) return 0;
  // Never late, and apart by at most the target separation (GJK grazing a surface stops that
  // close to it, which can be well before the touch); the closed form is the touch itself.
  const double speed = length(v);
  EXPECT_LE(got.fraction, truth + 1e-6);
  EXPECT_LE(distance_at(got.fraction), tol);
  if (got.iterations == 0) EXPECT_NEAR(got.fraction, truth, 1e-5 * (1.0 + 4.0 / speed));
  // The same touch as GJK's: a rounded shape has one normal there. (GJK may stop earlier
  // when grazing, still within its target separation: then the normals differ.)
  if (gjk.status == QueryStatus::hit && got.status == QueryStatus::hit &&
      std::fabs(got.fraction - gjk.fraction) < 2.0 * tol / speed) {
    EXPECT_GT(dot(got.normal, gjk.normal), 0.999f) << got.normal.x << " " << got.normal.y << " " << got.normal.z;
  }
  // The point is on both surfaces (a capsule lying on a face touches along a segment: GJK may
  // report another point of it).
  const test::DVec3 x(got.point);
  const test::DVec3 q0 = test::DVec3(p0) + double(got.fraction) * test::DVec3(v);
  const test::DVec3 q1 = test::DVec3(p1) + double(got.fraction) * test::DVec3(v);
  const double on_core = glm::length(x - test::closest_on_segment(q0, q1, x));
  EXPECT_NEAR(on_core, double(r), 2.0 * tol);
  EXPECT_LE(std::sqrt(test::point_triangle_d2(x, test::DVec3(tri.vertices[0]), test::DVec3(tri.vertices[1]),
                                              test::DVec3(tri.vertices[2]))),
            2.0 * tol);
  return got.iterations == 0 ? 1 : 0;
}

TEST(MeshShapeCast, RoundedShapesTakeTheClosedFormAndMatchBruteForce) {
  std::mt19937 rng(34);
  int closed = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    const Triangle tri = make_triangle(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f),
                                       test::random_point3(rng, 1.0f));
    const float r = test::uniform(rng, 0.05f, 0.5f);
    Vec3 p0 = test::random_point3(rng, 2.5f);
    // Spheres, capsules in any direction, and capsules parallel to an edge (the case that
    // leaves the parallelogram's plane to the cylinders).
    Vec3 p1 = p0;
    const int kind = iter % 3;
    if (kind == 1) p1 = p0 + test::random_point3(rng, 1.0f);
    if (kind == 2) p1 = p0 + test::uniform(rng, 0.3f, 1.5f) * (tri.vertices[1] - tri.vertices[0]);
    // Aimed at a point of the triangle, or anywhere; every fifth from in front of the face
    // (as a character's casts meet floors and walls).
    const Vec3 centroid = (tri.vertices[0] + tri.vertices[1] + tri.vertices[2]) / 3.0f;
    if (iter % 5 == 0) {
      const Vec3 n = normalize(cross(tri.vertices[1] - tri.vertices[0], tri.vertices[2] - tri.vertices[0]));
      const Vec3 lift = test::uniform(rng, 1.2f, 2.0f) * n;
      const Vec3 shift = (p1 - p0) * 0.5f;
      p0 = centroid + lift - shift + test::random_point3(rng, 0.1f);
      p1 = p0 + 2.0f * shift;
    }
    const Vec3 aim = centroid + test::random_point3(rng, 0.8f);
    const Vec3 v = iter % 4 == 1 ? test::random_point3(rng, 4.0f)
                                 : test::uniform(rng, 1.0f, 2.5f) * (aim - 0.5f * (p0 + p1));
    const int c = check_rounded_cast(p0, p1, r, v, tri, "case " + std::to_string(iter));
    closed += c;
    if (::testing::Test::HasFailure()) break;
  }
  // About 350 of the 3000 (most of the face-on fifth) take the closed form with this seed.
  EXPECT_GT(closed, 250);
}

TEST(MeshShapeCast, RoundedShapesOnAnalyticPatches) {
  // A wall fin in the plane z = 0: corners (0, 0), (2, 0), (0, 2) in x, y.
  const Triangle fin = make_triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  const float r = 0.25f;
  const auto cast = [&](const auto& shape, Vec3 at, Vec3 v) {
    return shape_cast(shape, Transform3::from(at, Quat{1, 0, 0, 0}), v, one_triangle(fin.vertices[0], fin.vertices[1], fin.vertices[2]),
                      Transform3{}, Vec3(0.0f));
  };
  // Face: a capsule along x 1 in front of the face moves onto it: touches after 1 - r.
  const Capsule3 along_x = make_capsule({-0.2f, 0, 0}, {0.2f, 0, 0}, r);
  ShapeCastResult3 h = cast(along_x, {0.6f, 0.6f, 1.0f}, {0, 0, -2});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (1.0f - r) / 2.0f, 1e-4f);
  EXPECT_VEC3_NEAR(h.normal, Vec3(0, 0, -1), 1e-5f);
  EXPECT_NEAR(h.point.y, 0.6f, 1e-4f);  // on the segment of contact, x in [0.4, 0.8]
  EXPECT_NEAR(h.point.z, 0.0f, 1e-4f);
  EXPECT_TRUE(h.point.x >= 0.4f - 1e-4f && h.point.x <= 0.8f + 1e-4f) << h.point.x;
  EXPECT_EQ(h.iterations, 0);
  // The core's side across an edge: a capsule along z above the bottom edge (y = 0) moves up
  // into it from below: touches after 1 - r, at the crossing (0.7, 0, 0).
  const Capsule3 along_z = make_capsule({0, 0, -0.5f}, {0, 0, 0.5f}, r);
  h = cast(along_z, {0.7f, -1.0f, 0.1f}, {0, 4, 0});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (1.0f - r) / 4.0f, 1e-4f);
  EXPECT_VEC3_NEAR(h.normal, Vec3(0, 1, 0), 1e-5f);
  EXPECT_VEC3_NEAR(h.point, Vec3(0.7f, 0, 0), 1e-3f);
  // An edge parallel to the core (two cylinders' axes): a capsule along y moving +x meets the
  // fin's edge x = 0 after 1 - r.
  const Capsule3 along_y = make_capsule({0, -0.3f, 0}, {0, 0.3f, 0}, r);
  h = cast(along_y, {-1.0f, 1.0f, 0}, {2, 0, 0});
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (1.0f - r) / 2.0f, 1e-4f);
  EXPECT_VEC3_NEAR(h.normal, Vec3(1, 0, 0), 1e-5f);
  // A corner: a sphere moving along the diagonal towards corner (2, 0, 0) from beyond it.
  const Vec3 dir = normalize(Vec3(1, -1, 1));
  h = cast(make_sphere(Vec3(0.0f), r), Vec3(2, 0, 0) + 2.0f * dir, -3.0f * dir);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.fraction, (2.0f - r) / 3.0f, 1e-4f);
  EXPECT_VEC3_NEAR(h.normal, -dir, 1e-4f);
  EXPECT_VEC3_NEAR(h.point, Vec3(2, 0, 0), 1e-3f);
  // Starting within reach is GJK's overlapped case; moving away misses.
  h = cast(along_x, {0.6f, 0.6f, 0.2f}, {0, 0, -1});
  EXPECT_EQ(h.status, QueryStatus::overlapped);
  h = cast(along_x, {0.6f, 0.6f, 1.0f}, {0, 0, 1});
  EXPECT_FALSE(h.hit);
}

TEST(MeshShapeCast, RoundedShapesNearlyParallelToAnEdge) {
  // A capsule along y turned by a small angle about z, moving +x into the fin's edge x = 0: the
  // parallelogram's plane is nearly degenerate; every angle is checked against brute force.
  const Triangle fin = make_triangle({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  for (const float angle : {0.0f, 1e-6f, 1e-4f, 1e-3f, 3e-3f, 1e-2f, 0.1f}) {
    for (const float r : {0.01f, 0.25f}) {
      const Vec3 axis(std::sin(angle), std::cos(angle), 0.0f);
      const Vec3 centre(-1.0f, 1.0f, 0.05f);
      check_rounded_cast(centre - 0.6f * axis, centre + 0.6f * axis, r, {2, 0, 0}, fin,
                         "angle " + std::to_string(angle) + " r " + std::to_string(r));
    }
  }
}

// Spheres and capsules cast straight at slivers 2 units long and 2^-3 to 2^-21 wide, in a
// one-triangle mesh and a mesh with a triangle behind the sliver: the touch is at (h - r) / |v|
// for a sphere at h from its nearest point moving towards it by |v| = 2h. The plane test that
// lets most casts skip GJK made the sliver's normal in float, which turns its plane by
// FLT_EPSILON times its length over its width: a sphere that touches the sliver first was taken
// for "separated" from it and hit the triangle behind, late (the fuzzer's cast check, stop 105:
// 0.655 of the step instead of 0.375). Now the normal is made in double.
TEST(MeshShapeCast, CastsStraightAtSliversTouchWhenTheDistanceSays) {
  std::mt19937 rng(105);
  int checked = 0;
  for (int i = 0; i < 6000; ++i) {
    const int e = 3 + static_cast<int>(rng() % 19);
    const std::array<Vec3, 3> t = test::random_sliver(rng, 2.0f, 2.0f, std::ldexp(1.0f, -e), i % 2 == 1);
    const double height = test::uniform(rng, 0.2f, 1.0f);
    const Vec3 p = test::random_point_over(rng, t, (i % 4 < 2 ? 1.0 : -1.0) * height);
    const glm::dvec3 q = test::brute_closest_on_triangle(glm::dvec3(p), glm::dvec3(t[0]), glm::dvec3(t[1]), glm::dvec3(t[2]));
    const double d = glm::length(q - glm::dvec3(p));
    if (d < 0.1) continue;
    const auto r = static_cast<float>(0.25 * d);
    const Vec3 v = 2.0f * Vec3(q - glm::dvec3(p));
    // Behind the sliver, across the cast's path: a big triangle the cast would reach later.
    const Vec3 n = normalize(v), side = normalize(cross(n, std::fabs(n.x) < 0.9f ? Vec3(1, 0, 0) : Vec3(0, 1, 0)));
    const Vec3 behind = Vec3(q) + n * 0.5f, other = cross(n, side);
    std::vector<Vec3> corners{t[0], t[1], t[2], behind - 5.0f * side - 5.0f * other, behind + 5.0f * side - 5.0f * other,
                              behind + 5.0f * other};
    const TriangleMesh mesh = make_triangle_mesh(corners, std::vector<glm::uvec3>{{0, 1, 2}, {3, 4, 5}});
    if (mesh.triangle_count() != 2) continue;
    const double expected = (d - r) / (2.0 * d);  // 0.375
    const Sphere sphere = make_sphere(Vec3(0.0f), r);
    const ShapeCastResult3 c = shape_cast(sphere, Transform3{p, Quat{1, 0, 0, 0}}, v, mesh, Transform3{}, Vec3(0.0f));
    ASSERT_TRUE(c.hit) << i << " width 2^-" << e;
    ASSERT_NEAR(c.fraction, expected, 1e-4) << i << " width 2^-" << e;
    // A capsule lying across the path, its core through p: it touches no later than the sphere.
    const Capsule3 capsule = make_capsule(p - r * side, p + r * side, r);
    const ShapeCastResult3 k = shape_cast(capsule, Transform3{}, v, mesh, Transform3{}, Vec3(0.0f));
    ASSERT_TRUE(k.hit) << i << " width 2^-" << e;
    ASSERT_LE(k.fraction, expected + 1e-4) << i << " width 2^-" << e;
    ++checked;
  }
  EXPECT_GT(checked, 4000);
}

// Bodies cast straight down (and up) at flat levels of needles 2^-60 to 2^-90 wide: a height
// field with that spacing along x, and a one-triangle mesh of such a needle. The touch is at
// (h - r) / |v| for a body whose lowest point is h - r above the ground, moving |v| down. The
// plane test squared the needles' area normal in float: subnormal below about 2^-63, so the
// unit normal made from it was 1.003 long and the closed-form face hit 0.3% of the distance late
// (the fuzzer's cast check, finding 24: a sphere 2 below a field with spacing 1.1e-22 touched
// at 0.37537 of its step, not 0.375). Now such a normal is scaled by a power of two first.
TEST(MeshShapeCast, CastsAtNeedlesWhoseNormalSquaresUnderflowTouchOnTime) {
  int checked = 0;
  for (int e = 60; e <= 90; e += 3) {
    const float width = std::ldexp(1.0f, -e);
    const std::vector<float> flat(3 * 8, -8.0f);
    const HeightField field = make_height_field(3, 8, flat, {width, 2.75f}, Vec3(-0.75f, 0.75f, -1.0f));
    const std::vector<Vec3> corners{{0.0f, -7.25f, 0.0f}, {0.0f, -7.25f, 19.25f}, {width, -7.25f, 0.0f}};
    const TriangleMesh mesh = make_triangle_mesh(corners, std::vector<glm::uvec3>{{0, 1, 2}});
    ASSERT_EQ(mesh.triangle_count(), 1u) << "width 2^-" << e;
    for (const float side : {1.0f, -1.0f}) {
      for (const float r : {0.5f, 0.125f}) {
        const float h = 2.0f;  // the body's centre above (below) the ground
        const Vec3 v(0.0f, -side * 2.0f * h, 0.0f);
        const double expected = (h - r) / (2.0 * h);
        const auto check = [&](const auto& body, float x, const auto& level, const char* what) {
          const Transform3 xf{Vec3(x, -7.25f + side * h, 2.4375f), Quat{1, 0, 0, 0}};
          const ShapeCastResult3 c = shape_cast(body, xf, v, level, Transform3{}, Vec3(0.0f));
          ASSERT_TRUE(c.hit) << what << " width 2^-" << e;
          EXPECT_NEAR(c.fraction, expected, 1e-5) << what << " width 2^-" << e << " side " << side << " r " << r;
          EXPECT_NEAR(length(c.normal), 1.0f, 1e-5f) << what << " width 2^-" << e << " side " << side << " r " << r;
          ++checked;
        };
        const Sphere sphere = make_sphere(Vec3(0.0f), r);
        const Capsule3 capsule = make_capsule(Vec3(0.0f, 0.0f, -r), Vec3(0.0f, 0.0f, r), r);  // lying along z
        const Box box = make_box(Vec3(r));
        check(sphere, -0.75f, field, "sphere at the field");
        check(capsule, -0.75f, field, "capsule at the field");
        check(box, -0.75f, field, "box at the field");
        check(sphere, 0.0f, mesh, "sphere at the mesh");
        check(capsule, 0.0f, mesh, "capsule at the mesh");
        check(box, 0.0f, mesh, "box at the mesh");
      }
    }
  }
  EXPECT_EQ(checked, 11 * 2 * 2 * 6);
}

// Finding 25: a height field spaced 1.4e-45 across: its cells are needles, in world space
// segments to float, whose area normals' float squares underflow to zero. A sphere cast along a
// needle's line at its tip first meets the needle's plane beyond the tip; the plane test's side
// check for the tiny edge there multiplies 1.4e-45 by the tip's distance, which underflows to
// zero and reads as on the edge, so a plane test run on such a normal (rescaled) reported that
// early touch, 10% early. Each field here is one row of such needles rising along z from height
// 0 to `rise` over 2 units; the sphere comes at the low end's edge from beyond it, so it first
// touches the end point: at (offset - r) / |v|, analytic.
TEST(MeshShapeCast, CastsAtTheTipsOfNeedlesTooThinForAFloatSquareTouchTheTip) {
  int checked = 0;
  for (const float width : {std::numeric_limits<float>::denorm_min(), std::ldexp(1.0f, -140), std::ldexp(1.0f, -130),
                            std::ldexp(1.0f, -120)}) {
    for (const float rise : {2.5f, 1.0f, -3.0f}) {
      for (const float origin_x : {0.0f, -7.0f, 5.5f}) {
        const std::vector<float> heights{0.0f, 0.0f, rise, rise};
        const HeightField field = make_height_field(2, 2, heights, {width, 2.0f}, Vec3(origin_x, 0.0f, 0.0f));
        for (const float r : {0.125f, 0.5f}) {
          const float offset = 0.5f + r;
          // From beyond the low end (z < 0) in the needles' own x, along z: the end stays the
          // nearest point of the field (the needles rise away from it), and the needles' plane,
          // tilted, is met first on their line continued beyond the end.
          const Vec3 start(origin_x, 0.0f, -offset);
          const Vec3 v(0.0f, 0.0f, 2.0f * offset);
          const double expected = (offset - r) / (2.0 * offset);
          const ShapeCastResult3 c =
              shape_cast(make_sphere(Vec3(0.0f), r), Transform3{start, Quat{1, 0, 0, 0}}, v, field, Transform3{}, Vec3(0.0f));
          ASSERT_TRUE(c.hit) << "width " << width << " rise " << rise << " origin " << origin_x << " r " << r;
          EXPECT_NEAR(c.fraction, expected, 1e-5) << "width " << width << " rise " << rise << " origin " << origin_x << " r " << r;
          ++checked;
        }
      }
    }
  }
  EXPECT_EQ(checked, 4 * 3 * 3 * 2);
}

// Finding 26: a capsule 7e-15 wide cast at a triangle of a mesh whose origin is 8.4e-8 from the
// world's missed it. The level's stored frame was placed in the body's as the body's frame of
// the level's, then the origin rotated into it: each of those terms rounds at the size of the
// coordinates, one float spacing there, the size of the body. Now the origin is added to the
// level's place first and the body's position taken from that sum (inv_mul with an offset),
// exact for a level at the identity. Here bodies a few spacings wide (u, the float spacing at the
// origin) beside a needle 8u by 120u, at origins from 9e-8 to 1.6e6: sphere and turned capsule,
// cast in the triangle's plane at its long edge, and at rest across it (from 1.5 up); the answers must be
// those of the same cast and contact against the triangle alone, in the mesh's own frame (where
// the coordinates are small integers times u, exact).
TEST(MeshShapeCast, BodiesAFloatSpacingWideBesideAFarMeshOriginMeetItAsNearTheOrigin) {
  const Quat turned = glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f});
  int checked = 0;
  for (const int e : {-24, 0, 10, 20}) {
    const float big = std::ldexp(1.5f, e);
    const float u = std::ldexp(1.0f, e - 23);  // the float spacing in [2^e, 2^(e+1))
    const Vec3 origin(big, -big, big);
    const std::array<Vec3, 3> local{Vec3(-8.0f * u, 0.0f, -120.0f * u), Vec3(0.0f), Vec3(0.0f, 0.0f, -120.0f * u)};
    const std::vector<Vec3> world{origin + local[0], origin + local[1], origin + local[2]};
    for (int k = 0; k < 3; ++k) ASSERT_EQ(world[k] - origin, local[k]) << "not exact at 2^" << e;
    const TriangleMesh mesh = make_triangle_mesh(world, std::vector<glm::uvec3>{{0, 1, 2}});
    const Triangle alone{local};
    const Vec3 start_local(2.0f * u, 0.0f, -30.0f * u), touch_local(0.0f, 0.0f, -30.0f * u);
    const Vec3 v = 2.0f * (touch_local - start_local);
    const float r = 0.5f * u;
    const auto check = [&](const auto& body, const char* what) {
      const ShapeCastResult3 truth = shape_cast(body, Transform3{start_local, turned}, v, alone, Transform3{}, Vec3(0.0f));
      ASSERT_TRUE(truth.hit) << what;
      const ShapeCastResult3 c = shape_cast(body, Transform3{origin + start_local, turned}, v, mesh, Transform3{}, Vec3(0.0f));
      ASSERT_TRUE(c.hit) << what << " at 2^" << e;
      EXPECT_NEAR(c.fraction, truth.fraction, 1e-3) << what << " at 2^" << e;
      const Manifold3 rest = contact(body, Transform3{touch_local, turned}, alone, Transform3{});
      ASSERT_GT(rest.count, 0) << what;
      const Manifold3 m = contact(body, Transform3{origin + touch_local, turned}, mesh, Transform3{});
      ASSERT_GT(m.count, 0) << what << " at 2^" << e;
      EXPECT_NEAR(m.max_depth() / u, rest.max_depth() / u, 1e-2) << what << " at 2^" << e;
      // The least depth: the radius, the core's centre on the edge. Until stop 108, at u = 2^-47
      // the capsule took the face's normal: 0.70u deep against the triangle alone (tolerances
      // floored at 1e-5 units), 0.50u against the mesh (its core's closest points to the edges
      // underflowed), finding 26's open part.
      EXPECT_NEAR(rest.max_depth() / u, 0.5f, 1e-2) << what << " at 2^" << e;
      EXPECT_NEAR(m.max_depth() / u, 0.5f, 1e-2) << what << " at 2^" << e;
      // The capsule's normal is that depth's: across its core and the edge (the sphere's centre on
      // the edge has that depth along any normal out of the triangle).
      if constexpr (std::is_same_v<std::decay_t<decltype(body)>, Capsule3>) {
        const Vec3 across = glm::normalize(cross(rotate(turned, Vec3(0.0f, 1.0f, 0.0f)), Vec3(0.0f, 0.0f, 1.0f)));
        EXPECT_GT(std::fabs(dot(rest.normal, across)), 1.0f - 1e-4f) << what << " at 2^" << e;
        EXPECT_GT(std::fabs(dot(m.normal, across)), 1.0f - 1e-4f) << what << " at 2^" << e;
      }
      ++checked;
    };
    check(make_sphere(Vec3(0.0f), r), "sphere");
    check(make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r), "capsule");
  }
  EXPECT_EQ(checked, 4 * 2);
}

}  // namespace
}  // namespace collide
