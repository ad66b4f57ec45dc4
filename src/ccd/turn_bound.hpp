#pragma once
/// @file
/// How far a turning body's extent along a fixed direction can grow over a further time dt:
/// the per-dimension motion bound of `time_of_impact`'s conservative advancement. Internal.
///
/// A core point at r from the centre of rotation (the body's current frame) projects onto a
/// fixed direction m as f = r.m. The body turns about a fixed axis u at `rate` radians per unit
/// t (in 2D, u is the plane's normal and the turn's sign is folded into g). After a further turn
/// by alpha the point is r_par + r_perp cos(alpha) + (u x r) sin(alpha) (r_par its component
/// along u), so it projects as
///   f(alpha) = f + F (cos(alpha) - 1) + g sin(alpha),  F = r_perp.m,  g = (u x r).m
/// (in 2D r_perp = r, so F = f and this is f cos(alpha) + g sin(alpha)). With
/// 1 - alpha^2/2 <= cos(alpha) <= 1 and alpha - alpha^3/6 <= sin(alpha) <= alpha:
///   f(alpha) <= f + g alpha + max(-F, 0) alpha^2/2 + max(-g, 0) alpha^3/6,
/// a polynomial with non-negative curvature on alpha >= 0. The body's extent h = max_i f_i then
/// grows by at most U(alpha) = max_i (f_i - h + g_i alpha + ...): a maximum of convex
/// functions, convex, U(0) = 0. Unlike one rate for the whole body (turn times reach), points
/// behind the extreme one count only once the turn could bring them forward: a box whose corner
/// points at the other body gains nothing from its side corners until it has turned far, and a
/// point moving away (g < 0) counts as moving away.
///
/// Frames: in 3D the axis is fixed in the world, R(t) = exp(t w) R0, so in the body's own frame
/// it is the constant u = R0^T w / |w|, and a further turn by alpha about the world axis is the
/// same as a turn by alpha about u in body coordinates: R(t + dt) = R(t) exp(alpha u). A world
/// direction is therefore passed as m = R(t)^T m_world, and the points stay in body
/// coordinates.

#include <collide/narrow/support.hpp>
#include <collide/shape/polygon.hpp>

#include <algorithm>
#include <array>
#include <cmath>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace collide::detail {

/// The per-point terms of the bound and its evaluation, the same in 2D and 3D: for each core
/// point, f_i - h (<= 0), g_i, max(-F_i, 0) / 2 and max(-g_i, 0) / 6 (see the file comment),
/// padded with copies of point 0 up to a multiple of 4 (the SIMD width), which changes no
/// maximum.
template <int Capacity>
class TurnTerms {
 public:
  /// How fast any core point moves, per unit t: turn rate times the largest distance of a core
  /// point from the axis.
  [[nodiscard]] float speed() const noexcept { return speed_; }

