// The OBJ reader (io::load_obj, io::load_triangle_mesh) on what exporters write and on hostile
// files (issue 15): concave n-gon faces triangulated in their plane, checked against the
// shoelace area of the face as written; faces that are no polygon refused by file and line; and
// files built to overflow, exhaust memory or run for hours refused by the limit they hit.
#include <collide/ccd/raycast.hpp>
#include <collide/core/error.hpp>
#include <collide/decompose/convex_decomposition.hpp>
#include <collide/io/obj.hpp>

#include "obj_mesh_check.hpp"
#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace collide {
namespace {

namespace fs = std::filesystem;

/// Writes `text` to a temporary file called `name` and returns its path.
std::string write_obj(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// The message load_obj throws for `text` (in a file called "hostile.obj"), or "no error".
std::string load_error(const std::string& text, const io::ObjLimits& limits = {}) {
  const std::string path = write_obj("hostile.obj", text);
  std::string message = "no error";
  try {
    (void)io::load_obj(path, limits);
  } catch (const InvalidInput& e) {
    message = e.what();
  }
  std::remove(path.c_str());
  return message;
}

/// "v x y z" lines for points (x, z) of the floor at height y, then the face through them.
std::string floor_face(const std::vector<Vec2>& xz, float y) {
  std::ostringstream text;
  text.precision(9);
  for (const Vec2& p : xz) text << "v " << p.x << ' ' << y << ' ' << p.y << '\n';
  text << 'f';
  for (std::size_t i = 0; i < xz.size(); ++i) text << " -" << xz.size() - i;
  text << '\n';
  return text.str();
}

/// Twice the signed area of (x, z) points seen from +y (shoelace formula, double).
double twice_area_from_above(const std::vector<Vec2>& xz) {
  double a = 0.0;
  for (std::size_t i = 0; i < xz.size(); ++i) {
    const Vec2 u = xz[i], v = xz[(i + 1) % xz.size()];
    a += static_cast<double>(u.y) * v.x - static_cast<double>(u.x) * v.y;
  }
  return a;
}

std::vector<Vec2> scaled(std::vector<Vec2> points, float s) {
  for (Vec2& p : points) p *= s;
  return points;
}

const std::vector<Vec2> kL{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
const std::vector<Vec2> kU{{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
const std::vector<Vec2> kCross{{2, 0}, {4, 0}, {4, 2}, {6, 2}, {6, 4}, {4, 4}, {4, 6}, {2, 6}, {2, 4}, {0, 4}, {0, 2}, {2, 2}};
/// 12 vertices, four of them on straight stretches of the U's edges.
const std::vector<Vec2> kStraightU{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 1}};

std::vector<Vec2> star(int points, float outer, float inner) {
  std::vector<Vec2> out;
  for (int i = 0; i < 2 * points; ++i) {
    const double a = 3.14159265358979 * i / points;
    const float r = i % 2 == 0 ? outer : inner;
    out.push_back({r * static_cast<float>(std::cos(a)), r * static_cast<float>(std::sin(a))});
  }
  return out;
}

/// Checks that `soup` holds, from triangle `first` on, `count` triangles that tile the floor
/// face `xz`: corners among the face's vertices (the last xz.size() positions before `end`),
/// each wound as the face, their areas from above adding up to the face's (shoelace), and each
/// one's centroid inside the face (crossing number).
void expect_tiles(const TriangleSoup& soup, std::size_t first, std::size_t count, const std::vector<Vec2>& xz) {
  ASSERT_LE(first + count, soup.triangles.size());
  const double whole = twice_area_from_above(xz);
  auto inside = [&](Vec2 p) {
    bool in = false;
    for (std::size_t i = 0, j = xz.size() - 1; i < xz.size(); j = i++) {
      const Vec2 a = xz[i], b = xz[j];
      if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
    }
    return in;
  };
  double sum = 0.0;
  for (std::size_t k = first; k < first + count; ++k) {
    const glm::uvec3 t = soup.triangles[k];
    std::vector<Vec2> corners;
    for (int c = 0; c < 3; ++c) corners.push_back({soup.positions[t[c]].x, soup.positions[t[c]].z});
    const double piece = twice_area_from_above(corners);
    EXPECT_GT(piece * whole, 0.0) << "triangle " << k << " not wound as the face";
    sum += piece;
    const Vec2 centroid = corners[0] / 3.0f + corners[1] / 3.0f + corners[2] / 3.0f;  // no overflow at 3e38
    EXPECT_TRUE(inside(centroid)) << "triangle " << k << " outside the face";
  }
  EXPECT_NEAR(sum, whole, 1e-6 * std::fabs(whole));
}

// Issue 15: "face with 8 vertices is not convex (no fan of triangles covers it); triangulate it
// when exporting" (every concave face past a quad with one reflex corner was refused).
TEST(ObjNgons, ConcaveFacesAreTriangulatedInTheirPlane) {
  const std::vector<std::vector<Vec2>> faces{kL, kU, star(5, 3.0f, 1.0f), kCross, kStraightU, scaled(kCross, 1e4f)};
  std::string text;
  for (std::size_t i = 0; i < faces.size(); ++i) text += floor_face(faces[i], static_cast<float>(i));
  text += floor_face({{0, 0}, {0, 2}, {3, 2}, {3, 0}}, -1.0f);  // a quad wound the other way
  const std::string path = write_obj("ngons.obj", text);
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  std::size_t first = 0;
  for (const auto& face : faces) {
    expect_tiles(soup, first, face.size() - 2, face);
    first += face.size() - 2;
  }
  expect_tiles(soup, first, 2, {{0, 0}, {0, 2}, {3, 2}, {3, 0}});
  EXPECT_EQ(first + 2, soup.triangles.size());
}

TEST(ObjNgons, RepeatedVerticesAreMergedWhileThreeRemain) {
  // The U with its third corner twice (by a second reference to the same vertex), and an L whose
  // last reference repeats its first: the duplicate goes, the rest tiles the face.
  std::string text = floor_face(kU, 0.0f);
  text.insert(text.rfind("f -8 -7 -6") + 10, " -6");
  text += floor_face(kL, 1.0f);
  text.back() = ' ';
  text += "-6\n";
  const std::string path = write_obj("repeated.obj", text);
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  ASSERT_EQ(soup.triangles.size(), kU.size() - 2 + kL.size() - 2);
  expect_tiles(soup, 0, kU.size() - 2, kU);
  expect_tiles(soup, kU.size() - 2, kL.size() - 2, kL);
}

TEST(ObjNgons, FacesThatAreNoPolygonAreRefusedByFileAndLine) {
  const std::string square = "v 0 0 0\nv 2 0 0\nv 2 0 2\nv 0 0 2\n";
  // A bow-tie (its two lobes' areas cancel).
  EXPECT_EQ(load_error(square + "f 1 3 2 4\n"), "hostile.obj:5: face 1: polygon is self-intersecting: edge 0-1 meets edge 2-3");
  // Repeated vertices that leave fewer than 3, and every vertex on one line.
  EXPECT_EQ(load_error(square + "f 1 2 3\nf 1 2 1 2\n"), "hostile.obj:6: face 2: polygon has zero area (all vertices collinear)");
  EXPECT_EQ(load_error(square + "f 1 1 1 1\n"), "hostile.obj:5: face 1: polygon has zero area (all vertices at one point)");
  EXPECT_EQ(load_error("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3 4\n"),
            "hostile.obj:5: face 1: polygon has zero area (all vertices collinear)");
  // A quad folded along its diagonal: each corner 2 / sqrt(24) = 0.408 from the plane through
  // their average with Newell's normal (1, -2, 1) / sqrt(6), for a face of size 2.
  EXPECT_EQ(load_error("v 0 0 0\nv 2 0 0\nv 2 2 2\nv 0 0 2\nf 1 2 3 4\n"),
            "hostile.obj:5: face 1: polygon is not planar: vertex 0 lies 0.4082 from its best-fit plane, more than 5% "
            "of its size 2 (kPlanarityTolerance)");
  // Bent by 1 % of its size: near-planar, two triangles.
  const std::string path = write_obj("bent.obj", "v 0 0 0\nv 2 0 0\nv 2 0.02 2\nv 0 0 2\nf 1 2 3 4\n");
  EXPECT_EQ(io::load_obj(path).triangles.size(), 2u);
  std::remove(path.c_str());
}

// The level of tests/data/ngon_level.obj as a collision mesh: every face's triangles, and rays
// straight down land at the heights the level was written with.
TEST(ObjNgons, TheNgonLevelIsACollisionMesh) {
  const TriangleMesh mesh = io::load_triangle_mesh(std::string(COLLIDE_TEST_DATA_DIR) + "/ngon_level.obj");
  EXPECT_EQ(mesh.triangle_count(), 34u);
  EXPECT_EQ(mesh.stats.degenerate_triangles, 0u);
  struct Probe {
    float x, z;
    bool hit;
    float y;
  };
  for (const Probe& p : {Probe{15, 15, true, 0}, Probe{5, 15, true, 0}, Probe{15, 25, true, 0}, Probe{33, 15, true, 1},
                         Probe{40, 15, true, 2}, Probe{48, 7, true, 2}, Probe{48, 15, false, 0}, Probe{55, 23, true, 1},
                         Probe{65, 30, true, 0}, Probe{60, 32, false, 0}, Probe{5, 5, false, 0}}) {
    const RayHit3 hit = raycast(mesh, Transform3{}, Ray3{{p.x, 10.0f, p.z}, {0.0f, -20.0f, 0.0f}});
    EXPECT_EQ(hit.hit, p.hit) << p.x << ", " << p.z;
    if (hit.hit && p.hit) EXPECT_NEAR(hit.point.y, p.y, 1e-4f) << p.x << ", " << p.z;
  }
}

// ---- hostile files ---------------------------------------------------------------------------

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 0 1\n";

// Issue 15: "-9223372036854775808" was negated to compare it with the vertex count (signed
// overflow: undefined behaviour, which UBSan stops at; in release it wrapped to itself and
// passed the check, leaving tinyobjloader to misread it).
TEST(ObjHostile, IndicesAtTheEndsOfTheIntegersAreOutOfRangeNotOverflowed) {
  EXPECT_EQ(load_error(kTriangle + "f 1 2 -9223372036854775808\n"),
            "hostile.obj:4: face 1: vertex index -9223372036854775808 points before the first vertex (3 vertices so far)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 9223372036854775807\n"),
            "hostile.obj:4: face 1: vertex index 9223372036854775807 out of range (more than the limit of 16777216 "
            "vertices, ObjLimits::max_vertices)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 -99999999999999999999/1/1\n"),
            "hostile.obj:4: face 1: vertex index '-99999999999999999999' out of range (3 vertices so far)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 -4\n"), "hostile.obj:4: face 1: vertex index -4 points before the first vertex (3 vertices so far)");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 2147483648\n"),
            "hostile.obj:4: face 1: vertex index 2147483648 out of range (more than the limit of 16777216 vertices, "
            "ObjLimits::max_vertices)");
}

