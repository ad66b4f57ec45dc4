// `collide walk` end to end through the real binary, on the shared dungeon level: it must exit 0,
// report every sampled position on the walk mesh, and write a real PNG; a missing file must fail
// with a message that names it.

#include "cli_run.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <regex>
#include <string>

namespace {

using collide::test::CommandRun;
const auto run = collide::test::run_cli;

TEST(WalkCommand, AgentsOnTheDungeonStayOnTheMeshAndThePictureIsAPng) {
  const std::string png = ::testing::TempDir() + "collide_walk_test.png";
  std::remove(png.c_str());
  const CommandRun r = run("walk " + std::string(COLLIDE_DATA_DIR) +
                    "/meshes/recast/dungeon.obj --agents 8 --steps 200 --seed 3 --png " + png);
  ASSERT_EQ(r.status, 0) << r.output;
  // "on-mesh check     1600/1600 positions on the mesh ..."
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(on-mesh check\s+(\d+)/(\d+) positions)")))
      << r.output;
  EXPECT_EQ(m[1].str(), m[2].str()) << r.output;
  EXPECT_EQ(std::stoi(m[2].str()), 8 * 200);
  EXPECT_TRUE(collide::test::has_png_signature(png)) << "no PNG at " << png;
}

TEST(WalkCommand, SameSeedGivesTheSameReport) {
  const std::string level = std::string(COLLIDE_DATA_DIR) + "/meshes/recast/undulating.obj";
  const CommandRun a = run("walk " + level + " --agents 4 --steps 100 --seed 9");
  const CommandRun b = run("walk " + level + " --agents 4 --steps 100 --seed 9");
  ASSERT_EQ(a.status, 0) << a.output;
  EXPECT_EQ(a.output, b.output);
}

TEST(WalkCommand, MissingLevelFailsNamingTheFile) {
  const CommandRun r = run("walk /nonexistent/level.obj");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("level.obj"), std::string::npos) << r.output;
}

}  // namespace