  /// Upper bound of the growth of the extent after a further time dt >= 0, and a subgradient
  /// of the bound (per unit t) at dt: max over points of the polynomial above, and the slope
  /// of the one that attains it.
  [[nodiscard]] float growth(float dt, float& slope) const noexcept {
    const float alpha = rate_ * dt;
#if defined(__SSE2__)
    const __m128 al = _mm_set1_ps(alpha);
    const __m128 two = _mm_set1_ps(2.0f);
    const __m128 three = _mm_set1_ps(3.0f);
    __m128 best = _mm_set1_ps(-INFINITY);
    __m128 best_slope = _mm_setzero_ps();
    for (int i = 0; i < padded(); i += 4) {
      const __m128 g = _mm_load_ps(&g_[i]);
      const __m128 c2 = _mm_load_ps(&c2_[i]);
      const __m128 c3 = _mm_load_ps(&c3_[i]);
      const __m128 c3a = _mm_mul_ps(al, c3);
      const __m128 inner = _mm_add_ps(g, _mm_mul_ps(al, _mm_add_ps(c2, c3a)));
      const __m128 value = _mm_add_ps(_mm_load_ps(&f_[i]), _mm_mul_ps(al, inner));
      const __m128 d = _mm_add_ps(
          g, _mm_mul_ps(al, _mm_add_ps(_mm_mul_ps(two, c2), _mm_mul_ps(three, c3a))));
      // Keep the larger value and its slope (ties: the larger slope, a subgradient too).
      const __m128 gt = _mm_cmpgt_ps(value, best);
      const __m128 eq = _mm_cmpeq_ps(value, best);
      const __m128 take = _mm_or_ps(gt, _mm_and_ps(eq, _mm_cmpgt_ps(d, best_slope)));
      best = _mm_max_ps(best, value);
      best_slope = _mm_or_ps(_mm_and_ps(take, d), _mm_andnot_ps(take, best_slope));
    }
    // Merge the lanes: the maximum, then the largest slope among the lanes that hold it.
    __m128 top = _mm_max_ps(best, _mm_shuffle_ps(best, best, _MM_SHUFFLE(1, 0, 3, 2)));
    top = _mm_max_ps(top, _mm_shuffle_ps(top, top, _MM_SHUFFLE(2, 3, 0, 1)));
    const __m128 holds = _mm_cmpeq_ps(best, top);
    __m128 s = _mm_or_ps(_mm_and_ps(holds, best_slope),
                         _mm_andnot_ps(holds, _mm_set1_ps(-INFINITY)));
    s = _mm_max_ps(s, _mm_shuffle_ps(s, s, _MM_SHUFFLE(1, 0, 3, 2)));
    s = _mm_max_ps(s, _mm_shuffle_ps(s, s, _MM_SHUFFLE(2, 3, 0, 1)));
    slope = rate_ * _mm_cvtss_f32(s);
    return _mm_cvtss_f32(top);
#else
    float best = -INFINITY;
    float best_slope = 0.0f;
    for (int i = 0; i < count_; ++i) {
      const float value = f_[i] + alpha * (g_[i] + alpha * (c2_[i] + alpha * c3_[i]));
      if (value > best) {
        best = value;
        best_slope = g_[i] + alpha * (2.0f * c2_[i] + 3.0f * alpha * c3_[i]);
      }
    }
    slope = rate_ * best_slope;
    return best;
#endif
  }

 protected:
  [[nodiscard]] int padded() const noexcept { return (count_ + 3) & ~3; }

  alignas(16) std::array<float, Capacity> f_;   // f_i - h (<= 0)
  alignas(16) std::array<float, Capacity> g_;   // rate of f_i per radian at the current pose
  alignas(16) std::array<float, Capacity> c2_;  // max(-F_i, 0) / 2
  alignas(16) std::array<float, Capacity> c3_;  // max(-g_i, 0) / 6
  float rate_ = 0.0f;                           // radians per unit t, >= 0
  float speed_ = 0.0f;  // rate times the farthest distance from the axis: fastest point speed
  int count_ = 0;
};

/// The 2D bound: proxy points in the body's frame, turning by a signed angle per unit t
/// (counter-clockwise positive), about the centre of rotation.
class TurnBound2 : public TurnTerms<kMaxPolygonVertices> {
 public:
  /// Proxy `p` (core points in its local frame) turning about its local point `center` by
  /// `turn` radians per unit t.
  TurnBound2(const ConvexProxy& p, Vec2 center, float turn) noexcept
      : sign_(turn < 0.0f ? -1.0f : 1.0f) {
    rate_ = std::fabs(turn);
    count_ = p.count();
    float reach2 = 0.0f;
    for (int i = 0; i < count_; ++i) {
      x_[i] = p.point(i).x - center.x;
      y_[i] = p.point(i).y - center.y;
      reach2 = std::max(reach2, x_[i] * x_[i] + y_[i] * y_[i]);
    }
    speed_ = rate_ * std::sqrt(reach2);
    // Padding repeats the first point (a point at the centre would change the maximum when
    // every real point lies behind it).
    for (int i = count_; i < padded(); ++i) {
      x_[i] = x_[0];
      y_[i] = y_[0];
    }
  }

