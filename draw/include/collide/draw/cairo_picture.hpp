#pragma once
/// @file
/// Pictures drawn with Cairo: one renderer (CairoSink) for every output, so a PNG, an SVG and a
/// PDF of the same Picture come from the same drawing code. Strokes and fills are anti-aliased,
/// text is set in a real font (kPictureFontFamily), and the image is drawn in pixels: Cairo's
/// user space, one unit per pixel (in an SVG a CSS pixel, in a PDF a point of 1/72 inch).

#include <collide/draw/palette.hpp>
#include <collide/draw/picture.hpp>

#include <cairo.h>

#include <filesystem>
#include <functional>

namespace collide {

/// A file format pictures are written in.
enum class PictureFormat : unsigned char {
  png,  ///< 8-bit RGB raster
  svg,  ///< SVG 1.1, text as glyph outlines
  pdf,  ///< one page of the picture's size
};

/// Sets `color` as the source of `cr`.
void set_source(cairo_t* cr, Color color) noexcept;

/// The renderer of laid-out pictures: draws what Picture::replay sends on a Cairo context, in
/// the palette's styles. Leaves the context's state as it found it (save/restore around the
/// picture); errors leave the context in an error state (cairo_status), which draw_picture
/// turns into exceptions.
class CairoSink final : public PixelSink {
 public:
  /// Draws on `cr` (not owned), whose user space must be in image pixels.
  explicit CairoSink(cairo_t* cr) noexcept : cr_(cr) {}

  void begin(const PictureLayout& layout) override;
  void begin_panel(const PanelView& view) override;
  void end_panel() override;
  void begin_legend() override {}
  void end_legend() override {}
  void polygon(std::span<const Vec2> vertices, float radius, DrawRole role) override;
  void circle(Vec2 center, float radius, DrawRole role) override;
  void capsule(Vec2 a, Vec2 b, float radius, DrawRole role) override;
  void segment(Vec2 a, Vec2 b, DrawRole role) override;
  void arrow(const ArrowPixels& arrow, DrawRole role) override;
  void point(Vec2 p, DrawRole role) override;
  void label(Vec2 origin, std::string_view text, DrawRole role) override;
  void text(Vec2 origin, std::string_view text) override;
  void end() override;

 private:
  /// Fills the current path with the role's fill and strokes it with its outline.
  void paint_solid(DrawRole role);
  /// Strokes the current path as the role's line (its width and dashes).
  void stroke_line(DrawRole role, bool dashed);
  void show_text(Vec2 origin, std::string_view text);

  cairo_t* cr_;
};

/// Draws `picture` (laid out, then replayed to a CairoSink) on `cr`, whose user space must be
/// in image pixels, with the image's top-left corner at its origin. Throws std::bad_alloc when
/// Cairo runs out of memory and std::runtime_error on any other Cairo error.
void draw_picture(const Picture& picture, cairo_t* cr);

/// Makes a `width` x `height` pixel surface for `format` at `path`, calls `draw` on a context
/// for it (user space in pixels, origin top-left), and writes the file. The one writer of
/// picture files: draw_picture's pictures and anything else drawn with Cairo (the walk mesh).
/// Throws InvalidInput when a side is not in [1, kMaxPictureSide] or the file cannot be
/// written (naming the path), std::bad_alloc when Cairo runs out of memory, std::runtime_error
/// on any other Cairo error, and whatever `draw` throws.
void save_drawing(const std::filesystem::path& path, PictureFormat format, int width, int height,
                  const std::function<void(cairo_t*)>& draw);

/// Writes `picture` to `path` in `format`, at its layout's size. Throws as save_drawing (a
/// layout taller than kMaxPictureSide is InvalidInput).
void save_picture(const Picture& picture, const std::filesystem::path& path, PictureFormat format);

}  // namespace collide
