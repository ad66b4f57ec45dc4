#include <collide/ccd/time_of_impact.hpp>

#include "polygon_axis_cast.hpp"
#include "shape_size.hpp"
#include "turn_bound.hpp"

#include <collide/core/tolerance.hpp>
#include <collide/narrow/distance.hpp>

#include <collide/narrow/gjk.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <variant>

namespace collide {
namespace {

using detail::TurnBound2;
using detail::TurnBound3;

/// The relative motion of two sweeps, per dimension: what the advancement loop needs to place
/// the pair at time t in A's frame, bound the turns, and report in the world.
template <int D>
struct PairMotion;

template <>
struct PairMotion<2> {
  using SweepT = Sweep;
  using RotA = Rot2;
  using Bound = TurnBound2;

  const Sweep& sa;
  const Sweep& sb;
  // Over the whole step: the centres' offset and its change, and the turns (radians over the
  // step: angular speeds per unit t).
  Vec2 offset0;
  Vec2 offset_move;
  float wa;
  float wb;
  float relative_a0;
  float relative_w;

  PairMotion(const Sweep& sweep_a, const Sweep& sweep_b) noexcept
      : sa(sweep_a),
        sb(sweep_b),
        offset0(sweep_b.c0 - sweep_a.c0),
        offset_move((sweep_b.c1 - sweep_b.c0) - (sweep_a.c1 - sweep_a.c0)),
        wa(sweep_a.a1 - sweep_a.a0),
        wb(sweep_b.a1 - sweep_b.a0),
        relative_a0(sweep_b.a0 - sweep_a.a0),
        relative_w(wb - wa) {}

  [[nodiscard]] static bool rotates(const Sweep& s) noexcept { return s.a0 != s.a1; }
  [[nodiscard]] Bound bound_a(const ConvexProxy& a) const noexcept {
    return Bound(a, sa.local_center, wa);
  }
  [[nodiscard]] Bound bound_b(const ConvexProxy& b) const noexcept {
    return Bound(b, sb.local_center, wb);
  }

  /// The pair at time t in A's frame, from the angles directly (one rotation for A, one for B
  /// relative to A): B placed by `b_in_a`, B's centre from A's in `centres`; returns A's
  /// rotation.
  Rot2 place(float t, Transform& b_in_a, Vec2& centres) const noexcept {
    const Rot2 qa = Rot2::from_angle(sa.a0 + t * wa);
    b_in_a.q = Rot2::from_angle(relative_a0 + t * relative_w);
    centres = inv_rotate(qa, offset0 + t * offset_move);
    b_in_a.p = sa.local_center + centres - rotate(b_in_a.q, sb.local_center);
    return qa;
  }
  /// A's transform at time t, given its rotation then.
  [[nodiscard]] Transform a_at(float t, Rot2 qa) const noexcept {
    return {sa.c0 + t * (sa.c1 - sa.c0) - rotate(qa, sa.local_center), qa};
  }
};

template <>
struct PairMotion<3> {
  using SweepT = Sweep3;
  using RotA = Quat;
  using Bound = TurnBound3;

  const Sweep3& sa;
  const Sweep3& sb;
  Vec3 offset0;      // B's centre from A's at t = 0, world
  Vec3 offset_move;  // its change over the step

  PairMotion(const Sweep3& sweep_a, const Sweep3& sweep_b) noexcept
      : sa(sweep_a),
        sb(sweep_b),
        offset0(sweep_b.c0 - sweep_a.c0),
        offset_move((sweep_b.c1 - sweep_b.c0) - (sweep_a.c1 - sweep_a.c0)) {}

  [[nodiscard]] static bool rotates(const Sweep3& s) noexcept { return s.rotation != Vec3(0.0f); }
  // The rotation vectors in the bodies' own frames (constant: the axis is fixed, see
  // turn_bound.hpp).
  [[nodiscard]] Bound bound_a(const ConvexProxy3& a) const noexcept {
    return Bound(a, sa.local_center, inv_rotate(sa.q0, sa.rotation));
  }
  [[nodiscard]] Bound bound_b(const ConvexProxy3& b) const noexcept {
    return Bound(b, sb.local_center, inv_rotate(sb.q0, sb.rotation));
  }

