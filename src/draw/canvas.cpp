#include <collide/draw/canvas.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Pixel rows/columns whose centres can lie in [lo, hi], clipped to [0, n).
void pixel_range(float lo, float hi, int n, int& first, int& last) noexcept {
  if (!(lo <= hi)) {  // empty, or NaN: draw nothing
    first = 0;
    last = -1;
    return;
  }
  const float limit = static_cast<float>(n) + 1.0f;  // clamp before converting: no int overflow
  first = std::max(0, static_cast<int>(std::floor(std::clamp(lo, -1.0f, limit) - 0.5f)));
  last = std::min(n - 1, static_cast<int>(std::ceil(std::clamp(hi, -1.0f, limit) - 0.5f)));
}

/// Clips segment a-b to the box [lo, hi] (Liang-Barsky 1984). False when nothing is left.
bool clip_segment(Vec2& a, Vec2& b, Vec2 lo, Vec2 hi) noexcept {
  float t0 = 0.0f, t1 = 1.0f;
  const Vec2 d = b - a;
  for (int axis = 0; axis < 2; ++axis) {
    for (const float bound : {lo[axis], hi[axis]}) {
      const bool is_lo = bound == lo[axis];
      const float p = is_lo ? -d[axis] : d[axis];
      const float q = is_lo ? a[axis] - bound : bound - a[axis];
      if (p == 0.0f) {
        if (q < 0.0f) return false;
        continue;
      }
      const float t = q / p;
      if (p < 0.0f) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
  }
  if (!(t0 <= t1)) return false;
  const Vec2 start = a;
  a = start + t0 * d;
  b = start + t1 * d;
  return true;
}

}  // namespace

Canvas::Canvas(int width, int height, Color background) : width_(width), height_(height) {
  if (width < 1 || width > kMaxCanvasSide || height < 1 || height > kMaxCanvasSide) {
    throw InvalidInput("canvas size " + std::to_string(width) + " x " + std::to_string(height) +
                       ": each side must be in [1, " + std::to_string(kMaxCanvasSide) + "]");
  }
  pixels_.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4);
  for (std::size_t i = 0; i < pixels_.size(); i += 4) {
    pixels_[i] = background.r;
    pixels_[i + 1] = background.g;
    pixels_[i + 2] = background.b;
    pixels_[i + 3] = background.a;
  }
}

Color Canvas::pixel(int x, int y) const noexcept {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)) * 4;
  return {pixels_[i], pixels_[i + 1], pixels_[i + 2], pixels_[i + 3]};
}

// Source-over compositing in 8 bits: out = src * a + dst * (1 - a).
void Canvas::blend(int x, int y, Color c) noexcept {
  const std::size_t i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)) * 4;
  if (c.a == 255) {
    pixels_[i] = c.r;
    pixels_[i + 1] = c.g;
    pixels_[i + 2] = c.b;
    pixels_[i + 3] = 255;
    return;
  }
  const unsigned a = c.a;
  auto mix = [a](std::uint8_t src, std::uint8_t dst) {
    return static_cast<std::uint8_t>((src * a + dst * (255u - a) + 127u) / 255u);
  };
  pixels_[i] = mix(c.r, pixels_[i]);
  pixels_[i + 1] = mix(c.g, pixels_[i + 1]);
  pixels_[i + 2] = mix(c.b, pixels_[i + 2]);
  pixels_[i + 3] = static_cast<std::uint8_t>(a + pixels_[i + 3] * (255u - a) / 255u);
}

void Canvas::fill_triangle(Vec2 a, Vec2 b, Vec2 c, Color color) noexcept {
  if (cross(b - a, c - a) < 0.0f) std::swap(b, c);  // counter-clockwise in x-right, y-down terms
  int x0, x1, y0, y1;
  pixel_range(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), width_, x0, x1);
  pixel_range(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), height_, y0, y1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Vec2 p{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
      if (cross(b - a, p - a) >= 0.0f && cross(c - b, p - b) >= 0.0f && cross(a - c, p - c) >= 0.0f) {
        blend(x, y, color);
      }
    }
  }
}

void Canvas::draw_line(Vec2 a, Vec2 b, Color color, float width) noexcept {
  const float r = 0.5f * std::max(width, 1.0f);
  // Clip first, so far-away ends cost nothing and keep float precision.
  const Vec2 margin(r + 1.0f);
  if (!clip_segment(a, b, -margin, Vec2(static_cast<float>(width_), static_cast<float>(height_)) + margin)) return;
  int x0, x1, y0, y1;
  pixel_range(std::min(a.x, b.x) - r, std::max(a.x, b.x) + r, width_, x0, x1);
  pixel_range(std::min(a.y, b.y) - r, std::max(a.y, b.y) + r, height_, y0, y1);
  const Vec2 d = b - a;
  const float dd = dot(d, d);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Vec2 p{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
      const float t = dd > 0.0f ? std::clamp(dot(p - a, d) / dd, 0.0f, 1.0f) : 0.0f;
      if (distance_squared(p, a + t * d) <= r * r) blend(x, y, color);
    }
  }
}

void Canvas::fill_circle(Vec2 center, float radius, Color color) noexcept {
  int x0, x1, y0, y1;
  pixel_range(center.x - radius, center.x + radius, width_, x0, x1);
  pixel_range(center.y - radius, center.y + radius, height_, y0, y1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Vec2 p{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
      if (distance_squared(p, center) <= radius * radius) blend(x, y, color);
    }
  }
}

}  // namespace collide
