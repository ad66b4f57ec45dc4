// SvgDraw: the document parses as XML (pugixml), holds one element per call with the role's
// class, and the world -> image mapping matches the layout analytically, y up and y down.
#include <collide/core/error.hpp>
#include <collide/draw/bitmap_font.hpp>
#include <collide/draw/palette.hpp>
#include <collide/draw/svg_draw.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace collide {
namespace {

pugi::xml_document parse(const std::string& svg) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(svg.data(), svg.size());
  EXPECT_TRUE(r) << r.description() << " at offset " << r.offset << "\n" << svg;
  return doc;
}

std::vector<pugi::xml_node> children(pugi::xml_node parent) {
  std::vector<pugi::xml_node> out;
  for (pugi::xml_node n : parent.children()) {
    if (n.type() == pugi::node_element) out.push_back(n);
  }
  return out;
}

pugi::xml_node find_class(pugi::xml_node root, const char* element, const std::string& cls) {
  return root.find_node([&](pugi::xml_node n) {
    return std::string(n.name()) == element && cls == n.attribute("class").value();
  });
}

std::vector<pugi::xml_node> panels(const pugi::xml_document& doc) {
  std::vector<pugi::xml_node> out;
  for (pugi::xml_node n : doc.child("svg").children("g")) {
    if (std::string(n.attribute("class").value()) == "panel") out.push_back(n);
  }
  return out;
}

// The plot area of a one-panel picture without title, panel title or legend, from the layout
// rules in picture.hpp: padding kPicturePadding * text_scale all round.
struct Plot {
  float x, y, w, h;
};
Plot single_plot(const PictureOptions& o, float world_aspect) {
  const float pad = static_cast<float>(kPicturePadding * o.text_scale);
  const float w = static_cast<float>(o.width) - 2.0f * pad;
  const float h = o.plot_height > 0 ? static_cast<float>(o.plot_height)
                                    : std::round(w * std::clamp(world_aspect, kMinPlotAspect, kMaxPlotAspect));
  return {pad, pad, w, h};
}

PictureOptions bare_options() {
  PictureOptions o;
  o.width = 400;
  o.legend = false;
  o.text_scale = 2;
  return o;
}

constexpr float kPrinted = 0.006f;  // coordinates are printed with 2 decimals

TEST(SvgDraw, OneElementPerCallInOrderWithTheRoleClass) {
  SvgDraw d(bare_options());
  const std::array<Vec2, 3> tri{Vec2{0, 0}, Vec2{4, 0}, Vec2{0, 3}};
  d.draw_polygon(tri, 0.0f, DrawRole::static_geometry);
  d.draw_circle({5, 5}, 1.0f, DrawRole::body);
  d.draw_capsule({1, 6}, {3, 6}, 0.5f, DrawRole::fast_body);
  d.draw_segment({0, 8}, {6, 8}, DrawRole::laser);
  d.draw_arrow({2, 2}, {3, 3}, DrawRole::contact_normal);
  d.draw_point({2, 2}, DrawRole::contact_point);
  d.draw_point({0, 0}, DrawRole::origin);
  d.draw_polygon(tri, 0.25f, DrawRole::minkowski);
  d.draw_label({1, 1}, "A & B", DrawRole::shape_a);
  const pugi::xml_document doc = parse(d.svg());
  const auto ps = panels(doc);
  ASSERT_EQ(ps.size(), 1u);
  const auto items = children(ps[0]);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"polygon", "role-static-geometry"}, {"circle", "role-body"},        {"path", "role-fast-body"},
      {"line", "role-laser"},              {"path", "role-contact-normal"}, {"circle", "role-contact-point"},
      {"path", "role-origin"},             {"path", "role-minkowski-difference"}, {"text", "role-shape-a"}};
  ASSERT_EQ(items.size(), expected.size());
  for (size_t i = 0; i < items.size(); ++i) {
    EXPECT_EQ(items[i].name(), expected[i].first) << i;
    EXPECT_EQ(items[i].attribute("class").value(), expected[i].second) << i;
  }
  EXPECT_STREQ(items[8].child_value(), "A & B");
  // The palette's colours and pixel stroke widths.
  const DrawStyle& body = draw_style(DrawRole::body);
  EXPECT_FLOAT_EQ(items[1].attribute("stroke-width").as_float(), body.stroke_width);
  EXPECT_STREQ(items[0].attribute("fill").value(), "#bebebe");  // static geometry grey (190)
  EXPECT_STREQ(items[3].attribute("stroke").value(), "#ff1414");  // laser red
}

