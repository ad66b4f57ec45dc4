#pragma once
// Internal: the contact of a convex core against one triangle of a level (a TriangleMesh or a
// HeightField), with the triangle's active edges. Implemented in contact3.cpp beside the
// convex-convex routines it reuses; called per candidate triangle by mesh_query.cpp.

#include <collide/core/aabb.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/narrow/manifold.hpp>
#include <collide/narrow/support.hpp>

#include "polytope3.hpp"

#include <array>
#include <cstdint>

namespace collide::detail {

/// Contact of convex core `a` (its polytope and support map, in A's local frame; `a_bounds`
/// its local bounding box, the rounding radius included) with the triangle whose corners
/// `corners` are given in A's frame; `m` in A's frame, normal from A to the triangle, B's
/// features numbered as a single Triangle's (vertex k, edge k, face 0).
///
/// First an early out, which leaves `m` empty: A and the triangle apart by more than `reach`
/// along one of four cheap separating axes, the three of A's bounding box and the triangle's
/// normal (A's extent along it from two support queries). Conservative: the axes are separating
/// axes of the pair, so a caller whose `reach` exceeds the contact's margin plus its rounding
/// allowance drops no contact (Ericson, Real-Time Collision Detection, 5.2.9: the box and plane
/// axes of the triangle-box test, here for any core). The triangle's normal is made once, in
/// double (triangle_normal), for the early out and the contact: a sliver's plane made in float
/// turns by FLT_EPSILON times its length over width.
///
/// `edges()` gives the triangle's active edges (active_edge_bit(k, side), as
/// TriangleMesh::active_edges: from the front and from behind); it is asked only when they
/// matter (a height field computes them from its neighbours). When the manifold's normal is not
/// the triangle's face normal (within kFaceContactSine) and the triangle's feature nearest to A
/// along it is an edge inactive from the side the contact comes from (the normal's; from both
/// when the normal lies in the plane), or a vertex whose two edges are both inactive from
/// there, the contact is made again with the triangle's face (the side facing A) as the
/// reference face: A's incident face (or core) clipped to the triangle's side planes, depth
/// along the face normal. A body sliding over a seam then meets the triangle it is over with
/// the face normal, and the triangle behind the seam gives no point (Jolt's
/// ActiveEdges::FixNormal idea, done by clipping so the depth is measured along the normal
/// reported).
void contact_level_triangle(const Polytope3& a, const ConvexProxy3& proxy_a, const Aabb3& a_bounds,
                            const std::array<Vec3, 3>& corners, float reach,
                            FunctionRef<std::uint8_t()> edges, float margin, Manifold3& m) noexcept;

/// Keeps at most 4 of `count` contact points sharing `normal` (world or A's frame alike): the
/// deepest, the farthest from it, then the two that span the largest area with them (the idea
/// of Jolt's PruneContactPoints); fewer than 5 are copied as they are. With `depth_tie` > 0,
/// points within it of the deepest count as deepest, and the first pick is the one of them
/// farthest from the points' centre (a patch of equal depth keeps its corners).
void reduce_contact_points(const ManifoldPoint3* points, int count, Vec3 normal, Manifold3& m,
                           float depth_tie = 0.0f) noexcept;

}  // namespace collide::detail
