#pragma once
/// @file
/// Cyrus-Beck clipping of a ray by the half-spaces of a convex polytope, shared by the 2D
/// polygon and the 3D hull ray casts. Internal to ccd.

namespace collide::detail {

/// Where a ray enters a convex polytope given by half-spaces.
struct ClipResult {
  int plane = -1;         ///< entering half-space (edge or face), -1 if none
  float fraction = 0.0f;  ///< entry fraction when plane >= 0
  bool inside = false;    ///< no entry because the origin lies in the closed polytope
};

/// Numerator and denominator of one half-space for the ray p + t d: num = offset - n . p
/// (>= 0 when p is inside), den = n . d; the ray is inside for t with t * den <= num.
struct PlaneCrossing {
  float num;
  float den;
};

/// Cyrus-Beck clipping of p + t d, t in [0, 1], by `count` half-spaces, half-space i given by
/// `crossing(i)` (Cyrus & Beck 1978; Ericson, Real-Time Collision Detection, 5.3.8). Entering
/// half-spaces (den < 0) raise the lower bound num / den, leaving ones (den > 0) lower the upper
/// bound. Bounds are kept as fractions with positive denominators so the loop never divides.
/// Returns the entering half-space, or -1 when the ray misses or starts inside (never enters);
/// then `inside` tells which. A ray with a NaN coordinate makes every crossing NaN: no bound
/// moves and the result says `inside`, which callers must not take for a hit.
template <class Crossing>
[[nodiscard]] inline ClipResult clip_ray(int count, Crossing&& crossing) noexcept {
  // lower = lo_num / lo_den, upper = up_num / up_den, denominators > 0.
  float lo_num = 0.0f, lo_den = 1.0f;
  float up_num = 1.0f, up_den = 1.0f;
  int entering = -1;
  for (int i = 0; i < count; ++i) {
    const PlaneCrossing c = crossing(i);
    if (c.den < 0.0f) {
      // Entering: t >= num / den = (-num) / (-den). Take it if above the lower bound.
      if (-c.num * lo_den > lo_num * -c.den) {
        lo_num = -c.num;
        lo_den = -c.den;
        entering = i;
      }
    } else if (c.den > 0.0f) {
      if (c.num * up_den < up_num * c.den) {  // leaving: t <= num / den
        up_num = c.num;
        up_den = c.den;
      }
    } else if (c.num < 0.0f) {
      return {};  // parallel and outside this half-space: never inside
    }
    if (up_num * lo_den < lo_num * up_den) return {};  // upper < lower: empty
  }
  // No entering half-space raised the lower bound above 0: the origin is inside every one.
  if (entering < 0) return {-1, 0.0f, true};
  return {entering, lo_num / lo_den, false};
}

}  // namespace collide::detail