TEST(SvgDraw, CirclesLandWhereTheMappingSaysYUpAndYDown) {
  for (const bool y_up : {true, false}) {
    PictureOptions o = bare_options();
    o.world = Aabb{{0.0f, 0.0f}, {10.0f, 5.0f}};
    o.y_up = y_up;
    SvgDraw d(o);
    d.draw_circle({2.0f, 1.0f}, 0.5f, DrawRole::body);
    d.draw_circle({10.0f, 5.0f}, 0.25f, DrawRole::body);  // the world's top-right corner
    const Plot plot = single_plot(o, 0.5f);
    const float scale = std::min(plot.w / 10.0f, plot.h / 5.0f);
    const pugi::xml_document doc = parse(d.svg());  // nodes point into it: keep it alive
    const auto items = children(panels(doc)[0]);
    ASSERT_EQ(items.size(), 2u);
    const float cx = plot.x + 0.5f * plot.w + scale * (2.0f - 5.0f);
    const float cy = plot.y + 0.5f * plot.h + (y_up ? -1.0f : 1.0f) * scale * (1.0f - 2.5f);
    EXPECT_NEAR(items[0].attribute("cx").as_float(), cx, kPrinted) << "y_up " << y_up;
    EXPECT_NEAR(items[0].attribute("cy").as_float(), cy, kPrinted) << "y_up " << y_up;
    EXPECT_NEAR(items[0].attribute("r").as_float(), 0.5f * scale, kPrinted);
    // The aspect matches the plot, so the world's corner is the plot's corner: top-right when
    // y is up, bottom-right when it is down.
    EXPECT_NEAR(items[1].attribute("cx").as_float(), plot.x + plot.w, kPrinted);
    EXPECT_NEAR(items[1].attribute("cy").as_float(), y_up ? plot.y : plot.y + plot.h, kPrinted);
    // Same as the layout's own mapping.
    const PanelView view = d.layout().panels[0];
    EXPECT_NEAR(view.to_image({2.0f, 1.0f}).x, cx, 1e-3f);
    EXPECT_NEAR(view.to_image({2.0f, 1.0f}).y, cy, 1e-3f);
  }
}

TEST(SvgDraw, AutoFitCentresTheContentWithItsMargin) {
  PictureOptions o = bare_options();
  o.margin = 0.1f;
  SvgDraw d(o);
  d.draw_circle({100.0f, 50.0f}, 10.0f, DrawRole::body);
  // Content [90, 110] x [40, 60], margin 0.1 * 20 on every side: a 24-unit square world.
  const Plot plot = single_plot(o, 1.0f);
  const float scale = std::min(plot.w, plot.h) / 24.0f;
  const pugi::xml_document doc = parse(d.svg());  // nodes point into it: keep it alive
  const auto items = children(panels(doc)[0]);
  ASSERT_EQ(items.size(), 1u);
  EXPECT_NEAR(items[0].attribute("cx").as_float(), plot.x + 0.5f * plot.w, kPrinted);
  EXPECT_NEAR(items[0].attribute("cy").as_float(), plot.y + 0.5f * plot.h, kPrinted);
  EXPECT_NEAR(items[0].attribute("r").as_float(), 10.0f * scale, kPrinted);
}

