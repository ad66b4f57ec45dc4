#pragma once
/// @file
/// `distance`: how far apart two convex shapes are, and their closest points, by GJK
/// (Gilbert, Johnson & Keerthi 1988; Ericson, Real-Time Collision Detection, 9.5; the simplex
/// solver by signed barycentric coordinates of Catto, "Computing Distance", GDC 2010).
///
/// GJK (narrow/gjk.hpp) runs on the shapes' cores (see ConvexProxy) and applies the radii after convergence,
/// which is exact for circles, capsules and rounded polygons. A `SimplexCache` carried from one
/// frame to the next warm-starts GJK with last frame's closest features.

#include <collide/core/status.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <array>
#include <cstdint>
#include <limits>

namespace collide {

/// GJK warm-start state: the vertex pairs of the last simplex. Zero-initialise for a cold
/// start; pass the same cache for the same pair of shapes every frame.
template <int D>
struct SimplexCacheN {
  int count = 0;                              ///< simplex vertices stored, 0..D + 1
  std::array<std::uint8_t, D + 1> index_a{};  ///< core point indices on A
  std::array<std::uint8_t, D + 1> index_b{};  ///< core point indices on B
};

using SimplexCache = SimplexCacheN<2>;   ///< 2D warm-start state
using SimplexCache3 = SimplexCacheN<3>;  ///< 3D warm-start state

/// Result of a distance query in D dimensions. All points world space.
template <int D>
struct DistanceResultN {
  /// Distance between the shapes (radii applied), world units; 0 when they overlap.
  float distance = 0.0f;
  /// Closest point on A's surface: A's core witness moved by A's radius along `normal`.
  /// When the radii overlap (cores apart, distance 0) it is still that point, A's deepest point
  /// towards B, and dot(point_b - point_a, normal) = -(penetration depth) <= 0. When the cores
  /// overlap: a point inside both cores (equal to point_b).
  VecN<D> point_a{0.0f};
  /// Closest point on B's surface: B's core witness moved by B's radius against `normal`; as
  /// point_a for the overlapping cases.
  VecN<D> point_b{0.0f};
  /// Unit direction from A to B along the closest points; zero when the cores overlap.
  VecN<D> normal{0.0f};
  int iterations = 0;  ///< GJK iterations used: support points evaluated (a cold start
                       ///< spends one on its seed)
  /// separated: the cores are apart; distance, points and normal are exact (the shapes may
  /// still overlap through their radii: then distance is 0). overlapped: the cores overlap
  /// (the origin is inside A - B). max_iterations: kGjkMaxIterations reached; the result is
  /// the best found.
  QueryStatus status = QueryStatus::separated;
};

using DistanceResult = DistanceResultN<2>;   ///< 2D distance result
using DistanceResult3 = DistanceResultN<3>;  ///< 3D distance result

/// GJK distance between two convex proxies placed by `xa` and `xb`, in 2D or 3D. `cache`
/// (optional) is read to warm-start (ignored if its indices do not fit these proxies or its
/// simplex is now degenerate) and written with the final simplex. Proxies must hold at least
/// one finite point (at most kMaxPolygonVertices in 2D, kMaxProxyPoints3 in 3D) and transforms
/// must be finite rigid (both checked by COLLIDE_ASSERT in debug builds: shapes and transforms
/// are trusted here, see core/error.hpp). Runs in A's local frame (B is moved there once), so
/// pairs far from the origin are as accurate as pairs near it; cores closer than
/// kRelativeTolerance of their coordinates' size count as overlapping. Cold starts are seeded
/// with the support points along the line between the two shapes' local origins. Allocates
/// nothing.
template <int D>
[[nodiscard]] DistanceResultN<D> gjk_distance(const ConvexProxyN<D>& a, const TransformN<D>& xa,
                                              const ConvexProxyN<D>& b, const TransformN<D>& xb,
                                              SimplexCacheN<D>* cache = nullptr) noexcept;

extern template DistanceResultN<2> gjk_distance<2>(const ConvexProxyN<2>&, const Transform&,
                                                   const ConvexProxyN<2>&, const Transform&,
                                                   SimplexCacheN<2>*) noexcept;
extern template DistanceResultN<3> gjk_distance<3>(const ConvexProxyN<3>&, const Transform3&,
                                                   const ConvexProxyN<3>&, const Transform3&,
                                                   SimplexCacheN<3>*) noexcept;

/// Distance and closest points between shape A placed by `xa` and shape B placed by `xb`, any
/// pair of 2D shape types. Swapping A and B swaps the points and flips the normal.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] DistanceResult distance(const A& a, const Transform& xa, const B& b,
                                      const Transform& xb,
                                      SimplexCache* cache = nullptr) noexcept {
  return gjk_distance<2>(ConvexProxy(a), xa, ConvexProxy(b), xb, cache);
}

