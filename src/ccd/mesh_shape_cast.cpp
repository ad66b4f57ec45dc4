// Shape casts of convex shapes against the level shapes (TriangleMesh, HeightField): the GJK
// ray cast of gjk_shape_cast against each candidate triangle, the earliest kept, candidates
// from the level's spatial index along A's swept box. Work happens in A's local frame at the
// start of the step (the triangles moved there, one rotation per corner), as in
// narrow/mesh_query.cpp, so large world coordinates cancel first. Spheres and capsules ask the
// triangle's prism planes first (LevelCast::plane_test): they skip the triangles the planes
// separate from their swept core, take a first touch on the face in closed form, and put off
// the triangles they can reach only later.

#include <collide/ccd/shape_cast.hpp>

#include "shape_size.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <type_traits>
#include <variant>

namespace collide {
namespace {

constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();

/// The state of one cast: A's proxy and motion relative to the level, both in A's frame.
struct LevelCast {
  ConvexProxy3 proxy;
  Frame3 stored_to_a;   ///< the level's stored frame placed in A's frame
  Vec3 va_local;        ///< A's translation, A's frame
  Vec3 vl_local;        ///< the level's translation, A's frame
  ShapeCastResult3 best{};
  std::uint32_t best_t = kNoTriangle;
  ShapeCastResult3 stalled{};  ///< the earliest safe fraction of a cast that hit the iteration cap
  bool any_stalled = false;
  /// A sphere or capsule: its core (A's frame) and radius, for prism_separates.
  bool rounded_core = false;
  Vec3 core0{0.0f};
  Vec3 core1{0.0f};
  float core_radius = 0.0f;
  float core_size = 0.0f;  ///< detail::proxy_size of A (the cast's tolerance scales with it)
  Vec3 motion{0.0f};       ///< A's motion against the level, va_local - vl_local
  float motion_length = 0.0f;
  /// Triangles `plane_test` found `outside`, with their first reach, for cast_deferred.
  struct Deferred {
    Triangle tri;  ///< A's frame
    float from;
    std::uint32_t t;
  };
  static constexpr int kMaxDeferred = 8;  ///< more go to GJK at once
  std::array<Deferred, kMaxDeferred> deferred{};
  int deferred_count = 0;

