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
/// less than their radii get the contact from the closest points of the two core edges.

#include <collide/narrow/manifold.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// The contact manifold between shape A placed by `xa` and shape B placed by `xb`.
/// Empty (count 0) when the shapes are apart; touching exactly counts as contact (depth 0).
/// Normal is unit, from A to B, world space; points are world space with per-point depth and
/// feature ids (vertex/edge indices of each shape, see ContactId). Swapping A and B gives
/// `reversed` of the result. Shapes must be valid (built by the make_* functions); transforms
/// must be finite (checked by COLLIDE_ASSERT).
template <Shape2DType A, Shape2DType B>
[[nodiscard]] Manifold contact(const A& a, const Transform& xa, const B& b,
                               const Transform& xb) noexcept;

/// `contact` for shapes of types known only at run time.
[[nodiscard]] Manifold contact(const Shape2D& a, const Transform& xa, const Shape2D& b,
                               const Transform& xb) noexcept;

}  // namespace collide
