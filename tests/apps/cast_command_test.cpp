// `collide cast`: the shape-cast picture checked against analytic geometry (a box moving into a
// circle: time of impact, A - B, the ray's entry point and where the picture puts them, in the
// calls the picture replays and in the pixels of its PNG), the Minkowski difference of every
// shape type against GJK distance, and the command end to end through the real binary (SVG that
// parses, a PNG and a PDF of the reported size, errors naming the field).

#include "cast.hpp"
#include "cli_run.hpp"
#include "support/picture_checks.hpp"

#include <collide/draw/cairo_picture.hpp>
#include <collide/draw/palette.hpp>
#include <collide/narrow/distance.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <regex>
#include <string>

namespace collide::cli {
namespace {

// The analytic case: box A (half 1 x 0.5) at the origin moving by (6, 0); circle B of radius 1
// at (5, 0), still. The gap is 5 - 1 - 1 = 3, closed at speed 6: t = 0.5. A - B is the box
// centred at (-5, 0) rounded by 1; the ray from the origin along vb - va = (-6, 0) enters it at
// (-3, 0), where its outward normal is (1, 0), the normal from A to B.
constexpr const char* kBoxIntoCircle =
    R"({"a": {"type": "box", "half": [1, 0.5]}, "va": [6, 0],
        "b": {"type": "circle", "radius": 1}, "xb": {"p": [5, 0]}, "vb": [0, 0]})";
constexpr float kExpectedT = 0.5f;
const Vec2 kEntry{-3.0f, 0.0f};
const Vec2 kDifferenceCenter{-5.0f, 0.0f};
const Vec2 kDifferenceHalf{1.0f, 0.5f};
constexpr float kDifferenceRadius = 1.0f;

/// Time and position tolerance of the analytic checks, world units: the cast's own tolerance
/// (kShapeCastTolerance of the shapes' size) with room to spare.
constexpr float kWorldTolerance = 1e-3f;
/// Float rounding of pixel coordinates a few hundred pixels from the origin.
constexpr float kPixelTolerance = 1e-3f;

/// Distance from `p` to the rounded box (core half extents `half` centred on `center`, grown by
/// `radius`): negative inside.
float rounded_box_distance(Vec2 p, Vec2 center, Vec2 half, float radius) {
  const Vec2 d = glm::abs(p - center) - half;
  const float outside = glm::length(glm::max(d, Vec2(0.0f)));
  const float inside = std::min(std::max(d.x, d.y), 0.0f);
  return outside + inside - radius;
}

/// Calls of one panel counted by role (a shape's solid and its label count apart: both are
/// calls).
std::map<std::string, int> roles(const std::vector<test::SinkCall>& calls) {
  std::map<std::string, int> out;
  for (const test::SinkCall& c : calls) ++out[to_string(c.role)];
  return out;
}

