#pragma once
/// @file
/// Point queries: the closest point on a shape's surface to a point, the signed distance, and
/// the Voronoi region (closest feature) the point lies in (the lesson's "Voronoi Regions";
/// Ericson, Real-Time Collision Detection, 5.1).

#include <collide/narrow/manifold.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>

namespace collide {

/// Result of a point query in D dimensions. World space.
template <int D>
struct PointQueryN {
  bool inside = false;      ///< the point lies strictly inside the solid shape
  float distance = 0.0f;    ///< signed distance to the surface: negative inside, world units
  VecN<D> closest{0.0f};    ///< closest point on the surface
  /// Voronoi feature of the core the point lies in: the feature whose region holds the point
  /// outside the core; inside a polygon's core, the edge of least penetration. Feature indices
  /// as in manifold.hpp (Circle: face 0. Capsule and segment: vertex 0 (end a), vertex 1
  /// (end b), edge 0 (the side to the right of a -> b), edge 1 (the side to the right of
  /// b -> a). Polygon: vertex i, or edge i from vertex i to i + 1).
  Feature feature{};
};

using PointQuery = PointQueryN<2>;   ///< 2D point query
using PointQuery3 = PointQueryN<3>;  ///< 3D point query

/// Closest surface point of shape placed by `xf` to world point `point`, with signed distance
/// and Voronoi feature; radii (circles, capsules, rounded polygons) applied along the direction
/// from the core's closest point to `point`. Ties: a point on a segment or capsule core is in
/// edge 0; the centre of a circle gets the closest point in local +x. A segment has no inside
/// (distance >= 0). Shapes must be valid; `point` and `xf` finite. O(n) for polygons: the edge
/// of greatest separation, then a walk through the Voronoi regions (Ericson 5.1.2-5.1.5).
template <Shape2DType S>
[[nodiscard]] PointQuery closest_point(const S& shape, const Transform& xf, Vec2 point) noexcept;

/// `closest_point` for a shape whose type is known only at run time.
[[nodiscard]] PointQuery closest_point(const Shape2D& shape, const Transform& xf,
                                       Vec2 point) noexcept;

/// Closest surface point of the 3D shape placed by `xf` to world point `point`, with signed
/// distance (negative inside) and the Voronoi feature of the core the point lies in, as the 2D
/// `closest_point` does; radii (spheres, capsules, rounded boxes) applied along the direction
/// from the core's closest point to `point`. The point is moved into the shape's local frame
/// first. Ties and degenerate directions: the centre of a sphere gets the closest point in
/// local +x; a point on a capsule's core line gets a direction across the axis (the axis'
/// cross product with the local coordinate axis it is least aligned with); a point on a core
/// end, the axis outward. A segment has no inside (distance >= 0). Shapes must be valid;
/// `point` and `xf` finite.
/// - Sphere: the centre. Capsule3 and Segment3: the core segment's projection clamped to the
///   ends (Ericson, Real-Time Collision Detection, 5.1.2): vertex 0 or 1 when clamped, edge 0
///   otherwise.
/// - Box: outside, clamp each coordinate to the half extents (Ericson 5.1.3); the number of
///   clamped coordinates names the feature (1: face, 2: edge, 3: vertex). Inside the core (or on
///   its surface), the face of least penetration, the lowest axis on ties.
/// - ConvexHull: the face of greatest separation; inside (no positive separation), it is the
///   face of least penetration and the point is pushed out to it. Outside, if the point
///   projects within that face the projection is the answer; otherwise the closest point of
///   every face with positive separation (its projection, or the nearest point of its sides) is
///   compared (Ericson 5.1.7, sides by 5.1.2). Features: face, `edges` index, vertex index. O(faces)
///   plus the sides of the separating faces.
/// - Triangle: its Voronoi regions (Ericson 5.1.5, `closest_point_on_triangle`): vertex k, edge
///   k (corner k to k + 1) or face 0. Two-sided with no inside: distance >= 0; a point on the
///   triangle reports the face (or the edge or vertex it lies on) at distance 0.
template <Shape3DType S>
[[nodiscard]] PointQuery3 closest_point(const S& shape, const Transform3& xf, Vec3 point) noexcept;

/// `closest_point` for a 3D shape whose type is known only at run time.
[[nodiscard]] PointQuery3 closest_point(const Shape3D& shape, const Transform3& xf,
                                        Vec3 point) noexcept;

}  // namespace collide
