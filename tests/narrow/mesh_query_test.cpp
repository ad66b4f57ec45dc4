// Convex shapes against TriangleMesh and HeightField: overlap, distance and contact. Checked
// analytically (a box resting on a flat grid, a sphere sliding over internal edges: the ghost
// contact test), by brute force (every triangle by the convex-triangle query), on a real level
// (recast's dungeon.obj), a height field against the equivalent mesh, far from the origin, and
// by the depth property.

#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/io/obj.hpp>

#include "support/brute_convex3.hpp"
#include "support/hull_pairs.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace collide {
namespace {

const std::string kMeshes = std::string(COLLIDE_DATA_DIR) + "/meshes/";

bool finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// A grid of n x n samples at `spacing`, heights from `h(x, z)`: the height field and the
/// equivalent mesh (vertex i = sample index, triangle t = the field's triangle t).
struct Terrain {
  HeightField field;
  TriangleMesh mesh;
};

template <class H>
Terrain make_terrain(int n, float spacing, H h) {
  std::vector<float> heights;
  std::vector<Vec3> vertices;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const float x = float(i) * spacing, z = float(j) * spacing;
      heights.push_back(h(x, z));
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
  return {make_height_field(n, n, heights, {spacing, spacing}), make_triangle_mesh(vertices, triangles)};
}

Triangle world_triangle(const TriangleMesh& mesh, std::uint32_t t) {
  return Triangle{{mesh.origin + mesh.corner(t, 0), mesh.origin + mesh.corner(t, 1), mesh.origin + mesh.corner(t, 2)}};
}

TEST(MeshQuery, BoxRestsOnFlatGridWithFourPoints) {
  const Terrain flat = make_terrain(21, 0.5f, [](float, float) { return 0.0f; });
  const Box box = make_box({0.6f, 0.4f, 0.7f});
  const Transform3 xb = Transform3::from_axis_angle({4.1f, 0.39f, 5.3f}, {0, 1, 0}, 0.3f);
  for (const bool use_field : {false, true}) {
    const Manifold3 m = use_field ? contact(box, xb, flat.field, Transform3{}) : contact(box, xb, flat.mesh, Transform3{});
    ASSERT_EQ(m.count, 4) << use_field;
    EXPECT_NEAR(m.normal.y, -1.0f, 1e-6f);
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(m.points[i].depth, 0.01f, 1e-5f);
      EXPECT_NEAR(m.points[i].point.y, -0.005f, 1e-5f);
      // The box's four bottom corners.
      const Vec3 local = inv_transform_point(xb, m.points[i].point + 0.005f * Vec3(0, 1, 0));
      EXPECT_NEAR(std::fabs(local.x), 0.6f, 1e-4f);
      EXPECT_NEAR(std::fabs(local.z), 0.7f, 1e-4f);
      EXPECT_LT(m.points[i].id.index_b, 3u * flat.mesh.triangle_count());
    }
    EXPECT_TRUE(use_field ? overlap(box, xb, flat.field, Transform3{}) : overlap(box, xb, flat.mesh, Transform3{}));
    // Reverse order: the reversed manifold.
    const Manifold3 r = contact(flat.mesh, Transform3{}, box, xb);
    EXPECT_NEAR(r.normal.y, 1.0f, 1e-6f);
    EXPECT_EQ(r.count, 4);
  }
}

/// Slides a sphere (radius 0.5, sunk 0.01) across a flat quad grid over many internal edges and
/// vertices; returns the largest tilt (1 - |n.y|) of any per-triangle manifold's normal, and
/// checks the merged manifold.
float slide_sphere(const TriangleMesh& mesh, int& contacts) {
  const Sphere s = make_sphere(Vec3(0.0f), 0.5f);
  float worst = 0.0f;
  contacts = 0;
  for (int step = 0; step <= 800; ++step) {
    for (const float z : {3.3f, 3.5f, 3.0f + 0.3f * float(step % 7) / 7.0f}) {
      const Transform3 xs{{1.0f + 0.01f * float(step), 0.49f, z}, Quat{1, 0, 0, 0}};
      contact(s, xs, mesh, Transform3{}, 0.0f, [&](std::uint32_t, const Manifold3& m) {
        ++contacts;
        worst = std::max(worst, 1.0f - std::fabs(m.normal.y));
        return true;
      });
      const Manifold3 merged = contact(s, xs, mesh, Transform3{});
      EXPECT_GE(merged.count, 1);
      EXPECT_NEAR(merged.normal.y, -1.0f, 1e-5f);
      EXPECT_NEAR(merged.max_depth(), 0.01f, 1e-4f);
    }
  }
  return worst;
}

