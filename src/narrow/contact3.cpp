// `contact` for every ordered pair of convex 3D shapes.
//
// Every core is a polytope (polytope3.hpp): a point (sphere), a segment (capsule, segment), a
// solid polyhedron (box, hull) or a flat one (triangle). The contact is found in A's frame:
//  1. Two cores without faces (points and segments): their closest points (Ericson 5.1.9),
//     one point, or two for parallel segments (capsule on capsule).
//  2. Otherwise the separating axis test over A's faces, B's faces and the edge pairs
//     (Gregorius, "The Separating Axis Test between Convex Polyhedra", GDC 2013): edge pairs of
//     two solids are pruned to those that form a face of the Minkowski difference A - B (their
//     arcs cross on the Gauss map); a triangle's edge (a half circle on the Gauss map) meets
//     the solid's silhouette edges along it, and a box's three directions name their edges
//     outright; other pairs with a flat or faceless core are all tested, with the
//     separation taken from support queries on both sides. The axis of largest separation is
//     the minimum-penetration axis when the cores overlap. Pairs whose edge test would cost
//     more than kSatEdgePairLimit pairs (contact.hpp) take GJK's answer and, when the cores overlap, EPA's axis
//     instead (epa.hpp); their manifold keeps EPA's normal, its clipped points are measured
//     along it (as Jolt's ManifoldBetweenTwoFaces does) and are no deeper than EPA's depth, and
//     EPA's deepest points join them when the clip missed them, so the deepest point is EPA's.
//  3. Cores that overlap (or touch): a face axis makes a face contact (the reference face's side
//     planes clip the other shape's most anti-parallel face, Sutherland & Hodgman 1974), an
//     edge axis one point between the two edges. Against a triangle, the incident core's
//     deepest vertex joins the clipped points when the clip left it out and the face axis is
//     the minimum translation (the EPA route's deepest point, here exact). Cores apart by less
//     than the radii plus the margin (rounded shapes, speculative contact): GJK gives their
//     closest points (a point or segment core against a triangle, as a capsule meets a level:
//     in closed form, Ericson 5.1.10, skipping the triangle edges the segment stays inside
//     of); if the normal is within kFaceContactSine of a face normal, that face clips as
//     above, else the closest points make one point. A point or segment core against a
//     triangle (a sphere or capsule on a level) takes all of this without building the
//     triangle's polytope while the cores are apart (core_triangle_contact: two ends clipped to
//     three side planes), the polytope only when the segment pierces the triangle.
//  4. More than 4 points are reduced to 4: the deepest, the farthest from it, then the two that
//     span the largest area (the idea of Jolt's PruneContactPoints).

#include <collide/core/config.hpp>
#include <collide/core/error.hpp>
#include <collide/core/lanes.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>

#include "contact3_triangle.hpp"
#include "penetration_cores.hpp"
#include "polytope3.hpp"
#include "scratch_array.hpp"
#include "segment_closest.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>
#include <variant>

// A hull's face planes are tested four at a time with SSE2 (every x86-64 CPU); elsewhere, or
// with COLLIDE_HULL_FACES_SSE2=0, one at a time (the same values).
#ifndef COLLIDE_HULL_FACES_SSE2
#if defined(__SSE2__) || defined(_M_X64)
#define COLLIDE_HULL_FACES_SSE2 1
#else
#define COLLIDE_HULL_FACES_SSE2 0
#endif
#endif
#if COLLIDE_HULL_FACES_SSE2
#include <emmintrin.h>
#endif

namespace collide {
namespace {

using detail::Polytope3;
using detail::ScratchArray;

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Most corners the face clipper holds: a clipped polygon has at most the incident face's
/// corners plus the reference face's. Faces with more corners than half of it are clipped by
/// their first corners only (never seen on real hulls: the 6755 shared hulls have at most 20).
constexpr int kMaxClipVertices = 64;


/// B's core placed in A's frame. `identity`: B's core is already given in A's frame (a level's
/// triangle, moved there once), and nothing is transformed.
struct PlacedPolytope {
  const Polytope3& p;
  Frame3 f;  ///< B's local -> A's frame
  bool identity = false;

