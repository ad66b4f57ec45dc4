// `collide cast`: the shape-cast picture checked against analytic geometry (a box moving into a
// circle: time of impact, A - B, the ray's entry point and where the picture puts them), the
// Minkowski difference of every shape type against GJK distance, and the command end to end
// through the real binary (SVG that parses, a PNG of the reported size, errors naming the field).

#include "cast.hpp"
#include "cli_run.hpp"

#include <collide/draw/canvas_draw.hpp>
#include <collide/draw/palette.hpp>
#include <collide/draw/svg_draw.hpp>
#include <collide/narrow/distance.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
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
/// Coordinates in the SVG are printed with 2 decimals (half a hundredth of a pixel).
constexpr float kPrintedPixels = 0.006f;

/// Distance from `p` to the rounded box (core half extents `half` centred on `center`, grown by
/// `radius`): negative inside.
float rounded_box_distance(Vec2 p, Vec2 center, Vec2 half, float radius) {
  const Vec2 d = glm::abs(p - center) - half;
  const float outside = glm::length(glm::max(d, Vec2(0.0f)));
  const float inside = std::min(std::max(d.x, d.y), 0.0f);
  return outside + inside - radius;
}

std::vector<pugi::xml_node> panels(const pugi::xml_document& doc) {
  std::vector<pugi::xml_node> out;
  for (pugi::xml_node n : doc.child("svg").children("g")) {
    if (std::string(n.attribute("class").value()) == "panel") out.push_back(n);
  }
  return out;
}

/// Elements of a panel counted by class.
std::map<std::string, int> classes(pugi::xml_node panel) {
  std::map<std::string, int> out;
  for (pugi::xml_node n : panel.children()) {
    if (n.type() == pugi::node_element) ++out[n.attribute("class").value()];
  }
  return out;
}

pugi::xml_node first_of(pugi::xml_node panel, const char* element, const char* cls) {
  for (pugi::xml_node n : panel.children(element)) {
    if (std::string(n.attribute("class").value()) == cls) return n;
  }
  return {};
}

TEST(CastPicture, BoxIntoCircleIsAnalyticInBothPanels) {
  SvgDraw svg;
  const CastPicture cast = draw_cast(svg, parse_cast_question(kBoxIntoCircle));
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

  pugi::xml_document doc;
  const std::string text = svg.svg();
  ASSERT_TRUE(doc.load_buffer(text.data(), text.size()));
  EXPECT_NE(std::string(doc.child("svg").child("text").child_value()).find("hit at t = 0.5"), std::string::npos);
  const auto ps = panels(doc);
  ASSERT_EQ(ps.size(), 2u);
  // Motion panel: B does not move, so it is drawn once; A has its end pose, arrow and pose at t.
  const std::map<std::string, int> motion{
      {"role-path", 2},        {"role-shape-a", 2}, {"role-shape-b", 2}, {"role-highlight", 1},
      {"role-contact-normal", 1}, {"role-contact-point", 1}};  // shape A/B: the solid and its label
  EXPECT_EQ(classes(ps[0]), motion);
  const std::map<std::string, int> difference{{"role-minkowski-difference", 1}, {"role-path", 1},
                                              {"role-origin", 2}, {"role-highlight", 2},
                                              {"role-contact-normal", 1}};
  EXPECT_EQ(classes(ps[1]), difference);

  // Where the configuration-space panel puts things: the entry point's dot and the origin's
  // label at the layout's world -> image mapping of the analytic points.
  const PictureLayout lay = svg.layout();
  const PanelView& view = lay.panels[1];
  const pugi::xml_node dot = first_of(ps[1], "circle", "role-highlight");
  ASSERT_TRUE(dot);
  const Vec2 entry_px = view.to_image(kEntry);
  EXPECT_NEAR(dot.attribute("cx").as_float(), entry_px.x, kPrintedPixels + view.scale * kWorldTolerance);
  EXPECT_NEAR(dot.attribute("cy").as_float(), entry_px.y, kPrintedPixels + view.scale * kWorldTolerance);
  const pugi::xml_node zero = first_of(ps[1], "text", "role-origin");
  const Vec2 origin_px = view.to_image({0.0f, 0.0f});
  EXPECT_NEAR(zero.attribute("x").as_float(), origin_px.x + kLabelOffset, kPrintedPixels);
  EXPECT_NEAR(zero.attribute("y").as_float(), origin_px.y - kLabelOffset, kPrintedPixels);
  // The rounded outline of A - B: every point of its path, mapped back to the world, is on the
  // analytic rounded box (the path's arcs' end points and the pushed-out edges).
  const std::string d = first_of(ps[1], "path", "role-minkowski-difference").attribute("d").value();
  const std::regex pair(R"((-?[0-9.]+),(-?[0-9.]+))");
  int points = 0;
  for (auto it = std::sregex_iterator(d.begin(), d.end(), pair); it != std::sregex_iterator(); ++it) {
    const Vec2 px{std::stof((*it)[1]), std::stof((*it)[2])};
    const Vec2 plot_center{view.plot.x + 0.5f * view.plot.width, view.plot.y + 0.5f * view.plot.height};
    const Vec2 off = (px - plot_center) / view.scale;
    const Vec2 world = view.world.center() + Vec2{off.x, -off.y};
    EXPECT_NEAR(rounded_box_distance(world, kDifferenceCenter, kDifferenceHalf, kDifferenceRadius), 0.0f,
                2.0f * kPrintedPixels / view.scale)
        << px.x << "," << px.y;
    ++points;
  }
  EXPECT_GE(points, 8);  // 4 pushed-out edges, 4 arcs

  // Legend: exactly the roles drawn.
  std::vector<std::string> legend;
  for (const LegendEntry& e : lay.legend) legend.emplace_back(to_string(e.role));
  EXPECT_EQ(legend, (std::vector<std::string>{"contact point", "contact normal", "path", "shape A", "shape B",
                                               "Minkowski difference", "origin", "highlight"}));
}