TEST(CastPicture, BoxIntoCircleIsAnalyticInBothPanels) {
  Picture picture;
  const CastPicture cast = draw_cast(picture, parse_cast_question(kBoxIntoCircle));
  ASSERT_EQ(cast.result.status, QueryStatus::hit);
  EXPECT_NEAR(cast.result.fraction, kExpectedT, kWorldTolerance);
  EXPECT_NEAR(cast.result.normal.x, 1.0f, kWorldTolerance);
  EXPECT_NEAR(cast.result.point.x, 4.0f, kWorldTolerance);  // the circle's leftmost point at t
  // The explicit difference: the box's 4 corners shifted by -5, radius 1.
  ASSERT_EQ(cast.difference.vertices.size(), 4u);
  EXPECT_FLOAT_EQ(cast.difference.radius, kDifferenceRadius);
  for (const Vec2 v : cast.difference.vertices) {
    EXPECT_NEAR(std::fabs(v.x - kDifferenceCenter.x), kDifferenceHalf.x, 1e-5f);
    EXPECT_NEAR(std::fabs(v.y - kDifferenceCenter.y), kDifferenceHalf.y, 1e-5f);
  }
  EXPECT_NEAR(rounded_box_distance(cast.result.fraction * cast.ray, kDifferenceCenter, kDifferenceHalf, kDifferenceRadius),
              0.0f, kWorldTolerance)
      << "the ray's entry point t (vb - va) lies on the boundary of A - B";

  test::RecordingSink sink;
  picture.replay(sink);
  const PictureLayout& lay = sink.layout;
  EXPECT_NE(lay.title.find("hit at t = 0.5"), std::string::npos) << lay.title;
  ASSERT_EQ(lay.panels.size(), 2u);
  // Motion panel: B does not move, so it is drawn once; A has its end pose, arrow and pose at t.
  const std::map<std::string, int> motion{{"path", 2},      {"shape A", 2},        {"shape B", 2},
                                          {"highlight", 1}, {"contact normal", 1}, {"contact point", 1}};
  EXPECT_EQ(roles(sink.in_panel(0)), motion);  // shape A/B: the solid and its label
  const std::vector<test::SinkCall> difference_calls = sink.in_panel(1);
  const std::map<std::string, int> difference{
      {"Minkowski difference", 1}, {"path", 1}, {"origin", 2}, {"highlight", 2}, {"contact normal", 1}};
  EXPECT_EQ(roles(difference_calls), difference);

  // Where the configuration-space panel puts things: the entry point's dot, the origin's label
  // and A - B (its core's corners and its radius) at the layout's world -> image mapping of the
  // analytic ones.
  const PanelView& view = lay.panels[1];
  int checked = 0;
  for (const test::SinkCall& c : difference_calls) {
    if (c.role == DrawRole::highlight && c.kind == test::SinkCall::Kind::point) {
      EXPECT_LE(distance(c.points[0], view.to_image(kEntry)), kPixelTolerance + view.scale * kWorldTolerance);
      ++checked;
    } else if (c.role == DrawRole::origin && c.kind == test::SinkCall::Kind::label) {
      EXPECT_EQ(c.text, "0");
      EXPECT_LE(distance(c.points[0], view.to_image({0.0f, 0.0f}) + Vec2{kLabelOffset, -kLabelOffset}), kPixelTolerance);
      ++checked;
    } else if (c.role == DrawRole::minkowski) {
      ASSERT_EQ(c.points.size(), 4u);
      for (const Vec2 corner_px : c.points) {
        const Vec2 off = (corner_px - view.to_image(kDifferenceCenter)) / view.scale;
        EXPECT_NEAR(std::fabs(off.x), kDifferenceHalf.x, kPixelTolerance);
        EXPECT_NEAR(std::fabs(off.y), kDifferenceHalf.y, kPixelTolerance);
      }
      EXPECT_NEAR(c.radius, kDifferenceRadius * view.scale, kPixelTolerance);
      ++checked;
    }
  }
  EXPECT_EQ(checked, 3);

  // Legend: exactly the roles drawn.
  std::vector<std::string> legend;
  for (const LegendEntry& e : lay.legend) legend.emplace_back(to_string(e.role));
  EXPECT_EQ(legend, (std::vector<std::string>{"contact point", "contact normal", "path", "shape A", "shape B",
                                               "Minkowski difference", "origin", "highlight"}));
}

TEST(CastPicture, RasterisedEntryPointAndDifferenceHaveTheirColours) {
  Picture picture;
  (void)draw_cast(picture, parse_cast_question(kBoxIntoCircle));
  const std::string path = ::testing::TempDir() + "cast_picture.png";
  save_picture(picture, path, PictureFormat::png);
  const test::PngImage png = test::read_png(path);
  const PictureLayout lay = picture.layout();
  ASSERT_EQ(png.width, lay.width);
  ASSERT_EQ(png.height, lay.height);
  const PanelView& view = lay.panels[1];
  auto at = [&](Vec2 world) { return png.at(view.to_image(world)); };
  EXPECT_EQ(at(kEntry), draw_style(DrawRole::highlight).stroke) << "the entry point's dot";
  EXPECT_PRED2(test::near, at(kDifferenceCenter + Vec2{0.0f, 0.8f}),
               test::over(draw_style(DrawRole::minkowski).fill, kPictureBackground))
      << "inside A - B, off the ray";
  EXPECT_EQ(at(kDifferenceCenter + Vec2{0.0f, 2.0f}), kPictureBackground) << "0.5 outside A - B";
}

TEST(CastPicture, SeparatedCastDrawsNoHighlight) {
  Picture picture;
  const CastPicture cast = draw_cast(picture, parse_cast_question(
      R"({"a": {"type": "circle", "radius": 1}, "va": [4, 0],
          "b": {"type": "circle", "radius": 0.5}, "xb": {"p": [3, 3]}, "vb": [0, 0]})"));
  EXPECT_EQ(cast.result.status, QueryStatus::separated);
  // Circle - circle: one vertex (B's centre subtracted from A's), the radii summed.
  ASSERT_EQ(cast.difference.vertices.size(), 1u);
  EXPECT_EQ(cast.difference.vertices[0], (Vec2{-3.0f, -3.0f}));
  EXPECT_FLOAT_EQ(cast.difference.radius, 1.5f);
  for (const DrawRole role : picture.roles_drawn()) {
    EXPECT_NE(role, DrawRole::highlight);
    EXPECT_NE(role, DrawRole::contact_point);
  }
}