TEST(ObjHostile, CountsBeyondTheLimitsAreRefusedNamingTheLimit) {
  EXPECT_EQ(io::kMaxObjVertices, 16777216u);
  EXPECT_EQ(io::kMaxObjTriangles, 33554432u);
  EXPECT_EQ(io::kMaxObjFaceVertices, 1024u);
  io::ObjLimits small;
  small.max_vertices = 3;
  EXPECT_EQ(load_error(kTriangle + "v 1 1 1\nf 1 2 3\n", small),
            "hostile.obj:4: vertex 4: more vertices than the limit of 3 (ObjLimits::max_vertices)");
  small = {};
  small.max_triangles = 3;
  EXPECT_EQ(load_error(kTriangle + "v 1 0 1\nf 1 2 3\nf 2 4 3\nf 1 2 4 3\n", small),
            "hostile.obj:7: face 3: the faces make more triangles than the limit of 3 (ObjLimits::max_triangles)");
  small = {};
  small.max_face_vertices = 4;
  EXPECT_EQ(load_error(floor_face(kL, 0.0f), small),
            "hostile.obj:7: face 1: more vertices than the limit of 4 per face (ObjLimits::max_face_vertices; "
            "triangulating is quadratic in them)");
  // Limits only tighten: a larger one counts as the default.
  io::ObjLimits loose;
  loose.max_vertices = std::size_t{1} << 40;
  EXPECT_EQ(load_error(kTriangle + "f 1 2 20000000\n", loose),
            "hostile.obj:4: face 1: vertex index 20000000 out of range (more than the limit of 16777216 vertices, "
            "ObjLimits::max_vertices)");
}