  /// What the planes of the triangle's prism tell a sphere's or capsule's cast before GJK is
  /// asked (`tri` in A's frame, the triangle still and A moving by `motion`):
  ///  - `separated`: a plane of the prism (its own, or one through an edge along its normal)
  ///    has A's core at the start and at the end of the step wholly beyond it by more than A's
  ///    radius plus the cast's target separation (gjk_shape_cast's tolerance for this pair):
  ///    the swept core is the hull of those points, so the cast would report no touch (a
  ///    separating axis of the swept core and the triangle); or the core is beyond an edge's
  ///    plane and, in that plane's and the triangle's distances together, farther than the
  ///    reach from the edge. In bench_world3d's character moves about half the candidates end
  ///    here (a GJK miss costs about 500 TSC cycles).
  ///  - `later`: A first reaches the triangle's plane (grown by its radius) at a fraction no
  ///    earlier than `clip` (the best touch so far), so it touches the triangle no earlier than
  ///    `clip`, if at all.
  ///  - `face`: A's core end nearer the plane first reaches it (grown by the radius) at a
  ///    fraction before `clip` at a point inside the triangle: the first touch, in closed form,
  ///    filled into `hit` as gjk_shape_cast reports it (A's frame, the triangle moving by
  ///    vl_local). The plane is the earliest any part of the triangle can be met.
  ///  - `outside`: A first reaches the plane before `clip`, but outside the triangle: it can
  ///    touch the triangle only after `from` (that first reach), if at all. For GJK, which
  ///    `test` puts off (see `deferred`).
  ///  - `unknown`: for GJK (a start within the target separation of the plane, a core across
  ///    it, a degenerate triangle).
  /// A character's casts meet floors and walls face on: most hits are `face` (a GJK hit costs
  /// about 950 cycles).
  enum class PlaneVerdict { separated, later, face, outside, unknown };
  [[nodiscard]] PlaneVerdict plane_test(const Triangle& tri, float clip, ShapeCastResult3& hit,
                                        float& from) const noexcept {
    const std::array<Vec3, 3>& c = tri.vertices;
    const Vec3 e[3] = {c[1] - c[0], c[2] - c[1], c[0] - c[2]};
    // The area normal made in double (triangle_area_normal), rounded once: made in float, a
    // sliver's plane turns by FLT_EPSILON times its length over its width, and the tests below
    // called a sphere that touches such a sliver first "separated" from it (the fuzzer's cast
    // check, stop 105: a cast hit the triangle behind it, 0.28 of its step late).
    // Every test below is homogeneous in nn: a normal whose nonzero square leaves float's normal
    // range (a needle 1e-22 wide: a subnormal square made the unit normal 1.003 long and the
    // face hit 0.3% late, finding 24) is scaled by a power of two first, from the double normal
    // made again (not kept across the common path). A square that underflows to zero goes on to
    // `unknown` (GJK), as before. Rescaled, a field spaced 1.4e-45 was cast 10% early (finding
    // 25): a needle that thin meets a cast in its own plane beyond its tip, and the side test of
    // its 1.4e-45 edge there, that width times the point's distance, underflowed to zero and read
    // as on the edge (inside). A nonzero square bounds that: width times length is then at least
    // 3.7e-23, so such a product underflows only within 1e-15 of the length from the tip.
    Vec3 nn = Vec3(triangle_area_normal(c[0], c[1], c[2]));
    float nn2 = dot(nn, nn);
    if (nn2 > 0.0f && !(nn2 >= kTriangleNormalDirectMinSquared && nn2 <= kTriangleNormalDirectMaxSquared)) [[unlikely]] {
      nn = Vec3(scaled_to_unit_magnitude(triangle_area_normal(c[0], c[1], c[2])));
      nn2 = dot(nn, nn);
    }
    // gjk_shape_cast's tolerance, B's size being the triangle's (corner 0 to corner 2).
    const float size_b = length(e[2]);
    const float tolerance = kShapeCastTolerance * detail::smaller_size(core_size, size_b) +
                            kShapeCastRounding * (motion_length + core_size + size_b);
    const float reach = core_radius + tolerance;
    const float rr = reach * reach;
    // The least signed distance (times |o|) of the core's ends at the start and the end of
    // the step from the plane through `at` on the side `o` points to.
    const auto lowest = [&](Vec3 o, Vec3 at) noexcept {
      const float g0 = dot(core0 - at, o);
      const float g1 = dot(core1 - at, o);
      const float mo = dot(motion, o);
      return std::min({g0, g1, g0 + mo, g1 + mo});
    };
    // All of them farther than the reach (o of squared length oo).
    const auto beyond = [&](float lo, float oo) noexcept { return lo > 0.0f && lo * lo > rr * oo; };
    if (beyond(lowest(nn, c[0]), nn2) || beyond(lowest(-nn, c[0]), nn2)) return PlaneVerdict::separated;
    // Outward in the plane (for the winding of nn), length |e| |nn|; only its outer side.
    const Vec3 out[3] = {cross(e[0], nn), cross(e[1], nn), cross(e[2], nn)};
    float edge_lo[3];
    for (int k = 0; k < 3; ++k) {
      edge_lo[k] = lowest(out[k], c[k]);
      if (beyond(edge_lo[k], dot(e[k], e[k]) * nn2)) return PlaneVerdict::separated;
    }
    const float len_n = std::sqrt(nn2);
    if (!(len_n > 0.0f)) return PlaneVerdict::unknown;
    Vec3 n = nn / len_n;
    // Beyond an edge's plane, but by less than the reach (a core beside a ledge, over the wall
    // below it): the triangle lies in its own plane on the edge plane's inner side, so a point
    // beyond the edge plane by a and off the triangle's plane by b is at least sqrt(a^2 + b^2)
    // from it. In those two distances the swept core is the parallelogram of its ends at the
    // start and the end; apart from the origin by more than the reach, it misses.
    for (int k = 0; k < 3; ++k) {
      if (!(edge_lo[k] > 0.0f)) continue;
      const Vec3 o = out[k] / (length(e[k]) * len_n);
      const Vec2 p0(dot(core0 - c[k], o), dot(core0 - c[k], n));
      const Vec2 p1(dot(core1 - c[k], o), dot(core1 - c[k], n));
      const Vec2 m(dot(motion, o), dot(motion, n));
      // Squared distance from the origin to the segment from p to p + d.
      const auto d2 = [](Vec2 p, Vec2 d) noexcept {
        const float dd = dot(d, d);
        const float t = dd > 0.0f ? std::clamp(-dot(p, d) / dd, 0.0f, 1.0f) : 0.0f;
        const Vec2 x = p + t * d;
        return dot(x, x);
      };
      if (std::min({d2(p0, p1 - p0), d2(p0 + m, p1 - p0), d2(p0, m), d2(p1, m)}) > rr) {
        return PlaneVerdict::separated;
      }
    }
    // The face: the plane seen from the core's side, both ends beyond the reach at the start.
    float g0 = dot(core0 - c[0], n);
    float g1 = dot(core1 - c[0], n);
    if (g0 < 0.0f) {
      n = -n;
      g0 = -g0;
      g1 = -g1;
    }
    const float g = std::min(g0, g1);
    const float approach = -dot(motion, n);  // > 0: beyond would have said separated otherwise
    if (!(g > reach) || !(approach > 0.0f)) return PlaneVerdict::unknown;
    const float fraction = (g - core_radius) / approach;
    if (!(fraction <= 1.0f)) return PlaneVerdict::unknown;  // within the tolerance at the end
    const Vec3 q = (g0 <= g1 ? core0 : core1) + fraction * motion - core_radius * n;
    bool inside = true;
    for (int k = 0; k < 3 && inside; ++k) inside = dot(cross(e[k], q - c[k]), nn) >= 0.0f;
    if (!inside) {
      from = fraction;
      return fraction >= clip ? PlaneVerdict::later : PlaneVerdict::outside;
    }
    if (!(fraction < clip)) return PlaneVerdict::later;
    hit.hit = true;
    hit.status = QueryStatus::hit;
    hit.fraction = fraction;
    hit.point = q + fraction * vl_local;
    hit.normal = -n;  // from A to the triangle
    hit.iterations = 0;
    return PlaneVerdict::face;
  }

