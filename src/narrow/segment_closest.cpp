#include "segment_closest.hpp"

#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace collide::detail {
namespace {

[[nodiscard]] float clamp01(float x) noexcept { return std::clamp(x, 0.0f, 1.0f); }

/// closest_between_segments solves its fractions on the segments as they are while the sum of
/// their squared lengths lies in [kSegmentsSquaredMin, kSegmentsSquaredMax], else on the
/// segments scaled by a power of two to about unit length. The denominator a e - b^2 and its
/// parallel bound are fourth powers of the lengths: below the range they underflow (a capsule
/// 1e-13 wide against a triangle's edge read as parallel to it, its closest points then s = 0
/// and a level contact took the triangle's face normal: finding 26's open part), above it they
/// overflow. Inside it the bound kParallelTolerance^2 a e stays normal for any segment that is
/// not a point (longer than kRelativeTolerance of the other). The scale also multiplies the
/// offset r between the segments, and stays finite for every query kFiniteQueryRange covers:
/// the sum is 0 (no scaling) or at least the least subnormal, 2^-149, so the scale is at most
/// 2^74, and r within 2^31 becomes at most 2^105. Beyond that range (segments 1e-18 long 1e21
/// apart) r may overflow and the fractions be NaN, as the range's contract allows.
constexpr float kSegmentsSquaredMin = 0x1p-32f;
constexpr float kSegmentsSquaredMax = 0x1p40f;

}  // namespace

template <int D>
PointSegmentClosest<D> closest_on_segment(VecN<D> x, VecN<D> p, VecN<D> q) noexcept {
  const VecN<D> d = q - p;
  const float dd = dot(d, d);
  // dd > 0 also rejects NaN; a zero-length segment is its point p.
  const float t = dd > 0.0f ? clamp01(dot(x - p, d) / dd) : 0.0f;
  const VecN<D> point = p + t * d;
  return {t, point, distance_squared(x, point)};
}

template <int D>
SegmentSegmentClosest<D> closest_between_segments(VecN<D> p1, VecN<D> q1, VecN<D> p2,
                                                  VecN<D> q2) noexcept {
  VecN<D> d1 = q1 - p1;
  VecN<D> d2 = q2 - p2;
  VecN<D> r = p1 - p2;
  float a = dot(d1, d1);  // squared length of segment 1
  float e = dot(d2, d2);  // squared length of segment 2
  // The fractions are solved on the segments scaled by a power of two (exact) when their
  // lengths leave the range where the denominator below stays a normal float.
  const float sum = a + e;
  if (!(sum >= kSegmentsSquaredMin && sum <= kSegmentsSquaredMax) && sum > 0.0f &&
      sum < std::numeric_limits<float>::infinity()) [[unlikely]] {
    const float scale = std::ldexp(1.0f, -std::ilogb(sum) / 2);
    d1 *= scale;
    d2 *= scale;
    r *= scale;
    a = dot(d1, d1);
    e = dot(d2, d2);
  }
  const float f = dot(d2, r);
  // A segment shorter than this fraction of the other is a point (its direction is noise).
  const float tiny = kRelativeTolerance * kRelativeTolerance * (a + e);

  float s = 0.0f;
  float t = 0.0f;
  if (a <= tiny && e <= tiny) {
    // Both are points.
  } else if (a <= tiny) {
    t = clamp01(f / e);  // point p1 against segment 2
  } else {
    const float c = dot(d1, r);
    if (e <= tiny) {
      s = clamp01(-c / a);  // point p2 against segment 1
    } else {
      // Stationary point of the quadratic: s = (b f - c e) / (a e - b^2). The denominator is
      // a e sin^2(angle) >= 0; near zero the segments are parallel and any s works.
      const float b = dot(d1, d2);
      const float denom = a * e - b * b;
      s = denom > kParallelTolerance * kParallelTolerance * a * e ? clamp01((b * f - c * e) / denom)
                                                                 : 0.0f;
      // Best t for this s; if it leaves [0, 1], clamp it and recompute s for the clamped t.
      const float t_num = b * s + f;
      if (t_num < 0.0f) {
        t = 0.0f;
        s = clamp01(-c / a);
      } else if (t_num > e) {
        t = 1.0f;
        s = clamp01((b - c) / a);
      } else {
        t = t_num / e;
      }
    }
  }
  const VecN<D> point1 = p1 + s * (q1 - p1);
  const VecN<D> point2 = p2 + t * (q2 - p2);
  return {s, t, point1, point2, distance_squared(point1, point2)};
}

template PointSegmentClosest<2> closest_on_segment<2>(Vec2, Vec2, Vec2) noexcept;
template PointSegmentClosest<3> closest_on_segment<3>(Vec3, Vec3, Vec3) noexcept;
template SegmentSegmentClosest<2> closest_between_segments<2>(Vec2, Vec2, Vec2, Vec2) noexcept;
template SegmentSegmentClosest<3> closest_between_segments<3>(Vec3, Vec3, Vec3, Vec3) noexcept;

}  // namespace collide::detail