TEST(MeshQuery, SphereSlidingOverInternalEdgesGetsFaceNormal) {
  const Terrain flat = make_terrain(21, 0.5f, [](float, float) { return 0.0f; });
  int contacts = 0;
  EXPECT_LT(slide_sphere(flat.mesh, contacts), 2e-5f);  // never a tilted (ghost) normal
  EXPECT_GT(contacts, 2000);
  // The same grid with every edge active from both sides: the seams give tilted normals (the
  // ghost contacts the active edges remove), so the check above can fail.
  TriangleMesh all_active = flat.mesh;
  std::fill(all_active.active_edges.begin(), all_active.active_edges.end(), std::uint8_t{0x3f});
  EXPECT_GT(slide_sphere(all_active, contacts), 1e-2f);
}

/// A shape resting on a vertex that stands out of a nearly flat surface (a fan of six triangles
/// around an apex 0.05 above a rim of radius 1: every edge at the apex turns by less than the
/// active-edge angle, so none is active) still touches it: the vertex contact is turned to a
/// face's normal, not dropped because the face's clip finds A beyond its prism (shapes sank
/// through such vertices on dungeon.obj, where Jolt reported them).
TEST(MeshQuery, ShapeOnAVertexWithoutActiveEdgesTouches) {
  std::vector<Vec3> vertices{{0.0f, 0.05f, 0.0f}};
  std::vector<glm::uvec3> triangles;
  for (int k = 0; k < 6; ++k) {
    const float angle = float(k) * 3.14159265f / 3.0f;
    vertices.push_back({std::cos(angle), 0.0f, -std::sin(angle)});
    triangles.push_back({0u, unsigned(1 + k), unsigned(1 + (k + 1) % 6)});
  }
  const TriangleMesh fan = make_triangle_mesh(vertices, triangles);
  for (std::uint32_t t = 0; t < 6; ++t) ASSERT_FALSE(fan.is_edge_active(t, 0)) << t;  // apex edges
  const float depth = 0.02f;
  const float r = 0.3f;
  const Vec3 centre(0.0f, 0.05f + r - depth, 0.0f);
  const Capsule3 capsule = make_capsule(Vec3(0.0f), Vec3(0.0f, 0.5f, 0.0f), r);
  const Sphere sphere{Vec3(0.0f), r};
  const Manifold3 from_capsule = contact(capsule, Transform3{centre, Quat(1, 0, 0, 0)}, fan, Transform3{});
  const Manifold3 from_sphere = contact(sphere, Transform3{centre, Quat(1, 0, 0, 0)}, fan, Transform3{});
  for (const Manifold3& m : {from_capsule, from_sphere}) {
    ASSERT_GT(m.count, 0);
    // Down into the fan, along a face's normal (3.3 degrees off the vertical).
    EXPECT_LT(m.normal.y, -0.99f);
    EXPECT_NEAR(m.max_depth(), depth, 0.1f * depth);
  }
}

// Found by fuzz_shapes' sphere contact check: a needle whose short side (2e-24) rounds away in
// a body's frame is a segment there, and its polytope had no face normal: a sphere on it, or a
// box, got no contact. Its two farthest corners now stand for it.
TEST(MeshQuery, ANeedleThatIsASegmentInTheBodysFrameIsTouched) {
  const std::vector<Vec3> corners{{-2.06917407e-24f, -4.75551373e-38f, 0.0f}, {2.0f, 3.0f, -0.75f}, {0.0f, 0.0f, 0.0f}};
  const TriangleMesh mesh = make_triangle_mesh(corners, std::vector<glm::uvec3>{{0, 1, 2}});
  const Vec3 on = 0.75f * corners[1];  // on the long side, (1.5, 2.25, -0.5625)
  const Vec3 along = glm::normalize(corners[1]);
  for (const float radius : {1e-4f, 0.5f}) {
    const Manifold3 m = contact(make_sphere(Vec3(0.0f), radius), Transform3{on, Quat{1, 0, 0, 0}}, mesh, Transform3{});
    ASSERT_EQ(m.count, 1) << radius;
    EXPECT_NEAR(m.points[0].depth, radius, 1e-5f * (1.0f + radius));
    EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f);
    EXPECT_NEAR(dot(m.normal, along), 0.0f, 1e-4f);  // across the segment
    // Beside it by 0.3: the depth is the radius less that, the normal towards it.
    const Vec3 side = glm::normalize(cross(along, Vec3(0.0f, 0.0f, 1.0f)));
    const Manifold3 b = contact(make_sphere(Vec3(0.0f), radius), Transform3{on + 0.3f * side, Quat{1, 0, 0, 0}}, mesh,
                                Transform3{}, 0.5f);
    ASSERT_EQ(b.count, 1) << radius;
    EXPECT_NEAR(b.points[0].depth, radius - 0.3f, 1e-5f);
    EXPECT_VEC3_NEAR(b.normal, -side, 1e-5f);
  }
  const Manifold3 box = contact(make_box(Vec3(0.25f)), Transform3{on + Vec3(0.0f, 0.0f, 0.2f), Quat{1, 0, 0, 0}}, mesh,
                                Transform3{});
  // The line runs through the box's lower part, 0.05 above its bottom face at `on` and rising
  // 0.0626 to where it leaves the box's side: lifting the box 0.113 frees it.
  ASSERT_GT(box.count, 0);
  EXPECT_GT(box.max_depth(), 0.05f);
  EXPECT_LT(box.max_depth(), 0.1127f);
  EXPECT_NEAR(length(box.normal), 1.0f, 1e-5f);
}