  /// As PairMotion<2>::place: each orientation from its sweep, B's relative to A's.
  Quat place(float t, Frame3& b_in_a, Vec3& centres) const noexcept {
    const Quat qa = sa.orientation(t);
    const Quat qb = sb.orientation(t);
    b_in_a.r = glm::mat3_cast(glm::conjugate(qa) * qb);
    centres = inv_rotate(qa, offset0 + t * offset_move);
    b_in_a.p = sa.local_center + centres - rotate(b_in_a, sb.local_center);
    return qa;
  }
  [[nodiscard]] Transform3 a_at(float t, const Quat& qa) const noexcept {
    return {sa.c0 + t * (sa.c1 - sa.c0) - rotate(qa, sa.local_center), qa};
  }
};

/// Fill point, normal and separation from a GJK result (with radii) at the reported time.
template <int D>
void set_contact(ToiResultN<D>& r, const DistanceResultN<D>& d) noexcept {
  r.separation = d.distance;
  if (d.status == QueryStatus::overlapped) {
    r.point = d.point_a;
    return;
  }
  r.normal = d.normal;
  r.point = 0.5f * (d.point_a + d.point_b);
}

/// The proxy with its radius grown by `extra`.
ConvexProxy grown(const ConvexProxy& p, float extra) noexcept {
  return {p.points(), p.count(), p.radius() + extra};
}
ConvexProxy3 grown(const ConvexProxy3& p, float extra) noexcept {
  return p.with_radius(p.radius() + extra);
}

/// Translation only: the GJK ray cast of shape_cast on the shapes grown by half the target
/// each, which touch exactly when the real shapes are `target` apart.
template <int D, class SweepT>
ToiResultN<D> translation_toi(const ConvexProxyN<D>& a, const SweepT& sweep_a,
                              const ConvexProxyN<D>& b, const SweepT& sweep_b,
                              float target) noexcept {
  const ConvexProxyN<D> grown_a = grown(a, 0.5f * target);
  const ConvexProxyN<D> grown_b = grown(b, 0.5f * target);
  const TransformN<D> xa = sweep_a.at(0.0f);
  const TransformN<D> xb = sweep_b.at(0.0f);
  const ShapeCastResultN<D> cast = gjk_shape_cast<D>(grown_a, xa, sweep_a.c1 - sweep_a.c0,
                                                     grown_b, xb, sweep_b.c1 - sweep_b.c0);
  ToiResultN<D> r;
  r.status = cast.status;
  r.fraction = cast.fraction;
  r.iterations = cast.iterations;
  if (!cast.hit) return r;
  set_contact(r, gjk_distance<D>(a, sweep_a.at(r.fraction), b, sweep_b.at(r.fraction)));
  return r;
}

/// The target separation time_of_impact works to (see its contract): the caller's, or the
/// default for shapes of these sizes (negative `target`), raised to what float resolves.
template <class SweepT>
float effective_target(float size_a, float size_b, const SweepT& sweep_a, const SweepT& sweep_b,
                       float target) noexcept {
  if (target < 0.0f) target = kToiTargetSeparation * detail::smaller_size(size_a, size_b);
  // Not below what float can resolve: the world positions are subtracted first (rounding
  // relative to their magnitude), and GJK then counts shapes closer than kRelativeTolerance of
  // their coordinates' size as touching.
  const float magnitude = std::max(std::max(length(sweep_a.c0), length(sweep_a.c1)),
                                   std::max(length(sweep_b.c0), length(sweep_b.c1)));
  return std::max({target, kToiRoundingTarget * (magnitude + size_a + size_b),
                   2.0f * kRelativeTolerance * (size_a + size_b)});
}

/// Conservative advancement, once for both dimensions (see time_of_impact.hpp).
template <int D>
ToiResultN<D> advance(const ConvexProxyN<D>& a, const typename PairMotion<D>::SweepT& sweep_a,
                      const ConvexProxyN<D>& b, const typename PairMotion<D>::SweepT& sweep_b,
                      float target) noexcept {
  using Motion = PairMotion<D>;
  using Vec = VecN<D>;
  target = effective_target(detail::proxy_size(a), detail::proxy_size(b), sweep_a, sweep_b,
                            target);
  if (!Motion::rotates(sweep_a) && !Motion::rotates(sweep_b)) {
    return translation_toi<D>(a, sweep_a, b, sweep_b, target);
  }
  const float tolerance = kToiToleranceFraction * target;
  const float radius = a.radius() + b.radius();
  const float goal = radius + target;  // target distance between the cores
  const Motion motion(sweep_a, sweep_b);

  ToiResultN<D> r;
  GjkSimplexN<D> simplex;
  typename Motion::Bound bound_a = motion.bound_a(a);
  typename Motion::Bound bound_b = motion.bound_b(b);
  float t = 0.0f;
  for (r.iterations = 1; r.iterations <= kToiMaxIterations; ++r.iterations) {
    // The pair at time t in A's frame (B placed by b_in_a).
    FrameN<D> b_in_a;
    Vec centres;  // B's centre from A's
    const typename Motion::RotA qa = motion.place(t, b_in_a, centres);
    // GJK distance between the cores, warm-started from the last step's simplex (its vertex
    // pairs, re-placed at time t).
    if (r.iterations == 1) {
      simplex.v[0] = gjk_seed_vertex<D>(a, b, b_in_a);
      simplex.count = 1;
    } else {
      for (int i = 0; i < simplex.count; ++i) {
        simplex.v[i] = gjk_vertex<D>(a, b, b_in_a, simplex.v[i].ia, simplex.v[i].ib);
      }
    }
    const float scale = gjk_scale<D>(simplex.v[0], radius);
    int gjk_iterations = 0;
    const GjkEnd end = run_gjk<D>(a, b, b_in_a, simplex, scale, GjkRunToEnd{}, gjk_iterations);
    Vec pa;
    Vec pb;
    gjk_witness_points(simplex, pa, pb);
    const Vec delta = pb - pa;
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
      const TransformN<D> xa = motion.a_at(t, qa);
      if (overlapped) {
        r.separation = 0.0f;
        r.point = transform_point(xa, 0.5f * (pa + pb));
      } else {
        const Vec n = delta * (1.0f / cores);
        r.separation = std::max(cores - radius, 0.0f);
        r.normal = rotate(qa, n);
        r.point = transform_point(xa, 0.5f * ((pa + a.radius() * n) + (pb - b.radius() * n)));
      }
      return r;
    }
    // Advance: along the closest-point normal n (fixed in the world; in A's frame now), the
    // gap cores - goal closes by at most G(dt) over the next dt (turn_bound.hpp), so every dt
    // with G <= gap is safe. Aim at the low end of the accepted band [goal - tolerance,
    // goal + tolerance] (keeping a quarter of it for rounding): a step that lands anywhere in
    // the band ends the search.
    // The gap is measured between the support planes along n (each body's extent from its
    // centre), not taken from GJK's distance: that is an upper bound of the distance (the
    // witnesses lie on the cores), exact only when GJK converged, and a warm-started GJK may
    // stop early (a stale simplex vertex dropped, then found again as the support point, ends
    // the run as "cycling"); a step sized from it could then overshoot the contact.
    // n from the simplex's own geometry where it is exact: on an edge (or, in 3D, a triangle)
    // of the Minkowski difference, its perpendicular (the witnesses' difference loses digits
    // to the barycentric weights, and an error of e radians in n moves a support plane by e
    // times the body's length: a long wall would then look much closer than it is).
    Vec n = delta * (1.0f / cores);
    if (simplex.count >= 2 && simplex.count <= D) {
      float dd;
      n = normalize(gjk_bounded_search_direction(simplex, dd));
    }
    const float extent_a = bound_a.reset(n);
    const float extent_b = bound_b.reset(inv_rotate(b_in_a, -n));
    const float separation_n = dot(centres, n) - extent_a - extent_b;  // <= core distance
    const float gap = separation_n - (goal - 0.75f * tolerance);
    const float closing = -dot(inv_rotate(qa, motion.offset_move), n);  // along n, per unit t
    float closure_at_end = 0.0f;
    float step = detail::safe_step(bound_a, bound_b, closing, gap, 1.0f - t, closure_at_end);
    // The crude bound, turn times the farthest point's distance from the axis, as a floor.
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

/// Two translating sharp polygons: the separating-axis cast into A - B with every axis moved by
/// the target (detail::polygon_axis_cast), no iterations. Before the time it finds the
/// separation along some axis exceeds the target, so the shapes are farther apart than that;
/// at that time the distance equals the axis's separation when the closest features include
/// an edge, which the polygons' distance walk confirms (corners meeting first are farther
/// apart there). Returns nothing, leaving the pair to the GJK ray cast, when the cast is
/// undecided (a start or a graze within the tolerance band) or corners meet first.
std::optional<ToiResult> toi_polygon_axes(const Polygon& a, const Sweep& sweep_a,
                                          const Polygon& b, const Sweep& sweep_b,
                                          float target) noexcept {
  if (a.radius > 0.0f || b.radius > 0.0f || a.count > detail::kAxisCastMaxVertices ||
      b.count > detail::kAxisCastMaxVertices) {
    return std::nullopt;
  }
  target = effective_target(detail::proxy_size(ConvexProxy(a)),
                            detail::proxy_size(ConvexProxy(b)), sweep_a, sweep_b, target);
  const float tolerance = kToiToleranceFraction * target;
  const detail::AxisCast cast =
      detail::polygon_axis_cast(a, sweep_a.at(0.0f), sweep_a.c1 - sweep_a.c0, b,
                                sweep_b.at(0.0f), sweep_b.c1 - sweep_b.c0, target, tolerance);
  if (cast.end == detail::AxisCastEnd::undecided) return std::nullopt;
  ToiResult r;
  if (cast.end == detail::AxisCastEnd::separated) return r;  // fraction 1
  const float t = cast.fraction;
  const DistanceResult d = distance(a, sweep_a.at(t), b, sweep_b.at(t));
  if (d.status == QueryStatus::overlapped || !(std::fabs(d.distance - target) <= tolerance)) {
    return std::nullopt;  // corners meet first (or rounding): the GJK ray cast decides
  }
  r.status = QueryStatus::hit;
  r.fraction = t;
  set_contact(r, d);
  return r;
}

/// A circle or capsule A and a polygon B, both translating: the shape cast of A grown by the
/// target against B (the rounded-outline ray into B - A's core, exact up to rounding, no
/// iterations; GJK's ray cast where the cast leaves it so), since A's surface is `target` from
/// B exactly where the grown surface touches it. Starts within the target go to the GJK path,
/// which reports them.
template <class Rounded>
ToiResult toi_rounded_polygon(const Rounded& a, const Sweep& sweep_a, const Polygon& b,
                              const Sweep& sweep_b, float target) {
  const ConvexProxy pa(a);
  const ConvexProxy pb(b);
  target = effective_target(detail::proxy_size(pa), detail::proxy_size(pb), sweep_a, sweep_b,
                            target);
  Rounded grown = a;
  grown.radius += target;
  const ShapeCastResult cast = shape_cast(grown, sweep_a.at(0.0f), sweep_a.c1 - sweep_a.c0, b,
                                          sweep_b.at(0.0f), sweep_b.c1 - sweep_b.c0);
  if (cast.status != QueryStatus::hit && cast.status != QueryStatus::separated) {
    return advance<2>(pa, sweep_a, pb, sweep_b, target);
  }
  ToiResult r;
  r.iterations = cast.iterations;
  if (cast.status == QueryStatus::separated) return r;  // fraction 1
  r.status = QueryStatus::hit;
  r.fraction = cast.fraction;
  // The grown surface touches B at cast.point: A's own surface is `target` behind it.
  r.separation = target;
  r.normal = cast.normal;
  r.point = cast.point - 0.5f * target * cast.normal;
  return r;
}

/// The result of B against A seen from A: the same time and point, the normal flipped.
ToiResult seen_from_b(ToiResult r) noexcept {
  r.normal = -r.normal;
  return r;
}

/// Whether neither sweep turns: the casts apply.
bool translating(const Sweep& sweep_a, const Sweep& sweep_b) noexcept {
  return !PairMotion<2>::rotates(sweep_a) && !PairMotion<2>::rotates(sweep_b);
}

/// A circle or capsule A and a polygon B, validated: the grown cast when neither turns, else
/// conservative advancement.
template <class Rounded>
ToiResult rounded_polygon_toi(const Rounded& a, const Sweep& sweep_a, const Polygon& b,
                              const Sweep& sweep_b, float target) {
  if (translating(sweep_a, sweep_b)) return toi_rounded_polygon(a, sweep_a, b, sweep_b, target);
  return advance<2>(ConvexProxy(a), sweep_a, ConvexProxy(b), sweep_b, target);
}

/// The validation of every time_of_impact on shapes.
void check_toi_input(const Sweep& sweep_a, const Sweep& sweep_b, float target) {
  check_sweep(sweep_a, "sweep_a");
  check_sweep(sweep_b, "sweep_b");
  if (!std::isfinite(target)) throw InvalidInput("target: not finite");
}

}  // namespace

ToiResult time_of_impact(const ConvexProxy& a, const Sweep& sweep_a, const ConvexProxy& b,
                         const Sweep& sweep_b, float target) noexcept {
  return advance<2>(a, sweep_a, b, sweep_b, target);
}

ToiResult3 time_of_impact(const ConvexProxy3& a, const Sweep3& sweep_a, const ConvexProxy3& b,
                          const Sweep3& sweep_b, float target) noexcept {
  return advance<3>(a, sweep_a, b, sweep_b, target);
}

ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Polygon& b,
                         const Sweep& sweep_b, float target) {
  check_toi_input(sweep_a, sweep_b, target);
  if (translating(sweep_a, sweep_b)) {
    if (const std::optional<ToiResult> r = toi_polygon_axes(a, sweep_a, b, sweep_b, target)) {
      return *r;
    }
  }
  return time_of_impact(ConvexProxy(a), sweep_a, ConvexProxy(b), sweep_b, target);
}

ToiResult time_of_impact(const Circle& a, const Sweep& sweep_a, const Polygon& b,
                         const Sweep& sweep_b, float target) {
  check_toi_input(sweep_a, sweep_b, target);
  return rounded_polygon_toi(a, sweep_a, b, sweep_b, target);
}

ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Circle& b,
                         const Sweep& sweep_b, float target) {
  check_toi_input(sweep_a, sweep_b, target);
  return seen_from_b(rounded_polygon_toi(b, sweep_b, a, sweep_a, target));
}

