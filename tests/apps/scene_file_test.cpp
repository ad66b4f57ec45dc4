// `collide run SCENE.json`: a scene file is the same world as the one built by hand through the
// World2D API (same state hash after the same frames), its spawn count and seed follow the file
// unless the command line overrides them, the example scenes run through the real binary with
// every option (exit 0, nothing tunnelled, the same hash in a second process), and a bad file is
// exit status 2 with a message that names the file and the JSON path.

#include "cli_run.hpp"
#include "run.hpp"
#include "support/picture_checks.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/palette.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

using test::CommandRun;
const auto run_cli = test::run_cli;

/// Writes `text` to a file named `name` in the test's temporary folder; returns its path.
std::string write_scene(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

RunOptions options_for(const std::string& input, int frames) {
  RunOptions o;
  o.input = input;
  o.frames = frames;
  o.progress = false;
  return o;
}

// A closed box (walls given as statics, "walls": 0), a concave L, a mirror, a chain, a sensor, a
// static of two pieces; bodies of every shape, a concave one, a bullet, a layered ghost and a
// sensor body. Below, the same world built by hand.
constexpr const char* kHandScene = R"({
  "bounds": [-20, -10, 20, 10],
  "walls": 0,
  "statics": [
    {"user_id": 1, "transform": {"p": [0, -10.5]}, "shape": {"type": "box", "half": [21, 0.5]}},
    {"user_id": 1, "transform": {"p": [0, 10.5]}, "shape": {"type": "box", "half": [21, 0.5]}},
    {"user_id": 1, "transform": {"p": [-20.5, 0]}, "shape": {"type": "box", "half": [0.5, 11]}},
    {"user_id": 1, "transform": {"p": [20.5, 0]}, "shape": {"type": "box", "half": [0.5, 11]}},
    {"user_id": 10, "transform": {"p": [-8, -4], "angle": 0.4},
     "shape": {"type": "polygon", "concave": true, "vertices": [[0, 0], [6, 0], [6, 1.5], [1.5, 1.5], [1.5, 6], [0, 6]]}},
    {"user_id": 11, "transform": {"p": [6, 3], "angle": -0.7}, "shape": {"type": "segment", "a": [-4, 0], "b": [4, 0]}},
    {"user_id": 12, "shape": {"type": "polyline", "points": [[8, -8], [12, -5], [16, -8]]}},
    {"user_id": 13, "transform": {"p": [0, 5]}, "sensor": true, "shape": {"type": "circle", "radius": 2.5}},
    {"user_id": 14, "transform": {"p": [12, 4]},
     "shapes": [{"type": "capsule", "a": [-1, 0], "b": [1, 0], "radius": 0.5},
                {"type": "polygon", "vertices": [[-1, 1], [1, 1], [0, 2.5]], "radius": 0.1}]}
  ],
  "bodies": [
    {"user_id": 100, "transform": {"p": [-15, 5]}, "velocity": [7, -3], "shape": {"type": "circle", "radius": 0.7}},
    {"user_id": 101, "transform": {"p": [-12, 7], "angle": 1.1}, "velocity": [-4, -6], "angular_velocity": 2,
     "shape": {"type": "box", "half": [0.8, 0.4]}},
    {"user_id": 102, "transform": {"p": [15, -2]}, "velocity": [-9, 2.5], "angular_velocity": -0.5,
     "shape": {"type": "capsule", "a": [-0.6, 0], "b": [0.6, 0], "radius": 0.3}},
    {"user_id": 103, "transform": {"p": [3, -6]}, "velocity": [1, 8],
     "shape": {"type": "polygon", "vertices": [[-0.5, -0.5], [0.7, -0.3], [0.4, 0.6], [-0.6, 0.4]]}},
    {"user_id": 104, "transform": {"p": [-3, 8]}, "velocity": [5, -5],
     "shape": {"type": "polygon", "concave": true, "vertices": [[0, 0], [1.2, 0], [1.2, 0.4], [0.4, 0.4], [0.4, 1.2], [0, 1.2]]}},
    {"user_id": 105, "bullet": true, "transform": {"p": [-18, -8]}, "velocity": [400, 130], "shape": {"type": "circle", "radius": 0.1}},
    {"user_id": 106, "layer": 4, "mask": 1, "transform": {"p": [17, 8]}, "velocity": [-6, -6], "shape": {"type": "circle", "radius": 0.5}},
    {"user_id": 107, "sensor": true, "transform": {"p": [0, 0]}, "velocity": [2, 3], "shape": {"type": "circle", "radius": 1}}
  ],
  "laser": {"origin": [-19, 0], "translation": [100, 10], "sweep": 0.01}
})";

