// Level meshes from OBJ files (io::load_obj): malformed files get an error naming the file and
// line, polygons become triangles that cover them, and the real levels load with the counts
// SOURCES.md measured independently.
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace collide {
namespace {

/// Writes `text` to a temporary file called `name` and returns its path.
std::string write_obj(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// The message load_obj throws for `text`, or "no error".
std::string load_error(const std::string& text) {
  const std::string path = write_obj("malformed.obj", text);
  std::string message = "no error";
  try {
    (void)io::load_obj(path);
  } catch (const InvalidInput& e) {
    message = e.what();
  }
  std::remove(path.c_str());
  return message;
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";

TEST(ObjLevel, MalformedFilesNameTheFileLineAndProblem) {
  // What tinyobjloader alone reads silently as 0 (a vertex moved to the origin) or skips.
  EXPECT_EQ(load_error("v 0 0 0\nv nan 0 0\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:2: vertex 2: coordinate x 'nan' is not finite");
  EXPECT_EQ(load_error("v 0 0 0\nv 1 -inf 0\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:2: vertex 2: coordinate y '-inf' is not finite");
  EXPECT_EQ(load_error("v 0 0 0\nv 1 0 abc\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:2: vertex 2: coordinate z 'abc' is not a number");
  EXPECT_EQ(load_error("v 0 0 0\nv 1 0 1.5x\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:2: vertex 2: coordinate z '1.5x' is not a number");
  EXPECT_EQ(load_error("v 0 0 0\nv 1e39 0 0\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:2: vertex 2: coordinate x '1e39' is out of float range");
  EXPECT_EQ(load_error("# a level\nv 0 0 0\n\nv 1 0\nv 0 0 1\nf 1 2 3\n"),
            "malformed.obj:4: vertex 2: 2 coordinates, need 3 (x y z)");
  // Faces: bad references, as written in the file (OBJ counts from 1; negative is relative).
  EXPECT_EQ(load_error(kTriangle + "f 1 2 3\nf 1 2 9\n"), "malformed.obj:5: face 2: vertex index 9 out of range (3 vertices)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 -4\n"),
            "malformed.obj:4: face 1: vertex index -4 points before the first vertex (3 vertices so far)");
  EXPECT_EQ(load_error(kTriangle + "f 1 0 3\n"),
            "malformed.obj:4: face 1: vertex reference '0' is not a vertex index (a non-zero integer; OBJ counts from 1)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 x/1\n"),
            "malformed.obj:4: face 1: vertex reference 'x/1' is not a vertex index (a non-zero integer; OBJ counts from 1)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 3q\n"),
            "malformed.obj:4: face 1: vertex reference '3q' is not a vertex index (a non-zero integer; OBJ counts from 1)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2\n"), "malformed.obj:4: face 1: 2 vertices, need at least 3");
  // Nothing to walk on.
  EXPECT_EQ(load_error(""), "malformed.obj: no faces (no 'f' statement)");
  EXPECT_EQ(load_error(kTriangle), "malformed.obj: no faces (no 'f' statement)");
  EXPECT_EQ(load_error("\x01\x02 binary \xff\n"), "malformed.obj: no faces (no 'f' statement)");
  // A polygon that crosses itself (a bow-tie): named, not folded over itself. (A concave one is
  // triangulated: tests/io/obj_reader_test.cpp.)
  EXPECT_EQ(load_error("v 0 0 0\nv 2 0 2\nv 2 0 0\nv 0 0 2\nf 1 2 3 4\n"),
            "malformed.obj:5: face 1: polygon is self-intersecting: edge 0-1 meets edge 2-3");
  // The file itself.
  try {
    (void)io::load_obj(::testing::TempDir() + "no_such_level.obj");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_level.obj: file not found"), std::string::npos) << e.what();
  }
}

TEST(ObjLevel, WhatTheFormatAllowsIsRead) {
  // CRLF and CR line ends, comments, objects and groups, negative (relative) references,
  // v/vt/vn references, a leading '+', an underflowing coordinate (a valid 0), a fourth (w)
  // coordinate, and statements the walk mesh does not use.
  const std::string text =
      "# header\r\nmtllib level.mtl\r\no floor\r\nv +1 0 0\r\nv 0 0 1e-50\r\nv 0 0 1 1\r\nvt 0 0\r\nvn 0 1 0\r\n"
      "g a\r\nusemtl stone\r\nf -3/1/1 -1/1/1 -2/1/1\rv 5 0 5\rf 1//1 4 2\nl 1 2\n";
  const std::string path = write_obj("allowed.obj", text);
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  EXPECT_EQ(soup.name, "allowed.obj");
  ASSERT_EQ(soup.positions.size(), 4u);
  EXPECT_EQ(soup.positions[0], Vec3(1, 0, 0));
  EXPECT_EQ(soup.positions[1], Vec3(0, 0, 0));
  EXPECT_EQ(soup.positions[2], Vec3(0, 0, 1));
  EXPECT_EQ(soup.positions[3], Vec3(5, 0, 5));
  ASSERT_EQ(soup.triangles.size(), 2u);
  EXPECT_EQ(soup.triangles[0], glm::uvec3(0, 2, 1));
  EXPECT_EQ(soup.triangles[1], glm::uvec3(0, 3, 1));
}

/// Twice the signed area of a polygon in the xz plane seen from +y (shoelace formula), and of a
/// triangle.
double twice_area_xz(const std::vector<Vec3>& p) {
  double a = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 u = p[i], v = p[(i + 1) % p.size()];
    a += static_cast<double>(u.z) * v.x - static_cast<double>(u.x) * v.z;
  }
  return a;
}

TEST(ObjLevel, PolygonsBecomeTrianglesThatCoverThem) {
  // Convex and non-convex quads (the reflex corner on either diagonal), a convex hexagon and
  // pentagon: the triangles are wound as the polygon and their areas add up
  // to its area (shoelace), so they cover it without folding.
  const std::vector<std::vector<Vec3>> polygons{
      {{0, 0, 0}, {0, 0, 4}, {4, 0, 4}, {4, 0, 0}},
      {{0, 0, 0}, {0, 0, 4}, {1, 0, 1}, {4, 0, 0}},  // dart, reflex at the third corner
      {{4, 0, 0}, {1, 0, 1}, {0, 0, 4}, {0, 0, 0}},  // dart, reflex at the second corner: the other diagonal
      {{2, 0, 0}, {0, 0, 1}, {0, 0, 3}, {2, 0, 4}, {4, 0, 3}, {4, 0, 1}},
      {{0, 0, 0}, {4, 0, 0}, {5, 0, 3}, {2, 0, 5}, {-1, 0, 3}},
  };
  std::string text;
  for (const auto& polygon : polygons) {
    for (const Vec3& v : polygon) text += "v " + std::to_string(v.x) + " " + std::to_string(v.y) + " " + std::to_string(v.z) + "\n";
    text += "f";
    for (std::size_t i = 0; i < polygon.size(); ++i) text += " -" + std::to_string(polygon.size() - i);
    text += "\n";
  }
  const std::string path = write_obj("polygons.obj", text);
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  std::size_t next = 0;
  for (const auto& polygon : polygons) {
    const double whole = twice_area_xz(polygon);
    double sum = 0.0;
    for (std::size_t k = 0; k + 2 < polygon.size(); ++k) {
      ASSERT_LT(next, soup.triangles.size());
      const glm::uvec3 t = soup.triangles[next++];
      const double piece = twice_area_xz({soup.positions[t.x], soup.positions[t.y], soup.positions[t.z]});
      EXPECT_GT(piece * whole, 0.0);  // wound as the polygon
      sum += piece;
    }
    EXPECT_NEAR(sum, whole, 1e-9 * std::fabs(whole));
  }
  EXPECT_EQ(next, soup.triangles.size());
}

// Issue 15: tests/data/ngon_level.obj, floors of concave 8- to 12-gons joined by ramps (which a
// fan could not cover), as a walk mesh: one island of exactly the floors' and ramps' area
// (shoelace, by hand), no T-junction to split, and a walk from the ground floor up the ramp ends
// on the platform at the height the geometry gives.
TEST(ObjLevel, ConcaveNgonFloorsBecomeOneWalkableIsland) {
  const TriangleSoup soup = io::load_obj(std::string(COLLIDE_TEST_DATA_DIR) + "/ngon_level.obj");
  ASSERT_EQ(soup.positions.size(), 36u);
  ASSERT_EQ(soup.triangles.size(), 34u);  // n - 2 for each face: 10 + 2 + 8 + 2 + 6 + 6
  const WalkMesh mesh = make_walk_mesh(soup);
  const WalkMeshStats& s = mesh.stats();
  EXPECT_EQ(s.too_steep_triangles, 6u);  // the wall
  EXPECT_EQ(s.degenerate_triangles, 0u);
  EXPECT_EQ(s.t_junction_splits, 0u);
  EXPECT_EQ(s.islands, 1u);
  EXPECT_EQ(mesh.triangle_count(), 28u);
  double area = 0.0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) area += mesh.triangle_area(t);
  const double ramps = (10.0 + 6.0) * std::sqrt(40.0);  // width x slanted length (6 across, 2 up)
  EXPECT_NEAR(area, 500.0 + 272.0 + 188.0 + ramps, 1e-3);
  // From the middle of the cross, 25 east (a walk keeps its length over edges): 15 over the
  // floor, sqrt(40) up the ramp (6 across, 2 up), the rest on the platform.
  const WalkResult r = mesh.walk(mesh.nearest_walk_point({15.0f, 0.0f, 15.0f}), {25.0f, 0.0f, 0.0f});
  EXPECT_EQ(r.status, WalkStatus::completed);
  const Vec3 end = mesh.to_world_point(r.end);
  EXPECT_NEAR(end.x, 36.0 + (25.0 - 15.0 - std::sqrt(40.0)), 1e-3);
  EXPECT_NEAR(end.y, 2.0f, 1e-3f);
  EXPECT_NEAR(end.z, 15.0f, 1e-3f);
  // On into the platform's notch (x > 44 between z 10 and 20 is open): the walk meets its wall.
  const WalkResult on = mesh.walk(r.end, {10.0f, 0.0f, 0.0f});
  EXPECT_GT(on.walls_hit, 0);
  EXPECT_LE(mesh.to_world_point(on.end).x, 44.0f + 1e-3f);
}

TEST(ObjLevel, RealLevelsLoadWithTheirMeasuredCounts) {
  // SOURCES.md counts, from its own OBJ parsing with fan triangulation.
  struct Expected {
    const char* file;
    std::size_t vertices, triangles;
  };
  for (const Expected& e : {Expected{"recast/dungeon.obj", 5101, 10133}, Expected{"recast/undulating.obj", 2800, 5202},
                            Expected{"fcl/env.obj", 6540, 2180}}) {  // env.obj opens with a non-standard "6540 2180" line
    const TriangleSoup soup = io::load_obj(std::string(COLLIDE_DATA_DIR) + "/meshes/" + e.file);
    EXPECT_EQ(soup.positions.size(), e.vertices) << e.file;
    EXPECT_EQ(soup.triangles.size(), e.triangles) << e.file;
  }
}

TEST(ObjLevel, DegenerateLevelTrianglesAreCountedAsSuchNotAsTooSteep) {
  const std::string path = write_obj("line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n");
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  const WalkMesh mesh = make_walk_mesh(soup);
  EXPECT_EQ(mesh.stats().degenerate_triangles, 1u);
  EXPECT_EQ(mesh.stats().too_steep_triangles, 0u);
  EXPECT_EQ(mesh.triangle_count(), 1u);
  TriangleSoup only_line = soup;
  only_line.triangles.pop_back();
  try {
    (void)make_walk_mesh(only_line);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "line.obj: no walkable triangles (0 too steep, 1 degenerate, 0 without headroom for the agent)");
  }
}

// Issue 15: a level with coordinates near +-3.4e38 on both sides overflowed the BVH query's stack
// in make_walk_mesh (its local coordinates overflowed to infinity). No float frame holds such a
// level: both builders now refuse it by name, before any local coordinate is computed. (Run
// under the sanitize preset; the BVH's own regression test is in tests/shape.)
TEST(ObjLevel, CoordinatesNearTheFloatLimitOnBothSidesAreRefusedNotOverflowed) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::ostringstream text;
  text.precision(9);
  const int n = 300;
  for (int i = 0; i < 3 * n; ++i) text << "v " << 3.3e38f * unit(rng) << ' ' << 3.3e38f * unit(rng) << ' ' << 3.3e38f * unit(rng) << '\n';
  for (int i = 0; i < n; ++i) text << "f " << 3 * i + 1 << ' ' << 3 * i + 2 << ' ' << 3 * i + 3 << '\n';
  const std::string path = write_obj("huge.obj", text.str());
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  ASSERT_EQ(soup.triangles.size(), static_cast<std::size_t>(n));
  const std::string expected = "huge.obj: spans more than float range (coordinates near +-3.4e38 on both sides); no float frame holds it";
  for (int builder = 0; builder < 2; ++builder) {
    try {
      (void)(builder == 0 ? make_walk_mesh(soup) : build_walk_mesh(soup));
      ADD_FAILURE() << "no error";
    } catch (const InvalidInput& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  }
}

}  // namespace
}  // namespace collide
