// `collide sdf` end to end through the real binary: on a shared Tiled map and on the shared
// dungeon mesh it reports the build and an error within the bound a field with exact nodes obeys;
// --sample prints only the values, each checked against an independent answer (a circle's
// |p - c| - r, a map's nearest collider by closest_point); --max-memory refuses a grid with the
// figure it needs; bad points files, options and inputs are named with their line or value;
// --png writes a picture with both sides of the surface; --band builds the sparse field; the
// particles stay out of the solid.

#include "cli_run.hpp"
#include "sdf.hpp"
#include "support/picture_checks.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/field_picture.hpp>
#include <collide/io/tiled.hpp>
#include <collide/narrow/closest_point.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::CommandRun;
using test::exit_code;
const auto run = test::run_cli;

const std::string kMap = std::string(COLLIDE_DATA_DIR) + "/tiled/melonjs/platformer/map/map1.tmx";
const std::string kDungeon = std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj";

/// Writes `text` to a file `name` in the test's temporary folder and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// A scene JSON of one circle of radius 3 at (1.5, -2) (and a sensor, which is not solid).
std::string circle_scene() {
  return write_temp("collide_sdf_circle.json", R"({"bounds": [-10, -10, 10, 10], "walls": 0, "statics": [
    {"transform": {"p": [1.5, -2]}, "shape": {"type": "circle", "radius": 3}},
    {"sensor": true, "transform": {"p": [-6, 6]}, "shape": {"type": "box", "half": [2, 2]}}]})");
}
const Vec2 kCircleCentre{1.5f, -2.0f};
constexpr float kCircleRadius = 3.0f;

/// The numbers a report line "  LABEL   a ... b ..." holds after its label, in order.
std::vector<double> numbers_after(const std::string& output, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("\\n  " + label + "  +([^\\n]*)"))) return {};
  std::vector<double> out;
  const std::regex number(R"([-+]?[0-9]*\.?[0-9]+(e[-+]?[0-9]+)?)");
  const std::string line = m[1].str();
  for (auto it = std::sregex_iterator(line.begin(), line.end(), number); it != std::sregex_iterator(); ++it) {
    out.push_back(std::stod(it->str()));
  }
  return out;
}

/// The report's numbers the tests check.
struct Report {
  double nodes = -1.0, band_nodes = -1.0, memory = -1.0;
  double max_error_voxels = -1.0, mean_error_voxels = -1.0, measured = -1.0;
  double right_sign = -1.0, points = -1.0;
};

Report read_report(const std::string& output) {
  Report r;
  if (const auto n = numbers_after(output, "nodes"); !n.empty()) r.nodes = n[0];
  if (const auto n = numbers_after(output, "band nodes"); !n.empty()) r.band_nodes = n[0];
  if (const auto n = numbers_after(output, "memory"); !n.empty()) r.memory = n[0];
  // "max 0.52 (0.07 voxels), mean 0.1 (0.013 voxels) on 812 random points ..."
  if (const auto e = numbers_after(output, "error"); e.size() >= 5) {
    r.max_error_voxels = e[1];
    r.mean_error_voxels = e[3];
    r.measured = e[4];
  }
  if (const auto s = numbers_after(output, "sign"); s.size() >= 2) r.right_sign = s[0], r.points = std::fabs(s[1]);
  return r;
}

/// The voxel of the report's grid line ("  grid   264 x 160 nodes, voxel 7.38, origin (...)").
double report_voxel(const std::string& output) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex(R"(nodes, voxel ([0-9.e+-]+))"))) return -1.0;
  return std::stod(m[1].str());
}

