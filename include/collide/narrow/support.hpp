#pragma once
/// @file
/// Support functions: the only thing GJK, EPA-free distance, ray casts against the Minkowski
/// difference and shape casts need to know about a convex shape.
///
/// A `ConvexProxy` views a shape as a core point set (1 point for a circle, 2 for a capsule or
/// segment, n for a polygon) plus a radius: the shape is the core's convex hull grown by the
/// radius. GJK works on cores and applies radii after convergence, which is exact for rounded
/// shapes (van den Bergen, Collision Detection in Interactive 3D Environments, 2003, 4.3.6).

#include <collide/core/lanes.hpp>
#include <collide/core/math.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/shape/triangle.hpp>

#include <array>
#include <limits>
#include <span>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

/// The scan of support_point_index over points [first, size) of `points`, against a best so far
/// (index `best`, whose dot product with `direction` is `best_dot`): the index of the farthest,
/// ties to the earlier. Selects, not a branch per point: which point wins is the data's choice,
/// and on pairs in no learnable order the branch missed about twice a distance query
/// (cachegrind, 4-gons); the index by a mask, since GCC turned a ternary back into a branch.
template <int D>
[[nodiscard]] inline int continue_support_scan(std::span<const VecN<D>> points, int first, int best, float best_dot,
                                               VecN<D> direction) noexcept {
  for (int i = first; i < static_cast<int>(points.size()); ++i) {
    const float d = dot(points[static_cast<std::size_t>(i)], direction);
    const bool further = d > best_dot;
    best ^= (best ^ i) & -static_cast<int>(further);
    best_dot = further ? d : best_dot;
  }
  return best;
}

/// Index of the point of `points` (n >= 1) farthest along `direction`, ties to the lowest index:
/// the support point of a point set by a full scan (Ericson, Real-Time Collision Detection,
/// 3.8), continue_support_scan from point 0.
template <int D>
[[nodiscard]] inline int support_point_index(std::span<const VecN<D>> points, VecN<D> direction) noexcept {
  return continue_support_scan<D>(points, 1, 0, dot(points[0], direction), direction);
}

/// A view of a convex shape's core points and radius, local space, in D dimensions: the
/// support map (gjk.hpp, `SupportMap`) of every collide shape.
template <int D>
class ConvexProxyN;

/// The 2D support map. Polygon proxies point into the polygon (keep it alive); circle, capsule
/// and segment proxies copy their 1-2 points.
template <>
class ConvexProxyN<2> {
 public:
  /// Polygon: its vertices (not copied) and its rounding radius.
  explicit ConvexProxyN(const Polygon& polygon) noexcept
      : points_(polygon.vertices.data()),
        count_(polygon.count),
        radius_(polygon.radius),
        convex_outline_(true) {}
  /// Circle: its centre and radius.
  explicit ConvexProxyN(const Circle& circle) noexcept
      : buffer_{circle.center, circle.center}, count_(1), radius_(circle.radius) {}
  /// Capsule: its two segment ends and radius.
  explicit ConvexProxyN(const Capsule& capsule) noexcept
      : buffer_{capsule.a, capsule.b}, count_(2), radius_(capsule.radius) {}
  /// Segment: its two ends, radius 0.
  explicit ConvexProxyN(const Segment& segment) noexcept
      : buffer_{segment.a, segment.b}, count_(2), radius_(0.0f) {}
  /// Any 2D shape.
  explicit ConvexProxyN(const Shape2D& shape) noexcept;
  /// A raw point set (1..kMaxPolygonVertices points, not copied beyond 2) and radius.
  ConvexProxyN(const Vec2* points, int count, float radius) noexcept;

  [[nodiscard]] const Vec2* points() const noexcept {
    return points_ != nullptr ? points_ : buffer_.data();
  }
  [[nodiscard]] Vec2 point(int i) const noexcept { return points()[i]; }
  [[nodiscard]] int count() const noexcept { return count_; }
  [[nodiscard]] float radius() const noexcept { return radius_; }

  /// Index of the core point farthest along `direction` (local space); ties go to the lowest
  /// index. Full scan (SIMD from kSimdSupportMinPoints points), correct for any point set and
  /// the right choice without a good starting guess; with one, on a polygon, use
  /// support_index_from.
  [[nodiscard]] int support_index(Vec2 direction) const noexcept {
    const Vec2* p = points();
#if defined(__SSE2__)
    if (count_ >= kSimdSupportMinPoints) return support_index_simd(p, count_, direction);
#endif
    return support_point_index<2>({p, static_cast<std::size_t>(count_)}, direction);
  }