/// `distance` for two polygons: the same answer as GJK (within rounding), found faster. The
/// closest pair of two convex polygons is an edge of one and a corner of the other, or a corner
/// of each, and a pair is proven closest by a few dot products (the line between its points
/// leaves both cores on their own sides). A closest-feature walk (Lin & Canny 1991, in 2D)
/// moves from last frame's pair (`cache`), or on a cold start from GJK's first support pair, to
/// the neighbouring feature each failed condition names, usually in 0-2 steps. When it meets a
/// corner behind an edge (the cores may overlap), polygons of up to 8 vertices take the
/// separating axis test in SSE registers (Ericson, Real-Time Collision Detection, 5.2.1):
/// overlap, or a new walk from the best axis's features. GJK runs only for overlapping or
/// touching cores and what the walks leave, started from the axis's features when there are
/// some. `iterations` is 0 when no GJK ran. `cache` is written with the closest features.
[[nodiscard]] DistanceResult distance(const Polygon& a, const Transform& xa, const Polygon& b,
                                      const Transform& xb, SimplexCache* cache = nullptr) noexcept;

/// `distance` for a polygon and a circle: the Voronoi region of the circle's centre (the edge
/// of greatest separation, four edges at a time in registers up to 8 vertices, or one of its
/// ends; Ericson, Real-Time Collision Detection, 5.2.7), exact, no GJK (`iterations` 0) unless
/// the centre is on or inside the polygon's core. `cache` is written with the closest features.
[[nodiscard]] DistanceResult distance(const Polygon& a, const Transform& xa, const Circle& b,
                                      const Transform& xb, SimplexCache* cache = nullptr) noexcept;

/// `distance` for a circle and a polygon: the polygon-circle answer seen from the circle.
[[nodiscard]] DistanceResult distance(const Circle& a, const Transform& xa, const Polygon& b,
                                      const Transform& xb, SimplexCache* cache = nullptr) noexcept;

/// `distance` for shapes of types known only at run time.
[[nodiscard]] DistanceResult distance(const Shape2D& a, const Transform& xa, const Shape2D& b,
                                      const Transform& xb,
                                      SimplexCache* cache = nullptr) noexcept;

/// Distance and closest points between 3D shape A placed by `xa` and shape B placed by `xb`,
/// any pair of convex 3D shape types, by GJK on their cores (signed-volume simplex solver).
/// Swapping A and B swaps the points and flips the normal.
template <Shape3DType A, Shape3DType B>
[[nodiscard]] DistanceResult3 distance(const A& a, const Transform3& xa, const B& b,
                                       const Transform3& xb,
                                       SimplexCache3* cache = nullptr) noexcept {
  return gjk_distance<3>(ConvexProxy3(a), xa, ConvexProxy3(b), xb, cache);
}

/// `distance` for 3D shapes of types known only at run time.
[[nodiscard]] DistanceResult3 distance(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                                       const Transform3& xb,
                                       SimplexCache3* cache = nullptr) noexcept;

/// Distance and closest points between convex shape A placed by `xa` and the nearest triangle
/// of the mesh placed by `xm`, world space, normal from A to the mesh; `triangle` (optional)
/// receives that triangle's index. Only triangles within `max_distance` (world units) count: a
/// game usually asks "is anything within d", and a bound keeps the search local. When none is
/// within it the result has distance +infinity, zero points and normal, status separated, and
/// `triangle` gets UINT32_MAX. When A overlaps a triangle: distance 0 (status overlapped when
/// the cores overlap), found early.
///
/// Exact for any bound, by branch and bound: the BVH's nearest triangle to the centre of A's box
/// (in the mesh's stored frame) gives a first distance by GJK; A's box grown by the best
/// distance so far (or the bound, if smaller) then queries the BVH, and each candidate whose
/// box is farther from A's box than the best distance is skipped without GJK. Allocates
/// nothing (src/narrow/mesh_query.cpp).
template <ConvexShape3DType A>
[[nodiscard]] DistanceResult3 distance(
    const A& a, const Transform3& xa, const TriangleMesh& mesh, const Transform3& xm,
    float max_distance = std::numeric_limits<float>::infinity(),
    std::uint32_t* triangle = nullptr) noexcept;

/// The same against a height field placed by `xf` (the first distance from the cell under A's
/// centre, clamped to the grid; holes have no triangles).
template <ConvexShape3DType A>
[[nodiscard]] DistanceResult3 distance(
    const A& a, const Transform3& xa, const HeightField& field, const Transform3& xf,
    float max_distance = std::numeric_limits<float>::infinity(),
    std::uint32_t* triangle = nullptr) noexcept;

/// The same result seen from the other side: points swapped, normal flipped.
template <int D>
[[nodiscard]] constexpr DistanceResultN<D> swapped(DistanceResultN<D> d) noexcept {
  const VecN<D> p = d.point_a;
  d.point_a = d.point_b;
  d.point_b = p;
  d.normal = -d.normal;
  return d;
}

/// `distance` with the mesh first: points swapped and normal flipped (from the mesh to B).
template <ConvexShape3DType B>
[[nodiscard]] DistanceResult3 distance(
    const TriangleMesh& mesh, const Transform3& xm, const B& b, const Transform3& xb,
    float max_distance = std::numeric_limits<float>::infinity(),
    std::uint32_t* triangle = nullptr) noexcept {
  return swapped(distance(b, xb, mesh, xm, max_distance, triangle));
}
/// `distance` with the height field first: points swapped and normal flipped.
template <ConvexShape3DType B>
[[nodiscard]] DistanceResult3 distance(
    const HeightField& field, const Transform3& xf, const B& b, const Transform3& xb,
    float max_distance = std::numeric_limits<float>::infinity(),
    std::uint32_t* triangle = nullptr) noexcept {
  return swapped(distance(b, xb, field, xf, max_distance, triangle));
}

}  // namespace collide
