// `collide run --layers` and the layers part of the run summary (issue 15): the sticker-knight
// sandbox with its ground and edges runs with zero tunnelling and its decorations skipped, an
// unknown name is exit status 2 listing the map's layers, and the shared maps keep the statics
// they had (melonJS's map1 alone changes: its Collision layer is declared by name).

#include "cli_run.hpp"
#include "run.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <regex>
#include <string>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

const fs::path kTiled = fs::path(COLLIDE_DATA_DIR) / "tiled";
const std::string kSandbox = (kTiled / "mapeditor-tiled/sticker-knight/map/sandbox.tmx").string();

RunOptions small(std::string input, int bodies, int frames) {
  RunOptions o;
  o.input = std::move(input);
  o.bodies = bodies;
  o.frames = frames;
  o.progress = false;
  return o;
}

TEST(RunLayers, StickerKnightGroundAndBoundsRunWithZeroTunnellingAndTheDecorationsSkipped) {
  const test::CommandRun r =
      test::run_cli("run " + kSandbox + " --layers ground,bounds --bodies 300 --frames 600 --seed 5 --no-progress");
  ASSERT_EQ(test::exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("layers (2 used, 9 skipped; chosen by --layers)\n"
                          "  used     'ground' (object layer, 35 objects, 35 colliders): named in layers\n"
                          "  used     'bounds' (object layer, 2 objects, 2 colliders): named in layers\n"),
            std::string::npos)
      << r.output;
  for (const char* deco : {"static", "parallax clouds", "parallax background", "background", "castle", "castledeco",
                           "shading", "game", "above"}) {
    EXPECT_TRUE(std::regex_search(r.output, std::regex("  skipped  '" + std::string(deco) +
                                                       R"(' \(object layer, \d+ objects?\): not named in layers\n)")))
        << deco << "\n"
        << r.output;
  }
  // The independent check: no body ended a frame inside the ground or outside the world.
  EXPECT_NE(r.output.find("tunnelled      0 bodies"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("escaped        0 bodies"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("41 statics"), std::string::npos) << r.output;  // 37 colliders + 4 walls
  EXPECT_NE(r.output.find("300 bodies"), std::string::npos) << r.output;  // the art no longer fills the space
}

// The same through run_world, with many bodies: the decorations' statics are gone, nothing
// tunnels, and a different world makes a different state.
TEST(RunLayers, NamingTheLayersTakesTheArtOutOfTheWorld) {
  RunOptions all = small(kSandbox, 2000, 120);
  RunOptions named = all;
  named.layers = {"ground", "bounds"};
  const RunReport with_art = run_world(all, nullptr);
  const RunReport without = run_world(named, nullptr);
  EXPECT_EQ(with_art.statics, 114 + 4);
  EXPECT_EQ(without.statics, 37 + 4);
  EXPECT_EQ(without.bodies, 2000);
  EXPECT_NE(without.state_hash, with_art.state_hash);
  EXPECT_EQ(without.total.tunnelled, 0);
  EXPECT_EQ(without.total.escaped, 0);
  EXPECT_EQ(with_art.total.tunnelled, 0);
}

TEST(RunLayers, AnUnknownLayerIsExitStatus2ListingTheMapsLayers) {
  test::CommandRun r = test::run_cli("run " + kSandbox + " --layers ground,clouds --frames 1 --no-progress");
  EXPECT_EQ(test::exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide run: " + kSandbox + ": layers: 'clouds' is no layer of the map (its layers: 'static', "
                          "'parallax clouds', 'parallax background', 'background', 'ground', 'castle', 'castledeco', "
                          "'shading', 'game', 'above', 'bounds')"),
            std::string::npos)
      << r.output;
  r = test::run_cli("run --layers ground --frames 1 --no-progress");  // the default scene has no layers
  EXPECT_EQ(test::exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide run: --layers: only Tiled maps have layers, not scene 'default'"), std::string::npos)
      << r.output;
  // --layers takes one list per use: the map after it is the scene, not a layer.
  r = test::run_cli("run --layers ground --layers bounds " + kSandbox + " --frames 1 --no-progress");
  EXPECT_EQ(test::exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("layers (2 used, 9 skipped; chosen by --layers)"), std::string::npos) << r.output;
}

// The default rule keeps what every shared map had, but for melonJS's map1: 31 statics before
// (its Player, Coins, Slimes and Flies spawn boxes were walls), the 19 Collision objects now.
TEST(RunLayers, SharedMapsKeepTheirStaticsButMelonJsKeepsItsCollisionLayerOnly) {
  const std::map<std::string, int> statics = {  // measured on main before the layer rule, minus map1
      {"mapeditor-tiled/sticker-knight/map/sandbox.tmx", 118},
      {"melonjs/platformer/map/map1.tmx", 19 + 4},
      {"raytmx/examples/assets/example.tmx", 232},
      {"raytmx/test/assets/collision_tiles.tmx", 78},
      {"tileson/test-maps/ultimate_test.json", 221},
      {"tileson/test-maps/ultimate_test.tmx", 212},
      {"tmxlite/ParseTest/maps/platform.tmx", 34},
  };
  for (const auto& [file, count] : statics) {
    SCOPED_TRACE(file);
    const RunReport r = run_world(small((kTiled / file).string(), 20, 1), nullptr);
    EXPECT_EQ(r.statics, count);
  }
  const test::CommandRun r = test::run_cli("run " + (kTiled / "melonjs/platformer/map/map1.tmx").string() +
                                           " --bodies 80 --frames 45 --no-progress");
  ASSERT_EQ(test::exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("layers (1 used, 9 skipped; the map's declarations decide, or --layers NAME,...)\n"
                          "  used     'Collision' (object layer, 19 objects, 19 colliders): name contains 'collision'\n"
                          "  skipped  'Background' (image layer): an image layer has no shapes\n"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("  skipped  'Player' (object layer, 4 objects): not declared a collision layer (the map "
                          "declares 'Collision')\n"),
            std::string::npos)
      << r.output;
}

// Issue 15's standing rule: the default scene's state hash does not move with the map loader's
// layer rules. (It moved once since, at stop 91, by a change of the step itself: a fast body
// clear of statics ends its motion composed as a slow body's, 3fa9a3fc4584e765 before.)
TEST(RunLayers, DefaultSceneStateHashIsUnchanged) {
  const test::CommandRun r = test::run_cli("run --no-progress");
  ASSERT_EQ(test::exit_code(r), 0) << r.output;
  EXPECT_NE(r.output.find("state hash       7f86a2aecc4de4d7"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("layers ("), std::string::npos) << "only maps have layers";
}

}  // namespace
}  // namespace collide::cli
