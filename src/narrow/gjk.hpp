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
/// w = wb - wa (a point of the Minkowski difference B - A), and the core point indices.
/// Left uninitialised on purpose: simplices are built vertex by vertex in the hot loop.
struct GjkVertex {
  Vec2 wa;
  Vec2 wb;
  Vec2 w;
  int ia;
  int ib;
};

/// 1 to 3 vertices of the Minkowski difference (only the first `count` are meaningful).
struct GjkSimplex {
  std::array<GjkVertex, 3> v;
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
  GjkVertex v;  // NOLINT: every field is set below
  v.ia = ia;
  v.ib = ib;
  v.wa = a.point(ia);
  v.wb = transform_point(b_in_a, b.point(ib));
  v.w = v.wb - v.wa;
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

/// (ia, ib) packed into one int; indices are < kMaxPolygonVertices.
[[nodiscard]] constexpr int vertex_key(int ia, int ib) noexcept { return ia | (ib << 8); }

/// Reduce an edge simplex to the sub-simplex (edge or one end) whose Voronoi region holds the
/// origin. Only signs are needed here; the weights are computed once, at the end
/// (witness_points), so the loop does no division.
inline void solve_edge(GjkSimplex& s) noexcept {
  const Vec2 w1 = s.v[0].w;
  const Vec2 w2 = s.v[1].w;
  const Vec2 e12 = w2 - w1;
  // Unnormalised barycentric coordinates of the origin's projection on the line w1 w2:
  // u1 = (w2 - 0).e12 and u2 = (0 - w1).e12; a non-positive one puts the origin beyond the
  // other end.
  if (!(-dot(w1, e12) > 0.0f)) {  // u2 <= 0: region of w1
    s.count = 1;
  } else if (!(dot(w2, e12) > 0.0f)) {  // u1 <= 0: region of w2
    s.v[0] = s.v[1];
    s.count = 1;
  }
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
    s.count = 1;
  } else if (u12_1 > 0.0f && u12_2 > 0.0f && t3 <= 0.0f) {  // region of edge w1 w2
    s.count = 2;
  } else if (u13_1 > 0.0f && u13_3 > 0.0f && t2 <= 0.0f) {  // region of edge w1 w3
    s.v[1] = s.v[2];
    s.count = 2;
  } else if (u12_1 <= 0.0f && u23_3 <= 0.0f) {  // region of w2
    s.v[0] = s.v[1];
    s.count = 1;
  } else if (u13_1 <= 0.0f && u23_2 <= 0.0f) {  // region of w3
    s.v[0] = s.v[2];
    s.count = 1;
  } else if (u23_2 > 0.0f && u23_3 > 0.0f && t1 <= 0.0f) {  // region of edge w2 w3
    s.v[0] = s.v[2];
    s.count = 2;
  }
  // else the interior: the origin is inside the triangle.
}

/// Witness points on A's and B's cores (A's frame): the barycentric coordinates of the
/// simplex's closest point to the origin, applied to the A and B halves of its vertices.
inline void witness_points(const GjkSimplex& s, Vec2& pa, Vec2& pb) noexcept {
  if (s.count == 1) {
    pa = s.v[0].wa;
    pb = s.v[0].wb;
  } else if (s.count == 2) {
    const Vec2 e12 = s.v[1].w - s.v[0].w;
    const float u1 = dot(s.v[1].w, e12);
    const float u2 = -dot(s.v[0].w, e12);
    const float inv = 1.0f / (u1 + u2);  // > 0: solve_edge kept the edge only if both are
    const float a1 = u1 * inv;
    const float a2 = u2 * inv;
    pa = a1 * s.v[0].wa + a2 * s.v[1].wa;
    pb = a1 * s.v[0].wb + a2 * s.v[1].wb;
  } else {
    // The origin is inside: the weighted A and B points coincide; take A's.
    const Vec2 w1 = s.v[0].w;
    const Vec2 w2 = s.v[1].w;
    const Vec2 w3 = s.v[2].w;
    const float t1 = cross(w2, w3);
    const float t2 = cross(w3, w1);
    const float t3 = cross(w1, w2);
    const float sum = t1 + t2 + t3;  // twice the signed area; 0 only for a flat triangle
    if (sum != 0.0f) {
      const float inv = 1.0f / sum;
      pa = (t1 * inv) * s.v[0].wa + (t2 * inv) * s.v[1].wa + (t3 * inv) * s.v[2].wa;
    } else {
      pa = s.v[0].wa;
    }
    pb = pa;
  }
}