// Found by fuzz_shapes' contact check (finding 18): a capsule through a needle whose short side
// is 1.4e-19 long got a normal 1.5% off unit length. The edge pair's axis, its core against that
// side, is a cross product about 1e-23 long, whose squared length is subnormal in float and
// kept 3 bits. Now such an axis is made again of the edges' directions scaled to unit size.
// Capsules, boxes and hulls at the short side of needles 2^-40 down to 2^-126 wide (before:
// capsules at six widths from 2^-60 to 2^-72, normals 0.965-1.015 long).
TEST(MeshQuery, BodiesAtANeedlesTinySideGetAUnitNormal) {
  const Quat turned = glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f});
  for (int e = 40; e <= 126; e += 2) {
    const float side = std::ldexp(1.3f, -e);
    const std::vector<Vec3> corners{{0.0f, 0.0f, side}, {0.0f, 0.0f, 0.0f}, {4.0f, -2.0f, 4.0f}};
    const TriangleMesh mesh = make_triangle_mesh(corners, std::vector<glm::uvec3>{{0, 1, 2}});
    for (const float r : {2.13623047e-4f, 0.1f}) {
      const std::vector<Vec3> octahedron{{2 * r, 0, 0}, {-2 * r, 0, 0}, {0, 2 * r, 0}, {0, -2 * r, 0}, {0, 0, 2 * r}, {0, 0, -2 * r}};
      for (const Vec3 centre : {corners[1], mesh.origin}) {
        const Transform3 at{centre, turned};
        const auto check = [&](const Manifold3& m, const char* what) {
          ASSERT_GT(m.count, 0) << what << " side " << side << " r " << r;
          EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f) << what << " side " << side << " r " << r;
          for (int i = 0; i < m.count; ++i) {
            EXPECT_TRUE(std::isfinite(m.points[i].depth)) << what;
            EXPECT_LE(m.points[i].depth, 4.0f * r) << what << " side " << side << " r " << r;
          }
        };
        check(contact(make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r), at, mesh, Transform3{}), "capsule");
        check(contact(make_box(Vec3(r, 1.25f * r, 1.5f * r)), at, mesh, Transform3{}), "box");
        check(contact(make_convex_hull(octahedron), at, mesh, Transform3{}), "hull");
      }
    }
  }
}

// Found by fuzz_shapes' contact check (finding 23): a needle 10.8 long whose short side
// (5.7e-14) lies at the body, its tip far away. The level contact made the triangle's normal
// from the tip, where double rounds the short side out of two long edges: the normal turned 2%,
// the plane through the tip missed the body by 0.2, and capsules and boxes centred on the short
// side had no contact. Here the bodies sit on a short side of 2^-44 to 2^-100 (with the found
// corners too, offset from the origin as the fuzzer had them); each holds the corner inside.
TEST(MeshQuery, BodiesAtANeedlesShortSideFarFromItsTipTouchIt) {
  const Quat turned = glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f});
  const float o = -8.36802414e-08f;
  std::vector<std::array<Vec3, 3>> needles{
      {Vec3(5.24809316e-08f, -7.75f, -7.5f) + Vec3(o), Vec3(o), Vec3(-5.68434189e-14f, 0.0f, 0.0f) + Vec3(o)}};
  for (int e = 44; e <= 100; e += 4) {
    needles.push_back({Vec3(0.0f, -7.75f, -7.5f), Vec3(0.0f), Vec3(-std::ldexp(1.0f, -e), 0.0f, 0.0f)});
  }
  for (const auto& corners : needles) {
    const std::vector<Vec3> v(corners.begin(), corners.end());
    const TriangleMesh mesh = make_triangle_mesh(v, std::vector<glm::uvec3>{{0, 1, 2}});
    for (const float r : {2.13623047e-4f, 0.01f}) {
      const std::vector<Vec3> octahedron{{2 * r, 0, 0}, {-2 * r, 0, 0}, {0, 2 * r, 0}, {0, -2 * r, 0}, {0, 0, 2 * r}, {0, 0, -2 * r}};
      const Transform3 at{corners[1], turned};
      const auto check = [&](const Manifold3& m, const char* what) {
        ASSERT_GT(m.count, 0) << what << " side " << distance(corners[1], corners[2]) << " r " << r;
        EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f) << what;
        for (int i = 0; i < m.count; ++i) EXPECT_LE(m.points[i].depth, 4.0f * r) << what;
      };
      check(contact(make_sphere(Vec3(0.0f), r), at, mesh, Transform3{}), "sphere");
      check(contact(make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r), at, mesh, Transform3{}), "capsule");
      check(contact(make_box(Vec3(r, 1.25f * r, 1.5f * r)), at, mesh, Transform3{}), "box");
      check(contact(make_convex_hull(octahedron), at, mesh, Transform3{}), "hull");
    }
  }
}