/// kHandScene through the World2D API; `nudge` is added to body 100's x velocity.
World2D hand_built_world(float nudge = 0.0f) {
  World2D world(WorldOptions{WorldBroadPhase::temporal, Aabb{{-20, -10}, {20, 10}}, true, true});
  const auto add_static = [&](std::uint64_t user, Transform xf, std::vector<Shape2D> shapes, bool sensor = false) {
    StaticDef def;
    def.shapes = std::move(shapes);
    def.transform = xf;
    def.user_id = user;
    def.sensor = sensor;
    world.add_static(def);
  };
  add_static(1, Transform::from({0, -10.5f}, 0), {make_box({21, 0.5f})});
  add_static(1, Transform::from({0, 10.5f}, 0), {make_box({21, 0.5f})});
  add_static(1, Transform::from({-20.5f, 0}, 0), {make_box({0.5f, 11})});
  add_static(1, Transform::from({20.5f, 0}, 0), {make_box({0.5f, 11})});
  const std::vector<Vec2> l = {{0, 0}, {6, 0}, {6, 1.5f}, {1.5f, 1.5f}, {1.5f, 6}, {0, 6}};
  add_static(10, Transform::from({-8, -4}, 0.4f), convex_pieces(l));
  add_static(11, Transform::from({6, 3}, -0.7f), {make_segment({-4, 0}, {4, 0})});
  add_static(12, Transform{}, {make_segment({8, -8}, {12, -5}), make_segment({12, -5}, {16, -8})});
  add_static(13, Transform::from({0, 5}, 0), {make_circle({0, 0}, 2.5f)}, true);
  const std::vector<Vec2> triangle = {{-1, 1}, {1, 1}, {0, 2.5f}};
  add_static(14, Transform::from({12, 4}, 0), {make_capsule({-1, 0}, {1, 0}, 0.5f), make_convex_polygon(triangle, 0.1f)});

  const auto body = [](std::uint64_t user, Transform xf, Vec2 v, float w, std::vector<Shape2D> shapes) {
    BodyDef def;
    def.shapes = std::move(shapes);
    def.transform = xf;
    def.velocity = v;
    def.angular_velocity = w;
    def.user_id = user;
    return def;
  };
  world.add_body(body(100, Transform::from({-15, 5}, 0), {7 + nudge, -3}, 0, {make_circle({0, 0}, 0.7f)}));
  world.add_body(body(101, Transform::from({-12, 7}, 1.1f), {-4, -6}, 2, {make_box({0.8f, 0.4f})}));
  world.add_body(body(102, Transform::from({15, -2}, 0), {-9, 2.5f}, -0.5f, {make_capsule({-0.6f, 0}, {0.6f, 0}, 0.3f)}));
  const std::vector<Vec2> quad = {{-0.5f, -0.5f}, {0.7f, -0.3f}, {0.4f, 0.6f}, {-0.6f, 0.4f}};
  world.add_body(body(103, Transform::from({3, -6}, 0), {1, 8}, 0, {make_convex_polygon(quad)}));
  const std::vector<Vec2> small_l = {{0, 0}, {1.2f, 0}, {1.2f, 0.4f}, {0.4f, 0.4f}, {0.4f, 1.2f}, {0, 1.2f}};
  world.add_body(body(104, Transform::from({-3, 8}, 0), {5, -5}, 0, convex_pieces(small_l)));
  BodyDef bullet = body(105, Transform::from({-18, -8}, 0), {400, 130}, 0, {make_circle({0, 0}, 0.1f)});
  bullet.bullet = true;
  world.add_body(bullet);
  BodyDef ghost = body(106, Transform::from({17, 8}, 0), {-6, -6}, 0, {make_circle({0, 0}, 0.5f)});
  ghost.filter = {4, 1};
  world.add_body(ghost);
  BodyDef sensor = body(107, Transform::from({0, 0}, 0), {2, 3}, 0, {make_circle({0, 0}, 1)});
  sensor.sensor = true;
  world.add_body(sensor);
  return world;
}

