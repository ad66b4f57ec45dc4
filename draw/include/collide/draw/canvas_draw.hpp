#pragma once
/// @file
/// Debug pictures rasterised on a Canvas (write them with write_png, png.hpp): the same
/// Picture as SvgDraw (panels, palette, legend, title; see picture.hpp), anti-aliased solids
/// and lines, and text in the built-in 5 x 7 bitmap font (bitmap_font.hpp) at the picture's
/// text scale. Rounded polygons and capsules are drawn as their true rounded outline.
/// Differences from the SVG: dashed outlines of solids are drawn solid (dashed lines stay
/// dashed), and labels get a 1-pixel white halo, so a label's pixels lie within one pixel of
/// its text box.

#include <collide/draw/picture.hpp>

namespace collide {

/// `picture` rasterised. Throws InvalidInput when the laid-out image is larger than
/// kMaxCanvasSide on a side (a very tall plot or a very long legend).
[[nodiscard]] Canvas render_canvas(const Picture& picture);

/// A DebugDraw that records a picture and rasterises it.
class CanvasDraw final : public Picture {
 public:
  /// Throws InvalidInput when an option is out of range (see PictureOptions).
  explicit CanvasDraw(PictureOptions options = {}) : Picture(std::move(options)) {}
  /// Everything drawn so far, rasterised; see render_canvas.
  [[nodiscard]] Canvas render() const { return render_canvas(*this); }
};

}  // namespace collide
