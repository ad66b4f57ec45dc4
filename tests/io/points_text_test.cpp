// The points reader (io::parse_points, io::load_points; `collide sdf --sample`): what it reads,
// every line checked and the file and line of anything wrong named; random points written with 9
// significant digits read back exactly; the fuzz target's contract replayed on its seeds.
#include <collide/core/error.hpp>
#include <collide/io/points_text.hpp>

#include "points_text_check.hpp"
#include "support/replay_files.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace collide {
namespace {

namespace fs = std::filesystem;

/// The message parse_points<D> throws for `text` (named "points.txt"), or "no error".
template <int D>
std::string error_of(const std::string& text) {
  try {
    (void)io::parse_points<D>(text, "points.txt");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

TEST(PointsText, ReadsTwoAndThreeNumbersPerLineSkippingBlankAndCommentLines) {
  const std::vector<Vec2> p2 = io::parse_points<2>("# x y\n0 0\n\n  1.5\t-2\n   # indented comment\n+3e2 4", "p.txt");
  ASSERT_EQ(p2.size(), 3u);
  EXPECT_EQ(p2[0], Vec2(0.0f, 0.0f));
  EXPECT_EQ(p2[1], Vec2(1.5f, -2.0f));
  EXPECT_EQ(p2[2], Vec2(300.0f, 4.0f));  // no line end after the last line
  const std::vector<Vec3> p3 = io::parse_points<3>("1 2 3\r\n-4 5.25 6\r\n\r\n7 8 9\r10 11 12\r", "p.txt");
  ASSERT_EQ(p3.size(), 4u);
  EXPECT_EQ(p3[1], Vec3(-4.0f, 5.25f, 6.0f));
  EXPECT_EQ(p3[3], Vec3(10.0f, 11.0f, 12.0f));
  EXPECT_TRUE(io::parse_points<3>("", "p.txt").empty());
  EXPECT_TRUE(io::parse_points<2>("# only a comment\n\n \t\n", "p.txt").empty());
  // What underflows float is a valid 0.
  EXPECT_EQ(io::parse_points<2>("1e-50 -1e-60", "p.txt")[0], Vec2(0.0f, 0.0f));
}

TEST(PointsText, ErrorsNameTheFileAndTheLineCountingBlankAndCommentLines) {
  EXPECT_EQ(error_of<3>("0 0 0\n\n# c\n1 2\n"), "points.txt:4: expected 3 numbers (x y z), found 2");
  EXPECT_EQ(error_of<2>("1 2 3\n"), "points.txt:1: expected 2 numbers (x y), found 3");
  EXPECT_EQ(error_of<2>("1 2\r\n3\r\n"), "points.txt:2: expected 2 numbers (x y), found 1");
  EXPECT_EQ(error_of<2>("1 2 # a trailing comment is no comment\n"), "points.txt:1: expected 2 numbers (x y), found 9");
  EXPECT_EQ(error_of<2>("1 nan\n"), "points.txt:1: y 'nan' is not finite");
  EXPECT_EQ(error_of<3>("0 0 0\n-inf 0 0\n"), "points.txt:2: x '-inf' is not finite");
  EXPECT_EQ(error_of<3>("1 2 1e39\n"), "points.txt:1: z '1e39' is out of float range");
  // The edge of float range is where rounding reaches infinity (2^128 - 2^103, about
  // 3.40282357e38), not FLT_MAX itself: FLT_MAX with 9 digits reads back as FLT_MAX.
  EXPECT_EQ(error_of<3>("1 2 3.4028236e38\n"), "points.txt:1: z '3.4028236e38' is out of float range");
  EXPECT_EQ(error_of<3>("1 2 -3.4028236e38\n"), "points.txt:1: z '-3.4028236e38' is out of float range");
  EXPECT_EQ(io::parse_points<3>("3.40282347e+38 3.4028235e38 -3.40282356e38\n", "edge.txt"),
            (std::vector<Vec3>{Vec3(std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                                    -std::numeric_limits<float>::max())}));
  EXPECT_EQ(error_of<2>("1 2x\n"), "points.txt:1: y '2x' is not a number");
  EXPECT_EQ(error_of<2>("1,2 3\n"), "points.txt:1: x '1,2' is not a number");
  // A quoted word is cut and its bytes escaped, so the message stays readable UTF-8.
  EXPECT_EQ(error_of<2>(std::string("1 \xff\x01") + "\n"), "points.txt:1: y '\\xFF\\x01' is not a number");
}

TEST(PointsText, LoadNamesAFileThatCannotBeRead) {
  const fs::path missing = fs::path(::testing::TempDir()) / "collide_no_such_points.txt";
  fs::remove(missing);
  try {
    (void)io::load_points<2>(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), missing.string() + ": cannot be read");
  }
  const fs::path file = fs::path(::testing::TempDir()) / "collide_points_test.txt";
  std::ofstream(file) << "0.5 1.5 2.5\nbad 0 0\n";
  try {
    (void)io::load_points<3>(file);
    ADD_FAILURE() << "no error for a bad line";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ":2: x 'bad' is not a number");
  }
}

TEST(PointsText, RandomPointsWrittenWithNineDigitsReadBackExactly) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> mantissa(-1.0f, 1.0f);
  std::uniform_int_distribution<int> exponent(-30, 30);
  std::vector<Vec3> written;
  std::string text;
  for (int i = 0; i < 1000; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = std::ldexp(mantissa(rng), exponent(rng));
    written.push_back(p);
    char line[128];
    std::snprintf(line, sizeof line, i % 2 ? "%.9g %.9g %.9g\n" : "  %.9e\t%.9e  %.9e\r\n", static_cast<double>(p.x),
                  static_cast<double>(p.y), static_cast<double>(p.z));
    text += line;
  }
  EXPECT_EQ(io::parse_points<3>(text, "random.txt"), written);
}

// The fuzz target's seeds (fuzz/seeds/points_text/) and any input it found a defect with
// (fuzz/regressions/points_text/, when there is one), replayed through its own check
// (fuzz/points_text_check.hpp).
TEST(PointsTextFuzzRegressions, EverySeedAndFoundInputPassesTheFuzzCheck) {
  const auto check = [](const std::string& input) { return fuzz::check_points_text(input); };
  EXPECT_GE(test::replay_files(fs::path(COLLIDE_FUZZ_DIR) / "seeds" / "points_text", check), 8);
  const fs::path regressions = fs::path(COLLIDE_FUZZ_DIR) / "regressions" / "points_text";
  if (fs::is_directory(regressions)) test::replay_files(regressions, check);
}

// The check itself can fail: a contract that holds for everything checks nothing.
TEST(PointsTextFuzzRegressions, TheCheckCountsDataLinesAsTheReaderShould) {
  EXPECT_EQ(fuzz::data_lines("1 2\n\n# c\n  \t\n3 4\r\n5 6"), 3u);
  EXPECT_EQ(fuzz::data_lines("\r\r\n\n"), 0u);
  EXPECT_EQ(fuzz::check_points_text("1 2\n"), "");
  EXPECT_EQ(fuzz::check_message("other.txt:1: x", "points.txt:"), "message does not name the file: other.txt:1: x");
}

}  // namespace
}  // namespace collide