// Found by fuzz_shapes' capsule check (finding 19): two triangles folded 23 degrees apart about
// a shared edge make a thin crease, its edge inactive (concave seen from the fronts). A capsule
// behind the crease's ridge, its core reaching across both planes beyond the edge, touched each
// triangle from the side its centre was not on; the active-edge correction turned each contact
// to the face on its centre's side, found no depth along it, and dropped both. Now the face the
// replaced normal goes through from A is taken then. Capsules placed about the ridge in every
// direction touch the mesh whenever their core comes within their radius of a triangle (brute
// force, in double: before, 44 of about 1,500 such capsules had no contact, some 1.5 deep);
// boxes whenever they overlap one (they held before too).
TEST(MeshQuery, CapsulesAndBoxesAtTheRidgeOfAThinCreaseTouchIt) {
  const std::vector<Vec3> v{{8.0f, 8.0f, -0.5f}, {8.0f, 8.0f, 13.5f}, {5.0f, 6.75f, 2.5f}, {-5.5f, -5.75f, 0.0f}};
  const TriangleMesh mesh = make_triangle_mesh(v, std::vector<glm::uvec3>{{0, 1, 2}, {1, 0, 3}});
  ASSERT_EQ(mesh.active_edges[0] & 1u, 0u);  // the shared edge is inactive
  const auto segment_triangle = [](test::DVec3 p, test::DVec3 q, const std::array<test::DVec3, 3>& t) {
    if (test::segment_crosses_triangle(p, q, t[0], t[1], t[2])) return 0.0;
    double d2 = std::min(test::point_triangle_d2(p, t[0], t[1], t[2]), test::point_triangle_d2(q, t[0], t[1], t[2]));
    for (int k = 0; k < 3; ++k) d2 = std::min(d2, test::segment_segment_d2(p, q, t[k], t[(k + 1) % 3]));
    return std::sqrt(d2);
  };
  const std::array<test::DVec3, 3> t0{test::DVec3(v[0]), test::DVec3(v[1]), test::DVec3(v[2])};
  const std::array<test::DVec3, 3> t1{test::DVec3(v[1]), test::DVec3(v[0]), test::DVec3(v[3])};
  std::mt19937 rng(19);
  int touching = 0;
  for (int i = 0; i < 4000; ++i) {
    const float r = test::uniform(rng, 0.2f, 2.0f);
    const Vec3 centre = Vec3(8.0f, 8.0f, test::uniform(rng, 0.0f, 13.0f)) + test::uniform(rng, 0.0f, 3.0f) * test::random_unit3(rng);
    const Transform3 xa{centre, test::random_rotation(rng)};
    const Capsule3 capsule = make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r);
    const test::DVec3 p = test::to_world(xa, capsule.a), q = test::to_world(xa, capsule.b);
    const double gap = std::min(segment_triangle(p, q, t0), segment_triangle(p, q, t1)) - r;
    if (gap > -1e-3) continue;
    ++touching;
    const Manifold3 m = contact(capsule, xa, mesh, Transform3{});
    ASSERT_GT(m.count, 0) << i << " gap " << gap;
    EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f) << i;
  }
  EXPECT_GT(touching, 1000);
  // Boxes the same, against the exact Minkowski difference of box and triangle (hull_pairs.hpp).
  int boxes = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 half(test::uniform(rng, 0.1f, 2.0f), test::uniform(rng, 0.1f, 2.0f), test::uniform(rng, 0.1f, 2.0f));
    std::vector<Vec3> corners;
    for (int k = 0; k < 8; ++k) corners.emplace_back(k & 1 ? half.x : -half.x, k & 2 ? half.y : -half.y, k & 4 ? half.z : -half.z);
    const ConvexHull hull = make_convex_hull(corners);
    const Vec3 centre = Vec3(8.0f, 8.0f, test::uniform(rng, 0.0f, 13.0f)) + test::uniform(rng, 0.0f, 3.0f) * test::random_unit3(rng);
    const Transform3 xa{centre, test::random_rotation(rng)};
    const double depth = std::max(test::minkowski_reference(hull, xa, t0).depth(), test::minkowski_reference(hull, xa, t1).depth());
    if (depth < 1e-3) continue;
    ++boxes;
    const Manifold3 m = contact(make_box(half), xa, mesh, Transform3{});
    ASSERT_GT(m.count, 0) << i << " depth " << depth;
    EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f) << i;
  }
  EXPECT_GT(boxes, 500);
}

TEST(MeshQuery, BoxSlidingOverSeamsOfAHeightFieldGetsFaceNormal) {
  const Terrain flat = make_terrain(21, 0.5f, [](float, float) { return 1.0f; });
  const Box box = make_box({0.3f, 0.3f, 0.3f});
  int tilted = 0, contacts = 0;
  for (int step = 0; step <= 600; ++step) {
    const Transform3 xb{{0.5f + 0.013f * float(step), 1.29f, 4.1f}, Quat{1, 0, 0, 0}};
    contact(box, xb, flat.field, Transform3{}, 0.0f, [&](std::uint32_t, const Manifold3& m) {
      ++contacts;
      if (1.0f - std::fabs(m.normal.y) > 1e-6f) ++tilted;
      return true;
    });
  }
  EXPECT_EQ(tilted, 0);
  EXPECT_GT(contacts, 600);
}

