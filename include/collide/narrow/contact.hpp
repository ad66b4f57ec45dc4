#pragma once
/// @file
/// `contact`: where and how deep two 2D shapes touch, for every pair of shape types in both
/// orders.
///
/// Routines (src/narrow/): circle-circle analytic; polygon-circle by the Voronoi region of the
/// circle centre (Ericson, Real-Time Collision Detection, 5.2.7); every other pair sees capsules
/// and segments as 2-vertex polygons and runs the separating axis test over both polygons' edge
/// normals, then clips the incident edge against the reference edge's side planes (Catto,
/// "Contact Manifolds", GDC 2007; Ericson 5.2.1 and 8.3.2). Rounded shapes that are apart by
/// less than their radii get the contact from the closest points of the two cores (Ericson
/// 5.1.9), so corner-against-corner contact has its true normal.
///
/// Feature ids (ContactId): a circle is face 0. Capsule and segment: vertex 0 (end a), vertex 1
/// (end b), edge 0 (the side to the right of a -> b), edge 1 (the side to the right of b -> a).
/// Polygon: vertex i, edge i (from vertex i to i + 1). A point where a vertex of one shape lies
/// on an edge of the other is (edge, vertex); where the incident edge was cut by a side plane
/// of the reference edge, (vertex of the reference edge, incident edge); corner against corner
/// of rounded shapes, (vertex, vertex). Ids do not change under small motions unless the
/// touching features do.

#include <collide/narrow/manifold.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// The contact manifold between shape A placed by `xa` and shape B placed by `xb`.
/// Empty (count 0) when the shapes are apart; touching exactly counts as contact (depth 0).
/// Normal is unit, from A to B, world space; points are world space, midway between the
/// surfaces, with per-point depth and feature ids (see the file comment). 1 or 2 points: 2 when
/// faces touch along a stretch (parallel edges).
///
/// Swapping A and B gives `reversed` of the result, except where the reference face is a
/// near-tie: A's face is kept unless B's separates more by kReferenceFaceTolerance of the
/// faces' size, for frame-to-frame stability, so the reported depth may exceed the minimum
/// penetration by that much. Exact far from the origin: B is moved into A's frame once.
/// Polygons with up to kMaxPolygonVertices vertices; allocates nothing.
///
/// Shapes must be valid (built by the make_* functions); transforms must be finite with unit
/// rotation (checked by COLLIDE_ASSERT in debug builds). Nothing is thrown.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] Manifold contact(const A& a, const Transform& xa, const B& b,
                               const Transform& xb) noexcept;

/// `contact` for shapes of types known only at run time.
[[nodiscard]] Manifold contact(const Shape2D& a, const Transform& xa, const Shape2D& b,
                               const Transform& xb) noexcept;

}  // namespace collide