// The bound a field with exact node values obeys: the distance is 1-Lipschitz, so the
// interpolated value at p is within the largest distance from p to a node of its cell, the
// cell's diagonal: sqrt(D) voxels. The check points are random: a field far off would exceed it.
TEST(SdfCommand, ATiledMapsFieldIsWithinACellDiagonalOfTheExactDistance) {
  const CommandRun r = run("sdf " + kMap);
  ASSERT_EQ(exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("(2D, "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("kind              dense"), std::string::npos) << r.output;
  const Report rep = read_report(r.output);
  EXPECT_GT(rep.nodes, 1000.0) << r.output;
  EXPECT_GT(rep.band_nodes, 0.0) << r.output;
  EXPECT_LE(rep.band_nodes, rep.nodes) << r.output;
  EXPECT_GE(rep.memory, 4.0 * rep.nodes) << "a float per node at least\n" << r.output;
  EXPECT_GT(rep.measured, 500.0) << "most random points of the map's box are outside its colliders\n" << r.output;
  EXPECT_GE(rep.max_error_voxels, 0.0) << r.output;
  EXPECT_LE(rep.max_error_voxels, std::sqrt(2.0)) << r.output;
  EXPECT_LE(rep.mean_error_voxels, 0.25) << r.output;
  EXPECT_EQ(rep.points, 1000.0) << r.output;
  EXPECT_GE(rep.right_sign, 0.98 * rep.points) << r.output;
  // The default voxel: the colliders' bounds' largest side / 256.
  EXPECT_NE(r.output.find("(the default: largest side"), std::string::npos) << r.output;
}

TEST(SdfCommand, SampledValuesOnAMapMatchTheNearestColliderWithinACellDiagonal) {
  const TiledMap map = load_tiled_map(kMap);
  Aabb box = compute_aabb(map.colliders[0].shape, map.colliders[0].transform);
  for (const TiledCollider& c : map.colliders) box = merge(box, compute_aabb(c.shape, c.transform));
  // Random points of the colliders' box outside every collider, their exact distance here.
  std::mt19937 rng(5);
  std::vector<Vec2> points;
  std::vector<float> exact;
  std::string text = "# random points of map1.tmx, map pixels\n";
  while (points.size() < 300) {
    const Vec2 p{std::uniform_real_distribution<float>(box.min.x, box.max.x)(rng),
                 std::uniform_real_distribution<float>(box.min.y, box.max.y)(rng)};
    float nearest = std::numeric_limits<float>::infinity();
    bool inside = false;
    for (const TiledCollider& c : map.colliders) {
      const PointQuery q = closest_point(c.shape, c.transform, p);
      inside = inside || q.inside;
      nearest = std::min(nearest, q.distance);
    }
    if (inside) continue;
    points.push_back(p);
    exact.push_back(nearest);
    char line[64];
    std::snprintf(line, sizeof line, "%.9g %.9g\n", static_cast<double>(p.x), static_cast<double>(p.y));
    text += line;
  }
  const std::string file = write_temp("collide_sdf_map_points.txt", text);
  constexpr float kVoxel = 4.0f;
  // Standard output alone: the values, one per line.
  const CommandRun r = test::run_shell("(\"$COLLIDE\" sdf " + kMap + " --voxel 4 --sample " + file + " 2>/dev/null)");
  ASSERT_EQ(exit_code(r), 0) << r.output;
  std::istringstream lines(r.output);
  std::string line;
  std::size_t i = 0;
  for (; std::getline(lines, line); ++i) {
    ASSERT_LT(i, points.size()) << "more lines than points: " << line;
    const float value = std::stof(line);
    EXPECT_NEAR(value, exact[i], kVoxel * std::sqrt(2.0f)) << "point " << i << " " << points[i].x << " " << points[i].y;
  }
  EXPECT_EQ(i, points.size());
}

TEST(SdfCommand, SampledValuesOfACircleAreWithinHalfAVoxelDiagonalAndStdoutHoldsThemAlone) {
  const std::string scene = circle_scene();
  std::mt19937 rng(11);
  std::vector<Vec2> points;
  std::string text;
  for (int i = 0; i < 400; ++i) {
    // Within the grid: the circle's box [-1.5, 4.5] x [-5, 1] and --margin 40 voxels of 0.1.
    const Vec2 p{std::uniform_real_distribution<float>(-5.4f, 8.4f)(rng), std::uniform_real_distribution<float>(-8.9f, 4.9f)(rng)};
    points.push_back(p);
    char line[64];
    std::snprintf(line, sizeof line, i % 50 == 0 ? "%.9g\t%.9g\n\n# a comment\n" : "%.9g %.9g\n",
                  static_cast<double>(p.x), static_cast<double>(p.y));
    text += line;
  }
  const std::string file = write_temp("collide_sdf_circle_points.txt", text);
  constexpr float kVoxel = 0.1f;
  const CommandRun r = test::run_shell("(\"$COLLIDE\" sdf " + scene + " --voxel 0.1 --margin 40 --sample " + file + " 2>/dev/null)");
  ASSERT_EQ(exit_code(r), 0) << r.output;
  std::istringstream lines(r.output);
  std::string line;
  std::size_t i = 0, inside = 0;
  for (; std::getline(lines, line); ++i) {
    ASSERT_LT(i, points.size()) << "more lines than points: " << line;
    const float truth = glm::length(points[i] - kCircleCentre) - kCircleRadius;
    inside += truth < 0.0f ? 1 : 0;
    EXPECT_NEAR(std::stof(line), truth, 0.5f * kVoxel * std::sqrt(2.0f)) << points[i].x << " " << points[i].y;
  }
  EXPECT_EQ(i, points.size());
  EXPECT_GT(inside, 20u) << "points inside the circle were sampled too";
  // With --sample the report goes to standard error.
  const CommandRun both = test::run_shell("(\"$COLLIDE\" sdf " + scene + " --voxel 0.1 --sample " + file + " 2>&1 >/dev/null)");
  EXPECT_NE(both.output.find("signed distance field of"), std::string::npos) << both.output;
}

TEST(SdfCommand, TheDungeonMeshsFieldIsWithinACellDiagonalAndItsSliceIsDrawn) {
  const std::string png = ::testing::TempDir() + "collide_sdf_dungeon.png";
  std::remove(png.c_str());
  const CommandRun r = run("sdf " + kDungeon + " --voxel 0.5 --png-size 300 --png " + png);
  ASSERT_EQ(exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("(3D, "), std::string::npos) << r.output;
  const Report rep = read_report(r.output);
  EXPECT_EQ(report_voxel(r.output), 0.5) << r.output;
  EXPECT_GT(rep.nodes, 100000.0) << r.output;
  EXPECT_EQ(rep.measured, 1000.0) << "3D: every point measured\n" << r.output;
  EXPECT_LE(rep.max_error_voxels, std::sqrt(3.0)) << r.output;
  EXPECT_LE(rep.mean_error_voxels, 0.25) << r.output;
  EXPECT_GE(rep.right_sign, 0.95 * rep.points) << "the open dungeon's inside by the winding number\n" << r.output;
  EXPECT_NE(r.output.find("wrote " + png), std::string::npos) << r.output;
  EXPECT_TRUE(test::has_png_signature(png));
  const test::PngImage image = test::read_png(png);
  EXPECT_GT(image.width, 300);
  // A slice outside the grid is refused with the grid's range.
  const CommandRun bad = run("sdf " + kDungeon + " --voxel 1 --slice y=500 --png " + png);
  EXPECT_EQ(exit_code(bad), 2) << bad.output;
  EXPECT_NE(bad.output.find("--slice y=500: outside the field's y range"), std::string::npos) << bad.output;
}

TEST(SdfCommand, ACoarseGridSaysItsBandWentNodeByNode) {
  // dungeon.obj's triangles are mostly under 2 units: at a voxel of 2 each band node lies within
  // the band of many of them, and the build asks the BVH node by node (FieldBuildStats).
  const CommandRun coarse = run("sdf " + kDungeon + " --voxel 2 --check-points 100");
  ASSERT_EQ(exit_code(coarse), 0) << coarse.output;
  const Report rep = read_report(coarse.output);
  const std::vector<double> queries = numbers_after(coarse.output, "nearest queries");
  ASSERT_FALSE(queries.empty()) << coarse.output;
  EXPECT_GE(queries[0], rep.band_nodes) << coarse.output;
  EXPECT_LE(rep.max_error_voxels, std::sqrt(3.0)) << coarse.output;
  // A map's field is built from shapes, never node by node: no such line.
  const CommandRun map = run("sdf " + kMap + " --voxel 2 --check-points 100");
  ASSERT_EQ(exit_code(map), 0) << map.output;
  EXPECT_EQ(map.output.find("nearest queries"), std::string::npos) << map.output;
}

TEST(SdfCommand, TheSparseFieldOfAMapHoldsLessThanTheDenseOne) {
  const CommandRun dense = run("sdf " + kMap + " --voxel 2 --check-points 200");
  const CommandRun sparse = run("sdf " + kMap + " --voxel 2 --band 3 --check-points 200");
  ASSERT_EQ(exit_code(dense), 0) << dense.output;
  ASSERT_EQ(exit_code(sparse), 0) << sparse.output;
  EXPECT_NE(sparse.output.find("kind              sparse"), std::string::npos) << sparse.output;
  EXPECT_NE(sparse.output.find("clamped to the band"), std::string::npos) << sparse.output;
  const Report d = read_report(dense.output), s = read_report(sparse.output);
  EXPECT_GT(s.memory, 0.0);
  EXPECT_LT(s.memory, d.memory) << dense.output << sparse.output;
  EXPECT_LE(s.max_error_voxels, std::sqrt(2.0)) << sparse.output;
}

TEST(SdfCommand, MaxMemoryRefusesAFieldWithTheBytesItWouldNeed) {
  const CommandRun r = run("sdf " + kMap + " --voxel 0.05 --max-memory 1M");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_EQ(r.output.rfind("collide sdf: " + kMap + ": ", 0), 0u) << r.output;
  // The figure it would need: 1890 x 1050 pixels at 0.05 is over 7e8 nodes, far over 1 MiB. The
  // message gives it in bytes or in binary units.
  const std::regex size(R"(([0-9]+(\.[0-9]+)?(e\+?[0-9]+)?) ?(bytes|B|KiB|MiB|GiB|TiB)\b)");
  double largest = 0.0;
  for (auto it = std::sregex_iterator(r.output.begin(), r.output.end(), size); it != std::sregex_iterator(); ++it) {
    const std::string unit = (*it)[4].str();
    const int power = unit == "KiB" ? 1 : unit == "MiB" ? 2 : unit == "GiB" ? 3 : unit == "TiB" ? 4 : 0;
    largest = std::max(largest, std::stod((*it)[1].str()) * std::pow(1024.0, power));
  }
  EXPECT_GT(largest, 1e9) << r.output;
  EXPECT_EQ(r.output.find("signed distance field of"), std::string::npos) << "no report of a field not built\n" << r.output;
  const CommandRun bad = run("sdf " + kMap + " --max-memory 12X");
  EXPECT_EQ(exit_code(bad), 2) << bad.output;
  EXPECT_NE(bad.output.find("--max-memory '12X': not a size"), std::string::npos) << bad.output;
}

TEST(SdfCommand, ByteSizesTakePowersOf1024) {
  EXPECT_EQ(cli::parse_byte_size("1048576", "--max-memory"), 1048576u);
  EXPECT_EQ(cli::parse_byte_size("512M", "--max-memory"), std::size_t{512} << 20);
  EXPECT_EQ(cli::parse_byte_size("2g", "--max-memory"), std::size_t{2} << 30);
  EXPECT_EQ(cli::parse_byte_size("1.5GiB", "--max-memory"), std::size_t{3} << 29);
  EXPECT_EQ(cli::parse_byte_size("64KB", "--max-memory"), std::size_t{64} << 10);
  for (const char* bad : {"", "0", "-5", "abc", "12X", "1e3", "M", "5 M", "0.1"}) {
    EXPECT_THROW((void)cli::parse_byte_size(bad, "--max-memory"), InvalidInput) << bad;
  }
}

TEST(SdfCommand, ABadPointsFileIsNamedWithItsLineAndNothingIsBuilt) {
  const std::string scene = circle_scene();
  const std::string file = write_temp("collide_sdf_bad_points.txt", "0 0\n\n# a comment\n1 2 3\n");
  const CommandRun r = run("sdf " + scene + " --sample " + file);
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_EQ(r.output, "collide sdf: " + file + ":4: expected 2 numbers (x y), found 3\n");
  const std::string nan = write_temp("collide_sdf_nan_points.txt", "0 0 0\n1 nan 2\n");
  const CommandRun n = run("sdf " + kDungeon + " --sample " + nan);
  EXPECT_EQ(exit_code(n), 2) << n.output;
  EXPECT_EQ(n.output, "collide sdf: " + nan + ":2: y 'nan' is not finite\n");
  const CommandRun missing = run("sdf " + scene + " --sample " + ::testing::TempDir() + "collide_no_such_points.txt");
  EXPECT_EQ(exit_code(missing), 2) << missing.output;
  EXPECT_NE(missing.output.find("collide_no_such_points.txt: cannot be read (no such file)"), std::string::npos)
      << missing.output;
}

TEST(SdfCommand, ThePictureOfACircleShowsBothSidesAndTheSurface) {
  const std::string png = ::testing::TempDir() + "collide_sdf_circle.png";
  std::remove(png.c_str());
  const CommandRun r = run("sdf " + circle_scene() + " --voxel 0.05 --png-size 400 --png " + png);
  ASSERT_EQ(exit_code(r), 0) << r.output;
  const test::PngImage image = test::read_png(png);
  ASSERT_GT(image.width, 0) << "no PNG at " << png;
  const auto near = [](Color c, Color want, int within) {
    return std::abs(c.r - want.r) <= within && std::abs(c.g - want.g) <= within && std::abs(c.b - want.b) <= within;
  };
  // Near the surface the colours are the map's own; the circle's area is pi r^2 of the grid's
  // (2 r + 2 margins)^2: a good part of the plot either side.
  const int inside = test::count_pixels(image, [&](Color c) { return near(c, kFieldInside, 60); });
  const int outside = test::count_pixels(image, [&](Color c) { return near(c, kFieldOutside, 60); });
  const int ink = test::count_pixels(image, [&](Color c) { return near(c, kFieldZeroContour, 40); });
  EXPECT_GT(inside, 400 * 400 / 20) << inside;
  EXPECT_GT(outside, 400 * 400 / 50) << outside;
  // The contour: about 2 pi r at 400 / 6.4 pixels per unit, 2.5 pixels wide.
  EXPECT_GT(ink, 1000) << ink;
  // 2D inputs take no slice.
  const CommandRun slice = run("sdf " + circle_scene() + " --slice y=0 --png " + png);
  EXPECT_EQ(exit_code(slice), 2) << slice.output;
  EXPECT_NE(slice.output.find("--slice: "), std::string::npos) << slice.output;
}

TEST(SdfCommand, ParticlesBounceAndStayOutOfTheSolid) {
  const CommandRun r = run("sdf " + circle_scene() + " --voxel 0.1 --particles 500 --frames 200 --gravity 5");
  ASSERT_EQ(exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("particles: 500 of 500 placed"), std::string::npos) << r.output;
  const auto step = numbers_after(r.output, "step time");
  ASSERT_FALSE(step.empty()) << r.output;
  EXPECT_GT(step[0], 0.0) << r.output;
  const auto bounces = numbers_after(r.output, "bounces");
  ASSERT_FALSE(bounces.empty()) << r.output;
  EXPECT_GT(bounces[0], 0.0) << "500 particles for 200 steps under gravity meet the circle\n" << r.output;
  const auto inside = numbers_after(r.output, "ended inside");
  ASSERT_FALSE(inside.empty()) << r.output;
  EXPECT_EQ(inside[0], 0.0) << r.output;
}

TEST(SdfCommand, InputsThatHoldNoFieldAreNamed) {
  const CommandRun other = run("sdf " + write_temp("collide_sdf_input.txt", "0 0\n"));
  EXPECT_EQ(exit_code(other), 2) << other.output;
  EXPECT_NE(other.output.find("not a Tiled map (.tmx, .tmj, .json), a scene JSON file (.json) nor an OBJ mesh"),
            std::string::npos) << other.output;
  const CommandRun missing = run("sdf " + ::testing::TempDir() + "collide_no_such_map.tmx");
  EXPECT_EQ(exit_code(missing), 2) << missing.output;
  EXPECT_NE(missing.output.find("collide_no_such_map.tmx: cannot be read (no such file)"), std::string::npos) << missing.output;
  const std::string sensors = write_temp("collide_sdf_sensors.json", R"({"bounds": [-10, -10, 10, 10], "statics": [
    {"sensor": true, "shape": {"type": "circle", "radius": 1}}]})");
  const CommandRun none = run("sdf " + sensors);
  EXPECT_EQ(exit_code(none), 2) << none.output;
  EXPECT_NE(none.output.find(sensors + ": no solid statics"), std::string::npos) << none.output;
  const CommandRun layers = run("sdf " + kDungeon + " --layers walls");
  EXPECT_EQ(exit_code(layers), 2) << layers.output;
  EXPECT_NE(layers.output.find("--layers: only Tiled maps have layers"), std::string::npos) << layers.output;
}

}  // namespace
}  // namespace collide