// Brute force on random triangle soups: the BVH answers equal the loop over every triangle.
TEST(MeshQuery, RandomSoupAgainstBruteForce) {
  std::mt19937 rng(21);
  int overlaps = 0, apart = 0, within = 0, beyond = 0;
  for (int mesh_iter = 0; mesh_iter < 6; ++mesh_iter) {
    std::vector<Vec3> vertices;
    std::vector<glm::uvec3> triangles;
    for (unsigned t = 0; t < 300; ++t) {
      const Vec3 c = test::random_point3(rng, 6.0f);
      for (int k = 0; k < 3; ++k) vertices.push_back(c + test::random_point3(rng, 0.8f));
      triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
    const Transform3 xm = test::random_transform3(rng, 3.0f);
    for (int iter = 0; iter < 150; ++iter) {
      const Shape3D shape = test::random_shape3(rng, 0.7f);
      const Transform3 xa{transform_point(xm, test::random_point3(rng, 6.0f)), test::random_rotation(rng)};
      bool any = false;
      bool any_contact = false;
      float best = std::numeric_limits<float>::infinity();
      for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
        const Triangle tri = world_triangle(mesh, t);
        std::visit(
            [&](const auto& a) {
              any = any || overlap(a, xa, tri, xm);
              any_contact = any_contact || contact(a, xa, tri, xm).touching();
              best = std::min(best, distance(a, xa, tri, xm).distance);
            },
            shape);
      }
      EXPECT_EQ(overlap(shape, xa, mesh, xm), any) << mesh_iter << " " << iter;
      EXPECT_EQ(contact(shape, xa, mesh, xm).touching(), any_contact) << mesh_iter << " " << iter;
      std::uint32_t tri = 0;
      const DistanceResult3 d = distance(shape, xa, mesh, xm, std::numeric_limits<float>::infinity(), &tri);
      EXPECT_NEAR(d.distance, best, 1e-4f) << mesh_iter << " " << iter;
      EXPECT_LT(tri, mesh.triangle_count());
      (any ? overlaps : apart)++;
      // Bounded: "anything within 0.5?"
      const DistanceResult3 b = distance(shape, xa, mesh, xm, 0.5f, &tri);
      if (best <= 0.5f - 1e-4f) {
        EXPECT_NEAR(b.distance, best, 1e-4f);
        ++within;
      } else if (best > 0.5f + 1e-4f) {
        EXPECT_EQ(b.distance, std::numeric_limits<float>::infinity());
        EXPECT_EQ(tri, std::numeric_limits<std::uint32_t>::max());
        ++beyond;
      }
    }
  }
  EXPECT_GT(overlaps, 150);
  EXPECT_GT(apart, 150);
  EXPECT_GT(within, 100);
  EXPECT_GT(beyond, 100);
}

// The per-triangle early out (the bounding box and plane axes) drops no triangle a contact
// needs: shapes placed so their nearest triangle grazes them at the margin (within float
// rounding) or pushed a little further in, and the triangles the mesh query reports compared
// with each triangle's own contact (the convex-triangle query): one it finds deeper than
// -margin by more than the tolerance must be reported, one farther than the margin by more than
// it must not.
TEST(MeshQuery, GrazingTrianglesAreAllVisited) {
  std::mt19937 rng(26);
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  for (unsigned t = 0; t < 400; ++t) {
    const Vec3 c = test::random_point3(rng, 3.0f);
    for (int k = 0; k < 3; ++k) vertices.push_back(c + test::random_point3(rng, 0.8f));
    triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
  const Transform3 xm = test::random_transform3(rng, 3.0f);
  constexpr float kBand = 1e-4f;  // contacts this close to the margin may go either way
  int required = 0, excluded = 0, grazes = 0;
  for (int iter = 0; iter < 600; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 0.6f);
    Transform3 xa{transform_point(xm, test::random_point3(rng, 4.0f)), test::random_rotation(rng)};
    const DistanceResult3 d = distance(shape, xa, mesh, xm);
    if (!(d.distance > 0.0f) || !std::isfinite(d.distance)) continue;
    // Half the placements touch the nearest triangle, half stand off from it by the margin;
    // every other one is pushed further in.
    const float margin = iter % 2 == 0 ? 0.0f : test::uniform(rng, 0.01f, 0.2f);
    const float push = iter % 4 < 2 ? 0.0f : test::uniform(rng, 0.0f, 0.6f);
    xa.p += d.normal * (d.distance - margin + push);
    std::vector<bool> reported(mesh.triangle_count(), false);
    contact(shape, xa, mesh, xm, margin, [&](std::uint32_t t, const Manifold3& m) -> bool {
      EXPECT_TRUE(m.touching());
      reported[t] = true;
      return true;
    });
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      const Triangle tri = world_triangle(mesh, t);
      float gap = 0.0f;
      Manifold3 own;
      std::visit(
          [&](const auto& a) {
            gap = distance(a, xa, tri, xm).distance;
            own = contact(a, xa, tri, xm, margin);
          },
          shape);
      // Its deepest point's depth (negative for a speculative contact; max_depth floors at 0).
      float deepest = -std::numeric_limits<float>::infinity();
      for (int i = 0; i < own.count; ++i) deepest = std::max(deepest, own.points[i].depth);
      if (deepest > kBand - margin) {
        EXPECT_TRUE(reported[t]) << iter << " triangle " << t << " depth " << deepest;
        ++required;
      } else if (gap > margin + kBand) {
        EXPECT_FALSE(reported[t]) << iter << " triangle " << t << " gap " << gap;
        ++excluded;
      } else {
        ++grazes;
      }
    }
  }
  EXPECT_GT(required, 120);
  EXPECT_GT(excluded, 100000);
  EXPECT_GT(grazes, 120);
}