// Ear clipping is quadratic in a face's vertices: a file of faces each 10^5 long (1 MB each)
// would take hours. Before, such faces went to a fan (convex ones) whatever their length.
TEST(ObjHostile, FacesOfThousandsOfVerticesAreRefusedAndTheLongestAllowedIsQuick) {
  std::vector<Vec2> circle;
  for (int i = 0; i < 1025; ++i) {
    const double a = -2.0 * 3.14159265358979 * i / 1025;
    circle.push_back({static_cast<float>(std::cos(a)), static_cast<float>(std::sin(a))});
  }
  EXPECT_EQ(load_error(floor_face(circle, 0.0f)),
            "hostile.obj:1026: face 1: more vertices than the limit of 1024 per face (ObjLimits::max_face_vertices; "
            "triangulating is quadratic in them)");
  // A 1024-vertex star (512 reflex corners): 1022 triangles tiling it.
  const std::vector<Vec2> spiky = star(512, 10.0f, 6.0f);
  const std::string path = write_obj("spiky.obj", floor_face(spiky, 0.0f));
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  ASSERT_EQ(soup.triangles.size(), 1022u);
  expect_tiles(soup, 0, 1022, spiky);
}

// Issue 15: a word of the file went into the message as it was: a NUL cut the C string what()
// returns short, other bytes made it invalid UTF-8, and a megabyte-long word made a megabyte-long
// message.
TEST(ObjHostile, MessagesQuoteTheFileAsPrintableTextOfBoundedLength) {
  EXPECT_EQ(load_error(std::string("v 0 0 1\0x\n", 10)),
            "hostile.obj:1: vertex 1: coordinate z '1\\x00x' is not a number");
  EXPECT_EQ(load_error("v 0 \xff\xfe 1\n"), "hostile.obj:1: vertex 1: coordinate y '\\xFF\\xFE' is not a number");
  EXPECT_EQ(load_error(kTriangle + "f 1 2 3\x1b[2J\n"),
            "hostile.obj:4: face 1: vertex reference '3\\x1B[2J' is not a vertex index (a non-zero integer; OBJ counts from 1)");
  const std::string message = load_error("v 1 2 " + std::string(1 << 20, '7') + "x\n");
  EXPECT_LT(message.size(), 200u) << message.substr(0, 300);
  EXPECT_NE(message.find("coordinate z '" + std::string(40, '7') + "...' is out of float range"), std::string::npos)
      << message.substr(0, 300);
}

