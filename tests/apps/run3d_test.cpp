// `collide run` in 3D: the embedded 3D scene and OBJ levels through run_world3d (the code behind
// the command), and the command end to end through the real binary. The independent checks (no
// body inside static geometry or across a level surface, none out of the room, no character move
// ending inside the level) must hold on the embedded scene, every shared mesh and levels written
// here the way exporters write them (n-gons, concave faces, holes, low ceilings, far from the
// origin); the state hash must not depend on the run, the broad phase or the early-out learning.

#include "cli_run.hpp"
#include "run.hpp"
#include "run_checks.hpp"

#include <collide/core/error.hpp>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

using test::CommandRun;
const auto run_cli = test::run_cli;

RunOptions small3d(std::string input, int bodies, int frames) {
  RunOptions o;
  o.input = std::move(input);
  o.three_d = true;
  o.bodies = bodies;
  o.frames = frames;
  o.progress = false;
  return o;
}

TEST(RunWorld3D, SameStateHashForEveryThreadCount) {
  // The 3D world runs the same step on the workers (issue 20): bit for bit the same world.
  RunOptions o = small3d("", 250, 120);
  o.threads = 1;
  const RunReport one = run_world3d(o, nullptr);
  EXPECT_EQ(one.threads, 1);
  EXPECT_EQ(one.total.tunnelled, 0);
  for (const int threads : {2, 3}) {
    o.threads = threads;
    const RunReport many = run_world3d(o, nullptr);
    EXPECT_EQ(many.threads, threads);
    EXPECT_EQ(many.state_hash, one.state_hash) << threads << " threads";
    EXPECT_EQ(many.total.contacts, one.total.contacts) << threads << " threads";
  }
}

TEST(RunWorld3D, EmbeddedSceneStaysCheckedAndBusy) {
  CharacterReport c;
  const RunReport r = run_world3d(small3d("", 250, 240), nullptr, &c);
  EXPECT_EQ(r.bodies, 250);
  EXPECT_GT(r.statics, 30);
  EXPECT_EQ(r.total.tunnelled, 0);
  EXPECT_EQ(r.total.escaped, 0);
  EXPECT_EQ(r.characters_inside, 0);
  EXPECT_GT(r.total.contacts, 0);
  EXPECT_GT(r.total.toi_hits, 0);  // the bullets hit walls
  EXPECT_GT(r.total.begin_events, 0);
  EXPECT_GT(r.total.end_events, 0);
  EXPECT_GE(r.laser_hits, 2 * 240);  // the room is closed: a bounce and a last surface, at least
  // The characters: all eight placed and moved every frame, standing on the floor nearly always
  // (they fall only off ledges), never inside the level.
  EXPECT_EQ(c.characters, 8);
  EXPECT_EQ(c.moves, 8 * 240);
  EXPECT_LT(c.airborne, c.moves / 4);
  EXPECT_EQ(c.inside, 0);
  EXPECT_LT(c.max_penetration, 0.01f);
}

TEST(RunWorld3D, StateHashIsTheSameForEveryRunBroadPhaseAndEarlyOutChoice) {
  test::expect_hash_independent_of_choices([](const RunOptions& o) { return run_world3d(o, nullptr); }, small3d("", 200, 120),
                                           {WorldBroadPhase::brute_force, WorldBroadPhase::hash_grid, WorldBroadPhase::loose_grid,
                                            WorldBroadPhase::dynamic_tree, WorldBroadPhase::sweep_and_prune});
}

TEST(RunWorld3D, GravityPilesTheBodiesOnTheFloorWithoutTunnelling) {
  RunOptions o = small3d("", 200, 300);
  o.gravity = 9.81f;
  const RunReport r = run_world3d(o, nullptr);
  EXPECT_EQ(r.total.tunnelled, 0);
  EXPECT_EQ(r.total.escaped, 0);
  EXPECT_GT(r.total.contacts, r.frames);  // bodies rest on the floor, the ramps and each other
}

// The issue: every mesh under the shared meshes folder runs as a level.
TEST(RunWorld3D, EverySharedMeshRunsWithoutTunnelling) {
  int meshes = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(COLLIDE_DATA_DIR) / "meshes")) {
    if (entry.path().extension() != ".obj") continue;
    SCOPED_TRACE(entry.path().string());
    CharacterReport c;
    const RunReport r = run_world3d(small3d(entry.path().string(), 150, 240), nullptr, &c);
    ++meshes;
    EXPECT_EQ(r.statics, 1);
    EXPECT_GT(r.bodies, 100);
    EXPECT_EQ(r.total.tunnelled, 0);
    EXPECT_EQ(r.characters_inside, 0);
    EXPECT_GT(c.characters, 0);
    EXPECT_EQ(run_world3d(small3d(entry.path().string(), 150, 240), nullptr).state_hash, r.state_hash);
  }
  EXPECT_EQ(meshes, 4);
}

