#pragma once
/// @file
/// Support functions: the only thing GJK, EPA-free distance, ray casts against the Minkowski
/// difference and shape casts need to know about a convex shape.
///
/// A `ConvexProxy` views a shape as a core point set (1 point for a circle, 2 for a capsule or
/// segment, n for a polygon) plus a radius: the shape is the core's convex hull grown by the
/// radius. GJK works on cores and applies radii after convergence, which is exact for rounded
/// shapes (van den Bergen, Collision Detection in Interactive 3D Environments, 2003, 4.3.6).

#include <collide/core/math.hpp>
#include <collide/shape/shape2d.hpp>

#include <array>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

/// A view of a convex shape's core points and radius, local space. Polygon proxies point into
/// the polygon (keep it alive); circle, capsule and segment proxies copy their 1-2 points.
class ConvexProxy {
 public:
  /// Polygon: its vertices (not copied) and its rounding radius.
  explicit ConvexProxy(const Polygon& polygon) noexcept
      : points_(polygon.vertices.data()),
        count_(polygon.count),
        radius_(polygon.radius),
        convex_outline_(true) {}
  /// Circle: its centre and radius.
  explicit ConvexProxy(const Circle& circle) noexcept
      : buffer_{circle.center, circle.center}, count_(1), radius_(circle.radius) {}
  /// Capsule: its two segment ends and radius.
  explicit ConvexProxy(const Capsule& capsule) noexcept
      : buffer_{capsule.a, capsule.b}, count_(2), radius_(capsule.radius) {}
  /// Segment: its two ends, radius 0.
  explicit ConvexProxy(const Segment& segment) noexcept
      : buffer_{segment.a, segment.b}, count_(2), radius_(0.0f) {}
  /// Any 2D shape.
  explicit ConvexProxy(const Shape2D& shape) noexcept;
  /// A raw point set (1..kMaxPolygonVertices points, not copied beyond 2) and radius.
  ConvexProxy(const Vec2* points, int count, float radius) noexcept;

  [[nodiscard]] const Vec2* points() const noexcept {
    return points_ != nullptr ? points_ : buffer_.data();
  }
  [[nodiscard]] Vec2 point(int i) const noexcept { return points()[i]; }
  [[nodiscard]] int count() const noexcept { return count_; }
  [[nodiscard]] float radius() const noexcept { return radius_; }

  /// Index of the core point farthest along `direction` (local space); ties go to the lowest
  /// index. Full scan (SIMD from kSimdSupportMinPoints points), correct for any point set and
  /// the right choice without a good starting guess; with one, on a polygon, use
  /// support_index_from.
  [[nodiscard]] int support_index(Vec2 direction) const noexcept {
    const Vec2* p = points();
#if defined(__SSE2__)
    if (count_ >= kSimdSupportMinPoints) return support_index_simd(p, count_, direction);
#endif
    int best = 0;
    float best_dot = dot(p[0], direction);
    for (int i = 1; i < count_; ++i) {
      const float d = dot(p[i], direction);
      if (d > best_dot) {
        best = i;
        best_dot = d;
      }
    }
    return best;
  }

  /// A core point farthest along `direction`, found by walking from point `start` to a
  /// neighbour while that improves: on a strictly convex outline (a polygon) the projection is
  /// unimodal around the outline, so the walk ends at the maximum and costs only the points it
  /// passes (about 3 when `start` is last iteration's answer). Ties: the first one reached.
  /// Point sets that are not a polygon's outline take the full scan.
  [[nodiscard]] int support_index_from(Vec2 direction, int start) const noexcept {
    if (!convex_outline_) return support_index(direction);
    const Vec2* p = points();
    const int n = count_;
    int i = start;
    float best = dot(p[i], direction);
    int next = i + 1 == n ? 0 : i + 1;
    float next_dot = dot(p[next], direction);
    if (next_dot > best) {  // uphill forwards
      do {
        i = next;
        best = next_dot;
        next = i + 1 == n ? 0 : i + 1;
        next_dot = dot(p[next], direction);
      } while (next_dot > best);
      return i;
    }
    int prev = i == 0 ? n - 1 : i - 1;
    float prev_dot = dot(p[prev], direction);
    while (prev_dot > best) {  // uphill backwards (or already at the top)
      i = prev;
      best = prev_dot;
      prev = i == 0 ? n - 1 : i - 1;
      prev_dot = dot(p[prev], direction);
    }
    return i;
  }

