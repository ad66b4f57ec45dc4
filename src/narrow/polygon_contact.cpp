// Contact between two convex polygons, rounded or not (capsules and segments arrive as
// 2-vertex polygons, or as B through their own front end, contact_polygon_segment: the same
// steps with B's separating axis pass reduced to one row of dot products).
//
// 1. Move B into A's local frame once, shifted so that A's vertex 0 is the origin: coordinates
//    stay small however far from the world origin the pair is.
// 2. Separating axis test over A's edge normals, then B's (sat.cpp), four edges at a time; stop
//    at an axis that separates the rounded shapes. Two parallel segments also need their common
//    direction as an axis.
// 3. The reference face is the axis of greatest separation, preferring A unless B's is larger by
//    kReferenceFaceTolerance of the faces' size, so that the choice does not flicker between
//    frames. The incident edge is the other polygon's edge most anti-parallel to the reference
//    normal.
// 4. If the cores overlap (or nearly touch), clip the incident edge to the reference edge's side
//    planes and keep the points within the radii sum of the reference face: 1 or 2 points.
//    If the cores are apart (rounded shapes only reach here then), the exact closest features of
//    the cores decide: corner against corner gives one point with the normal along the closest
//    points, otherwise clip against whichever edge holds the inside closest point.
// 5. If deep overlap of many short edges leaves the incident edge beside the reference edge,
//    try the other polygon's face, then report the deepest vertex alone.
// Catto, "Contact Manifolds", GDC 2007; Ericson, Real-Time Collision Detection, 5.2.1, 5.1.9.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <collide/core/config.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/sat.hpp>
#include <span>

#include "contact_routines.hpp"
#include "polygon_clip.hpp"
#include "segment_closest.hpp"
#include "sat_lanes.hpp"
#include "sat_soa.hpp"

namespace collide::detail {
namespace {

/// A polygon's core in the shared local frame, with its rounding radius.
struct LocalPolygon {
  const SoaPolygon* soa = nullptr;
  int count = 0;
  float radius = 0.0f;

