// `collide run`: the scenes through run_world (the code behind the command), and the command end
// to end through the real binary. The independent check (no body inside static geometry, none
// outside the bounds) must hold on every scene and every shared Tiled map; the state hash must
// not depend on the run, the broad phase or the early-out learning; events must parse.

#include "cli_run.hpp"
#include "run.hpp"
#include "run_checks.hpp"
#include "support/picture_checks.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/palette.hpp>
#include <collide/io/tiled.hpp>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <fcntl.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

using test::CommandRun;
const auto run_cli = test::run_cli;

RunOptions small(std::string input, int bodies, int frames) {
  RunOptions o;
  o.input = std::move(input);
  o.bodies = bodies;
  o.frames = frames;
  o.progress = false;
  return o;
}

TEST(RunWorld, DefaultSceneStaysCheckedAndBusy) {
  const RunReport r = run_world(small("", 600, 240), nullptr);
  EXPECT_EQ(r.bodies, 600);
  EXPECT_EQ(r.total.tunnelled, 0);
  EXPECT_EQ(r.total.escaped, 0);
  EXPECT_GT(r.total.contacts, 0);
  EXPECT_GT(r.total.sensor_contacts, 0);
  EXPECT_GT(r.total.toi_hits, 0);       // the bullets hit walls
  EXPECT_GT(r.total.begin_events, 0);
  EXPECT_GT(r.total.persist_events, 0);
  EXPECT_GT(r.total.end_events, 0);
  EXPECT_GT(r.laser_hits, 240);         // at least one reflection per frame
  EXPECT_GT(r.static_pieces, r.statics);  // concave obstacles went in as several pieces
}

TEST(RunWorld, StateHashIsTheSameForEveryRunBroadPhaseAndEarlyOutChoice) {
  test::expect_hash_independent_of_choices([](const RunOptions& o) { return run_world(o, nullptr); }, small("", 400, 120),
                                           {WorldBroadPhase::brute_force, WorldBroadPhase::sorted_grid, WorldBroadPhase::loose_grid,
                                            WorldBroadPhase::dynamic_tree, WorldBroadPhase::sweep_and_prune});
}

TEST(RunWorld, BulletsNeverTunnelThroughThinWalls) {
  const RunReport r = run_world(small("bullets", 300, 300), nullptr);
  EXPECT_EQ(r.bodies, 300);
  EXPECT_EQ(r.total.tunnelled, 0);
  EXPECT_EQ(r.total.escaped, 0);  // the outer walls are thin, too
  EXPECT_EQ(r.total.ccd_bodies, 300 * 300);
  EXPECT_GT(r.total.toi_hits, 300 * 10);
}

// The issue: every map under the shared Tiled folder loads and runs.
TEST(RunWorld, EverySharedTiledMapLoadsAndRunsWithoutTunnelling) {
  int maps = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(COLLIDE_DATA_DIR) / "tiled")) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".tmx" && ext != ".tmj" && ext != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const RunReport r = run_world(small(entry.path().string(), 150, 180), nullptr);
    ++maps;
    EXPECT_GT(r.statics, 4);  // the map's colliders besides the four boundary walls
    EXPECT_GT(r.bodies, 0);
    EXPECT_EQ(r.total.tunnelled, 0);
    EXPECT_EQ(r.total.escaped, 0);
    EXPECT_EQ(run_world(small(entry.path().string(), 150, 180), nullptr).state_hash, r.state_hash);
  }
  EXPECT_EQ(maps, 7);
}

// The same through the real binary, every option of the issue on the command line: each map
// runs with exit status 0, the summary echoes the options, the independent check reads 0, a
// picture is written, and a second process with the same arguments ends in the same state.
TEST(RunCommand, EverySharedTiledMapRunsThroughTheBinary) {
  int maps = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(COLLIDE_DATA_DIR) / "tiled")) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".tmx" && ext != ".tmj" && ext != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const std::string png = ::testing::TempDir() + "collide_run_map_" + std::to_string(maps) + ".png";
    std::remove(png.c_str());
    const std::string args = "run " + entry.path().string() + " --bodies 80 --seed 3 --frames 45 --dt 0.02";
    const CommandRun r = run_cli(args + " --png " + png);
    ++maps;
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("collide run: " + entry.path().string()), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("45 frames of 20.00 ms"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("seed 3"), std::string::npos) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(, (\d+) bodies \()"))) << r.output;
    EXPECT_GT(std::stoi(m[1].str()), 0);
    EXPECT_LE(std::stoi(m[1].str()), 80);
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(tunnelled\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0");
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(escaped\s+(\d+) bodies)"))) << r.output;
    EXPECT_EQ(m[1].str(), "0");
    EXPECT_TRUE(test::has_png_signature(png)) << png;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(state hash\s+([0-9a-f]{16}))"))) << r.output;
    const std::string hash = m[1].str();
    const CommandRun again = run_cli(args);
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("state hash       " + hash), std::string::npos) << again.output;
  }
  EXPECT_EQ(maps, 7);
}

