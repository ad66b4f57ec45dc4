#include <collide/narrow/overlap.hpp>

#include <collide/narrow/gjk.hpp>
#include "sat_lanes.hpp"
#include "segment_closest.hpp"

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/support.hpp>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace collide {
namespace {

/// Largest coordinate magnitude of `p`: rounding of arithmetic on p is about ulp of this.
[[nodiscard]] float coord_size(Vec2 p) noexcept { return std::max(std::abs(p.x), std::abs(p.y)); }

/// Circles, capsules and segments are all a segment [p, q] (a point for a circle) grown by a
/// radius. Here in A's local frame.
struct RoundedSegment {
  Vec2 p;
  Vec2 q;
  float radius;
};

[[nodiscard]] RoundedSegment rounded_segment(const Circle& c, const Transform& xf) noexcept {
  const Vec2 p = transform_point(xf, c.center);
  return {p, p, c.radius};
}
[[nodiscard]] RoundedSegment rounded_segment(const Capsule& c, const Transform& xf) noexcept {
  return {transform_point(xf, c.a), transform_point(xf, c.b), c.radius};
}
[[nodiscard]] RoundedSegment rounded_segment(const Segment& s, const Transform& xf) noexcept {
  return {transform_point(xf, s.a), transform_point(xf, s.b), 0.0f};
}

/// Closest distance^2 <= (ra + rb + slop)^2, where slop absorbs rounding at this scale, so that
/// exactly touching shapes count as overlapping.
[[nodiscard]] bool within_reach(float distance_squared, float radius_sum, float scale) noexcept {
  const float reach = radius_sum + kRelativeTolerance * scale;
  return distance_squared <= reach * reach;
}

/// Analytic test for two rounded segments; `a_is_point` / `b_is_point` (circles) pick the
/// cheapest closest-point routine at compile time.
template <bool a_is_point, bool b_is_point>
[[nodiscard]] bool overlap_rounded(const RoundedSegment& a, const RoundedSegment& b) noexcept {
  const float radius_sum = a.radius + b.radius;
  float scale = std::max({coord_size(a.p), coord_size(a.q), coord_size(b.p), coord_size(b.q)});
  scale += radius_sum;
  float d2;
  if constexpr (a_is_point && b_is_point) {
    d2 = distance_squared(a.p, b.p);  // circle-circle
  } else if constexpr (a_is_point) {
    d2 = detail::closest_on_segment<2>(a.p, b.p, b.q).distance_squared;
  } else if constexpr (b_is_point) {
    d2 = detail::closest_on_segment<2>(b.p, a.p, a.q).distance_squared;
  } else {
    d2 = detail::closest_between_segments<2>(a.p, a.q, b.p, b.q).distance_squared;
  }
  return within_reach(d2, radius_sum, scale);
}

/// GJK early-exit policy for a yes/no question: stop as soon as the upper bound of the core
/// distance is within reach (touching) or the lower bound exceeds it (apart). Squared and
/// multiplied out, with d, dd, k, dw as in GjkRunToEnd: -k/|d| <= reach and -dw/|d| > reach.
struct GjkOverlapBounds {
  float reach2;  ///< (ra + rb + slop)^2

  [[nodiscard]] bool touching(float k, float dd) const noexcept { return k * k <= reach2 * dd; }
  [[nodiscard]] bool apart(float dw, float dd) const noexcept {
    return dw < 0.0f && dw * dw > reach2 * dd;
  }
};

/// Boolean GJK on two proxies (van den Bergen 2003, 4.3.4: the separating-axis lower bound),
/// in 2D or 3D.
template <int D, SupportMap<D> PA, SupportMap<D> PB>
[[nodiscard]] bool overlap_gjk(const PA& a, const TransformN<D>& xa, const PB& b,
                               const TransformN<D>& xb) noexcept {
  const FrameN<D> b_in_a = to_frame(inv_mul(xa, xb));
  const float radius_sum = a.radius() + b.radius();
  GjkSimplexN<D> s;
  s.v[0] = gjk_seed_vertex<D>(a, b, b_in_a);
  s.count = 1;
  const float scale = gjk_scale<D>(s.v[0], radius_sum);
  const float reach = radius_sum + kRelativeTolerance * scale;
  const GjkOverlapBounds bounds{reach * reach};
  // The seed is the support pair along c = B's origin in A's frame, so every point of the
  // Minkowski difference A - B has c.x <= c.w0: a separating-axis test for free, which
  // settles most well-separated pairs before any iteration.
  const VecN<D> c = b_in_a.p;
  if (bounds.apart(dot(c, s.v[0].w), dot(c, c))) return false;
  int iterations = 0;
  switch (run_gjk<D>(a, b, b_in_a, s, scale, bounds, iterations)) {
    case GjkEnd::overlapped:
    case GjkEnd::decided_touch:
      return true;
    case GjkEnd::decided_apart:
    case GjkEnd::converged:  // converged only after touching() said no at this |v|
      return false;
    case GjkEnd::max_iterations:
      break;
  }
  VecN<D> pa;
  VecN<D> pb;
  gjk_witness_points(s, pa, pb);
  return distance_squared(pa, pb) <= reach * reach;
}

/// What the separating axis test could settle for a pair of polygons.
enum class SatVerdict { apart, overlapping, undecided };

/// Two polygons of up to two groups of vertices each: the separating axis test in registers
/// (sat_lanes.hpp) over both polygons' edge normals (Ericson, Real-Time Collision Detection,
/// 5.2.1). An axis separating the cores by more than the reach proves the shapes apart (a
/// separation is a lower bound of the distance); no axis separating them at all proves the
/// cores overlap (in 2D the edge normals of two convex polygons are the only candidate axes).
/// A gap between the two (within the rounding band, or rounded corners that may or may not
/// reach each other) is left undecided for GJK. For overlapping pairs, which GJK settles only
/// after building a simplex around the origin, this is 2-3x faster (bench/narrow_distance).
SatVerdict overlap_polygon_axes(const Polygon& a, const Transform& xa, const Polygon& b,
                                const Transform& xb) noexcept {
  SatVerdict verdict = SatVerdict::undecided;
#if COLLIDE_SMALL_POLYGON_SSE2
  const detail::SharedFrame f = detail::shared_frame(a, xa, xb);
  const float radius_sum = a.radius + b.radius;
  // The rounding band as GJK draws it: relative to the size of the coordinates in A's frame.
  const Vec2 b0 = rotate(f.b_in_a.q, b.vertices[0]) + f.b_in_a.p;
  const float scale = std::max(coord_size(f.origin), coord_size(b0)) + radius_sum;
  const float reach = radius_sum + kRelativeTolerance * scale;
  detail::with_lane_groups(a.count, b.count, [&](auto groups_a, auto groups_b) {
    detail::LanePair<groups_a(), groups_b()> p;
    if (!detail::separate_lanes(a, b, f, reach, p)) return;  // a NaN lane: GJK decides
    if (p.sep_a.separation > reach || p.sep_b.separation > reach) {
      verdict = SatVerdict::apart;
    } else if (p.sep_a.separation <= 0.0f && p.sep_b.separation <= 0.0f) {
      verdict = SatVerdict::overlapping;
    }
  });
#else
  static_cast<void>(a);
  static_cast<void>(xa);
  static_cast<void>(b);
  static_cast<void>(xb);
#endif
  return verdict;
}

}  // namespace

template <Shape2DType A, Shape2DType B>
bool overlap(const A& a, const Transform& xa, const B& b, const Transform& xb) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "overlap: transforms must be finite rigid");
  if constexpr (std::is_same_v<A, Polygon> && std::is_same_v<B, Polygon>) {
    const SatVerdict verdict = overlap_polygon_axes(a, xa, b, xb);
    if (verdict != SatVerdict::undecided) return verdict == SatVerdict::overlapping;
    return overlap_gjk<2>(ConvexProxy(a), xa, ConvexProxy(b), xb);
  } else if constexpr (std::is_same_v<A, Polygon> || std::is_same_v<B, Polygon>) {
    return overlap_gjk<2>(ConvexProxy(a), xa, ConvexProxy(b), xb);
  } else {
    // Everything in A's frame, so large world coordinates cancel first.
    return overlap_rounded<std::is_same_v<A, Circle>, std::is_same_v<B, Circle>>(
        rounded_segment(a, Transform{}), rounded_segment(b, inv_mul(xa, xb)));
  }
}

