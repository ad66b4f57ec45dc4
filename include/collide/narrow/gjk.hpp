#pragma once
/// @file
/// GJK, once for 2D and 3D: the loop that `distance`, `overlap`, `shape_cast` and
/// `time_of_impact` all run, templated on the dimension and on any two support maps.
///
/// GJK (Gilbert, Johnson & Keerthi 1988) finds the point of the Minkowski difference
/// A - B = {a - b} closest to the origin without building it (the lesson: A and B overlap iff
/// A - B contains the origin, and a - b closest to the origin gives the closest points). It
/// keeps a simplex (1 to D + 1 points of A - B, each the difference of a support point of A and
/// one of B), reduces it to the sub-simplex whose Voronoi region holds the origin, and adds the
/// support point of A - B in the direction from that sub-simplex towards the origin, until no
/// support point gets closer. The simplex's distance to the origin is then the distance between
/// the cores, and its barycentric coordinates, applied to the A and B halves of its vertices,
/// give the witness points. If the simplex ever holds the origin, the cores overlap.
///
/// The simplex solver decides regions by signs of unnormalised barycentric coordinates, with no
/// square root and no division: in 2D the signed lengths and areas of Catto ("Computing
/// Distance", GDC 2010; Ericson, Real-Time Collision Detection, 9.5 and 5.1.5); in 3D the signed
/// volumes of Montanari, Petrinic & Barbieri ("Improving the GJK algorithm for faster and more
/// reliable distance queries between convex objects", ACM TOG 2017): a tetrahedron's four
/// sub-volumes with the origin in place of each vertex, a triangle's sub-areas projected on the
/// coordinate plane where it is largest, a segment's sub-lengths on its longest axis.
///
/// The search direction is computed exactly from the kept feature (the origin itself for a
/// vertex; the perpendicular from an edge; a triangle's normal), never from the barycentric
/// weights, which lose digits to cancellation near the origin.
///
/// Everything runs in A's local frame: B is placed there once (`b_in_a`), so large world
/// coordinates cancel before any arithmetic.

#include <collide/core/aabb.hpp>  // VecN
#include <collide/core/config.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/core/transform3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>

