#pragma once
/// @file
/// Convex hulls in 3D, built from point clouds by quickhull, with exact, clean topology for the
/// narrow phase: polygonal faces (near-coplanar triangles merged, no slivers), an edge list that
/// names the two faces of each edge (Gauss-map pruning in SAT), and vertex adjacency for
/// hill-climbing support queries on big hulls.

#include <collide/core/aabb.hpp>
#include <collide/core/lanes.hpp>
#include <collide/core/transform3.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

namespace collide {

/// Most vertices a ConvexHull holds, so that a vertex index fits `HullVertexIndex` (one byte).
inline constexpr int kMaxHullVertices = 256;

/// Index of a hull vertex in `ConvexHull::vertices`.
using HullVertexIndex = std::uint8_t;
static_assert(kMaxHullVertices - 1 <= std::numeric_limits<HullVertexIndex>::max());

/// A hull's `tolerance` is at least this fraction of the point set's extent (the largest side
/// of its bounding box). Points within the tolerance of the hull are not added as vertices, and
/// faces are merged into one polygon when that keeps them planar within half of it; see
/// `make_convex_hull`. The same fraction as kRelativeTolerance (core/tolerance.hpp).
inline constexpr float kHullRelativeTolerance = 1e-5f;

/// ... and at least this many float epsilons times (max |x| + max |y| + max |z|) of the points,
/// measured from the origin of their own space: the hull is stored in float in that space, and
/// a plane evaluated in float there is no more exact (Gregorius, "Implementing Quickhull",
/// GDC 2014, who uses 3). It dominates for small clouds far from their origin.
inline constexpr float kHullRoundingFactor = 3.0f;

/// A point set whose thickness (its extent across the plane of its three most spread points)
/// is at most this many tolerances is rejected as coplanar: a thinner hull would have side
/// faces no wider than the tolerance.
inline constexpr float kHullFlatFactor = 4.0f;

/// ConvexHull::support_index_from scans hulls of up to this many vertices instead of climbing
/// their adjacency: the SIMD scan has no data-dependent branch, while each climbing step
/// mispredicts about once. Measured on the Jolt-cloud hulls (17.7 vertices on average): GJK
/// boolean on overlapping pairs 750 -> 493 ns, distance 1.01 -> 0.91 us (bench_narrow3); a
/// coherent climb costs about 16 ns at any size, a scan 23 ns at 64 vertices and 44 ns at 128
/// (bench_convex_hull).
inline constexpr int kHullScanMaxVertices = 64;

/// A face of a hull: a convex polygon on the plane dot(normal, x) = offset, local space.
struct HullFace {
  Vec3 normal;          ///< unit outward normal, local space
  float offset;         ///< plane offset: dot(normal, v) <= offset for every hull vertex v
                        ///< (exactly), the face's own corners within `tolerance` of it
  std::uint16_t first;  ///< first slot of the face in `face_vertices` and `face_edges`
  std::uint16_t count;  ///< number of corners (>= 3)
};

/// An edge of a hull, stored once per undirected edge. v0 < v1. `face0` is the face whose
/// counter-clockwise boundary runs v0 -> v1 (seen from outside, face0 lies to the left of
/// v0 -> v1), `face1` the one whose boundary runs v1 -> v0. For a clearly bent edge
/// dot(cross(normal(face0), normal(face1)), v1 - v0) > 0; where the faces are within a few
/// tolerances of coplanar their float normals may not resolve the sign, so Gauss-map tests
/// should take the arc's axis from the edge direction, not from the normals' cross product.
struct HullEdge {
  HullVertexIndex v0;   ///< first vertex (the lower index)
  HullVertexIndex v1;   ///< second vertex
  std::uint16_t face0;  ///< face on the left of v0 -> v1 (its boundary runs v0 -> v1)
  std::uint16_t face1;  ///< face on the right of v0 -> v1 (its boundary runs v1 -> v0)
};

/// A convex polyhedron in local space, optionally rounded: the solid set of points within
/// `radius` of the convex hull of `vertices`. Build it with `make_convex_hull`, which
/// establishes the invariants below; treat the fields as read-only afterwards.
///
/// Invariants, with t = `tolerance` (checked on every test hull, exactly in double):
/// - `vertices` are input points (exact copies), pairwise farther apart than t, each a corner
///   of at least 3 faces; V - E + F = 2, every edge has two different faces.
/// - Every face is a polygon, counter-clockwise seen from outside, no thinner than t across
///   any of its sides, planar (its corners lie on or at most t below its plane) and convex (a
///   corner lies at most t inside the chord of its two neighbours).
/// - Every face plane supports the hull: every vertex lies on or behind it, and, unless
///   max_vertices stopped the build, so does every input point, within t.
/// - Every edge is convex: each face's corner centroid lies below the other face's plane.
/// - Neighbouring faces whose union would be planar within t / 2 are merged (unless that would
///   make a reflex corner), so there are no slivers and no needless splits of a flat side.
/// A face's normal is exact to about t / (the face's width): for very elongated hulls (the
/// tolerance is relative to the longest side) the normals of narrow faces are rough.
///
/// Face i has corners face_vertices[first, first + count) in counter-clockwise order, and
/// face_edges[first + k] is the edge from corner k to corner k + 1 (mod count). Vertex i's
/// neighbours (the other ends of its edges) are neighbours[neighbour_offsets[i],
/// neighbour_offsets[i + 1]).
struct alignas(64) ConvexHull {
  // What a support query reads (ConvexProxy3, GJK) comes first, on one cache line: a query on
  // many hulls (a scene's worth) waits on each hull's lines, and these were spread over four.
  std::vector<Vec3> vertices;                   ///< local space, in the order of the input points
  /// `vertices` again, four at a time for SIMD support queries: block b holds the x of vertices
  /// 4b..4b+3, then their y, then their z (12 floats); the last block is padded with vertex 0.
  std::vector<float> vertex_blocks;
  float radius = 0.0f;                          ///< rounding radius, >= 0
  std::vector<HullFace> faces;                  ///< polygonal faces
  std::vector<HullVertexIndex> face_vertices;   ///< corners of all faces, face by face
  std::vector<std::uint16_t> face_edges;        ///< edge index of each face side, as corners
  std::vector<HullEdge> edges;                  ///< each undirected edge once
  std::vector<std::uint16_t> neighbour_offsets; ///< vertex adjacency offsets, size V + 1
  std::vector<HullVertexIndex> neighbours;      ///< vertex adjacency lists, size 2E
  /// `faces`' planes again, four at a time for SIMD separating-axis tests: block b holds the
  /// normal x of faces 4b..4b+3, then their normal y, normal z and offset (16 floats); the last
  /// block is padded with face 0.
  std::vector<float> face_blocks;
  float tolerance = 0.0f;       ///< the build's tolerance t, local units (see above)
  float volume = 0.0f;          ///< volume of the core (without the radius)
  Vec3 centroid{0.0f};          ///< volume centroid of the core, local space
  Aabb3 bounds;                 ///< local bounds of the core (without the radius)

