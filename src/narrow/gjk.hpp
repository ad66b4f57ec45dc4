#pragma once
/// @file
/// The GJK loop on the cores of two convex proxies, shared by `gjk_distance` (run to
/// convergence) and the boolean `overlap` (stopped as soon as a bound decides). Internal.
///
/// GJK (Gilbert, Johnson & Keerthi 1988) finds the point of the Minkowski difference
/// D = B - A = {b - a} closest to the origin without building D: it keeps a simplex (1 to 3
/// points of D, each the difference of a support point of B and one of A), finds the simplex's
/// closest point v to the origin, and adds the support point of D in the direction -v, until no
/// support point gets closer. |v| is then the distance between the cores and the barycentric
/// coordinates of v, applied to the A and B halves of the simplex vertices, give the witness
/// points. If the simplex ever contains the origin, the cores overlap.
///
/// The simplex solver uses signed barycentric coordinates: for each sub-simplex (vertex, edge,
/// triangle) the unnormalised barycentric coordinates of the origin's projection tell at once
/// whether the origin lies in that feature's Voronoi region, with no square roots and no
/// projection (Catto, "Computing Distance", GDC 2010; Ericson, Real-Time Collision Detection,
/// 9.5 and 5.1.5).
///
/// Everything runs in A's local frame: B is moved into it once by b_in_a = xa^-1 * xb, so large
/// world coordinates cancel before any arithmetic (a pair 1e4 from the origin is as accurate as a
/// pair at the origin).

#include <collide/core/tolerance.hpp>
#include <collide/core/transform.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/support.hpp>

#include <algorithm>
#include <array>