bool overlap(const Shape2D& a, const Transform& xa, const Shape2D& b,
             const Transform& xb) noexcept {
  return std::visit([&](const auto& sa, const auto& sb) { return overlap(sa, xa, sb, xb); }, a,
                    b);
}

// The 16 ordered pairs the header's template promises.
#define COLLIDE_OVERLAP_PAIR(A, B) \
  template bool overlap<A, B>(const A&, const Transform&, const B&, const Transform&) noexcept;
#define COLLIDE_OVERLAP_ROW(A)        \
  COLLIDE_OVERLAP_PAIR(A, Circle)     \
  COLLIDE_OVERLAP_PAIR(A, Capsule)    \
  COLLIDE_OVERLAP_PAIR(A, Polygon)    \
  COLLIDE_OVERLAP_PAIR(A, Segment)
COLLIDE_OVERLAP_ROW(Circle)
COLLIDE_OVERLAP_ROW(Capsule)
COLLIDE_OVERLAP_ROW(Polygon)
COLLIDE_OVERLAP_ROW(Segment)
#undef COLLIDE_OVERLAP_ROW
#undef COLLIDE_OVERLAP_PAIR

template <Shape3DType A, Shape3DType B>
bool overlap(const A& a, const Transform3& xa, const B& b, const Transform3& xb) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "overlap: transforms must be finite rigid");
  if constexpr (std::is_same_v<A, Sphere> && std::is_same_v<B, Sphere>) {
    // The offset between the centres, world positions subtracted first (as in A's frame).
    const Vec3 d = (xb.p - xa.p) + (rotate(xb.q, b.center) - rotate(xa.q, a.center));
    const float radius_sum = a.radius + b.radius;
    const float reach = radius_sum + kRelativeTolerance * (max_abs(d) + radius_sum);
    return dot(d, d) <= reach * reach;
  } else if constexpr (std::is_same_v<A, ConvexHull> && std::is_same_v<B, ConvexHull>) {
    return overlap_gjk<3>(HullSupportMap(a), xa, HullSupportMap(b), xb);
  } else {
    return overlap_gjk<3>(ConvexProxy3(a), xa, ConvexProxy3(b), xb);
  }
}