  /// Always inlined: kept out of line, its Vec3 came back as two registers that contact_cores
  /// put back together through the stack by loads that cannot be store-forwarded (two of the
  /// twelve such reloads scripts/store-forward-scan finds there; the rest have other sources).
  [[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 vertex(int i) const noexcept {
    return identity ? p.vertex(i) : transform_point(f, p.vertex(i));
  }
  /// Support vertex along `d` given in A's frame.
  [[nodiscard]] int support(Vec3 d) const noexcept { return p.support(identity ? d : inv_rotate(f, d)); }
  [[nodiscard]] Vec3 face_normal(int face) const noexcept {
    return identity ? p.faces[face].normal : rotate(f, p.faces[face].normal);
  }
  [[nodiscard]] float face_offset(int face, Vec3 normal) const noexcept {
    return identity ? p.faces[face].offset : p.faces[face].offset + dot(normal, f.p);
  }
  /// A point of A's frame in B's local frame.
  [[nodiscard]] Vec3 to_local(Vec3 point) const noexcept {
    return identity ? point : inv_transform_point(f, point);
  }
};

/// A's core in its own frame, and B's placed in A's: vertices and face normals, for helpers
/// written once for either side.
struct IdentityPlace {
  const Polytope3& p;
  [[nodiscard]] Vec3 vertex(int i) const noexcept { return p.vertex(i); }
  [[nodiscard]] Vec3 normal(int face) const noexcept { return p.faces[face].normal; }
};
struct BPlace {
  const PlacedPolytope& b;
  [[nodiscard]] Vec3 vertex(int i) const noexcept { return b.vertex(i); }
  [[nodiscard]] Vec3 normal(int face) const noexcept { return b.face_normal(face); }
};

/// Most faces a solid core has: a hull of kMaxHullVertices vertices has at most 2 V - 4
/// (Euler's formula, all faces triangles).
constexpr int kMaxSolidFaces = 2 * kMaxHullVertices;

/// The best axis of one kind.
struct FaceQuery {
  float separation = -kInf;
  int face = -1;
};
struct EdgeQuery {
  float separation = -kInf;
  int edge_a = -1;
  int edge_b = -1;
  Vec3 axis{0.0f};  ///< unit, from A towards B
};

/// query_faces_a for a hull A (face_blocks set) and a triangle B given in A's frame: B's
/// separation from a face is the least height of B's three corners over its plane, the same
/// float values as the support query takes, four faces at a time and all of them (no early
/// stop: a branch per face cost more than the faces after it). The first face of the largest
/// separation, as the scalar loop.
FaceQuery hull_faces_against_triangle(const Polytope3& a, const PlacedPolytope& b) noexcept {
  const Vec3 t0 = b.p.vertex(0);
  const Vec3 t1 = b.p.vertex(1);
  const Vec3 t2 = b.p.vertex(2);
  FaceQuery q;
#if COLLIDE_HULL_FACES_SSE2
  static_assert(kMaxSolidFaces + 4 < simd::ArgMax4::kNone);
  // dot(n, t) = (n.x t.x + n.y t.y) + n.z t.z, as glm's dot.
  const auto height = [](__m128 nx, __m128 ny, __m128 nz, Vec3 t) {
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, _mm_set1_ps(t.x)), _mm_mul_ps(ny, _mm_set1_ps(t.y))),
                      _mm_mul_ps(nz, _mm_set1_ps(t.z)));
  };
  simd::ArgMax4 scan;
  const float* p = a.face_blocks;
  const float* end = p + 16 * ((a.face_count + 3) / 4);
  for (; p != end; p += 16) {
    const __m128 nx = _mm_loadu_ps(p);
    const __m128 ny = _mm_loadu_ps(p + 4);
    const __m128 nz = _mm_loadu_ps(p + 8);
    const __m128 low = _mm_min_ps(_mm_min_ps(height(nx, ny, nz, t0), height(nx, ny, nz, t1)),
                                  height(nx, ny, nz, t2));
    scan.add(_mm_sub_ps(low, _mm_loadu_ps(p + 12)));
  }
  // The largest over the lanes, then the lowest face index holding it.
  const simd::ArgMax4::Result best = scan.result();
  if (best.index != simd::ArgMax4::kNone) {
    q.face = best.index;
    q.separation = best.max;
  }
#else
  for (int i = 0; i < a.face_count; ++i) {
    const HullFace& face = a.faces[i];
    const float s = std::min({dot(face.normal, t0), dot(face.normal, t1), dot(face.normal, t2)}) - face.offset;
    if (s > q.separation) {
      q.separation = s;
      q.face = i;
    }
  }
#endif
  return q;
}

/// query_faces_a for a box A and a triangle B given in A's frame: B's least height over face
/// 2k + 1 (normal +e_k) is its least coordinate k less the half extent, over face 2k (-e_k)
/// minus its greatest coordinate k less the half extent (box.hpp's numbering), the values the
/// support query gives; the first face of the largest separation.
FaceQuery box_faces_against_triangle(const Polytope3& a, const PlacedPolytope& b) noexcept {
  const Vec3 lo = glm::min(glm::min(b.p.vertex(0), b.p.vertex(1)), b.p.vertex(2));
  const Vec3 hi = glm::max(glm::max(b.p.vertex(0), b.p.vertex(1)), b.p.vertex(2));
  FaceQuery q;
  for (int k = 0; k < 3; ++k) {
    const float half = a.faces[2 * k + 1].offset;
    const float below = -hi[k] - half;
    const float above = lo[k] - half;
    if (below > q.separation) {
      q.separation = below;
      q.face = 2 * k;
    }
    if (above > q.separation) {
      q.separation = above;
      q.face = 2 * k + 1;
    }
  }
  return q;
}

/// Separation of B from each face of A; stops early once a face separates by more than `reach`.
FaceQuery query_faces_a(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  if (b.identity && b.p.kind == Polytope3::Kind::triangle) {
    if (a.face_blocks != nullptr) return hull_faces_against_triangle(a, b);
    if (a.kind == Polytope3::Kind::box) return box_faces_against_triangle(a, b);
  }
  FaceQuery q;
  for (int i = 0; i < a.face_count; ++i) {
    const HullFace& face = a.faces[i];
    const Vec3 p = b.vertex(b.support(-face.normal));
    const float s = dot(face.normal, p) - face.offset;
    if (s > q.separation) {
      q.separation = s;
      q.face = i;
      if (s > reach) break;
    }
  }
  return q;
}

/// Separation of A from each face of B (B's faces turned into A's frame).
FaceQuery query_faces_b(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  FaceQuery q;
  for (int j = 0; j < b.p.face_count; ++j) {
    const Vec3 n = b.face_normal(j);
    const Vec3 p = a.vertex(a.support(-n));
    const float s = dot(n, p) - b.face_offset(j, n);
    if (s > q.separation) {
      q.separation = s;
      q.face = j;
      if (s > reach) break;
    }
  }
  return q;
}

/// Gauss-map test (Gregorius 2013): do the arc a-b (normals of an edge of A) and the arc c-d
/// (negated normals of an edge of B) cross? Then the two edges make a face of A - B. `bxa` and
/// `dxc` are the edges' directions (b x a and d x c).
[[nodiscard]] bool is_minkowski_face(Vec3 a, Vec3 b, Vec3 bxa, Vec3 c, Vec3 d, Vec3 dxc) noexcept {
  const float cba = dot(c, bxa);
  const float dba = dot(d, bxa);
  const float adc = dot(a, dxc);
  const float bdc = dot(b, dxc);
  return cba * dba < 0.0f && adc * bdc < 0.0f && cba * bdc > 0.0f;
}

/// Floor of the size the contact's tolerances scale with (the smaller core's size; a bare point,
/// or a segment of no length and no radius, has size 0). It was kRelativeTolerance, 1e-5 units,
/// which left cores smaller than that with absolute tolerances: a capsule 7e-15 wide lying
/// across a triangle's edge took the face axis, 1.4 times its least depth, since the edge axis
/// had to beat the face by 1e-8 (finding 26's open part). 2^-90 keeps the tolerances scaled from
/// it (kEdgeContactTolerance of it) normal floats.
constexpr float kMinToleranceSize = 0x1p-90f;

/// Edges with a squared length below this (shorter than 2^-24) are taken by their direction
/// scaled to unit size (scale_edge) for the edge pairs' axes: then both squares are at
/// least 2^-48 and the parallel test's bound kParallelTolerance^2 |da|^2 |db|^2, below which
/// an axis counts as parallel, stays in float's normal range, and so does the squared length
/// of every axis that passes it.
constexpr float kTinyEdgeSquared = 0x1p-48f;
/// Above this squared length (longer than 2^30) contact_faceless takes a segment by its scaled
/// direction too (scale_edge<true>): its parallel test multiplies two squared lengths, and
/// within [kTinyEdgeSquared, kHugeEdgeSquared] each their product, [2^-96, 2^120], and the bound
/// made from it stay normal floats. (The edge pairs' axes need no such bound: their edges lie
/// within kFiniteQueryRange, so their squared cross products stay below 2^124.)
constexpr float kHugeEdgeSquared = 0x1p60f;

/// An edge direction `d` with its squared length `d2`, for products of edges (the edge pairs'
/// axes, their cross products; contact_faceless' parallel test): a tiny edge's (below
/// kTinyEdgeSquared) and, with `kHugeToo`, a huge one's (above kHugeEdgeSquared) scaled by a
/// power of two to unit size. A needle's side 1.4e-19 long against a capsule's core gave an
/// axis whose squared length, about 1e-46, is subnormal: the normal came out 1.5% off unit
/// length (the fuzzer's contact check, finding 18), and the parallel test's bound had
/// underflowed to zero. The direction is the same to the bit, so every test made from it
/// (a ratio of equal powers of the lengths) decides as on the edge itself, and the separation
/// and the unit axis are made from it as from any other.
template <bool kHugeToo = false>
COLLIDE_ALWAYS_INLINE void scale_edge(Vec3& d, float& d2) noexcept {
  const bool outside = kHugeToo ? !(d2 >= kTinyEdgeSquared && d2 <= kHugeEdgeSquared) : !(d2 >= kTinyEdgeSquared);
  if (outside) [[unlikely]] {
    d = scaled_to_unit_magnitude(d);
    d2 = dot(d, d);
  }
}

/// False when none of A's edges can be tiny (below kTinyEdgeSquared), so the edge pair loops
/// need not scale A's edges (their template flag: a test per edge in the inner loops cost the
/// hull level contact 5%). A hull's vertices lie pairwise farther apart than its tolerance
/// (convex_hull.hpp), a box's edges are its sides, a segment's and a triangle's are checked.
[[nodiscard]] bool may_have_tiny_edges(const Polytope3& a) noexcept {
  switch (a.kind) {
    case Polytope3::Kind::point:
      return false;
    case Polytope3::Kind::hull:
      return !(a.hull != nullptr && a.hull->tolerance * a.hull->tolerance >= kTinyEdgeSquared);
    case Polytope3::Kind::box: {
      const float half = std::min({a.faces[1].offset, a.faces[3].offset, a.faces[5].offset});
      return !(4.0f * half * half >= kTinyEdgeSquared);
    }
    default:
      for (int i = 0; i < a.edge_count; ++i) {
        const Vec3 d = a.vertex(a.edges[i].v1) - a.vertex(a.edges[i].v0);
        if (!(dot(d, d) >= kTinyEdgeSquared)) return true;
      }
      return false;
  }
}

/// Largest support value of A along `l` (A's frame).
[[nodiscard]] float support_value(const Polytope3& a, Vec3 l) noexcept {
  return dot(a.vertex(a.support(l)), l);
}
[[nodiscard]] float support_value(const PlacedPolytope& b, Vec3 l) noexcept {
  return dot(b.vertex(b.support(l)), l);
}

/// A solid A against a triangle B with a normal: the triangle's edges meet A's edges on the
/// Gauss map (query_box_triangle_edges, query_solid_triangle_edges), a few products each.
[[nodiscard]] bool triangle_against_solid(const Polytope3& a, const PlacedPolytope& b) noexcept {
  return a.solid && b.p.kind == Polytope3::Kind::triangle && b.p.faces[0].normal != Vec3(0.0f);
}

/// Box edge index (kBoxEdges' numbering) by direction k and the corner it starts from (bit k
/// clear; -1 for corners with bit k set).
constexpr std::array<std::array<int, 8>, 3> kBoxEdgeFrom = [] {
  std::array<std::array<int, 8>, 3> t{};
  for (auto& row : t) row.fill(-1);
  for (int e = 0; e < int(detail::kBoxEdges.size()); ++e) {
    const HullEdge& edge = detail::kBoxEdges[std::size_t(e)];
    const int bit = int(edge.v1) ^ int(edge.v0);
    const int k = bit == 1 ? 0 : bit == 2 ? 1 : 2;
    t[std::size_t(k)][edge.v0] = e;
  }
  return t;
}();

/// query_edges for a box A (centred on its frame's origin) against a triangle B. A box has
/// three edge directions; a triangle edge's half circle on -B's Gauss map crosses the great
/// circle of one direction's four arcs once, at l = e_k x d (oriented into the half circle),
/// and the box edge there is the one that supports A along l. So each of the nine pairs names
/// its box edge by the signs of l, without searching the Gauss map (Gregorius 2013), and the
/// separation is the triangle edge's offset along l less the box's support value: the nine
/// edge axes of Ericson 5.2.9 (Akenine-Moeller's triangle-box test) with their features.
EdgeQuery query_box_triangle_edges(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  EdgeQuery q;
  const Vec3 n = b.face_normal(0);
  std::array<Vec3, 3> dbs;
  std::array<float, 3> db2s;
  for (int j = 0; j < 3; ++j) {
    const HullEdge& eb = b.p.edges[j];
    dbs[std::size_t(j)] = b.vertex(eb.v1) - b.vertex(eb.v0);
    db2s[std::size_t(j)] = dot(dbs[std::size_t(j)], dbs[std::size_t(j)]);
  }
  if (!(std::min({db2s[0], db2s[1], db2s[2]}) >= kTinyEdgeSquared)) [[unlikely]] {
    for (int j = 0; j < 3; ++j) scale_edge(dbs[std::size_t(j)], db2s[std::size_t(j)]);
  }
  for (int j = 0; j < 3; ++j) {
    const HullEdge& eb = b.p.edges[j];
    const Vec3 pb = b.vertex(eb.v0);
    const Vec3 db = dbs[std::size_t(j)];
    const float min_ll = kParallelTolerance * kParallelTolerance * db2s[std::size_t(j)];
    // The edge's outward direction in the triangle's plane (its length does not matter).
    Vec3 u = cross(db, n);
    if (dot(u, b.vertex(3 - eb.v0 - eb.v1) - pb) > 0.0f) u = -u;
    for (int k = 0; k < 3; ++k) {
      // e_k x db, e_k the box's k-th axis.
      Vec3 l = k == 0 ? Vec3(0.0f, -db.z, db.y) : k == 1 ? Vec3(db.z, 0.0f, -db.x) : Vec3(-db.y, db.x, 0.0f);
      const float ll = dot(l, l);
      if (!(ll > min_ll)) continue;  // parallel: a face axis covers it
      if (dot(l, u) > 0.0f) l = -l;  // on -B's half circle: B's edge supports B along -l
      const int corner = (l.x > 0.0f ? 1 : 0) | (l.y > 0.0f ? 2 : 0) | (l.z > 0.0f ? 4 : 0);
      const int from = corner & ~(1 << k);
      const Vec3 pa = a.vertex(from);
      const float t = dot(l, pb - pa);
      if (q.edge_a >= 0 && !(t * std::fabs(t) > q.separation * std::fabs(q.separation) * ll)) continue;
      const float inv = 1.0f / std::sqrt(ll);
      q.separation = t * inv;
      q.edge_a = kBoxEdgeFrom[std::size_t(k)][std::size_t(from)];
      q.edge_b = j;
      q.axis = l * inv;
      if (q.separation > reach) return q;
    }
  }
  return q;
}

/// query_edges for a solid A against a triangle B, by silhouettes: the great circle of normals
/// perpendicular to a triangle edge's direction d holds that edge's half circle on -B's Gauss
/// map, and an edge of A crosses it where its two faces lie on either side of it (dot(n, d) of
/// opposite signs: A's silhouette seen along d). Each such edge is a Minkowski face of A - B
/// when the crossing lies on the half circle (Gregorius 2013). Each face's products with the
/// three edge directions are taken once, so an edge of A costs a comparison of stored signs
/// per triangle edge, where the arc-against-arc test takes four products.
template <bool kScaleA>
EdgeQuery query_solid_triangle_edges(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  struct TriangleEdge {
    Vec3 p, d, u;    ///< start, direction, outward direction in the plane (unnormalised)
    float min_ll;    ///< kParallelTolerance^2 |d|^2: shorter axes (over |da|^2) are parallel
  };
  const Vec3 n = b.face_normal(0);
  const std::array<Vec3, 3> v{b.vertex(0), b.vertex(1), b.vertex(2)};
  std::array<TriangleEdge, 3> te;
  std::array<float, 3> d2;
  for (int j = 0; j < 3; ++j) {
    const HullEdge& eb = b.p.edges[j];
    TriangleEdge& e = te[std::size_t(j)];
    e.p = v[eb.v0];
    e.d = v[eb.v1] - e.p;
    d2[std::size_t(j)] = dot(e.d, e.d);
  }
  if (!(std::min({d2[0], d2[1], d2[2]}) >= kTinyEdgeSquared)) [[unlikely]] {
    for (int j = 0; j < 3; ++j) scale_edge(te[std::size_t(j)].d, d2[std::size_t(j)]);
  }
  for (int j = 0; j < 3; ++j) {
    const HullEdge& eb = b.p.edges[j];
    TriangleEdge& e = te[std::size_t(j)];
    e.u = cross(e.d, n);
    if (dot(e.u, v[3u - eb.v0 - eb.v1] - e.p) > 0.0f) e.u = -e.u;
    e.min_ll = kParallelTolerance * kParallelTolerance * d2[std::size_t(j)];
  }
  // Each face's side of the three great circles: bit j when dot(normal, d_j) > 0, bit 4 + j
  // when < 0 (on the circle: neither); and bit 8 + j when the normal leans to the outer side
  // of edge j, dot(normal, u_j) > 0. An edge of A whose two faces both lean that way crosses
  // the circle there (its crossing is a positive mix of their normals), on the half that is
  // not B's.
  const auto face_signs = [&](int f) {
    const Vec3 fn = a.faces[f].normal;
    unsigned m = 0;
    for (int j = 0; j < 3; ++j) {
      const float s = dot(fn, te[std::size_t(j)].d);
      m |= (s > 0.0f ? 1u : 0u) << j;
      m |= (s < 0.0f ? 16u : 0u) << j;
      m |= (dot(fn, te[std::size_t(j)].u) > 0.0f ? 256u : 0u) << j;
    }
    return m;
  };
  alignas(16) std::uint16_t signs[kMaxSolidFaces + 4];
  const bool stored = a.face_count <= kMaxSolidFaces;  // always, for shapes built by collide
  if (stored) {
#if COLLIDE_HULL_FACES_SSE2
    if (a.face_blocks != nullptr) {
      // Four faces at a time: the same products as dot(), the six comparisons' lanes masked
      // to their bits and packed to one byte per face.
      const __m128 zero = _mm_setzero_ps();
      const int blocks = (a.face_count + 3) / 4;
      for (int blk = 0; blk < blocks; ++blk) {
        const float* p = a.face_blocks + 16 * blk;
        const __m128 nx = _mm_loadu_ps(p);
        const __m128 ny = _mm_loadu_ps(p + 4);
        const __m128 nz = _mm_loadu_ps(p + 8);
        __m128i m = _mm_setzero_si128();
        const auto along = [&](Vec3 d) {
          return _mm_add_ps(
              _mm_add_ps(_mm_mul_ps(nx, _mm_set1_ps(d.x)), _mm_mul_ps(ny, _mm_set1_ps(d.y))),
              _mm_mul_ps(nz, _mm_set1_ps(d.z)));
        };
        const auto bits = [](__m128 yes, int bit) {
          return _mm_and_si128(_mm_castps_si128(yes), _mm_set1_epi32(bit));
        };
        for (int j = 0; j < 3; ++j) {
          const __m128 s = along(te[std::size_t(j)].d);
          const __m128 lean = along(te[std::size_t(j)].u);
          m = _mm_or_si128(m, bits(_mm_cmpgt_ps(s, zero), 1 << j));
          m = _mm_or_si128(m, bits(_mm_cmplt_ps(s, zero), 16 << j));
          m = _mm_or_si128(m, bits(_mm_cmpgt_ps(lean, zero), 256 << j));
        }
        // Four 16-bit words (the values fit: below 2^11).
        const __m128i words = _mm_packs_epi32(m, m);
        std::memcpy(signs + 4 * blk, &words, 8);
      }
    } else
#endif
    {
      for (int f = 0; f < a.face_count; ++f) signs[f] = std::uint16_t(face_signs(f));
    }
  }
  EdgeQuery q;
  for (int i = 0; i < a.edge_count; ++i) {
    const HullEdge& ea = a.edges[i];
    const unsigned s0 = stored ? signs[ea.face0] : face_signs(ea.face0);
    const unsigned s1 = stored ? signs[ea.face1] : face_signs(ea.face1);
    // On the silhouette along triangle edge j: the two faces strictly on either side, and
    // not both leaning out of the triangle at that edge.
    const unsigned across = ((s0 & (s1 >> 4)) | (s1 & (s0 >> 4))) & ~((s0 & s1) >> 8) & 7u;
    if (across == 0) continue;
    const Vec3 pa = a.vertex(ea.v0);
    Vec3 da = a.vertex(ea.v1) - pa;
    float da2 = dot(da, da);
    if constexpr (kScaleA) scale_edge(da, da2);
    const Vec3 mid = a.faces[ea.face0].normal + a.faces[ea.face1].normal;  // inside A's arc
    for (int j = 0; j < 3; ++j) {
      if ((across & (1u << j)) == 0) continue;
      const TriangleEdge& e = te[std::size_t(j)];
      Vec3 l = cross(da, e.d);
      const float ll = dot(l, l);
      if (!(ll > e.min_ll * da2)) continue;
      // The crossing, on A's arc (between its two normals): there l is A's outward normal.
      if (dot(l, mid) < 0.0f) l = -l;
      if (dot(l, e.u) > 0.0f) continue;  // on the other half of the circle: not B's edge
      const float t = dot(l, e.p - pa);
      if (q.edge_a >= 0 && !(t * std::fabs(t) > q.separation * std::fabs(q.separation) * ll)) continue;
      const float inv = 1.0f / std::sqrt(ll);
      q.separation = t * inv;
      q.edge_a = i;
      q.edge_b = j;
      q.axis = l * inv;
      if (q.separation > reach) return q;
    }
  }
  return q;
}

/// Separation of A and B along the edge pairs' axes (see the file comment). B's edge (its
/// ends, direction and face normals turned into A's frame) is prepared once in the outer loop;
/// the inner loop over A's edges reads A's local data as it is.
template <bool kScaleA>
EdgeQuery query_edges_between(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  EdgeQuery q;
  const bool solids = a.solid && b.p.solid;
  for (int j = 0; j < b.p.edge_count; ++j) {
    const HullEdge& eb = b.p.edges[j];
    const Vec3 pb = b.vertex(eb.v0);
    Vec3 db = b.vertex(eb.v1) - pb;
    float db2 = dot(db, db);
    scale_edge(db, db2);
    // The arcs' axes (b x a, d x c) are taken from the edge directions, which point the same
    // way (v0 - v1: face0 lies left of v0 -> v1, so n0 x n1 runs along v1 - v0): on nearly
    // coplanar faces the cross product of the float normals can get the sign wrong.
    Vec3 c{0.0f};
    Vec3 d{0.0f};
    if (solids) {
      c = -b.face_normal(eb.face0);
      d = -b.face_normal(eb.face1);
    }
    for (int i = 0; i < a.edge_count; ++i) {
      const HullEdge& ea = a.edges[i];
      const Vec3 pa = a.vertex(ea.v0);
      Vec3 da = a.vertex(ea.v1) - pa;
      if (solids && !is_minkowski_face(a.faces[ea.face0].normal, a.faces[ea.face1].normal, -da, c,
                                       d, -db)) {
        continue;
      }
      float da2 = dot(da, da);
      if constexpr (kScaleA) scale_edge(da, da2);
      Vec3 l = cross(da, db);
      const float ll = dot(l, l);
      // Parallel edges: their axis is a face normal's or nothing new.
      if (!(ll > kParallelTolerance * kParallelTolerance * da2 * db2)) continue;
      float s;
      if (solids) {
        // The axis points out of A at its edge (away from A's centre), and A - B's face
        // through the two edges is at distance dot(l, pb - pa) / |l| from the origin. Most
        // pairs do not beat the best so far: compared first without the square root, as
        // t |t| against best |best| |l|^2 (x |x| grows with x).
        if (dot(l, pa - a.centroid) < 0.0f) l = -l;
        const float t = dot(l, pb - pa);
        if (q.edge_a >= 0 && !(t * std::fabs(t) > q.separation * std::fabs(q.separation) * ll)) continue;
        const float inv = 1.0f / std::sqrt(ll);
        l *= inv;
        s = t * inv;
      } else {
        l *= 1.0f / std::sqrt(ll);
        // Either side may be the separating one: take the better orientation.
        const float plus = -support_value(b, -l) - support_value(a, l);
        const float minus = -support_value(a, -l) - support_value(b, l);
        if (minus > plus) {
          l = -l;
          s = minus;
        } else {
          s = plus;
        }
      }
      if (s > q.separation) {
        q.separation = s;
        q.edge_a = i;
        q.edge_b = j;
        q.axis = l;
        if (s > reach) return q;
      }
    }
  }
  return q;
}

/// Separation of A and B along their edge pairs' axes: the best pair and its axis (A's frame,
/// out of A). A solid against a triangle by its own queries; A's edges scaled in the loops only
/// when one may be tiny (may_have_tiny_edges).
EdgeQuery query_edges(const Polytope3& a, const PlacedPolytope& b, float reach) noexcept {
  if (triangle_against_solid(a, b)) {
    if (a.kind == Polytope3::Kind::box) return query_box_triangle_edges(a, b, reach);
    return may_have_tiny_edges(a) ? query_solid_triangle_edges<true>(a, b, reach)
                                  : query_solid_triangle_edges<false>(a, b, reach);
  }
  return may_have_tiny_edges(a) ? query_edges_between<true>(a, b, reach) : query_edges_between<false>(a, b, reach);
}

// ---- manifold assembly -------------------------------------------------------------------

/// A point of the clipped polygon (on the incident core, A's frame) with the features that
/// made it: the incident feature, and the reference side that cut it (if any).
struct ClipVertex {
  Vec3 p;
  Feature incident;   ///< incident vertex, or the incident edge a side plane cut
  Feature reference;  ///< the reference face, or the reference side edge that cut it
  std::uint32_t incident_edge;  ///< incident polygon edge leaving this vertex
};

/// Clip buffer of capacity N: face_contact's polygons (kMaxClipVertices), or a point's or a
/// segment's ends (2: a segment clipped by a half-space stays a segment).
template <int N>
struct ClipBuffer {
  ScratchArray<ClipVertex, N> v;
  int count = 0;
};
using ClipPolygon = ClipBuffer<kMaxClipVertices>;
using ClipSegment = ClipBuffer<2>;

/// Clip `in` against the half-space dot(normal, x) <= offset (`normal` of any length: only the
/// signs of the heights and their ratios count); points created on a crossing get
/// the features (side edge `side`, the incident edge they lie on). A 2-point polygon is a
/// segment (no closing edge).
void clip_half_space(const ClipPolygon& in, ClipPolygon& out, Vec3 normal, float offset,
                     Feature side) noexcept {
  out.count = 0;
  const int n = in.count;
  if (n == 0) return;
  const bool closed = n > 2;
  const int last = closed ? n : n - 1;
  if (n == 1) {
    if (dot(normal, in.v[0].p) <= offset) out.v[out.count++] = in.v[0];
    return;
  }
  // Each corner's height over the plane is taken once and carried to the next edge.
  float dp = dot(normal, in.v[0].p) - offset;
  for (int i = 0; i < last; ++i) {
    const ClipVertex& p = in.v[i];
    const ClipVertex& q = in.v[i + 1 == n ? 0 : i + 1];
    const float dq = dot(normal, q.p) - offset;
    if (dp <= 0.0f && out.count < kMaxClipVertices) out.v[out.count++] = p;
    if ((dp < 0.0f && dq > 0.0f) || (dp > 0.0f && dq < 0.0f)) {
      if (out.count < kMaxClipVertices) {
        const float t = dp / (dp - dq);
        ClipVertex c;
        c.p = p.p + t * (q.p - p.p);
        c.incident = Feature{FeatureType::edge, p.incident_edge};
        c.reference = side;
        c.incident_edge = p.incident_edge;
        out.v[out.count++] = c;
      }
    }
    dp = dq;
  }
  // (An open polyline's loop ends with dp at its last corner.)
  if (!closed && dp <= 0.0f && out.count < kMaxClipVertices) {
    out.v[out.count++] = in.v[n - 1];
  }
}

/// The same clip for a point or a segment (at most 2 points, and a segment cut by a
/// half-space stays one), in place and without the polygon loop: the same points in the same
/// order as the polygon clip gives them (a point kept before the crossing after it, or the
/// crossing before the point kept), the same arithmetic.
void clip_half_space(ClipSegment& s, Vec3 normal, float offset, Feature side) noexcept {
  if (s.count == 0) return;
  if (s.count == 1) {
    if (!(dot(normal, s.v[0].p) <= offset)) s.count = 0;
    return;
  }
  const float dp = dot(normal, s.v[0].p) - offset;
  const float dq = dot(normal, s.v[1].p) - offset;
  if (dp <= 0.0f && dq <= 0.0f) return;  // both kept
  if ((dp < 0.0f && dq > 0.0f) || (dp > 0.0f && dq < 0.0f)) {
    const ClipVertex& p = s.v[0];
    const float t = dp / (dp - dq);
    ClipVertex c;
    c.p = p.p + t * (s.v[1].p - p.p);
    c.incident = Feature{FeatureType::edge, p.incident_edge};
    c.reference = side;
    c.incident_edge = p.incident_edge;
    s.v[dp < 0.0f ? 1 : 0] = c;
    return;
  }
  // One end on the plane and the other beyond it (or a height not a number): the end kept.
  if (dp <= 0.0f) {
    s.count = 1;
  } else if (dq <= 0.0f) {
    s.v[0] = s.v[1];
    s.count = 1;
  } else {
    s.count = 0;
  }
}

/// Calls `cut(normal, offset, side)` with each side plane of a reference face, while it
/// returns true (the clip is not empty yet): the face has outward normal `n` and `count`
/// corners counter-clockwise seen from outside, `corner(k)` (A's frame); side k runs from
/// corner k to k + 1 and is the edge feature `edge(k)`. A side plane's normal is
/// cross(edge, n), outward for a counter-clockwise loop (the face's interior is to the left of
/// each edge), not normalised: a clip needs only the sign of each height and their ratio.
template <class Corner, class Edge, class Cut>
void for_each_side(Vec3 n, int count, Corner corner, Edge edge, Cut cut) noexcept {
  for (int k = 0; k < count; ++k) {
    const Vec3 v0 = corner(k);
    const Vec3 v1 = corner(k + 1 == count ? 0 : k + 1);
    const Vec3 normal = cross(v1 - v0, n);
    if (!cut(normal, dot(normal, v0), Feature{FeatureType::edge, edge(k)})) return;
  }
}

/// The ends of a core without faces (a point or a segment, placed by `place`) as a clip
/// polygon: a sphere's one feature is its face 0 (sphere.hpp), a segment's ends are vertices.
template <class Place>
void core_ends(const Polytope3& core, const Place& place, Feature reference,
               ClipSegment& out) noexcept {
  const FeatureType type =
      core.kind == Polytope3::Kind::point ? FeatureType::face : FeatureType::vertex;
  out.count = core.vertex_count;
  for (int i = 0; i < core.vertex_count; ++i) {
    out.v[i] = ClipVertex{place.vertex(i), Feature{type, std::uint32_t(i)}, reference, 0u};
  }
}

/// The points of a face contact from the clipped incident points (on the incident core, A's
/// frame), for a reference plane of outward normal `n` and `offset`: those whose depth (radii
/// included) is at least -keep, placed midway between the surfaces, with depth along `d` (the
/// face's normal, or an axis turned outward from the reference face, of cosine `c` to it).
/// Written to `out`; returns how many.
template <int N>
int face_points(const ClipBuffer<N>& clipped, Vec3 n, float offset, Vec3 d, float c,
                float ref_radius, float inc_radius, bool ref_is_a, float keep,
                ManifoldPoint3* out) noexcept {
  // Separation s of the incident core point above the plane along d: s = height / c.
  const float radii = ref_radius + inc_radius;
  const float inv_c = c > 0.0f ? 1.0f / c : 1.0f;
  int count = 0;
  for (int i = 0; i < clipped.count; ++i) {
    const ClipVertex& v = clipped.v[i];
    const float s = (dot(n, v.p) - offset) * inv_c;
    const float depth = radii - s;
    if (!(depth >= -keep)) continue;
    const Vec3 ref_surface = v.p - s * d + ref_radius * d;
    const Vec3 inc_surface = v.p - inc_radius * d;
    ManifoldPoint3& mp = out[count++];
    mp.point = 0.5f * (ref_surface + inc_surface);
    mp.depth = depth;
    if (ref_is_a) {
      mp.id = ContactId{v.reference.index, v.incident.index, v.reference.type, v.incident.type};
    } else {
      mp.id = ContactId{v.incident.index, v.reference.index, v.incident.type, v.reference.type};
    }
  }
  return count;
}

/// The incident face of a core with faces, `inc` (placed by `place`), facing against `normal`
/// (A's frame): its face most anti-parallel to it, as a clip polygon in A's frame.
template <class Place>
void incident_polygon(const Polytope3& inc, const Place& place, Vec3 normal, Feature reference,
                      ClipPolygon& out) noexcept {
  out.count = 0;
  int best = 0;
  float best_dot = kInf;
  for (int j = 0; j < inc.face_count; ++j) {
    const float d = dot(place.normal(j), normal);
    if (d < best_dot) {
      best_dot = d;
      best = j;
    }
  }
  const HullFace& face = inc.faces[best];
  const int count = std::min<int>(face.count, kMaxClipVertices / 2);
  for (int k = 0; k < count; ++k) {
    const int c = inc.face_vertices[face.first + k];
    out.v[out.count++] =
        ClipVertex{place.vertex(c), Feature{FeatureType::vertex, std::uint32_t(c)}, reference,
                   std::uint32_t(inc.face_edges[face.first + k])};
  }
}


/// Appends `m`'s points, keeping at most 4 (see the file comment).
struct PointSet {
  ScratchArray<ManifoldPoint3, kMaxClipVertices> points;
  int count = 0;
};

void reduce_to_four(const PointSet& in, Vec3 normal, Manifold3& m) noexcept {
  detail::reduce_contact_points(in.points.data(), in.count, normal, m);
}

}  // namespace

