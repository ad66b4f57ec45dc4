// The hull writer (io::write_hulls_obj) read back by the OBJ reader (io::load_obj): every vertex
// position comes back bit for bit (boxes, random clouds with coordinates of every magnitude, a
// hull far from the origin), every polygonal face comes back as its count - 2 triangles wound
// outward, one `o` object per hull; a path that cannot be written is an error naming it. And
// io::load_hulls_obj: the written hulls come back as the same hulls, a file without `o`
// statements by its connected surfaces, a flat one as an error naming the hull.
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace collide {
namespace {

/// The hulls the tests write: a box (quadrilateral faces), a tetrahedron, random clouds at
/// several scales and offsets (coordinates of many digits; one 9000 units out, one tiny).
std::vector<ConvexHull> sample_hulls() {
  std::vector<ConvexHull> hulls;
  std::vector<Vec3> box;
  for (int i = 0; i < 8; ++i) box.emplace_back((i & 1) ? 1.5f : -0.5f, (i & 2) ? 2.0f : -1.0f, (i & 4) ? 0.25f : -3.0f);
  hulls.push_back(make_convex_hull(box));
  const std::vector<Vec3> tetrahedron{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  hulls.push_back(make_convex_hull(tetrahedron));
  std::mt19937 rng(18);
  for (const auto& [scale, offset] : {std::pair{1.0f, Vec3(0.0f)}, std::pair{0.3f, Vec3(9000.0f, -12.5f, 3.1f)},
                                      std::pair{1e-3f, Vec3(-1e-3f, 0.0f, 2e-3f)}, std::pair{250.0f, Vec3(0.0f)}}) {
    std::normal_distribution<float> gauss(0.0f, scale);
    std::vector<Vec3> cloud;
    for (int i = 0; i < 200; ++i) cloud.push_back(offset + Vec3(gauss(rng), gauss(rng), gauss(rng)));
    hulls.push_back(make_convex_hull(cloud, {.max_vertices = 40}));
  }
  return hulls;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Lines of `text` that start with `tag` and a space.
int count_lines(const std::string& text, const std::string& tag) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind(tag + " ", 0) == 0 ? 1 : 0;
  return n;
}

TEST(ObjWriter, HullsReadBackBitForBitWithTheirFacesWoundOutward) {
  const std::vector<ConvexHull> hulls = sample_hulls();
  const std::string path = ::testing::TempDir() + "collide_hulls_roundtrip.obj";
  io::write_hulls_obj(path, hulls);
  const TriangleSoup soup = io::load_obj(path);

  std::size_t vertices = 0, faces = 0, triangles = 0;
  for (const ConvexHull& h : hulls) {
    vertices += h.vertices.size();
    faces += h.faces.size();
    for (const HullFace& f : h.faces) triangles += f.count - 2u;
  }
  ASSERT_EQ(soup.positions.size(), vertices);
  ASSERT_EQ(soup.triangles.size(), triangles);
  const std::string text = read_text(path);
  EXPECT_EQ(count_lines(text, "o"), static_cast<int>(hulls.size()));
  EXPECT_EQ(count_lines(text, "f"), static_cast<int>(faces));
  EXPECT_NE(text.find("o hull_1\n"), std::string::npos);
  EXPECT_NE(text.find("o hull_" + std::to_string(hulls.size()) + "\n"), std::string::npos);

  // Positions: the hulls' vertices in order, every bit the same (the sign of a zero too).
  std::size_t i = 0;
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    for (const Vec3& v : hulls[h].vertices) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(soup.positions[i][k]), std::bit_cast<std::uint32_t>(v[k]))
            << "hull " << h + 1 << " vertex " << i << " axis " << k << ": " << soup.positions[i][k] << " vs " << v[k];
      }
      ++i;
    }
  }

  // Triangles: each hull's faces in order, each fan of a face within its hull's vertex range and
  // wound counter-clockwise seen from outside (its normal along the face's outward normal).
  std::size_t t = 0, base = 0;
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    const ConvexHull& hull = hulls[h];
    for (const HullFace& f : hull.faces) {
      for (int k = 0; k + 2 < f.count; ++k, ++t) {
        const glm::uvec3 tri = soup.triangles[t];
        for (int c = 0; c < 3; ++c) {
          ASSERT_GE(tri[c], base);
          ASSERT_LT(tri[c], base + hull.vertices.size());
        }
        const Vec3 a = soup.positions[tri[0]], b = soup.positions[tri[1]], c = soup.positions[tri[2]];
        const Vec3 n = glm::cross(b - a, c - a);
        EXPECT_GT(glm::dot(n, f.normal), 0.0f) << "hull " << h + 1 << " face " << (&f - hull.faces.data());
      }
    }
    base += hull.vertices.size();
  }
  std::remove(path.c_str());
}