namespace collide::detail {

/// One simplex vertex: a core point of A, one of B (both in A's frame), their difference
/// w = wb - wa (a point of the Minkowski difference B - A), and w's barycentric weight in the
/// closest point.
struct GjkVertex {
  Vec2 wa{0.0f, 0.0f};
  Vec2 wb{0.0f, 0.0f};
  Vec2 w{0.0f, 0.0f};
  float weight = 1.0f;
  int ia = 0;
  int ib = 0;
};

/// 1 to 3 vertices of the Minkowski difference.
struct GjkSimplex {
  std::array<GjkVertex, 3> v{};
  int count = 0;
};

/// How the loop ended.
enum class GjkEnd : unsigned char {
  converged,       ///< no support point gets closer: v is the closest point of D
  overlapped,      ///< the simplex holds the origin (within rounding): cores overlap
  decided_apart,   ///< the policy's lower bound proved the shapes apart (overlap query only)
  decided_touch,   ///< the policy's upper bound proved the shapes touch (overlap query only)
  max_iterations,  ///< kGjkMaxIterations reached
};

/// The simplex vertex for core point `ia` of A and `ib` of B, with B placed by `b_in_a`.
[[nodiscard]] inline GjkVertex make_vertex(const ConvexProxy& a, const ConvexProxy& b,
                                           const Transform& b_in_a, int ia, int ib) noexcept {
  GjkVertex v;
  v.ia = ia;
  v.ib = ib;
  v.wa = a.point(ia);
  v.wb = transform_point(b_in_a, b.point(ib));
  v.w = v.wb - v.wa;
  v.weight = 1.0f;
  return v;
}

/// The first simplex vertex of a cold start: the support pair along the line between the
/// shapes' local origins (A's farthest point towards B's origin, B's farthest towards A's).
/// Shapes are usually modelled around their origin, so this pair is already close to the
/// closest features and saves iterations over starting from vertex 0 of each. Coincident
/// origins fall back to vertex 0 of each.
[[nodiscard]] inline GjkVertex seed_vertex(const ConvexProxy& a, const ConvexProxy& b,
                                           const Transform& b_in_a) noexcept {
  const Vec2 c = b_in_a.p;  // B's origin in A's frame
  if (!(dot(c, c) > 0.0f)) return make_vertex(a, b, b_in_a, 0, 0);
  return make_vertex(a, b, b_in_a, a.support_index(c), b.support_index(inv_rotate(b_in_a.q, -c)));
}

/// Reduce an edge simplex to the sub-simplex (edge or one end) whose Voronoi region holds the
/// origin, and set the barycentric weights of the origin's projection.
inline void solve_edge(GjkSimplex& s) noexcept {
  const Vec2 w1 = s.v[0].w;
  const Vec2 w2 = s.v[1].w;
  const Vec2 e12 = w2 - w1;
  // Unnormalised barycentric coordinates of the origin's projection on the line w1 w2:
  // u1 = (w2 - 0).e12 and u2 = (0 - w1).e12; a non-positive one puts the origin beyond the
  // other end.
  const float u1 = dot(w2, e12);
  const float u2 = -dot(w1, e12);
  if (u2 <= 0.0f) {  // region of w1
    s.v[0].weight = 1.0f;
    s.count = 1;
    return;
  }
  if (u1 <= 0.0f) {  // region of w2
    s.v[0] = s.v[1];
    s.v[0].weight = 1.0f;
    s.count = 1;
    return;
  }
  const float inv = 1.0f / (u1 + u2);
  s.v[0].weight = u1 * inv;
  s.v[1].weight = u2 * inv;
}

/// Reduce a triangle simplex to the sub-simplex whose Voronoi region holds the origin: one of
/// 3 vertices, 3 edges, or the interior (count stays 3: the cores overlap).
inline void solve_triangle(GjkSimplex& s) noexcept {
  const Vec2 w1 = s.v[0].w;
  const Vec2 w2 = s.v[1].w;
  const Vec2 w3 = s.v[2].w;
  // Edge barycentrics, as in solve_edge, for the three edges.
  const Vec2 e12 = w2 - w1;
  const float u12_1 = dot(w2, e12);
  const float u12_2 = -dot(w1, e12);
  const Vec2 e13 = w3 - w1;
  const float u13_1 = dot(w3, e13);
  const float u13_3 = -dot(w1, e13);
  const Vec2 e23 = w3 - w2;
  const float u23_2 = dot(w3, e23);
  const float u23_3 = -dot(w2, e23);
  // Triangle barycentrics: signed areas of the sub-triangles the origin makes with each edge,
  // times the orientation of the whole triangle (so they are positive inside either winding).
  const float area = cross(e12, e13);
  const float t1 = area * cross(w2, w3);
  const float t2 = area * cross(w3, w1);
  const float t3 = area * cross(w1, w2);

  if (u12_2 <= 0.0f && u13_3 <= 0.0f) {  // region of w1
    s.v[0].weight = 1.0f;
    s.count = 1;
    return;
  }
  if (u12_1 > 0.0f && u12_2 > 0.0f && t3 <= 0.0f) {  // region of edge w1 w2
    const float inv = 1.0f / (u12_1 + u12_2);
    s.v[0].weight = u12_1 * inv;
    s.v[1].weight = u12_2 * inv;
    s.count = 2;
    return;
  }
  if (u13_1 > 0.0f && u13_3 > 0.0f && t2 <= 0.0f) {  // region of edge w1 w3
    const float inv = 1.0f / (u13_1 + u13_3);
    s.v[0].weight = u13_1 * inv;
    s.v[2].weight = u13_3 * inv;
    s.v[1] = s.v[2];
    s.count = 2;
    return;
  }
  if (u12_1 <= 0.0f && u23_3 <= 0.0f) {  // region of w2
    s.v[0] = s.v[1];
    s.v[0].weight = 1.0f;
    s.count = 1;
    return;
  }
  if (u13_1 <= 0.0f && u23_2 <= 0.0f) {  // region of w3
    s.v[0] = s.v[2];
    s.v[0].weight = 1.0f;
    s.count = 1;
    return;
  }
  if (u23_2 > 0.0f && u23_3 > 0.0f && t1 <= 0.0f) {  // region of edge w2 w3
    const float inv = 1.0f / (u23_2 + u23_3);
    s.v[1].weight = u23_2 * inv;
    s.v[2].weight = u23_3 * inv;
    s.v[0] = s.v[2];
    s.count = 2;
    return;
  }
  // Interior: the origin is inside the triangle.
  const float inv = 1.0f / (t1 + t2 + t3);
  s.v[0].weight = t1 * inv;
  s.v[1].weight = t2 * inv;
  s.v[2].weight = t3 * inv;
}

/// Witness points on A's and B's cores (A's frame) from the barycentric weights.
inline void witness_points(const GjkSimplex& s, Vec2& pa, Vec2& pb) noexcept {
  switch (s.count) {
    case 1:
      pa = s.v[0].wa;
      pb = s.v[0].wb;
      break;
    case 2:
      pa = s.v[0].weight * s.v[0].wa + s.v[1].weight * s.v[1].wa;
      pb = s.v[0].weight * s.v[0].wb + s.v[1].weight * s.v[1].wb;
      break;
    default:
      // The origin is inside: the weighted A and B points coincide; take A's.
      pa = s.v[0].weight * s.v[0].wa + s.v[1].weight * s.v[1].wa + s.v[2].weight * s.v[2].wa;
      pb = pa;
      break;
  }
}

/// An early-exit policy that never decides: run GJK to convergence (distance queries).
struct GjkRunToEnd {
  /// Called with the simplex's closest point v (|v|^2 = vv): true stops with decided_touch.
  [[nodiscard]] constexpr bool touching(float /*vv*/) const noexcept { return false; }
  /// Called with the new support point w, searched in direction -v: true stops with
  /// decided_apart.
  [[nodiscard]] constexpr bool apart(Vec2 /*v*/, float /*vv*/, Vec2 /*w*/) const noexcept {
    return false;
  }
};

/// Run GJK on the simplex `s` (1..3 valid vertices on entry; on exit the final simplex with its
/// barycentric weights). `scale` is the size of the problem in A's frame (coordinate magnitude):
/// the origin counts as on the simplex when within kRelativeTolerance * scale of it.
/// `policy` may stop early (see GjkRunToEnd). `iterations` counts support points added.
template <class Policy>
[[nodiscard]] GjkEnd run_gjk(const ConvexProxy& a, const ConvexProxy& b, const Transform& b_in_a,
                             GjkSimplex& s, float scale, const Policy& policy,
                             int& iterations) noexcept {
  const float on_simplex = kRelativeTolerance * scale;
  const float on_simplex2 = on_simplex * on_simplex;
  iterations = 0;
  for (;;) {
    // The vertices before reduction: a new support point equal to one of them means GJK is
    // cycling on a flat piece of D (converged within rounding).
    std::array<int, 3> saved_a{};
    std::array<int, 3> saved_b{};
    const int saved_count = s.count;
    for (int i = 0; i < saved_count; ++i) {
      saved_a[i] = s.v[i].ia;
      saved_b[i] = s.v[i].ib;
    }

    if (s.count == 2) {
      solve_edge(s);
    } else if (s.count == 3) {
      solve_triangle(s);
      if (s.count == 3) return GjkEnd::overlapped;
    }

    // Closest point v of the simplex and search direction d towards the origin. On an edge,
    // d is the edge's perpendicular (exact), and v its projection, rather than the weighted sum
    // of the ends, which loses digits to cancellation near the origin.
    Vec2 v;
    Vec2 d;
    if (s.count == 1) {
      v = s.v[0].w;
      d = -v;
    } else {
      const Vec2 w1 = s.v[0].w;
      const Vec2 e12 = s.v[1].w - w1;
      d = cross(e12, -w1) > 0.0f ? left_perp(e12) : right_perp(e12);
      const float dd = dot(d, d);
      v = dd > 0.0f ? d * (dot(w1, d) / dd) : w1;
    }
    const float vv = dot(v, v);
    if (!(vv > on_simplex2)) return GjkEnd::overlapped;  // origin on the simplex (or NaN)
    if (policy.touching(vv)) return GjkEnd::decided_touch;
    if (iterations == kGjkMaxIterations) return GjkEnd::max_iterations;

    // Support point of D = B - A in direction d: B's farthest along d, A's farthest along -d.
    const int ib = b.support_index(inv_rotate(b_in_a.q, d));
    const int ia = a.support_index(-d);
    const Vec2 wb = transform_point(b_in_a, b.point(ib));
    const Vec2 wa = a.point(ia);
    const Vec2 w = wb - wa;
    ++iterations;

    if (policy.apart(v, vv, w)) return GjkEnd::decided_apart;
    // No progress: the new point is no closer along v than the simplex (van den Bergen's
    // relative test: |v|^2 - v.w is an upper bound on the gap between |v| and the distance,
    // times |v|).
    if (vv - dot(v, w) <= kGjkRelativeTolerance * vv) return GjkEnd::converged;
    for (int i = 0; i < saved_count; ++i) {
      if (saved_a[i] == ia && saved_b[i] == ib) return GjkEnd::converged;
    }
    GjkVertex& nv = s.v[s.count++];
    nv.wa = wa;
    nv.wb = wb;
    nv.w = w;
    nv.ia = ia;
    nv.ib = ib;
    nv.weight = 1.0f;
  }
}

/// The size of a proxy pair in A's frame for the relative tolerances of run_gjk: the largest
/// coordinate magnitude among the first simplex vertex's points, plus the radii.
[[nodiscard]] inline float gjk_scale(const GjkVertex& first, float radius_sum) noexcept {
  const float ma = std::max(std::abs(first.wa.x), std::abs(first.wa.y));
  const float mb = std::max(std::abs(first.wb.x), std::abs(first.wb.y));
  return std::max(ma, mb) + radius_sum;
}

}  // namespace collide::detail