  /// A core point farthest along `direction`, found by walking from point `start` to a
  /// neighbour while that improves: on a strictly convex outline (a polygon) the projection is
  /// unimodal around the outline, so the walk ends at the maximum and costs only the points it
  /// passes (about 3 when `start` is last iteration's answer). Ties: the first one reached.
  /// Point sets that are not a polygon's outline take the full scan.
  [[nodiscard]] int support_index_from(Vec2 direction, int start) const noexcept {
    if (!convex_outline_) return support_index(direction);
    const Vec2* p = points();
    const int n = count_;
    int i = start;
    float best = dot(p[i], direction);
    int next = i + 1 == n ? 0 : i + 1;
    float next_dot = dot(p[next], direction);
    if (next_dot > best) {  // uphill forwards
      do {
        i = next;
        best = next_dot;
        next = i + 1 == n ? 0 : i + 1;
        next_dot = dot(p[next], direction);
      } while (next_dot > best);
      return i;
    }
    int prev = i == 0 ? n - 1 : i - 1;
    float prev_dot = dot(p[prev], direction);
    while (prev_dot > best) {  // uphill backwards (or already at the top)
      i = prev;
      best = prev_dot;
      prev = i == 0 ? n - 1 : i - 1;
      prev_dot = dot(p[prev], direction);
    }
    return i;
  }

 private:
#if defined(__SSE2__)
  /// Point sets at least this big take the SIMD scan (measured: bench_narrow_distance).
  static constexpr int kSimdSupportMinPoints = 8;

  /// The scalar scan of support_index, four points at a time (SSE2): lane j keeps the best of
  /// points j, j+4, j+8... (first index on ties); the lanes are then merged without branches:
  /// the maximum, then the lowest index among the lanes that hold it.
  [[nodiscard]] static int support_index_simd(const Vec2* p, int n, Vec2 direction) noexcept {
    const __m128 dx = _mm_set1_ps(direction.x);
    const __m128 dy = _mm_set1_ps(direction.y);
    simd::ArgMax4 scan;
    int i = 0;
    for (; i + 4 <= n; i += 4) {
      const __m128 p01 = _mm_loadu_ps(&p[i].x);      // x0 y0 x1 y1
      const __m128 p23 = _mm_loadu_ps(&p[i + 2].x);  // x2 y2 x3 y3
      const __m128 xs = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 ys = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(3, 1, 3, 1));
      scan.add(_mm_add_ps(_mm_mul_ps(xs, dx), _mm_mul_ps(ys, dy)));
    }
    const simd::ArgMax4::Result merged = scan.result();
    // The last n % 4 points (their number varies from shape to shape: selects, as above).
    const int result = continue_support_scan<2>({p, static_cast<std::size_t>(n)}, i, merged.index, merged.max, direction);
    // All dots NaN: no lane improved on -infinity; the scalar scan answers 0 then too.
    return result == simd::ArgMax4::kNone ? 0 : result;
  }
#endif

  std::array<Vec2, 2> buffer_{};
  const Vec2* points_ = nullptr;
  int count_ = 0;
  float radius_ = 0.0f;
  bool convex_outline_ = false;  ///< points are a strictly convex counter-clockwise outline
};

using ConvexProxy = ConvexProxyN<2>;  ///< the 2D support map

/// Most points a raw 3D point-set proxy may hold (support indices fit a byte, as hulls' do).
inline constexpr int kMaxProxyPoints3 = 256;

/// The 3D support map. Sphere, capsule, segment and triangle proxies copy their 1-3 points; a box
/// proxy keeps its half extents and answers by the signs of the direction (its 8 corners are
/// numbered as box.hpp's vertices); raw point sets are not copied (keep them alive).
template <>
class ConvexProxyN<3> {
 public:
  /// Sphere: its centre and radius.
  explicit ConvexProxyN(const Sphere& sphere) noexcept
      : buffer_{sphere.center, sphere.center}, count_(1), radius_(sphere.radius) {}
  /// Capsule: its two segment ends and radius.
  explicit ConvexProxyN(const Capsule3& capsule) noexcept
      : buffer_{capsule.a, capsule.b}, count_(2), radius_(capsule.radius) {}
  /// Segment: its two ends, radius 0.
  explicit ConvexProxyN(const Segment3& segment) noexcept
      : buffer_{segment.a, segment.b}, count_(2), radius_(0.0f) {}
  /// Triangle: its 3 corners (copied; core point k is corner k, as its vertex features), radius
  /// 0. Flat: GJK, EPA and the casts treat it as the convex hull of the 3 points.
  explicit ConvexProxyN(const Triangle& triangle) noexcept
      : buffer_{triangle.vertices[0], triangle.vertices[1], triangle.vertices[2]},
        count_(3),
        radius_(0.0f),
        kind_(Kind::triangle) {}
  /// Box: 8 corners by the feature numbering of box.hpp, and its rounding radius.
  explicit ConvexProxyN(const Box& box) noexcept
      : buffer_{box.half, box.half}, count_(8), radius_(box.radius), kind_(Kind::box) {}
  /// Convex hull: its vertices (not copied: keep the hull alive), its SIMD scan and its
  /// hill-climbing walk, and its rounding radius.
  explicit ConvexProxyN(const ConvexHull& hull) noexcept
      : points_(hull.vertices.data()),
        count_(hull.vertex_count()),
        radius_(hull.radius),
        kind_(Kind::hull),
        hull_(&hull) {}
  /// A raw point set (1..kMaxProxyPoints3 points, not copied) and radius.
  ConvexProxyN(const Vec3* points, int count, float radius) noexcept
      : points_(points), count_(count), radius_(radius), kind_(Kind::points) {}
  /// Any convex 3D shape.
  explicit ConvexProxyN(const Shape3D& shape) noexcept
      : ConvexProxyN(std::visit([](const auto& s) { return ConvexProxyN(s); }, shape)) {}

