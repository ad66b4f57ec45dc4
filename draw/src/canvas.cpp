#include <collide/draw/canvas.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Pixel rows/columns whose centres can lie in [lo, hi], clipped to [begin, end).
void pixel_range(float lo, float hi, int begin, int end, int& first, int& last) noexcept {
  if (!(lo <= hi)) {  // empty, or NaN: draw nothing
    first = 0;
    last = -1;
    return;
  }
  // Clamp before converting: no int overflow.
  const float low = static_cast<float>(begin) - 1.0f, high = static_cast<float>(end) + 1.0f;
  first = std::max(begin, static_cast<int>(std::floor(std::clamp(lo, low, high) - 0.5f)));
  last = std::min(end - 1, static_cast<int>(std::ceil(std::clamp(hi, low, high) - 0.5f)));
}

/// `c` with its alpha scaled by `coverage` in [0, 1].
Color scaled(Color c, float coverage) noexcept {
  c.a = static_cast<std::uint8_t>(std::lround(static_cast<float>(c.a) * coverage));
  return c;
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

Canvas::Canvas(int width, int height, Color background)
    : width_(width), height_(height), clip_{0, 0, width, height} {
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

void Canvas::set_clip(PixelBox box) noexcept {
  // 64-bit ends: x + width cannot overflow.
  const long long x0 = std::max<long long>(0, box.x), y0 = std::max<long long>(0, box.y);
  const long long x1 = std::min<long long>(width_, static_cast<long long>(box.x) + std::max(0, box.width));
  const long long y1 = std::min<long long>(height_, static_cast<long long>(box.y) + std::max(0, box.height));
  clip_ = {static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(std::max(0LL, x1 - x0)),
           static_cast<int>(std::max(0LL, y1 - y0))};
}

void Canvas::fill_rect(int x, int y, int w, int h, Color color) noexcept {
  const long long x0 = std::max<long long>(clip_.x, x), y0 = std::max<long long>(clip_.y, y);
  const long long x1 = std::min<long long>(clip_.x + clip_.width, static_cast<long long>(x) + w);
  const long long y1 = std::min<long long>(clip_.y + clip_.height, static_cast<long long>(y) + h);
  for (long long j = y0; j < y1; ++j) {
    for (long long i = x0; i < x1; ++i) blend(static_cast<int>(i), static_cast<int>(j), color);
  }
}

void Canvas::fill_triangle(Vec2 a, Vec2 b, Vec2 c, Color color) noexcept {
  if (cross(b - a, c - a) < 0.0f) std::swap(b, c);  // counter-clockwise in x-right, y-down terms
  int x0, x1, y0, y1;
  pixel_range(std::min({a.x, b.x, c.x}), std::max({a.x, b.x, c.x}), clip_.x, clip_.x + clip_.width, x0, x1);
  pixel_range(std::min({a.y, b.y, c.y}), std::max({a.y, b.y, c.y}), clip_.y, clip_.y + clip_.height, y0, y1);
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
  pixel_range(std::min(a.x, b.x) - r, std::max(a.x, b.x) + r, clip_.x, clip_.x + clip_.width, x0, x1);
  pixel_range(std::min(a.y, b.y) - r, std::max(a.y, b.y) + r, clip_.y, clip_.y + clip_.height, y0, y1);
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
  pixel_range(center.x - radius, center.x + radius, clip_.x, clip_.x + clip_.width, x0, x1);
  pixel_range(center.y - radius, center.y + radius, clip_.y, clip_.y + clip_.height, y0, y1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const Vec2 p{static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
      if (distance_squared(p, center) <= radius * radius) blend(x, y, color);
    }
  }
}

// Signed distance of each pixel centre to the core's convex hull (Ericson 5.1.2 per edge):
// inside, the largest edge separation (negative); outside, the distance to the nearest edge
// segment, which is always one the point lies in front of. The shape is the hull grown by
// `radius`, so the distance to its boundary is that minus the radius.
void Canvas::fill_convex(std::span<const Vec2> core, float radius, Color fill, Color stroke,
                         float stroke_width) noexcept {
  const std::size_t n = core.size();
  if (n == 0 || !(radius >= 0.0f) || !std::isfinite(radius) || !(stroke_width >= 0.0f) ||
      !std::isfinite(stroke_width)) {
    return;
  }
  Vec2 lo = core[0], hi = core[0];
  for (const Vec2 v : core) {
    if (!is_finite(v)) return;
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  const float half_stroke = stroke.a > 0 ? 0.5f * stroke_width : 0.0f;
  if (fill.a == 0 && half_stroke == 0.0f) return;
  // Orientation: +1 counter-clockwise in (x right, y down) numbers, -1 clockwise, 0 for a core
  // with no area (a point, a segment, or collinear points), which has no inside.
  float twice_area = 0.0f;
  for (std::size_t i = 0; i < n; ++i) twice_area += cross(core[i], core[(i + 1) % n]);
  const float extent = std::max(hi.x - lo.x, hi.y - lo.y);
  const float side = n >= 3 && std::fabs(twice_area) > kDegenerateAreaTolerance * extent * extent
                         ? (twice_area > 0.0f ? 1.0f : -1.0f)
                         : 0.0f;
  auto signed_distance = [&](Vec2 p) {
    float max_separation = -INFINITY;
    float min_dist2 = INFINITY;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = core[i];
      const Vec2 e = core[(i + 1) % n] - a;
      const float ee = dot(e, e);
      if (side != 0.0f && ee > 0.0f) {
        // Outward normal: right of the edge for counter-clockwise, left for clockwise.
        const float separation = side * cross(e, p - a) * (-1.0f / std::sqrt(ee));
        max_separation = std::max(max_separation, separation);
        if (separation <= 0.0f) continue;  // the nearest point is on an edge facing p
      }
      const float t = ee > 0.0f ? std::clamp(dot(p - a, e) / ee, 0.0f, 1.0f) : 0.0f;
      min_dist2 = std::min(min_dist2, distance_squared(p, a + t * e));
    }
    return side != 0.0f && max_separation <= 0.0f ? max_separation : std::sqrt(min_dist2);
  };
  const float reach = radius + half_stroke + 1.0f;
  int x0, x1, y0, y1;
  pixel_range(lo.x - reach, hi.x + reach, clip_.x, clip_.x + clip_.width, x0, x1);
  pixel_range(lo.y - reach, hi.y + reach, clip_.y, clip_.y + clip_.height, y0, y1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const float d = signed_distance({static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f}) - radius;
      const float fill_coverage = std::clamp(0.5f - d, 0.0f, 1.0f);
      if (fill.a > 0 && fill_coverage > 0.0f) blend(x, y, scaled(fill, fill_coverage));
      const float stroke_coverage = std::clamp(half_stroke + 0.5f - std::fabs(d), 0.0f, 1.0f);
      if (half_stroke > 0.0f && stroke_coverage > 0.0f) blend(x, y, scaled(stroke, stroke_coverage));
    }
  }
}

}  // namespace collide