// A real level: random shapes near dungeon.obj's surface against the loop over all triangles.
TEST(MeshQuery, DungeonAgainstBruteForce) {
  const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + "recast/dungeon.obj");
  std::mt19937 rng(22);
  const Transform3 xm{{3.0f, -1.0f, 2.0f}, glm::angleAxis(0.4f, Vec3(0, 1, 0))};
  int overlaps = 0, apart = 0;
  for (int iter = 0; iter < 120; ++iter) {
    const std::uint32_t near = std::uniform_int_distribution<std::uint32_t>(0, mesh.triangle_count() - 1)(rng);
    const Triangle nt = world_triangle(mesh, near);
    const Vec3 centre = (nt.vertices[0] + nt.vertices[1] + nt.vertices[2]) / 3.0f;
    const Shape3D shape = test::random_shape3(rng, 0.5f);
    const Transform3 xa{transform_point(xm, centre + test::random_point3(rng, 1.0f)), test::random_rotation(rng)};
    bool any = false;
    float best = std::numeric_limits<float>::infinity();
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      std::visit(
          [&](const auto& a) {
            const Triangle tri = world_triangle(mesh, t);
            any = any || overlap(a, xa, tri, xm);
            best = std::min(best, distance(a, xa, tri, xm).distance);
          },
          shape);
    }
    EXPECT_EQ(overlap(shape, xa, mesh, xm), any) << iter;
    EXPECT_NEAR(distance(shape, xa, mesh, xm).distance, best, 1e-4f) << iter;
    const Manifold3 m = contact(shape, xa, mesh, xm);
    if (any && best == 0.0f) EXPECT_TRUE(m.touching()) << iter;
    if (!any) EXPECT_FALSE(m.touching()) << iter;
    for (int i = 0; i < m.count; ++i) EXPECT_TRUE(finite(m.points[i].point) && std::isfinite(m.points[i].depth));
    (any ? overlaps : apart)++;
  }
  EXPECT_GT(overlaps, 20);
  EXPECT_GT(apart, 20);
}

// The height field and the mesh built from the same samples give the same answers.
TEST(MeshQuery, HeightFieldMatchesEquivalentMesh) {
  const Terrain hills = make_terrain(17, 0.7f, [](float x, float z) { return 0.8f * std::sin(0.6f * x) * std::cos(0.5f * z); });
  for (std::uint32_t t = 0; t < hills.mesh.triangle_count(); ++t) {
    ASSERT_EQ(hills.mesh.active_edges[t], hills.field.active_edges(t)) << t;
  }
  std::mt19937 rng(23);
  const Transform3 xl = test::random_transform3(rng, 5.0f);
  int touching = 0, apart = 0;
  for (int iter = 0; iter < 600; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 0.6f);
    const Vec3 local{test::uniform(rng, -0.5f, 11.5f), test::uniform(rng, -1.5f, 1.5f), test::uniform(rng, -0.5f, 11.5f)};
    const Transform3 xa{transform_point(xl, local), test::random_rotation(rng)};
    EXPECT_EQ(overlap(shape, xa, hills.mesh, xl), overlap(shape, xa, hills.field, xl)) << iter;
    std::uint32_t tm = 0, tf = 1;
    const DistanceResult3 dm = distance(shape, xa, hills.mesh, xl, 2.0f, &tm);
    const DistanceResult3 df = distance(shape, xa, hills.field, xl, 2.0f, &tf);
    if (std::isinf(dm.distance) || std::isinf(df.distance)) {
      EXPECT_EQ(dm.distance, df.distance) << iter;
    } else {
      EXPECT_NEAR(dm.distance, df.distance, 1e-4f) << iter;
    }
    const Manifold3 mm = contact(shape, xa, hills.mesh, xl, 0.05f);
    const Manifold3 mf = contact(shape, xa, hills.field, xl, 0.05f);
    ASSERT_EQ(mm.count, mf.count) << iter;
    if (mm.count == 0) {
      ++apart;
      continue;
    }
    ++touching;
    EXPECT_GT(dot(mm.normal, mf.normal), 1.0f - 1e-5f) << iter;
    EXPECT_NEAR(mm.max_depth(), mf.max_depth(), 1e-4f) << iter;
    // Ids name the same features (vertex = sample = mesh vertex, edge 3t + k, face t); which
    // of two coincident points on a shared edge is kept may differ with the visiting order.
    for (int i = 0; i < mf.count; ++i) {
      const ContactId id = mf.points[i].id;
      const std::uint32_t bound = id.type_b == FeatureType::vertex ? 17u * 17u
                                  : id.type_b == FeatureType::edge ? 3u * hills.mesh.triangle_count()
                                                                   : hills.mesh.triangle_count();
      EXPECT_LT(id.index_b, bound) << iter;
    }
  }
  EXPECT_GT(touching, 100);
  EXPECT_GT(apart, 100);
}

