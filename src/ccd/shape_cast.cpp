#include <collide/ccd/shape_cast.hpp>

#include <collide/narrow/gjk.hpp>
#include <collide/narrow/sat.hpp>
#include "polygon_axis_cast.hpp"
#include "rounded_polygon_ray.hpp"
#include "shape_size.hpp"
#include "touching_feature.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <variant>

namespace collide {
namespace {

template <int D>
[[nodiscard]] bool holds(const GjkSimplexN<D>& s, int ia, int ib) noexcept {
  for (int i = 0; i < s.count; ++i) {
    if (s.v[i].ia == ia && s.v[i].ib == ib) return true;
  }
  return false;
}

/// The vertex pairs of a simplex, to notice an iteration that changed nothing.
template <int D>
struct SimplexIds {
  std::array<int, D + 1> ia{};
  std::array<int, D + 1> ib{};
  int count = 0;

  explicit SimplexIds(const GjkSimplexN<D>& s) noexcept : count(s.count) {
    for (int i = 0; i < s.count; ++i) {
      ia[i] = s.v[i].ia;
      ib[i] = s.v[i].ib;
    }
  }
  /// Same vertex pairs as `s`, as a set?
  [[nodiscard]] bool same_as(const GjkSimplexN<D>& s) const noexcept {
    if (s.count != count) return false;
    for (int i = 0; i < count; ++i) {
      if (!holds(s, ia[i], ib[i])) return false;
    }
    return true;
  }
};

/// The sine of the angle between unit vectors n and m (its absolute value): |n x m|.
[[nodiscard]] inline float sin_between(Vec2 n, Vec2 m) noexcept { return std::fabs(cross(n, m)); }
[[nodiscard]] inline float sin_between(Vec3 n, Vec3 m) noexcept { return length(cross(n, m)); }

/// Cyrus-Beck clipping of the cast's time interval [0, 1] by separating axes (see
/// cast_polygon_axes).
struct AxisClip {
  float t_enter = 0.0f;  ///< latest time an axis closes
  float t_exit = 1.0f;   ///< earliest time an axis reopens (or the end of the step)
  int enter_axis = -1;   ///< the first axis closing at t_enter, -1 if none closes
  int exit_axis = -1;    ///< the first axis reopening at t_exit, -1 if none before the end
  unsigned never = 0;      ///< an axis apart and not closing
  unsigned undecided = 0;  ///< such an axis within the tolerance of touching
};

/// Over the first N slots of `sep` (separations at t = 0) and `rate` (their rates of change):
/// an axis apart (sep > 0) closes at sep / -rate if closing, never otherwise; an axis
/// overlapping (sep <= 0) and opening reopens at -sep / rate. Selects rather than branches
/// (random casts mispredict them), over a fixed count so the compiler runs four axes at a time
/// (unused slots hold an overlapping, still axis, which bounds nothing): 8-gon casts 181 -> 143
/// ns. N = 8 when both polygons have 4 sides or fewer (16 slots slowed box casts by a tenth).
template <int N, std::size_t M>
AxisClip clip_axes(const std::array<float, M>& sep, const std::array<float, M>& rate,
                   float tolerance) noexcept {
  static_assert(N <= static_cast<int>(M));
  std::array<float, N> t_in;   // when axis k closes, or 0
  std::array<float, N> t_out;  // when axis k reopens, or 1
  AxisClip c;
  for (int k = 0; k < N; ++k) {
    const float s = sep[k];
    const float r = rate[k];
    const unsigned apart = unsigned{s > 0.0f};
    const unsigned closing = unsigned{r < 0.0f};
    c.never |= apart & (closing ^ 1u);
    c.undecided |= apart & (closing ^ 1u) & unsigned{s <= tolerance};
    const float at = -s / r;  // when sep + t rate = 0
    t_in[k] = (apart & closing) != 0 ? at : 0.0f;
    t_out[k] = (apart == 0 && r > 0.0f) ? at : 1.0f;
  }
  for (int k = 0; k < N; ++k) {
    c.t_enter = std::max(c.t_enter, t_in[k]);
    c.t_exit = std::min(c.t_exit, t_out[k]);
  }
  for (int k = N - 1; k >= 0; --k) {
    c.enter_axis = c.t_enter > 0.0f && t_in[k] == c.t_enter ? k : c.enter_axis;
    c.exit_axis = c.t_exit < 1.0f && t_out[k] == c.t_exit ? k : c.exit_axis;
  }
  return c;
}

}  // namespace

namespace detail {

// The lesson's ray into the Minkowski difference, for two sharp polygons, without building
// A - B: its edges' normals are exactly A's and B's edge normals, so the ray from the origin
// along B's motion relative to A enters A - B where Cyrus-Beck clipping by those half-planes
// says. Along axis k the cores' separation is s_k + t rate_k: A's edge i gives
// s = min_j n_i . (b_j - a_i), rate = n_i . r; B's edge j gives s = min_i m_j . (a_i - b_j),
// rate = -m_j . r. The separation first comes down to `gap` at the largest time an axis
// closes to it, if no axis has reopened by then. No iterations.
AxisCast polygon_axis_cast(const Polygon& a, const Transform& xa, Vec2 va, const Polygon& b,
                           const Transform& xb, Vec2 vb, float gap, float tolerance) noexcept {
  AxisCast cast;
  if (a.radius > 0.0f || b.radius > 0.0f || a.count > kAxisCastMaxVertices ||
      b.count > kAxisCastMaxVertices) {
    return cast;
  }
  const int na = a.count;
  const int nb = b.count;
  cast.b_in_a = inv_mul(xa, xb);
  cast.ray = inv_rotate(xa.q, vb - va);  // B's motion relative to A, A's frame

  // Every axis's separation at t = 0 (the separating axis test's, each polygon's in its own
  // frame: the values do not depend on it) less the gap, and its rate of change, A's edges
  // then B's.
  constexpr int kAxes = 2 * kAxisCastMaxVertices;
  std::array<float, kAxes> sep;
  std::array<float, kAxes> rate;
  edge_separations(a, b, cast.b_in_a, std::span(sep).first(na));
  edge_separations(b, a, inv_mul(xb, xa), std::span(sep).subspan(na, nb));
  const Vec2 ray_in_b = inv_rotate(cast.b_in_a.q, cast.ray);
  for (int i = 0; i < na; ++i) rate[i] = dot(a.normals[i], cast.ray);
  for (int j = 0; j < nb; ++j) rate[na + j] = -dot(b.normals[j], ray_in_b);
  if (gap != 0.0f) {
    for (int k = 0; k < na + nb; ++k) sep[k] -= gap;
  }
  for (int k = na + nb; k < kAxes; ++k) {  // unused slots: overlapping and still
    sep[k] = -1.0f;
    rate[k] = 0.0f;
  }
  const AxisClip clip = na + nb <= kAxes / 2 ? clip_axes<kAxes / 2>(sep, rate, tolerance)
                                             : clip_axes<kAxes>(sep, rate, tolerance);
  const int enter_axis = clip.enter_axis;
  const int exit_axis = clip.exit_axis;

  // A miss decided within the tolerance, or at the gap at the start: undecided.
  if (clip.undecided != 0) return cast;
  if (clip.never != 0) {
    cast.end = AxisCastEnd::separated;
    return cast;
  }
  if (enter_axis < 0 || sep[enter_axis] <= tolerance) return cast;
  const float t_enter = clip.t_enter;
  if (!(t_enter <= clip.t_exit)) {
    // Misses: the closing axis arrives after the step ends or after another axis reopened.
    // A graze (the gap left at t_enter along the reopened axis, or along the closing axis at
    // the step's end, within tolerance) is undecided.
    const float left = exit_axis >= 0 ? sep[exit_axis] + t_enter * rate[exit_axis]
                                      : sep[enter_axis] + rate[enter_axis];  // closing one at 1
    if (left > tolerance) cast.end = AxisCastEnd::separated;
    return cast;
  }
  cast.end = AxisCastEnd::hit;
  cast.fraction = t_enter;
  cast.normal = enter_axis < na ? a.normals[enter_axis]
                                : -rotate(cast.b_in_a.q, b.normals[enter_axis - na]);  // A to B
  return cast;
}

}  // namespace detail

namespace {

/// The separating-axis cast (detail::polygon_axis_cast) stopped at touching, with the contact
/// point from the touching features. Exact up to rounding (GJK stops within
/// kShapeCastTolerance). Returns nothing, leaving the pair to GJK, when it does not apply
/// (rounded or larger polygons) or when the answer is within GJK's tolerance of another
/// (touching at the start, grazing), so those cases keep GJK's tolerance semantics.
std::optional<ShapeCastResult> cast_polygon_axes(const Polygon& a, const Transform& xa, Vec2 va,
                                                 const Polygon& b, const Transform& xb,
                                                 Vec2 vb) noexcept {
  // The tolerance of gjk_shape_cast for this pair: answers within it of a graze go to GJK.
  const float size_a = detail::proxy_size(ConvexProxy(a));
  const float size_b = detail::proxy_size(ConvexProxy(b));
  const float magnitude = length(vb - va) + length(xb.p - xa.p) + size_a + size_b;
  const float tolerance =
      kShapeCastTolerance * detail::smaller_size(size_a, size_b) + kShapeCastRounding * magnitude;
  const detail::AxisCast cast = detail::polygon_axis_cast(a, xa, va, b, xb, vb, 0.0f, tolerance);
  if (cast.end == detail::AxisCastEnd::undecided) return std::nullopt;
  ShapeCastResult result;
  if (cast.end == detail::AxisCastEnd::separated) return result;  // fraction 1
  const float t = cast.fraction;
  const Vec2 n = cast.normal;
  // The touching features, in A's frame shifted to A's vertex 0, B moved by t ray.
  const Vec2 origin = a.vertices[0];
  const Vec2 shift = cast.b_in_a.p - origin + t * cast.ray;
  const float tie = detail::kFeatureTieTolerance * std::max(size_a, size_b);
  const detail::TouchingFeature fa = detail::touching_feature(
      a.count, [&](int i) { return a.vertices[i] - origin; }, n, 1.0f, tie);
  const detail::TouchingFeature fb = detail::touching_feature(
      b.count, [&](int i) { return rotate(cast.b_in_a.q, b.vertices[i]) + shift; }, n, -1.0f,
      tie);
  result.hit = true;
  result.fraction = t;
  result.status = QueryStatus::hit;
  result.normal = rotate(xa.q, n);
  // A's frame at t: A has moved by t va in the world.
  result.point = transform_point(xa, detail::touching_point(fa, 0.0f, fb, 0.0f, n) + origin) + t * va;
  return result;
}

/// Circle A against polygon B: the lesson's ray into A - B, literally, since B - A is B grown by
/// the circle: the ray from the circle's centre along its motion relative to B into B rounded
/// by the sum of the radii (ray_rounded_polygon), in B's frame. Exact up to rounding, no
/// iterations. Returns nothing, leaving the pair to GJK (whose tolerance decides what counts as
/// overlapped), when the shapes start touching or within that tolerance of it inside the
/// pushed-out edges, or do not move relative to each other.
std::optional<ShapeCastResult> cast_circle_polygon(const Circle& a, const Transform& xa, Vec2 va,
                                                   const Polygon& b, const Transform& xb,
                                                   Vec2 vb) noexcept {
  // Relative to B's origin first, so large world coordinates cancel before the rotation.
  const Vec2 p = inv_rotate(xb.q, (xa.p - xb.p) + rotate(xa.q, a.center));
  const Vec2 d = inv_rotate(xb.q, va - vb);
  if (!(length_squared(d) > 0.0f)) return std::nullopt;
  const detail::RoundedPolygonEntry entry = detail::ray_rounded_polygon(b, a.radius + b.radius, p, d);
  if (entry.start_gap <= kShapeCastTolerance * detail::smaller_size(2.0f * a.radius,
                                                                    detail::proxy_size(ConvexProxy(b))) +
                             kShapeCastRounding * (length(d) + length(p))) {
    // In or within tolerance of the shape at the start, inside the pushed-out edges. (A start
    // just outside them, within tolerance of an edge, is left to the exact cast: a hit at a
    // small fraction, or a miss when moving away, where GJK might say overlapped.)
    return std::nullopt;
  }
  ShapeCastResult result;
  if (!entry.hit.hit) return result;  // separated, fraction 1
  const float t = entry.hit.fraction;
  const Vec2 outward = rotate(xb.q, entry.hit.normal);  // B's outward normal at the contact
  result.hit = true;
  result.fraction = t;
  result.status = QueryStatus::hit;
  result.normal = -outward;  // from A (the circle) to B
  result.point = transform_point(xa, a.center) + t * va - a.radius * outward;
  return result;
}

/// Capsule A against polygon B: the ray from the origin along A's motion relative to B into
/// B - S rounded by the sum of the radii, S being A's core segment (B's frame): A touches B
/// when S moved by t d comes within the radii of B, that is when t d enters (B - S) grown by
/// them. B - S = B + (-S) is built on the stack: B's edges, each moved by the end of -S
/// farthest along its normal, and -S's direction inserted as an edge (both ways) where that end
/// changes (the Minkowski sum of a convex polygon and a segment; de Berg et al. 13.3). Then the
/// rounded-outline ray of the circle cast: exact up to rounding, no iterations. Returns nothing,
/// leaving the pair to GJK, when the start is within the outline of edges pushed out by the
/// radii (touching, or near it) or the shapes do not move relative to each other.
std::optional<ShapeCastResult> cast_capsule_polygon(const Capsule& a, const Transform& xa, Vec2 va,
                                                    const Polygon& b, const Transform& xb,
                                                    Vec2 vb) noexcept {
  // Relative to B's origin first, so large world coordinates cancel before the rotation.
  const Vec2 offset = xa.p - xb.p;
  const Vec2 s0 = inv_rotate(xb.q, offset + rotate(xa.q, a.a));
  const Vec2 s1 = inv_rotate(xb.q, offset + rotate(xa.q, a.b));
  const Vec2 d = inv_rotate(xb.q, va - vb);
  if (!(length_squared(d) > 0.0f)) return std::nullopt;
  // -S runs from u0 = -s0 to u1 = -s1; edge i of B moves by u1 where its normal leans along
  // f = u1 - u0, else by u0.
  const Vec2 u0 = -s0;
  const Vec2 u1 = -s1;
  const Vec2 f = u1 - u0;
  const Vec2 m = normalize_or_zero(right_perp(f));  // outward normal of an inserted edge along f
  std::array<Vec2, kMaxPolygonVertices + 2> vertices;
  std::array<Vec2, kMaxPolygonVertices + 2> normals;
  int count = 0;
  bool previous_high = dot(b.normals[b.count - 1], f) > 0.0f;
  for (int i = 0; i < b.count; ++i) {
    const bool high = dot(b.normals[i], f) > 0.0f;
    if (high != previous_high) {  // -S's edge, from the end before to the end after
      vertices[count] = b.vertices[i] + (previous_high ? u1 : u0);
      normals[count] = high ? m : -m;
      ++count;
    }
    vertices[count] = b.vertices[i] + (high ? u1 : u0);
    normals[count] = b.normals[i];
    ++count;
    previous_high = high;
  }
  const float radius = a.radius + b.radius;
  bool inside = false;
  const detail::LocalHitN<2> hit = detail::ray_rounded_outline(
      {vertices.data(), normals.data(), count}, radius, Vec2{0.0f, 0.0f}, d, inside);
  if (inside) return std::nullopt;
  ShapeCastResult result;
  if (!hit.hit) return result;  // separated, fraction 1
  const float t = hit.fraction;
  const Vec2 n = -hit.normal;  // from A to B, B's frame (B - S's outward normal faces A)
  // The contact point: the middle of the touching features at t, between the surfaces.
  const float size_a = detail::proxy_size(ConvexProxy(a));
  const float size_b = detail::proxy_size(ConvexProxy(b));
  const float tie = detail::kFeatureTieTolerance * std::max(size_a, size_b);
  const Vec2 moved = t * d;
  const detail::TouchingFeature fa = detail::touching_feature(
      2, [&](int i) { return (i == 0 ? s0 : s1) + moved; }, n, 1.0f, tie);
  const detail::TouchingFeature fb = detail::touching_feature(
      b.count, [&](int i) { return b.vertices[i]; }, n, -1.0f, tie);
  result.hit = true;
  result.fraction = t;
  result.status = QueryStatus::hit;
  result.normal = rotate(xb.q, n);
  // B's frame at t: B has moved by t vb in the world.
  result.point =
      transform_point(xb, detail::touching_point(fa, a.radius, fb, b.radius, n)) + t * vb;
  return result;
}

/// A cast of B against A seen as A against B: the same time and point, the normal flipped.
ShapeCastResult seen_from_b(ShapeCastResult r) noexcept {
  r.normal = -r.normal;
  return r;
}

}  // namespace

void check_cast_input(const Transform& xa, Vec2 va, const Transform& xb, Vec2 vb) {
  if (!is_valid(xa)) throw InvalidInput("xa: not finite or rotation not unit length");
  if (!is_valid(xb)) throw InvalidInput("xb: not finite or rotation not unit length");
  if (!is_finite(va)) throw InvalidInput("va: not finite");
  if (!is_finite(vb)) throw InvalidInput("vb: not finite");
}

// GJK ray cast (van den Bergen 2004). The GJK machinery (simplex of Minkowski difference
// points, signed-barycentric reduction, witness points) is the one of gjk_distance
// (narrow/gjk.hpp), so it works on D = A - B in A's frame: A + t va and B + t vb touch at t
// when (A - B) + t (va - vb) holds the origin, i.e. when the ray point x(t) = t s,
// s = vb - va, is within the radius sum R of D (the lesson's ray into the Minkowski
// difference). The simplex points are stored relative to x, so the reduction finds the simplex
// point closest to x.
//
// Loop invariant: no contact before t. Each step takes the search direction n (unit, from the
// simplex's closest point towards x) and the support point p of D along n. The plane through p
// with normal n bounds D, so the separation at x is at least gap = (x - p).n - R. If gap > 0
// the ray may safely move forward to where it meets that plane (shifted by R); if it moves
// along or away from the plane instead, it never touches D. Then p joins the simplex. The
// loop ends when the upper bound of the separation at x (distance to the simplex, minus R) is
// within tolerance and the simplex is D's closest feature (lower and upper bounds agree).
template <int D>
ShapeCastResultN<D> gjk_shape_cast(const ConvexProxyN<D>& a, const TransformN<D>& xa, VecN<D> va,
                                   const ConvexProxyN<D>& b, const TransformN<D>& xb,
                                   VecN<D> vb) noexcept {
  COLLIDE_ASSERT(is_finite(va) && is_finite(vb), "shape cast velocities must be finite");
  COLLIDE_ASSERT(a.count() >= 1 && b.count() >= 1, "shape cast proxies must hold points");

  const FrameN<D> b_in_a = to_frame(inv_mul(xa, xb));
  const VecN<D> ray = inv_rotate(xa.q, vb - va);  // x(t) = t * ray, A's frame
  const float radius = a.radius() + b.radius();

  const float size_a = detail::proxy_size(a);
  const float size_b = detail::proxy_size(b);
  const float smaller = detail::smaller_size(size_a, size_b);
  const float magnitude = length(ray) + length(b_in_a.p) + size_a + size_b;
  const float tolerance = kShapeCastTolerance * smaller + kShapeCastRounding * magnitude;

  GjkSimplexN<D> simplex;
  // Start from the first core points (x = 0, so relative is absolute). The seed of
  // gjk_distance (support pair between the origins) saved no time here: casts converge in 2-3
  // iterations either way and the seed costs one support query.
  simplex.v[0] = gjk_vertex<D>(a, b, b_in_a, 0, 0);
  simplex.count = 1;

  ShapeCastResultN<D> result;
  float t = 0.0f;
  VecN<D> plane_normal{0.0f};  // of the last support plane advanced to, from D towards x
  VecN<D> n{0.0f};             // current search direction, unit
  float dist = 0.0f;              // distance from x to the simplex: upper bound of the cores'
  float lower_known = -INFINITY;  // best lower bound of the cores' distance at x (support planes)
  VecN<D> lower_normal{0.0f};     // normal of the plane that gives it
  bool advanced = false;
  bool converged = false;
  bool moved = true;
  bool stalled = false;
  // The reduced simplex of the last iteration, recorded only when x did not move in it (the
  // only case the stall test above reads it): copying it every iteration cost 6%.
  SimplexIds<D> previous(simplex);
  int last_ia = 0;               // last support points: where the next support walk starts
  int last_ib = 0;
  int iteration = 0;
  for (; iteration < kShapeCastMaxIterations; ++iteration) {
    if (gjk_reduce(simplex)) {
      converged = true;  // x inside the cores' difference: they touch or overlap at t
      break;
    }
    if (!moved && previous.same_as(simplex)) {
      // The new support point was dropped again and x did not move: no progress is possible
      // in float; the distance is as converged as it gets.
      converged = dist - radius <= tolerance;
      stalled = !converged;
      break;
    }
    // Direction from the simplex towards x (the points are stored relative to x): on an edge
    // the edge's perpendicular, on a triangle its normal (exact even when the points are far
    // from x, which the support planes built on it need).
    const VecN<D> w0 = simplex.v[0].w;
    float dd;
    const VecN<D> d = gjk_bounded_search_direction(simplex, dd);
    const float d_len = std::sqrt(dd);
    dist = -dot(d, w0) / d_len;
    if (!(dist > 0.0f)) {
      converged = true;  // x on the simplex: the cores touch at t
      break;
    }
    n = d * (1.0f / d_len);
    if (dist - radius <= tolerance && dist - lower_known <= tolerance &&
        dist * sin_between(n, lower_normal) <= tolerance && dot(n, lower_normal) > 0.0f) {
      // Converged without another support query (the usual end, right after the ray advanced
      // onto a plane): that plane bounds the distance from below, and the simplex's direction
      // is the plane's (within tolerance at this distance), so the simplex's closest point
      // lies on D's boundary in that plane: it is D's closest feature, not a chord.
      converged = true;
      break;
    }

    // Support point of D along n (the side facing x): A's farthest along n, B's along -n.
    // Walked from the last ones (polygons; other proxies scan).
    const int ia = a.support_index_from(n, last_ia);
    const int ib = b.support_index_from(inv_rotate(b_in_a, -n), last_ib);
    last_ia = ia;
    last_ib = ib;
    const VecN<D> wa = a.point(ia);
    const VecN<D> wb = transform_point(b_in_a, b.point(ib));
    VecN<D> w = (wa - wb) - t * ray;  // relative to x
    const float lower = -dot(n, w);  // lower bound of the cores' distance at x
    if (lower > lower_known) {
      lower_known = lower;
      lower_normal = n;
    }
    if (dist - radius <= tolerance && (dist - lower <= tolerance || dist <= tolerance)) {
      // Within tolerance of touching, and either the simplex is the closest feature (not a
      // chord through D), so its barycentric coordinates give the contact point, or x is
      // within tolerance of the simplex itself (cores touching: any simplex point that close
      // to x is on D's boundary, and the search direction is rounding noise).
      converged = true;
      break;
    }
    const float gap = lower - radius;  // lower bound of the separation at x
    moved = false;
    if (gap > 0.0f) {
      const float rn = dot(ray, n);
      if (!(rn < 0.0f)) {
        // Moving along or away from a plane that D lies behind: never closer than gap.
        if (gap > tolerance) break;
      } else {
        const float t_old = t;
        float t_new = t + gap / -rn;
        if (!(t_new <= 1.0f)) {
          // Reaches the plane only after the step; a hit only if within tolerance at t = 1.
          if (gap + (1.0f - t) * rn > tolerance) break;
          t_new = 1.0f;
        }
        const VecN<D> dx = (t_new - t) * ray;
        for (int i = 0; i < simplex.count; ++i) simplex.v[i].w -= dx;
        w -= dx;
        moved = t_new > t;
        t = t_new;
        plane_normal = n;
        advanced = true;
        // At the new x the plane through p is exactly the radius sum away (or, clamped at
        // t = 1, gap + (1 - t) rn further).
        lower_known = lower + (t_new - t_old) * rn;
        lower_normal = n;
      }
    }
    if (!moved) previous = SimplexIds<D>(simplex);
    if (holds(simplex, ia, ib)) {
      if (!moved) {
        // No new support point and x did not move: converged within rounding, and the
        // support plane says the separation is at most the tolerance.
        converged = true;
        break;
      }
    } else {
      GjkVertexN<D>& nv = simplex.v[simplex.count++];
      nv.wa = wa;
      nv.wb = wb;
      nv.w = w;
      nv.ia = ia;
      nv.ib = ib;
    }
  }
  result.iterations = iteration;
  result.fraction = t;

  if (!converged) {
    result.status = iteration >= kShapeCastMaxIterations || stalled ? QueryStatus::max_iterations
                                                                    : QueryStatus::separated;
    if (result.status == QueryStatus::separated) result.fraction = 1.0f;
    return result;
  }

  // Contact: the closest features' points from the simplex's barycentric coordinates.
  VecN<D> pa{0.0f};
  VecN<D> pb{0.0f};
  gjk_witness_points(simplex, pa, pb);
  // With x inside the triangle, gjk_witness_points returns A's point for both (right only at
  // x = 0); B's point is A's minus x, since x is the difference A - B there.
  if (simplex.count == D + 1) pb = pa - t * ray;
  // The normal, from A to B: D's outward normal at x (the direction from D towards x), which
  // is A's outward normal at the contact, since D = A - B. When the
  // cores are apart by more than the tolerance (rounded shapes), the direction between their
  // closest points: the simplex is their closest feature pair, so it is exact, and on a curved
  // surface it is the only right one. Otherwise the normal of the last support plane the ray
  // advanced to: x lies on it, so the shapes' separation along it is exactly zero at t, which
  // makes it a contact normal (at a vertex, one of the valid ones). Without an advance
  // (overlapped at t = 0) and with touching cores there is none.
  VecN<D> n_local{0.0f};
  if (simplex.count < D + 1 && dist > tolerance) {
    n_local = n;
  } else if (advanced) {
    n_local = plane_normal;
  }
  const VecN<D> surface_a = pa + t * inv_rotate(xa.q, va) + a.radius() * n_local;
  const VecN<D> surface_b = pb + t * inv_rotate(xa.q, vb) - b.radius() * n_local;
  result.hit = true;
  result.status = advanced ? QueryStatus::hit : QueryStatus::overlapped;
  result.point = transform_point(xa, 0.5f * (surface_a + surface_b));
  result.normal = rotate(xa.q, n_local);
  return result;
}

template ShapeCastResultN<2> gjk_shape_cast<2>(const ConvexProxyN<2>&, const Transform&, Vec2,
                                               const ConvexProxyN<2>&, const Transform&,
                                               Vec2) noexcept;
template ShapeCastResultN<3> gjk_shape_cast<3>(const ConvexProxyN<3>&, const Transform3&, Vec3,
                                               const ConvexProxyN<3>&, const Transform3&,
                                               Vec3) noexcept;

void check_cast_input(const Transform3& xa, Vec3 va, const Transform3& xb, Vec3 vb) {
  if (!is_valid(xa)) throw InvalidInput("xa: not finite or rotation not unit length");
  if (!is_valid(xb)) throw InvalidInput("xb: not finite or rotation not unit length");
  if (!is_finite(va)) throw InvalidInput("va: not finite");
  if (!is_finite(vb)) throw InvalidInput("vb: not finite");
}

ShapeCastResult3 shape_cast(const Shape3D& a, const Transform3& xa, Vec3 va, const Shape3D& b,
                            const Transform3& xb, Vec3 vb) {
  check_cast_input(xa, va, xb, vb);
  return gjk_shape_cast<3>(ConvexProxy3(a), xa, va, ConvexProxy3(b), xb, vb);
}

ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va, const Polygon& b,
                           const Transform& xb, Vec2 vb) {
  check_cast_input(xa, va, xb, vb);
  if (const std::optional<ShapeCastResult> r = cast_polygon_axes(a, xa, va, b, xb, vb)) return *r;
  return gjk_shape_cast<2>(ConvexProxy(a), xa, va, ConvexProxy(b), xb, vb);
}

