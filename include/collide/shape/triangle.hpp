#pragma once
/// @file
/// A single 3D triangle as a shape, the closest point of a triangle to a point, and the
/// watertight ray-triangle crossing that every triangle ray cast in collide uses (single
/// triangles, `TriangleBvh`, `HeightField`).

#include <collide/core/aabb.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/math.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/transform3.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

namespace collide {

/// A triangle in local space, zero thickness and two-sided. Corner k is `vertices[k]`; edge k
/// runs from corner k to corner k + 1 (mod 3), as in meshes. Its geometric normal is
/// (v1 - v0) x (v2 - v0) (counter-clockwise seen from the side it points to). Feature ids:
/// vertex k, edge k, face 0.
struct Triangle {
  std::array<Vec3, 3> vertices{};  ///< local space
};

/// A validated triangle. Throws InvalidInput if a coordinate is not finite (naming the corner,
/// "triangle vertex 2: not finite") or the triangle is degenerate: its area is at most
/// kDegenerateAreaTolerance of its longest edge squared (repeated or collinear corners, slivers
/// too thin to have a reliable plane).
[[nodiscard]] Triangle make_triangle(Vec3 a, Vec3 b, Vec3 c);

/// Bounding box of the triangle placed by `xf`, world space.
[[nodiscard]] Aabb3 compute_aabb(const Triangle& triangle, const Transform3& xf) noexcept;

/// The normal (b - a) x (c - a) of triangle (a, b, c), not normalised, in double, made as the
/// cross product of the two edges at the corner opposite the longest edge (the widest angle,
/// whose sine is the largest): within about DBL_EPSILON of its direction for any triangle that
/// is not collinear to double's rounding. triangle_area_normal's rare path, out of line; zero
/// when the corners are collinear.
[[nodiscard]] glm::dvec3 triangle_area_normal_at_widest_corner(Vec3 a, Vec3 b, Vec3 c) noexcept;

/// triangle_area_normal keeps the cross product at corner a when the sine of a's angle, squared,
/// is at least this: the normal is then within about DBL_EPSILON / sin a = 2^-33 of its
/// direction, far inside float's rounding.
inline constexpr double kAreaNormalMinSineSquared = 0x1p-40;

/// The normal (b - a) x (c - a) of triangle (a, b, c), not normalised (its length is twice the
/// triangle's area), in double: the differences of float corners are exact there (or within
/// double's rounding when their magnitudes are far apart), and so are their products, so a
/// sliver's normal (from two nearly parallel edges) keeps about 29 more bits than its length
/// over width can cost. Made in float it turns by about FLT_EPSILON times that ratio: on a
/// triangle 2 units long and 1e-8 wide, a plane distance or a projection off by a whole unit.
/// A rounded edge turns the cross product by about DBL_EPSILON over the sine of the angle
/// between its edges; at a needle's tip that sine can be below double's rounding (a needle 10.8
/// long with a 5.7e-14 side, its tip 10 from the origin, turned 2%: fuzzing.md, finding 23). So
/// when a's angle is that sharp (kAreaNormalMinSineSquared), the product is taken at the corner
/// opposite the longest edge instead, whose sine is the largest (law of sines): the same vector
/// in exact arithmetic. (Our derivation; Kahan's "Miscalculating Area and Angles of a
/// Needle-like Triangle" orders a needle's sides for its area the same way.) Finite for any
/// finite float corners, and zero only when they are collinear.
[[nodiscard]] COLLIDE_ALWAYS_INLINE glm::dvec3 triangle_area_normal(Vec3 a, Vec3 b, Vec3 c) noexcept {
  const glm::dvec3 da(a);
  const glm::dvec3 ab = glm::dvec3(b) - da, ac = glm::dvec3(c) - da;
  const glm::dvec3 n = glm::cross(ab, ac);
  // |n|^2 = |ab|^2 |ac|^2 sin^2(a); nothing here overflows or underflows for float corners.
  if (glm::dot(n, n) >= kAreaNormalMinSineSquared * glm::dot(ab, ab) * glm::dot(ac, ac)) [[likely]] {
    return n;
  }
  return triangle_area_normal_at_widest_corner(a, b, c);
}

/// The squared lengths of a float normal that `triangle_normal` normalises in float: squares of
/// components far below the length underflow harmlessly above the low end, and the square root
/// and reciprocal are exact to rounding below the high end; outside (edges below about 1e-15
/// or above 1e15 units), it normalises in double.
inline constexpr float kTriangleNormalDirectMinSquared = 1e-30f;
/// The high end of the squared lengths `triangle_normal` normalises in float.
inline constexpr float kTriangleNormalDirectMaxSquared = 1e30f;

/// Unit normal of triangle (a, b, c) by the right-hand rule, (b - a) x (c - a) normalised;
/// zero when the corners are collinear. The cross product is made in double
/// (triangle_area_normal), so that a sliver's normal is right to float rounding whatever its
/// length over width; rounded to float, its direction stays right to float rounding, and most
/// triangles are normalised there (one float square root and reciprocal, as before stop 104: a
/// level contact makes a normal per candidate triangle); a tiny or huge one in double, where its
/// length neither underflows nor overflows. Inlined by force: called out of line, its arguments
/// (each Vec3 in two registers) were put back together through the stack by loads spanning two
/// stores, which the processor cannot forward; that stall was a fifth of a mesh ray cast's time
/// (bench_mesh_raycast), and with the double cross product GCC no longer inlined it unasked.
[[nodiscard]] COLLIDE_ALWAYS_INLINE Vec3 triangle_normal(Vec3 a, Vec3 b, Vec3 c) noexcept {
  const glm::dvec3 exact = triangle_area_normal(a, b, c);
  const Vec3 n(exact);
  const float nn = dot(n, n);
  if (nn >= kTriangleNormalDirectMinSquared && nn <= kTriangleNormalDirectMaxSquared) [[likely]] {
    return n * (1.0f / std::sqrt(nn));
  }
  // (finite and in double's normal range for any finite float corners)
  const double squared = glm::dot(exact, exact);
  return squared > 0.0 ? Vec3(exact * (1.0 / std::sqrt(squared))) : Vec3(0.0f);
}

/// Called with each triangle a level query finds (`for_each_triangle` of a TriangleMesh or a
/// HeightField): its index in the level and its corners, world space. Return true to go on,
/// false to stop.
using TriangleCornersCallback =
    FunctionRef<bool(std::uint32_t triangle, const std::array<Vec3, 3>& corners)>;

/// Closest point of triangle (a, b, c) to `p`, and its barycentric weights.
struct TrianglePoint {
  Vec3 point{0.0f};                  ///< closest point on the closed triangle, same space as input
  Vec3 weights{1.0f, 0.0f, 0.0f};    ///< barycentric weights of a, b, c: >= 0, sum 1
};

/// The point of the closed triangle (a, b, c) nearest to `p`, found by which Voronoi region
/// (vertex, edge or face) of the triangle holds `p` (Ericson, Real-Time Collision Detection,
/// 5.1.5), grouped as: the face when `p` projects inside all three edges, else the nearest of
/// the three edges' clamped points. Computed in double, so slivers (nearly collinear corners,
/// whose plane float cannot hold) get their nearest point within float rounding as any
/// triangle does, and weights that give that point back; any winding; a degenerate triangle
/// yields a nearest point of its edges.
/// Inputs should be finite and expressed near the origin (shift large coordinates first).
/// (`TriangleBvh::nearest` tests four triangles at once with the same grouping in float lanes,
/// on unit normals made in double, then asks this function for the winner's point.)
[[nodiscard]] TrianglePoint closest_point_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) noexcept;