void detail::reduce_contact_points(const ManifoldPoint3* points, int count, Vec3 normal,
                                   Manifold3& m, float depth_tie) noexcept {
  if (count <= 4) {
    for (int i = 0; i < count; ++i) m.points[i] = points[i];
    m.count = count;
    return;
  }
  int i0 = 0;
  for (int i = 1; i < count; ++i) {
    if (points[i].depth > points[i0].depth) i0 = i;
  }
  if (depth_tie > 0.0f) {
    // Among the points as deep as the deepest within depth_tie, the one farthest from the
    // points' centre: a corner of the patch rather than a point inside it.
    Vec3 centre(0.0f);
    for (int i = 0; i < count; ++i) centre += points[i].point;
    centre *= 1.0f / float(count);
    const float deepest = points[i0].depth;
    float far = -1.0f;
    for (int i = 0; i < count; ++i) {
      const float d = distance_squared(points[i].point, centre);
      if (points[i].depth >= deepest - depth_tie && d > far) {
        far = d;
        i0 = i;
      }
    }
  }
  const Vec3 p0 = points[i0].point;
  int i1 = -1;
  float best = -1.0f;
  for (int i = 0; i < count; ++i) {
    const float d = distance_squared(points[i].point, p0);
    if (i != i0 && d > best) {
      best = d;
      i1 = i;
    }
  }
  const Vec3 p1 = points[i1].point;
  // Signed area of (p0, p1, p) about the normal.
  const auto area = [&](Vec3 a, Vec3 b, Vec3 p) { return dot(cross(b - a, p - a), normal); };
  int i2 = -1;
  best = -1.0f;
  for (int i = 0; i < count; ++i) {
    const float s = std::fabs(area(p0, p1, points[i].point));
    if (i != i0 && i != i1 && s > best) {
      best = s;
      i2 = i;
    }
  }
  const Vec3 p2 = points[i2].point;
  const float side = area(p0, p1, p2) >= 0.0f ? 1.0f : -1.0f;
  // The fourth: the point that adds the most area to the triangle, outside one of its edges.
  int i3 = -1;
  best = 0.0f;
  for (int i = 0; i < count; ++i) {
    if (i == i0 || i == i1 || i == i2) continue;
    const Vec3 p = points[i].point;
    const float added = std::max({-side * area(p0, p1, p), -side * area(p1, p2, p),
                                  -side * area(p2, p0, p)});
    if (added > best) {
      best = added;
      i3 = i;
    }
  }
  m.points[0] = points[i0];
  m.points[1] = points[i1];
  m.points[2] = points[i2];
  m.count = 3;
  if (i3 >= 0) m.points[m.count++] = points[i3];
}

