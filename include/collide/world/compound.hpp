#pragma once
/// @file
/// Compound colliders from convex hulls: the bridge from a convex decomposition to the 3D world.
/// A concave prop goes through `decompose_approximate` (decompose/approximate_decomposition.hpp)
/// once, at load time, and its hulls become one body (or one static) of several convex pieces:
/// the world then meets the concave shape itself, not its convex hull (a ray through the hole
/// of a ring, or between the plates of a dumbbell, passes).
///
/// ```cpp
/// const ApproximateDecomposition d = decompose_approximate(prop_mesh);
/// BodyDef3 def = make_compound_body(d.hulls, Transform3{{0, 5, 0}});  // the mesh placed there
/// def.user_id = 42;
/// const BodyId prop = world.add_body(def);
/// // Draw the mesh at mul(world.transform(prop), Transform3{-compound_centroid(d.hulls)}).
/// ```

#include <collide/core/transform3.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/world/world3d.hpp>

#include <span>

namespace collide {

/// Volume centroid of `hulls` taken together, in their space (mesh space for a decomposition's
/// hulls): the sum of each hull's core volume times its centroid over the sum of the volumes
/// (rounding radii left out; where hulls overlap, the overlap counts once per hull). Summed in
/// double. Throws InvalidInput for no hulls ("compound hulls: none given"), or for a hull
/// without volume or with a non-finite centroid, naming its index ("compound hulls[3]: ...":
/// hulls must come from make_convex_hull or decompose_approximate).
[[nodiscard]] Vec3 compound_centroid(std::span<const ConvexHull> hulls);

/// A body made of `hulls` (their space: mesh space for the hulls of a decomposition, world units)
/// that sits where `placement` puts that space: every hull vertex v ends up at
/// transform_point(placement, v) in the world (to float rounding).
///
/// The body's local origin is the hulls' volume centroid c (`compound_centroid`), so the body
/// turns about its centre of volume: each shape is its hull rebuilt by make_convex_hull from
/// its vertices shifted by -c (the same corners in the same order, the radius kept), and the
/// body's transform is placement * translate(c) = {placement.p + placement.q * c,
/// placement.q}. Only `shapes` and `transform` are set; velocity, user id, filter and flags are
/// the caller's to fill in. The mesh the hulls came from is at mul(body transform,
/// Transform3{-c}) as the body moves.
///
/// Allocates (one rebuild per hull); for load time, not per frame. Throws InvalidInput naming
/// the problem: no hulls ("compound hulls: none given"); a hull without volume ("compound
/// hulls[K]: ..."), as compound_centroid; a placement that is not finite or whose quaternion is
/// not unit ("compound placement: ..."). WorldN::add_body checks the rest (the coordinate range,
/// at most 65535 pieces).
[[nodiscard]] BodyDef3 make_compound_body(std::span<const ConvexHull> hulls, const Transform3& placement);

/// A static made of `hulls` (their space, world units) placed by `placement`: the hulls are
/// kept as they are (a static never turns, so it needs no centre), with `placement` as the
/// static's transform. Only `shapes` and `transform` are set. Throws InvalidInput as
/// make_compound_body: no hulls, a hull without volume, a bad placement.
[[nodiscard]] StaticDef3 make_compound_static(std::span<const ConvexHull> hulls, const Transform3& placement);

}  // namespace collide
