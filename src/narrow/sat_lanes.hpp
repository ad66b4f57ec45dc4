#pragma once
// Internal: the separating axis test of two small polygons (up to two groups of kSatLanes
// vertices each) in SSE registers, shared by `contact` (polygon_contact.cpp), `overlap`
// (overlap.cpp), `distance` (distance.cpp) and `edge_separations` (sat.cpp, which the polygon
// shape cast uses): both polygons are loaded straight into x and y lanes in A's frame (shifted
// to A's vertex 0), B rotated there, and both passes run without copies.

#include <collide/core/config.hpp>
#include <collide/narrow/sat.hpp>

#include "sat_soa.hpp"

#include <bit>
#include <limits>
#include <type_traits>

// The small-polygon front ends use SSE2 (every x86-64 CPU); elsewhere, or with
// COLLIDE_SMALL_POLYGON_SSE2=0, every pair takes the general paths.
#ifndef COLLIDE_SMALL_POLYGON_SSE2
#if defined(__SSE2__) || defined(_M_X64)
#define COLLIDE_SMALL_POLYGON_SSE2 1
#else
#define COLLIDE_SMALL_POLYGON_SSE2 0
#endif
#endif
#if COLLIDE_SMALL_POLYGON_SSE2
#include <emmintrin.h>
#endif

namespace collide::detail {

/// The frame both front ends work in: A's local frame shifted so that A's vertex 0 is the
/// origin (coordinates stay small however far from the world origin the pair is). `shift`
/// takes B's local points there after rotating them by b_in_a.q.
struct SharedFrame {
  Transform b_in_a;
  Vec2 origin;  ///< A's vertex 0, A's local frame
  Vec2 shift;   ///< b_in_a.p - origin
};

COLLIDE_ALWAYS_INLINE SharedFrame shared_frame(const Polygon& a, const Transform& xa,
                                               const Transform& xb) noexcept {
  const Transform b_in_a = inv_mul(xa, xb);
  const Vec2 origin = a.vertices[0];
  return {b_in_a, origin, b_in_a.p - origin};
}

#if COLLIDE_SMALL_POLYGON_SSE2
/// Points 0..3 of an array of `count` (1..4) points as x and y lanes, the last point repeated
/// past `count`. Reads only the first `count` points.
inline void load_lanes(const Vec2* v, int count, __m128& x, __m128& y) noexcept {
  // One point as x y x y: one 8-byte load (float alignment is enough for it), duplicated.
  const auto pair = [](const Vec2* p) {
    const __m128 one = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p->x)));
    return _mm_movelh_ps(one, one);
  };
  __m128 lo;  // x0 y0 x1 y1
  __m128 hi;  // x2 y2 x3 y3
  if (count == 1) {
    lo = pair(v);
    hi = lo;
  } else {
    lo = _mm_loadu_ps(&v[0].x);
    if (count == 4) {
      hi = _mm_loadu_ps(&v[2].x);
    } else if (count == 3) {
      hi = pair(v + 2);
    } else {
      hi = _mm_movehl_ps(lo, lo);
    }
  }
  x = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
  y = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
}

/// A polygon of up to kGroups * kSatLanes points in registers: x and y lanes per group of four,
/// the last point repeated to fill the last group (SoaPolygon's padding).
template <int kGroups>
struct LanePoints {
  __m128 x[kGroups];
  __m128 y[kGroups];
};

template <int kGroups>
inline LanePoints<kGroups> load_points(const Vec2* v, int count) noexcept {
  LanePoints<kGroups> p;
  if constexpr (kGroups == 1) {
    load_lanes(v, count, p.x[0], p.y[0]);
  } else {
    static_assert(kGroups == 2, "up to two groups: eight points");
    load_lanes(v, kSatLanes, p.x[0], p.y[0]);
    load_lanes(v + kSatLanes, count - kSatLanes, p.x[1], p.y[1]);
  }
  return p;
}

/// Lane `k` (0..3) of `v` in every lane.
COLLIDE_ALWAYS_INLINE __m128 broadcast_lane(__m128 v, int k) noexcept {
  switch (k) {
    case 0: return _mm_shuffle_ps(v, v, _MM_SHUFFLE(0, 0, 0, 0));
    case 1: return _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 1, 1, 1));
    case 2: return _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 2, 2, 2));
    default: return _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 3, 3, 3));
  }
}

/// The least of the four lanes of `v`, in every lane: with the halves swapped, then the
/// neighbours (one fixed order, so ties of signed zeros and NaNs fall the same way each call).
COLLIDE_ALWAYS_INLINE __m128 min_in_every_lane(__m128 v) noexcept {
  v = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
}

/// The greatest of the four lanes of `v`, in every lane (the same order as min_in_every_lane).
COLLIDE_ALWAYS_INLINE __m128 max_in_every_lane(__m128 v) noexcept {
  v = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
}

