// `collide walk` end to end through the real binary, on the shared dungeon level: it must exit 0,
// report every sampled position on the walk mesh, print what make_walk_mesh built for the options
// given, and write a real PNG; a missing or malformed file must fail with a message that names it
// (and the line).

#include "cli_run.hpp"
#include "support/picture_checks.hpp"

#include <collide/io/obj.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <regex>
#include <string>
#include <numbers>
#include <tuple>

namespace {

using collide::test::CommandRun;
const auto run = collide::test::run_cli;

TEST(WalkCommand, AgentsOnTheDungeonStayOnTheMeshAndThePictureIsAPng) {
  const std::string png = ::testing::TempDir() + "collide_walk_test.png";
  std::remove(png.c_str());
  const CommandRun r = run("walk " + std::string(COLLIDE_DATA_DIR) +
                    "/meshes/recast/dungeon.obj --agents 8 --steps 200 --seed 3 --png-size 300 --png " + png);
  ASSERT_EQ(r.status, 0) << r.output;
  // "on-mesh check     1600/1600 positions on the mesh ..."
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(on-mesh check\s+(\d+)/(\d+) positions)")))
      << r.output;
  EXPECT_EQ(m[1].str(), m[2].str()) << r.output;
  EXPECT_EQ(std::stoi(m[2].str()), 8 * 200);
  // The top-down picture: the size asked for, the dark ground in its corner (the mesh is fitted
  // inside a margin), and a good part of it covered by the mesh's light island colours.
  const collide::test::PngImage image = collide::test::read_png(png);
  ASSERT_EQ(image.width, 300) << "no PNG at " << png;
  ASSERT_EQ(image.height, 300);
  const collide::Color ground = image.at(0, 0);
  EXPECT_LT(ground.r + ground.g + ground.b, 3 * 64) << "dark ground";
  constexpr int kIslandChannelMin = 150;  // walk_command.cpp's island colours are lighter than this
  const int mesh = collide::test::count_pixels(image, [](collide::Color c) {
    return c.r >= kIslandChannelMin && c.g >= kIslandChannelMin && c.b >= kIslandChannelMin;
  });
  EXPECT_GT(mesh, 300 * 300 / 10) << "the walk mesh covers a tenth of the picture";
}

TEST(WalkCommand, SameSeedGivesTheSameReport) {
  const std::string level = std::string(COLLIDE_DATA_DIR) + "/meshes/recast/undulating.obj";
  const CommandRun a = run("walk " + level + " --agents 4 --steps 100 --seed 9");
  const CommandRun b = run("walk " + level + " --agents 4 --steps 100 --seed 9");
  ASSERT_EQ(a.status, 0) << a.output;
  EXPECT_EQ(a.output, b.output);
}

/// The number after `label` in the tool's report ("  islands           224").
long report_number(const std::string& output, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("\\n  " + label + "\\s+(\\d+)"))) return -1;
  return std::stol(m[1].str());
}

TEST(WalkCommand, ReportsWhatMakeWalkMeshBuildsForTheOptionsGiven) {
  const std::string level = std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj";
  const collide::TriangleSoup soup = collide::io::load_obj(level);
  long kept_default = 0;
  for (const auto& [args, slope_degrees, height] :
       {std::tuple<std::string, float, float>{"", 45.0f, 2.0f}, {" --max-slope 30 --agent-height 3", 30.0f, 3.0f}}) {
    const CommandRun r = run("walk " + level + args + " --agents 3 --steps 50");
    ASSERT_EQ(r.status, 0) << r.output;
    const collide::WalkMesh mesh =
        collide::make_walk_mesh(soup, {slope_degrees * std::numbers::pi_v<float> / 180.0f, height, {0.0f, 1.0f, 0.0f}});
    const collide::WalkMeshStats& s = mesh.stats();
    EXPECT_EQ(report_number(r.output, "level triangles"), static_cast<long>(s.input_triangles)) << args;
    EXPECT_EQ(report_number(r.output, "too steep"), static_cast<long>(s.too_steep_triangles)) << args;
    EXPECT_EQ(report_number(r.output, "triangles kept"), static_cast<long>(s.triangles)) << args;
    EXPECT_EQ(report_number(r.output, "islands"), static_cast<long>(s.islands)) << args;
    EXPECT_EQ(report_number(r.output, "boundary edges"), static_cast<long>(s.boundary_edges)) << args;
    if (args.empty()) kept_default = report_number(r.output, "triangles kept");
    if (!args.empty()) EXPECT_LT(report_number(r.output, "triangles kept"), kept_default);  // the options matter
    // How the walking went: some distance, not more than 3 agents x 50 steps x 0.1.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(distance walked\s+([0-9.]+))"))) << r.output;
    EXPECT_GT(std::stod(m[1].str()), 0.0);
    EXPECT_LE(std::stod(m[1].str()), 3 * 50 * 0.1 + 1e-3);
    EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(on-mesh check\s+150/150 positions)"))) << r.output;
  }
}

// Issue 15: a level of concave n-gon faces (8 to 12 sides, with ramps; tests/data/ngon_level.obj)
// was refused ("not convex (no fan of triangles covers it)"). Now every agent stays on the mesh
// by the tool's own check, the five floors are one island joined without T-junctions (the
// vertices where the ramps meet the floors' straight edges are triangle corners), and the
// crenellated wall is too steep to walk.
TEST(WalkCommand, AgentsOnALevelOfConcaveNgonsStayOnTheMesh) {
  const CommandRun r = run("walk " + std::string(COLLIDE_TEST_DATA_DIR) + "/ngon_level.obj --agents 16 --steps 400 --speed 0.25 --seed 15");
  ASSERT_EQ(r.status, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(on-mesh check\s+(\d+)/(\d+) positions)"))) << r.output;
  EXPECT_EQ(m[1].str(), m[2].str()) << r.output;
  EXPECT_EQ(std::stoi(m[2].str()), 16 * 400);
  EXPECT_EQ(report_number(r.output, "level triangles"), 34) << r.output;  // 10 + 2 + 8 + 2 + 6 + 6
  EXPECT_EQ(report_number(r.output, "too steep"), 6) << r.output;         // the wall
  EXPECT_EQ(report_number(r.output, "degenerate"), 0) << r.output;
  EXPECT_EQ(report_number(r.output, "islands"), 1) << r.output;
  std::smatch splits;
  ASSERT_TRUE(std::regex_search(r.output, splits, std::regex(R"((\d+) T-junction splits)"))) << r.output;
  EXPECT_EQ(splits[1].str(), "0") << r.output;
  EXPECT_GT(report_number(r.output, "edges crossed"), 100) << r.output;
}

TEST(WalkCommand, MalformedLevelFailsNamingTheFileAndLine) {
  const std::string path = ::testing::TempDir() + "walk_bad_level.obj";
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 0 nan\nf 1 2 3\n";
  const CommandRun r = run("walk " + path);
  std::remove(path.c_str());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("walk_bad_level.obj:3: vertex 3: coordinate z 'nan' is not finite"), std::string::npos) << r.output;
}

TEST(WalkCommand, MissingLevelFailsNamingTheFile) {
  const CommandRun r = run("walk /nonexistent/level.obj");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("level.obj"), std::string::npos) << r.output;
}

}  // namespace
