// CanvasDraw and its text: pixels at analytically known positions carry the role's colour
// (inside a circle or polygon, on a segment, at a point), y up and y down; text paints inside
// its box and nowhere else; bad calls are skipped; rounded shapes keep their rounded corners.
#include <collide/core/error.hpp>
#include <collide/draw/bitmap_font.hpp>
#include <collide/draw/canvas_draw.hpp>
#include <collide/draw/palette.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>
#include <string>

namespace collide {
namespace {

/// `ink` composited over `under` with the source-over rule, rounded like the canvas.
Color over(Color ink, Color under) {
  auto mix = [&](std::uint8_t s, std::uint8_t d) {
    return static_cast<std::uint8_t>((s * ink.a + d * (255u - ink.a) + 127u) / 255u);
  };
  return {mix(ink.r, under.r), mix(ink.g, under.g), mix(ink.b, under.b), 255};
}

PictureOptions bare_options(bool y_up = true) {
  PictureOptions o;
  o.width = 400;
  o.legend = false;
  o.world = Aabb{{0.0f, 0.0f}, {10.0f, 5.0f}};
  o.y_up = y_up;
  return o;
}

Color at(const Canvas& c, Vec2 p) { return c.pixel(static_cast<int>(p.x), static_cast<int>(p.y)); }

TEST(CanvasDraw, ShapesPaintTheirRoleColourWhereTheMappingPutsThem) {
  for (const bool y_up : {true, false}) {
    CanvasDraw d(bare_options(y_up));
    const std::array<Vec2, 4> wall{Vec2{0.5f, 0.5f}, Vec2{3.5f, 0.5f}, Vec2{3.5f, 1.5f}, Vec2{0.5f, 1.5f}};
    d.draw_polygon(wall, 0.0f, DrawRole::static_geometry);
    d.draw_circle({7.0f, 3.0f}, 1.0f, DrawRole::body);
    d.draw_segment({0.5f, 4.0f}, {9.5f, 4.0f}, DrawRole::laser);
    d.draw_point({5.0f, 2.5f}, DrawRole::contact_point);
    const Canvas c = d.render();
    const PanelView view = d.layout().panels[0];
    // The analytic mapping (picture.hpp): plot centre plus scale times the offset from the
    // world's centre, y flipped when up.
    const float pad = static_cast<float>(kPicturePadding * d.options().text_scale);
    const float plot_w = 400.0f - 2.0f * pad;
    const float scale = plot_w / 10.0f;  // the plot has the world's aspect: 0.5
    auto image = [&](Vec2 w) {
      const float sy = y_up ? -1.0f : 1.0f;
      return Vec2{pad + 0.5f * plot_w + scale * (w.x - 5.0f), pad + 0.25f * plot_w + sy * scale * (w.y - 2.5f)};
    };
    EXPECT_NEAR(view.to_image({7.0f, 3.0f}).x, image({7.0f, 3.0f}).x, 1e-3f);
    EXPECT_NEAR(view.to_image({7.0f, 3.0f}).y, image({7.0f, 3.0f}).y, 1e-3f);

    const DrawStyle& wall_style = draw_style(DrawRole::static_geometry);
    EXPECT_EQ(at(c, image({2.0f, 1.0f})), wall_style.fill) << "inside the wall, y_up " << y_up;
    EXPECT_EQ(at(c, image({2.0f, 2.5f})), kPictureBackground) << "above/below the wall";
    EXPECT_EQ(at(c, image({7.0f, 3.0f})), over(draw_style(DrawRole::body).fill, kPictureBackground))
        << "inside the circle";
    EXPECT_EQ(at(c, image({7.0f, 3.0f + 1.3f})), kPictureBackground) << "outside the circle";
    EXPECT_EQ(at(c, image({7.0f, 3.0f - 1.3f})), kPictureBackground);
    // The laser's line runs along a row of pixels; its centre row is fully inked.
    const Vec2 on_laser = image({5.2f, 4.0f});
    const Color laser = at(c, on_laser);
    const Color neighbour = at(c, on_laser + Vec2{0.0f, on_laser.y - std::floor(on_laser.y) < 0.5f ? -1.0f : 1.0f});
    EXPECT_TRUE(laser == draw_style(DrawRole::laser).stroke || neighbour == draw_style(DrawRole::laser).stroke);
    EXPECT_EQ(at(c, on_laser + Vec2{0.0f, 4.0f}), kPictureBackground);
    EXPECT_EQ(at(c, image({5.0f, 2.5f})), draw_style(DrawRole::contact_point).stroke) << "the contact dot";
  }
}

TEST(CanvasDraw, RoundedPolygonsAndCapsulesHaveRoundCorners) {
  PictureOptions o = bare_options();
  CanvasDraw d(o);
  const std::array<Vec2, 4> core{Vec2{2, 1}, Vec2{4, 1}, Vec2{4, 3}, Vec2{2, 3}};
  d.draw_polygon(core, 0.8f, DrawRole::static_geometry);
  d.draw_capsule({6, 2.5f}, {9, 2.5f}, 1.0f, DrawRole::static_geometry);
  const Canvas c = d.render();
  const PanelView view = d.layout().panels[0];
  const Color fill = draw_style(DrawRole::static_geometry).fill;
  const Vec2 diagonal = glm::normalize(Vec2{1, 1});
  // Near a corner: in the rounding (0.6 from the vertex) is painted, the square corner of the
  // pushed-out box (0.8 * sqrt 2 = 1.13 from the vertex, outside the radius) is not.
  EXPECT_EQ(at(c, view.to_image(Vec2{4, 3} + 0.6f * diagonal)), fill);
  EXPECT_EQ(at(c, view.to_image(Vec2{4, 3} + Vec2{0.78f, 0.78f})), kPictureBackground);
  EXPECT_EQ(at(c, view.to_image(Vec2{3, 3.6f})), fill);  // edge pushed out by the radius
  // The capsule: its end cap is round.
  EXPECT_EQ(at(c, view.to_image({9.8f, 2.5f})), fill);
  EXPECT_EQ(at(c, view.to_image({9.75f, 3.35f})), kPictureBackground);
  EXPECT_EQ(at(c, view.to_image({7.5f, 3.3f})), fill);
}

// A translucent rounded shape is blended once at every pixel: no darker seams where the pushed
// out edges and the vertex discs would overlap in a union of pieces.
TEST(CanvasDraw, TranslucentShapesHaveNoSeams) {
  CanvasDraw d(bare_options());
  const std::array<Vec2, 3> tri{Vec2{2, 1}, Vec2{8, 1}, Vec2{5, 4}};
  d.draw_polygon(tri, 0.5f, DrawRole::minkowski);
  const Canvas c = d.render();
  const PanelView view = d.layout().panels[0];
  const Color expected = over(draw_style(DrawRole::minkowski).fill, kPictureBackground);
  // A row through the interior and the pushed-out bottom edge region, away from the outline.
  std::set<std::uint32_t> colours;
  for (float x = 3.0f; x <= 7.0f; x += 0.05f) {
    for (const float y : {0.75f, 1.0f, 1.5f, 2.0f}) {
      const Color p = at(c, view.to_image({x, y}));
      colours.insert(static_cast<std::uint32_t>(p.r) << 16 | static_cast<std::uint32_t>(p.g) << 8 | p.b);
      EXPECT_EQ(p, expected) << x << ", " << y;
    }
  }
  EXPECT_EQ(colours.size(), 1u);
}

TEST(CanvasDraw, ALabelPaintsOnlyInsideItsBox) {
  PictureOptions o = bare_options();
  o.text_scale = 2;
  CanvasDraw d(o);
  d.draw_label({5.0f, 2.5f}, "t = 0.25", DrawRole::highlight);
  const Canvas c = d.render();
  const PanelView view = d.layout().panels[0];
  const Vec2 anchor = view.to_image({5.0f, 2.5f});
  // The documented box: from kLabelOffset right of the anchor, baseline kLabelOffset above it,
  // text_width wide and a glyph (ascent and descent) tall, plus the one-pixel halo.
  const int x0 = static_cast<int>(std::lround(anchor.x + kLabelOffset)) - 1;
  const int y0 = static_cast<int>(std::lround(anchor.y - kLabelOffset - kGlyphAscent * 2)) - 1;
  const int x1 = x0 + text_width("t = 0.25", 2) + 2;
  const int y1 = y0 + kGlyphHeight * 2 + 2;
  int inside = 0, text_colour = 0;
  for (int y = view.plot.y; y < view.plot.y + view.plot.height; ++y) {
    for (int x = view.plot.x; x < view.plot.x + view.plot.width; ++x) {
      const Color p = c.pixel(x, y);
      const bool in_box = x >= x0 && x < x1 && y >= y0 && y < y1;
      if (!in_box) {
        ASSERT_EQ(p, kPictureBackground) << "pixel " << x << ", " << y << " outside the label box";
      }
      inside += in_box;
      text_colour += p == draw_style(DrawRole::highlight).stroke;
    }
  }
  EXPECT_GT(inside, 0);
  EXPECT_GT(text_colour, 20);
}

TEST(CanvasDraw, TitleLegendAndPanelTitlesAreDrawn) {
  PictureOptions o;
  o.width = 500;
  o.title = "a title";
  CanvasDraw d(o);
  d.begin_panel("left");
  d.draw_circle({0, 0}, 1, DrawRole::shape_a);
  d.begin_panel("right");
  d.draw_circle({0, 0}, 1, DrawRole::shape_b);
  const Canvas c = d.render();
  const PictureLayout lay = d.layout();
  EXPECT_EQ(c.width(), lay.width);
  EXPECT_EQ(c.height(), lay.height);
  auto ink_in = [&](int x, int y, int w, int h) {
    int n = 0;
    for (int j = y; j < y + h; ++j) {
      for (int i = x; i < x + w; ++i) n += c.pixel(i, j) == kPictureText;
    }
    return n;
  };
  const int u = lay.text_scale;
  EXPECT_GT(ink_in(lay.title_x, lay.title_y, text_width(lay.title, u), kGlyphHeight * u), 10);
  ASSERT_EQ(lay.legend.size(), 2u);
  for (const LegendEntry& e : lay.legend) {
    EXPECT_GT(ink_in(e.text_x, e.text_y, text_width(to_string(e.role), u), kGlyphHeight * u), 10);
    const Color swatch = c.pixel(e.swatch.x + e.swatch.width / 2, e.swatch.y + e.swatch.height / 2);
    EXPECT_EQ(swatch, over(draw_style(e.role).fill, kPictureBackground));
  }
  for (const PanelView& p : lay.panels) {
    EXPECT_GT(ink_in(p.plot.x, p.plot.y - kLineAdvance * u, text_width(p.title, u), kGlyphHeight * u), 5);
  }
}

TEST(CanvasDraw, BadCallsAreSkippedAndTooLargePicturesThrow) {
  CanvasDraw d(bare_options());
  d.draw_circle({NAN, 0}, 1.0f, DrawRole::body);
  d.draw_capsule({0, 0}, {1, 1}, -2.0f, DrawRole::body);
  d.draw_polygon({}, 0.0f, DrawRole::body);
  EXPECT_EQ(d.skipped(), 3);
  const Canvas c = d.render();  // no crash; nothing drawn in the plot
  const PanelView view = d.layout().panels[0];
  for (int y = view.plot.y; y < view.plot.y + view.plot.height; ++y) {
    for (int x = view.plot.x; x < view.plot.x + view.plot.width; ++x) ASSERT_EQ(c.pixel(x, y), kPictureBackground);
  }
  PictureOptions tall = bare_options();
  tall.plot_height = kMaxCanvasSide;  // plus padding: too tall for a canvas
  CanvasDraw big(tall);
  EXPECT_THROW((void)big.render(), InvalidInput);
}

TEST(CanvasDraw, DrawingIsClippedToThePlot) {
  CanvasDraw d(bare_options());
  d.draw_circle({5.0f, 2.5f}, 50.0f, DrawRole::static_geometry);  // covers the plot and beyond
  const Canvas c = d.render();
  const PixelBox plot = d.layout().panels[0].plot;
  EXPECT_EQ(c.pixel(plot.x + 3, plot.y + 3), draw_style(DrawRole::static_geometry).fill);
  EXPECT_EQ(c.pixel(plot.x - 3, plot.y + 3), kPictureBackground);           // padding, left
  EXPECT_EQ(c.pixel(plot.x + 3, plot.y + plot.height + 3), kPictureBackground);  // padding, below
}

}  // namespace
}  // namespace collide
