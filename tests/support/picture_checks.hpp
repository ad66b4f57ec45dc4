#pragma once
// Checking pictures from outside the renderer (tests/draw, tests/apps): PNG files read back with
// Cairo's own PNG reader, colours composited by the textbook source-over rule, and a PixelSink
// that records what Picture::replay sends (each call's kind, role and pixel coordinates).

#include <collide/draw/palette.hpp>
#include <collide/draw/picture.hpp>

#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <ostream>
#include <string>
#include <vector>

namespace collide::test {

/// Largest difference per channel between a colour Cairo composited and the same colour
/// computed here: Cairo blends in 8-bit premultiplied steps, rounding each once or twice.
inline constexpr int kChannelTolerance = 2;

/// A PNG read back: its size and unpremultiplied pixels, row by row from the top.
struct PngImage {
  int width = 0;
  int height = 0;
  std::vector<Color> pixels;

  /// The pixel at column x, row y (in range).
  [[nodiscard]] Color at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  /// The pixel that holds image point `p` (pixels, x right, y down).
  [[nodiscard]] Color at(Vec2 p) const {
    return at(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)));
  }
};

/// Number of pixels of `image` for which `pred(Color)` holds.
template <class Pred>
int count_pixels(const PngImage& image, Pred pred) {
  int n = 0;
  for (const Color c : image.pixels) n += pred(c) ? 1 : 0;
  return n;
}

/// `path` read with cairo_image_surface_create_from_png; width 0 when it is not a readable PNG.
inline PngImage read_png(const std::string& path) {
  PngImage image;
  cairo_surface_t* surface = cairo_image_surface_create_from_png(path.c_str());
  if (cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS) {
    cairo_surface_flush(surface);
    const bool alpha = cairo_image_surface_get_format(surface) == CAIRO_FORMAT_ARGB32;
    image.width = cairo_image_surface_get_width(surface);
    image.height = cairo_image_surface_get_height(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    image.pixels.reserve(static_cast<std::size_t>(image.width) * image.height);
    for (int y = 0; y < image.height; ++y) {
      const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
      for (int x = 0; x < image.width; ++x) {
        const std::uint32_t v = row[x];  // 0xAARRGGBB in native order, premultiplied
        const unsigned a = alpha ? v >> 24 : 255u;
        auto channel = [&](int shift) {
          const unsigned c = (v >> shift) & 0xffu;
          return static_cast<std::uint8_t>(a == 0 ? 0 : (c * 255u + a / 2) / a);
        };
        image.pixels.push_back({channel(16), channel(8), channel(0), static_cast<std::uint8_t>(a)});
      }
    }
  }
  cairo_surface_destroy(surface);
  return image;
}

/// `ink` over the opaque colour `under`, by the source-over rule.
inline Color over(Color ink, Color under) {
  auto mix = [&](std::uint8_t s, std::uint8_t d) {
    return static_cast<std::uint8_t>(std::lround((s * ink.a + d * (255.0 - ink.a)) / 255.0));
  };
  return {mix(ink.r, under.r), mix(ink.g, under.g), mix(ink.b, under.b), 255};
}

/// True when every channel of `a` and `b` differs by at most `tolerance`.
inline bool near_within(Color a, Color b, int tolerance) {
  return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance &&
         std::abs(a.b - b.b) <= tolerance && std::abs(a.a - b.a) <= tolerance;
}
/// near_within kChannelTolerance (for EXPECT_PRED2).
inline bool near(Color a, Color b) { return near_within(a, b, kChannelTolerance); }

/// Font metrics and text widths measured here, with Cairo's font API directly (not through
/// collide_draw): the pictures' family at `size` pixels, metrics not hinted.
struct FontCheck {
  double ascent = 0.0, descent = 0.0;

  explicit FontCheck(double size)
      : surface_(cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1)), cr_(cairo_create(surface_)) {
    cairo_select_font_face(cr_, kPictureFontFamily, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, size);
    cairo_font_options_t* options = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
    cairo_set_font_options(cr_, options);
    cairo_font_options_destroy(options);
    cairo_font_extents_t e;
    cairo_font_extents(cr_, &e);
    ascent = e.ascent;
    descent = e.descent;
  }
  ~FontCheck() {
    cairo_destroy(cr_);
    cairo_surface_destroy(surface_);
  }
  FontCheck(const FontCheck&) = delete;
  FontCheck& operator=(const FontCheck&) = delete;

  /// Advance width of `text`, pixels.
  [[nodiscard]] double width(const std::string& text) const {
    cairo_text_extents_t e;
    cairo_text_extents(cr_, text.c_str(), &e);
    return e.x_advance;
  }

 private:
  cairo_surface_t* surface_;
  cairo_t* cr_;
};