ToiResult time_of_impact(const Capsule& a, const Sweep& sweep_a, const Polygon& b,
                         const Sweep& sweep_b, float target) {
  check_toi_input(sweep_a, sweep_b, target);
  return rounded_polygon_toi(a, sweep_a, b, sweep_b, target);
}

ToiResult time_of_impact(const Polygon& a, const Sweep& sweep_a, const Capsule& b,
                         const Sweep& sweep_b, float target) {
  check_toi_input(sweep_a, sweep_b, target);
  return seen_from_b(rounded_polygon_toi(b, sweep_b, a, sweep_a, target));
}

ToiResult time_of_impact(const Shape2D& a, const Sweep& sweep_a, const Shape2D& b,
                         const Sweep& sweep_b, float target) {
  return std::visit(
      [&](const auto& sa, const auto& sb) {
        return time_of_impact(sa, sweep_a, sb, sweep_b, target);
      },
      a, b);
}


ToiResult3 time_of_impact(const Shape3D& a, const Sweep3& sweep_a, const Shape3D& b,
                          const Sweep3& sweep_b, float target) {
  check_sweep(sweep_a, "sweep_a");
  check_sweep(sweep_b, "sweep_b");
  if (!std::isfinite(target)) throw InvalidInput("target: not finite");
  return time_of_impact(ConvexProxy3(a), sweep_a, ConvexProxy3(b), sweep_b, target);
}

}  // namespace collide