  /// Start from the current frame, with direction `m` (unit, the body's local frame): for
  /// each point f = r.m, g = sign * cross(r, m), the curvature terms, and f relative to the
  /// extreme point (the maximum of f). Returns that maximum: the body's extent along m from
  /// its centre of rotation (a support query along m).
  float reset(Vec2 m) noexcept {
#if defined(__SSE2__)
    const __m128 mx = _mm_set1_ps(m.x);
    const __m128 my = _mm_set1_ps(m.y);
    const __m128 sign = _mm_set1_ps(sign_);
    const __m128 zero = _mm_setzero_ps();
    const __m128 half = _mm_set1_ps(0.5f);
    const __m128 sixth = _mm_set1_ps(1.0f / 6.0f);
    __m128 top = _mm_set1_ps(-INFINITY);
    for (int i = 0; i < padded(); i += 4) {
      const __m128 x = _mm_load_ps(&x_[i]);
      const __m128 y = _mm_load_ps(&y_[i]);
      const __m128 f = _mm_add_ps(_mm_mul_ps(x, mx), _mm_mul_ps(y, my));
      const __m128 g = _mm_mul_ps(sign, _mm_sub_ps(_mm_mul_ps(x, my), _mm_mul_ps(y, mx)));
      _mm_store_ps(&f_[i], f);
      _mm_store_ps(&g_[i], g);
      _mm_store_ps(&c2_[i], _mm_mul_ps(half, _mm_max_ps(_mm_sub_ps(zero, f), zero)));
      _mm_store_ps(&c3_[i], _mm_mul_ps(sixth, _mm_max_ps(_mm_sub_ps(zero, g), zero)));
      top = _mm_max_ps(top, f);
    }
    top = _mm_max_ps(top, _mm_shuffle_ps(top, top, _MM_SHUFFLE(1, 0, 3, 2)));
    top = _mm_max_ps(top, _mm_shuffle_ps(top, top, _MM_SHUFFLE(2, 3, 0, 1)));
    for (int i = 0; i < padded(); i += 4) {
      _mm_store_ps(&f_[i], _mm_sub_ps(_mm_load_ps(&f_[i]), top));
    }
    return _mm_cvtss_f32(top);
#else
    float top = -INFINITY;
    for (int i = 0; i < count_; ++i) {
      const float f = x_[i] * m.x + y_[i] * m.y;
      const float g = sign_ * (x_[i] * m.y - y_[i] * m.x);
      f_[i] = f;
      g_[i] = g;
      c2_[i] = 0.5f * std::max(-f, 0.0f);
      c3_[i] = (1.0f / 6.0f) * std::max(-g, 0.0f);
      top = std::max(top, f);
    }
    for (int i = 0; i < count_; ++i) f_[i] -= top;
    return top;
#endif
  }

 private:
  alignas(16) std::array<float, kMaxPolygonVertices> x_;  // points from the centre, local
  alignas(16) std::array<float, kMaxPolygonVertices> y_;
  float sign_;
};

/// The 3D bound: proxy points in the body's frame, turning about a fixed axis (body frame) at
/// a constant rate, about the centre of rotation. Up to kMaxProxyPoints3 points.
class TurnBound3 : public TurnTerms<kMaxProxyPoints3> {
 public:
  /// Proxy `p` (core points in its local frame) turning about its local point `center` by the
  /// rotation vector `turn` (the body's frame: axis times radians per unit t).
  TurnBound3(const ConvexProxy3& p, Vec3 center, Vec3 turn) noexcept {
    rate_ = length(turn);
    axis_ = rate_ > 0.0f ? turn * (1.0f / rate_) : Vec3(0.0f, 0.0f, 1.0f);
    count_ = p.count();
    float arc2 = 0.0f;
    for (int i = 0; i < count_; ++i) {
      const Vec3 r = p.point(i) - center;
      x_[i] = r.x;
      y_[i] = r.y;
      z_[i] = r.z;
      arc2 = std::max(arc2, length_squared(cross(axis_, r)));
    }
    speed_ = rate_ * std::sqrt(arc2);
    for (int i = count_; i < padded(); ++i) {
      x_[i] = x_[0];
      y_[i] = y_[0];
      z_[i] = z_[0];
    }
  }