// ---- OBJ levels no shared file has, written as exporters write them ---------------------------

/// A level as OBJ text: a floor of quads around a hole and an L-shaped concave n-gon beside it,
/// a 16-gon platform reached by a 30 degree ramp, a slab with a low ceiling under it (lower
/// than a character in part), a few walls, no outer walls (an open mesh). `offset` moves it all;
/// `crlf` ends lines as Windows tools do. Faces use every index form (v, v/vt, v//vn, v/vt/vn,
/// negative), with groups, materials and smoothing statements between them.
std::string level_obj(Vec3 offset, bool crlf) {
  std::ostringstream s;
  const char* eol = crlf ? "\r\n" : "\n";
  int count = 0;
  const auto v = [&](float x, float y, float z) {
    s << "v " << x + offset.x << ' ' << y + offset.y << ' ' << z + offset.z << eol;
    return ++count;
  };
  s << "# written by run3d_test.cpp as a modelling tool would" << eol << "mtllib level.mtl" << eol;
  s << "vt 0 0" << eol << "vt 1 0" << eol << "vt 1 1" << eol << "vn 0 1 0" << eol;
  // Floor: 2 x 2 quads over [0, 24]^2, one of them missing (a hole at [12, 14] x [12, 14]).
  s << "o floor" << eol << "usemtl stone" << eol << "s off" << eol;
  for (int j = 0; j < 12; ++j) {
    for (int i = 0; i < 12; ++i) {
      if (i == 6 && j == 6) continue;
      const float x = 2.0f * static_cast<float>(i), z = 2.0f * static_cast<float>(j);
      const int a = v(x, 0, z), b = v(x, 0, z + 2), c = v(x + 2, 0, z + 2), d = v(x + 2, 0, z);
      // Counter-clockwise seen from above (+y): a, b, c, d (z grows towards the viewer).
      if ((i + j) % 3 == 0) {
        s << "f " << a << "/1/1 " << b << "/2/1 " << c << "/3/1 " << d << "/1/1" << eol;
      } else if ((i + j) % 3 == 1) {
        s << "f " << a << "//1 " << b << "//1 " << c << "//1 " << d << "//1" << eol;
      } else {
        s << "f -4 -3 -2 -1" << eol;
      }
    }
  }
  // An L-shaped floor beside it, one concave face of 8 vertices (two on straight edges).
  s << "g annex" << eol;
  const int l0 = v(24, 0, 0), l1 = v(24, 0, 24), l2 = v(32, 0, 24), l3 = v(32, 0, 16), l4 = v(28, 0, 16);
  const int l5 = v(28, 0, 8), l6 = v(36, 0, 8), l7 = v(36, 0, 0);
  s << "f " << l0 << ' ' << l1 << ' ' << l2 << ' ' << l3 << ' ' << l4 << ' ' << l5 << ' ' << l6 << ' ' << l7 << eol;
  // A 16-gon platform of radius 3 at height 2 over (6, 4), and a 30 degree ramp up to it.
  s << "g platform" << eol << "usemtl wood" << eol;
  std::vector<int> rim;
  for (int k = 0; k < 16; ++k) {
    const float a = -2.0f * std::numbers::pi_v<float> * static_cast<float>(k) / 16.0f;
    rim.push_back(v(6.0f + 3.0f * std::cos(a), 2.0f, 4.0f + 3.0f * std::sin(a)));
  }
  s << "f";
  for (const int k : rim) s << ' ' << k;
  s << eol;
  const float run = 2.0f / std::tan(std::numbers::pi_v<float> / 6.0f);
  const int r0 = v(9.0f + run, 0, 3), r1 = v(9.0f + run, 0, 5), r2 = v(8.9f, 2, 5), r3 = v(8.9f, 2, 3);
  s << "f " << r0 << ' ' << r3 << ' ' << r2 << ' ' << r1 << eol;
  // A slab over [2, 10] x [16, 22]: its underside 1.1 high over half and 0.5 over the other
  // half (lower than a character), 0.3 thick; faces down and up, sides closed.
  s << "g slab" << eol << "s 1" << eol;
  for (const auto& [x0, x1, h] : {std::tuple{2.0f, 6.0f, 1.1f}, std::tuple{6.0f, 10.0f, 0.5f}}) {
    const int b0 = v(x0, h, 16), b1 = v(x1, h, 16), b2 = v(x1, h, 22), b3 = v(x0, h, 22);
    const int t0 = v(x0, h + 0.3f, 16), t1 = v(x1, h + 0.3f, 16), t2 = v(x1, h + 0.3f, 22), t3 = v(x0, h + 0.3f, 22);
    s << "f " << b0 << ' ' << b1 << ' ' << b2 << ' ' << b3 << eol;  // facing down
    s << "f " << t0 << ' ' << t3 << ' ' << t2 << ' ' << t1 << eol;  // facing up
    s << "f " << b0 << ' ' << t0 << ' ' << t1 << ' ' << b1 << eol;
    s << "f " << b1 << ' ' << t1 << ' ' << t2 << ' ' << b2 << eol;
    s << "f " << b2 << ' ' << t2 << ' ' << t3 << ' ' << b3 << eol;
    s << "f " << b3 << ' ' << t3 << ' ' << t0 << ' ' << b0 << eol;
  }
  // Walls: thin quads (one face each, two-sided) standing on the floor.
  s << "g walls" << eol;
  for (const auto& [x, z0, z1] : {std::tuple{16.0f, 2.0f, 10.0f}, std::tuple{20.0f, 14.0f, 22.0f}}) {
    const int w0 = v(x, 0, z0), w1 = v(x, 3, z0), w2 = v(x, 3, z1), w3 = v(x, 0, z1);
    s << "f " << w0 << ' ' << w1 << ' ' << w2 << ' ' << w3 << eol;
  }
  return s.str();
}