namespace {

/// Face contact: `ref_is_a` says which core's face `ref_face` is the reference. `n` is the
/// reference face's outward normal in A's frame; the manifold normal is n (A) or -n (B), or
/// `axis` when given (A's frame, from A to B, within kFaceContactSine of the face's normal:
/// EPA's penetration axis): then each clipped point is paired with the reference plane's
/// point along the axis, and its depth is measured along it (as Jolt's ManifoldBetweenTwoFaces
/// does). Points are kept while their depth (radii included) is at least -margin.
void face_contact(const Polytope3& a, const PlacedPolytope& b, bool ref_is_a, int ref_face,
                  float margin, Manifold3& m, const Vec3* axis = nullptr) noexcept {
  const Polytope3& ref = ref_is_a ? a : b.p;
  const Polytope3& inc = ref_is_a ? b.p : a;
  const HullFace& rface = ref.faces[ref_face];
  const Vec3 n = ref_is_a ? rface.normal : b.face_normal(ref_face);
  const float offset = ref_is_a ? rface.offset : b.face_offset(ref_face, n);
  const Feature ref_feature{FeatureType::face, std::uint32_t(ref.face_feature(ref_face))};
  const auto corner = [&](int k) {
    const int c = ref.face_vertices[rface.first + k];
    return ref_is_a ? a.vertex(c) : b.vertex(c);
  };
  const auto edge = [&](int k) { return std::uint32_t(ref.face_edges[rface.first + k]); };
  // Depth along the face's normal, or along the axis turned outward from the reference face.
  const Vec3 d = axis == nullptr ? n : (ref_is_a ? *axis : -*axis);
  const float c = axis == nullptr ? 1.0f : dot(n, d);
  const float inc_radius = inc.radius;
  PointSet set;
  if (inc.face_count == 0) {
    // A point or a segment: its ends, clipped in place.
    ClipSegment ends;
    if (ref_is_a) {
      core_ends(inc, BPlace{b}, ref_feature, ends);
    } else {
      core_ends(inc, IdentityPlace{a}, ref_feature, ends);
    }
    for_each_side(n, rface.count, corner, edge, [&](Vec3 normal, float off, Feature side) {
      clip_half_space(ends, normal, off, side);
      return ends.count > 0;
    });
    set.count = face_points(ends, n, offset, d, c, ref.radius, inc_radius, ref_is_a, margin,
                            &set.points[0]);
  } else {
    ClipPolygon poly;
    ClipPolygon tmp;
    if (ref_is_a) {
      incident_polygon(inc, BPlace{b}, n, ref_feature, poly);
    } else {
      incident_polygon(inc, IdentityPlace{a}, n, ref_feature, poly);
    }
    // Clipped back and forth between the two buffers (copying one is 1.8 KB).
    ClipPolygon* in = &poly;
    ClipPolygon* out = &tmp;
    for_each_side(n, rface.count, corner, edge, [&](Vec3 normal, float off, Feature side) {
      clip_half_space(*in, *out, normal, off, side);
      std::swap(in, out);
      return in->count > 0;
    });
    set.count = face_points(*in, n, offset, d, c, ref.radius, inc_radius, ref_is_a, margin,
                            &set.points[0]);
  }
  m.normal = ref_is_a ? d : -d;
  reduce_to_four(set, m.normal, m);
}

/// One point from the closest points `pa` (on A's core) and `pb` (on B's core), normal `n` from
/// A to B, separation of the cores `s` along it.
void point_contact(Vec3 pa, Vec3 pb, Vec3 n, float s, float ra, float rb, ContactId id,
                   Manifold3& m) noexcept {
  m.normal = n;
  m.count = 1;
  m.points[0].point = 0.5f * ((pa + ra * n) + (pb - rb * n));
  m.points[0].depth = ra + rb - s;
  m.points[0].id = id;
}

/// The other core's vertex deepest below reference face `ref_face` (of A when `ref_is_a`, else
/// of B): the face's outward normal (A's frame), the vertex and its height above the plane.
struct FaceSupport {
  Vec3 normal;
  Vec3 point;
  int vertex;
  float separation;
};

FaceSupport face_support(const Polytope3& a, const PlacedPolytope& b, bool ref_is_a,
                         int ref_face) noexcept {
  FaceSupport f;
  if (ref_is_a) {
    const HullFace& face = a.faces[ref_face];
    f.normal = face.normal;
    f.vertex = b.support(-f.normal);
    f.point = b.vertex(f.vertex);
    f.separation = dot(f.normal, f.point) - face.offset;
  } else {
    f.normal = b.face_normal(ref_face);
    f.vertex = a.support(-f.normal);
    f.point = a.vertex(f.vertex);
    f.separation = dot(f.normal, f.point) - b.face_offset(ref_face, f.normal);
  }
  return f;
}

/// One point for reference face `ref_face` (of A when `ref_is_a`, else of B): the other core's
/// deepest vertex `f` (face_support) against the face's plane.
void deepest_vertex_contact(const Polytope3& a, const PlacedPolytope& b, bool ref_is_a,
                            int ref_face, const FaceSupport& f, Manifold3& m) noexcept {
  const Vec3 on_plane = f.point - f.separation * f.normal;
  if (ref_is_a) {
    point_contact(on_plane, f.point, f.normal, f.separation, a.radius, b.p.radius,
                  ContactId{std::uint32_t(a.face_feature(ref_face)), std::uint32_t(f.vertex),
                            FeatureType::face, FeatureType::vertex},
                  m);
  } else {
    point_contact(f.point, on_plane, -f.normal, f.separation, a.radius, b.p.radius,
                  ContactId{std::uint32_t(f.vertex), std::uint32_t(b.p.face_feature(ref_face)),
                            FeatureType::vertex, FeatureType::face},
                  m);
  }
}

/// Of the edges of `p` (placed by `place`) parallel to edge `e`, the one farthest along `l`:
/// the unpruned edge test records the first of several parallel edges that give the same axis,
/// and the contact is on the one that supports the core along it.
template <class Place>
[[nodiscard]] int supporting_parallel_edge(const Polytope3& p, const Place& place, int e,
                                           Vec3 l) noexcept {
  const Vec3 d = place.vertex(p.edges[e].v1) - place.vertex(p.edges[e].v0);
  const float dd = dot(d, d);
  int best = e;
  float best_dot = dot(l, place.vertex(p.edges[e].v0));
  for (int i = 0; i < p.edge_count; ++i) {
    const Vec3 v0 = place.vertex(p.edges[i].v0);
    const Vec3 di = place.vertex(p.edges[i].v1) - v0;
    const Vec3 c = cross(d, di);
    if (dot(c, c) > kParallelTolerance * kParallelTolerance * dd * dot(di, di)) continue;
    const float v = dot(l, v0);
    if (v > best_dot) {
      best_dot = v;
      best = i;
    }
  }
  return best;
}

/// Edge contact of edge `ea` of A and `eb` of B along axis `n` (A to B), separation `s`.
void edge_contact(const Polytope3& a, const PlacedPolytope& b, int ea, int eb, Vec3 n, float s,
                  Manifold3& m) noexcept {
  // The pruned tests (two solids, a solid and a triangle) name the supporting edges already.
  if (!(a.solid && b.p.solid) && !triangle_against_solid(a, b)) {
    ea = supporting_parallel_edge(a, IdentityPlace{a}, ea, n);
    eb = supporting_parallel_edge(b.p, BPlace{b}, eb, -n);
  }
  const HullEdge& e1 = a.edges[ea];
  const HullEdge& e2 = b.p.edges[eb];
  const detail::SegmentSegmentClosest<3> c = detail::closest_between_segments<3>(
      a.vertex(e1.v0), a.vertex(e1.v1), b.vertex(e2.v0), b.vertex(e2.v1));
  point_contact(c.point1, c.point2, n, s, a.radius, b.p.radius,
                ContactId{std::uint32_t(ea), std::uint32_t(eb), FeatureType::edge, FeatureType::edge},
                m);
}

/// Feature of a core near a closest point given by GJK: the simplex's vertex if it used one
/// point of this core, else (an edge or a face of it) the vertex nearest to the point.
Feature near_feature(const Polytope3& p, Vec3 local_point) noexcept {
  if (p.kind == Polytope3::Kind::point) return Feature{FeatureType::face, 0};
  int best = 0;
  float best_d = kInf;
  for (int i = 0; i < p.vertex_count; ++i) {
    const float d = distance_squared(p.vertex(i), local_point);
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return Feature{FeatureType::vertex, std::uint32_t(best)};
}

/// The id of one point between A's core point `pa` and B's core point `pb` (both in A's
/// frame): the features of the cores nearest to them.
ContactId near_features(const Polytope3& a, const PlacedPolytope& b, Vec3 pa, Vec3 pb) noexcept {
  const Feature ka = near_feature(a, pa);
  const Feature kb = near_feature(b.p, b.to_local(pb));
  return ContactId{ka.index, kb.index, ka.type, kb.type};
}

/// Two cores without faces (points and segments): closest points; parallel overlapping
/// segments give two points (the overlap of B's segment clipped to A's slab).
void contact_faceless(const Polytope3& a, const PlacedPolytope& b, float margin,
                      Manifold3& m) noexcept {
  const Vec3 a0 = a.vertex(0);
  const Vec3 a1 = a.vertex(a.vertex_count - 1);
  const Vec3 b0 = b.vertex(0);
  const Vec3 b1 = b.vertex(b.p.vertex_count - 1);
  const detail::SegmentSegmentClosest<3> c = detail::closest_between_segments<3>(a0, a1, b0, b1);
  const float radii = a.radius + b.p.radius;
  const float reach = radii + margin;
  if (!(c.distance_squared <= reach * reach)) return;
  float s = std::sqrt(c.distance_squared);
  Vec3 n;
  if (s > kRelativeTolerance * (max_abs(c.point1) + max_abs(c.point2) + radii)) {
    n = unit_from(c.point2 - c.point1, c.distance_squared);
  } else {
    // The cores cross: any direction across both will do (one along a segment would not part
    // them: a sphere centred on a segment was pushed along it). Take the one across both
    // segments; else from A's centre to B's, less its part along the segment (a point and a
    // segment, or parallel segments; points: centre to centre); else across the segment; else up.
    s = 0.0f;
    const Vec3 da = a1 - a0;
    const Vec3 db = b1 - b0;
    const Vec3 centres = b.vertex(0) + 0.5f * db - (a0 + 0.5f * da);
    const Vec3 line = da != Vec3(0.0f) ? da : db;  // a segment's direction (zero for two points)
    n = normalize_or_zero(cross(da, db));             // across both segments
    if (n == Vec3(0.0f)) {
      const float ll = dot(line, line);
      n = normalize_or_zero(ll > 0.0f ? centres - line * (dot(centres, line) / ll) : centres);
    }
    if (n == Vec3(0.0f) && line != Vec3(0.0f)) {  // across the segment
      const Vec3 ad = collide::abs(line);
      Vec3 e(0.0f);
      e[ad.x <= ad.y && ad.x <= ad.z ? 0 : (ad.y <= ad.z ? 1 : 2)] = 1.0f;
      n = normalize_or_zero(cross(line, e));
    }
    if (n == Vec3(0.0f)) n = Vec3(0.0f, 1.0f, 0.0f);
    if (dot(n, centres) < 0.0f) n = -n;
  }
  const auto feature_of = [](const Polytope3& p, float t) {
    if (p.kind == Polytope3::Kind::point) return Feature{FeatureType::face, 0};
    if (t <= 0.0f) return Feature{FeatureType::vertex, 0};
    if (t >= 1.0f) return Feature{FeatureType::vertex, 1};
    return Feature{FeatureType::edge, 0};
  };
  // Parallel segments overlapping along their length: clip B's segment to A's slab.
  if (a.kind == Polytope3::Kind::segment && b.p.kind == Polytope3::Kind::segment) {
    const Vec3 da = a1 - a0;
    const Vec3 db = b1 - b0;
    const float la2 = dot(da, da);
    const float lb2 = dot(db, db);
    // Parallel by the sine of their angle. The test's terms are fourth powers of the lengths:
    // they would underflow for segments shorter than about 1e-10 (crossed capsules read as
    // parallel) or overflow for ones longer than about 1e9, so such a segment is taken by its
    // direction scaled by a power of two (scale_edge: the same test, exactly).
    Vec3 ua = da;
    Vec3 ub = db;
    float ua2 = la2;
    float ub2 = lb2;
    if (la2 > 0.0f && lb2 > 0.0f) {
      scale_edge<true>(ua, ua2);
      scale_edge<true>(ub, ub2);
    }
    const Vec3 axb = cross(ua, ub);
    if (dot(axb, axb) <= kParallelTolerance * kParallelTolerance * ua2 * ub2) {
      const float inv = 1.0f / la2;
      float t0 = dot(b0 - a0, da) * inv;
      float t1 = dot(b1 - a0, da) * inv;
      const bool reversed_b = t1 < t0;
      if (reversed_b) std::swap(t0, t1);
      const float lo = std::max(t0, 0.0f);
      const float hi = std::min(t1, 1.0f);
      if (hi - lo > kRelativeTolerance) {
        m.normal = n;
        m.count = 0;
        for (const float t : {lo, hi}) {
          const Vec3 pa = a0 + t * da;
          // B's point across from pa: B's core point minus the offset along n.
          const Vec3 pb = pa + s * n;
          ManifoldPoint3& mp = m.points[m.count++];
          mp.point = 0.5f * ((pa + a.radius * n) + (pb - b.p.radius * n));
          mp.depth = radii - s;
          const bool at_a_end = t <= 0.0f || t >= 1.0f;
          const Feature fa = at_a_end ? Feature{FeatureType::vertex, t <= 0.0f ? 0u : 1u}
                                      : Feature{FeatureType::edge, 0};
          const bool b_end = (t == lo && lo == t0) || (t == hi && hi == t1);
          const std::uint32_t b_vertex = (t == lo) != reversed_b ? 0u : 1u;
          const Feature fb = b_end ? Feature{FeatureType::vertex, b_vertex}
                                   : Feature{FeatureType::edge, 0};
          mp.id = ContactId{fa.index, fb.index, fa.type, fb.type};
        }
        return;
      }
    }
  }
  const Feature fa = feature_of(a, c.s);
  const Feature fb = feature_of(b.p, c.t);
  point_contact(c.point1, c.point2, n, s, a.radius, b.p.radius,
                ContactId{fa.index, fb.index, fa.type, fb.type}, m);
}

/// Tolerances of a pair scale with the smaller core (its diameter about its centre, plus its
/// radius).

/// How `contact_along` was asked: from EPA's result when the cores overlap (its depth, the
/// tolerance within which a face's depth counts as the same axis, and EPA's own accuracy).
struct EpaAxis {
  float depth;
  float tolerance;
  float accuracy;
};

/// EPA's deepest points `point_a` and `point_b` (A's frame) as one manifold point of depth
/// `depth` along `n`, with the features of the cores nearest to them.
ManifoldPoint3 epa_point(const Polytope3& a, const PlacedPolytope& b, Vec3 n, Vec3 point_a,
                         Vec3 point_b, float depth) noexcept {
  ManifoldPoint3 mp;
  mp.point = 0.5f * (point_a + point_b);
  mp.depth = depth;
  mp.id = near_features(a, b, point_a - a.radius * n, point_b + b.p.radius * n);
  return mp;
}

/// Adds point `p` (deeper than every point of face contact `m`) to `m`, over its shallowest
/// point when `m` is full.
void add_deepest(Manifold3& m, const ManifoldPoint3& p) noexcept {
  int slot = m.count;
  if (slot == kMaxManifoldPoints<3>) {
    slot = 0;
    for (int i = 1; i < m.count; ++i) {
      if (m.points[i].depth < m.points[slot].depth) slot = i;
    }
  } else {
    ++m.count;
  }
  m.points[slot] = p;
}

/// A face contact `m` made along EPA's normal `n` with reference face `ref_face`. If the face's
/// axis is worse than EPA's (the shapes' depth along it beyond EPA's by more than the
/// tolerance), the contact is an edge's or a corner's: EPA's deepest points make one point
/// along `n` (as the separating axis test gives for an edge pair). Otherwise the face's points
/// stay, no deeper than EPA's depth, and EPA's deepest points join them when the clip left them out (their depth short of
/// EPA's by more than its accuracy), over the shallowest point when the manifold is full: the
/// manifold's deepest point is the penetration depth.
void along_epa_axis(const Polytope3& a, const PlacedPolytope& b, bool ref_is_a, int ref_face,
                    Vec3 n, Vec3 point_a, Vec3 point_b, const EpaAxis& epa,
                    Manifold3& m) noexcept {
  const FaceSupport below = face_support(a, b, ref_is_a, ref_face);
  const float face_depth = a.radius + b.p.radius - below.separation;
  if (face_depth > epa.depth + epa.tolerance) {
    m.normal = n;
    m.count = 1;
    m.points[0] = epa_point(a, b, n, point_a, point_b, epa.depth);
    return;
  }
  // Along the axis no point is deeper than the shapes overlap (moving B by EPA's depth parts
  // them): a clipped point that projects past the reference face's edge along the tilted axis
  // would report more.
  for (int i = 0; i < m.count; ++i) m.points[i].depth = std::min(m.points[i].depth, epa.depth);
  if (m.max_depth() >= epa.depth - epa.accuracy) return;
  add_deepest(m, epa_point(a, b, n, point_a, point_b, epa.depth));
}

/// The contact along a known normal `n` (A's frame, from A to B) with the surfaces' closest
/// (apart: GJK) or deepest (overlapping: EPA, `epa` given) points `point_a` and `point_b`: a
/// face contact if a face faces along the normal (points kept down to depth -keep), else one
/// point; nothing beyond the margin. With EPA, a face whose axis is worse than EPA's by more
/// than the tolerance still makes the points, but along EPA's normal (as Jolt's manifold between
/// two faces keeps the penetration axis), and EPA's deepest point joins the manifold when the
/// clip left it out.
void contact_along(const Polytope3& a, const PlacedPolytope& b, Vec3 n, Vec3 point_a,
                   Vec3 point_b, float margin, float keep, const EpaAxis* epa,
                   Manifold3& m) noexcept {
  const float radii = a.radius + b.p.radius;
  // Separation of the cores along n (the points carry the radii, and pass each other when the
  // radii overlap).
  const float s = dot(point_b - point_a, n) + radii;
  if (s > radii + margin) return;
  int face_a = -1;
  float align_a = -kInf;
  for (int i = 0; i < a.face_count; ++i) {
    const float c = dot(a.faces[i].normal, n);
    if (c > align_a) {
      align_a = c;
      face_a = i;
    }
  }
  int face_b = -1;
  float align_b = -kInf;
  for (int j = 0; j < b.p.face_count; ++j) {
    const float c = -dot(b.face_normal(j), n);
    if (c > align_b) {
      align_b = c;
      face_b = j;
    }
  }
  const float min_cos = std::sqrt(1.0f - kFaceContactSine * kFaceContactSine);
  const bool ref_is_a = face_a >= 0 && align_a >= min_cos && align_a >= align_b;
  if (ref_is_a || (face_b >= 0 && align_b >= min_cos)) {
    face_contact(a, b, ref_is_a, ref_is_a ? face_a : face_b, keep, m, epa != nullptr ? &n : nullptr);
    if (m.count > 0) {
      if (epa != nullptr) {
        along_epa_axis(a, b, ref_is_a, ref_is_a ? face_a : face_b, n, point_a, point_b, *epa, m);
      }
      return;
    }
  }
  // One point from the closest points of the cores (undo the radii).
  const Vec3 pa = point_a - a.radius * n;
  const Vec3 pb = point_b + b.p.radius * n;
  point_contact(pa, pb, n, s, a.radius, b.p.radius, near_features(a, b, pa, pb), m);
}

/// A triangle's edge functions (seen along its normal): >= 0 inside edge k, which runs from
/// t[k] to t[k + 1]. Inside all three, a point is over the triangle (its projection is inside).
/// The triple product dot(cross(e_k, x - t_k), n) is dot(x - t_k, cross(n, e_k)): the edges'
/// inward normals in the plane are made once, and each point costs three dot products.
struct TriangleSides {
  const std::array<Vec3, 3>& t;
  float nn;  ///< squared length of the triangle's normal n (1 within rounding, or 0)
  std::array<Vec3, 3> inward;

  struct At {
    std::array<float, 3> e;  ///< the three edge functions (an array: glm's vec3[k] is a switch)
    bool over;
  };
  /// Inlined by force: an out-of-line call returning the four values took a tenth of a capsule's
  /// level contact (perf).
  [[nodiscard]] COLLIDE_ALWAYS_INLINE At at(Vec3 x) const noexcept {
    At s{{dot(x - t[0], inward[0]), dot(x - t[1], inward[1]), dot(x - t[2], inward[2])}, false};
    s.over = nn > 0.0f && s.e[0] >= 0.0f && s.e[1] >= 0.0f && s.e[2] >= 0.0f;
    return s;
  }
};

/// GJK's answer for a point or segment core A (sphere, capsule, segment) and a triangle with
/// corners `t` (A's frame) and rounding radius `t_radius`, in
/// closed form: the segment pierces the triangle (overlapped), or the closest points are those
/// of an endpoint and the triangle or of the segment and a triangle edge (Ericson, Real-Time
/// Collision Detection, 5.1.10). Cores closer than `touch` count as overlapping, as in GJK. The
/// result is gjk_distance's for the two proxies (A's frame; radii applied). `n` is the
/// triangle's unit normal as triangle_normal makes it (in double, so right on slivers too;
/// zero for a triangle without area). False when the pair is not one of these (then GJK
/// answers).
bool closest_to_triangle(const Polytope3& a, const std::array<Vec3, 3>& t, Vec3 n, float t_radius,
                         float touch, DistanceResult3& d) noexcept {
  using Kind = Polytope3::Kind;
  if (a.kind != Kind::point && a.kind != Kind::segment) return false;
  const Vec3 p = a.vertex(0);
  const Vec3 q = a.vertex(a.vertex_count - 1);
  d = DistanceResult3{};
  d.status = QueryStatus::overlapped;
  const float nn = dot(n, n);
  const TriangleSides sides{t, nn, {cross(n, t[1] - t[0]), cross(n, t[2] - t[1]), cross(n, t[0] - t[2])}};
  const float hp = dot(n, p - t[0]);
  const float hq = dot(n, q - t[0]);
  const bool one_side = (hp > 0.0f && hq > 0.0f) || (hp < 0.0f && hq < 0.0f);
  if (!one_side && hp != hq) {
    // Pierced: the ends on opposite sides of the plane (or one on it), the crossing over it.
    const Vec3 x = p + (hp / (hp - hq)) * (q - p);
    if (sides.at(x).over) {
      d.point_a = x;
      d.point_b = x;
      return true;
    }
  }
  // The closest pair is an end over the triangle with its projection, or lies on a triangle
  // edge: an end that is not over the triangle is nearest to an edge, which the segment-edge
  // pairs cover. The pair can lie inside edge k only where the segment is outside it, so an
  // edge with both ends inside is skipped. Ends on one side of the plane: the height is linear
  // along the segment, so no point of it is nearer the plane (and the triangle) than its lower
  // end; that end over the triangle is the answer, and no edge is tried.
  const TriangleSides::At sp = sides.at(p);
  Vec3 on_a = p;
  Vec3 on_b = p;
  float best = kInf;
  if (sp.over || a.kind == Kind::point) {
    on_b = sp.over ? p - (hp / nn) * n : closest_point_on_triangle(p, t[0], t[1], t[2]).point;
    best = length_squared(on_b - on_a);
  }
  if (a.kind == Kind::segment && !(sp.over && one_side && std::fabs(hp) <= std::fabs(hq))) {
    const auto consider = [&](Vec3 pa, Vec3 pb) {
      const float d2 = length_squared(pb - pa);
      if (d2 < best) {
        best = d2;
        on_a = pa;
        on_b = pb;
      }
    };
    const TriangleSides::At sq = sides.at(q);
    if (sq.over) consider(q, q - (hq / nn) * n);
    if (!(sq.over && one_side && std::fabs(hq) <= std::fabs(hp))) {
      for (std::size_t k = 0; k < 3; ++k) {
        if (nn > 0.0f && sp.e[k] >= 0.0f && sq.e[k] >= 0.0f) continue;
        const auto c = detail::closest_between_segments<3>(p, q, t[k], t[k == 2 ? 0 : k + 1]);
        consider(c.point1, c.point2);
      }
    }
  }
  const float core_distance = std::sqrt(best);
  if (!(core_distance > touch)) {
    d.point_a = 0.5f * (on_a + on_b);
    d.point_b = d.point_a;
    return true;
  }
  const Vec3 unit = unit_from(on_b - on_a, best);
  d.status = QueryStatus::separated;
  d.normal = unit;
  d.point_a = on_a + a.radius * unit;
  d.point_b = on_b - t_radius * unit;
  d.distance = std::max(core_distance - (a.radius + t_radius), 0.0f);
  return true;
}

/// The contact of two placed cores: `proxy_a` / `proxy_b` are the same shapes' support maps,
/// for GJK when the cores may be apart. `flat_closest`, when given, is the flat pair's closest
/// points already found (closest_to_triangle), not looked for again.
void contact_cores(const Polytope3& a, const ConvexProxy3& proxy_a, const PlacedPolytope& b,
                   const ConvexProxy3& proxy_b, const Transform3& b_in_a, float margin,
                   Manifold3& m, const DistanceResult3* flat_closest = nullptr) noexcept {
  m.count = 0;
  if (a.face_count == 0 && b.p.face_count == 0) {
    contact_faceless(a, b, margin, m);
    return;
  }
  const float radii = a.radius + b.p.radius;
  const float reach = radii + margin;
  const float size = std::max(std::min(a.size, b.p.size), kMinToleranceSize);
  // Touching within rounding counts: the clip keeps points that far apart too.
  const float touch = kRelativeTolerance * (size + max_abs(b_in_a.p));
  // The edge test's work, in solid pairs (kSatEdgePairLimit); a solid against a triangle
  // always takes the test. Two flat cores stay with the test below (A - B may be flat, which
  // EPA cannot grow around).
  const bool flat_pair = !a.solid && !b.p.solid;
  const int edge_work = triangle_against_solid(a, b) ? 0
                        : a.edge_count * b.p.edge_count *
                              (a.solid && b.p.solid ? 1 : a.vertex_count + b.p.vertex_count);
  if (edge_work > kSatEdgePairLimit && !flat_pair) {
    // Many edge pairs: GJK, and EPA for the axis when the cores overlap, then the same face
    // clipping (or one point). Cores apart: GJK's closest points, as below.
    const detail::CorePenetration r =
        detail::penetration_of_cores(proxy_a, Transform3{}, proxy_b, b_in_a);
    if (!r.cores_overlap) {
      contact_along(a, b, r.result.normal, r.result.point_a, r.result.point_b, margin, margin,
                    nullptr, m);
      return;
    }
    if (r.result.status != QueryStatus::max_iterations) {
      const EpaAxis axis{r.result.depth, kEdgeContactTolerance * size, touch};
      contact_along(a, b, r.result.normal, r.result.point_a, r.result.point_b, margin,
                    margin + touch, &axis, m);
      return;
    }
  }
  // Rounded or speculative cores found apart: the contact lies between their closest points,
  // which GJK finds.
  const auto closest = [&] { return gjk_distance<3>(proxy_a, Transform3{}, proxy_b, b_in_a); };
  const auto contact_at = [&](const DistanceResult3& d) {
    contact_along(a, b, d.normal, d.point_a, d.point_b, margin, margin, nullptr, m);
  };
  if (flat_pair) {
    // Two cores without volume (a triangle against a segment or a triangle): A - B may be
    // flat, and then the axes below miss the directions within its plane that separate it
    // from the origin. GJK decides apart or touching for them, and the separating axis test
    // runs only when they overlap.
    DistanceResult3 d;
    if (flat_closest != nullptr) {
      d = *flat_closest;
    } else if (b.p.kind != Polytope3::Kind::triangle ||
               !closest_to_triangle(a, {b.vertex(0), b.vertex(1), b.vertex(2)},
                                    triangle_normal(b.vertex(0), b.vertex(1), b.vertex(2)),
                                    b.p.radius, touch, d)) {
      d = closest();
    }
    if (d.status != QueryStatus::overlapped) {
      if (reach > 0.0f) {
        contact_at(d);
        return;
      }
      // Bare flat cores: apart unless within rounding of touching.
      if (d.distance > touch) return;
    }
  }
  const FaceQuery fa = query_faces_a(a, b, reach);
  if (fa.separation > reach) return;
  const FaceQuery fb = query_faces_b(a, b, reach);
  if (fb.separation > reach) return;
  const EdgeQuery ee = query_edges(a, b, reach);
  if (ee.separation > reach) return;
  if (reach > 0.0f && !flat_pair && std::max({fa.separation, fb.separation, ee.separation}) > 0.0f) {
    // An axis separates the cores (the test is complete for polytopes: cores that overlap have
    // no such axis). The test first, as most pairs a level gives overlap, and then GJK (which
    // must build a simplex around the origin to say so) would be wasted.
    const DistanceResult3 d = closest();
    if (d.status != QueryStatus::overlapped) {
      contact_at(d);
      return;
    }
  }

  const float best_face = std::max(fa.separation, fb.separation);
  if (std::max(best_face, ee.separation) > reach + touch) return;
  const float keep = margin + touch;
  const float edge_tolerance = kEdgeContactTolerance * size;
  if (ee.edge_a >= 0 && ee.separation > best_face + edge_tolerance) {
    edge_contact(a, b, ee.edge_a, ee.edge_b, ee.axis, ee.separation, m);
    return;
  }
  const float face_tolerance = kReferenceFaceTolerance * size;
  const bool ref_b = fb.face >= 0 && (fa.face < 0 || fb.separation > fa.separation + face_tolerance);
  const int ref_face = ref_b ? fb.face : fa.face;
  face_contact(a, b, !ref_b, ref_face, keep, m);
  if (m.count > 0) {
    // The clip keeps the incident core over the reference face. When its vertex deepest below
    // the face lies beyond the face's side planes (a small hull face over a large triangle),
    // the points fall short of the axis' depth. If that axis is the best of all (the minimum
    // translation, exactly: no tolerance preferred it), the vertex joins them, as EPA's
    // deepest point does in along_epa_axis. (A solid against a triangle only: between two
    // solids the clipped face is the contact a stack rests on.)
    const float ref_separation = ref_b ? fb.separation : fa.separation;
    const float axis_depth = radii - ref_separation;
    if (triangle_against_solid(a, b) && ref_separation >= best_face &&
        ref_separation >= ee.separation && m.max_depth() < axis_depth - touch) {
      Manifold3 deepest;
      deepest_vertex_contact(a, b, !ref_b, ref_face, face_support(a, b, !ref_b, ref_face), deepest);
      add_deepest(m, deepest.points[0]);
    }
    return;
  }
  // The clip kept nothing (a face axis at a corner, within the tolerances). The edges when
  // their axis is as good within the tolerance; else the face axis stays the answer, with the
  // incident core's deepest vertex as the one point (an edge axis would report a deeper,
  // wrong depth).
  if (ee.edge_a >= 0 && ee.separation >= best_face - edge_tolerance) {
    edge_contact(a, b, ee.edge_a, ee.edge_b, ee.axis, ee.separation, m);
  } else {
    deepest_vertex_contact(a, b, !ref_b, ref_face, face_support(a, b, !ref_b, ref_face), m);
  }
}

}  // namespace

namespace {

/// contact_level_triangle's box axes: the triangle's bounds apart from A's by more than `reach`.
[[nodiscard]] bool box_beyond(const Aabb3& a_bounds, const std::array<Vec3, 3>& corners,
                              float reach) noexcept {
  const Vec3 lo = glm::min(glm::min(corners[0], corners[1]), corners[2]);
  const Vec3 hi = glm::max(glm::max(corners[0], corners[1]), corners[2]);
  const Vec3 gap = glm::max(lo - a_bounds.max, a_bounds.min - hi);
  return gap.x > reach || gap.y > reach || gap.z > reach;
}

/// contact_level_triangle's plane axis: A apart from the triangle's plane by more than `reach`,
/// for the plane's unit normal `n` (triangle_normal's, in double: a sliver's plane made in float
/// turned far enough to drop contacts 0.05 deep) through `corner`. A's extent along n, the
/// support queries' values: a point's or a segment's ends and a box's corner by the signs of n
/// directly (called per candidate triangle; Polytope3::support is not inlined for its hull scan).
[[nodiscard]] bool plane_beyond(const Polytope3& a, Vec3 n, Vec3 corner, float reach) noexcept {
  const float plane = dot(n, corner);
  const float grown = reach + a.radius;
  float top;
  float bottom;
  if (a.kind == Polytope3::Kind::point || a.kind == Polytope3::Kind::segment) {
    const float d0 = dot(n, a.vertex(0));
    const float d1 = dot(n, a.vertex(a.vertex_count - 1));
    top = std::max(d0, d1);
    bottom = std::min(d0, d1);
  } else if (a.kind == Polytope3::Kind::box) {
    const int up = int(n.x > 0.0f) | (int(n.y > 0.0f) << 1) | (int(n.z > 0.0f) << 2);
    const int down = int(n.x < 0.0f) | (int(n.y < 0.0f) << 1) | (int(n.z < 0.0f) << 2);
    top = dot(n, a.vertex(up));
    bottom = dot(n, a.vertex(down));
  } else {
    top = dot(n, a.vertex(a.support(n)));
    bottom = dot(n, a.vertex(a.support(-n)));
  }
  const float above = plane - top;
  const float below = bottom - plane;
  return above > grown || below > grown;
}

}  // namespace

namespace {

/// A triangle as the reference face of a core without faces: its corners (A's frame), unit
/// normal `n` (the front's, corners counter-clockwise, triangle_normal's; zero for a
/// degenerate triangle) and the front's plane offset, as make_triangle_polytope makes its two
/// faces.
struct TriangleFaces {
  const std::array<Vec3, 3>& corners;
  Vec3 n;
  float offset;
};

/// face_contact for a core without faces (a point or a segment: A, the incident core) and the
/// triangle's side `face` (0: the front, 1: the back) as the reference, without the triangle's
/// polytope: A's ends clipped to the triangle's side planes, depth along the face's normal.
void core_on_triangle_face(const Polytope3& a, const TriangleFaces& t, int face, float keep,
                           Manifold3& m) noexcept {
  const Vec3 n = face == 0 ? t.n : -t.n;
  const float offset = face == 0 ? t.offset : -t.offset;
  ClipSegment ends;
  core_ends(a, IdentityPlace{a}, Feature{FeatureType::face, 0}, ends);
  // The side's corners as make_triangle_polytope's faces loop them (front 0 1 2, back 0 2 1).
  const std::size_t first = face == 0 ? 0 : 3;
  for_each_side(
      n, 3, [&](int k) { return t.corners[detail::kTriangleFaceVertices[first + std::size_t(k)]]; },
      [&](int k) { return std::uint32_t(detail::kTriangleFaceEdges[first + std::size_t(k)]); },
      [&](Vec3 normal, float off, Feature side) {
        clip_half_space(ends, normal, off, side);
        return ends.count > 0;
      });
  // (At most 2 points: the manifold holds them as they are.)
  m.count = face_points(ends, n, offset, n, 1.0f, 0.0f, a.radius, false, keep, m.points.data());
  m.normal = -n;
}

/// The tolerance size of a triangle as make_triangle_polytope's view has it (set_size): twice
/// the largest distance of a corner from the centroid.
[[nodiscard]] float triangle_size(const std::array<Vec3, 3>& t) noexcept {
  const Vec3 centroid = (t[0] + t[1] + t[2]) * (1.0f / 3.0f);
  float r = 0.0f;
  for (const Vec3& c : t) r = std::max(r, distance_squared(c, centroid));
  return 2.0f * std::sqrt(r);
}

/// contact_level_triangle for a core without faces (a sphere's point, a capsule's or a segment's
/// segment) whose closest points to the triangle are apart: contact_cores' answer for the pair
/// (the closest points in closed form; a face contact when their normal is within
/// kFaceContactSine of the triangle's, else one point), without the triangle's polytope, which
/// costs more to make than this whole answer. False when the cores overlap or touch (the
/// segment pierces the triangle), or A has neither a radius nor a margin: the separating axis
/// test decides those, with `d` (the closest points, when found) passed on.
bool core_triangle_contact(const Polytope3& a, const TriangleFaces& t, float margin,
                           Manifold3& m, DistanceResult3& d, bool& found) noexcept {
  m.count = 0;
  found = false;
  const float radii = a.radius;
  if (!(radii + margin > 0.0f)) return false;
  // contact_cores' tolerances: the smaller core's size (the triangle is in A's frame).
  const float size = std::max(std::min(a.size, triangle_size(t.corners)), kMinToleranceSize);
  closest_to_triangle(a, t.corners, t.n, 0.0f, kRelativeTolerance * size, d);
  found = true;
  if (d.status == QueryStatus::overlapped) return false;
  // contact_along with the triangle as B: its side most anti-parallel to the normal is the
  // reference face when within kFaceContactSine of it.
  const Vec3 n = d.normal;
  const float s = dot(d.point_b - d.point_a, n) + radii;
  if (s > radii + margin) return true;
  const float c = dot(t.n, n);
  const int face = c > -c ? 1 : 0;
  const float min_cos = std::sqrt(1.0f - kFaceContactSine * kFaceContactSine);
  if (std::max(c, -c) >= min_cos) {
    core_on_triangle_face(a, t, face, margin, m);
    if (m.count > 0) return true;
  }
  // One point from the closest points of the cores (undo A's radius), with the features
  // nearest to them (near_features).
  const Vec3 pa = d.point_a - a.radius * n;
  const Vec3 pb = d.point_b;
  const Feature fa = near_feature(a, pa);
  int kb = 0;
  float best = kInf;
  for (int k = 0; k < 3; ++k) {
    const float dk = distance_squared(t.corners[static_cast<std::size_t>(k)], pb);
    if (dk < best) {
      best = dk;
      kb = k;
    }
  }
  point_contact(pa, pb, n, s, a.radius, 0.0f,
                ContactId{fa.index, std::uint32_t(kb), fa.type, FeatureType::vertex}, m);
  return true;
}

/// The active-edge correction of contact_level_triangle (see contact3_triangle.hpp) for manifold
/// `m` of A (its `centroid` and `size`) against the triangle of corners `corners` and unit
/// normal `n`: `face_clip(face, keep, out)` makes the face contact with the triangle's side
/// `face` as the reference.
template <class FaceClip>
void use_active_edges(const std::array<Vec3, 3>& corners, Vec3 n, Vec3 centroid, float size,
                      FunctionRef<std::uint8_t()> edges, float margin, Manifold3& m,
                      FaceClip&& face_clip) noexcept {
  if (m.count == 0) return;
  if (n == Vec3(0.0f)) return;
  const float c = dot(m.normal, n);
  // Already the face's normal (within rounding): the face axis made it. (A normal only near it,
  // from the closest points of a rounded A beside the triangle, is an edge's or a vertex's.)
  if (std::fabs(c) >= 1.0f - kRelativeTolerance) return;
  // The triangle's feature nearest to A along the normal: the corners tied within
  // kParallelTolerance (the normal perpendicular to the edge between them, to that sine).
  float h[3];
  int top = 0;
  for (int k = 0; k < 3; ++k) {
    h[k] = -dot(corners[k], m.normal);
    if (h[k] > h[top]) top = k;
  }
  unsigned on = 0;
  for (int k = 0; k < 3; ++k) {
    if (k == top || h[top] - h[k] <= kParallelTolerance * length(corners[top] - corners[k])) {
      on |= 1u << k;
    }
  }
  // The edges active from the side the contact comes from (bits 3-5 behind: an edge concave
  // from the front is convex from behind, where a body below a height field meets a spike's
  // tip, finding 22): the normal's side. Not the centre's: a box under the spike, a little to
  // one side, has its centre in front of the plane of the tip's far face, continued below the
  // tip, and that face's clip turned its normal 107 degrees. A normal in the plane (to
  // kParallelTolerance) comes from neither side: an edge active from either stands (a sphere
  // above a height field collapsed to a vertical line lost its contact at the line's top to one
  // side's bits, finding 27). Asked only now (a height field computes them from its neighbours),
  // after the early outs.
  const std::uint8_t both = edges();
  const auto active_edges = static_cast<std::uint8_t>(
      (c < -kParallelTolerance ? both : c > kParallelTolerance ? both >> 3 : both | both >> 3) & 7u);
  if (active_edges == 7u) return;
  bool active = false;
  switch (on) {
    case 1u: active = (active_edges & 0b101u) != 0; break;  // vertex 0: edges 0 and 2
    case 2u: active = (active_edges & 0b011u) != 0; break;  // vertex 1: edges 0 and 1
    case 4u: active = (active_edges & 0b110u) != 0; break;  // vertex 2: edges 1 and 2
    case 3u: active = (active_edges & 0b001u) != 0; break;  // edge 0
    case 6u: active = (active_edges & 0b010u) != 0; break;  // edge 1
    case 5u: active = (active_edges & 0b100u) != 0; break;  // edge 2
    default:
      // All three corners level along the normal, which is not the face's: a tiny triangle, or
      // a needle seen across its length (the fuzzer's mesh probes found a sphere beside a needle
      // 1e8 long and 14 wide, touching its active long sides, whose contact the face clip below
      // dropped). The normal stands when any of its edges is active.
      active = active_edges != 0;
      break;
  }
  if (active) return;
  // The face that looks at A: face 0's outward normal is n. Which side A is on is told by its
  // centre (the replaced normal may lie almost in the triangle's plane), else by that normal.
  const float side = dot(n, centroid - corners[0]);
  const int face = side > 0.0f || (side == 0.0f && c < 0.0f) ? 0 : 1;
  Manifold3 fixed;
  const float touch = kRelativeTolerance * (size + max_abs(corners[0]));
  face_clip(face, margin + touch, fixed);
  if (fixed.count > 0) {
    m = fixed;
    return;
  }
  // The clip kept nothing. A touches the feature beyond the face's prism (a vertex that
  // stands out of a surface whose edges are all nearly flat). The contact stays, turned to the
  // face's normal as Jolt's ActiveEdges::FixNormal turns it, with its depth along that normal;
  // dropping it let shapes sink through such vertices.
  // A normal across the face (a shape entering the triangle sideways over an inactive seam)
  // has no depth along it: the neighbour beyond the seam holds the contact, and this one goes.
  Vec3 face_normal = face == 0 ? -n : n;  // from A to the triangle, as face_contact's
  float turn = dot(m.normal, face_normal);
  if (turn < -kParallelTolerance) {
    // The replaced normal goes through the triangle from the other side than A's centre: A
    // reaches across the triangle's plane beyond its edges and touches it from behind (a
    // capsule at a thin crease, touching both its sides beyond their shared inactive edge,
    // lost both contacts here: the fuzzer's capsule check, finding 19). That side's face then.
    face_clip(1 - face, margin + touch, fixed);
    if (fixed.count > 0) {
      m = fixed;
      return;
    }
    face_normal = -face_normal;
    turn = -turn;
  }
  if (!(turn > kParallelTolerance)) {
    m = fixed;
    return;
  }
  m.normal = face_normal;
  for (int i = 0; i < m.count; ++i) m.points[i].depth *= turn;
}

}  // namespace

namespace {

/// The frame of a polytope made in A's frame: PlacedPolytope's `identity` is set, so it is not read.
const Frame3 kIdentityFrame = Frame3::from(Transform3{});

/// contact_level_triangle's contact through the triangle's polytope (contact_cores), `n` the
/// triangle's unit normal (triangle_normal), `closest` the closest points of a core without
/// faces when already found.
void contact_triangle_polytope(const Polytope3& a, const ConvexProxy3& proxy_a,
                               const std::array<Vec3, 3>& corners, Vec3 n,
                               FunctionRef<std::uint8_t()> edges, float margin, Manifold3& m,
                               const DistanceResult3* closest) noexcept {
  Polytope3 tri;
  detail::make_triangle_polytope(tri, corners[0], corners[1], corners[2], 0.0f, n);
  const PlacedPolytope placed{tri, kIdentityFrame, true};
  const ConvexProxy3 proxy_b(Triangle{corners});
  contact_cores(a, proxy_a, placed, proxy_b, Transform3{}, margin, m, closest);
  use_active_edges(corners, n, a.centroid, a.size, edges, margin, m,
                   [&](int face, float keep, Manifold3& out) {
                     face_contact(a, placed, false, face, keep, out);
                   });
}

/// contact_level_triangle's contact for a core without faces, with the triangle's unit normal
/// `n` as triangle_normal makes it (and make_triangle_polytope its face; zero without area).
void core_contact_triangle(const Polytope3& a, const ConvexProxy3& proxy_a,
                           const std::array<Vec3, 3>& corners, Vec3 n,
                           FunctionRef<std::uint8_t()> edges, float margin, Manifold3& m) noexcept {
  const TriangleFaces t{corners, n, dot(n, corners[0])};
  DistanceResult3 closest;
  bool found = false;
  if (core_triangle_contact(a, t, margin, m, closest, found)) {
    use_active_edges(corners, n, a.centroid, a.size, edges, margin, m,
                     [&](int face, float keep, Manifold3& out) {
                       core_on_triangle_face(a, t, face, keep, out);
                     });
    return;
  }
  contact_triangle_polytope(a, proxy_a, corners, n, edges, margin, m, found ? &closest : nullptr);
}

/// contact_level_triangle for a triangle whose corners are collinear in A's frame (a needle
/// whose short side rounds away there: the fuzzer's mesh probes found a sphere on such a needle
/// without a contact, the triangle's polytope having no face normal): the segment between its
/// two farthest corners, which holds the third, through contact_cores, B's features renamed
/// to the triangle's (the segment's ends its corners, its edge the triangle's edge between them).
void collinear_triangle_contact(const Polytope3& a, const ConvexProxy3& proxy_a,
                                const std::array<Vec3, 3>& corners, float margin, Manifold3& m) noexcept {
  // Edge k runs from corner k to corner k + 1 (mod 3): the longest holds the third corner.
  int edge = 0;
  float longest = distance_squared(corners[0], corners[1]);
  for (int k = 1; k < 3; ++k) {
    const float d = distance_squared(corners[std::size_t(k)], corners[std::size_t((k + 1) % 3)]);
    if (d > longest) {
      longest = d;
      edge = k;
    }
  }
  const auto from = static_cast<std::uint32_t>(edge);
  const auto to = static_cast<std::uint32_t>((edge + 1) % 3);
  Polytope3 segment;
  detail::make_segment_polytope(segment, corners[from], corners[to], 0.0f);
  const PlacedPolytope placed{segment, kIdentityFrame, true};
  const ConvexProxy3 proxy_b(Segment3{corners[from], corners[to]});
  contact_cores(a, proxy_a, placed, proxy_b, Transform3{}, margin, m);
  for (int i = 0; i < m.count; ++i) {
    ContactId& id = m.points[i].id;
    if (id.type_b == FeatureType::vertex) id.index_b = id.index_b == 0 ? from : to;
    if (id.type_b == FeatureType::edge) id.index_b = from;
  }
}

}  // namespace

void detail::contact_level_triangle(const Polytope3& a, const ConvexProxy3& proxy_a,
                                    const Aabb3& a_bounds, const std::array<Vec3, 3>& corners,
                                    float reach, FunctionRef<std::uint8_t()> edges, float margin,
                                    Manifold3& m) noexcept {
  m.count = 0;
  if (box_beyond(a_bounds, corners, reach)) return;
  const Vec3 n = triangle_normal(corners[0], corners[1], corners[2]);
  if (n == Vec3(0.0f)) {
    collinear_triangle_contact(a, proxy_a, corners, margin, m);
    return;
  }
  if (plane_beyond(a, n, corners[0], reach)) return;
  if (a.face_count == 0) {
    // A sphere, capsule or segment: most triangles of a level it meets are answered without
    // the triangle's polytope.
    core_contact_triangle(a, proxy_a, corners, n, edges, margin, m);
    return;
  }
  contact_triangle_polytope(a, proxy_a, corners, n, edges, margin, m, nullptr);
}

template <Shape3DType A, Shape3DType B>
Manifold3 contact(const A& a, const Transform3& xa, const B& b, const Transform3& xb,
                  float margin) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xb), "contact: transform not finite or not unit");
  const Transform3 b_in_a = inv_mul(xa, xb);
  Polytope3 pa;
  Polytope3 pb;
  detail::make_polytope(pa, a);
  detail::make_polytope(pb, b);
  const PlacedPolytope placed{pb, Frame3::from(b_in_a)};
  Manifold3 m;
  contact_cores(pa, ConvexProxy3(a), placed, ConvexProxy3(b), b_in_a, std::max(margin, 0.0f), m);
  // Back to the world.
  m.normal = rotate(xa.q, m.normal);
  for (int i = 0; i < m.count; ++i) m.points[i].point = transform_point(xa, m.points[i].point);
  if (m.count == 0) m.normal = Vec3(0.0f);
  return m;
}