TEST(MeshQuery, HeightFieldHolesHaveNoTriangles) {
  std::vector<float> heights(16, 0.0f);
  std::vector<std::uint8_t> holes(9, 0);
  holes[4] = 1;  // the middle cell
  const HeightField field = make_height_field(4, 4, heights, {1.0f, 1.0f}, Vec3(0.0f), holes);
  const Sphere s = make_sphere(Vec3(0.0f), 0.3f);
  EXPECT_FALSE(overlap(s, Transform3{{1.5f, 0.0f, 1.5f}, Quat{1, 0, 0, 0}}, field, Transform3{}));
  EXPECT_FALSE(contact(s, Transform3{{1.5f, 0.1f, 1.5f}, Quat{1, 0, 0, 0}}, field, Transform3{}).touching());
  EXPECT_TRUE(overlap(s, Transform3{{0.5f, 0.1f, 1.5f}, Quat{1, 0, 0, 0}}, field, Transform3{}));
  // The hole's rim is a boundary: its edges are active.
  EXPECT_EQ(field.active_edges(2 * 3 + 1) & active_edge_bit(1), active_edge_bit(1));
}

// Finding 22: triangles are two-sided, and so are their active edges. A spike pointing down out
// of a flat field: every edge at its tip is concave seen from above (inactive there) and convex
// from below. A body under the tip touches the tip; with one-sided active edges the correction
// turned its normal to a face's (across which the body has no depth) and the contact was
// dropped. Under the field and under the same terrain as a mesh: spheres and upright capsules
// whose top sphere's centre is on a line through the tip, down and a little to the side (the tip
// stays the nearest feature: the spike's faces are 66 degrees steep), normal along that line;
// boxes with their top face level under the tip, normal straight up.
TEST(MeshQuery, BodiesUnderASpikeTouchItsTipFromBelow) {
  const Vec3 tip(2.0f, -2.25f, 2.0f);
  const Terrain spike = make_terrain(5, 1.0f, [&](float x, float z) { return x == tip.x && z == tip.z ? tip.y : 0.0f; });
  const float r = 0.3f;
  int checked = 0;
  for (const float depth : {0.01f, 0.05f}) {
    for (const Vec2 off : {Vec2(0.0f), Vec2(0.1f, 0.0f), Vec2(-0.05f, 0.08f)}) {
      const auto check = [&](const auto& body, const Transform3& xa, Vec3 normal, const char* what) {
        for (const bool use_field : {false, true}) {
          const Manifold3 m = use_field ? contact(body, xa, spike.field, Transform3{}) : contact(body, xa, spike.mesh, Transform3{});
          const std::string where = std::string(what) + (use_field ? " field" : " mesh") + " depth " +
                                    std::to_string(depth) + " off " + std::to_string(off.x) + " " + std::to_string(off.y);
          ASSERT_GT(m.count, 0) << where;
          EXPECT_NEAR(dot(m.normal, normal), 1.0f, 1e-5f) << where;
          EXPECT_NEAR(m.max_depth(), depth, 1e-4f) << where;
          ++checked;
        }
      };
      const Vec3 down = glm::normalize(Vec3(off.x, -1.0f, off.y));
      const Vec3 centre = tip + (r - depth) * down;  // the (top) sphere's centre
      check(make_sphere(Vec3(0.0f), r), Transform3{centre, Quat{1, 0, 0, 0}}, -down, "sphere");
      check(make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r), Transform3{centre - Vec3(0.0f, r, 0.0f), Quat{1, 0, 0, 0}},
            -down, "capsule");
      const Vec3 box_centre(tip.x + off.x, tip.y + depth - 0.5f * r, tip.z + off.y);
      check(make_box(Vec3(r, 0.5f * r, r)), Transform3{box_centre, Quat{1, 0, 0, 0}}, Vec3(0.0f, 1.0f, 0.0f), "box");
    }
  }
  EXPECT_EQ(checked, 2 * 3 * 3 * 2);
}