// Long lines cost time linear in their length and no memory beyond the file's: a 4 MB comment,
// and a vertex with 10^6 extra words (only x, y, z are read).
TEST(ObjHostile, VeryLongLinesAreReadInLinearTime) {
  std::string text = "# " + std::string(4 << 20, 'c') + "\n";
  text += "v 0 0 0";
  for (int i = 0; i < 1000000; ++i) text += " 1";
  text += "\nv 1 0 0\nv 0 0 1\nf 1 2 3\n";
  const std::string path = write_obj("long_lines.obj", text);
  const TriangleSoup soup = io::load_obj(path);
  std::remove(path.c_str());
  ASSERT_EQ(soup.positions.size(), 3u);
  EXPECT_EQ(soup.positions[0], Vec3(0.0f));
}

// Issue 15: an OBJ input that is a folder, or empty. (A file without end, such as /dev/zero,
// is refused by the file-size limit of read_text_file.) A folder read as a file came back empty:
// "no faces", as if the level had none.
TEST(ObjHostile, AFolderOrAnEmptyFileIsRefusedSayingWhy) {
  const std::string folder = ::testing::TempDir() + "level_folder.obj";
  fs::create_directories(folder);
  try {
    (void)io::load_obj(folder);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), folder + ": is a folder, not an OBJ file");
  }
  fs::remove(folder);
  EXPECT_EQ(load_error(""), "hostile.obj: no faces (no 'f' statement)");
}