/// separation[i] = min_j dot(n_i, v2_j) - dot(n_i, v1_i) for every lane of the edge groups:
/// the same products and sums as find_max_separation_soa, so the results are bitwise equal (a
/// minimum is exact, so the pairwise order of the minima, shorter in latency than a chain,
/// gives the same value). Vertex lanes are padded by repetition, so the minimum over them is
/// the minimum over the real ones.
template <int kEdgeGroups, int kVertexGroups>
COLLIDE_ALWAYS_INLINE void separation_lanes(const LanePoints<kEdgeGroups>& n,
                                            const LanePoints<kEdgeGroups>& v1,
                                            const LanePoints<kVertexGroups>& v2,
                                            __m128 (&s)[kEdgeGroups]) noexcept {
  static_assert(kSatLanes == 4, "four lanes: one SSE register");
  for (int g = 0; g < kEdgeGroups; ++g) {
    const auto dots = [&](int h, int j) {
      return _mm_add_ps(_mm_mul_ps(n.x[g], broadcast_lane(v2.x[h], j)),
                        _mm_mul_ps(n.y[g], broadcast_lane(v2.y[h], j)));
    };
    __m128 lowest = _mm_min_ps(_mm_min_ps(dots(0, 0), dots(0, 1)),
                               _mm_min_ps(dots(0, 2), dots(0, 3)));
    for (int h = 1; h < kVertexGroups; ++h) {
      lowest = _mm_min_ps(lowest, _mm_min_ps(_mm_min_ps(dots(h, 0), dots(h, 1)),
                                             _mm_min_ps(dots(h, 2), dots(h, 3))));
    }
    s[g] = _mm_sub_ps(lowest,
                      _mm_add_ps(_mm_mul_ps(n.x[g], v1.x[g]), _mm_mul_ps(n.y[g], v1.y[g])));
  }
}

/// The largest of the separations `s` (one per lane, kGroups * kSatLanes edges) and the first
/// lane holding it, found without branches, into `out`. Returns false (and nothing) if a lane
/// is NaN.
template <int kGroups>
COLLIDE_ALWAYS_INLINE bool max_lane(const __m128 (&s)[kGroups], EdgeSeparation& out) noexcept {
  __m128 ordered = _mm_cmpord_ps(s[0], s[0]);
  __m128 top = s[0];
  for (int g = 1; g < kGroups; ++g) {
    ordered = _mm_and_ps(ordered, _mm_cmpord_ps(s[g], s[g]));
    top = _mm_max_ps(top, s[g]);
  }
  if (_mm_movemask_ps(ordered) != 0xF) return false;
  top = max_in_every_lane(top);
  // First lane equal to the maximum: padded lanes repeat the last edge, so they never come
  // before it.
  unsigned mask = 0;
  for (int g = 0; g < kGroups; ++g) {
    mask |= static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(s[g], top))) << (kSatLanes * g);
  }
  out = EdgeSeparation{std::countr_zero(mask), _mm_cvtss_f32(top), 0};
  return true;
}

/// find_max_separation_soa for the edges of one polygon against the vertices of the other, all
/// in registers: separation_lanes, then the largest. All groups are computed (no early exit
/// between them: the caller's test of the maximum against the radius then rejects the same
/// pairs). Returns false (and nothing) if a lane is NaN: the general path then decides, as it
/// would.
template <int kEdgeGroups, int kVertexGroups>
inline bool max_separation_lanes(const LanePoints<kEdgeGroups>& n,
                                 const LanePoints<kEdgeGroups>& v1,
                                 const LanePoints<kVertexGroups>& v2,
                                 EdgeSeparation& out) noexcept {
  __m128 s[kEdgeGroups];
  separation_lanes(n, v1, v2, s);
  return max_lane(s, out);
}

/// Index of the first of the points in `p` with the least dot product with `n`: the support
/// point in direction -n, without branches. Padded lanes repeat the last point, so they never
/// come before it. NaN dots are never the least (a NaN-free point wins; all NaN: point 0).
template <int kGroups>
inline int lowest_point(const LanePoints<kGroups>& p, Vec2 n) noexcept {
  const __m128 nx = _mm_set1_ps(n.x);
  const __m128 ny = _mm_set1_ps(n.y);
  __m128 d[kGroups];
  __m128 low = _mm_set1_ps(std::numeric_limits<float>::infinity());
  for (int g = 0; g < kGroups; ++g) {
    d[g] = _mm_add_ps(_mm_mul_ps(nx, p.x[g]), _mm_mul_ps(ny, p.y[g]));
    low = _mm_min_ps(d[g], low);  // a NaN dot keeps the other operand
  }
  low = min_in_every_lane(low);
  unsigned mask = 0;
  for (int g = 0; g < kGroups; ++g) {
    mask |= static_cast<unsigned>(_mm_movemask_ps(_mm_cmpeq_ps(d[g], low))) << (kSatLanes * g);
  }
  return mask != 0 ? std::countr_zero(mask) : 0;
}

/// Both polygons of a pair in registers, in the shared frame, and their separating axis passes.
template <int kGroupsA, int kGroupsB>
struct LanePair {
  LanePoints<kGroupsA> av;  ///< A's vertices minus the origin
  LanePoints<kGroupsA> an;  ///< A's edge normals
  LanePoints<kGroupsB> bv;  ///< B's vertices, rotated and shifted into the frame
  LanePoints<kGroupsB> bn;  ///< B's edge normals, rotated (set only when sep_b is)
  EdgeSeparation sep_a;     ///< over A's edges
  EdgeSeparation sep_b;     ///< over B's edges (set only when sep_a.separation <= early_exit)
};

