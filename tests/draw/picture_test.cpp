// Picture: what it records and how it lays it out, checked without drawing: replayed to a
// RecordingSink, one call per DrawDebug call with its role, in order, at the world -> image
// mapping worked out analytically from picture.hpp's rules (y up and y down); the legend lists
// exactly the roles drawn, its entries and the title fit the width as Cairo measures their text
// (measured here independently); text is made valid UTF-8; bad calls and options are refused.
#include "support/picture_checks.hpp"
#include "support/test_util.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/palette.hpp>
#include <collide/draw/picture.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::RecordingSink;
using test::SinkCall;

RecordingSink replayed(const Picture& picture) {
  RecordingSink sink;
  picture.replay(sink);
  return sink;
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

/// Mapped coordinates are floats of a few hundred pixels.
constexpr float kPixelTolerance = 1e-3f;

TEST(Picture, OneCallPerDrawInOrderWithItsRole) {
  Picture d(bare_options());
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
  const RecordingSink sink = replayed(d);
  ASSERT_EQ(sink.layout.panels.size(), 1u);
  const PanelView& view = sink.layout.panels[0];
  const std::vector<SinkCall> calls = sink.in_panel(0);
  using K = SinkCall::Kind;
  const std::vector<std::pair<K, DrawRole>> expected = {
      {K::polygon, DrawRole::static_geometry}, {K::circle, DrawRole::body},        {K::capsule, DrawRole::fast_body},
      {K::segment, DrawRole::laser},           {K::arrow, DrawRole::contact_normal}, {K::point, DrawRole::contact_point},
      {K::point, DrawRole::origin},            {K::polygon, DrawRole::minkowski},  {K::label, DrawRole::shape_a}};
  ASSERT_EQ(calls.size(), expected.size());
  for (size_t i = 0; i < calls.size(); ++i) {
    EXPECT_EQ(calls[i].kind, expected[i].first) << i;
    EXPECT_EQ(calls[i].role, expected[i].second) << i;
  }
  // Every point mapped by the layout's view; radii scaled to pixels.
  for (size_t i = 0; i < tri.size(); ++i) EXPECT_VEC2_NEAR(calls[7].points[i], view.to_image(tri[i]), kPixelTolerance);
  EXPECT_NEAR(calls[7].radius, 0.25f * view.scale, kPixelTolerance);
  EXPECT_NEAR(calls[1].radius, 1.0f * view.scale, kPixelTolerance);
  EXPECT_VEC2_NEAR(calls[2].points[1], view.to_image({3, 6}), kPixelTolerance);
  // The arrow ends at its tip; its head is kArrowHeadLength long (the arrow is longer than 2 heads).
  ASSERT_GT(view.scale * std::sqrt(2.0f), 2.0f * kArrowHeadLength);
  EXPECT_VEC2_NEAR(calls[4].points[2], view.to_image({3, 3}), kPixelTolerance);
  EXPECT_NEAR(distance(calls[4].points[1], calls[4].points[2]), kArrowHeadLength, kPixelTolerance);
  // The label: its text, and its baseline kLabelOffset right of and above the anchor.
  EXPECT_EQ(calls[8].text, "A & B");
  EXPECT_VEC2_NEAR(calls[8].points[0], (view.to_image({1, 1}) + Vec2{kLabelOffset, -kLabelOffset}), kPixelTolerance);
}

TEST(Picture, ShapesLandWhereTheMappingSaysYUpAndYDown) {
  for (const bool y_up : {true, false}) {
    PictureOptions o = bare_options();
    o.world = Aabb{{0.0f, 0.0f}, {10.0f, 5.0f}};
    o.y_up = y_up;
    Picture d(o);
    d.draw_circle({2.0f, 1.0f}, 0.5f, DrawRole::body);
    d.draw_circle({10.0f, 5.0f}, 0.25f, DrawRole::body);  // the world's top-right corner
    const Plot plot = single_plot(o, 0.5f);
    const float scale = std::min(plot.w / 10.0f, plot.h / 5.0f);
    const std::vector<SinkCall> calls = replayed(d).in_panel(0);
    ASSERT_EQ(calls.size(), 2u);
    const Vec2 c{plot.x + 0.5f * plot.w + scale * (2.0f - 5.0f),
                 plot.y + 0.5f * plot.h + (y_up ? -1.0f : 1.0f) * scale * (1.0f - 2.5f)};
    SCOPED_TRACE(y_up ? "y up" : "y down");
    EXPECT_VEC2_NEAR(calls[0].points[0], c, kPixelTolerance);
    EXPECT_NEAR(calls[0].radius, 0.5f * scale, kPixelTolerance);
    // The aspect matches the plot, so the world's corner is the plot's corner: top-right when
    // y is up, bottom-right when it is down.
    EXPECT_VEC2_NEAR(calls[1].points[0], (Vec2{plot.x + plot.w, y_up ? plot.y : plot.y + plot.h}), kPixelTolerance);
    const PanelView view = d.layout().panels[0];
    EXPECT_EQ(view.plot, (PixelBox{static_cast<int>(plot.x), static_cast<int>(plot.y), static_cast<int>(plot.w),
                                   static_cast<int>(plot.h)}));
    EXPECT_VEC2_NEAR(view.to_image({2.0f, 1.0f}), c, kPixelTolerance);
  }
}

TEST(Picture, AutoFitCentresTheContentWithItsMargin) {
  PictureOptions o = bare_options();
  o.margin = 0.1f;
  Picture d(o);
  d.draw_circle({100.0f, 50.0f}, 10.0f, DrawRole::body);
  // Content [90, 110] x [40, 60], margin 0.1 * 20 on every side: a 24-unit square world.
  const Plot plot = single_plot(o, 1.0f);
  const float scale = std::min(plot.w, plot.h) / 24.0f;
  const std::vector<SinkCall> calls = replayed(d).in_panel(0);
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_VEC2_NEAR(calls[0].points[0], (Vec2{plot.x + 0.5f * plot.w, plot.y + 0.5f * plot.h}), kPixelTolerance);
  EXPECT_NEAR(calls[0].radius, 10.0f * scale, kPixelTolerance);
}

TEST(Picture, PanelsSitSideBySideEachFittedToItsOwnContentUnderItsTitle) {
  PictureOptions o = bare_options();
  o.width = 600;
  Picture d(o);
  d.begin_panel("world space");
  d.draw_circle({0.0f, 0.0f}, 1.0f, DrawRole::shape_a);
  d.begin_panel("configuration space");
  d.draw_circle({1000.0f, -1000.0f}, 5.0f, DrawRole::minkowski);
  const RecordingSink sink = replayed(d);
  const PictureLayout& lay = sink.layout;
  ASSERT_EQ(lay.panels.size(), 2u);
  const test::FontCheck font(lay.font_size);
  for (int i = 0; i < 2; ++i) {
    const PanelView& view = lay.panels[static_cast<size_t>(i)];
    const PixelBox& b = view.plot;
    const std::vector<SinkCall> calls = sink.in_panel(i);
    ASSERT_EQ(calls.size(), 1u);
    EXPECT_VEC2_NEAR(calls[0].points[0],
                     (Vec2{b.x + 0.5f * static_cast<float>(b.width), b.y + 0.5f * static_cast<float>(b.height)}),
                     kPixelTolerance);
    // The title: over the plot's left edge, its descenders above the plot and its ascent below
    // the top padding.
    EXPECT_EQ(view.title, i == 0 ? "world space" : "configuration space");
    EXPECT_FLOAT_EQ(view.title_origin.x, static_cast<float>(b.x));
    EXPECT_LE(view.title_origin.y + font.descent, b.y + 0.5);
    EXPECT_GE(view.title_origin.y - font.ascent, kPicturePadding * o.text_scale - 0.5);
    EXPECT_LE(font.width(view.title), b.width);
  }
  // Side by side, in order, not overlapping, top-aligned.
  EXPECT_GT(lay.panels[1].plot.x, lay.panels[0].plot.x + lay.panels[0].plot.width);
  EXPECT_EQ(lay.panels[0].plot.y, lay.panels[1].plot.y);
}

TEST(Picture, LegendListsExactlyTheRolesDrawnInRoleOrderWithTheirSwatches) {
  PictureOptions o;
  o.title = "three things";
  Picture d(o);
  d.draw_label({0, 0}, "hello", DrawRole::highlight);
  d.draw_point({0, 0}, DrawRole::origin);
  d.draw_segment({0, 0}, {1, 1}, DrawRole::laser);
  d.draw_circle({1, 1}, 0.5f, DrawRole::body);
  d.draw_circle({1, 1}, -0.5f, DrawRole::sensor);  // skipped: not drawn, not listed
  const std::vector<DrawRole> roles = {DrawRole::body, DrawRole::laser, DrawRole::origin, DrawRole::highlight};
  EXPECT_EQ(d.roles_drawn(), roles);
  const RecordingSink sink = replayed(d);
  std::vector<DrawRole> listed;
  for (const LegendEntry& e : sink.layout.legend) listed.push_back(e.role);
  EXPECT_EQ(listed, roles);
  // Outside the panel: per entry its swatch (the role's kind of swatch) then its name.
  std::vector<SinkCall> legend;
  for (const SinkCall& c : sink.calls) {
    if (c.panel < 0) legend.push_back(c);
  }
  using K = SinkCall::Kind;
  const std::vector<K> kinds = {K::polygon, K::text, K::segment, K::text, K::point, K::text, K::polygon, K::text};
  ASSERT_EQ(legend.size(), kinds.size());
  for (size_t i = 0; i < legend.size(); ++i) {
    EXPECT_EQ(legend[i].kind, kinds[i]) << i;
    const LegendEntry& e = sink.layout.legend[i / 2];
    if (i % 2 == 0) {
      EXPECT_EQ(legend[i].role, e.role);
      for (const Vec2 p : legend[i].points) {  // the swatch's drawing stays in its box
        EXPECT_GE(p.x, e.swatch.x);
        EXPECT_LE(p.x, e.swatch.x + e.swatch.width);
        EXPECT_GE(p.y, e.swatch.y);
        EXPECT_LE(p.y, e.swatch.y + e.swatch.height);
      }
    } else {
      EXPECT_EQ(legend[i].text, to_string(e.role));
      EXPECT_VEC2_NEAR(legend[i].points[0], e.text_origin, 0.0f);
    }
  }
  EXPECT_EQ(sink.layout.title, "three things  [1 bad draw call skipped]");
}

TEST(Picture, LegendEntriesWrapWithinTheWidthWithoutOverlapping) {
  PictureOptions o;
  o.width = 320;
  Picture d(o);
  for (int r = 0; r < kDrawRoleCount; ++r) d.draw_point({static_cast<float>(r), 0.0f}, static_cast<DrawRole>(r));
  const PictureLayout lay = d.layout();
  ASSERT_EQ(lay.legend.size(), static_cast<size_t>(kDrawRoleCount));
  const test::FontCheck font(lay.font_size);
  const float pad = static_cast<float>(kPicturePadding * o.text_scale);
  const float plot_bottom = static_cast<float>(lay.panels[0].plot.y + lay.panels[0].plot.height);
  int rows = 1;
  for (size_t i = 0; i < lay.legend.size(); ++i) {
    const LegendEntry& e = lay.legend[i];
    const double text_width = font.width(to_string(e.role));
    EXPECT_NEAR(e.text_width, text_width, 0.01) << to_string(e.role);
    EXPECT_GE(e.swatch.x, pad);
    EXPECT_LE(e.text_origin.x + text_width, o.width - pad) << to_string(e.role) << " overflows";
    EXPECT_GT(e.text_origin.x, e.swatch.x + e.swatch.width) << "the name starts after its swatch";
    EXPECT_GE(e.text_origin.y - font.ascent, plot_bottom) << "below the plot";
    EXPECT_LE(e.text_origin.y + font.descent, lay.height - pad + 0.5) << "inside the picture";
    if (i == 0) continue;
    const LegendEntry& prev = lay.legend[i - 1];
    if (e.text_origin.y == prev.text_origin.y) {
      EXPECT_GT(e.swatch.x, prev.text_origin.x + font.width(to_string(prev.role))) << "overlaps the one before";
    } else {
      ++rows;
      EXPECT_GE(e.text_origin.y - prev.text_origin.y, font.ascent + font.descent - 0.5) << "rows overlap";
      EXPECT_FLOAT_EQ(static_cast<float>(e.swatch.x), pad);
    }
  }
  EXPECT_GE(rows, 3) << "14 roles in 320 pixels take several rows";
}

TEST(Picture, LongTitlesAreCutToTheWidthWithAnEllipsis) {
  PictureOptions o = bare_options();
  o.width = 300;
  o.title = "collide run: a title much longer than three hundred pixels of fourteen-pixel text, ✓ é";
  Picture d(o);
  d.begin_panel("a panel title that is also far too long for its panel");
  d.draw_point({0, 0}, DrawRole::origin);
  const PictureLayout lay = d.layout();
  const test::FontCheck font(lay.font_size);
  const float pad = static_cast<float>(kPicturePadding * o.text_scale);
  const std::string ellipsis = "\u2026";
  ASSERT_GT(lay.title.size(), ellipsis.size());
  EXPECT_EQ(lay.title.substr(lay.title.size() - ellipsis.size()), ellipsis);
  EXPECT_EQ(o.title.rfind(lay.title.substr(0, lay.title.size() - ellipsis.size()), 0), 0u) << "a prefix";
  EXPECT_LE(font.width(lay.title), o.width - 2.0f * pad);
  EXPECT_GT(font.width(lay.title), 0.8 * (o.width - 2.0f * pad)) << "cut no shorter than needed";
  const PanelView& view = lay.panels[0];
  EXPECT_EQ(view.title.substr(view.title.size() - ellipsis.size()), ellipsis);
  EXPECT_LE(font.width(view.title), view.plot.width);
  // Cut between characters, never inside one: a title of 2-byte characters keeps whole ones.
  o.title.clear();
  for (int i = 0; i < 100; ++i) o.title += "é";
  const std::string cut = Picture(o).layout().title;
  const std::string kept = cut.substr(0, cut.size() - ellipsis.size());
  EXPECT_GT(kept.size(), 10u);
  EXPECT_EQ(kept.size() % 2, 0u);
  EXPECT_EQ(o.title.rfind(kept, 0), 0u);
  // A title that fits is kept whole.
  o.title = "short";
  EXPECT_EQ(Picture(o).layout().title, "short");
}

TEST(Picture, TextIsMadeValidUtf8) {
  PictureOptions o = bare_options();
  const std::string nasty = "a<b & c>\"d\" 'e' \x01 \xff\xfe é ✓ \xed\xa0\x80 \xe2\x82 \xef\xbf\xbf \xc0\xaf";
  o.title = nasty;
  Picture d(o);
  d.begin_panel(nasty);
  d.draw_label({0, 0}, nasty, DrawRole::laser);
  // One U+FFFD per control character, per noncharacter (U+FFFF), and per byte of an ill-formed
  // sequence (a surrogate, a cut sequence, an overlong '/').
  const std::string fffd = "\xef\xbf\xbd";
  const std::string expected = "a<b & c>\"d\" 'e' " + fffd + " " + fffd + fffd + " é ✓ " + fffd + fffd + fffd + " " +
                               fffd + fffd + " " + fffd + " " + fffd + fffd;
  PictureOptions wide = o;
  wide.width = kMaxPictureSide;  // no cut
  Picture whole(wide);
  EXPECT_EQ(whole.layout().title, expected);
  const RecordingSink sink = replayed(d);
  const std::vector<SinkCall> calls = sink.in_panel(0);
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0].text, expected);
}

