// Issue 15: whatever goes wrong around `collide run`, `walk` and `cast` is exit status 2 with one
// line that names it, never an abort and never a hang. Each case went wrong before the fix: a
// FIFO or /dev/zero hung (`timeout` below turns a hang into a failure), a folder or an empty
// file was read as a question without naming the file, std::bad_alloc aborted `walk` and
// `cast`, a command line CLI11 refused exited 105 or 106, and a summary written to a full disk
// was lost with exit status 0.

#include "cli_run.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace collide::cli {
namespace {

namespace fs = std::filesystem;

using test::exit_code;
using test::run_shell;

/// A seconds limit on each command: a hang fails the test instead of stalling it.
const std::string kTimeout = "timeout 60 ";

const std::string kDungeon = (fs::path(COLLIDE_DATA_DIR) / "meshes/recast/dungeon.obj").string();

/// A scratch folder with a folder, an empty file and a FIFO, named as each command expects.
class Inputs {
 public:
  Inputs() : root_(fs::path(::testing::TempDir()) / "collide_command_errors") {
    fs::remove_all(root_);
    fs::create_directories(root_);
    for (const char* ext : {".tmx", ".json", ".obj"}) {
      fs::create_directories(root_ / (std::string("folder") + ext));
      std::ofstream(root_ / (std::string("empty") + ext)).flush();
      EXPECT_EQ(mkfifo((root_ / (std::string("fifo") + ext)).c_str(), 0600), 0);
    }
  }
  ~Inputs() { fs::remove_all(root_); }
  [[nodiscard]] std::string operator()(const std::string& name) const { return (root_ / name).string(); }