  /// The best fraction so far, the bound past which no triangle matters (1 before a hit).
  [[nodiscard]] float clip() const noexcept { return best_t == kNoTriangle ? 1.0f : best.fraction; }

  /// Cast against triangle `t` (stored corners); returns the new clip fraction (0: stop).
  float test(std::uint32_t t, const std::array<Vec3, 3>& c) noexcept {
    const Triangle tri{{transform_point(stored_to_a, c[0]), transform_point(stored_to_a, c[1]),
                        transform_point(stored_to_a, c[2])}};
    if (!rounded_core) return keep(t, gjk(tri));
    ShapeCastResult3 r;
    float from = 0.0f;
    switch (plane_test(tri, clip(), r, from)) {
      case PlaneVerdict::separated:
      case PlaneVerdict::later: return clip();
      case PlaneVerdict::face: return keep(t, r);
      case PlaneVerdict::outside:
        if (deferred_count < kMaxDeferred) {
          deferred[deferred_count++] = {tri, from, t};
          return clip();
        }
        break;
      case PlaneVerdict::unknown: break;
    }
    return keep(t, gjk(tri));
  }

  /// gjk_shape_cast against `tri` (A's frame, moving by vl_local).
  [[nodiscard]] ShapeCastResult3 gjk(const Triangle& tri) const noexcept {
    return gjk_shape_cast<3>(proxy, Transform3{}, va_local, ConvexProxy3(tri), Transform3{}, vl_local);
  }