TEST(RunWorld, SceneFileIsTheSameWorldAsBuiltByHand) {
  constexpr int kFrames = 300;
  const RunReport r = run_world(options_for(write_scene("hand_scene.json", kHandScene), kFrames), nullptr);
  World2D world = hand_built_world();
  for (int f = 0; f < kFrames; ++f) world.step(1.0f / 60.0f);
  EXPECT_EQ(r.statics, world.static_count());
  EXPECT_EQ(r.bodies, world.body_count());
  EXPECT_EQ(r.bodies, 8);
  EXPECT_EQ(r.static_pieces, 4 + 2 + 1 + 2 + 1 + 2);  // walls, L, mirror, chain, sensor, capsule + triangle
  EXPECT_EQ(r.state_hash, world.state_hash());
  EXPECT_EQ(r.total.contacts, world.total_stats().contacts);
  EXPECT_EQ(r.total.begin_events, world.total_stats().begin_events);
  // Not a trivially equal pair of quiet worlds: things happened, and the hash sees a change of
  // one body's speed in the sixth digit.
  EXPECT_GT(r.total.contacts, 20);
  EXPECT_GT(r.total.sensor_contacts, 0);
  EXPECT_GT(r.total.toi_hits, 10);  // the bullet
  EXPECT_GT(r.laser_hits, kFrames);
  EXPECT_EQ(r.total.tunnelled, 0);
  EXPECT_EQ(r.total.escaped, 0);
  World2D nudged = hand_built_world(1e-5f);
  for (int f = 0; f < kFrames; ++f) nudged.step(1.0f / 60.0f);
  EXPECT_NE(nudged.state_hash(), world.state_hash());
}

constexpr const char* kSpawnScene = R"({
  "bounds": [-30, -30, 30, 30],
  "statics": [{"shape": {"type": "polygon", "concave": true, "vertices": [[0, 0], [10, 0], [10, 3], [3, 3], [3, 10], [0, 10]]}}],
  "bodies": [{"transform": {"p": [-20, -20]}, "velocity": [5, 5], "shape": {"type": "circle", "radius": 1}}],
  "spawn": {"count": 60, "seed": 9, "bullets": 3, "radius": [0.3, 0.8], "speed": [2, 10], "bullet_speed": 200}
})";

TEST(RunWorld, SceneSpawnTakesCountAndSeedFromTheFileUnlessTheCommandLineGivesThem) {
  const std::string path = write_scene("spawn_scene.json", kSpawnScene);
  const RunReport file = run_world(options_for(path, 60), nullptr);
  EXPECT_EQ(file.bodies, 61);
  EXPECT_EQ(file.total.tunnelled, 0);
  RunOptions same_seed = options_for(path, 60);
  same_seed.seed = 9;
  same_seed.seed_given = true;
  EXPECT_EQ(run_world(same_seed, nullptr).state_hash, file.state_hash);
  RunOptions other_seed = options_for(path, 60);
  other_seed.seed = 1;  // the default, but given: it overrides the file's 9
  other_seed.seed_given = true;
  EXPECT_NE(run_world(other_seed, nullptr).state_hash, file.state_hash);
  RunOptions fewer = options_for(path, 60);
  fewer.bodies = 20;
  EXPECT_EQ(run_world(fewer, nullptr).bodies, 21);
  // A scene without spawn: only its own bodies, unless --bodies asks for more.
  const std::string bare = write_scene("bare_scene.json", R"({"bounds": [-30, -30, 30, 30],
    "bodies": [{"velocity": [5, 5], "shape": {"type": "circle", "radius": 1}}]})");
  EXPECT_EQ(run_world(options_for(bare, 10), nullptr).bodies, 1);
  RunOptions more = options_for(bare, 10);
  more.bodies = 25;
  const RunReport spawned = run_world(more, nullptr);
  EXPECT_EQ(spawned.bodies, 26);
  EXPECT_EQ(spawned.total.tunnelled, 0);
  EXPECT_EQ(spawned.total.escaped, 0);
}