std::string write_level(const std::string& name, Vec3 offset, bool crlf) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << level_obj(offset, crlf);
  return path;
}

TEST(RunWorld3D, LevelsAsExportersWriteThemRunWithoutTunnelling) {
  struct Case {
    const char* name;
    Vec3 offset;
    bool crlf;
  };
  for (const Case& k : {Case{"collide_level_origin.obj", Vec3(0.0f), false},
                        Case{"collide_level_windows.obj", Vec3(-3.5f, 1.25f, 7.0f), true},
                        Case{"collide_level_far.obj", Vec3(9000.0f, -150.0f, -7000.0f), false}}) {
    SCOPED_TRACE(k.name);
    const std::string path = write_level(k.name, k.offset, k.crlf);
    CharacterReport c;
    const RunReport r = run_world3d(small3d(path, 200, 300), nullptr, &c);
    EXPECT_EQ(r.statics, 1);
    EXPECT_GT(r.bodies, 150);
    EXPECT_EQ(r.total.tunnelled, 0);
    // Overlaps within the float spacing of the coordinates (1e-3 at 9000), far below the
    // check's own allowance there: a level's triangles are queried placed at a corner, not at
    // the origin (placed at the origin, a capsule 0.016 under a slab got a contact 0.047 deep).
    EXPECT_LT(r.total.max_static_depth, 2e-3f);
    EXPECT_GT(r.total.contacts + r.total.toi_hits, 0);
    EXPECT_EQ(c.characters, 8);
    EXPECT_EQ(c.inside, 0);
    EXPECT_EQ(r.characters_inside, 0);
    EXPECT_LT(c.airborne, c.moves);  // they stand on the floor (the hole and the open edges drop some)
  }
}

