// Every input the shape fuzzer found a defect with (fuzz/regressions/shapes/) and its seeds,
// replayed through the fuzz target's own check (fuzz/shapes_check.hpp).

#include "shapes_check.hpp"

#include <collide/core/error.hpp>

#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace collide {
namespace {

namespace fs = std::filesystem;

int replay(const fs::path& folder) {
  return test::replay_files(folder, [](const std::string& input) { return fuzz::check_shapes(input); });
}

TEST(ShapesFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "shapes");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "shapes"), 14);
}

// The recipe decoder the check reads inputs with: small values, special ones, raw bytes, and
// zeros past the end.
TEST(ShapesFuzzRegressions, RecipesDecodeAsDocumented) {
  const char bytes[] = {36, 0, 66, static_cast<char>(200), 0x3f, static_cast<char>(0x80), 0, 0};
  fuzz::FuzzFloats in({bytes, sizeof bytes});
  EXPECT_EQ(in.number(), 1.0f);    // (36 - 32) / 4
  EXPECT_EQ(in.number(), -8.0f);   // (0 - 32) / 4
  EXPECT_TRUE(std::isnan(in.number()));  // special value 2
  EXPECT_EQ(in.number(), 1.0f);    // raw 0x3f800000
  EXPECT_EQ(in.number(), -8.0f);   // past the end: byte 0
}

// The hull recipe's plane check (check_hull_planes) passes a built hull and catches a plane moved
// in: a face offset lowered below a vertex, and, with the cap above the point count, one lowered
// by more than the tolerance below an input point.
TEST(ShapesFuzzRegressions, HullPlaneCheckCatchesPlanesMovedIn) {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i) points.push_back({i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, i & 4 ? 1.0f : -1.0f});
  points.push_back({0.2f, 0.1f, -0.3f});
  const ConvexHull hull = make_convex_hull(points);
  ASSERT_EQ(hull.faces.size(), 6u);
  EXPECT_EQ(fuzz::check_hull_planes(hull, points, kMaxHullVertices), "");
  ConvexHull moved = hull;
  moved.faces[2].offset -= 0.5f;  // below the face's own vertices
  EXPECT_EQ(fuzz::check_hull_planes(moved, points, kMaxHullVertices), "convex hull: a vertex lies above a face plane");
  // Only input points above the plane: an extra point beyond the face, not a vertex.
  std::vector<Vec3> beyond = points;
  const Vec3 n = hull.faces[2].normal;
  beyond.push_back(n * (hull.faces[2].offset + 3.0f * hull.tolerance));
  EXPECT_EQ(fuzz::check_hull_planes(hull, beyond, kMaxHullVertices),
            "convex hull: an input point lies more than the tolerance above a face plane");
  // The same point within the tolerance passes; past the cap nothing is promised of it.
  beyond.back() = n * (hull.faces[2].offset + 0.5f * hull.tolerance);
  EXPECT_EQ(fuzz::check_hull_planes(hull, beyond, kMaxHullVertices), "");
  beyond.back() = n * (hull.faces[2].offset + 3.0f * hull.tolerance);
  EXPECT_EQ(fuzz::check_hull_planes(hull, beyond, 4), "");
}