int exit_status(const CommandRun& r) { return WIFEXITED(r.status) ? WEXITSTATUS(r.status) : -1; }

std::string hash_of(const std::string& output) {
  std::smatch m;
  return std::regex_search(output, m, std::regex(R"(state hash\s+([0-9a-f]{16}))")) ? m[1].str() : "none";
}

// The examples through the real binary with the options of the issue: exit 0, the summary echoes
// the options, the check reads 0, every event line parses as counted, pictures are written, and
// a second process ends in the same state.
TEST(RunCommand, ExampleScenesRunThroughTheBinary) {
  const std::vector<std::pair<std::string, int>> scenes = {{"pinball.json", 50}, {"thin_walls.json", 202}};
  for (const auto& [name, bodies] : scenes) {
    const std::string scene = std::string(COLLIDE_EXAMPLES_DIR) + "/scenes/" + name;
    SCOPED_TRACE(scene);
    const std::string base = ::testing::TempDir() + "collide_scene_" + name;
    const std::string events = base + ".jsonl", png = base + ".png", svg = base + ".svg";
    for (const std::string& f : {events, png, svg}) std::remove(f.c_str());
    const std::string args = "run " + scene + " --frames 120 --dt 0.01 --seed 5";
    const CommandRun r = run_cli(args + " --events " + events + " --png " + png + " --svg " + svg + " --width 800");
    ASSERT_EQ(exit_status(r), 0) << r.output;
    EXPECT_NE(r.output.find("collide run: " + scene), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("120 frames of 10.00 ms"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("seed 5"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(", " + std::to_string(bodies) + " bodies ("), std::string::npos) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(tunnelled\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0");
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(escaped\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0");
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"((\d+) written to)"))) << r.output;
    std::ifstream in(events);
    long lines = 0;
    for (std::string line; std::getline(in, line); ++lines) {
      EXPECT_NE(line.find("\"type\":"), std::string::npos) << line;
    }
    EXPECT_EQ(lines, std::stol(m[1].str()));
    EXPECT_GT(lines, 0);
    // The pictures: a PNG 800 pixels wide showing static geometry, the laser's hits and fast
    // bodies in their palette colours, and an SVG of the same size.
    const test::PngImage image = test::read_png(png);
    ASSERT_EQ(image.width, 800) << png;
    for (const DrawRole role : {DrawRole::static_geometry, DrawRole::fast_body}) {
      const Color fill = test::over(draw_style(role).fill, kPictureBackground);
      EXPECT_GT(test::count_pixels(image, [&](Color c) { return test::near(c, fill); }), 0) << to_string(role);
    }
    const Color hit = draw_style(DrawRole::laser_hit).stroke;
    EXPECT_GT(test::count_pixels(image, [&](Color c) { return c == hit; }), 0) << "laser hit";
    pugi::xml_document doc;
    ASSERT_TRUE(doc.load_file(svg.c_str())) << svg;
    EXPECT_EQ(std::string(doc.child("svg").attribute("height").value()), std::to_string(image.height) + "px");
    const std::string hash = hash_of(r.output);
    ASSERT_NE(hash, "none") << r.output;
    const CommandRun again = run_cli(args + " --broadphase sweep_and_prune");
    ASSERT_EQ(exit_status(again), 0) << again.output;
    EXPECT_EQ(hash_of(again.output), hash) << again.output;
  }
  // Without --seed the file's own seed is used and shown.
  const CommandRun pinball = run_cli("run " + std::string(COLLIDE_EXAMPLES_DIR) + "/scenes/pinball.json --frames 10");
  ASSERT_EQ(exit_status(pinball), 0) << pinball.output;
  EXPECT_NE(pinball.output.find("seed 7"), std::string::npos) << pinball.output;
}

TEST(RunCommand, SceneWithoutALaserSaysSo) {
  const std::string path = write_scene("no_laser.json", R"({"bounds": [-5, -5, 5, 5],
    "bodies": [{"velocity": [3, 1], "shape": {"type": "circle", "radius": 0.5}}]})");
  const CommandRun r = run_cli("run " + path + " --frames 30");
  ASSERT_EQ(exit_status(r), 0) << r.output;
  EXPECT_NE(r.output.find("laser          none in this scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 bodies"), std::string::npos) << r.output;
}

