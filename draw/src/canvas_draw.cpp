#include <collide/draw/canvas_draw.hpp>

#include <collide/draw/bitmap_font.hpp>
#include <collide/draw/palette.hpp>

#include <array>
#include <cmath>
#include <optional>

namespace collide {
namespace {

class CanvasWriter final : public PixelSink {
 public:
  std::optional<Canvas> canvas;

  void begin(const PictureLayout& layout) override {
    canvas.emplace(layout.width, layout.height, kPictureBackground);  // throws when too large
    scale_ = layout.text_scale;
    if (!layout.title.empty()) draw_text(*canvas, layout.title_x, layout.title_y, layout.title, kPictureText, scale_);
  }

  void begin_panel(const PanelView& view) override {
    const PixelBox& b = view.plot;
    // A 1-pixel frame just outside the plot area.
    canvas->fill_rect(b.x - 1, b.y - 1, b.width + 2, 1, kPanelFrame);
    canvas->fill_rect(b.x - 1, b.y + b.height, b.width + 2, 1, kPanelFrame);
    canvas->fill_rect(b.x - 1, b.y, 1, b.height, kPanelFrame);
    canvas->fill_rect(b.x + b.width, b.y, 1, b.height, kPanelFrame);
    if (!view.title.empty()) draw_text(*canvas, b.x, b.y - kLineAdvance * scale_, view.title, kPictureText, scale_);
    canvas->set_clip(b);
  }
  void end_panel() override { canvas->reset_clip(); }
  void begin_legend() override {}
  void end_legend() override {}

  void polygon(std::span<const Vec2> v, float radius, DrawRole role) override {
    const DrawStyle& s = draw_style(role);
    canvas->fill_convex(v, radius, s.fill, s.stroke, s.stroke_width);
  }
  void circle(Vec2 c, float radius, DrawRole role) override { polygon({&c, 1}, radius, role); }
  void capsule(Vec2 a, Vec2 b, float radius, DrawRole role) override {
    const std::array<Vec2, 2> ends{a, b};
    polygon(ends, radius, role);
  }

  void segment(Vec2 a, Vec2 b, DrawRole role) override {
    const DrawStyle& s = draw_style(role);
    line(a, b, s.stroke, s.stroke_width, s.dashed);
  }

  void arrow(const ArrowPixels& a, DrawRole role) override {
    const DrawStyle& s = draw_style(role);
    line(a.from, a.shaft_end, s.stroke, s.stroke_width, s.dashed);
    const std::array<Vec2, 3> head{a.head_left, a.tip, a.head_right};
    canvas->fill_convex(head, 0.0f, s.stroke, s.stroke, s.stroke_width);
  }

  void point(Vec2 p, DrawRole role) override {
    const DrawStyle& s = draw_style(role);
    if (s.marker == PointMarker::cross) {
      line(p - Vec2{s.point_size, 0.0f}, p + Vec2{s.point_size, 0.0f}, s.stroke, s.stroke_width, false);
      line(p - Vec2{0.0f, s.point_size}, p + Vec2{0.0f, s.point_size}, s.stroke, s.stroke_width, false);
      return;
    }
    canvas->fill_convex({&p, 1}, s.point_size, s.stroke);
  }

  void label(Vec2 top_left, std::string_view text, DrawRole role) override {
    const int x = static_cast<int>(std::lround(top_left.x));
    const int y = static_cast<int>(std::lround(top_left.y));
    // The halo: the text stamped one pixel away in each of 8 directions, in the background colour.
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx != 0 || dy != 0) draw_text(*canvas, x + dx, y + dy, text, kPictureBackground, scale_);
      }
    }
    draw_text(*canvas, x, y, text, draw_style(role).stroke, scale_);
  }

  void text(int x, int y, std::string_view text) override {
    draw_text(*canvas, x, y, text, kPictureText, scale_);
  }

  void end() override {}

 private:
  /// A line `width` pixels wide with round ends; dashed: pieces of kDashLength with gaps of
  /// the same length, starting with a dash at `a`.
  void line(Vec2 a, Vec2 b, Color color, float width, bool dashed) {
    const float len = distance(a, b);
    if (!dashed || !(len > kDashLength)) {
      const std::array<Vec2, 2> ends{a, b};
      canvas->fill_convex(ends, 0.5f * width, color);
      return;
    }
    const Vec2 dir = (b - a) / len;
    for (float s = 0.0f; s < len; s += 2.0f * kDashLength) {
      const std::array<Vec2, 2> dash{a + s * dir, a + std::min(s + kDashLength, len) * dir};
      canvas->fill_convex(dash, 0.5f * width, color);
    }
  }

  int scale_ = 1;
};

}  // namespace

Canvas render_canvas(const Picture& picture) {
  CanvasWriter writer;
  picture.replay(writer);
  return std::move(*writer.canvas);
}

}  // namespace collide