/// Fraction in (0, max_fraction] at which `ray` (point = origin + fraction * translation)
/// crosses the triangle (a, b, c), from either side; a negative value on a miss. All in one
/// space (local: shift large coordinates first).
///
/// Watertight (Woop, Benthin & Wald, "Watertight Ray/Triangle Intersection", JCGT 2(1), 2013):
/// the corners are moved to the ray's origin and sheared so the ray runs along the z axis, then
/// the three edge functions are evaluated in 2D, recomputed in double when one is exactly zero.
/// The edge function of an edge depends only on the edge's two corners and the ray, so
/// triangles that share an edge (the same corner coordinates) see the same value with opposite
/// sign: a ray through the edge or a vertex of a closed mesh hits at least one of the triangles
/// around it, never slips between them.
/// Edge behaviour: a point exactly on an edge or corner counts as inside (closed triangle), so
/// such a ray hits every triangle that meets there (each at the same fraction).
/// A ray starting exactly on the triangle (fraction 0) does not hit it: the ray must leave the
/// surface to hit, as for every shape (see `raycast`). A ray in the triangle's plane does not
/// hit it (its projection has no area; within rounding of the plane the answer may go either
/// way). A ray of zero length or with a non-finite coordinate never hits.
[[nodiscard]] float ray_triangle_fraction(const Ray3& ray, Vec3 a, Vec3 b, Vec3 c,
                                          float max_fraction = 1.0f) noexcept;