 private:
#if defined(__SSE2__)
  /// Point sets at least this big take the SIMD scan (measured: bench_narrow_distance).
  static constexpr int kSimdSupportMinPoints = 8;

  /// The scalar scan of support_index, four points at a time (SSE2): lane j keeps the best of
  /// points j, j+4, j+8... (first index on ties); the lanes are then merged without branches:
  /// the maximum, then the lowest index among the lanes that hold it.
  [[nodiscard]] static int support_index_simd(const Vec2* p, int n, Vec2 direction) noexcept {
    const __m128 dx = _mm_set1_ps(direction.x);
    const __m128 dy = _mm_set1_ps(direction.y);
    __m128 best = _mm_set1_ps(-std::numeric_limits<float>::infinity());
    __m128i best_index = _mm_setzero_si128();
    __m128i index = _mm_setr_epi32(0, 1, 2, 3);
    const __m128i four = _mm_set1_epi32(4);
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      const __m128 p01 = _mm_loadu_ps(&p[i].x);      // x0 y0 x1 y1
      const __m128 p23 = _mm_loadu_ps(&p[i + 2].x);  // x2 y2 x3 y3
      const __m128 xs = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 ys = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(3, 1, 3, 1));
      const __m128 dots = _mm_add_ps(_mm_mul_ps(xs, dx), _mm_mul_ps(ys, dy));
      const __m128i better = _mm_castps_si128(_mm_cmpgt_ps(dots, best));
      best = _mm_max_ps(dots, best);  // a NaN dot keeps the old best, as the scalar scan
      best_index =
          _mm_or_si128(_mm_and_si128(better, index), _mm_andnot_si128(better, best_index));
      index = _mm_add_epi32(index, four);
    }
    // Maximum over the lanes, broadcast to all of them.
    __m128 top = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
    top = _mm_max_ps(top, _mm_shuffle_ps(top, top, _MM_SHUFFLE(2, 3, 0, 1)));
    // Lowest index among the lanes holding it (indices < 64 fit the 16-bit minimum).
    const __m128i holds = _mm_castps_si128(_mm_cmpeq_ps(best, top));
    __m128i candidate = _mm_or_si128(_mm_and_si128(holds, best_index),
                                     _mm_andnot_si128(holds, _mm_set1_epi32(0x7fff)));
    candidate = _mm_min_epi16(candidate, _mm_shuffle_epi32(candidate, _MM_SHUFFLE(1, 0, 3, 2)));
    candidate = _mm_min_epi16(candidate, _mm_shuffle_epi32(candidate, _MM_SHUFFLE(2, 3, 0, 1)));
    int result = _mm_cvtsi128_si32(candidate) & 0x7fff;
    float result_dot = _mm_cvtss_f32(top);
    for (; i < n; ++i) {  // the last n % 4 points
      const float d = dot(p[i], direction);
      if (d > result_dot) {
        result = i;
        result_dot = d;
      }
    }
    // All dots NaN: no lane improved on -infinity; the scalar scan answers 0 then too.
    return result == 0x7fff ? 0 : result;
  }
#endif

  std::array<Vec2, 2> buffer_{};
  const Vec2* points_ = nullptr;
  int count_ = 0;
  float radius_ = 0.0f;
  bool convex_outline_ = false;  ///< points are a strictly convex counter-clockwise outline
};

}  // namespace collide