  [[nodiscard]] int next(int i) const noexcept { return i + 1 == count ? 0 : i + 1; }
  [[nodiscard]] Vec2 vertex(int i) const noexcept { return soa->vertex(i); }
  [[nodiscard]] Vec2 normal(int i) const noexcept { return soa->normal(i); }
};

/// Index of the edge of `p` whose normal is most anti-parallel to `normal`.
int incident_edge(const LocalPolygon& p, Vec2 normal) noexcept {
  int best = 0;
  float lowest = dot(normal, p.normal(0));
  for (int i = 1; i < p.count; ++i) {
    const float d = dot(normal, p.normal(i));
    const bool lower = d < lowest;  // selects, not branches: the winner is data
    best = lower ? i : best;
    lowest = lower ? d : lowest;
  }
  return best;
}

/// What the routines below share: the map from the shared local frame to world space and the
/// scene's length tolerances.
struct Context {
  Transform frame;     ///< local (A's frame, origin at A's vertex 0) to world
  float apart = 0.0f;  ///< core separation above which the cores count as apart
  float merge = 0.0f;  ///< contact points closer than this are one point
};

/// Which side the routines below write their manifold from: as computed, polygon 1 being the
/// caller's A, or reversed (polygon 1 is the caller's B: normal flipped, A and B swapped in the
/// ids, the rule of `reverse` in manifold.hpp). Applied as each value is written, so the
/// caller's manifold is built in place, once, and never copied to be reversed.
struct Side {
  bool reversed = false;
  [[nodiscard]] Vec2 normal(Vec2 n) const noexcept { return reversed ? -n : n; }
  [[nodiscard]] ContactId id(ContactId i) const noexcept { return reversed ? swapped(i) : i; }
  [[nodiscard]] Side other() const noexcept { return Side{!reversed}; }
};

/// Face contact with polygon 1 as "A": clip edge `i21` of p2 to the side planes of reference
/// edge `i11` of p1 and keep the points within the radii sum of the reference face (merged into
/// one when they coincide, as when segments meet end to end). Normal: the reference edge's
/// outward normal. Written into `m` (fresh, count 0) from `side`.
void clip_manifold(const LocalPolygon& p1, int i11, const LocalPolygon& p2, int i21,
                   const Context& ctx, Side side, Manifold& m) noexcept {
  const Transform& frame = ctx.frame;
  const Vec2 n1 = p1.normal(i11);
  const EdgeRef ref{p1.vertex(i11), p1.vertex(p1.next(i11)), i11, p1.next(i11)};
  const EdgeRef inc{p2.vertex(i21), p2.vertex(p2.next(i21)), i21, p2.next(i21)};
  const float r1 = p1.radius;
  const float r2 = p2.radius;
  const float radius = r1 + r2;
  // The tangent left_perp(n1) is the unit direction of the reference edge.
  const ClippedEdge clipped = clip_incident_edge(ref, left_perp(n1), inc);
  Vec2 kept[2];
  float depth[2];
  ContactId id[2];
  int count = 0;
  for (int k = 0; k < clipped.count; ++k) {
    const ClipVertex& cv = clipped.vertices[k];
    const float separation = dot(n1, cv.point - ref.start);  // of the cores
    if (separation <= radius) {
      // B's core point is cv.point; A's surface lies at (r1 - separation) along n1 from it and
      // B's at -r2: the midpoint is half their sum.
      kept[count] = cv.point + (0.5f * (r1 - separation - r2)) * n1;
      depth[count] = radius - separation;
      id[count] = cv.id;
      ++count;
    }
  }
  if (count == 2 && distance_squared(kept[0], kept[1]) <= ctx.merge * ctx.merge) {
    if (depth[1] > depth[0]) {
      kept[0] = kept[1];
      depth[0] = depth[1];
      id[0] = id[1];
    }
    count = 1;
  }
  if (count == 0) return;
  m.normal = side.normal(rotate(frame.q, n1));
  for (int k = 0; k < count; ++k) {
    m.points[k] = {transform_point(frame, kept[k]), depth[k], side.id(id[k])};
  }
  m.count = count;
}

/// One point at the vertex of p2 deepest below reference edge `i11` of p1, with that depth,
/// written into `m` as clip_manifold does.
void deepest_point_manifold(const LocalPolygon& p1, int i11, const LocalPolygon& p2,
                            const Context& ctx, Side side, Manifold& m) noexcept {
  const Transform& frame = ctx.frame;
  const Vec2 n1 = p1.normal(i11);
  int deepest = 0;
  for (int k = 1; k < p2.count; ++k) {
    if (dot(n1, p2.vertex(k)) < dot(n1, p2.vertex(deepest))) deepest = k;
  }
  const float separation = dot(n1, p2.vertex(deepest) - p1.vertex(i11));
  const float radius = p1.radius + p2.radius;
  if (!(separation <= radius)) return;
  m.normal = side.normal(rotate(frame.q, n1));
  m.points[0] = {transform_point(frame, p2.vertex(deepest) +
                                            (0.5f * (p1.radius - separation - p2.radius)) * n1),
                 radius - separation,
                 side.id(ContactId{static_cast<std::uint8_t>(i11),
                                   static_cast<std::uint8_t>(deepest), FeatureType::edge,
                                   FeatureType::vertex})};
  m.count = 1;
}

/// Closest points of edge e1 of p1 and edge e2 of p2, with the edges.
struct ClosestEdges {
  int e1 = 0;
  int e2 = 0;
  SegmentSegmentClosest<2> points{};
  float distance2 = 0.0f;
};

ClosestEdges closest_edges(const LocalPolygon& p1, int e1, const LocalPolygon& p2,
                           int e2) noexcept {
  const SegmentSegmentClosest<2> c = closest_between_segments<2>(
      p1.vertex(e1), p1.vertex(p1.next(e1)), p2.vertex(e2), p2.vertex(p2.next(e2)));
  return {e1, e2, c, c.distance_squared};
}

/// The edge of `p` on the other side of the end of edge `e` where `fraction` sits (0: start,
/// 1: end), or `e` itself when the fraction is inside the edge.
int edge_across(const LocalPolygon& p, int e, float fraction) noexcept {
  if (fraction == 0.0f) return e == 0 ? p.count - 1 : e - 1;
  if (fraction == 1.0f) return p.next(e);
  return e;
}

/// The manifold with polygon 1 as "A" and `reference.edge` of p1 the axis of greatest
/// separation. `apart` is the core separation above which the cores count as apart (rounded
/// shapes only). Then the exact closest features of the cores decide, found by walking from
/// the reference and incident edges to neighbouring edges while the distance drops (a closest
/// feature walk, as in Lin-Canny and V-Clip; one or two steps in practice): corner against
/// corner gives one point with the normal along the closest points; a corner against the inside
/// of an edge makes that edge the reference face; otherwise p1's edge is. Written into `m` as
/// clip_manifold does.
void reference_face_manifold(const LocalPolygon& p1, const EdgeSeparation& reference,
                             const LocalPolygon& p2, const Context& ctx, Side side,
                             Manifold& m) noexcept {
  const Transform& frame = ctx.frame;
  const int i11 = reference.edge;
  const int i21 = incident_edge(p2, p1.normal(i11));
  if (!(reference.separation > ctx.apart)) return clip_manifold(p1, i11, p2, i21, ctx, side, m);

  ClosestEdges best = closest_edges(p1, i11, p2, i21);
  for (int step = 0; step < p1.count + p2.count; ++step) {
    const int across1 = edge_across(p1, best.e1, best.points.s);
    const int across2 = edge_across(p2, best.e2, best.points.t);
    ClosestEdges next = best;
    if (across1 != best.e1) {
      const ClosestEdges c = closest_edges(p1, across1, p2, best.e2);
      if (c.distance2 < next.distance2) next = c;
    }
    if (across2 != best.e2) {
      const ClosestEdges c = closest_edges(p1, best.e1, p2, across2);
      if (c.distance2 < next.distance2) next = c;
    }
    if (!(next.distance2 < best.distance2)) break;
    best = next;
  }
  const float f1 = best.points.s;
  const float f2 = best.points.t;
  const bool end1 = f1 == 0.0f || f1 == 1.0f;
  const bool end2 = f2 == 0.0f || f2 == 1.0f;
  if (end1 && end2) {
    const float r1 = p1.radius;
    const float r2 = p2.radius;
    if (!(best.distance2 <= (r1 + r2) * (r1 + r2))) return;
    // The corners' offset gives the normal. Rounding can put the two corners together although
    // the separating axis holds the cores apart (a polygon 2.7e7 long, whose far corner touches a
    // small box: 2 units a float step in the shared frame, fuzz_shapes): then the axis and its
    // separation serve, the cores being at least that far apart.
    const bool offset = best.distance2 >= kMinDirectionLengthSquared;
    const float dist = offset ? std::sqrt(best.distance2) : reference.separation;
    const Vec2 n = offset ? (best.points.point2 - best.points.point1) * (1.0f / dist) : p1.normal(i11);
    // Midway between A's surface point1 + r1 n and B's point2 - r2 n.
    const Vec2 mid = best.points.point1 + (0.5f * (r1 + dist - r2)) * n;
    const int v1 = f1 == 0.0f ? best.e1 : p1.next(best.e1);
    const int v2 = f2 == 0.0f ? best.e2 : p2.next(best.e2);
    m.normal = side.normal(rotate(frame.q, n));
    m.points[0] = {transform_point(frame, mid), r1 + r2 - dist,
                   side.id(ContactId{static_cast<std::uint8_t>(v1), static_cast<std::uint8_t>(v2),
                                     FeatureType::vertex, FeatureType::vertex})};
    m.count = 1;
    return;
  }
  if (end1) {
    return clip_manifold(p2, best.e2, p1, incident_edge(p1, p2.normal(best.e2)), ctx,
                         side.other(), m);
  }
  clip_manifold(p1, best.e1, p2, incident_edge(p2, p1.normal(best.e1)), ctx, side, m);
}

/// Everything after the separating axis test, shared by both front ends: `pa` and `pb` are the
/// cores in A's frame shifted so that A's vertex 0 is the origin (`origin` in A's local frame),
/// sep_a and sep_b the axes of greatest separation over A's and B's edges, neither above the
/// radius sum. `xa` and `origin` map that frame to world space. The manifold is written into
/// `m` (fresh, count 0: the caller's return slot).
void finish_contact(const LocalPolygon& pa, const EdgeSeparation& sep_a, const LocalPolygon& pb,
                    const EdgeSeparation& sep_b, const Transform& xa, Vec2 origin,
                    Manifold& m) noexcept {
  const float radius = pa.radius + pb.radius;
  EdgeSeparation ref_a = sep_a;
  if (pa.count == 2 && pb.count == 2) {
    // Two segments' Minkowski difference is a parallelogram whose edge normals are the two
    // segment normals, except when the segments are parallel: then it is a segment and its end
    // caps add the segments' direction as an axis (collinear segments are apart only along it).
    const Vec2 t = left_perp(pa.normal(0));  // A's direction, in A's frame
    const float a0 = dot(t, pa.vertex(0)), a1 = dot(t, pa.vertex(1));
    const float b0 = dot(t, pb.vertex(0)), b1 = dot(t, pb.vertex(1));
    const float axial =
        std::max(std::min(b0, b1) - std::max(a0, a1), std::min(a0, a1) - std::max(b0, b1));
    if (axial > radius) return;
    // Apart along the direction: the closest features decide (from A's edge, see below).
    if (axial > std::max(sep_a.separation, sep_b.separation)) ref_a.separation = axial;
  }

  // The size that the tolerances scale with: the longer of the two competing faces (largest
  // coordinate extent), found without a loop or a square root.
  const auto edge_extent = [](const LocalPolygon& p, int e) {
    return collide::abs(p.vertex(p.next(e)) - p.vertex(e));
  };
  const Vec2 ea = edge_extent(pa, sep_a.edge);
  const Vec2 eb = edge_extent(pb, sep_b.edge);
  const float size = std::max(std::max(ea.x, ea.y), std::max(eb.x, eb.y));
  const Context ctx{{transform_point(xa, origin), xa.q},
                    kRelativeTolerance * size,
                    kContactMergeTolerance * size};
  const bool b_reference = sep_b.separation > ref_a.separation + kReferenceFaceTolerance * size;
  constexpr Side as_is{false};
  constexpr Side reversed_side{true};
  if (b_reference) {
    reference_face_manifold(pb, sep_b, pa, ctx, reversed_side, m);
  } else {
    reference_face_manifold(pa, ref_a, pb, ctx, as_is, m);
  }
  const float best_separation = std::max(ref_a.separation, sep_b.separation);
  if (m.count > 0 || best_separation > ctx.apart) return;
  // Cores touching within the tolerance (rounding decides the sign), yet the incident edge
  // clipped to nothing: a corner resting on the face. The deepest vertex below the best face is
  // the answer. The other polygon's face is not: a small box resting on a long wall is deep
  // below the wall's far corners along its own axes, and clipping against its face reported
  // metres of depth (a box pushed through the boundary of a large world).
  if (best_separation >= -ctx.apart) {
    if (b_reference) {
      deepest_point_manifold(pb, sep_b.edge, pa, ctx, reversed_side, m);
    } else {
      deepest_point_manifold(pa, ref_a.edge, pb, ctx, as_is, m);
    }
    return;
  }
  // Cores overlap yet the incident edge missed the reference edge's slab: it happens when many
  // short edges overlap deeply (a 64-gon), where the edge facing the least-overlap axis can lie
  // beside the reference edge. Try the other polygon's best face, then the deepest vertex.
  if (b_reference) {
    reference_face_manifold(pa, ref_a, pb, ctx, as_is, m);
  } else {
    reference_face_manifold(pb, sep_b, pa, ctx, reversed_side, m);
  }
  if (m.count > 0) return;
  if (b_reference) {
    deepest_point_manifold(pb, sep_b.edge, pa, ctx, reversed_side, m);
  } else {
    deepest_point_manifold(pa, ref_a.edge, pb, ctx, as_is, m);
  }
}

/// The general front end: both cores copied into 4-wide x/y arrays in A's frame. Writes into
/// `m` (fresh, count 0).
void contact_polygons_general(const Polygon& a, const Transform& xa, const Polygon& b,
                              const Transform& xb, Manifold& m) noexcept {
  const int na = a.count;
  const int nb = b.count;
  const SharedFrame f = shared_frame(a, xa, xb);
  const Transform& b_in_a = f.b_in_a;
  const Vec2 origin = f.origin;
  const Vec2 shift = f.shift;

  // Both cores in A's frame, origin at A's vertex 0, as x and y arrays (the separating axis
  // test runs four edges wide on them).
  SoaPolygon pa_soa;
  SoaPolygon pb_soa;
  for (int i = 0; i < na; ++i) {
    pa_soa.set_vertex(i, a.vertices[i] - origin);
    pa_soa.set_normal(i, a.normals[i]);
  }
  pa_soa.finish_vertices(na);
  pa_soa.finish_normals();
  for (int j = 0; j < nb; ++j) pb_soa.set_vertex(j, rotate(b_in_a.q, b.vertices[j]) + shift);
  pb_soa.finish_vertices(nb);
  const float radius = a.radius + b.radius;

  const EdgeSeparation sep_a = find_max_separation_soa(pa_soa, pb_soa, radius);
  if (sep_a.separation > radius) return;
  for (int j = 0; j < nb; ++j) pb_soa.set_normal(j, rotate(b_in_a.q, b.normals[j]));
  pb_soa.finish_normals();
  const EdgeSeparation sep_b = find_max_separation_soa(pb_soa, pa_soa, radius);
  if (sep_b.separation > radius) return;
  finish_contact({&pa_soa, na, a.radius}, sep_a, {&pb_soa, nb, b.radius}, sep_b, xa, origin, m);
}

#if COLLIDE_SMALL_POLYGON_SSE2
/// finish_contact on cores held in lanes: only the groups used are stored (no fill of the full
/// capacity).
template <int kGroupsA, int kGroupsB>
void finish_from_lanes(const LanePoints<kGroupsA>& av, const LanePoints<kGroupsA>& an, int na,
                       float ra, const EdgeSeparation& sep_a, const LanePoints<kGroupsB>& bv,
                       const LanePoints<kGroupsB>& bn, int nb, float rb,
                       const EdgeSeparation& sep_b, const Transform& xa, Vec2 origin,
                       Manifold& m) noexcept {
  SoaPolygon pa_soa;  // NOLINT: arrays deliberately left unset beyond the groups used
  SoaPolygon pb_soa;  // NOLINT
  pa_soa.count = na;
  pa_soa.padded = kGroupsA * kSatLanes;
  pb_soa.count = nb;
  pb_soa.padded = kGroupsB * kSatLanes;
  for (int g = 0; g < kGroupsA; ++g) {
    _mm_store_ps(pa_soa.x + kSatLanes * g, av.x[g]);
    _mm_store_ps(pa_soa.y + kSatLanes * g, av.y[g]);
    _mm_store_ps(pa_soa.nx + kSatLanes * g, an.x[g]);
    _mm_store_ps(pa_soa.ny + kSatLanes * g, an.y[g]);
  }
  for (int g = 0; g < kGroupsB; ++g) {
    _mm_store_ps(pb_soa.x + kSatLanes * g, bv.x[g]);
    _mm_store_ps(pb_soa.y + kSatLanes * g, bv.y[g]);
    _mm_store_ps(pb_soa.nx + kSatLanes * g, bn.x[g]);
    _mm_store_ps(pb_soa.ny + kSatLanes * g, bn.y[g]);
  }
  finish_contact({&pa_soa, na, ra}, sep_a, {&pb_soa, nb, rb}, sep_b, xa, origin, m);
}

/// The register front end for polygons of up to kGroupsA (kGroupsB) groups of kSatLanes
/// vertices. Writes into `m` (fresh, count 0).
template <int kGroupsA, int kGroupsB>
void contact_polygons_lanes(const Polygon& a, const Transform& xa, const Polygon& b,
                            const Transform& xb, Manifold& m) noexcept {
  const int na = a.count;
  const int nb = b.count;
  const SharedFrame f = shared_frame(a, xa, xb);
  const Vec2 origin = f.origin;
  const float radius = a.radius + b.radius;
  LanePair<kGroupsA, kGroupsB> p;
  if (!separate_lanes(a, b, f, radius, p)) {
    contact_polygons_general(a, xa, b, xb, m);
    return;
  }
  const EdgeSeparation& sep_a = p.sep_a;
  const EdgeSeparation& sep_b = p.sep_b;
  if (sep_a.separation > radius || sep_b.separation > radius) return;

  finish_from_lanes<kGroupsA, kGroupsB>(p.av, p.an, na, a.radius, sep_a, p.bv, p.bn, nb,
                                         b.radius, sep_b, xa, origin, m);
}

/// The register front end for a polygon A (up to kGroupsA groups of kSatLanes vertices)
/// against a 2-vertex B, a capsule's or segment's core b0 -> b1: B's edges are one line with
/// normals m and -m, so B's separating axis pass is one row of dot products of m with A's
/// vertices, their minimum giving edge 0's separation and their maximum edge 1's
/// (min_j -(m . v_j) = -max_j (m . v_j), exactly), and A's pass needs B's two points only (B's
/// padding repeats b1, and min(d0, d1, d1, d1) = min(d0, d1)). The same values as
/// contact_polygons_lanes on B's 2-vertex polygon, so the manifold is bitwise the same (tests/
/// narrow check it; with finite products: a NaN can survive a minimum taken in one order and
/// not in another). Returns false (nothing written) on a NaN lane: the caller's general path
/// decides.
template <int kGroupsA>
bool contact_polygon_segment_lanes(const Polygon& a, const Transform& xa, const SegmentCore& b,
                                   const Transform& xb, Manifold& m) noexcept {
  const int na = a.count;
  const SharedFrame f = shared_frame(a, xa, xb);
  const float radius = a.radius + b.radius;
  LanePoints<kGroupsA> av;
  LanePoints<kGroupsA> an;
  load_reference(a, f.origin, av, an);
  const __m128 c = _mm_set1_ps(f.b_in_a.q.c);
  const __m128 s = _mm_set1_ps(f.b_in_a.q.s);
  // B's lanes as load_points lays out a 2-vertex polygon (the last point repeated), set from
  // registers: a 16-byte load of two 8-byte stores just made would stall on store forwarding.
  LanePoints<1> bv;
  bv.x[0] = _mm_setr_ps(b.b0.x, b.b1.x, b.b1.x, b.b1.x);
  bv.y[0] = _mm_setr_ps(b.b0.y, b.b1.y, b.b1.y, b.b1.y);
  rotate_lanes(bv, c, s, f.shift.x, f.shift.y);

  // A's edges against B's two points.
  const __m128 b0x = broadcast_lane(bv.x[0], 0);
  const __m128 b0y = broadcast_lane(bv.y[0], 0);
  const __m128 b1x = broadcast_lane(bv.x[0], 1);
  const __m128 b1y = broadcast_lane(bv.y[0], 1);
  __m128 sa[kGroupsA];
  for (int g = 0; g < kGroupsA; ++g) {
    const __m128 d0 = _mm_add_ps(_mm_mul_ps(an.x[g], b0x), _mm_mul_ps(an.y[g], b0y));
    const __m128 d1 = _mm_add_ps(_mm_mul_ps(an.x[g], b1x), _mm_mul_ps(an.y[g], b1y));
    sa[g] = _mm_sub_ps(_mm_min_ps(d0, d1), _mm_add_ps(_mm_mul_ps(an.x[g], av.x[g]),
                                                      _mm_mul_ps(an.y[g], av.y[g])));
  }
  EdgeSeparation sep_a;
  if (!max_lane(sa, sep_a)) return false;
  if (sep_a.separation > radius) return true;

  // B's edges against A's vertices: d_j = m . v_j in lanes, then their minimum and maximum.
  LanePoints<1> bn;  // m -m -m -m
  bn.x[0] = _mm_setr_ps(b.normal.x, -b.normal.x, -b.normal.x, -b.normal.x);
  bn.y[0] = _mm_setr_ps(b.normal.y, -b.normal.y, -b.normal.y, -b.normal.y);
  rotate_lanes(bn, c, s);
  const __m128 mx = broadcast_lane(bn.x[0], 0);
  const __m128 my = broadcast_lane(bn.y[0], 0);
  __m128 low = _mm_add_ps(_mm_mul_ps(mx, av.x[0]), _mm_mul_ps(my, av.y[0]));
  __m128 high = low;
  for (int g = 1; g < kGroupsA; ++g) {
    const __m128 d = _mm_add_ps(_mm_mul_ps(mx, av.x[g]), _mm_mul_ps(my, av.y[g]));
    low = _mm_min_ps(low, d);
    high = _mm_max_ps(high, d);
  }
  low = min_in_every_lane(low);
  high = max_in_every_lane(high);
  // Lane 0: min_j (m . v_j) - m . b0; lanes 1-3: min_j (-m . v_j) - (-m . b1), written as
  // -max_j (m . v_j) - (-m . b1).
  const __m128 lowest = _mm_move_ss(_mm_xor_ps(high, _mm_set1_ps(-0.0f)), low);
  __m128 sb[1] = {_mm_sub_ps(lowest, _mm_add_ps(_mm_mul_ps(bn.x[0], bv.x[0]),
                                                _mm_mul_ps(bn.y[0], bv.y[0])))};
  EdgeSeparation sep_b;
  if (!max_lane(sb, sep_b)) return false;
  if (sep_b.separation > radius) return true;
  finish_from_lanes<kGroupsA, 1>(av, an, na, a.radius, sep_a, bv, bn, 2, b.radius, sep_b, xa,
                                 f.origin, m);
  return true;
}
#endif

}  // namespace

Manifold contact_polygons_general_path(const Polygon& a, const Transform& xa, const Polygon& b,
                                       const Transform& xb) noexcept {
  Manifold m;
  contact_polygons_general(a, xa, b, xb, m);
  return m;
}

// Small pairs (both polygons within two groups of kSatLanes vertices: boxes, triangles,
// hexagons, octagons, capsules and segments) skip the copies: each polygon's arrays are loaded
// straight into x and y registers, B is rotated into A's frame there, and both separating axis
// passes run in registers with a branch-free choice of the winning edge. Same operations in the
// same order as the general front end, so the manifold is bitwise the same (tests/narrow check
// it).
Manifold contact_polygons(const Polygon& a, const Transform& xa, const Polygon& b,
                          const Transform& xb) noexcept {
  Manifold m;  // the one object returned on every path: built in the caller's slot
#if COLLIDE_SMALL_POLYGON_SSE2
  const bool small = with_lane_groups(a.count, b.count, [&](auto groups_a, auto groups_b) {
    contact_polygons_lanes<groups_a(), groups_b()>(a, xa, b, xb, m);
  });
  if (small) return m;
#endif
  contact_polygons_general(a, xa, b, xb, m);
  return m;
}

Manifold contact_polygon_segment(const Polygon& a, const Transform& xa, const SegmentCore& b,
                                 const Transform& xb) noexcept {
  Manifold m;
#if COLLIDE_SMALL_POLYGON_SSE2
  if (a.count <= kSatLanes) {
    if (contact_polygon_segment_lanes<1>(a, xa, b, xb, m)) return m;
  } else if (a.count <= 2 * kSatLanes) {
    if (contact_polygon_segment_lanes<2>(a, xa, b, xb, m)) return m;
  }
#endif
  contact_polygons_general(a, xa, two_vertex_polygon(b.b0, b.b1, b.radius), xb, m);
  return m;
}

}  // namespace collide::detail
