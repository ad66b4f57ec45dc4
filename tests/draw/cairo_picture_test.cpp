// The Cairo renderer, checked on the files it writes: PNGs read back with Cairo's PNG reader
// have the layout's size, the background colour where nothing is drawn, and each role's palette
// colour at the pixels the layout's mapping (PanelView::to_image) gives for points inside what
// was drawn (y up and y down); rounded shapes are round, translucent ones blended once, drawing
// is clipped to the plot, text inks only inside the box its measured width and the font's
// extents give. SVG parses as XML and PDF has one page, both of the layout's size. Files that
// cannot be written, sizes out of range and Cairo errors throw.
#include "support/picture_checks.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/cairo_picture.hpp>
#include <collide/draw/palette.hpp>

#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>

namespace collide {
namespace {

using test::near;
using test::near_within;
using test::over;
using test::PngImage;

PictureOptions bare_options(bool y_up = true) {
  PictureOptions o;
  o.width = 400;
  o.legend = false;
  o.world = Aabb{{0.0f, 0.0f}, {10.0f, 5.0f}};
  o.y_up = y_up;
  return o;
}

/// `picture` written as a PNG under a name of its own, and read back.
PngImage png_of(const Picture& picture, const std::string& name) {
  const std::string path = ::testing::TempDir() + name + ".png";
  save_picture(picture, path, PictureFormat::png);
  PngImage image = test::read_png(path);
  EXPECT_GT(image.width, 0) << path << " is no readable PNG";
  return image;
}

/// Pixels in [x0, x1) x [y0, y1) (clamped to the image) for which `pred` holds.
template <class Pred>
int count_in(const PngImage& image, int x0, int y0, int x1, int y1, Pred pred) {
  int n = 0;
  for (int y = std::max(y0, 0); y < std::min(y1, image.height); ++y) {
    for (int x = std::max(x0, 0); x < std::min(x1, image.width); ++x) n += pred(image.at(x, y)) ? 1 : 0;
  }
  return n;
}

/// Anti-aliased glyphs are thin: their ink is counted when within this much of the text colour.
constexpr int kTextInkTolerance = 40;

/// Darker than mid grey: text ink (kPictureText is nearly black), not the background.
bool is_ink(Color c) { return c.r + c.g + c.b < 3 * 128; }

TEST(CairoPicture, ShapesPaintTheirRoleColourWhereTheMappingPutsThem) {
  for (const bool y_up : {true, false}) {
    SCOPED_TRACE(y_up ? "y up" : "y down");
    Picture d(bare_options(y_up));
    const std::array<Vec2, 4> wall{Vec2{0.5f, 0.5f}, Vec2{3.5f, 0.5f}, Vec2{3.5f, 1.5f}, Vec2{0.5f, 1.5f}};
    d.draw_polygon(wall, 0.0f, DrawRole::static_geometry);
    d.draw_circle({7.0f, 3.0f}, 1.0f, DrawRole::body);
    d.draw_segment({0.5f, 4.0f}, {9.5f, 4.0f}, DrawRole::laser);
    d.draw_point({5.0f, 2.5f}, DrawRole::contact_point);
    const PngImage png = png_of(d, y_up ? "shapes_up" : "shapes_down");
    const PictureLayout lay = d.layout();
    ASSERT_EQ(png.width, lay.width);
    ASSERT_EQ(png.height, lay.height);
    const PanelView& view = lay.panels[0];
    auto at = [&](Vec2 world) { return png.at(view.to_image(world)); };

    EXPECT_EQ(at({2.0f, 1.0f}), draw_style(DrawRole::static_geometry).fill) << "inside the wall (opaque)";
    EXPECT_EQ(at({2.0f, 2.5f}), kPictureBackground) << "beside the wall";
    EXPECT_PRED2(near, at({7.0f, 3.0f}), over(draw_style(DrawRole::body).fill, kPictureBackground))
        << "inside the circle: its translucent fill over the background";
    EXPECT_EQ(at({7.0f, 3.0f + 1.3f}), kPictureBackground) << "outside the circle";
    EXPECT_EQ(at({7.0f, 3.0f - 1.3f}), kPictureBackground);
    EXPECT_EQ(at({5.0f, 2.5f}), draw_style(DrawRole::contact_point).stroke) << "the contact dot";
    // The laser (1.25 pixels wide, anti-aliased) covers more than half of the pixel row it
    // runs through most; four rows away is background.
    const Color laser = draw_style(DrawRole::laser).stroke;
    const Vec2 on_laser = view.to_image({5.2f, 4.0f});
    int most_covered = 255;
    for (int dy = -1; dy <= 1; ++dy) most_covered = std::min<int>(most_covered, png.at(on_laser + Vec2{0.0f, dy}).g);
    EXPECT_LT(most_covered, 255 - (255 - laser.g) / 2) << "green of the laser's pixels";
    EXPECT_EQ(png.at(on_laser + Vec2{0.0f, 4.0f}), kPictureBackground);
    // The frame: one crisp pixel just outside the plot; the padding beyond is background.
    EXPECT_EQ(png.at(view.plot.x - 1, view.plot.y + 10), kPanelFrame);
    EXPECT_EQ(png.at(view.plot.x + view.plot.width, view.plot.y + 10), kPanelFrame);
    EXPECT_EQ(png.at(view.plot.x - 3, view.plot.y + 10), kPictureBackground);
  }
}

TEST(CairoPicture, RoundedPolygonsAndCapsulesHaveRoundCorners) {
  Picture d(bare_options());
  const std::array<Vec2, 4> core{Vec2{2, 1}, Vec2{4, 1}, Vec2{4, 3}, Vec2{2, 3}};
  d.draw_polygon(core, 0.8f, DrawRole::static_geometry);
  d.draw_capsule({6, 2.5f}, {9, 2.5f}, 1.0f, DrawRole::static_geometry);
  const PngImage png = png_of(d, "rounded");
  const PanelView view = d.layout().panels[0];
  auto at = [&](Vec2 world) { return png.at(view.to_image(world)); };
  const Color fill = draw_style(DrawRole::static_geometry).fill;
  const Vec2 diagonal = glm::normalize(Vec2{1, 1});
  // Near a corner: in the rounding (0.6 from the vertex) is filled, the square corner of the
  // pushed-out box (0.78 sqrt 2 = 1.1 from the vertex, outside the radius) is not.
  EXPECT_EQ(at(Vec2{4, 3} + 0.6f * diagonal), fill);
  EXPECT_EQ(at(Vec2{4, 3} + Vec2{0.78f, 0.78f}), kPictureBackground);
  EXPECT_EQ(at({3, 3.6f}), fill);                 // the edge pushed out by the radius
  EXPECT_EQ(at({3, 3.95f}), kPictureBackground);  // and no further
  // The capsule: its end caps are round.
  EXPECT_EQ(at({9.8f, 2.5f}), fill);
  EXPECT_EQ(at({9.75f, 3.35f}), kPictureBackground);
  EXPECT_EQ(at({7.5f, 3.3f}), fill);
  EXPECT_EQ(at({5.2f, 2.5f}), fill);
  EXPECT_EQ(at({4.9f, 2.5f}), kPictureBackground);  // between the box and the capsule
}

// A translucent rounded shape is blended once at every pixel: no darker seams where its edges
// and the arcs at its vertices meet.
TEST(CairoPicture, TranslucentShapesHaveNoSeams) {
  Picture d(bare_options());
  const std::array<Vec2, 3> tri{Vec2{2, 1}, Vec2{8, 1}, Vec2{5, 4}};
  d.draw_polygon(tri, 0.5f, DrawRole::minkowski);
  const PngImage png = png_of(d, "seams");
  const PanelView view = d.layout().panels[0];
  const Color expected = over(draw_style(DrawRole::minkowski).fill, kPictureBackground);
  // Rows through the interior and the pushed-out bottom edge, away from the outline.
  std::set<std::uint32_t> colours;
  for (float x = 3.0f; x <= 7.0f; x += 0.05f) {
    for (const float y : {0.75f, 1.0f, 1.5f, 2.0f}) {
      const Color p = png.at(view.to_image({x, y}));
      colours.insert(static_cast<std::uint32_t>(p.r) << 16 | static_cast<std::uint32_t>(p.g) << 8 | p.b);
      EXPECT_PRED2(near, p, expected) << x << ", " << y;
    }
  }
  EXPECT_EQ(colours.size(), 1u);
}

TEST(CairoPicture, DrawingIsClippedToThePlot) {
  Picture d(bare_options());
  d.draw_circle({5.0f, 2.5f}, 50.0f, DrawRole::static_geometry);  // covers the plot and beyond
  const PngImage png = png_of(d, "clipped");
  const PixelBox plot = d.layout().panels[0].plot;
  const Color fill = draw_style(DrawRole::static_geometry).fill;
  EXPECT_EQ(count_in(png, plot.x, plot.y, plot.x + plot.width, plot.y + plot.height, [&](Color c) { return c == fill; }),
            plot.width * plot.height);
  EXPECT_EQ(count_in(png, 0, 0, png.width, png.height, [&](Color c) { return c == fill; }), plot.width * plot.height);
}

TEST(CairoPicture, ALabelInksOnlyInsideItsBox) {
  PictureOptions o = bare_options();
  Picture d(o);
  const std::string text = "t = 0.25";
  d.draw_label({5.0f, 2.5f}, text, DrawRole::highlight);
  const PngImage png = png_of(d, "label");
  const PictureLayout lay = d.layout();
  const PanelView& view = lay.panels[0];
  const test::FontCheck font(lay.font_size);
  // The box: from the baseline's start kLabelOffset right of and above the anchor, as wide as
  // the text's advance and as tall as the font's extents, grown by the halo and one pixel of
  // anti-aliasing.
  const Vec2 origin = view.to_image({5.0f, 2.5f}) + Vec2{kLabelOffset, -kLabelOffset};
  const double grow = 0.5 * kLabelHaloWidth + 1.0;
  const int x0 = static_cast<int>(std::floor(origin.x - grow));
  const int x1 = static_cast<int>(std::ceil(origin.x + font.width(text) + grow));
  const int y0 = static_cast<int>(std::floor(origin.y - font.ascent - grow));
  const int y1 = static_cast<int>(std::ceil(origin.y + font.descent + grow));
  for (int y = view.plot.y; y < view.plot.y + view.plot.height; ++y) {
    for (int x = view.plot.x; x < view.plot.x + view.plot.width; ++x) {
      if (x >= x0 && x < x1 && y >= y0 && y < y1) continue;
      ASSERT_EQ(png.at(x, y), kPictureBackground) << "pixel " << x << ", " << y << " outside the label's box";
    }
  }
  const Color ink = draw_style(DrawRole::highlight).stroke;
  EXPECT_GT(count_in(png, x0, y0, x1, y1, [&](Color c) { return near_within(c, ink, kTextInkTolerance); }), 20) << "the text is drawn";
  // It spans its measured width: ink in the first and in the last sixth of the box.
  const int sixth = (x1 - x0) / 6;
  EXPECT_GT(count_in(png, x0, y0, x0 + sixth, y1, [&](Color c) { return near_within(c, ink, kTextInkTolerance); }), 0);
  EXPECT_GT(count_in(png, x1 - sixth, y0, x1, y1, [&](Color c) { return near_within(c, ink, kTextInkTolerance); }), 0);
}

TEST(CairoPicture, TitleLegendAndPanelTitlesAreDrawnWhereTheLayoutPutsThem) {
  PictureOptions o;
  o.width = 500;
  o.title = "a title";
  Picture d(o);
  d.begin_panel("left");
  d.draw_circle({0, 0}, 1, DrawRole::shape_a);
  d.begin_panel("right");
  d.draw_circle({0, 0}, 1, DrawRole::shape_b);
  d.draw_segment({0, 0}, {1, 0}, DrawRole::laser);
  const PngImage png = png_of(d, "titled");
  const PictureLayout lay = d.layout();
  ASSERT_EQ(png.width, lay.width);
  ASSERT_EQ(png.height, lay.height);
  const test::FontCheck font(lay.font_size);
  // Text inks its box (the baseline's start, the measured advance, the font's extents) and
  // nothing right of it on its line.
  auto check_text = [&](Vec2 origin, const std::string& text) {
    SCOPED_TRACE(text);
    const int x0 = static_cast<int>(std::floor(origin.x)) - 1;
    const int x1 = static_cast<int>(std::ceil(origin.x + font.width(text))) + 1;
    const int y0 = static_cast<int>(std::floor(origin.y - font.ascent));
    const int y1 = static_cast<int>(std::ceil(origin.y + font.descent));
    EXPECT_GT(count_in(png, x0, y0, x1, y1, is_ink), 5 * static_cast<int>(text.size()));
    EXPECT_EQ(count_in(png, x1, y0, x1 + static_cast<int>(font.ascent), y1, is_ink), 0);
  };
  check_text(lay.title_origin, lay.title);
  for (const PanelView& p : lay.panels) check_text(p.title_origin, p.title);
  ASSERT_EQ(lay.legend.size(), 3u);
  for (const LegendEntry& e : lay.legend) {
    check_text(e.text_origin, to_string(e.role));
    const Color centre = png.at(e.swatch.x + e.swatch.width / 2, e.swatch.y + e.swatch.height / 2);
    const DrawStyle& style = draw_style(e.role);
    if (style.swatch == Swatch::solid) {
      EXPECT_PRED2(near, centre, over(style.fill, kPictureBackground)) << to_string(e.role);
    } else {  // the laser's line through the middle of its swatch
      EXPECT_NE(centre, kPictureBackground) << to_string(e.role);
    }
  }
}

TEST(CairoPicture, SvgAndPdfAreOfTheLayoutsSize) {
  Picture d(bare_options());
  d.set_title("vector");
  d.draw_circle({5.0f, 2.5f}, 1.0f, DrawRole::body);
  d.draw_label({5.0f, 2.5f}, "label", DrawRole::body);
  const PictureLayout lay = d.layout();
  const std::string w = std::to_string(lay.width), h = std::to_string(lay.height);

  const std::string svg = ::testing::TempDir() + "picture.svg";
  save_picture(d, svg, PictureFormat::svg);
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_file(svg.c_str());
  ASSERT_TRUE(parsed) << parsed.description();
  const pugi::xml_node root = doc.child("svg");
  EXPECT_EQ(std::string(root.attribute("width").value()), w + "px");
  EXPECT_EQ(std::string(root.attribute("height").value()), h + "px");
  EXPECT_EQ(std::string(root.attribute("viewBox").value()), "0 0 " + w + " " + h);
  int paths = 0;
  for (pugi::xpath_node n : doc.select_nodes("//path")) paths += n.node() ? 1 : 0;
  EXPECT_GE(paths, 3) << "the frame, the circle and text glyphs";

  const std::string pdf = ::testing::TempDir() + "picture.pdf";
  save_picture(d, pdf, PictureFormat::pdf);
  std::ifstream in(pdf, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.rfind("%PDF-", 0), 0u);
  EXPECT_NE(bytes.find("/MediaBox [ 0 0 " + w + " " + h + " ]"), std::string::npos);
}

TEST(CairoPicture, UnwritableFilesAndOversizedPicturesThrowNamingThePath) {
  Picture d;
  d.draw_circle({0, 0}, 1.0f, DrawRole::body);
  for (const PictureFormat format : {PictureFormat::png, PictureFormat::svg, PictureFormat::pdf}) {
    const std::string path = "/nonexistent-dir/picture." + std::to_string(static_cast<int>(format));
    try {
      save_picture(d, path, format);
      ADD_FAILURE() << "no throw for " << path;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  PictureOptions tall = bare_options();
  tall.plot_height = kMaxPictureSide;  // plus padding: too tall
  Picture big(tall);
  const std::string path = ::testing::TempDir() + "too_tall.png";
  try {
    save_picture(big, path, PictureFormat::png);
    ADD_FAILURE() << "no throw for a picture taller than kMaxPictureSide";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxPictureSide)), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::ifstream(path).good()) << "nothing written";
}

TEST(CairoPicture, SaveDrawingPassesItsContextAndReportsErrors) {
  const std::string path = ::testing::TempDir() + "drawing.png";
  save_drawing(path, PictureFormat::png, 30, 20, [](cairo_t* cr) {
    cairo_rectangle(cr, 0, 0, 10, 20);
    set_source(cr, {10, 200, 30, 255});
    cairo_fill(cr);
  });
  const PngImage png = test::read_png(path);
  ASSERT_EQ(png.width, 30);
  ASSERT_EQ(png.height, 20);
  EXPECT_EQ(png.at(5, 10), (Color{10, 200, 30, 255}));
  EXPECT_EQ(png.at(20, 10), (Color{0, 0, 0, 255})) << "a new surface is black where nothing is drawn";
  EXPECT_THROW(save_drawing(path, PictureFormat::png, 0, 20, [](cairo_t*) {}), InvalidInput);
  EXPECT_THROW(save_drawing(path, PictureFormat::svg, 20, kMaxPictureSide + 1, [](cairo_t*) {}), InvalidInput);
  EXPECT_THROW(save_drawing(path, PictureFormat::png, 20, 20, [](cairo_t*) { throw std::logic_error("mine"); }),
               std::logic_error);
  // A context left in an error state (a restore without a save) is reported, not written.
  EXPECT_THROW(save_drawing(path, PictureFormat::png, 20, 20, [](cairo_t* cr) { cairo_restore(cr); }),
               std::runtime_error);
}

// draw_picture draws on any context: here an image surface larger than the picture, moved by a
// translation. It paints only its own rectangle and leaves the context's state as it was.
TEST(CairoPicture, DrawsOnACallersContextAndRestoresItsState) {
  Picture d(bare_options());
  d.draw_circle({5.0f, 2.5f}, 1.0f, DrawRole::static_geometry);
  const PictureLayout lay = d.layout();
  constexpr int kOffset = 50;
  cairo_surface_t* surface =
      cairo_image_surface_create(CAIRO_FORMAT_ARGB32, lay.width + 2 * kOffset, lay.height + 2 * kOffset);
  cairo_t* cr = cairo_create(surface);
  cairo_translate(cr, kOffset, kOffset);
  cairo_set_line_width(cr, 7.0);
  cairo_set_source_rgb(cr, 0.0, 0.0, 1.0);
  draw_picture(d, cr);
  EXPECT_EQ(cairo_get_line_width(cr), 7.0);
  double r = -1, g = -1, b = -1, a = -1;
  EXPECT_EQ(cairo_pattern_get_rgba(cairo_get_source(cr), &r, &g, &b, &a), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(b, 1.0) << "the caller's source is back";
  EXPECT_EQ(cairo_status(cr), CAIRO_STATUS_SUCCESS);
  cairo_surface_flush(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  auto pixel = [&](int x, int y) { return *reinterpret_cast<const std::uint32_t*>(data + y * stride + 4 * x); };
  EXPECT_EQ(pixel(kOffset / 2, kOffset / 2), 0u) << "outside the picture: untouched (transparent)";
  EXPECT_EQ(pixel(kOffset + 2, kOffset + 2), 0xffffffffu) << "the picture's background, opaque white";
  const Vec2 centre = lay.panels[0].to_image({5.0f, 2.5f}) + Vec2{kOffset, kOffset};
  const Color fill = draw_style(DrawRole::static_geometry).fill;
  EXPECT_EQ(pixel(static_cast<int>(centre.x), static_cast<int>(centre.y)),
            0xff000000u | std::uint32_t{fill.r} << 16 | std::uint32_t{fill.g} << 8 | fill.b);
  cairo_destroy(cr);
  cairo_surface_destroy(surface);
}

TEST(CairoPicture, IllFormedTextIsDrawnWithoutCairoErrors) {
  PictureOptions o = bare_options();
  o.title = "bad \xff\xfe bytes \xed\xa0\x80 and \x01 controls \xef\xbf\xbe";
  Picture d(o);
  d.begin_panel("\xc3");
  d.draw_label({5.0f, 2.5f}, "\xe2\x82 cut", DrawRole::laser);
  const PngImage png = png_of(d, "ill_formed");  // Cairo refuses invalid UTF-8 with an error
  EXPECT_EQ(png.width, o.width);
}

}  // namespace
}  // namespace collide