// 1e4 from the origin: the same answers as near it (within float spacing there), never NaN.
TEST(MeshQuery, FarFromOrigin) {
  const Terrain hills = make_terrain(17, 0.7f, [](float x, float z) { return 0.5f * std::sin(0.6f * x) * std::cos(0.5f * z); });
  std::mt19937 rng(24);
  const Vec3 far{1.0e4f, -2.0e3f, -1.0e4f};
  int touching = 0;
  for (int iter = 0; iter < 300; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 0.6f);
    const Vec3 local{test::uniform(rng, 0.5f, 10.5f), test::uniform(rng, -1.0f, 1.0f), test::uniform(rng, 0.5f, 10.5f)};
    const Quat q = test::random_rotation(rng);
    const Transform3 xa{local, q}, xa_far{local + far, q};
    const Transform3 xl{}, xl_far{far, Quat{1, 0, 0, 0}};
    for (const bool field : {false, true}) {
      const Manifold3 m = field ? contact(shape, xa, hills.field, xl, 0.02f) : contact(shape, xa, hills.mesh, xl, 0.02f);
      const Manifold3 f = field ? contact(shape, xa_far, hills.field, xl_far, 0.02f) : contact(shape, xa_far, hills.mesh, xl_far, 0.02f);
      ASSERT_TRUE(finite(f.normal));
      for (int i = 0; i < f.count; ++i) ASSERT_TRUE(finite(f.points[i].point) && std::isfinite(f.points[i].depth));
      if (m.touching() && m.max_depth() > 5e-3f) {
        ASSERT_TRUE(f.touching()) << iter;
        EXPECT_NEAR(m.max_depth(), f.max_depth(), 2e-3f) << iter;
        EXPECT_GT(dot(m.normal, f.normal), 0.999f) << iter;
        ++touching;
      }
      const DistanceResult3 d = field ? distance(shape, xa, hills.field, xl) : distance(shape, xa, hills.mesh, xl);
      const DistanceResult3 e = field ? distance(shape, xa_far, hills.field, xl_far) : distance(shape, xa_far, hills.mesh, xl_far);
      ASSERT_TRUE(std::isfinite(e.distance) && finite(e.point_a) && finite(e.point_b));
      EXPECT_NEAR(d.distance, e.distance, 2e-3f) << iter;
    }
  }
  EXPECT_GT(touching, 100);
}

// Property: moving A back along the reported normal by the depth plus eps separates it from the
// terrain; by the depth minus eps it still overlaps. Gentle hills (slopes under 20 degrees, so
// every touching triangle joins the merged manifold).
TEST(MeshQuery, DepthPropertyOnTerrain) {
  const auto hill = [](float x, float z) { return 0.4f * std::sin(0.6f * x) * std::cos(0.5f * z); };
  const Terrain hills = make_terrain(17, 0.7f, hill);
  std::mt19937 rng(25);
  int checked = 0, short_depth = 0, long_depth = 0;
  for (int iter = 0; iter < 1500; ++iter) {
    const Shape3D shape = test::random_shape3(rng, 0.4f);
    // A landing on or resting in the terrain from above (a shape sunk through a two-sided
    // surface may be pushed out of either side, triangle by triangle).
    const float x = test::uniform(rng, 1.0f, 10.0f), z = test::uniform(rng, 1.0f, 10.0f);
    const Vec3 local{x, hill(x, z) + test::uniform(rng, 0.1f, 0.4f), z};
    const Transform3 xa{local, test::random_rotation(rng)};
    const bool field = iter % 2 == 1;
    const Manifold3 m = field ? contact(shape, xa, hills.field, Transform3{}) : contact(shape, xa, hills.mesh, Transform3{});
    if (!m.touching() || m.max_depth() < 2e-3f) continue;
    const float depth = m.max_depth();
    const float eps = 1e-3f;
    Transform3 out = xa, in = xa;
    out.p -= (depth + eps) * m.normal;
    in.p -= (depth - eps) * m.normal;
    const bool o_out = field ? overlap(shape, out, hills.field, Transform3{}) : overlap(shape, out, hills.mesh, Transform3{});
    const bool o_in = field ? overlap(shape, in, hills.field, Transform3{}) : overlap(shape, in, hills.mesh, Transform3{});
    // Short depths (the clip keeps the part of an incident face over the reference face, see
    // triangle_query_test) are counted and held to a small share.
    // On a mesh the merged manifold also re-projects neighbouring triangles' depths onto the
    // deepest one's normal (depth / cos), which can overstate: both counted, held to small
    // shares (measured: 27 short and 2 long of 726 at the time of writing).
    if (o_out) ++short_depth;
    if (!o_in) ++long_depth;
    ++checked;
  }
  EXPECT_GT(checked, 300);
  EXPECT_LE(short_depth * 20, checked) << short_depth << " of " << checked;
  EXPECT_LE(long_depth * 100, checked) << long_depth << " of " << checked;
}

}  // namespace
}  // namespace collide