 private:
  fs::path root_;
};

void expect_error(const std::string& args, const std::string& message) {
  const test::CommandRun r = run_shell(kTimeout + "\"$COLLIDE\" " + args + " < /dev/null");
  EXPECT_EQ(exit_code(r), 2) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << args << "\nexpected: " << message << "\ngot: " << r.output;
}

TEST(CommandErrors, FoldersEmptyFilesFifosAndDevicesAreNamedNeverOpened) {
  const Inputs in;
  for (const auto& [command, ext] : {std::pair{"run", ".tmx"}, {"run", ".json"}, {"walk", ".obj"}, {"cast", ".json"}}) {
    const std::string c = command;
    expect_error(c + " " + in(std::string("folder") + ext),
                 "collide " + c + ": " + in(std::string("folder") + ext) + ": cannot be read (a directory)");
    expect_error(c + " " + in(std::string("empty") + ext),
                 "collide " + c + ": " + in(std::string("empty") + ext) + ": cannot be read (an empty file)");
    expect_error(c + " " + in(std::string("fifo") + ext),
                 "collide " + c + ": " + in(std::string("fifo") + ext) + ": cannot be read (a FIFO: give a regular file)");
  }
  expect_error("walk /dev/zero", "collide walk: /dev/zero: cannot be read (a device: give a regular file)");
  expect_error("cast /dev/zero", "collide cast: /dev/zero: cannot be read (a device: give a regular file)");
  expect_error("walk " + in("missing.obj"), "collide walk: " + in("missing.obj") + ": cannot be read (no such file)");
}

TEST(CommandErrors, CommandLinesCli11RefusesAreStatus2) {
  expect_error("run --frames -3", "--frames: Value -3 not in range");
  expect_error("run --no-such-option", "--no-such-option");
  expect_error("walk", "MESH is required");
  expect_error("", "A subcommand is required");
  expect_error("cast --width 5", "--width");
  for (const char* fine : {"--help", "--version", "run --help"}) {
    const test::CommandRun r = run_shell("\"$COLLIDE\" " + std::string(fine));
    EXPECT_EQ(exit_code(r), 0) << fine << "\n" << r.output;
  }
}

TEST(CommandErrors, OutputsThatCannotBeWrittenAreNamedBeforeTheWork) {
  expect_error("run --frames 1 --png /nonexistent/folder/run.png",
               "collide run: --png /nonexistent/folder/run.png: cannot be written (no folder '/nonexistent/folder')");
  expect_error("run --frames 1 --svg /nonexistent/run.svg",
               "collide run: --svg /nonexistent/run.svg: cannot be written (no folder '/nonexistent')");
  expect_error("run --frames 1 --events /nonexistent/events.jsonl", "collide run: --events /nonexistent/events.jsonl: cannot be written");
  expect_error("walk " + kDungeon + " --steps 1 --png /nonexistent/walk.png",
               "collide walk: --png /nonexistent/walk.png: cannot be written (no folder '/nonexistent')");
  const std::string question =
      R"('{"a": {"type": "circle", "radius": 1}, "va": [4, 0], "b": {"type": "circle", "radius": 1}, "xb": {"p": [5, 0]}, "vb": [0, 0]}')";
  expect_error("cast --question " + question + " --svg /nonexistent/cast.svg",
               "collide cast: --svg /nonexistent/cast.svg: cannot be written (no folder '/nonexistent')");
  expect_error("cast --question " + question + " --pdf /nonexistent/cast.pdf",
               "collide cast: --pdf /nonexistent/cast.pdf: cannot be written (no folder '/nonexistent')");
  // Standard output on a full disk: the summary is lost, so the run is not a success.
  for (const std::string& args : {std::string("run --frames 1 --bodies 10 --no-progress"), "cast --question " + question,
                                 "walk " + kDungeon + " --steps 1"}) {
    const test::CommandRun r = run_shell("{ " + kTimeout + "\"$COLLIDE\" " + args + " > /dev/full; }");
    EXPECT_EQ(exit_code(r), 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("collide: standard output could not be written"), std::string::npos) << args << "\n" << r.output;
  }
}

// Out of memory under an address-space limit: exit status 2 and "out of memory", not an abort.
TEST(CommandErrors, OutOfMemoryIsStatus2WithAMessage) {
#ifdef COLLIDE_TEST_UNDER_ASAN
  GTEST_SKIP() << "ulimit -v and AddressSanitizer's shadow memory do not mix";
#else
  // walk: 100,000 agents' paths, kept for the picture, outgrow 150 MB within a few steps.
  test::CommandRun r = run_shell("(ulimit -v 150000; " + kTimeout + "\"$COLLIDE\" walk " + kDungeon +
                                 " --agents 100000 --steps 10000 --png " + ::testing::TempDir() + "oom_walk.png > /dev/null)");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide walk: " + kDungeon + ": out of memory"), std::string::npos) << r.output;
  // run and cast: a picture 16,000 pixels wide needs more than 200 MB.
  r = run_shell("(ulimit -v 200000; " + kTimeout + "\"$COLLIDE\" run --frames 1 --bodies 100 --no-progress --png " +
                ::testing::TempDir() + "oom.png --width 16000 > /dev/null)");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide run: default: out of memory"), std::string::npos) << r.output;
  r = run_shell("(ulimit -v 200000; " + kTimeout + "\"$COLLIDE\" cast --width 16000 --png " + ::testing::TempDir() +
                R"(oom.png --question '{"a": {"type": "circle", "radius": 1}, "va": [4, 0], "b": {"type": "circle", "radius": 1}, "xb": {"p": [5, 0]}, "vb": [0, 0]}' > /dev/null))");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide cast: --question: out of memory"), std::string::npos) << r.output;
  // A question without end on standard input stops at the 16 MiB limit of a question.
  r = run_shell("head -c 100000000 /dev/zero | (ulimit -v 100000; " + kTimeout + "\"$COLLIDE\" cast)");
  EXPECT_EQ(exit_code(r), 2) << r.output;
  EXPECT_NE(r.output.find("collide cast: standard input: longer than 16777216 bytes (the limit of a question, 16 MiB)"),
            std::string::npos)
      << r.output;
#endif
}

}  // namespace
}  // namespace collide::cli