/// An early-exit policy that never decides: run GJK to convergence (distance queries).
///
/// Policies see the bounds on the core distance without divisions: `d` is the search
/// direction (towards the origin, not unit), dd = |d|^2, k = d.v for the simplex's closest
/// point v (k < 0, and |v| = -k / |d| is the upper bound), and dw = d.w for the new support
/// point w (every point of the Minkowski difference has d.x <= dw, so if dw < 0 the distance
/// is at least -dw / |d|: the lower bound).
struct GjkRunToEnd {
  /// Upper bound -k/|d| known: true stops with decided_touch.
  [[nodiscard]] constexpr bool touching(float /*k*/, float /*dd*/) const noexcept {
    return false;
  }
  /// Lower bound -dw/|d| known: true stops with decided_apart.
  [[nodiscard]] constexpr bool apart(float /*dw*/, float /*dd*/) const noexcept { return false; }
};

/// Run GJK on the simplex `s` (1..3 valid vertices on entry; on exit the final simplex).
/// `scale` is the size of the problem in A's frame (coordinate magnitude): the origin counts as
/// on the simplex when within kRelativeTolerance * scale of it. `policy` may stop early (see
/// GjkRunToEnd). `iterations` counts support points evaluated.
template <class Policy>
[[nodiscard]] GjkEnd run_gjk(const ConvexProxy& a, const ConvexProxy& b, const Transform& b_in_a,
                             GjkSimplex& s, float scale, const Policy& policy,
                             int& iterations) noexcept {
  const float on_simplex = kRelativeTolerance * scale;
  const float on_simplex2 = on_simplex * on_simplex;
  iterations = 0;
  for (;;) {
    // The vertices before reduction, as (ia, ib) keys: a new support point equal to one of
    // them means GJK is cycling on a flat piece of D (converged within rounding). Unused slots
    // hold -1, so the test below is three compares and no loop.
    std::array<int, 3> saved{-1, -1, -1};
    for (int i = 0; i < s.count; ++i) saved[i] = vertex_key(s.v[i].ia, s.v[i].ib);

    if (s.count == 2) {
      solve_edge(s);
    } else if (s.count == 3) {
      solve_triangle(s);
      if (s.count == 3) return GjkEnd::overlapped;
    }

    // Search direction d from the simplex's closest point v towards the origin. On an edge, d
    // is the edge's perpendicular (exact), not -v computed from weights, which loses digits to
    // cancellation near the origin.
    Vec2 d;
    if (s.count == 1) {
      d = -s.v[0].w;
    } else {
      const Vec2 w1 = s.v[0].w;
      const Vec2 e12 = s.v[1].w - w1;
      // The side of the edge the origin is on (right_perp = -left_perp), without a branch.
      d = left_perp(e12) * (cross(e12, -w1) > 0.0f ? 1.0f : -1.0f);
    }
    const float dd = dot(d, d);
    const float k = dot(d, s.v[0].w);  // = -|v| |d|
    // Origin on the simplex (|v| <= on_simplex), or NaN: the cores touch or overlap.
    if (!(k < 0.0f && k * k > on_simplex2 * dd)) return GjkEnd::overlapped;
    if (policy.touching(k, dd)) return GjkEnd::decided_touch;
    if (iterations == kGjkMaxIterations) return GjkEnd::max_iterations;

    // Support point of D = B - A in direction d: B's farthest along d, A's farthest along -d.
    // Walk from the newest simplex vertex's points: the support moves little per iteration.
    const GjkVertex& last = s.v[s.count - 1];
    const int ib = b.support_index_from(inv_rotate(b_in_a.q, d), last.ib);
    const int ia = a.support_index_from(-d, last.ia);
    const Vec2 wb = transform_point(b_in_a, b.point(ib));
    const Vec2 wa = a.point(ia);
    const Vec2 w = wb - wa;
    ++iterations;

    const float dw = dot(d, w);
    if (policy.apart(dw, dd)) return GjkEnd::decided_apart;
    // No progress: the gap between the upper and lower bounds, (dw - k) / |d|, is within
    // kGjkRelativeTolerance of the upper bound -k / |d| (van den Bergen 2003, 4.3.4).
    if (dw - k <= kGjkRelativeTolerance * -k) return GjkEnd::converged;
    const int key = vertex_key(ia, ib);
    if ((key == saved[0]) | (key == saved[1]) | (key == saved[2])) return GjkEnd::converged;
    GjkVertex& nv = s.v[s.count++];
    nv.wa = wa;
    nv.wb = wb;
    nv.w = w;
    nv.ia = ia;
    nv.ib = ib;
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