// A map's concave polygon objects and polylines stay one static each, of several pieces.
TEST(RunWorld, MapObjectsStayOneStaticOfSeveralPieces) {
  const fs::path path = fs::path(COLLIDE_DATA_DIR) / "tiled/tmxlite/ParseTest/maps/platform.tmx";
  const TiledMap map = load_tiled_map(path);
  std::set<int> objects;
  int several = 0;
  std::map<int, int> pieces;
  for (const TiledCollider& c : map.colliders) {
    ASSERT_NE(c.source.object_id, 0);  // platform.tmx: object layers only
    objects.insert(c.source.object_id);
    several += ++pieces[c.source.object_id] == 2 ? 1 : 0;
  }
  ASSERT_GT(several, 0);
  const RunReport r = run_world(small(path.string(), 20, 1), nullptr);
  EXPECT_EQ(r.static_pieces, static_cast<int>(map.colliders.size()) + 4);  // and the four boundary walls
  EXPECT_EQ(r.statics, static_cast<int>(objects.size()) + 4);
  EXPECT_EQ(r.split_statics, several);
}

TEST(RunWorld, BadInputIsAnErrorThatNamesIt) {
  try {
    (void)run_world(small("/nonexistent/level.tmx", 10, 10), nullptr);
    FAIL() << "a missing map was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/level.tmx"), std::string::npos) << e.what();
  }
  try {
    (void)run_world(small("galaxy", 10, 10), nullptr);
    FAIL() << "an unknown scene was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("bullets"), std::string::npos) << e.what();
  }
  RunOptions bad_dt = small("", 10, 10);
  bad_dt.dt = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW((void)run_world(bad_dt, nullptr), InvalidInput);
}

TEST(RunCommand, SummaryAndEventsEndToEnd) {
  const std::string events = ::testing::TempDir() + "collide_run_events.jsonl";
  std::remove(events.c_str());
  const CommandRun r = run_cli("run --bodies 300 --frames 90 --seed 4 --events " + events);
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* line : {"broad phase", "early out", "narrow phase", "ccd", "events", "laser",
                           "time per frame", "body-static", "body-body"}) {
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  }
  const test::RunSummary summary = test::expect_clean_summary(r.output);
  const std::string hash = summary.hash;
  ASSERT_FALSE(hash.empty());
  const long lines = test::expect_valid_events_file(events, 2);
  EXPECT_EQ(lines, summary.written);
  EXPECT_GT(lines, 50);
  // Same arguments, same final state.
  const CommandRun again = run_cli("run --bodies 300 --frames 90 --seed 4 --broadphase hash_grid");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find(hash), std::string::npos) << again.output;
}

TEST(RunCommand, PicturesOfTheLastFrameShowEveryKindOfThing) {
  const std::string png = ::testing::TempDir() + "collide_run_test.png";
  const std::string svg = ::testing::TempDir() + "collide_run_test.svg";
  std::remove(png.c_str());
  std::remove(svg.c_str());
  const CommandRun r = run_cli("run --bodies 400 --frames 60 --png " + png + " --svg " + svg + " --width 900");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("wrote " + png), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("wrote " + svg), std::string::npos) << r.output;
  const test::PngImage image = test::read_png(png);
  ASSERT_EQ(image.width, 900) << png;
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file(svg.c_str())) << svg;
  EXPECT_EQ(std::string(doc.child("svg").attribute("width").value()), "900px");
  EXPECT_EQ(std::string(doc.child("svg").attribute("height").value()), std::to_string(image.height) + "px");
  // Statics, sensors, bodies, contacts with their normals, the laser and its hits are all
  // drawn: pixels of each one's palette colour (solids' fills over the background; the
  // stroke colour where a dot or an arrow head covers a whole pixel).
  auto fill_over_background = [](DrawRole role) { return test::over(draw_style(role).fill, kPictureBackground); };
  auto stroke = [](DrawRole role) { return draw_style(role).stroke; };
  const std::vector<std::pair<DrawRole, Color>> expected = {
      {DrawRole::static_geometry, fill_over_background(DrawRole::static_geometry)},
      {DrawRole::sensor, fill_over_background(DrawRole::sensor)},
      {DrawRole::body, fill_over_background(DrawRole::body)},
      {DrawRole::contact_point, stroke(DrawRole::contact_point)},
      {DrawRole::contact_normal, stroke(DrawRole::contact_normal)},
      {DrawRole::laser_hit, stroke(DrawRole::laser_hit)}};
  for (const auto& [role, colour] : expected) {
    EXPECT_GT(test::count_pixels(image, [&](Color c) { return test::near(c, colour); }), 4) << to_string(role);
  }
  // The laser's thin line over the background: full red, green and blue alike and under half.
  const Color laser = stroke(DrawRole::laser);
  EXPECT_GT(test::count_pixels(image, [&](Color c) {
              return c.r == laser.r && c.g < 128 && std::abs(c.g - c.b) <= test::kChannelTolerance;
            }),
            20);
}