TEST(Picture, BadCallsAreSkippedAndCountedNeverDrawn) {
  Picture d(bare_options());
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
  const RecordingSink sink = replayed(d);
  EXPECT_EQ(sink.layout.panels.size(), 1u);  // the empty picture still has its (empty) panel
  EXPECT_TRUE(sink.calls.empty());
  EXPECT_TRUE(sink.layout.legend.empty());
  EXPECT_NE(sink.layout.title.find("9 bad draw calls skipped"), std::string::npos) << sink.layout.title;
}

TEST(Picture, BadOptionsThrowNamingTheOption) {
  auto throws_naming = [](PictureOptions o, const std::string& word) {
    try {
      Picture d(o);
      ADD_FAILURE() << "no throw for " << word;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
    }
  };
  PictureOptions o;
  o.width = 0;
  throws_naming(o, "width");
  o = {};
  o.width = kMaxPictureSide + 1;
  throws_naming(o, "width");
  o = {};
  o.plot_height = -1;
  throws_naming(o, "plot_height");
  o = {};
  o.text_scale = 0;
  throws_naming(o, "text_scale");
  o = {};
  o.text_scale = kMaxTextScale + 1;
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
  Picture d;
  EXPECT_THROW(d.begin_panel("p", Aabb{{1, 1}, {0, 2}}), InvalidInput);
}

TEST(Picture, FarAwayGeometryIsCulledAndRaysAreClipped) {
  PictureOptions o = bare_options();
  o.world = Aabb{{0, 0}, {10, 10}};
  Picture d(o);
  d.draw_circle({1e30f, 1e30f}, 1.0f, DrawRole::body);         // off the plot: culled
  d.draw_segment({5, 5}, {3e38f, 5}, DrawRole::laser);         // a ray to "infinity": clipped
  d.draw_arrow({5, 5}, {5, 1e20f}, DrawRole::contact_normal);  // its head is off the plot
  d.draw_label({-1e6f, 5}, "far", DrawRole::laser);            // culled
  const std::vector<SinkCall> calls = replayed(d).in_panel(0);
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls[0].kind, SinkCall::Kind::segment);
  EXPECT_GT(calls[0].points[1].x, 400.0f) << "reaches past the plot";
  EXPECT_LT(calls[0].points[1].x, 400.0f + 100.0f) << "but not far";
  EXPECT_EQ(calls[1].kind, SinkCall::Kind::segment);  // drawn as its shaft only
  EXPECT_EQ(calls[1].role, DrawRole::contact_normal);
}

}  // namespace
}  // namespace collide