/// What a PixelSink received, one entry per call, in order.
struct SinkCall {
  enum class Kind { polygon, circle, capsule, segment, arrow, point, label, text } kind;
  DrawRole role = DrawRole::static_geometry;
  int panel = -1;            ///< index of the panel it came in; -1: outside (the legend)
  std::vector<Vec2> points;  ///< pixels: vertices, centre, ends, (from, shaft end, tip), point, origin
  float radius = 0.0f;       ///< pixels
  std::string text;
};

/// A PixelSink that records every call.
class RecordingSink final : public PixelSink {
 public:
  PictureLayout layout;
  std::vector<SinkCall> calls;

  void begin(const PictureLayout& l) override { layout = l; }
  void begin_panel(const PanelView&) override { ++panel_; inside_ = true; }
  void end_panel() override { inside_ = false; }
  void begin_legend() override {}
  void end_legend() override {}
  void polygon(std::span<const Vec2> v, float radius, DrawRole role) override {
    add(SinkCall::Kind::polygon, role, {v.begin(), v.end()}, radius);
  }
  void circle(Vec2 c, float radius, DrawRole role) override { add(SinkCall::Kind::circle, role, {c}, radius); }
  void capsule(Vec2 a, Vec2 b, float radius, DrawRole role) override {
    add(SinkCall::Kind::capsule, role, {a, b}, radius);
  }
  void segment(Vec2 a, Vec2 b, DrawRole role) override { add(SinkCall::Kind::segment, role, {a, b}); }
  void arrow(const ArrowPixels& a, DrawRole role) override {
    add(SinkCall::Kind::arrow, role, {a.from, a.shaft_end, a.tip});
  }
  void point(Vec2 p, DrawRole role) override { add(SinkCall::Kind::point, role, {p}); }
  void label(Vec2 origin, std::string_view text, DrawRole role) override {
    add(SinkCall::Kind::label, role, {origin}, 0.0f, std::string(text));
  }
  void text(Vec2 origin, std::string_view text) override {
    add(SinkCall::Kind::text, DrawRole::static_geometry, {origin}, 0.0f, std::string(text));
  }
  void end() override {}

  /// The calls made in panel `i`, in order.
  [[nodiscard]] std::vector<SinkCall> in_panel(int i) const {
    std::vector<SinkCall> out;
    for (const SinkCall& c : calls) {
      if (c.panel == i) out.push_back(c);
    }
    return out;
  }

 private:
  void add(SinkCall::Kind kind, DrawRole role, std::vector<Vec2> points, float radius = 0.0f, std::string text = {}) {
    calls.push_back({kind, role, inside_ ? panel_ : -1, std::move(points), radius, std::move(text)});
  }
  int panel_ = -1;
  bool inside_ = false;
};

}  // namespace collide::test

namespace collide {
/// Colours in test messages (found by argument-dependent lookup).
inline std::ostream& operator<<(std::ostream& out, Color c) {
  return out << "rgba(" << int{c.r} << ", " << int{c.g} << ", " << int{c.b} << ", " << int{c.a} << ")";
}
}  // namespace collide