ShapeCastResult shape_cast(const Circle& a, const Transform& xa, Vec2 va, const Polygon& b,
                           const Transform& xb, Vec2 vb) {
  check_cast_input(xa, va, xb, vb);
  if (const std::optional<ShapeCastResult> r = cast_circle_polygon(a, xa, va, b, xb, vb)) return *r;
  return gjk_shape_cast<2>(ConvexProxy(a), xa, va, ConvexProxy(b), xb, vb);
}

ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va, const Circle& b,
                           const Transform& xb, Vec2 vb) {
  return seen_from_b(shape_cast(b, xb, vb, a, xa, va));
}

ShapeCastResult shape_cast(const Capsule& a, const Transform& xa, Vec2 va, const Polygon& b,
                           const Transform& xb, Vec2 vb) {
  check_cast_input(xa, va, xb, vb);
  if (const std::optional<ShapeCastResult> r = cast_capsule_polygon(a, xa, va, b, xb, vb)) {
    return *r;
  }
  return gjk_shape_cast<2>(ConvexProxy(a), xa, va, ConvexProxy(b), xb, vb);
}

ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va, const Capsule& b,
                           const Transform& xb, Vec2 vb) {
  return seen_from_b(shape_cast(b, xb, vb, a, xa, va));
}

ShapeCastResult shape_cast(const Shape2D& a, const Transform& xa, Vec2 va, const Shape2D& b,
                           const Transform& xb, Vec2 vb) {
  return std::visit(
      [&](const auto& sa, const auto& sb) { return shape_cast(sa, xa, va, sb, xb, vb); }, a, b);
}

}  // namespace collide