// The mesh recipe's oracle fails on a tree that answers for other triangles: a corner moved
// after the build (the BVH still holds the old one) is nearer a probe than the tree's answer.
TEST(ShapesFuzzRegressions, MeshNearestCheckCatchesAWrongTree) {
  const std::vector<Vec3> vertices{{0.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f},
                                   {5.0f, 0.0f, 1.0f}, {7.0f, 0.0f, 1.0f}, {5.0f, 2.0f, 1.0f}};
  TriangleMesh mesh = make_triangle_mesh(vertices, std::vector<glm::uvec3>{{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(fuzz::check_mesh_nearest(mesh), "");
  mesh.vertices[mesh.triangles[1].x] += Vec3(0.0f, 0.0f, 0.5f);  // (the tree keeps the corner where it was)
  EXPECT_EQ(fuzz::check_mesh_nearest(mesh), "triangle mesh: the BVH's nearest distance differs from the nearest triangle's");
}

// The contact oracle fails where the level query misses a triangle: a corner moved towards the
// probe after the build (the BVH's box is where it was) is touched by each body, and the
// contact, which finds triangles through the tree, has none. Each body kind is asked on its own.
TEST(ShapesFuzzRegressions, MeshContactCheckCatchesADroppedContact) {
  const std::vector<Vec3> vertices{{0.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}};
  TriangleMesh mesh = make_triangle_mesh(vertices, std::vector<glm::uvec3>{{0, 1, 2}});
  const Vec3 probe = mesh.origin + mesh.corner(0, 0) + Vec3(0.5f, 0.5f, 3.0f);  // 3 above the triangle
  EXPECT_EQ(fuzz::check_level_contact(mesh, probe, 3.0, 1e-6, 0.0f), "");
  for (const std::uint32_t v : {mesh.triangles[0].x, mesh.triangles[0].y, mesh.triangles[0].z}) {
    mesh.vertices[v] += Vec3(0.0f, 0.0f, 2.9f);  // 0.1 below the probe now, the tree's box 3 below
  }
  EXPECT_EQ(fuzz::check_level_contact(mesh, probe, 0.1, 1e-6, 0.0f),
            "triangle mesh: a sphere reaching past the nearest triangle has no contact");
  const Transform3 at{probe, glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f})};
  const std::vector<Vec3> octahedron{{0.4f, 0, 0}, {-0.4f, 0, 0}, {0, 0.4f, 0}, {0, -0.4f, 0}, {0, 0, 0.4f}, {0, 0, -0.4f}};
  EXPECT_EQ(fuzz::check_level_touch(mesh, make_capsule(Vec3(0, -0.2f, 0), Vec3(0, 0.2f, 0), 0.2f), at, "capsule"),
            "triangle mesh: a capsule reaching past the nearest triangle has no contact");
  EXPECT_EQ(fuzz::check_level_touch(mesh, make_box(Vec3(0.2f, 0.25f, 0.3f)), at, "box"),
            "triangle mesh: a box reaching past the nearest triangle has no contact");
  EXPECT_EQ(fuzz::check_level_touch(mesh, make_convex_hull(octahedron), at, "hull"),
            "triangle mesh: a hull reaching past the nearest triangle has no contact");
}

// The cast oracle (since stop 105) fails on the same moved triangle: cast at its nearest point,
// bodies pass where the tree's boxes say nothing is.
TEST(ShapesFuzzRegressions, MeshCastCheckCatchesAMissedTriangle) {
  const std::vector<Vec3> vertices{{0.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}};
  TriangleMesh mesh = make_triangle_mesh(vertices, std::vector<glm::uvec3>{{0, 1, 2}});
  const Vec3 probe = mesh.origin + mesh.corner(0, 0) + Vec3(0.5f, 0.5f, 3.0f);  // 3 above the triangle
  EXPECT_EQ(fuzz::check_level_cast(mesh, probe, probe - Vec3(0.0f, 0.0f, 3.0f), 3.0, 1e-6, 0.0f), "");
  for (const std::uint32_t v : {mesh.triangles[0].x, mesh.triangles[0].y, mesh.triangles[0].z}) {
    mesh.vertices[v] += Vec3(0.0f, 0.0f, 2.9f);  // 0.1 below the probe now, the tree's box 3 below
  }
  EXPECT_EQ(fuzz::check_level_cast(mesh, probe, probe - Vec3(0.0f, 0.0f, 0.1f), 0.1, 1e-6, 0.0f),
            "triangle mesh: a sphere cast at the nearest triangle misses it");
}

// The same oracle on a height field (since stop 105): heights raised after the build leave the
// blocks' height ranges where they were, so the query skips the block, and the check, which
// measures the triangles as they are, finds the dropped contacts.
TEST(ShapesFuzzRegressions, HeightFieldContactCheckCatchesADroppedContact) {
  const std::vector<float> heights(16, 0.0f);
  HeightField field = make_height_field(4, 4, heights, Vec2(1.0f), Vec3(-1.5f, 0.0f, -1.5f));
  EXPECT_EQ(fuzz::check_height_field_contact(field), "");
  for (float& h : field.heights) h += 5.0f;
  EXPECT_EQ(fuzz::check_height_field_contact(field), "height field: a sphere reaching past the nearest triangle has no contact");
}

// Found by fuzz_shapes: ends 5e-32 apart passed "a and b coincide" (a == b), but their squared
// distance underflows to 0, and a ray cast divided by it (a hit with a NaN fraction). Such ends
// now coincide, in 2D and 3D, for segments and capsules; 1e-18 apart still builds.
TEST(ShapesFuzzRegressions, EndsWhoseSquaredDistanceUnderflowsCoincide) {
  const float t = -5.375e-32f;
  auto message = [](auto make) {
    try {
      make();
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string closer = " (closer than about 1e-19: their squared distance underflows float)";
  EXPECT_EQ(message([&] { (void)make_segment(Vec3(0.0f), Vec3(t)); }), "segment: a and b coincide" + closer);
  EXPECT_EQ(message([&] { (void)make_segment(Vec2(0.0f), Vec2(t)); }), "segment: a and b coincide" + closer);
  EXPECT_EQ(message([&] { (void)make_capsule(Vec3(0.0f), Vec3(t), 1.0f); }), "capsule: a and b coincide (use a sphere)" + closer);
  EXPECT_EQ(message([&] { (void)make_capsule(Vec2(0.0f), Vec2(t), 1.0f); }), "capsule: a and b coincide (use a circle)" + closer);
  EXPECT_EQ(message([&] { (void)make_segment(Vec3(1.0f), Vec3(1.0f)); }), "segment: a and b coincide");
  const Segment3 short_one = make_segment(Vec3(0.0f), Vec3(1e-18f));
  const RayHit3 hit = raycast(short_one, Transform3{}, Ray3{{-100.0f, 0.1f, 0.2f}, {200.0f, 0.0f, 0.0f}});
  EXPECT_FALSE(hit.hit);
}

}  // namespace
}  // namespace collide