namespace collide {

/// What GJK needs of a convex shape: its core as indexed points (the shape is their convex hull
/// grown by `radius()`), local space. `support_index(d)`: a point farthest along direction d
/// (ties: any, but deterministic). `support_index_from(d, start)`: the same, allowed to walk
/// from a previous answer (a shape without a faster way just scans). `ConvexProxyN` is the
/// support map of every collide shape.
template <class P, int D>
concept SupportMap = requires(const P& p, VecN<D> d, int i) {
  { p.support_index(d) } -> std::convertible_to<int>;
  { p.support_index_from(d, i) } -> std::convertible_to<int>;
  { p.point(i) } -> std::convertible_to<VecN<D>>;
  { p.count() } -> std::convertible_to<int>;
  { p.radius() } -> std::convertible_to<float>;
};

/// One simplex vertex: a core point of A and one of B (both in A's frame), their difference
/// w = wa - wb (a point of the Minkowski difference A - B) and the core point indices.
/// Left uninitialised on purpose: simplices are built vertex by vertex in the hot loop.
template <int D>
struct GjkVertexN {
  VecN<D> wa;
  VecN<D> wb;
  VecN<D> w;
  int ia;
  int ib;
};

/// 1 to D + 1 vertices of the Minkowski difference (only the first `count` are meaningful).
template <int D>
struct GjkSimplexN {
  std::array<GjkVertexN<D>, D + 1> v;
  int count = 0;
};

/// How the loop ended.
enum class GjkEnd : unsigned char {
  converged,       ///< no support point gets closer: the simplex holds A - B's closest point
  overlapped,      ///< the simplex holds the origin (within rounding): the cores overlap
  decided_apart,   ///< the policy's lower bound proved the shapes apart (boolean queries)
  decided_touch,   ///< the policy's upper bound proved the shapes touch (boolean queries)
  max_iterations,  ///< kGjkMaxIterations reached
};

/// `v` read component by component. GCC stores a 12-byte vector as 8 + 4 bytes and its SLP
/// vectoriser may read (y, z) back as one 8-byte load across that seam, which the CPU cannot
/// forward from the two stores (about 12 cycles each time); single-float reads forward.
template <int D>
[[nodiscard]] COLLIDE_ALWAYS_INLINE VecN<D> gjk_load(const VecN<D>& v) noexcept {
  if constexpr (D == 3) {
    return {v.x, v.y, v.z};
  } else {
    return v;
  }
}

/// The simplex vertex for core point `ia` of A and `ib` of B, with B placed by `b_in_a`.
template <int D, class PA, class PB>
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkVertexN<D> gjk_vertex(const PA& a, const PB& b, const FrameN<D>& b_in_a,
                                              int ia, int ib) noexcept {
  GjkVertexN<D> v;  // NOLINT: every field is set below
  v.ia = ia;
  v.ib = ib;
  v.wa = a.point(ia);
  v.wb = transform_point(b_in_a, b.point(ib));
  v.w = v.wa - v.wb;
  return v;
}

/// The first simplex vertex of a cold start: the support pair along the line between the
/// shapes' local origins (A's farthest point towards B's origin, B's farthest towards A's).
/// Shapes are usually modelled around their origin, so this pair is already close to the
/// closest features and saves iterations over starting from point 0 of each. Coincident origins
/// fall back to point 0 of each.
template <int D, class PA, class PB>
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkVertexN<D> gjk_seed_vertex(const PA& a, const PB& b,
                                                   const FrameN<D>& b_in_a) noexcept {
  const VecN<D> c = b_in_a.p;  // B's origin in A's frame
  if (!(dot(c, c) > 0.0f)) return gjk_vertex<D>(a, b, b_in_a, 0, 0);
  return gjk_vertex<D>(a, b, b_in_a, a.support_index(c), b.support_index(inv_rotate(b_in_a, -c)));
}

/// (ia, ib) packed into one int; indices are < 2^15.
[[nodiscard]] constexpr int gjk_vertex_key(int ia, int ib) noexcept { return ia | (ib << 15); }

// ---- the simplex solver ----------------------------------------------------------------------

/// Reduce an edge simplex to the sub-simplex (edge or one end) whose Voronoi region holds the
/// origin. Only signs are needed here; the weights are computed once, at the end
/// (gjk_witness_points), so the loop does no division. Same in any dimension.
template <int D>
COLLIDE_ALWAYS_INLINE void gjk_solve_edge(GjkSimplexN<D>& s) noexcept {
  const VecN<D> w1 = s.v[0].w;
  const VecN<D> w2 = s.v[1].w;
  const VecN<D> e12 = w2 - w1;
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

/// Reduce a 2D triangle simplex to the sub-simplex whose Voronoi region holds the origin: one of
/// 3 vertices, 3 edges, or the interior (count stays 3: the cores overlap).
COLLIDE_ALWAYS_INLINE void gjk_solve_triangle(GjkSimplexN<2>& s) noexcept {
  const Vec2 w1 = s.v[0].w;
  const Vec2 w2 = s.v[1].w;
  const Vec2 w3 = s.v[2].w;
  // Edge barycentrics, as in gjk_solve_edge, for the three edges.
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

/// A candidate sub-simplex of a 3D simplex: a bit per vertex it keeps, and the squared distance
/// of its closest point to the origin (to pick the nearest when the origin lies beyond several
/// features). The solver below decides regions by signed volumes (Montanari, Petrinic & Barbieri
/// 2017): a tetrahedron's sub-volumes with the origin in place of each vertex, a triangle's
/// sub-areas around the origin's projection on its plane, a segment's sub-lengths. Only signs
/// and the winner are needed in the loop; the weights are computed once, for the final simplex
/// (gjk_weights3).
struct GjkSubSimplex3 {
  unsigned keep = 0;                  ///< bit i: vertex i is in the sub-simplex
  float distance_squared = INFINITY;  ///< |closest point|^2
  bool faint = false;                 ///< a sub-area's or sub-volume's scale left float's normal range (kGjkFaintProduct)
};

/// A triangle's squared normal (a fourth power of its size) or a tetrahedron's volume (a third
/// power) below this is faint: for a simplex smaller than kGjkTinySimplex the 3D solver solves it
/// again on its points scaled by a power of two (gjk_solve_3d). Below 2^-31 units a fourth power is
/// subnormal and below 2^-37 zero: overlapping boxes 2^-40 units in size read as apart (finding
/// 29, docs/fuzzing.md).
inline constexpr float kGjkFaintProduct = 0x1p-100f;
/// A simplex whose largest coordinate is below this is tiny: its faint products are its size,
/// not its shape, and a power-of-two scale makes them normal (the signs, the nearest sub-simplex
/// and the weights unchanged, exactly).
inline constexpr float kGjkTinySimplex = 0x1p-20f;

/// The power of two that takes `m` (the largest coordinate of a simplex's points) into [1, 2)
/// when m is tiny (below kGjkTinySimplex, not zero); else 1. At most 2^126 (a float): a
/// subnormal m is taken up to 2^-23 at least.
[[nodiscard]] inline float gjk_tiny_simplex_scale(float m) noexcept {
  return m < kGjkTinySimplex && m > 0.0f ? std::ldexp(1.0f, std::min(-std::ilogb(m), 126)) : 1.0f;
}

/// The largest coordinate among the first `count` simplex points' w.
template <int D>
[[nodiscard]] inline float gjk_simplex_magnitude(const GjkSimplexN<D>& s) noexcept {
  float m = 0.0f;
  for (int i = 0; i < s.count; ++i) m = std::max(m, max_abs(s.v[i].w));
  return m;
}

/// The nearer of two candidates (the first on ties).
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkSubSimplex3 gjk_nearer(GjkSubSimplex3 a, GjkSubSimplex3 b) noexcept {
  return b.distance_squared < a.distance_squared ? b : a;
}

/// Closest feature of segment (s1, s2) (vertex bits b1, b2) to the origin: the unnormalised
/// weights u1 = s2.t and u2 = -s1.t (t = s2 - s1) are the signed sub-lengths; a non-positive
/// one puts the origin beyond the other end.
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkSubSimplex3 gjk_closest_segment3(Vec3 s1, Vec3 s2, unsigned b1,
                                                                 unsigned b2) noexcept {
  const Vec3 t = s2 - s1;
  const float tt = dot(t, t);
  const float u2 = -dot(s1, t);  // weight of s2 times tt
  if (!(tt > 0.0f) || !(u2 > 0.0f)) return {b1, dot(s1, s1)};
  if (!(dot(s2, t) > 0.0f)) return {b2, dot(s2, s2)};
  const Vec3 p = s1 + (u2 / tt) * t;
  return {b1 | b2, dot(p, p)};
}

/// Closest feature of triangle (s1, s2, s3) (vertex bits b1, b2, b3) to the origin (Montanari's
/// S2D): the origin's projection p0 on the plane, and its signed sub-areas c_i (the triangle with
/// p0 in place of vertex i), measured along the normal n: c1 + c2 + c3 = n.n > 0, so all
/// positive means p0 is inside. Otherwise the closest point is on an edge whose sub-area is not
/// positive (all of them for a degenerate triangle). Montanari measures the areas on the
/// coordinate plane where the triangle's shadow is largest; along n they are the same areas
/// times |n|, with the same accuracy (p0 is subtracted first), and no axis is chosen at run time.
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkSubSimplex3 gjk_closest_triangle3(Vec3 s1, Vec3 s2, Vec3 s3,
                                                                  unsigned b1, unsigned b2,
                                                                  unsigned b3) noexcept {
  const Vec3 n = cross(s2 - s1, s3 - s1);
  const float nn = dot(n, n);
  bool out1 = true;
  bool out2 = true;
  bool out3 = true;
  const bool faint = !(nn >= kGjkFaintProduct);
  if (nn > 0.0f) {
    const Vec3 p0 = (dot(s1, n) / nn) * n;
    const Vec3 a1 = s1 - p0;
    const Vec3 a2 = s2 - p0;
    const Vec3 a3 = s3 - p0;
    out1 = !(dot(n, cross(a2, a3)) > 0.0f);
    out2 = !(dot(n, cross(a3, a1)) > 0.0f);
    out3 = !(dot(n, cross(a1, a2)) > 0.0f);
    if (!out1 && !out2 && !out3) return {b1 | b2 | b3, dot(p0, p0), faint};
  }
  GjkSubSimplex3 best;
  if (out1) best = gjk_closest_segment3(s2, s3, b2, b3);
  if (out2) best = gjk_nearer(best, gjk_closest_segment3(s1, s3, b1, b3));
  if (out3) best = gjk_nearer(best, gjk_closest_segment3(s1, s2, b1, b2));
  best.faint = faint;
  return best;
}

/// Same signs: both strictly positive or both strictly negative (Montanari's compareSigns).
[[nodiscard]] constexpr bool gjk_same_sign(float a, float b) noexcept {
  return (a > 0.0f && b > 0.0f) || (a < 0.0f && b < 0.0f);
}

/// Signed volume (times 6) of tetrahedron (a, b, c, d): (b - a) . ((c - a) x (d - a)).
[[nodiscard]] COLLIDE_ALWAYS_INLINE float gjk_volume(Vec3 a, Vec3 b, Vec3 c, Vec3 d) noexcept {
  return dot(b - a, cross(c - a, d - a));
}

/// Closest feature of tetrahedron (w1..w4) to the origin (Montanari's S3D): the signed volumes
/// with the origin in place of each vertex are its barycentric coordinates times the whole
/// volume; all of the whole's sign means the origin is inside; otherwise the closest point is on
/// a face whose sub-volume has the other sign (the origin is beyond that face).
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkSubSimplex3 gjk_closest_tetrahedron3(Vec3 w1, Vec3 w2, Vec3 w3,
                                                                     Vec3 w4) noexcept {
  const Vec3 o(0.0f);
  const float c1 = gjk_volume(o, w2, w3, w4);
  const float c2 = gjk_volume(w1, o, w3, w4);
  const float c3 = gjk_volume(w1, w2, o, w4);
  const float c4 = gjk_volume(w1, w2, w3, o);
  const float det = c1 + c2 + c3 + c4;
  const bool faint = !(std::fabs(det) >= kGjkFaintProduct);
  const bool in1 = gjk_same_sign(det, c1);
  const bool in2 = gjk_same_sign(det, c2);
  const bool in3 = gjk_same_sign(det, c3);
  const bool in4 = gjk_same_sign(det, c4);
  if (in1 && in2 && in3 && in4) return {15u, 0.0f, faint};
  GjkSubSimplex3 best;
  if (!in1) best = gjk_closest_triangle3(w2, w3, w4, 2u, 4u, 8u);
  if (!in2) best = gjk_nearer(best, gjk_closest_triangle3(w1, w3, w4, 1u, 4u, 8u));
  if (!in3) best = gjk_nearer(best, gjk_closest_triangle3(w1, w2, w4, 1u, 2u, 8u));
  if (!in4) best = gjk_nearer(best, gjk_closest_triangle3(w1, w2, w3, 1u, 2u, 4u));
  best.faint = best.faint || faint;
  return best;
}

/// Keep the vertices of `s` whose bits are set in `keep`, in order.
template <int D>
COLLIDE_ALWAYS_INLINE void gjk_keep(GjkSimplexN<D>& s, unsigned keep) noexcept {
  int n = 0;
  for (int i = 0; i < s.count; ++i) {
    if (keep & (1u << i)) {
      if (n != i) s.v[n] = s.v[i];
      ++n;
    }
  }
  s.count = n;
}

/// The 3D solver's answer for simplex `s` with its points scaled by `scale` (1: as they are).
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkSubSimplex3 gjk_closest_sub_simplex3(const GjkSimplexN<3>& s, float scale) noexcept {
  return s.count == 4 ? gjk_closest_tetrahedron3(scale * gjk_load<3>(s.v[0].w), scale * gjk_load<3>(s.v[1].w),
                                                 scale * gjk_load<3>(s.v[2].w), scale * gjk_load<3>(s.v[3].w))
                      : gjk_closest_triangle3(scale * gjk_load<3>(s.v[0].w), scale * gjk_load<3>(s.v[1].w),
                                              scale * gjk_load<3>(s.v[2].w), 1u, 2u, 4u);
}

/// gjk_closest_sub_simplex3 again for a faint answer: on the points scaled to unit size when
/// the simplex is tiny (kGjkTinySimplex), else the answer as it was (a sliver or a flat
/// tetrahedron of normal size). Not forced inline: a cold path.
[[nodiscard]] inline GjkSubSimplex3 gjk_closest_sub_simplex3_rescaled(const GjkSimplexN<3>& s, GjkSubSimplex3 sub) noexcept {
  const float scale = gjk_tiny_simplex_scale(gjk_simplex_magnitude(s));
  return scale == 1.0f ? sub : gjk_closest_sub_simplex3(s, scale);
}

/// The solver of a 3D simplex of 3 or 4 vertices: reduce it to the sub-simplex whose Voronoi
/// region holds the origin; 4 vertices kept means the origin is inside (the cores overlap).
/// A faint answer of a tiny simplex is made again on its points scaled to unit size.
COLLIDE_ALWAYS_INLINE void gjk_solve_3d(GjkSimplexN<3>& s) noexcept {
  GjkSubSimplex3 sub = gjk_closest_sub_simplex3(s, 1.0f);
  if (sub.faint) [[unlikely]] sub = gjk_closest_sub_simplex3_rescaled(s, sub);
  gjk_keep(s, sub.keep);
}

/// Barycentric weights of the origin's closest point on a reduced 3D simplex (the one the
/// solver kept, whose Voronoi region holds the origin: no weight negative): sub-lengths,
/// sub-areas along the normal, or sub-volumes over their sum.
/// A tiny simplex (kGjkTinySimplex) is weighed on its points scaled to unit size, as the solver
/// decides it: the weights are ratios, unchanged by the scale.
[[nodiscard]] inline std::array<float, 4> gjk_weights3(const GjkSimplexN<3>& s) noexcept {
  std::array<float, 4> lambda{1.0f, 0.0f, 0.0f, 0.0f};
  const float scale = s.count >= 2 ? gjk_tiny_simplex_scale(gjk_simplex_magnitude(s)) : 1.0f;
  std::array<Vec3, 4> w{};
  for (int i = 0; i < s.count; ++i) w[static_cast<std::size_t>(i)] = scale * s.v[i].w;
  if (s.count == 2) {
    const Vec3 t = w[1] - w[0];
    const float u1 = dot(w[1], t);
    const float u2 = -dot(w[0], t);
    const float sum = u1 + u2;  // = t.t > 0 when the solver kept the edge
    if (sum > 0.0f) lambda = {u1 / sum, u2 / sum, 0.0f, 0.0f};
  } else if (s.count == 3) {
    const Vec3 n = cross(w[1] - w[0], w[2] - w[0]);
    const float nn = dot(n, n);
    if (nn > 0.0f) {
      const Vec3 p0 = (dot(w[0], n) / nn) * n;
      const Vec3 a1 = w[0] - p0;
      const Vec3 a2 = w[1] - p0;
      const Vec3 a3 = w[2] - p0;
      const float c1 = dot(n, cross(a2, a3));
      const float c2 = dot(n, cross(a3, a1));
      const float c3 = dot(n, cross(a1, a2));
      const float sum = c1 + c2 + c3;
      if (sum > 0.0f) lambda = {c1 / sum, c2 / sum, c3 / sum, 0.0f};
    }
  } else if (s.count == 4) {
    const Vec3 o(0.0f);
    const float c1 = gjk_volume(o, w[1], w[2], w[3]);
    const float c2 = gjk_volume(w[0], o, w[2], w[3]);
    const float c3 = gjk_volume(w[0], w[1], o, w[3]);
    const float c4 = gjk_volume(w[0], w[1], w[2], o);
    const float det = c1 + c2 + c3 + c4;
    if (det != 0.0f) lambda = {c1 / det, c2 / det, c3 / det, c4 / det};
  }
  return lambda;
}

/// Reduce any simplex to the sub-simplex whose Voronoi region holds the origin. Returns true
/// when the whole simplex of D + 1 vertices holds the origin (the cores overlap).
template <int D>
[[nodiscard]] COLLIDE_ALWAYS_INLINE bool gjk_reduce(GjkSimplexN<D>& s) noexcept {
  if (s.count == 2) {
    gjk_solve_edge(s);
  } else if (s.count >= 3) {
    if constexpr (D == 2) {
      gjk_solve_triangle(s);
    } else {
      gjk_solve_3d(s);
    }
    return s.count == D + 1;
  }
  return false;
}

/// The search direction from a reduced simplex's closest point towards the origin, not unit,
/// computed exactly from the kept feature: -w for a vertex, the edge's perpendicular towards
/// the origin, a triangle's normal towards it (3D). Zero length only when the origin is on
/// the kept feature's line or plane.
template <int D>
[[nodiscard]] COLLIDE_ALWAYS_INLINE VecN<D> gjk_search_direction(const GjkSimplexN<D>& s) noexcept {
  const VecN<D> w1 = gjk_load<D>(s.v[0].w);
  if (s.count == 1) return -w1;
  const VecN<D> e12 = gjk_load<D>(s.v[1].w) - w1;
  if constexpr (D == 2) {
    // The side of the edge the origin is on (right_perp = -left_perp), without a branch.
    return left_perp(e12) * (cross(e12, -w1) > 0.0f ? 1.0f : -1.0f);
  } else {
    if (s.count == 2) return cross(cross(e12, -w1), e12);  // |e|^2 times the perpendicular
    const Vec3 n = cross(e12, gjk_load<3>(s.v[2].w) - w1);
    return dot(n, w1) < 0.0f ? n : -n;
  }
}

/// Bounds of GJK's squared search direction, beyond which run_gjk scales it to unit size
/// (scaled_to_unit_magnitude). The direction is not unit: a segment simplex's is |e|^2 times the
/// perpendicular, so it grows as the cube of the simplex's size, and its square as the sixth
/// power. A needle 4e8 long gave |d|^2 = inf, and "origin on the simplex" followed (the fuzzer's
/// cast check, stop 105: a sphere 1e8 from a mesh reported overlapping it). Below 2^60, k = d.w
/// stays below 2^62 for coordinates within kFiniteQueryRange, so k^2 stays finite; above
/// 2^-60 no square underflows.
inline constexpr float kGjkDirectionMaxSquared = 0x1p60f;

/// gjk_search_direction with its squared length `dd`, in 3D scaled to unit size
/// (scaled_to_unit_magnitude, exactly by a power of two) when that square leaves
/// [1 / kGjkDirectionMaxSquared, kGjkDirectionMaxSquared]: only its direction counts for its
/// users (run_gjk compares k^2 with dd and dw with k; the cast and the time of impact normalise
/// it). A 2D direction is an edge's perpendicular as long as the edge, whose square stays
/// within float for coordinates within kFiniteQueryRange: 2D takes no test (the 2D cast of
/// boxes measured 5% slower with it).
template <int D>
[[nodiscard]] COLLIDE_ALWAYS_INLINE VecN<D> gjk_bounded_search_direction(const GjkSimplexN<D>& s, float& dd) noexcept {
  VecN<D> d = gjk_search_direction(s);
  dd = dot(d, d);
  if constexpr (D == 3) {
    if (!(dd <= kGjkDirectionMaxSquared && dd >= 1.0f / kGjkDirectionMaxSquared)) [[unlikely]] {
      // A tiny simplex's direction (a third power of its size for a segment) is made again on
      // its points scaled to unit size, before its digits are lost to subnormals.
      const float scale = gjk_tiny_simplex_scale(gjk_simplex_magnitude(s));
      if (scale != 1.0f) {
        GjkSimplexN<D> scaled = s;
        for (int i = 0; i < s.count; ++i) scaled.v[i].w = scale * s.v[i].w;
        d = gjk_search_direction(scaled);
      }
      d = scaled_to_unit_magnitude(d);
      dd = dot(d, d);
    }
  }
  return d;
}

/// Witness points on A's and B's cores (A's frame): the barycentric coordinates of the
/// simplex's closest point to the origin, applied to the A and B halves of its vertices. When
/// the simplex holds the origin, one point inside both (equal outputs).
template <int D>
COLLIDE_ALWAYS_INLINE void gjk_witness_points(const GjkSimplexN<D>& s, VecN<D>& pa, VecN<D>& pb) noexcept {
  if (s.count == 1) {
    pa = s.v[0].wa;
    pb = s.v[0].wb;
  } else if (s.count == 2) {
    const VecN<D> e12 = s.v[1].w - s.v[0].w;
    const float u1 = dot(s.v[1].w, e12);
    const float u2 = -dot(s.v[0].w, e12);
    const float inv = 1.0f / (u1 + u2);  // > 0: the solver kept the edge only if both are
    const float a1 = u1 * inv;
    const float a2 = u2 * inv;
    pa = a1 * s.v[0].wa + a2 * s.v[1].wa;
    pb = a1 * s.v[0].wb + a2 * s.v[1].wb;
  } else if constexpr (D == 2) {
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
  } else {
    const std::array<float, 4> lambda = gjk_weights3(s);
    pa = Vec3(0.0f);
    pb = Vec3(0.0f);
    for (int i = 0; i < s.count; ++i) {
      pa += lambda[i] * s.v[i].wa;
      pb += lambda[i] * s.v[i].wb;
    }
    if (s.count == 4) pb = pa;
  }
}

// ---- the loop --------------------------------------------------------------------------------

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

/// Run GJK on the simplex `s` (1..D+1 valid vertices on entry; on exit the final simplex) of
/// support maps A and B, B placed in A's frame by `b_in_a`. `scale` is the size of the problem
/// in A's frame (coordinate magnitude): the origin counts as on the simplex when within
/// kRelativeTolerance * scale of it. `policy` may stop early (see GjkRunToEnd). `iterations`
/// counts support points evaluated.
template <int D, class PA, class PB, class Policy>
[[nodiscard]] COLLIDE_ALWAYS_INLINE GjkEnd run_gjk(const PA& a, const PB& b, const FrameN<D>& b_in_a,
                             GjkSimplexN<D>& s, float scale, const Policy& policy,
                             int& iterations) noexcept {
  static_assert(SupportMap<PA, D> && SupportMap<PB, D>);
  const float on_simplex = kRelativeTolerance * scale;
  const float on_simplex2 = on_simplex * on_simplex;
  iterations = 0;
  for (;;) {
    // The vertices before reduction, as (ia, ib) keys: a new support point equal to one of
    // them means GJK is cycling on a flat piece of A - B (converged within rounding). Unused
    // slots hold -1, so the test below is a few compares and no loop.
    std::array<int, D + 1> saved;
    saved.fill(-1);
    for (int i = 0; i < s.count; ++i) saved[i] = gjk_vertex_key(s.v[i].ia, s.v[i].ib);

    if (gjk_reduce(s)) return GjkEnd::overlapped;

    // Search direction d from the simplex's closest point v towards the origin.
    float dd;
    const VecN<D> d = gjk_bounded_search_direction(s, dd);
    const float k = dot(d, gjk_load<D>(s.v[0].w));  // = -|v| |d|
    // Origin on the simplex (|v| <= on_simplex), or NaN: the cores touch or overlap.
    if (!(k < 0.0f && k * k > on_simplex2 * dd)) return GjkEnd::overlapped;
    if (policy.touching(k, dd)) return GjkEnd::decided_touch;
    if (iterations == kGjkMaxIterations) return GjkEnd::max_iterations;

    // Support point of A - B in direction d: A's farthest along d, B's farthest along -d.
    // Walk from the newest simplex vertex's points: the support moves little per iteration.
    const GjkVertexN<D>& last = s.v[s.count - 1];
    const int ia = a.support_index_from(d, last.ia);
    const int ib = b.support_index_from(inv_rotate(b_in_a, -d), last.ib);
    const VecN<D> wa = a.point(ia);
    const VecN<D> wb = transform_point(b_in_a, b.point(ib));
    const VecN<D> w = wa - wb;
    ++iterations;

    const float dw = dot(d, w);
    if (policy.apart(dw, dd)) return GjkEnd::decided_apart;
    // No progress: the gap between the upper and lower bounds, (dw - k) / |d|, is within
    // kGjkRelativeTolerance of the upper bound -k / |d| (van den Bergen 2003, 4.3.4).
    if (dw - k <= kGjkRelativeTolerance * -k) return GjkEnd::converged;
    const int key = gjk_vertex_key(ia, ib);
    bool repeated = false;
    for (int i = 0; i < D + 1; ++i) repeated |= key == saved[i];
    if (repeated) return GjkEnd::converged;
    GjkVertexN<D>& nv = s.v[s.count++];
    nv.wa = wa;
    nv.wb = wb;
    nv.w = w;
    nv.ia = ia;
    nv.ib = ib;
  }
}

/// The size of a support-map pair in A's frame for the relative tolerances of run_gjk: the
/// largest coordinate magnitude among the first simplex vertex's points, plus the radii.
template <int D>
[[nodiscard]] inline float gjk_scale(const GjkVertexN<D>& first, float radius_sum) noexcept {
  return std::max(max_abs(first.wa), max_abs(first.wb)) + radius_sum;
}

}  // namespace collide
