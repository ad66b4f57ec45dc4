#pragma once
/// @file
/// The closest point of a 3D triangle to a point, with its barycentric coordinates.
/// (`TriangleBvh::nearest` tests four triangles at once with a branch-free grouping of the same
/// regions instead.)

#include <collide/core/math.hpp>

namespace collide {

/// Closest point of triangle (a, b, c) to `p`, and its barycentric weights.
struct TrianglePoint {
  Vec3 point{0.0f};                  ///< closest point on the closed triangle, same space as input
  Vec3 weights{1.0f, 0.0f, 0.0f};    ///< barycentric weights of a, b, c: >= 0, sum 1
};

/// The point of the closed triangle (a, b, c) nearest to `p`, found by testing which Voronoi
/// region (vertex, edge or face) of the triangle holds `p` (Ericson, Real-Time Collision
/// Detection, 5.1.5). Any winding; a degenerate triangle yields a nearest point of its edges.
/// Inputs should be finite and expressed near the origin (shift large coordinates first).
[[nodiscard]] TrianglePoint closest_point_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) noexcept;

}  // namespace collide