Manifold3 contact(const Shape3D& a, const Transform3& xa, const Shape3D& b, const Transform3& xb,
                  float margin) noexcept {
  return std::visit([&](const auto& sa, const auto& sb) { return contact(sa, xa, sb, xb, margin); },
                    a, b);
}

#define COLLIDE_CONTACT3_PAIR(A, B)                                                          \
  template Manifold3 contact<A, B>(const A&, const Transform3&, const B&, const Transform3&, \
                                   float) noexcept;
#define COLLIDE_CONTACT3_ROW(A)        \
  COLLIDE_CONTACT3_PAIR(A, Sphere)     \
  COLLIDE_CONTACT3_PAIR(A, Capsule3)   \
  COLLIDE_CONTACT3_PAIR(A, Segment3)   \
  COLLIDE_CONTACT3_PAIR(A, Box)        \
  COLLIDE_CONTACT3_PAIR(A, ConvexHull) \
  COLLIDE_CONTACT3_PAIR(A, Triangle)
COLLIDE_CONTACT3_ROW(Sphere)
COLLIDE_CONTACT3_ROW(Capsule3)
COLLIDE_CONTACT3_ROW(Segment3)
COLLIDE_CONTACT3_ROW(Box)
COLLIDE_CONTACT3_ROW(ConvexHull)
COLLIDE_CONTACT3_ROW(Triangle)
#undef COLLIDE_CONTACT3_ROW
#undef COLLIDE_CONTACT3_PAIR

}  // namespace collide