/// An internal edge between two triangles that meet at a convex dihedral angle is active when
/// their normals turn by more than the angle whose cosine this is: 5 degrees (Jolt's default,
/// MeshShapeSettings::mActiveEdgeCosThresholdAngle). Flatter convex edges and every concave
/// edge are inactive (seen from the side where they are concave; see active_edge_sides).
inline constexpr float kActiveEdgeCosAngle = 0.996194698f;  // cos(5 degrees)

/// Two triangles over an edge whose normals are closer to opposite than this cosine (folded
/// back onto each other within about 1 degree: a fin, a zero-thickness wall) have an active
/// edge: the convex / concave test has no reliable sign there.
inline constexpr float kFoldBackCosAngle = -0.999847695f;  // cos(179 degrees)

/// Bit of `TriangleMesh::active_edges[t]` (and `HeightField::active_edges(t)`) for edge k (corner
/// k to corner k + 1) of triangle t, seen from its `side`: 0 the front (where the geometric normal
/// points; bits 0-2), 1 behind it (bits 3-5). Triangles are two-sided, and an edge that is concave
/// from the front is convex from behind: a body under a height field meets a spike's tip there
/// (docs/fuzzing.md, finding 22).
[[nodiscard]] constexpr std::uint8_t active_edge_bit(int k, int side = 0) noexcept {
  return static_cast<std::uint8_t>(1u << (k + 3 * side));
}

/// The bits (active_edge_bit) of edge k for `sides` as active_edge_sides gives them: bit 0 the
/// front, bit 1 behind; 3 for a boundary or non-manifold edge, active from both.
[[nodiscard]] constexpr std::uint8_t active_edge_bits(int k, unsigned sides) noexcept {
  return static_cast<std::uint8_t>(((sides & 1u) ? active_edge_bit(k, 0) : 0u) | ((sides & 2u) ? active_edge_bit(k, 1) : 0u));
}

/// The sides of triangle 1 from which the edge it shares with triangle 2 is active (see
/// kActiveEdgeCosAngle): bit 0 from its front (where unit normal `n1` points), bit 1 from behind.
/// `e` is the edge's direction as triangle 1 runs it; `n2` is already turned to agree with
/// triangle 1's winding. Convex from the front when n2 turns away from n1 about e, (n1 x n2) . e
/// > 0 (the idea of Jolt's ActiveEdges.h and Bullet's btInternalEdgeUtility, written here from
/// the definition), and then concave from behind; the other way round when (n1 x n2) . e < 0. A
/// side from which the edge is convex sees it active when the normals turn by more than the
/// threshold; a flatter edge is inactive from both. When the two windings disagree over the edge
/// (`consistent` false) there is no front and back to tell apart: active from both sides unless
/// flat within the threshold. Folded-back pairs (kFoldBackCosAngle) are active from both.
[[nodiscard]] std::uint8_t active_edge_sides(Vec3 n1, Vec3 n2, Vec3 e, bool consistent, float cos_threshold) noexcept;

/// The triangle of a set (a TriangleBvh, a HeightField) that a ray crosses first.
struct TriangleRayHit {
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< triangle index; max() on a miss
  float fraction = 0.0f;  ///< along the ray's translation, (0, max_fraction]; 0 on a miss
  /// Unit geometric normal of the triangle, (b - a) x (c - a) normalised for its corners
  /// (a, b, c) as given (the set's space); it may face either way along the ray. Zero on a miss.
  Vec3 normal{0.0f};
};

/// Called by `TriangleBvh::ray_cast` and `HeightField::ray_cast` for each triangle the ray
/// crosses within the current maximum fraction, with the triangle's index and the fraction of
/// the crossing. Returns the new maximum fraction (Box2D and Jolt convention): the crossing's
/// `fraction` to keep only nearer ones (closest hit), a value at or above the current maximum
/// (1 always is) to go on unclipped (every hit), 0 (or less) to stop at once.
using TriangleRayCallback = FunctionRef<float(std::uint32_t triangle, float fraction)>;

}  // namespace collide