/// Runs `collide run ARGS...` with its stderr on a pseudo-terminal (`stderr_on_tty`) or its
/// stdout on one (else), the other stream going to a file; returns (terminal text, file text).
std::pair<std::string, std::string> run_with_a_terminal(bool stderr_on_tty, std::vector<std::string> args) {
  int master = -1, slave = -1;
  if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) {
    ADD_FAILURE() << "openpty failed";
    return {};
  }
  const std::string file = ::testing::TempDir() + "collide_run_tty_other_stream.txt";
  const pid_t pid = fork();
  if (pid == 0) {
    const int other = open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(slave, stderr_on_tty ? STDERR_FILENO : STDOUT_FILENO);
    dup2(other, stderr_on_tty ? STDOUT_FILENO : STDERR_FILENO);
    close(master);
    close(slave);
    close(other);
    std::vector<char*> argv;
    args.insert(args.begin(), {"collide", "run"});
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(COLLIDE_CLI_PATH, argv.data());
    _exit(127);
  }
  close(slave);
  std::string tty;
  std::array<char, 4096> buf{};
  for (;;) {
    const ssize_t n = read(master, buf.data(), buf.size());
    if (n <= 0) break;  // EIO once the child has closed the terminal
    tty.append(buf.data(), static_cast<std::size_t>(n));
  }
  close(master);
  int status = -1;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << tty;
  std::ifstream in(file);
  const std::string other((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return {tty, other};
}

// The issue: a progress bar on long runs when stderr is a terminal, and only then.
TEST(RunCommand, ProgressBarOnlyWhenStderrIsATerminal) {
  const std::vector<std::string> args = {"--bodies", "50", "--frames", "200"};
  const std::regex bar(R"(\[#+ *\] +\d+% frame \d+/200)");
  // stderr on a terminal: the bar is drawn there (and cleared at the end); the summary goes to
  // stdout untouched.
  const auto [tty, out] = run_with_a_terminal(true, args);
  EXPECT_TRUE(std::regex_search(tty, bar)) << tty;
  EXPECT_NE(tty.find("frame 200/200"), std::string::npos) << tty;
  EXPECT_FALSE(std::regex_search(out, bar)) << out;
  EXPECT_NE(out.find("state hash"), std::string::npos) << out;
  // stdout on a terminal, stderr a file: no bar anywhere.
  const auto [tty2, err2] = run_with_a_terminal(false, args);
  EXPECT_FALSE(std::regex_search(tty2, bar)) << tty2;
  EXPECT_FALSE(std::regex_search(err2, bar)) << err2;
  EXPECT_NE(tty2.find("state hash"), std::string::npos) << tty2;
  // stderr on a terminal but --no-progress, or a short run (fewer frames than the bar has
  // steps): no bar.
  std::vector<std::string> quiet = args;
  quiet.push_back("--no-progress");
  EXPECT_FALSE(std::regex_search(run_with_a_terminal(true, quiet).first, bar));
  EXPECT_EQ(run_with_a_terminal(true, {"--bodies", "50", "--frames", "60"}).first.find("frame"), std::string::npos);
  // A pipe (how the other tests run the tool): no bar.
  EXPECT_FALSE(std::regex_search(run_cli("run --bodies 50 --frames 200").output, bar));
}

TEST(RunCommand, BadArgumentsFailWithAMessage) {
  const CommandRun missing = run_cli("run /nonexistent/map.tmx");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("/nonexistent/map.tmx"), std::string::npos) << missing.output;
  const CommandRun broad = run_cli("run --frames 1 --broadphase octree");
  EXPECT_NE(broad.status, 0);
  EXPECT_NE(broad.output.find("temporal"), std::string::npos) << broad.output;
}

}  // namespace
}  // namespace collide::cli