TEST(SvgDraw, PanelsSitSideBySideEachFittedToItsOwnContent) {
  PictureOptions o = bare_options();
  o.width = 600;
  SvgDraw d(o);
  d.begin_panel("world space");
  d.draw_circle({0.0f, 0.0f}, 1.0f, DrawRole::shape_a);
  d.begin_panel("configuration space");
  d.draw_circle({1000.0f, -1000.0f}, 5.0f, DrawRole::minkowski);
  const PictureLayout lay = d.layout();
  ASSERT_EQ(lay.panels.size(), 2u);
  const pugi::xml_document doc = parse(d.svg());
  const auto ps = panels(doc);
  ASSERT_EQ(ps.size(), 2u);
  for (int i = 0; i < 2; ++i) {
    const PixelBox& b = lay.panels[static_cast<size_t>(i)].plot;
    const auto c = children(ps[static_cast<size_t>(i)]);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].attribute("cx").as_float(), static_cast<float>(b.x) + 0.5f * static_cast<float>(b.width), kPrinted);
    EXPECT_NEAR(c[0].attribute("cy").as_float(), static_cast<float>(b.y) + 0.5f * static_cast<float>(b.height), kPrinted);
  }
  // Side by side, in order, not overlapping; both titled.
  EXPECT_GT(lay.panels[1].plot.x, lay.panels[0].plot.x + lay.panels[0].plot.width);
  EXPECT_EQ(lay.panels[0].plot.y, lay.panels[1].plot.y);
  EXPECT_TRUE(find_class(doc, "text", "panel-title"));
  int titles = 0;
  for (pugi::xml_node t : doc.child("svg").children("text")) {
    if (std::string(t.attribute("class").value()) == "panel-title") {
      EXPECT_EQ(std::string(t.child_value()), titles == 0 ? "world space" : "configuration space");
      ++titles;
    }
  }
  EXPECT_EQ(titles, 2);
}

TEST(SvgDraw, LegendListsExactlyTheRolesDrawnInRoleOrder) {
  PictureOptions o;
  o.title = "three things";
  SvgDraw d(o);
  d.draw_label({0, 0}, "hello", DrawRole::highlight);
  d.draw_point({0, 0}, DrawRole::origin);
  d.draw_segment({0, 0}, {1, 1}, DrawRole::laser);
  d.draw_circle({1, 1}, 0.5f, DrawRole::body);
  d.draw_circle({1, 1}, -0.5f, DrawRole::sensor);  // skipped: not drawn, not listed
  const std::vector<DrawRole> roles = {DrawRole::body, DrawRole::laser, DrawRole::origin, DrawRole::highlight};
  EXPECT_EQ(d.roles_drawn(), roles);
  const pugi::xml_document doc = parse(d.svg());
  const pugi::xml_node legend = find_class(doc, "g", "legend");
  ASSERT_TRUE(legend);
  std::vector<std::string> names;
  int swatches = 0;
  for (pugi::xml_node n : children(legend)) {
    if (std::string(n.attribute("class").value()) == "legend-text") names.emplace_back(n.child_value());
    else ++swatches;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"body", "laser", "origin", "highlight"}));
  EXPECT_EQ(swatches, 4);
  // The swatch of each entry is drawn in its role's class.
  EXPECT_TRUE(find_class(legend, "polygon", "role-body"));
  EXPECT_TRUE(find_class(legend, "line", "role-laser"));
  EXPECT_TRUE(find_class(legend, "path", "role-origin"));
  const pugi::xml_node title = find_class(doc, "text", "title");
  ASSERT_TRUE(title);
  EXPECT_EQ(std::string(title.child_value()), "three things  [1 bad draw call skipped]");
}

TEST(SvgDraw, TextIsEscapedAndAlwaysParses) {
  PictureOptions o = bare_options();
  const std::string nasty = "a<b & c>\"d\" 'e' \x01 \xff\xfe é ✓ \xed\xa0\x80 \xe2\x82";
  o.title = nasty;
  SvgDraw d(o);
  d.draw_label({0, 0}, nasty, DrawRole::laser);
  const pugi::xml_document doc = parse(d.svg());
  const std::string expected =
      "a<b & c>\"d\" 'e' \xef\xbf\xbd \xef\xbf\xbd\xef\xbf\xbd é ✓ \xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd \xef\xbf\xbd\xef\xbf\xbd";
  EXPECT_EQ(std::string(find_class(doc, "text", "title").child_value()), expected);
  EXPECT_EQ(std::string(find_class(doc, "text", "role-laser").child_value()), expected);
  // The bitmap font counts the same columns as the SVG shows characters.
  EXPECT_EQ(text_columns(nasty), text_columns(expected));
}