bool overlap(const Shape3D& a, const Transform3& xa, const Shape3D& b,
             const Transform3& xb) noexcept {
  return std::visit([&](const auto& sa, const auto& sb) { return overlap(sa, xa, sb, xb); }, a,
                    b);
}

// Every ordered pair of convex 3D shapes.
#define COLLIDE_OVERLAP3_PAIR(A, B) \
  template bool overlap<A, B>(const A&, const Transform3&, const B&, const Transform3&) noexcept;
#define COLLIDE_OVERLAP3_ROW(A)        \
  COLLIDE_OVERLAP3_PAIR(A, Sphere)     \
  COLLIDE_OVERLAP3_PAIR(A, Capsule3)   \
  COLLIDE_OVERLAP3_PAIR(A, Segment3)   \
  COLLIDE_OVERLAP3_PAIR(A, Box)        \
  COLLIDE_OVERLAP3_PAIR(A, ConvexHull) \
  COLLIDE_OVERLAP3_PAIR(A, Triangle)
COLLIDE_OVERLAP3_ROW(Sphere)
COLLIDE_OVERLAP3_ROW(Capsule3)
COLLIDE_OVERLAP3_ROW(Segment3)
COLLIDE_OVERLAP3_ROW(Box)
COLLIDE_OVERLAP3_ROW(ConvexHull)
COLLIDE_OVERLAP3_ROW(Triangle)
#undef COLLIDE_OVERLAP3_ROW
#undef COLLIDE_OVERLAP3_PAIR

}  // namespace collide
