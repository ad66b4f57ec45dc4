#pragma once
/// @file
/// `distance`: how far apart two convex shapes are, and their closest points, by GJK
/// (Gilbert, Johnson & Keerthi 1988; Ericson, Real-Time Collision Detection, 9.5; the simplex
/// solver by signed barycentric coordinates of Catto, "Computing Distance", GDC 2010).
///
/// GJK runs on the shapes' cores (see ConvexProxy) and applies the radii after convergence,
/// which is exact for circles, capsules and rounded polygons. A `SimplexCache` carried from one
/// frame to the next warm-starts GJK with last frame's closest features.

#include <collide/narrow/support.hpp>

#include <array>
#include <cstdint>

namespace collide {

/// GJK warm-start state: the vertex pairs of the last simplex. Zero-initialise for a cold
/// start; pass the same cache for the same pair of shapes every frame.
struct SimplexCache {
  int count = 0;                          ///< simplex vertices stored, 0..3
  std::array<std::uint8_t, 3> index_a{};  ///< core point indices on A
  std::array<std::uint8_t, 3> index_b{};  ///< core point indices on B
};

/// How GJK ended.
enum class GjkStatus : std::uint8_t {
  /// Cores apart; distance, points and normal are exact. The shapes themselves may still
  /// overlap through their radii: then distance is 0 (see DistanceResult::point_a).
  separated,
  overlapped,  ///< cores overlap (the origin is inside the Minkowski difference)
  max_iterations,  ///< hit kGjkMaxIterations; the result is the best found (never seen in tests)
};

/// Result of a distance query. All points world space.
struct DistanceResult {
  /// Distance between the shapes (radii applied), world units; 0 when they overlap.
  float distance = 0.0f;
  /// Closest point on A's surface: A's core witness moved by A's radius along `normal`.
  /// When the radii overlap (cores apart, distance 0) it is still that point, A's deepest point
  /// towards B, and dot(point_b - point_a, normal) = -(penetration depth) <= 0. When the cores
  /// overlap: a point inside both cores (equal to point_b).
  Vec2 point_a{0.0f, 0.0f};
  /// Closest point on B's surface: B's core witness moved by B's radius against `normal`; as
  /// point_a for the overlapping cases.
  Vec2 point_b{0.0f, 0.0f};
  /// Unit direction from A to B along the closest points; zero when the cores overlap.
  Vec2 normal{0.0f, 0.0f};
  int iterations = 0;  ///< GJK iterations used: support points evaluated (a cold start
                       ///< spends one on its seed)
  GjkStatus status = GjkStatus::separated;
};

/// GJK distance between two convex proxies placed by `xa` and `xb`. `cache` (optional) is read
/// to warm-start (ignored if its indices do not fit these proxies or its simplex is now
/// degenerate) and written with the final simplex. Proxies must hold 1..kMaxPolygonVertices
/// finite points and transforms must be finite rigid (both checked by COLLIDE_ASSERT in debug
/// builds: shapes and transforms are trusted here, see core/error.hpp). Runs in A's local frame (B is moved there once), so pairs far from the origin
/// are as accurate as pairs near it; cores closer than kRelativeTolerance of their coordinates'
/// size count as overlapping. Cold starts are seeded with the support points along the line
/// between the two shapes' local origins. Allocates nothing.
[[nodiscard]] DistanceResult gjk_distance(const ConvexProxy& a, const Transform& xa,
                                          const ConvexProxy& b, const Transform& xb,
                                          SimplexCache* cache = nullptr) noexcept;

/// Distance and closest points between shape A placed by `xa` and shape B placed by `xb`, any
/// pair of 2D shape types. Swapping A and B swaps the points and flips the normal.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] DistanceResult distance(const A& a, const Transform& xa, const B& b,
                                      const Transform& xb,
                                      SimplexCache* cache = nullptr) noexcept {
  return gjk_distance(ConvexProxy(a), xa, ConvexProxy(b), xb, cache);
}

/// `distance` for shapes of types known only at run time.
[[nodiscard]] DistanceResult distance(const Shape2D& a, const Transform& xa, const Shape2D& b,
                                      const Transform& xb,
                                      SimplexCache* cache = nullptr) noexcept;

}  // namespace collide
