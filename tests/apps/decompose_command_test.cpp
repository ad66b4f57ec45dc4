// `collide decompose` end to end through the real binary, on a dumbbell written here (two boxes
// joined by a thin bar): it exits 0, reports as many hulls as the OBJ it writes has objects
// (at least 3: no hull may span a box and the bar within the concavity asked), the OBJ reads back,
// the hulls are the same bit for bit on 1 and 2 threads, and the picture shows each hull's own
// colour. Bad inputs (missing, NaN, flat), bad options and an output folder that does not exist
// fail with exit status 2 and a message naming the file or the option. `--hulls` measures
// another tool's hulls: an exact decomposition reaches nowhere outside, one box around all 1.

#include "cli_run.hpp"
#include "support/picture_checks.hpp"

#include <collide/decompose/approximate_decomposition.hpp>
#include <collide/draw/palette.hpp>
#include <collide/io/obj.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::CommandRun;
using test::exit_code;
const auto run = test::run_cli;

/// Appends a closed box [lo, hi] to an OBJ text: 8 vertices (numbered from `first`, 1-based),
/// 6 quadrilaterals counter-clockwise seen from outside.
void add_box(std::ostringstream& obj, Vec3 lo, Vec3 hi, int first) {
  for (int i = 0; i < 8; ++i) {
    obj << "v " << ((i & 1) ? hi.x : lo.x) << ' ' << ((i & 2) ? hi.y : lo.y) << ' ' << ((i & 4) ? hi.z : lo.z) << '\n';
  }
  constexpr std::array<std::array<int, 4>, 6> kFaces{{{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                                      {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}};
  for (const auto& f : kFaces) {
    obj << 'f';
    for (const int k : f) obj << ' ' << first + k;
    obj << '\n';
  }
}

/// Writes `text` to a file `name` in the test's temporary folder and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// Two 2 x 2 x 2 boxes 2 apart, joined by a bar 0.2 thick reaching into both.
std::string dumbbell() {
  std::ostringstream obj;
  obj << "# two boxes and a bar\n";
  add_box(obj, {-3.0f, -1.0f, -1.0f}, {-1.0f, 1.0f, 1.0f}, 1);
  add_box(obj, {1.0f, -1.0f, -1.0f}, {3.0f, 1.0f, 1.0f}, 9);
  add_box(obj, {-1.2f, -0.1f, -0.1f}, {1.2f, 0.1f, 0.1f}, 17);
  return write_temp("collide_decompose_dumbbell.obj", obj.str());
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Lines of `text` that start with "o ".
int objects(const std::string& text) {
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) n += line.rfind("o ", 0) == 0 ? 1 : 0;
  return n;
}

/// The first number after a report line's label ("  hulls   4 (...)"), -1 when there is none.
double report_number(const std::string& output, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(output, m, std::regex("\\n  " + label + " +([-+]?[0-9]*\\.?[0-9]+(e[-+]?[0-9]+)?)"))) return -1.0;
  return std::stod(m[1].str());
}

/// Pixels of `image` that are `c` shaded (every channel the same multiple of c's, within a
/// rounding step or two): where a hull drawn in c shows.
int pixels_shaded_from(const test::PngImage& image, Color c) {
  return test::count_pixels(image, [&](Color p) {
    const int sum = p.r + p.g + p.b;
    if (sum < 60) return false;
    const double s = static_cast<double>(sum) / (c.r + c.g + c.b);
    return std::abs(p.r - s * c.r) <= 3.0 && std::abs(p.g - s * c.g) <= 3.0 && std::abs(p.b - s * c.b) <= 3.0;
  });
}

/// The default resolution (a voxel of about 0.06 for the bar's 0.2): a coarser grid sees the bar
/// too thick to reach the concavity asked and spends the hull budget on it.
constexpr const char* kOptions = " --max-hulls 8 --concavity 0.01 --samples 4000 --no-progress";

TEST(DecomposeCommand, TheDumbbellBecomesSeveralHullsWrittenOneObjectEach) {
  const std::string mesh = dumbbell();
  const std::string out = ::testing::TempDir() + "collide_decompose_hulls.obj";
  const std::string png = ::testing::TempDir() + "collide_decompose_hulls.png";
  std::remove(out.c_str());
  std::remove(png.c_str());
  const CommandRun r = run("decompose " + mesh + kOptions + " --threads 2 --out " + out + " --png " + png + " --width 900");
  ASSERT_EQ(exit_code(r), 0) << r.output;
  const double hulls = report_number(r.output, "hulls");
  EXPECT_GE(hulls, 3.0) << r.output;
  EXPECT_LE(hulls, 8.0) << r.output;
  EXPECT_EQ(report_number(r.output, "input"), 36.0) << r.output;  // 3 boxes x 12 triangles
  EXPECT_EQ(report_number(r.output, "threads"), 2.0) << r.output;
  for (const char* label : {"voxel", "grid nodes", "solid nodes", "hull vertices", "splits", "candidates",
                            "grid concavity", "hull_to_mesh", "mesh_to_hull", "volume ratio", "time"}) {
    EXPECT_GE(report_number(r.output, label), 0.0) << label << "\n" << r.output;
  }
  EXPECT_GT(report_number(r.output, "solid nodes"), 0.0) << r.output;
  EXPECT_GT(report_number(r.output, "volume ratio"), 0.5) << r.output;

  const std::string text = read_text(out);
  EXPECT_EQ(objects(text), static_cast<int>(hulls)) << text;
  const TriangleSoup soup = io::load_obj(out);  // reads back
  EXPECT_GE(soup.triangles.size(), 4u * static_cast<std::size_t>(hulls));

  ASSERT_TRUE(test::has_png_signature(png));
  const test::PngImage image = test::read_png(png);
  ASSERT_EQ(image.width, 900);
  // Each hull in its own colour; one may hide behind another (a piece of the bar behind a box).
  int shown = 0;
  for (int h = 0; h < static_cast<int>(hulls); ++h) shown += pixels_shaded_from(image, distinct_color(h)) > 30 ? 1 : 0;
  EXPECT_GE(shown, 3) << "hull colours seen";
  std::remove(out.c_str());
  std::remove(png.c_str());
}

TEST(DecomposeCommand, HullsAreTheSameOnOneAndTwoThreads) {
  const std::string mesh = dumbbell();
  std::string written[2];
  for (const int threads : {1, 2}) {
    const std::string out = ::testing::TempDir() + "collide_decompose_threads" + std::to_string(threads) + ".obj";
    const CommandRun r = run("decompose " + mesh + kOptions + " --threads " + std::to_string(threads) + " --out " + out);
    ASSERT_EQ(exit_code(r), 0) << r.output;
    EXPECT_EQ(report_number(r.output, "threads"), threads) << r.output;
    written[threads - 1] = read_text(out);
    std::remove(out.c_str());
  }
  EXPECT_FALSE(written[0].empty());
  EXPECT_EQ(written[0], written[1]);
}

TEST(DecomposeCommand, AnotherToolsHullsAreMeasuredByTheSameYardstick) {
  // --hulls: the dumbbell's own three boxes (its exact decomposition) reach nowhere outside it;
  // the hull of the whole dumbbell (one box around it) reaches 1 out (the middle of the gap
  // between the boxes, 1 from each; the bar is farther); both cover it. Written by hand as another tool would: vertices per hull, no `o`.
  const std::string mesh = dumbbell();
  std::ostringstream exact, single;
  add_box(exact, {-3.0f, -1.0f, -1.0f}, {-1.0f, 1.0f, 1.0f}, 1);
  add_box(exact, {1.0f, -1.0f, -1.0f}, {3.0f, 1.0f, 1.0f}, 9);
  add_box(exact, {-1.2f, -0.1f, -0.1f}, {1.2f, 0.1f, 0.1f}, 17);
  add_box(single, {-3.0f, -1.0f, -1.0f}, {3.0f, 1.0f, 1.0f}, 1);
  const std::string exact_path = write_temp("collide_decompose_exact_hulls.obj", exact.str());
  const std::string single_path = write_temp("collide_decompose_single_hull.obj", single.str());
  const std::string png = ::testing::TempDir() + "collide_decompose_their_hulls.png";
  std::remove(png.c_str());

  const CommandRun e = run("decompose " + mesh + " --hulls " + exact_path + " --samples 4000 --png " + png + " --width 700");
  ASSERT_EQ(exit_code(e), 0) << e.output;
  EXPECT_EQ(report_number(e.output, "hulls"), 3.0) << e.output;
  EXPECT_EQ(report_number(e.output, "hull vertices"), 24.0) << e.output;
  EXPECT_LT(report_number(e.output, "hull_to_mesh"), 1e-3) << e.output;
  EXPECT_LT(report_number(e.output, "mesh_to_hull"), 1e-3) << e.output;
  EXPECT_EQ(report_number(e.output, "splits"), -1.0) << "no decomposition run\n" << e.output;
  ASSERT_TRUE(test::has_png_signature(png));
  EXPECT_GT(pixels_shaded_from(test::read_png(png), distinct_color(0)), 30);

  const CommandRun one = run("decompose " + mesh + " --hulls " + single_path + " --samples 4000");
  ASSERT_EQ(exit_code(one), 0) << one.output;
  EXPECT_EQ(report_number(one.output, "hulls"), 1.0) << one.output;
  EXPECT_NEAR(report_number(one.output, "hull_to_mesh"), 1.0, 0.05) << one.output;
  EXPECT_LT(report_number(one.output, "mesh_to_hull"), 1e-3) << one.output;

  const CommandRun missing = run("decompose " + mesh + " --hulls /nonexistent/hulls.obj");
  EXPECT_EQ(exit_code(missing), 2) << missing.output;
  EXPECT_NE(missing.output.find("/nonexistent/hulls.obj: cannot be read (no such file)"), std::string::npos)
      << missing.output;
  for (const std::string& path : {exact_path, single_path, png}) std::remove(path.c_str());
}

TEST(DecomposeCommand, BadInputsFailNamingTheFile) {
  const CommandRun missing = run("decompose /nonexistent/prop.obj");
  EXPECT_EQ(exit_code(missing), 2) << missing.output;
  EXPECT_NE(missing.output.find("collide decompose: /nonexistent/prop.obj: cannot be read (no such file)"),
            std::string::npos) << missing.output;

  const std::string nan = write_temp("decompose_nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 1\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  const CommandRun bad = run("decompose " + nan);
  EXPECT_EQ(exit_code(bad), 2) << bad.output;
  EXPECT_NE(bad.output.find("decompose_nan.obj:3: vertex 3: coordinate y 'nan' is not finite"), std::string::npos)
      << bad.output;

  // A single triangle bounds no volume: the decomposition refuses it, the message naming the file.
  const std::string flat = write_temp("decompose_flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const CommandRun no_volume = run("decompose " + flat);
  EXPECT_EQ(exit_code(no_volume), 2) << no_volume.output;
  EXPECT_NE(no_volume.output.find("collide decompose: decompose_flat.obj: "), std::string::npos) << no_volume.output;

  const std::string empty = write_temp("decompose_empty.obj", "");
  const CommandRun nothing = run("decompose " + empty);
  EXPECT_EQ(exit_code(nothing), 2) << nothing.output;
  EXPECT_NE(nothing.output.find("decompose_empty.obj: cannot be read (an empty file)"), std::string::npos) << nothing.output;
  for (const std::string& path : {nan, flat, empty}) std::remove(path.c_str());
}

TEST(DecomposeCommand, OptionsOutOfRangeAndUnwritableOutputsAreRefusedBeforeTheWork) {
  const std::string mesh = dumbbell();
  const std::vector<std::string> refused{
      "--max-hulls 0", "--max-hulls " + std::to_string(kDecompositionMaxHulls + 1), "--max-vertices 3",
      "--max-vertices " + std::to_string(kMaxHullVertices + 1),
      "--resolution " + std::to_string(kDecompositionMinResolution - 1),
      "--resolution " + std::to_string(kDecompositionMaxResolution + 1), "--concavity -0.1", "--concavity 2", "--concavity nan",
      "--samples -1", "--threads -1", "--width 10"};
  for (const std::string& option : refused) {
    const CommandRun r = run("decompose " + mesh + " " + option);
    EXPECT_EQ(exit_code(r), 2) << option << "\n" << r.output;
    EXPECT_NE(r.output.find(option.substr(0, option.find(' '))), std::string::npos) << option << "\n" << r.output;
    EXPECT_EQ(r.output.find("hulls  "), std::string::npos) << "no work done for " << option;
  }
  for (const std::string option : {"--out", "--png"}) {
    const CommandRun r = run("decompose " + mesh + " " + option + " /nonexistent/folder/hulls.out");
    EXPECT_EQ(exit_code(r), 2) << r.output;
    EXPECT_NE(r.output.find(option + " /nonexistent/folder/hulls.out: cannot be written (no folder"), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("hulls  "), std::string::npos) << "no work done for " << option;
  }
}

}  // namespace
}  // namespace collide