/// `text` written to a temporary file named `name`; returns its path.
std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(ObjWriter, HullsReadBackAsHullsOneComponentEach) {
  const std::vector<ConvexHull> hulls = sample_hulls();
  const std::string path = ::testing::TempDir() + "collide_hulls_components.obj";
  io::write_hulls_obj(path, hulls);
  const std::vector<ConvexHull> back = io::load_hulls_obj(path);
  ASSERT_EQ(back.size(), hulls.size());
  for (std::size_t h = 0; h < hulls.size(); ++h) {
    // The same points (hull vertices are extreme points: rebuilding keeps every one).
    auto sorted = [](std::vector<Vec3> p) {
      std::sort(p.begin(), p.end(), [](Vec3 a, Vec3 b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); });
      return p;
    };
    EXPECT_EQ(sorted(back[h].vertices), sorted(hulls[h].vertices)) << "hull " << h + 1;
    EXPECT_NEAR(back[h].volume, hulls[h].volume, 1e-5f * hulls[h].volume) << "hull " << h + 1;
  }
  std::remove(path.c_str());
}

TEST(ObjWriter, HullsWithoutObjectStatementsAreTheirConnectedSurfaces) {
  // Two tetrahedra with vertices of their own, no `o` or `g`, the second's faces listed first
  // and interleaved with the first's (a tool's order): two hulls, in order of first face.
  const std::string path = write_text("collide_hulls_no_o.obj",
                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                      "v 5 0 0\nv 7 0 0\nv 5 2 0\nv 5 0 2\n"
                                      "f 5 7 6\nf 1 3 2\nf 5 6 8\nf 1 2 4\nf 5 8 7\nf 1 4 3\nf 6 7 8\nf 2 3 4\n");
  const std::vector<ConvexHull> hulls = io::load_hulls_obj(path);
  ASSERT_EQ(hulls.size(), 2u);
  EXPECT_NEAR(hulls[0].volume, 8.0f / 6.0f, 1e-5f);  // the second tetrahedron, 2 m legs
  EXPECT_NEAR(hulls[1].volume, 1.0f / 6.0f, 1e-6f);
  std::remove(path.c_str());
}

TEST(ObjWriter, AFlatHullIsAnErrorNamingTheFileAndTheHull) {
  const std::string path = write_text("collide_hulls_flat.obj",
                                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                      "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                                      "v 5 0 0\nv 6 0 0\nv 5 1 0\nf 5 6 7\n");
  try {
    (void)io::load_hulls_obj(path);
    ADD_FAILURE() << "a flat triangle was read as a hull";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()).rfind("collide_hulls_flat.obj: hull 2: ", 0), 0u) << e.what();
  }
  std::remove(path.c_str());
}

TEST(ObjWriter, NoHullsWritesAFileWithNoObject) {
  const std::string path = ::testing::TempDir() + "collide_hulls_none.obj";
  io::write_hulls_obj(path, {});
  const std::string text = read_text(path);
  EXPECT_EQ(count_lines(text, "o"), 0);
  EXPECT_EQ(count_lines(text, "v"), 0);
  EXPECT_THROW((void)io::load_obj(path), InvalidInput) << "no faces to read back";
  std::remove(path.c_str());
}

TEST(ObjWriter, APathThatCannotBeWrittenIsAnErrorNamingIt) {
  const std::vector<ConvexHull> hulls = sample_hulls();
  for (const std::string path : {std::string("/nonexistent-folder/hulls.obj"), ::testing::TempDir()}) {
    try {
      io::write_hulls_obj(path, hulls);
      ADD_FAILURE() << path << " was written";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path + ": cannot be written (", 0), 0u) << what;
    }
  }
  // A full disk: the open succeeds, the writes fail.
  if (std::FILE* full = std::fopen("/dev/full", "wb")) {
    std::fclose(full);
    try {
      io::write_hulls_obj("/dev/full", hulls);
      ADD_FAILURE() << "/dev/full was written";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("/dev/full: cannot be written"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace collide