  /// Index of the vertex farthest along `direction` (any length, local space); on ties the
  /// lowest index. A NaN direction gives 0. Brute force over all vertices, four at a time
  /// (SSE2 over `vertex_blocks`; the same float dot products and answer as the plain loop).
  /// Inline: GJK and EPA call it in their loops, and a 12-byte direction passed by value to
  /// an out-of-line call is assembled through the stack (a failed store forwarding per call).
  [[nodiscard]] int support_index(Vec3 direction) const noexcept;

  /// A vertex farthest along `direction`, allowed to start from vertex `start` (e.g. the
  /// previous answer). Hulls of up to kHullScanMaxVertices vertices are scanned
  /// (`support_index`: faster than climbing at that size); bigger ones are climbed over the
  /// vertex adjacency from `start` (O(1) steps under coherent motion), whose support value
  /// dot(vertex, direction) equals the maximum within the hull's `tolerance` times |direction|
  /// (faces are planar only within it) and on exact ties may differ from `support_index`.
  /// `start` must be a vertex index.
  [[nodiscard]] int support_index_from(Vec3 direction, int start) const noexcept {
    if (vertex_count() <= kHullScanMaxVertices) return support_index(direction);
    return climb_support(direction, start);
  }

  /// The hill climb of support_index_from, at any size.
  [[nodiscard]] int climb_support(Vec3 direction, int start) const noexcept;

  /// Number of vertices.
  [[nodiscard]] int vertex_count() const noexcept { return static_cast<int>(vertices.size()); }