// Bad files: exit status 2 and one line naming the file and the JSON path, never a crash.
TEST(RunCommand, BadSceneFilesExitWithStatus2NamingTheFileAndThePath) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"bounds": [0, 0, 10, 10], "statics": [{"shape": {"type": "circle", "radius": -1}}]})",
       "bad_scene.json: statics[0].shape.radius: negative (-1)"},
      {R"({"bounds": [0, 0, 10, 10], "statics": [{"shape": {"type": "circle", "radius": 1e400}}]})",
       "bad_scene.json: statics[0].shape.radius: not a finite float (1e400 is beyond double range)"},
      {"{\"bounds\": [0, 0, 10, 10],\n \"bodies\": [{\"shape\": {\"type\": \"circle\" \"radius\": 1}}]}",
       "bad_scene.json: bodies[0].shape: JSON syntax error at line 2, column"},
      {R"({"bounds": [0, 0, 10, 10], "statics": [{"shape": {"type": "polygon", "vertices": [[0, 0], [2, 0], [1, 0.5], [2, 2], [0, 2]]}}]})",
       "bad_scene.json: statics[0].shape.vertices: polygon vertex 2: turns clockwise"},
      {R"({"bounds": [0, 0, 10, 10], "bodies": [{"shape": {"type": "circle", "radius": 1}, "transform": {"p": [0.5, 5]}}]})",
       "bad_scene.json: bodies[0]: reaches outside the bounds"},
  };
  for (const auto& [text, message] : cases) {
    const std::string path = write_scene("bad_scene.json", text);
    const CommandRun r = run_cli("run " + path + " --frames 5");
    EXPECT_EQ(exit_status(r), 2) << r.output;
    EXPECT_NE(r.output.find("collide run: " + ::testing::TempDir() + message), std::string::npos)
        << "'" << message << "' not in: " << r.output;
  }
  const std::string folder = ::testing::TempDir() + "folder_scene.json";
  fs::create_directories(folder);
  const CommandRun r = run_cli("run " + folder);
  EXPECT_EQ(exit_status(r), 2) << r.output;
  EXPECT_NE(r.output.find(folder + ": cannot be read"), std::string::npos) << r.output;
}