  /// Takes `r`, the cast against triangle `t`, into the best; returns the new clip fraction.
  float keep(std::uint32_t t, const ShapeCastResult3& r) noexcept {
    if (r.hit) {
      if (best_t == kNoTriangle || r.fraction < best.fraction) {
        best = r;
        best_t = t;
      }
      return best.fraction > 0.0f ? best.fraction : 0.0f;
    }
    if (r.status == QueryStatus::max_iterations && (!any_stalled || r.fraction < stalled.fraction)) {
      stalled = r;
      any_stalled = true;
    }
    return clip();
  }

  /// The triangles put off as `outside`, cast by GJK nearest first reach first while that
  /// reach is before the best touch (the others cannot be touched earlier). A character's end
  /// probe meets the floor triangle it stands over face on, and the floor triangles beside it
  /// reach their shared plane no earlier: put off, they are never cast.
  void cast_deferred() noexcept {
    std::sort(deferred.begin(), deferred.begin() + deferred_count,
              [](const Deferred& a, const Deferred& b) { return a.from < b.from; });
    for (int i = 0; i < deferred_count && deferred[i].from < clip() && clip() > 0.0f; ++i) {
      keep(deferred[i].t, gjk(deferred[i].tri));
    }
    deferred_count = 0;
  }

  /// The result in the world.
  ShapeCastResult3 finish(const Transform3& xa, std::uint32_t* triangle) noexcept {
    cast_deferred();
    if (triangle != nullptr) *triangle = best_t;
    ShapeCastResult3 r;
    if (best_t != kNoTriangle && !(any_stalled && stalled.fraction < best.fraction)) {
      r = best;
    } else if (any_stalled) {
      r = stalled;
      if (triangle != nullptr) *triangle = kNoTriangle;
    } else {
      return r;  // separated over the whole step
    }
    if (r.hit) {
      r.point = transform_point(xa, r.point);
      r.normal = rotate(xa.q, r.normal);
    }
    return r;
  }
};

/// The placement of a cast: A's box in the level's stored frame, the relative translation there.
struct CastSetup {
  LevelCast cast;
  Aabb3 box;          ///< A's box at the start, stored frame, fattened by the rounding slop
  Vec3 translation;   ///< A's translation relative to the level, stored frame
};

template <Shape3DType A>
CastSetup setup(const A& a, const Transform3& xa, Vec3 va, const Transform3& xl, Vec3 vl,
                Vec3 offset) noexcept {
  const Transform3 level_in_a = inv_mul(xa, xl, offset);
  const Transform3 a_in_stored = inv_mul(level_in_a, Transform3{});
  CastSetup s{LevelCast{ConvexProxy3(a), Frame3::from(level_in_a), inv_rotate(xa.q, va),
                        inv_rotate(xa.q, vl)},
              compute_aabb(a, a_in_stored), inv_rotate(xl.q, va - vl)};
  // Boxes that touch within rounding count (the cast's own tolerance decides the rest).
  const float slop = kShapeCastRounding * (max_abs(s.box.min) + max_abs(s.box.max) +
                                           max_abs(s.translation)) +
                     kShapeCastTolerance * max_abs(s.box.max - s.box.min);
  s.box = fatten(s.box, slop);
  s.cast.core_size = detail::proxy_size(s.cast.proxy);
  s.cast.motion = s.cast.va_local - s.cast.vl_local;
  s.cast.motion_length = length(s.cast.motion);
  if constexpr (std::is_same_v<A, Capsule3>) {
    s.cast.rounded_core = true;
    s.cast.core0 = a.a;
    s.cast.core1 = a.b;
    s.cast.core_radius = a.radius;
  } else if constexpr (std::is_same_v<A, Sphere>) {
    s.cast.rounded_core = true;
    s.cast.core0 = a.center;
    s.cast.core1 = a.center;
    s.cast.core_radius = a.radius;
  }
  return s;
}

template <Shape3DType A>
ShapeCastResult3 cast_mesh(const A& a, const Transform3& xa, Vec3 va, const TriangleMesh& mesh,
                           const Transform3& xm, Vec3 vm, std::uint32_t* triangle) noexcept {
  CastSetup s = setup(a, xa, va, xm, vm, mesh.origin);
  mesh.bvh.box_cast(s.box, s.translation, [&](std::uint32_t t, float) -> float {
    return s.cast.test(t, {mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)});
  });
  return s.cast.finish(xa, triangle);
}

template <Shape3DType A>
ShapeCastResult3 cast_field(const A& a, const Transform3& xa, Vec3 va, const HeightField& field,
                            const Transform3& xf, Vec3 vf, std::uint32_t* triangle) noexcept {
  CastSetup s = setup(a, xa, va, xf, vf, field.origin);
  const Aabb3& box = s.box;
  const Aabb3 swept = merge(box, Aabb3{box.min + s.translation, box.max + s.translation});
  float clip = 1.0f;
  field.query(Aabb3{swept.min + field.origin, swept.max + field.origin}, [&](std::uint32_t t) -> bool {
    const std::array<Vec3, 3> c = field.grid_corners(t);
    if (clip < 1.0f) {
      // A's box swept only up to the best fraction so far.
      const Vec3 d = clip * s.translation;
      const Aabb3 part = merge(box, Aabb3{box.min + d, box.max + d});
      const Aabb3 tb{glm::min(glm::min(c[0], c[1]), c[2]), glm::max(glm::max(c[0], c[1]), c[2])};
      if (!overlap(part, tb)) return true;
    }
    clip = s.cast.test(t, c);
    return clip > 0.0f;
  });
  return s.cast.finish(xa, triangle);
}

}  // namespace

