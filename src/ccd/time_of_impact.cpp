#include <collide/ccd/time_of_impact.hpp>

#include "shape_size.hpp"

#include <collide/core/tolerance.hpp>
#include <collide/narrow/distance.hpp>

#include <collide/narrow/gjk.hpp>

#include <algorithm>
#include <array>
#include <cmath>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace collide {
namespace {

/// Rounds of the safe-step root bracketing (one tangent and one chord each). One round lands
/// close enough to the bound's root that a second saved 0.1% of the iterations (bench_ccd,
/// rotating pairs) for one more bound evaluation per step (+13% instructions).
constexpr int kSafeStepRounds = 1;

/// How far a turning body's extent along a fixed direction can grow over a time dt, bounded
/// point by point. A core point at r from the centre of rotation (current frame) projects
/// onto the direction m as f = r.m; after a further turn by alpha it projects as
/// f cos(alpha) + g sin(alpha), g = cross(r, m) signed by the turn (alpha >= 0). With
/// cos(alpha) >= 1 - alpha^2/2 and alpha - alpha^3/6 <= sin(alpha) <= alpha:
///   f cos(alpha) + g sin(alpha) <= f + g alpha + max(-f, 0) alpha^2/2 + max(-g, 0) alpha^3/6,
/// a polynomial with non-negative curvature on alpha >= 0. The body's extent h = max_i f_i
/// then grows by at most U(alpha) = max_i (f_i - h + g_i alpha + ...): a maximum of convex
/// functions, convex, U(0) = 0. Unlike one rate for the whole body (turn times reach), points
/// behind the extreme one count only once the turn could bring them forward: a box whose
/// corner points at the other body gains nothing from its side corners until it has turned
/// far, and a point moving away (g < 0) counts as moving away.
class TurnBound {
 public:
  /// Proxy `p` (core points in its local frame) turning about its local point `center` by
  /// `turn` radians per unit t.
  TurnBound(const ConvexProxy& p, Vec2 center, float turn) noexcept
      : rate_(std::fabs(turn)), sign_(turn < 0.0f ? -1.0f : 1.0f), count_(p.count()) {
    float reach2 = 0.0f;
    for (int i = 0; i < count_; ++i) {
      x_[i] = p.point(i).x - center.x;
      y_[i] = p.point(i).y - center.y;
      reach2 = std::max(reach2, x_[i] * x_[i] + y_[i] * y_[i]);
    }
    speed_ = rate_ * std::sqrt(reach2);
    // Padding up to a multiple of 4 (the SIMD width) repeats the first point, which changes
    // no maximum (a point at the centre would, when every real point lies behind it).
    for (int i = count_; i < padded(); ++i) {
      x_[i] = x_[0];
      y_[i] = y_[0];
    }
  }

  /// How fast any core point moves, per unit t: turn rate times the reach from the centre.
  [[nodiscard]] float speed() const noexcept { return speed_; }

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

 private:
  [[nodiscard]] int padded() const noexcept { return (count_ + 3) & ~3; }