TEST(CastPicture, RasterisedEntryPointAndDifferenceHaveTheirColours) {
  CanvasDraw png;
  (void)draw_cast(png, parse_cast_question(kBoxIntoCircle));
  const Canvas c = png.render();
  const PanelView view = png.layout().panels[1];
  auto at = [&](Vec2 world) {
    const Vec2 p = view.to_image(world);
    return c.pixel(static_cast<int>(p.x), static_cast<int>(p.y));
  };
  EXPECT_EQ(at(kEntry), draw_style(DrawRole::highlight).stroke);
  const Color fill = draw_style(DrawRole::minkowski).fill;
  const Color expected{static_cast<std::uint8_t>((fill.r * fill.a + 255 * (255 - fill.a) + 127) / 255),
                       static_cast<std::uint8_t>((fill.g * fill.a + 255 * (255 - fill.a) + 127) / 255),
                       static_cast<std::uint8_t>((fill.b * fill.a + 255 * (255 - fill.a) + 127) / 255), 255};
  EXPECT_EQ(at(kDifferenceCenter + Vec2{0.0f, 0.8f}), expected) << "inside A - B, off the ray";
  EXPECT_EQ(at(kDifferenceCenter + Vec2{0.0f, 2.0f}), kPictureBackground) << "0.5 outside A - B";
}

TEST(CastPicture, SeparatedCastDrawsNoHighlight) {
  SvgDraw svg;
  const CastPicture cast = draw_cast(svg, parse_cast_question(
      R"({"a": {"type": "circle", "radius": 1}, "va": [4, 0],
          "b": {"type": "circle", "radius": 0.5}, "xb": {"p": [3, 3]}, "vb": [0, 0]})"));
  EXPECT_EQ(cast.result.status, QueryStatus::separated);
  // Circle - circle: one vertex (B's centre subtracted from A's), the radii summed.
  ASSERT_EQ(cast.difference.vertices.size(), 1u);
  EXPECT_EQ(cast.difference.vertices[0], (Vec2{-3.0f, -3.0f}));
  EXPECT_FLOAT_EQ(cast.difference.radius, 1.5f);
  for (const DrawRole role : svg.roles_drawn()) {
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

std::uint32_t big_endian(const unsigned char* p) {
  return std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3];
}

TEST(CastCommand, WritesAParsingSvgAndAPngOfTheReportedSize) {
  const std::string dir = ::testing::TempDir();
  const std::string question = dir + "collide_cast_question.json", svg = dir + "collide_cast.svg",
                    png = dir + "collide_cast.png";
  std::ofstream(question) << kBoxIntoCircle;
  std::remove(svg.c_str());
  std::remove(png.c_str());
  const CommandRun r = run("cast " + question + " --width 640 --svg " + svg + " --png " + png);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("hit at t = 0.5 "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("A - B     4 vertices, radius 1"), std::string::npos) << r.output;
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_file(svg.c_str())) << svg;
  EXPECT_EQ(panels(doc).size(), 2u);
  EXPECT_STREQ(doc.child("svg").attribute("width").value(), "640");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(wrote \S+collide_cast.png \((\d+) x (\d+)\))"))) << r.output;
  std::ifstream file(png, std::ios::binary);
  std::array<unsigned char, 24> head{};
  file.read(reinterpret_cast<char*>(head.data()), head.size());
  ASSERT_TRUE(file.good()) << "no PNG at " << png;
  const std::array<unsigned char, 8> signature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_TRUE(std::equal(signature.begin(), signature.end(), head.begin()));
  EXPECT_EQ(big_endian(&head[16]), 640u);  // IHDR width, then height
  EXPECT_EQ(big_endian(&head[20]), static_cast<std::uint32_t>(std::stoi(m[2].str())));
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