TEST(SvgDraw, NumbersAreCompact) {
  SvgDraw d(bare_options());
  d.draw_circle({1.0f / 3.0f, 2.0f / 7.0f}, 0.1234567f, DrawRole::body);
  d.draw_segment({-1e-9f, 0.0f}, {1.0f, 0.0f}, DrawRole::laser);
  const std::string document = d.svg();
  const std::string svg = document.substr(document.find("<g class=\"panel\""));
  EXPECT_FALSE(std::regex_search(svg, std::regex(R"(\d\.\d{3})"))) << svg;
  EXPECT_FALSE(std::regex_search(svg, std::regex(R"(\.\d*0")"))) << svg;  // no trailing zeros
  EXPECT_EQ(svg.find("-0\""), std::string::npos) << svg;
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

// A rounded box and a capsule are paths whose straight pieces lie exactly `radius` (in pixels)
// outside the core: parse the L and M points back and measure.
TEST(SvgDraw, RoundedOutlinesStayOneRadiusOutsideTheCore) {
  PictureOptions o = bare_options();
  o.world = Aabb{{-4.0f, -4.0f}, {4.0f, 4.0f}};
  SvgDraw d(o);
  const std::array<Vec2, 4> box{Vec2{-1, -1}, Vec2{1, -1}, Vec2{1, 1}, Vec2{-1, 1}};
  d.draw_polygon(box, 0.5f, DrawRole::body);
  d.draw_capsule({-2, 2}, {2, 3}, 0.5f, DrawRole::fast_body);
  const PictureLayout lay = d.layout();
  const PanelView& view = lay.panels[0];
  const pugi::xml_document doc = parse(d.svg());  // nodes point into it: keep it alive
  const auto items = children(panels(doc)[0]);
  ASSERT_EQ(items.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    std::vector<Vec2> core;
    if (k == 0) {
      for (const Vec2 v : box) core.push_back(view.to_image(v));
    } else {
      core = {view.to_image({-2, 2}), view.to_image({2, 3})};
    }
    const float radius = 0.5f * view.scale;
    std::string path = items[static_cast<size_t>(k)].attribute("d").value();
    EXPECT_EQ(std::count(path.begin(), path.end(), 'A'), static_cast<long>(core.size()));
    // Endpoints of M, L and A commands (an A's last two numbers).
    std::regex cmd(R"(([MLA])([^MLAZ]*))");
    int checked = 0;
    for (auto it = std::sregex_iterator(path.begin(), path.end(), cmd); it != std::sregex_iterator(); ++it) {
      std::string args = (*it)[2].str();
      std::replace(args.begin(), args.end(), ',', ' ');
      std::istringstream in(args);
      std::vector<float> nums;
      for (float v; in >> v;) nums.push_back(v);
      ASSERT_GE(nums.size(), 2u);
      const Vec2 p{nums[nums.size() - 2], nums.back()};
      float nearest = INFINITY;
      for (size_t i = 0; i < core.size(); ++i) {
        const Vec2 a = core[i], b = core[(i + 1) % core.size()];
        const float t = std::clamp(dot(p - a, b - a) / dot(b - a, b - a), 0.0f, 1.0f);
        nearest = std::min(nearest, distance(p, a + t * (b - a)));
      }
      EXPECT_NEAR(nearest, radius, 0.02f) << path;
      ++checked;
    }
    EXPECT_EQ(checked, 1 + 2 * static_cast<int>(core.size()));
  }
}

TEST(SvgDraw, BadCallsAreSkippedAndCountedNeverDrawn) {
  SvgDraw d(bare_options());
  const std::array<Vec2, 3> bad_tri{Vec2{0, 0}, Vec2{NAN, 0}, Vec2{0, 1}};
  d.draw_polygon(bad_tri, 0.0f, DrawRole::body);
  d.draw_polygon({}, 0.0f, DrawRole::body);
  d.draw_circle({0, 0}, -1.0f, DrawRole::body);
  d.draw_circle({0, 0}, INFINITY, DrawRole::body);
  d.draw_segment({0, 0}, {INFINITY, 0}, DrawRole::laser);
  d.draw_arrow({NAN, NAN}, {0, 0}, DrawRole::contact_normal);
  d.draw_point({0, -INFINITY}, DrawRole::contact_point);
  d.draw_label({NAN, 0}, "x", DrawRole::laser);
  d.draw_circle({0, 0}, 1.0f, static_cast<DrawRole>(200));
  EXPECT_EQ(d.skipped(), 9);
  EXPECT_TRUE(d.roles_drawn().empty());
  const pugi::xml_document doc = parse(d.svg());
  EXPECT_EQ(panels(doc).size(), 1u);  // the empty picture still has its (empty) panel
  EXPECT_TRUE(children(panels(doc)[0]).empty());
  EXPECT_NE(std::string(find_class(doc, "text", "title").child_value()).find("9 bad draw calls skipped"),
            std::string::npos);
}

TEST(SvgDraw, BadOptionsThrowNamingTheOption) {
  auto throws_naming = [](PictureOptions o, const std::string& word) {
    try {
      SvgDraw d(o);
      ADD_FAILURE() << "no throw for " << word;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  PictureOptions o;
  o.width = 0;
  throws_naming(o, "width");
  o = {};
  o.width = kMaxCanvasSide + 1;
  throws_naming(o, "width");
  o = {};
  o.plot_height = -1;
  throws_naming(o, "plot_height");
  o = {};
  o.text_scale = 0;
  throws_naming(o, "text_scale");
  o = {};
  o.margin = NAN;
  throws_naming(o, "margin");
  o = {};
  o.world = Aabb{{0, 0}, {0, 1}};
  throws_naming(o, "world");
  o = {};
  o.world = Aabb{{0, 0}, {NAN, 1}};
  throws_naming(o, "world");
  SvgDraw d;
  EXPECT_THROW(d.begin_panel("p", Aabb{{1, 1}, {0, 2}}), InvalidInput);
}

TEST(SvgDraw, FarAwayGeometryIsCulledAndRaysAreClipped) {
  PictureOptions o = bare_options();
  o.world = Aabb{{0, 0}, {10, 10}};
  SvgDraw d(o);
  d.draw_circle({1e30f, 1e30f}, 1.0f, DrawRole::body);               // off the plot: culled
  d.draw_segment({5, 5}, {3e38f, 5}, DrawRole::laser);               // a ray to "infinity": clipped
  d.draw_arrow({5, 5}, {5, 1e20f}, DrawRole::contact_normal);        // its head is off the plot
  const pugi::xml_document doc = parse(d.svg());  // nodes point into it: keep it alive
  const auto items = children(panels(doc)[0]);
  ASSERT_EQ(items.size(), 2u);
  EXPECT_STREQ(items[0].name(), "line");
  EXPECT_LT(items[0].attribute("x2").as_float(), 400.0f + 100.0f);
  EXPECT_STREQ(items[1].name(), "line");  // drawn as its shaft only
}

TEST(SvgDraw, SaveWritesTheDocumentOrNamesThePath) {
  SvgDraw d;
  d.draw_circle({0, 0}, 1.0f, DrawRole::body);
  const std::string path = ::testing::TempDir() + "collide_svg_draw_test.svg";
  d.save(path);
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), d.svg());
  try {
    d.save("/nonexistent-dir/picture.svg");
    ADD_FAILURE() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/picture.svg"), std::string::npos);
  }
}

}  // namespace
}  // namespace collide