  /// Vertex i as vertex_blocks holds it (the same values as vertices[i]): a support query that
  /// has just scanned the blocks finds its answer's coordinates there, already in the cache,
  /// where vertices[i] is a second array to load.
  [[nodiscard]] Vec3 block_vertex(int i) const noexcept {
    const float* block = vertex_blocks.data() + 12 * (i >> 2) + (i & 3);
    return {block[0], block[4], block[8]};
  }
};

#if defined(__SSE2__) || defined(_M_X64)
inline int ConvexHull::support_index(Vec3 direction) const noexcept {
  // Plain meaning: the first i maximising dot(vertices[i], direction), scanned in order with
  // a strict '>'. Each SIMD lane does that over its quarter of the vertices, and the lanes are
  // merged without branches (simd::ArgMax4). The padding lanes repeat vertex 0, which comes
  // first. No dot product above -infinity (all NaN): vertex 0.
  static_assert(kMaxHullVertices + 4 < simd::ArgMax4::kNone);
  const __m128 dx = _mm_set1_ps(direction.x);
  const __m128 dy = _mm_set1_ps(direction.y);
  const __m128 dz = _mm_set1_ps(direction.z);
  simd::ArgMax4 scan;
  const float* p = vertex_blocks.data();
  const float* end = p + vertex_blocks.size();
  for (; p != end; p += 12) {
    scan.add(_mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_loadu_ps(p), dx), _mm_mul_ps(_mm_loadu_ps(p + 4), dy)),
                        _mm_mul_ps(_mm_loadu_ps(p + 8), dz)));
  }
  const int result = scan.result().index;
  return result == simd::ArgMax4::kNone ? 0 : result;
}
#else
inline int ConvexHull::support_index(Vec3 direction) const noexcept {
  int best = 0;
  float best_dot = dot(vertices[0], direction);
  const int n = vertex_count();
  for (int i = 1; i < n; ++i) {
    const float d = dot(vertices[i], direction);
    if (d > best_dot) {
      best_dot = d;
      best = i;
    }
  }
  return best;
}
#endif

/// Options of `make_convex_hull`.
struct HullOptions {
  float radius = 0.0f;                    ///< rounding radius, >= 0, local units
  int max_vertices = kMaxHullVertices;    ///< cap on hull vertices, in [4, kMaxHullVertices]
};

/// The convex hull of `points` (local space, any order) with rounding radius `options.radius`.
///
/// Quickhull (Barber, Dobkin & Huhdanpaa, "The Quickhull Algorithm for Convex Hulls", ACM TOMS
/// 1996): the farthest outside point is added first, the faces it sees are replaced by a cone
/// from their horizon. After each point, faces are merged as in Gregorius ("Implementing
/// Quickhull", GDC 2014), but with a planarity test instead of his centroid test (which let
/// corners stray several tolerances off the merged plane on real data): two neighbours merge
/// when their union is planar within half the tolerance and stays convex, and always when
/// their edge is concave; a face thinner than the tolerance merges into its most coplanar
/// neighbour. A last pass re-adds any point that the merges left more than the tolerance
/// outside. The tolerance is max(kHullRelativeTolerance x extent, kHullRoundingFactor x
/// FLT_EPSILON x (max |x| + max |y| + max |z|)). The build runs in double on the points
/// shifted to the centre of their bounding box (exact differences however far the cloud is
/// from its origin); it allocates and takes O(n h) time for n points and h hull faces.
///
/// `options.max_vertices` caps the vertex count. Since the farthest point goes first, stopping
/// at the cap gives a good approximation: the result is then the convex hull of its own
/// vertices (all invariants hold for it), while input points farther out than the tolerance
/// remain outside it (ever closer as the cap grows). Without the cap, points within the
/// tolerance of the hull may lie outside it by up to the tolerance (they are dropped as on the
/// hull, and so is a vertex whose faces merged flat).
///
/// Throws InvalidInput naming the field if: a coordinate is not finite (names the point
/// index); there are fewer than 4 points; the points all coincide, are collinear or are
/// coplanar within the tolerance (zero volume, says which; coplanar: thinner than
/// kHullFlatFactor tolerances), or are a needle or sliver so few tolerances across that merging
/// faces within the tolerance would fold the hull flat ("too thin for the tolerance"); the
/// radius is negative or not finite; max_vertices is outside [4, kMaxHullVertices].
[[nodiscard]] ConvexHull make_convex_hull(std::span<const Vec3> points,
                                          const HullOptions& options = {});

/// Bounding box of the hull (including its radius) placed by `xf`, world space: exact (every
/// vertex is transformed), O(V).
[[nodiscard]] Aabb3 compute_aabb(const ConvexHull& hull, const Transform3& xf) noexcept;

}  // namespace collide