template <ConvexShape3DType A>
ShapeCastResult3 shape_cast(const A& a, const Transform3& xa, Vec3 va, const TriangleMesh& mesh,
                            const Transform3& xm, Vec3 vm, std::uint32_t* triangle) {
  check_cast_input(xa, va, xm, vm);
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit([&](const auto& s) { return cast_mesh(s, xa, va, mesh, xm, vm, triangle); }, a);
  } else {
    return cast_mesh(a, xa, va, mesh, xm, vm, triangle);
  }
}

template <ConvexShape3DType A>
ShapeCastResult3 shape_cast(const A& a, const Transform3& xa, Vec3 va, const HeightField& field,
                            const Transform3& xf, Vec3 vf, std::uint32_t* triangle) {
  check_cast_input(xa, va, xf, vf);
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit([&](const auto& s) { return cast_field(s, xa, va, field, xf, vf, triangle); },
                      a);
  } else {
    return cast_field(a, xa, va, field, xf, vf, triangle);
  }
}

#define COLLIDE_LEVEL_CAST(A)                                                                    \
  template ShapeCastResult3 shape_cast<A>(const A&, const Transform3&, Vec3, const TriangleMesh&, \
                                          const Transform3&, Vec3, std::uint32_t*);              \
  template ShapeCastResult3 shape_cast<A>(const A&, const Transform3&, Vec3, const HeightField&,  \
                                          const Transform3&, Vec3, std::uint32_t*);
COLLIDE_LEVEL_CAST(Sphere)
COLLIDE_LEVEL_CAST(Capsule3)
COLLIDE_LEVEL_CAST(Segment3)
COLLIDE_LEVEL_CAST(Box)
COLLIDE_LEVEL_CAST(ConvexHull)
COLLIDE_LEVEL_CAST(Triangle)
COLLIDE_LEVEL_CAST(Shape3D)
#undef COLLIDE_LEVEL_CAST

}  // namespace collide
