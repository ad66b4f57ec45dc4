#pragma once
/// @file
/// A minimal RGBA raster canvas for pictures of scenes and walk meshes: filled triangles, thick
/// lines and filled circles, with source-over alpha blending. No file format here: png.hpp
/// writes it as PNG.

#include <collide/core/math.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// An 8-bit RGBA colour; a = 255 is opaque.
struct Color {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  friend constexpr bool operator==(Color, Color) noexcept = default;
};

/// Largest canvas side, pixels: keeps a mistyped size from allocating gigabytes.
inline constexpr int kMaxCanvasSide = 16384;

/// A rectangle of whole pixels: columns [x, x + width), rows [y, y + height).
struct PixelBox {
  int x = 0, y = 0, width = 0, height = 0;
  friend constexpr bool operator==(PixelBox, PixelBox) noexcept = default;
};

/// Pixels in rows, top row first. Pixel coordinates: x to the right, y down; pixel (i, j) covers
/// [i, i + 1) x [j, j + 1) and is painted when its centre (i + 0.5, j + 0.5) is inside the shape
/// (fill_convex instead shades its edge pixels by coverage). Shapes are clipped to the canvas and
/// to the clip box.
class Canvas {
 public:
  /// A `width` x `height` canvas filled with `background`. Throws InvalidInput when a side is
  /// not in [1, kMaxCanvasSide].
  Canvas(int width, int height, Color background = {255, 255, 255, 255});

  [[nodiscard]] int width() const noexcept { return width_; }
  [[nodiscard]] int height() const noexcept { return height_; }
  /// The pixel at column x, row y (both in range).
  [[nodiscard]] Color pixel(int x, int y) const noexcept;
  /// All pixels, 4 bytes (r, g, b, a) each, row by row from the top.
  [[nodiscard]] const std::vector<std::uint8_t>& rgba() const noexcept { return pixels_; }

  /// Restricts every later drawing to `box` (intersected with the canvas).
  void set_clip(PixelBox box) noexcept;
  /// Drawing reaches the whole canvas again.
  void reset_clip() noexcept { clip_ = {0, 0, width_, height_}; }
  /// The current clip box, inside the canvas.
  [[nodiscard]] PixelBox clip() const noexcept { return clip_; }

  /// Fills the pixels [x, x + w) x [y, y + h) (text, legend swatches).
  void fill_rect(int x, int y, int w, int h, Color color) noexcept;
  /// Fills the triangle (either winding), edges inclusive: pixel centres with all three edge
  /// functions of one sign (Pineda 1988).
  void fill_triangle(Vec2 a, Vec2 b, Vec2 c, Color color) noexcept;
  /// A line of `width` pixels with round caps: pixel centres within width / 2 of the segment.
  void draw_line(Vec2 a, Vec2 b, Color color, float width = 1.0f) noexcept;
  /// Pixel centres within `radius` of `center`.
  void fill_circle(Vec2 center, float radius, Color color) noexcept;
  /// The solid set of points within `radius` (>= 0) of the convex hull of `core`: 1 point is a
  /// disc, 2 a capsule (with radius 0: a hairline of `stroke_width`), 3 or more a convex polygon
  /// in either winding, rounded when `radius` > 0. Filled with `fill`, then its outline stroked
  /// with `stroke` in a band `stroke_width` pixels wide centred on the boundary (alpha 0 or width
  /// 0 skips either). Anti-aliased: each pixel's ink is scaled by its coverage, estimated from
  /// the signed distance d of its centre to the boundary as clamp(0.5 - d, 0, 1), so a pixel
  /// whose centre is half a pixel inside is fully painted. One pass per pixel, so translucent
  /// shapes are blended once everywhere (no seams where pieces would overlap). Cost: the
  /// bounding box's pixels times the core's size. Non-finite input draws nothing.
  void fill_convex(std::span<const Vec2> core, float radius, Color fill, Color stroke = {0, 0, 0, 0},
                   float stroke_width = 0.0f) noexcept;

 private:
  void blend(int x, int y, Color c) noexcept;
  int width_ = 0;
  int height_ = 0;
  PixelBox clip_;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace collide
