#pragma once
/// @file
/// Support functions: the only thing GJK, EPA-free distance, ray casts against the Minkowski
/// difference and shape casts need to know about a convex shape.
///
/// A `ConvexProxy` views a shape as a core point set (1 point for a circle, 2 for a capsule or
/// segment, n for a polygon) plus a radius: the shape is the core's convex hull grown by the
/// radius. GJK works on cores and applies radii after convergence, which is exact for rounded
/// shapes (van den Bergen, Collision Detection in Interactive 3D Environments, 2003, 4.3.6).

#include <collide/core/math.hpp>
#include <collide/shape/shape2d.hpp>

#include <array>

namespace collide {

/// A view of a convex shape's core points and radius, local space. Polygon proxies point into
/// the polygon (keep it alive); circle, capsule and segment proxies copy their 1-2 points.
class ConvexProxy {
 public:
  /// Polygon: its vertices (not copied) and its rounding radius.
  explicit ConvexProxy(const Polygon& polygon) noexcept
      : points_(polygon.vertices.data()), count_(polygon.count), radius_(polygon.radius) {}
  /// Circle: its centre and radius.
  explicit ConvexProxy(const Circle& circle) noexcept
      : buffer_{circle.center, circle.center}, count_(1), radius_(circle.radius) {}
  /// Capsule: its two segment ends and radius.
  explicit ConvexProxy(const Capsule& capsule) noexcept
      : buffer_{capsule.a, capsule.b}, count_(2), radius_(capsule.radius) {}
  /// Segment: its two ends, radius 0.
  explicit ConvexProxy(const Segment& segment) noexcept
      : buffer_{segment.a, segment.b}, count_(2), radius_(0.0f) {}
  /// Any 2D shape.
  explicit ConvexProxy(const Shape2D& shape) noexcept;
  /// A raw point set (1..kMaxPolygonVertices points, not copied beyond 2) and radius.
  ConvexProxy(const Vec2* points, int count, float radius) noexcept;

  [[nodiscard]] const Vec2* points() const noexcept {
    return points_ != nullptr ? points_ : buffer_.data();
  }
  [[nodiscard]] Vec2 point(int i) const noexcept { return points()[i]; }
  [[nodiscard]] int count() const noexcept { return count_; }
  [[nodiscard]] float radius() const noexcept { return radius_; }

  /// Index of the core point farthest along `direction` (local space); ties go to the lowest
  /// index. Linear scan: for the sizes collide allows, faster than hill climbing.
  [[nodiscard]] int support_index(Vec2 direction) const noexcept {
    const Vec2* p = points();
    int best = 0;
    float best_dot = dot(p[0], direction);
    for (int i = 1; i < count_; ++i) {
      const float d = dot(p[i], direction);
      if (d > best_dot) {
        best = i;
        best_dot = d;
      }
    }
    return best;
  }

 private:
  std::array<Vec2, 2> buffer_{};
  const Vec2* points_ = nullptr;
  int count_ = 0;
  float radius_ = 0.0f;
};

}  // namespace collide