// The explicit A - B built from the shapes' cores (core_polygon) has, for every pair of shape
// types, the signed distance to the origin that GJK distance gives between the shapes: the gap
// when apart, <= 0 when they overlap. Fixed seed; both outcomes exercised.
TEST(CastPicture, DifferenceOfEveryShapePairMatchesGjkDistance) {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<float> coord(-3.0f, 3.0f), size(0.2f, 1.5f), angle(-3.14f, 3.14f);
  auto random_shape = [&](int type) -> Shape2D {
    switch (type) {
      case 0: return make_circle({coord(rng) * 0.2f, coord(rng) * 0.2f}, size(rng));
      case 1: return make_capsule({-size(rng), 0.0f}, {size(rng), 0.1f}, 0.5f * size(rng));
      case 2: return make_segment({-size(rng), -0.2f}, {size(rng), 0.3f});
      default: return make_box({size(rng), size(rng)}, coord(rng) < 0.0f ? 0.0f : 0.2f * size(rng));
    }
  };
  constexpr float kDistanceTolerance = 1e-4f;  // relative to the scene's size (about 10)
  int apart = 0, overlapping = 0;
  for (int i = 0; i < 400; ++i) {
    const Shape2D a = random_shape(i % 4), b = random_shape((i / 4) % 4);
    const Transform xa{{coord(rng), coord(rng)}, Rot2::from_angle(angle(rng))};
    const Transform xb{{coord(rng), coord(rng)}, Rot2::from_angle(angle(rng))};
    MinkowskiPolygon md = minkowski_difference(core_polygon(a), xa, core_polygon(b), xb);
    const float signed_distance = md.signed_distance_to_origin();
    const DistanceResult d = distance(a, xa, b, xb);
    if (d.distance > 0.0f) {
      ++apart;
      EXPECT_NEAR(signed_distance, d.distance, kDistanceTolerance * 10.0f) << i;
    } else {
      ++overlapping;
      EXPECT_LE(signed_distance, kDistanceTolerance * 10.0f) << i;
    }
  }
  EXPECT_GT(apart, 100);
  EXPECT_GT(overlapping, 50);
}

// ---- the command, end to end ---------------------------------------------------------------

using test::CommandRun;
const auto run = test::run_cli;

TEST(CastCommand, WritesAParsingSvgAPngAndAPdfOfTheReportedSize) {
  const std::string dir = ::testing::TempDir();
  const std::string question = dir + "collide_cast_question.json", svg = dir + "collide_cast.svg",
                    png = dir + "collide_cast.png", pdf = dir + "collide_cast.pdf";
  std::ofstream(question) << kBoxIntoCircle;
  for (const std::string& f : {svg, png, pdf}) std::remove(f.c_str());
  const CommandRun r = run("cast " + question + " --width 640 --svg " + svg + " --png " + png + " --pdf " + pdf);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("hit at t = 0.5 "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("A - B     4 vertices, radius 1"), std::string::npos) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(wrote \S+collide_cast.png \((\d+) x (\d+)\))"))) << r.output;
  const std::string width = m[1].str(), height = m[2].str();
  EXPECT_EQ(width, "640");
  for (const std::string& f : {svg, pdf}) {
    EXPECT_NE(r.output.find("wrote " + f + " (" + width + " x " + height + ")"), std::string::npos) << r.output;
  }
  const test::PngImage image = test::read_png(png);
  EXPECT_EQ(image.width, 640);
  EXPECT_EQ(std::to_string(image.height), height);
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file(svg.c_str())) << svg;
  EXPECT_EQ(std::string(doc.child("svg").attribute("width").value()), "640px");
  EXPECT_EQ(std::string(doc.child("svg").attribute("height").value()), height + "px");
  std::ifstream in(pdf, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.rfind("%PDF-", 0), 0u) << pdf;
  EXPECT_NE(bytes.find("/MediaBox [ 0 0 640 " + height + " ]"), std::string::npos) << pdf;
}

TEST(CastCommand, BadQuestionsFailNamingTheField) {
  CommandRun r = run(R"(cast --question '{"a": {"type": "circle", "radius": -1}, "va": [1, 0], "b": {"type": "circle", "radius": 1}, "vb": [0, 0]}')");
  EXPECT_EQ(WEXITSTATUS(r.status), 2) << r.output;
  EXPECT_NE(r.output.find("a.radius: negative"), std::string::npos) << r.output;
  r = run(R"(cast --question '{"op": "distance"}')");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("op:"), std::string::npos) << r.output;
  r = run("cast --question 'not json'");
  EXPECT_NE(r.output.find("root: JSON syntax error at line 1, column 2"), std::string::npos) << r.output;
  r = run("cast /nonexistent/question.json");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("question.json"), std::string::npos) << r.output;
  r = run(std::string("cast --width 10 --question '") + kBoxIntoCircle + "'");
  EXPECT_NE(r.status, 0) << r.output;
}

}  // namespace
}  // namespace collide::cli