/// Directions rotated by the rotation whose cosine and sine fill `c` and `s`:
/// x' = c x - s y, y' = s x + c y.
template <int kGroups>
COLLIDE_ALWAYS_INLINE void rotate_lanes(LanePoints<kGroups>& p, __m128 c, __m128 s) noexcept {
  for (int g = 0; g < kGroups; ++g) {
    const __m128 x = p.x[g];
    const __m128 y = p.y[g];
    p.x[g] = _mm_sub_ps(_mm_mul_ps(c, x), _mm_mul_ps(s, y));
    p.y[g] = _mm_add_ps(_mm_mul_ps(s, x), _mm_mul_ps(c, y));
  }
}
/// Points rotated so, then moved by (`dx`, `dy`).
template <int kGroups>
COLLIDE_ALWAYS_INLINE void rotate_lanes(LanePoints<kGroups>& p, __m128 c, __m128 s, float dx,
                                        float dy) noexcept {
  rotate_lanes(p, c, s);
  for (int g = 0; g < kGroups; ++g) {
    p.x[g] = _mm_add_ps(p.x[g], _mm_set1_ps(dx));
    p.y[g] = _mm_add_ps(p.y[g], _mm_set1_ps(dy));
  }
}

/// A's vertices minus the origin and A's normals, as lanes.
template <int kGroups>
COLLIDE_ALWAYS_INLINE void load_reference(const Polygon& a, Vec2 origin, LanePoints<kGroups>& v,
                                          LanePoints<kGroups>& n) noexcept {
  v = load_points<kGroups>(a.vertices.data(), a.count);
  for (int g = 0; g < kGroups; ++g) {
    v.x[g] = _mm_sub_ps(v.x[g], _mm_set1_ps(origin.x));
    v.y[g] = _mm_sub_ps(v.y[g], _mm_set1_ps(origin.y));
  }
  n = load_points<kGroups>(a.normals.data(), a.count);
}

/// Loads A's vertices (minus the origin) and normals, and B's vertices rotated and shifted into
/// frame `f`, into `p`.
template <int kGroupsA, int kGroupsB>
COLLIDE_ALWAYS_INLINE void load_pair(const Polygon& a, const Polygon& b, const SharedFrame& f,
                                     LanePair<kGroupsA, kGroupsB>& p) noexcept {
  // A: vertices - origin, normals as stored. B: rotate(q, v) + shift.
  load_reference(a, f.origin, p.av, p.an);
  p.bv = load_points<kGroupsB>(b.vertices.data(), b.count);
  rotate_lanes(p.bv, _mm_set1_ps(f.b_in_a.q.c), _mm_set1_ps(f.b_in_a.q.s), f.shift.x, f.shift.y);
}

/// The separating axis test of A's edges against B's vertices, then (unless that found an axis
/// separating by more than `early_exit`) B's edges against A's vertices, in frame `f`. Same
/// operations in the same order as find_max_separation_soa on SoaPolygon copies, so the
/// separations are bitwise the same. Returns false (and nothing usable) when a lane is NaN:
/// the caller's general path then decides.
template <int kGroupsA, int kGroupsB>
COLLIDE_ALWAYS_INLINE bool separate_lanes(const Polygon& a, const Polygon& b, const SharedFrame& f,
                                          float early_exit,
                                          LanePair<kGroupsA, kGroupsB>& p) noexcept {
  load_pair(a, b, f, p);
  if (!max_separation_lanes(p.an, p.av, p.bv, p.sep_a)) return false;
  if (p.sep_a.separation > early_exit) return true;
  p.bn = load_points<kGroupsB>(b.normals.data(), b.count);
  rotate_lanes(p.bn, _mm_set1_ps(f.b_in_a.q.c), _mm_set1_ps(f.b_in_a.q.s));
  return max_separation_lanes(p.bn, p.bv, p.av, p.sep_b);
}

/// Calls `visit(std::integral_constant<int, kGroupsA>{}, std::integral_constant<int, kGroupsB>{})`
/// with the fewest groups of kSatLanes that hold A's and B's vertices, when both fit in two
/// groups; returns false (without calling) otherwise.
template <class Visit>
COLLIDE_ALWAYS_INLINE bool with_lane_groups(int na, int nb, Visit&& visit) {
  using One = std::integral_constant<int, 1>;
  using Two = std::integral_constant<int, 2>;
  constexpr int kOneGroup = kSatLanes;
  constexpr int kTwoGroups = 2 * kSatLanes;
  if (na > kTwoGroups || nb > kTwoGroups) return false;
  if (na <= kOneGroup) {
    if (nb <= kOneGroup) {
      visit(One{}, One{});
    } else {
      visit(One{}, Two{});
    }
  } else if (nb <= kOneGroup) {
    visit(Two{}, One{});
  } else {
    visit(Two{}, Two{});
  }
  return true;
}
#endif

}  // namespace collide::detail
