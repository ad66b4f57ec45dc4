#include "segment_closest.hpp"

#include <collide/core/tolerance.hpp>

#include <algorithm>

namespace collide::detail {
namespace {

[[nodiscard]] float clamp01(float x) noexcept { return std::clamp(x, 0.0f, 1.0f); }

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
  const VecN<D> d1 = q1 - p1;
  const VecN<D> d2 = q2 - p2;
  const VecN<D> r = p1 - p2;
  const float a = dot(d1, d1);  // squared length of segment 1
  const float e = dot(d2, d2);  // squared length of segment 2
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
  const VecN<D> point1 = p1 + s * d1;
  const VecN<D> point2 = p2 + t * d2;
  return {s, t, point1, point2, distance_squared(point1, point2)};
}

template PointSegmentClosest<2> closest_on_segment<2>(Vec2, Vec2, Vec2) noexcept;
template PointSegmentClosest<3> closest_on_segment<3>(Vec3, Vec3, Vec3) noexcept;
template SegmentSegmentClosest<2> closest_between_segments<2>(Vec2, Vec2, Vec2, Vec2) noexcept;
template SegmentSegmentClosest<3> closest_between_segments<3>(Vec3, Vec3, Vec3, Vec3) noexcept;

}  // namespace collide::detail