/// A small walled level with a static box, a segment, a body and spawned bodies and bullets,
/// every length (positions, sizes, speeds, walls) times `scale`.
std::string scaled_scene(double scale) {
  const auto n = [&](double v) {
    std::ostringstream os;
    os.precision(9);
    os << v * scale;
    return os.str();
  };
  return R"({"bounds": [)" + n(-20) + ", " + n(-10) + ", " + n(20) + ", " + n(10) + R"(], "walls": )" + n(0.5) +
         R"(, "statics": [{"transform": {"p": [0, )" + n(-3) + R"(]}, "shape": {"type": "box", "half": [)" + n(6) + ", " +
         n(0.5) + R"(]}}, {"shape": {"type": "segment", "a": [)" + n(-10) + ", " + n(4) + R"(], "b": [)" + n(-4) + ", " +
         n(6) + R"(]}}], "bodies": [{"transform": {"p": [0, )" + n(3) + R"(]}, "shape": {"type": "circle", "radius": )" +
         n(0.5) + R"(}, "velocity": [)" + n(3) + ", " + n(-7) + R"(]}], "spawn": {"count": 40, "radius": [)" + n(0.2) +
         ", " + n(0.4) + R"(], "speed": [)" + n(1) + ", " + n(5) + R"(], "bullets": 6, "bullet_speed": )" + n(400) + "}}";
}

// Issue 15: a level scaled by 1e10 and one with 1e38 bounds were accepted and then failed the
// independent check. Through the real binary: the level at its own scale and scaled by 1e6 runs
// with zero tunnelling and escapes; scaled by 1e10, with 1e38 bounds, with one static at 1e38,
// and a Tiled map with an object at 1e38 are refused before the first frame (exit 2), the file,
// the field and the range named.
TEST(RunCommand, ExtremeCoordinatesRunWithinTheRangeAndAreRefusedBeyondIt) {
  const std::string range = "beyond the coordinate range [-1073741824, 1073741824] (kMaxWorldCoordinate)";
  for (const double scale : {1.0, 1e6}) {
    const std::string path = write_scene("scaled_level.json", scaled_scene(scale));
    const CommandRun r = run_cli("run " + path + " --frames 200");
    ASSERT_EQ(exit_status(r), 0) << scale << ": " << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(tunnelled\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0") << scale;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(escaped\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0") << scale;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(, (\d+) bodies \()"))) << r.output;
    EXPECT_GT(std::stoi(m[1].str()), 30) << r.output;  // the spawned bodies fitted
  }
  const std::string tmx = ::testing::TempDir() + "far_object.tmx";
  std::ofstream(tmx) << R"(<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" width="4" height="4" tilewidth="16" tileheight="16">
 <objectgroup id="1" name="walls">
  <object id="1" x="0" y="0" width="64" height="8"/>
  <object id="2" x="1e38" y="0" width="16" height="16"/>
 </objectgroup>
</map>)";
  const std::vector<std::pair<std::string, std::string>> refused = {
      {write_scene("scaled_1e10.json", scaled_scene(1e10)), "scaled_1e10.json: bounds (with the walls): the box"},
      {write_scene("bounds_1e38.json", R"({"bounds": [-1e38, -1e38, 1e38, 1e38], "walls": 0})"),
       "bounds_1e38.json: bounds: the box [-1e+38, -1e+38, 1e+38, 1e+38] reaches -1e+38, "},
      {write_scene("static_1e38.json", R"({"bounds": [0, 0, 10, 10],
         "statics": [{"shape": {"type": "circle", "radius": 1}}, {"transform": {"p": [1e38, 5]}, "shape": {"type": "circle", "radius": 1}}]})"),
       "static_1e38.json: statics[1] shapes[0]: the box"},
  };
  for (const auto& [path, message] : refused) {
    const CommandRun r = run_cli("run " + path + " --frames 5");
    EXPECT_EQ(exit_status(r), 2) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << "'" << message << "' not in: " << r.output;
    EXPECT_NE(r.output.find(range), std::string::npos) << r.output;
  }
  // A Tiled map is refused by its reader first, at the far smaller kMaxTiledCoordinate (docs/limits.md).
  const CommandRun r = run_cli("run " + tmx + " --frames 5");
  EXPECT_EQ(exit_status(r), 2) << r.output;
  EXPECT_NE(r.output.find("far_object.tmx: <object id=2>: attribute x: 1e+38 is beyond +-1e7 (the limit, kMaxTiledCoordinate)"),
            std::string::npos) << r.output;
}

}  // namespace
}  // namespace collide::cli