// Coordinates up to the float limit: the face is triangulated in its own scale (a concave face
// 3e38 across tiles as one 1 across does). As a collision mesh it is either supported or refused
// naming the file (today: refused, its triangles' normals overflow float); one wider than float
// range is refused by name.
TEST(ObjHostile, CoordinatesNearTheFloatLimitTriangulateOrAreRefusedByName) {
  const std::vector<Vec2> huge = scaled(kCross, 5e37f);
  const std::string path = write_obj("huge_ngon.obj", floor_face(huge, 3e38f));
  const TriangleSoup soup = io::load_obj(path);
  ASSERT_EQ(soup.triangles.size(), kCross.size() - 2);
  expect_tiles(soup, 0, kCross.size() - 2, huge);
  try {
    EXPECT_EQ(io::load_triangle_mesh(path).triangle_count(), kCross.size() - 2);
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()).rfind("huge_ngon.obj: ", 0), 0u) << e.what();
  }
  std::remove(path.c_str());
  const std::string wide = write_obj("too_wide.obj", floor_face({{-3e38f, -3e38f}, {3e38f, -3e38f}, {3e38f, 3e38f}, {-3e38f, 3e38f}}, 0.0f));
  EXPECT_EQ(io::load_obj(wide).triangles.size(), 2u);
  try {
    (void)io::load_triangle_mesh(wide);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()).rfind("too_wide.obj: ", 0), 0u) << e.what();
  }
  std::remove(wide.c_str());
}

// Issue 15: the OBJ text went to tinyobjloader after our checks, and it allocates what the file
// asks for: a `t` (tag) line of 20 bytes reserves 8192 integers, reals and strings (330 KB) and
// keeps them to the end, so a 1 MB file of them asked for 16 GB (std::bad_alloc, or the OOM
// killer). Run in a child with its address space capped at 1 GB. (Not under AddressSanitizer,
// which reserves terabytes of address space up front.)
TEST(ObjHostile, StatementsALevelDoesNotUseCostNoMemory) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "an address-space cap does not work under AddressSanitizer";
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  GTEST_SKIP() << "an address-space cap does not work under AddressSanitizer";
#endif
#endif
  std::string text = kTriangle + "f 1 2 3\n";
  while (text.size() < (1u << 20)) text += "t crease 8192/8192/8192\n";
  const std::string path = write_obj("tags.obj", text);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const rlimit cap{1u << 30, 1u << 30};
    setrlimit(RLIMIT_AS, &cap);
    try {
      _exit(io::load_obj(path).triangles.size() == 1 ? 0 : 1);
    } catch (...) {
      _exit(2);
    }
  }
  int status = 0;
  waitpid(child, &status, 0);
  std::remove(path.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

// Every input the OBJ fuzzer found a defect with (fuzz/regressions/obj_mesh/) and its seeds,
// replayed through the fuzz target's own check (fuzz/obj_mesh_check.hpp).
TEST(ObjFuzzRegressions, EveryFoundInputAndSeedPassesTheFuzzCheck) {
  auto replay = [](const fs::path& folder) {
    return test::replay_files(folder, [](const std::string& input) { return fuzz::check_obj_mesh(input); });
  };
  replay(fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "obj_mesh");
  EXPECT_GE(replay(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "obj_mesh"), 5);
}

}  // namespace
}  // namespace collide
