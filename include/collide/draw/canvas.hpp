#pragma once
/// @file
/// A minimal RGBA raster canvas for pictures of scenes and walk meshes: filled triangles, thick
/// lines and filled circles, with source-over alpha blending. No file format here (the library
/// proper stays glm-only); collide_io writes it as PNG.

#include <collide/core/math.hpp>

#include <cstdint>
#include <vector>

namespace collide {

/// An 8-bit RGBA colour; a = 255 is opaque.
struct Color {
  std::uint8_t r = 0, g = 0, b = 0, a = 255;
  friend constexpr bool operator==(Color, Color) noexcept = default;
};

/// Largest canvas side, pixels: keeps a mistyped size from allocating gigabytes.
inline constexpr int kMaxCanvasSide = 16384;

/// Pixels in rows, top row first. Pixel coordinates: x to the right, y down; pixel (i, j) covers
/// [i, i + 1) x [j, j + 1) and is painted when its centre (i + 0.5, j + 0.5) is inside the shape.
/// Shapes are clipped to the canvas.
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

  /// Fills the triangle (either winding), edges inclusive: pixel centres with all three edge
  /// functions of one sign (Pineda 1988).
  void fill_triangle(Vec2 a, Vec2 b, Vec2 c, Color color) noexcept;
  /// A line of `width` pixels with round caps: pixel centres within width / 2 of the segment.
  void draw_line(Vec2 a, Vec2 b, Color color, float width = 1.0f) noexcept;
  /// Pixel centres within `radius` of `center`.
  void fill_circle(Vec2 center, float radius, Color color) noexcept;

 private:
  void blend(int x, int y, Color c) noexcept;
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> pixels_;
};

}  // namespace collide