  alignas(16) std::array<float, kMaxPolygonVertices> x_;   // points from the centre, local
  alignas(16) std::array<float, kMaxPolygonVertices> y_;
  alignas(16) std::array<float, kMaxPolygonVertices> f_;   // f_i - h (<= 0)
  alignas(16) std::array<float, kMaxPolygonVertices> g_;   // signed rate per radian
  alignas(16) std::array<float, kMaxPolygonVertices> c2_;  // max(-f_i, 0) / 2
  alignas(16) std::array<float, kMaxPolygonVertices> c3_;  // max(-g_i, 0) / 6
  float rate_;
  float speed_;  // rate times reach: the fastest any point moves, per unit t
  float sign_;
  int count_;
};

/// The largest step dt in [0, dt_max] that the bounds prove safe: the separation along n
/// closes by at most G(dt) = closing dt + U_a(dt) + U_b(dt), convex with G(0) = 0, so every
/// dt up to the first root of G = gap is safe. Returns dt_max when G stays below gap on the
/// whole interval. Root bracketing for convex G: a chord from a point left of the root stays
/// above G, so where it meets gap is still left of the root (safe); a tangent at a point
/// right of the root stays below G, so where it meets gap is still right of it (a better
/// right end for the next chord). `closure_at_max` receives G(dt_max): the most the gap can
/// close by the end of the interval.
float safe_step(const TurnBound& bound_a, const TurnBound& bound_b, float closing, float gap,
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

/// Fill point, normal and separation from a GJK result (with radii) at the reported time.
void set_contact(ToiResult& r, const DistanceResult& d) noexcept {
  r.separation = d.distance;
  if (d.status == QueryStatus::overlapped) {
    r.point = d.point_a;
    return;
  }
  r.normal = d.normal;
  r.point = 0.5f * (d.point_a + d.point_b);
}

/// Translation only: the GJK ray cast of shape_cast on the shapes grown by half the target
/// each, which touch exactly when the real shapes are `target` apart.
ToiResult translation_toi(const ConvexProxy& a, const Sweep& sweep_a, const ConvexProxy& b,
                          const Sweep& sweep_b, float target) noexcept {
  const ConvexProxy grown_a(a.points(), a.count(), a.radius() + 0.5f * target);
  const ConvexProxy grown_b(b.points(), b.count(), b.radius() + 0.5f * target);
  const Transform xa = sweep_a.at(0.0f);
  const Transform xb = sweep_b.at(0.0f);
  const ShapeCastResult cast = gjk_shape_cast<2>(grown_a, xa, sweep_a.c1 - sweep_a.c0, grown_b, xb,
                                              sweep_b.c1 - sweep_b.c0);
  ToiResult r;
  r.status = cast.status;
  r.fraction = cast.fraction;
  r.iterations = cast.iterations;
  if (!cast.hit) return r;
  set_contact(r, gjk_distance(a, sweep_a.at(r.fraction), b, sweep_b.at(r.fraction)));
  return r;
}

}  // namespace

ToiResult time_of_impact(const ConvexProxy& a, const Sweep& sweep_a, const ConvexProxy& b,
                         const Sweep& sweep_b, float target) noexcept {
  const float size_a = detail::proxy_size(a);
  const float size_b = detail::proxy_size(b);
  if (target < 0.0f) target = kToiTargetSeparation * detail::smaller_size(size_a, size_b);
  // Not below what float can resolve: the world positions are subtracted first (rounding
  // relative to their magnitude), and GJK then counts shapes closer than kRelativeTolerance of
  // their coordinates' size as touching.
  const float magnitude = std::max(std::max(length(sweep_a.c0), length(sweep_a.c1)),
                                   std::max(length(sweep_b.c0), length(sweep_b.c1)));
  target = std::max({target, kToiRoundingTarget * (magnitude + size_a + size_b),
                     2.0f * kRelativeTolerance * (size_a + size_b)});
  if (sweep_a.a0 == sweep_a.a1 && sweep_b.a0 == sweep_b.a1) {
    return translation_toi(a, sweep_a, b, sweep_b, target);
  }
  const float tolerance = kToiToleranceFraction * target;
  const float radius = a.radius() + b.radius();
  const float goal = radius + target;  // target distance between the cores
  // Over the whole step: the centres' offset and its change, and the turns (radians over the
  // step: angular speeds per unit t).
  const Vec2 offset0 = sweep_b.c0 - sweep_a.c0;
  const Vec2 offset_move = (sweep_b.c1 - sweep_b.c0) - (sweep_a.c1 - sweep_a.c0);
  const float wa = sweep_a.a1 - sweep_a.a0;
  const float wb = sweep_b.a1 - sweep_b.a0;
  const float relative_a0 = sweep_b.a0 - sweep_a.a0;
  const float relative_w = wb - wa;

  ToiResult r;
  GjkSimplexN<2> simplex;
  TurnBound bound_a(a, sweep_a.local_center, wa);
  TurnBound bound_b(b, sweep_b.local_center, wb);
  float t = 0.0f;
  for (r.iterations = 1; r.iterations <= kToiMaxIterations; ++r.iterations) {
    // The pair at time t in A's frame (B placed by b_in_a), from the angles directly: one
    // rotation for A, one for B relative to A.
    const Rot2 qa = Rot2::from_angle(sweep_a.a0 + t * wa);
    Transform b_in_a;
    b_in_a.q = Rot2::from_angle(relative_a0 + t * relative_w);
    const Vec2 centres = inv_rotate(qa, offset0 + t * offset_move);  // B's centre from A's
    b_in_a.p = sweep_a.local_center + centres - rotate(b_in_a.q, sweep_b.local_center);
    // GJK distance between the cores, warm-started from the last step's simplex (its vertex
    // pairs, re-placed at time t).
    if (r.iterations == 1) {
      simplex.v[0] = gjk_seed_vertex<2>(a, b, b_in_a);
      simplex.count = 1;
    } else {
      for (int i = 0; i < simplex.count; ++i) {
        simplex.v[i] = gjk_vertex<2>(a, b, b_in_a, simplex.v[i].ia, simplex.v[i].ib);
      }
    }
    const float scale = gjk_scale<2>(simplex.v[0], radius);
    int gjk_iterations = 0;
    const GjkEnd end = run_gjk<2>(a, b, b_in_a, simplex, scale,
                                               GjkRunToEnd{}, gjk_iterations);
    Vec2 pa;
    Vec2 pb;
    gjk_witness_points(simplex, pa, pb);
    const Vec2 delta = pb - pa;
    const float cores = length(delta);
    const bool overlapped = end == GjkEnd::overlapped || !(cores > 0.0f);
    if (overlapped || cores < goal + tolerance) {
      // Within the target (or overlapping): at t = 0 the shapes started there; later, this is
      // the time of impact (the steps never overshoot, up to rounding).
      r.fraction = t;
      if (t == 0.0f) {
        r.status = QueryStatus::overlapped;
      } else {
        r.status = cores > goal - tolerance ? QueryStatus::hit : QueryStatus::max_iterations;
      }
      const Transform xa{sweep_a.c0 + t * (sweep_a.c1 - sweep_a.c0) -
                             rotate(qa, sweep_a.local_center),
                         qa};
      if (overlapped) {
        r.separation = 0.0f;
        r.point = transform_point(xa, 0.5f * (pa + pb));
      } else {
        const Vec2 n = delta * (1.0f / cores);
        r.separation = std::max(cores - radius, 0.0f);
        r.normal = rotate(qa, n);
        r.point = transform_point(xa, 0.5f * ((pa + a.radius() * n) + (pb - b.radius() * n)));
      }
      return r;
    }
    // Advance: along the closest-point normal n (fixed in the world; in A's frame now), the
    // gap cores - goal closes by at most G(dt) over the next dt (TurnBound), so every dt with
    // G <= gap is safe. Aim at the low end of the accepted band [goal - tolerance,
    // goal + tolerance] (keeping a quarter of it for rounding): a step that lands anywhere in
    // the band ends the search.
    // The gap is measured between the support planes along n (each body's extent from its
    // centre), not taken from GJK's distance: that is an upper bound of the distance (the
    // witnesses lie on the cores), exact only when GJK converged, and a warm-started GJK may
    // stop early (a stale simplex vertex dropped, then found again as the support point, ends
    // the run as "cycling"); a step sized from it could then overshoot the contact.
    // n from the simplex's own geometry where it is exact: on an edge of the Minkowski
    // difference, the edge's perpendicular (the witnesses' difference loses digits to the
    // barycentric weights, and an error of e radians in n moves a support plane by e times
    // the body's length: a long wall would then look much closer than it is).
    Vec2 n = delta * (1.0f / cores);
    if (simplex.count == 2) n = normalize(gjk_search_direction(simplex));
    const float extent_a = bound_a.reset(n);
    const float extent_b = bound_b.reset(inv_rotate(b_in_a.q, -n));
    const float separation_n = dot(centres, n) - extent_a - extent_b;  // <= core distance
    const float gap = separation_n - (goal - 0.75f * tolerance);
    const float closing = -dot(inv_rotate(qa, offset_move), n);  // centres, along n, per unit t
    float closure_at_end = 0.0f;
    float step = safe_step(bound_a, bound_b, closing, gap, 1.0f - t, closure_at_end);
    const float crude_rate = std::max(closing, 0.0f) + bound_a.speed() + bound_b.speed();
    if (crude_rate > 0.0f) step = std::max(step, gap / crude_rate);
    closure_at_end = std::min(closure_at_end, crude_rate * (1.0f - t));
    if (!(step < 1.0f - t)) {
      // Safe up to t = 1. Separated, unless the shapes may end the step within the band
      // (the lower bound of the separation at t = 1 below goal + tolerance): then look at
      // t = 1 itself, where such a graze is a hit.
      if (t == 1.0f || gap - closure_at_end > 1.75f * tolerance) break;
      t = 1.0f;
      continue;
    }
    if (!(step > 0.0f)) {
      // The bounds disagree by more than the band (GJK's distance above it, the support
      // planes below it): no step is provably safe. Report the safe time reached.
      r.status = QueryStatus::max_iterations;
      r.fraction = t;
      return r;
    }
    t += step;
  }
  if (r.iterations > kToiMaxIterations) {
    r.iterations = kToiMaxIterations;
    r.status = QueryStatus::max_iterations;
    r.fraction = t;
    return r;
  }
  r.status = QueryStatus::separated;
  r.fraction = 1.0f;
  return r;
}

ToiResult time_of_impact(const Shape2D& a, const Sweep& sweep_a, const Shape2D& b,
                         const Sweep& sweep_b, float target) {
  check_sweep(sweep_a, "sweep_a");
  check_sweep(sweep_b, "sweep_b");
  if (!std::isfinite(target)) throw InvalidInput("target: not finite");
  return time_of_impact(ConvexProxy(a), sweep_a, ConvexProxy(b), sweep_b, target);
}

}  // namespace collide