  /// As TurnBound2::reset, for direction `m` (unit, the body's local frame): f = r.m,
  /// F = r.m_perp (m_perp: m without its component along the axis), g = (u x r).m = r.(m x u).
  /// Returns the body's extent along m from its centre of rotation.
  float reset(Vec3 m) noexcept {
    const Vec3 mp = m - dot(m, axis_) * axis_;
    const Vec3 mg = cross(m, axis_);
    float top = -INFINITY;
    // Plain loops over the padded arrays: the compiler vectorises them.
    for (int i = 0; i < padded(); ++i) {
      const float f = x_[i] * m.x + y_[i] * m.y + z_[i] * m.z;
      const float shrink = x_[i] * mp.x + y_[i] * mp.y + z_[i] * mp.z;
      const float g = x_[i] * mg.x + y_[i] * mg.y + z_[i] * mg.z;
      f_[i] = f;
      g_[i] = g;
      c2_[i] = 0.5f * std::max(-shrink, 0.0f);
      c3_[i] = (1.0f / 6.0f) * std::max(-g, 0.0f);
      top = std::max(top, f);
    }
    for (int i = 0; i < padded(); ++i) f_[i] -= top;
    return top;
  }

 private:
  alignas(16) std::array<float, kMaxProxyPoints3> x_;  // points from the centre, local
  alignas(16) std::array<float, kMaxProxyPoints3> y_;
  alignas(16) std::array<float, kMaxProxyPoints3> z_;
  Vec3 axis_{0.0f};  // unit rotation axis, body frame
};

/// Rounds of the safe-step root bracketing (one tangent and one chord each). One round lands
/// close enough to the bound's root that a second saved 0.1% of the iterations (bench_ccd,
/// rotating pairs) for one more bound evaluation per step (+13% instructions).
inline constexpr int kSafeStepRounds = 1;

/// The largest step dt in [0, dt_max] that the bounds prove safe: the separation along n
/// closes by at most G(dt) = closing dt + U_a(dt) + U_b(dt), convex with G(0) = 0, so every
/// dt up to the first root of G = gap is safe. Returns dt_max when G stays below gap on the
/// whole interval. Root bracketing for convex G: a chord from a point left of the root stays
/// above G, so where it meets gap is still left of the root (safe); a tangent at a point
/// right of the root stays below G, so where it meets gap is still right of it (a better
/// right end for the next chord). `closure_at_max` receives G(dt_max): the most the gap can
/// close by the end of the interval.
template <class Bound>
float safe_step(const Bound& bound_a, const Bound& bound_b, float closing, float gap,
                float dt_max, float& closure_at_max) noexcept {
  auto closure = [&](float dt, float& slope) {
    float slope_a = 0.0f;
    float slope_b = 0.0f;
    const float g = closing * dt + bound_a.growth(dt, slope_a) + bound_b.growth(dt, slope_b);
    slope = closing + slope_a + slope_b;
    return g;
  };
  float hi = dt_max;
  float slope_hi = 0.0f;
  float g_hi = closure(hi, slope_hi);
  closure_at_max = g_hi;
  if (g_hi < gap) return dt_max;
  float lo = 0.0f;
  float g_lo = 0.0f;
  for (int round = 0; round < kSafeStepRounds; ++round) {
    if (slope_hi > 0.0f) {
      const float tangent = hi - (g_hi - gap) / slope_hi;
      if (tangent > lo && tangent < hi) {
        hi = tangent;
        g_hi = closure(hi, slope_hi);
        // Rounding may put the tangent's point at or left of the root: then it is safe itself,
        // and a chord through it would extrapolate past the root.
        if (!(g_hi > gap)) return hi;
      }
    }
    if (!(g_hi > g_lo)) break;
    const float chord = lo + (gap - g_lo) * (hi - lo) / (g_hi - g_lo);
    if (!(chord > lo)) break;
    lo = chord;
    if (round + 1 < kSafeStepRounds) {
      float unused = 0.0f;
      g_lo = closure(lo, unused);
    }
  }
  return lo;
}

}  // namespace collide::detail