TEST(RunWorld3D, BadInputIsAnErrorThatNamesIt) {
  const auto message = [](const RunOptions& o) {
    try {
      (void)run_world3d(o, nullptr);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(small3d("/nonexistent/level.obj", 10, 10)).find("/nonexistent/level.obj"), std::string::npos);
  // A face that names a vertex the file does not have: the file and the line.
  const std::string broken = ::testing::TempDir() + "collide_level_broken.obj";
  std::ofstream(broken) << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\nf 1 2 9\n";
  const std::string m = message(small3d(broken, 10, 10));
  EXPECT_NE(m.find("collide_level_broken.obj:5"), std::string::npos) << m;
  RunOptions nan_dt = small3d("", 10, 10);
  nan_dt.dt = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(message(nan_dt).find("--dt"), std::string::npos);
  RunOptions svg = small3d("", 10, 10);
  svg.svg = ::testing::TempDir() + "x.svg";
  EXPECT_NE(message(svg).find("--svg"), std::string::npos);
  RunOptions layers = small3d("", 10, 10);
  layers.layers = {"walls"};
  EXPECT_NE(message(layers).find("--layers"), std::string::npos);
  // 3D options on a 2D run.
  RunOptions characters;
  characters.characters = 3;
  characters.frames = 1;
  EXPECT_THROW((void)run_world(characters, nullptr), InvalidInput);
  RunOptions gravity;
  gravity.gravity = 9.81f;
  gravity.frames = 1;
  EXPECT_THROW((void)run_world(gravity, nullptr), InvalidInput);
}

// The command end to end: the 3D summary with the characters' numbers, the events as JSON Lines
// with unit 3D normals, and a second process with other broad phase ending in the same state.
TEST(RunCommand3D, SummaryAndEventsEndToEnd) {
  const std::string events = ::testing::TempDir() + "collide_run3d_events.jsonl";
  std::remove(events.c_str());
  const CommandRun r = run_cli("run --3d --bodies 150 --frames 90 --seed 4 --characters 5 --events " + events);
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* line : {"(3D)", "5 characters", "broad phase", "early out", "narrow phase", "ccd", "events",
                           "laser", "characters ", "steps climbed", "time per frame", "escaped", "moves ended inside"}) {
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  }
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(characters\s+(\d+) moves ended inside)"))) << r.output;
  EXPECT_EQ(m[1].str(), "0");
  const test::RunSummary summary = test::expect_clean_summary(r.output);
  const std::string hash = summary.hash;
  ASSERT_FALSE(hash.empty());
  const long lines = test::expect_valid_events_file(events, 3);
  EXPECT_EQ(lines, summary.written);
  EXPECT_GT(lines, 20);
  const CommandRun again = run_cli("run --3d --bodies 150 --frames 90 --seed 4 --characters 5 --broadphase dynamic_tree");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find(hash), std::string::npos) << again.output;
  // An OBJ level is a 3D run by its name.
  const std::string level = write_level("collide_level_cli.obj", Vec3(0.0f), false);
  const CommandRun obj = run_cli("run " + level + " --bodies 60 --frames 30");
  ASSERT_EQ(obj.status, 0) << obj.output;
  EXPECT_NE(obj.output.find("(3D)"), std::string::npos) << obj.output;
}

// --png in 3D: a PNG of the asked width, from any camera --view names; a view that is no
// camera is refused before the run.
TEST(RunCommand3D, PictureOfTheLastFrame) {
  for (const char* view : {"", "top", "side", "20,40,1.5", "-135,-10"}) {
    SCOPED_TRACE(view);
    const std::string png = ::testing::TempDir() + "collide_run3d.png";
    std::remove(png.c_str());
    const std::string v = *view != 0 ? std::string(" --view ") + view : std::string();
    const CommandRun r = run_cli("run --3d --bodies 80 --frames 20 --characters 3 --width 700 --png " + png + v);
    ASSERT_EQ(r.status, 0) << r.output;
    std::ifstream in(png, std::ios::binary);
    std::array<unsigned char, 24> head{};
    in.read(reinterpret_cast<char*>(head.data()), head.size());
    ASSERT_TRUE(in.good()) << png;
    EXPECT_EQ(std::string(head.begin() + 1, head.begin() + 4), "PNG");
    EXPECT_EQ((head[16] << 24) | (head[17] << 16) | (head[18] << 8) | head[19], 700);  // IHDR width
  }
  // An OBJ level too.
  const std::string level = write_level("collide_level_png.obj", Vec3(0.0f), false);
  const std::string png = ::testing::TempDir() + "collide_run3d_level.png";
  const CommandRun obj = run_cli("run " + level + " --bodies 60 --frames 20 --png " + png);
  ASSERT_EQ(obj.status, 0) << obj.output;
  EXPECT_TRUE(std::ifstream(png).good());
  for (const char* bad : {"abc", "10", "10,100", "10,20,0", "10,20,30,40", "10,,20"}) {
    SCOPED_TRACE(bad);
    const CommandRun r = run_cli(std::string("run --3d --frames 1 --bodies 5 --view ") + bad + " --png " + png);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--view"), std::string::npos) << r.output;
  }
  const CommandRun two_d = run_cli("run --frames 1 --view top");
  EXPECT_NE(two_d.status, 0);
  EXPECT_NE(two_d.output.find("--view"), std::string::npos) << two_d.output;
}

TEST(RunCommand3D, BadArgumentsFailWithAMessage) {
  const CommandRun svg = run_cli("run --3d --frames 1 --svg " + ::testing::TempDir() + "x.svg");
  EXPECT_NE(svg.status, 0);
  EXPECT_NE(svg.output.find("--svg"), std::string::npos) << svg.output;
  const CommandRun two_d = run_cli("run --frames 1 --characters 2");
  EXPECT_NE(two_d.status, 0);
  EXPECT_NE(two_d.output.find("--characters"), std::string::npos) << two_d.output;
  const CommandRun missing = run_cli("run /nonexistent/level.obj");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("/nonexistent/level.obj"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace collide::cli
