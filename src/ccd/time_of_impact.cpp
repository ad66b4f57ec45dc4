#include <collide/ccd/time_of_impact.hpp>

#include "shape_size.hpp"

#include <collide/core/tolerance.hpp>
#include <collide/narrow/distance.hpp>

#include <algorithm>
#include <cmath>

namespace collide {
namespace {

/// Largest distance of the proxy's core points from the centre of rotation: how fast (per
/// radian) any core point can move when the body turns.
float reach_from(const ConvexProxy& p, Vec2 local_center) noexcept {
  float r2 = 0.0f;
  for (int i = 0; i < p.count(); ++i) r2 = std::max(r2, distance_squared(p.point(i), local_center));
  return std::sqrt(r2);
}

/// How fast body turning at `w` (radians per unit t) now moves its farthest-going core point
/// along the world direction `n`: max over core points p of w * cross(R (p - c), n), at least
/// 0. Rotation keeps cross products, so this is w * cross(p - c, m) with m = R^-1 n: a support
/// query along right_perp(m), signed by the turn.
float turning_rate(const ConvexProxy& p, const Transform& xf, Vec2 center, float w,
                   Vec2 n) noexcept {
  if (w == 0.0f) return 0.0f;
  const Vec2 m = inv_rotate(xf.q, n);
  const Vec2 along = w > 0.0f ? right_perp(m) : -right_perp(m);
  const Vec2 r = p.point(p.support_index(along)) - center;
  return std::max(w * cross(r, m), 0.0f);
}

/// Fill point, normal and separation from a GJK result (with radii) at the reported time.
void set_contact(ToiResult& r, const DistanceResult& d) noexcept {
  r.separation = d.distance;
  if (d.status == GjkStatus::overlapped) {
    r.point = d.point_a;
    return;
  }
  r.normal = d.normal;
  r.point = 0.5f * (d.point_a + d.point_b);
}

/// Distance between the cores from a GJK result with radii: the witnesses are the core points
/// moved by the radii along the normal (also when the radii overlap), so the cores are
/// radius + (point_b - point_a) . normal apart. 0 when the cores overlap.
float core_distance(const DistanceResult& d, float radius) noexcept {
  if (d.status == GjkStatus::overlapped) return 0.0f;
  return radius + dot(d.point_b - d.point_a, d.normal);
}

/// Translation only: the GJK ray cast of shape_cast on the shapes grown by half the target
/// each, which touch exactly when the real shapes are `target` apart.
ToiResult translation_toi(const ConvexProxy& a, const Sweep& sweep_a, const ConvexProxy& b,
                          const Sweep& sweep_b, float target) noexcept {
  const ConvexProxy grown_a(a.points(), a.count(), a.radius() + 0.5f * target);
  const ConvexProxy grown_b(b.points(), b.count(), b.radius() + 0.5f * target);
  const Transform xa = sweep_a.at(0.0f);
  const Transform xb = sweep_b.at(0.0f);
  const ShapeCastResult cast = gjk_shape_cast(grown_a, xa, sweep_a.c1 - sweep_a.c0, grown_b, xb,
                                              sweep_b.c1 - sweep_b.c0);
  ToiResult r;
  r.status = cast.status;
  r.t = cast.t;
  r.iterations = cast.iterations;
  if (!cast.hit) return r;
  set_contact(r, gjk_distance(a, sweep_a.at(r.t), b, sweep_b.at(r.t)));
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
  // Over the whole step: relative translation of the centres, the turns (radians over the
  // step: angular speeds per unit t), and each core's reach from its centre of rotation.
  const Vec2 relative_move = (sweep_a.c1 - sweep_a.c0) - (sweep_b.c1 - sweep_b.c0);
  const float wa = sweep_a.a1 - sweep_a.a0;
  const float wb = sweep_b.a1 - sweep_b.a0;
  const float reach_a = reach_from(a, sweep_a.local_center);
  const float reach_b = reach_from(b, sweep_b.local_center);
  const float turn_speed = std::fabs(wa) * reach_a + std::fabs(wb) * reach_b;
  // How fast the turning terms can grow (see below).
  const float turn_growth = wa * wa * reach_a + wb * wb * reach_b;

  ToiResult r;
  SimplexCache cache{};
  float t = 0.0f;
  for (r.iterations = 1; r.iterations <= kToiMaxIterations; ++r.iterations) {
    const Transform xa = sweep_a.at(t);
    const Transform xb = sweep_b.at(t);
    const DistanceResult gjk = gjk_distance(a, xa, b, xb, &cache);
    const float cores = core_distance(gjk, radius);
    if (gjk.status == GjkStatus::overlapped || cores < goal + tolerance) {
      // Within the target (or overlapping): at t = 0 the shapes started there; later, this is
      // the time of impact (the steps never overshoot, up to rounding).
      r.t = t;
      if (t == 0.0f) {
        r.status = ImpactStatus::overlapped;
      } else {
        r.status = cores > goal - tolerance ? ImpactStatus::hit : ImpactStatus::failed;
      }
      set_contact(r, gjk);
      return r;
    }
    // Along the closest-point normal n (fixed in the world), no pair of core points closes in
    // faster than max(0, relative_move . n) plus, for each body, the most its turning moves
    // any of its core points towards the other along n. Two bounds of the turning part, both
    // safe, so the larger step of the two is taken:
    //  - crude: turn times reach (turn_speed), for all time;
    //  - current: for A, max over core points r (from the centre, rotated to now) of
    //    wa * cross(r, n), which changes at most at rate wa^2 * reach_a as A turns (the same
    //    for B towards -n). The gap g then lasts at least tau with
    //    k0 tau + turn_growth tau^2 / 2 = g, k0 the current rate.
    const Vec2 n = gjk.normal;
    // Aim at the low end of the accepted band [goal - tolerance, goal + tolerance] (keeping a
    // quarter of it for rounding): a step that lands anywhere in the band ends the search, so
    // this saves steps when the bound overestimates the closing speed.
    const float gap = cores - (goal - 0.75f * tolerance);
    const float move_rate = std::max(dot(relative_move, n), 0.0f);
    float step = 0.0f;
    if (move_rate + turn_speed > 0.0f) step = gap / (move_rate + turn_speed);
    const float k0 = move_rate + turning_rate(a, xa, sweep_a.local_center, wa, n) +
                     turning_rate(b, xb, sweep_b.local_center, wb, -n);
    const float root = std::sqrt(k0 * k0 + 2.0f * turn_growth * gap);
    if (k0 + root > 0.0f) step = std::max(step, 2.0f * gap / (k0 + root));
    if (!(move_rate + turn_speed > 0.0f)) break;  // nothing approaches: separated
    t += step;
    if (!(t <= 1.0f)) break;
  }
  if (r.iterations > kToiMaxIterations) {
    r.iterations = kToiMaxIterations;
    r.status = ImpactStatus::failed;
    r.t = t;
    return r;
  }
  r.status = ImpactStatus::separated;
  r.t = 1.0f;
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