  [[nodiscard]] int count() const noexcept { return count_; }
  [[nodiscard]] float radius() const noexcept { return radius_; }
  /// The same core with another radius (a margin added: the shape grown by it, as the time of
  /// impact's target separation needs). Raw point sets still point at the caller's points.
  [[nodiscard]] ConvexProxyN with_radius(float radius) const noexcept {
    ConvexProxyN p = *this;
    p.radius_ = radius;
    return p;
  }

  /// Core point i, local space.
  [[nodiscard]] Vec3 point(int i) const noexcept {
    switch (kind_) {
      case Kind::box: {
        const Vec3 h = buffer_[0];
        return {(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z};
      }
      case Kind::points:
      case Kind::hull: return hull_->block_vertex(i);
      case Kind::inline_points:
      case Kind::triangle: break;
    }
    return buffer_[i];
  }

  /// Index of a core point farthest along `direction` (local space). Ties go to the lowest
  /// index (a box: the - side on an axis where the direction is 0).
  [[nodiscard]] int support_index(Vec3 direction) const noexcept {
    switch (kind_) {
      case Kind::box:
        return int(direction.x > 0.0f) | (int(direction.y > 0.0f) << 1) |
               (int(direction.z > 0.0f) << 2);
      case Kind::points: return support_point_index<3>({points_, static_cast<std::size_t>(count_)}, direction);
      case Kind::hull: return hull_->support_index(direction);
      case Kind::triangle: return support_point_index<3>(buffer_, direction);
      case Kind::inline_points: break;
    }
    return count_ == 2 && dot(buffer_[1], direction) > dot(buffer_[0], direction) ? 1 : 0;
  }
  /// The same, walked from a previous answer `start` where the shape can (a hull's hill
  /// climbing over its vertex adjacency: a few steps under coherent motion; its answer is
  /// farthest within the hull's tolerance); other shapes answer directly.
  [[nodiscard]] int support_index_from(Vec3 direction, int start) const noexcept {
    if (kind_ == Kind::hull) return hull_->support_index_from(direction, start);
    return support_index(direction);
  }

 private:
  enum class Kind : unsigned char { inline_points, box, points, hull, triangle };

  std::array<Vec3, 3> buffer_{};  ///< inline points; a box's half extents in [0]
  const Vec3* points_ = nullptr;
  int count_ = 0;
  float radius_ = 0.0f;
  Kind kind_ = Kind::inline_points;
  const ConvexHull* hull_ = nullptr;
};

using ConvexProxy3 = ConvexProxyN<3>;  ///< the 3D support map

/// A ConvexHull's support map alone (SupportMap, gjk.hpp): ConvexProxy3's answers for a hull,
/// without its dispatch on the shape's kind at every point and support query, for the queries
/// that know both shapes are hulls. Keep the hull alive.
class HullSupportMap {
 public:
  explicit HullSupportMap(const ConvexHull& hull) noexcept : hull_(&hull) {}
  [[nodiscard]] Vec3 point(int i) const noexcept { return hull_->block_vertex(i); }
  [[nodiscard]] int count() const noexcept { return hull_->vertex_count(); }
  [[nodiscard]] float radius() const noexcept { return hull_->radius; }
  [[nodiscard]] int support_index(Vec3 direction) const noexcept { return hull_->support_index(direction); }
  [[nodiscard]] int support_index_from(Vec3 direction, int start) const noexcept {
    return hull_->support_index_from(direction, start);
  }

 private:
  const ConvexHull* hull_;
};

}  // namespace collide
