#pragma once
/// @file
/// Ray casts against single shapes (lasers, mouse picks, line of sight), and reflection for
/// lasers and mirrors. One fraction convention: point = origin + fraction * translation.
/// 2D shapes, and in 3D the triangle shapes of levels: Triangle, TriangleMesh, HeightField.

#include <collide/core/function_ref.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>

#include <collide/shape/triangle.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <cstdint>

namespace collide {

/// Where a ray first enters a shape, in D dimensions. On a miss: hit false, every other field
/// zero.
template <int D>
struct RayHitN {
  bool hit = false;
  float fraction = 0.0f;     ///< along the ray's translation, [0, 1]
  VecN<D> point{0.0f};       ///< world space, on the shape's surface
  VecN<D> normal{0.0f};      ///< unit outward surface normal at `point`, world space
  /// Which part of a shape made of parts was hit: the triangle index of a `TriangleMesh` or
  /// `HeightField`; 0 for a convex shape.
  std::uint32_t sub_shape = 0;
};

using RayHit = RayHitN<2>;   ///< 2D ray hit
using RayHit3 = RayHitN<3>;  ///< 3D ray hit

/// Where a ray first enters a shape, the fraction alone (`raycast_fraction`), in 2D and 3D. On a
/// miss: hit false, fraction zero.
struct RayFraction {
  bool hit = false;
  float fraction = 0.0f;  ///< along the ray's translation, [0, 1]: point = origin + fraction * translation
};

/// First entry of `ray` (world space) into the shape placed by `xf`. A ray must enter to hit:
/// one that starts in the closed shape (inside, or exactly on its surface whichever way it
/// heads) reports no hit, and so do a ray of zero length and a ray with a NaN coordinate. Shapes
/// must be valid (built by the make_* functions), `xf` finite. The ray is moved into the shape's
/// local frame first, so precision does not degrade far from the world origin.
/// - Circle: analytic quadratic (Ericson, Real-Time Collision Detection, 5.3.2), discriminant
///   from the closest approach (Haines et al., Ray Tracing Gems, ch. 7).
/// - Capsule: its flat sides as a slab, then the end disc on the side the ray meets (Ericson
///   5.3.7 in 2D).
/// - Polygon: the ray's line splits the vertices into left and right; walking
///   counter-clockwise, the edge that crosses from left to right is where the line enters (a
///   branch-free scan, one division). A rounded polygon is exactly the union of its core, its
///   edges pushed out by the radius and a disc at each vertex: the pushed-out polygon is
///   clipped by its edge half-planes (Cyrus & Beck 1978; Ericson 5.3.8), then one vertex disc
///   is tested when the entry lands beyond an edge's end.
/// - Segment: two-sided, the normal faces the ray's origin. A ray along the segment's line
///   (parallel within kParallelTolerance, on the line within kRelativeTolerance of the
///   segment's length) hits the nearer end with the normal pointing back along the ray, since
///   touching counts; one starting on the segment reports no hit.
template <Shape2DType S>
[[nodiscard]] RayHit raycast(const S& shape, const Transform& xf, const Ray& ray) noexcept;

/// `raycast` for a shape whose type is known only at run time.
[[nodiscard]] RayHit raycast(const Shape2D& shape, const Transform& xf, const Ray& ray) noexcept;

/// `raycast`'s hit and fraction alone, for the questions that need no point or normal: line of
/// sight, a sensor ray, whether anything lies within a distance. The same hit and the same
/// fraction as `raycast`, bit for bit (one code makes both; the point and normal are left
/// unmade, which saves a ball's or a rounded corner's square root and division). The rules of
/// `raycast` hold: a ray must enter to hit, and a miss is hit false with fraction 0.
template <Shape2DType S>
[[nodiscard]] RayFraction raycast_fraction(const S& shape, const Transform& xf, const Ray& ray) noexcept;

/// `raycast_fraction` for a shape whose type is known only at run time.
[[nodiscard]] RayFraction raycast_fraction(const Shape2D& shape, const Transform& xf, const Ray& ray) noexcept;

/// First entry of `ray` (world space) into the 3D shape placed by `xf`, under the same rules as
/// the 2D `raycast`: the ray must enter to hit (an origin in the closed shape, a zero-length ray
/// and a NaN coordinate report no hit); `fraction` in [0, 1], `point` on the surface (world),
/// `normal` unit and outward (world); `sub_shape` 0. Shapes must be valid (make_* functions),
/// `xf` finite. The ray is moved into the shape's local frame first (a sphere's: only its
/// origin, relative to the centre), so precision does not degrade far from the world origin.
/// - Sphere: analytic quadratic (Ericson, Real-Time Collision Detection, 5.3.2), discriminant
///   from the closest approach (Haines et al., Ray Tracing Gems, ch. 7).
/// - Capsule3: the infinite cylinder about the core first; an entry beyond an end, or an origin
///   inside the cylinder beyond an end, leaves only that end's sphere to test (Ericson 5.3.7).
/// - Segment3: it has no area, so a ray in general position never meets it. A ray hits when its
///   line passes within kRelativeTolerance of sqrt(|segment|^2 + |translation|^2) of the
///   segment's line (coplanar within rounding) and crosses it between the segment's ends, the
///   normal then lying in their common plane, perpendicular to the segment and facing the
///   ray's origin. A ray along the segment's line (parallel within kParallelTolerance, on the
///   line within the same distance) hits the nearer end with the normal pointing back along the
///   ray, as in 2D. Far from the world origin a ray can only be aimed that exactly when its
///   coordinates are, so use a thin Capsule3 for a ray to hit a rope or a laser's path.
/// - Box: the slab test (Kay & Kajiya 1986; Williams et al., "An Efficient and Robust Ray-Box
///   Intersection Algorithm", JGT 2005): the last slab entered before the first one left. A
///   rounded box exactly: the box grown by the radius is clipped by its slabs; an entry beside
///   the face's core is the answer, otherwise the ray is followed through the Voronoi regions of
///   the core (between the fractions where a coordinate crosses a half extent the closest core
///   feature is fixed: a face, an edge or a corner) and each region's distance function (to a
///   plane, a line, a point) is solved for the first fraction at the radius.
/// - ConvexHull: Cyrus-Beck clipping by the face planes (Cyrus & Beck 1978; Ericson 5.3.8); the
///   normal is the entering face's. A rounded hull exactly: the hull with its faces pushed out
///   by the radius is clipped the same way; an entry beside the core face is the answer,
///   otherwise the first entry over the capsules around the core's edges (with a face turned
///   towards the ray) is, the rounded surface away from the faces being made of those.
///   O(faces + edges) for a rounded hull's edge and corner hits, O(faces) otherwise.
template <Shape3DType S>
[[nodiscard]] RayHit3 raycast(const S& shape, const Transform3& xf, const Ray3& ray) noexcept;

/// `raycast` for a 3D shape whose type is known only at run time.
[[nodiscard]] RayHit3 raycast(const Shape3D& shape, const Transform3& xf,
                              const Ray3& ray) noexcept;

/// The 3D `raycast`'s hit and fraction alone (see the 2D `raycast_fraction`): bit for bit
/// `raycast`'s, without the point and the world-space normal (a sphere's cast then skips the
/// normal's square root and division, a box's and a hull's the normal's turn into the world).
template <Shape3DType S>
[[nodiscard]] RayFraction raycast_fraction(const S& shape, const Transform3& xf, const Ray3& ray) noexcept;

/// `raycast_fraction` for a 3D shape whose type is known only at run time.
[[nodiscard]] RayFraction raycast_fraction(const Shape3D& shape, const Transform3& xf, const Ray3& ray) noexcept;

// ---- 3D: triangles, meshes, height fields ------------------------------------------------

/// First crossing of `ray` (world space) with the triangle shape placed by `xf` (valid transform,
/// shape built by its make_* function). The ray is moved into the shape's local frame first (and
/// for meshes and height fields to their stored origin), so precision does not degrade far from
/// the world origin. Results are world space: `point` = ray.at(fraction), `normal` the unit
/// normal of the triangle hit turned to face the ray's origin (against the ray), `sub_shape` the
/// triangle's index (its face feature id; 0 for a Triangle).
///
/// Triangles are two-sided surfaces with no inside, so the 2D rule "a ray must enter" reads: a
/// ray that starts exactly on a triangle (fraction 0) does not hit that triangle, whichever way
/// it heads (a ray cast again from a hit point does not find the surface it left), and a ray
/// starting inside a closed mesh hits its inner side. A ray in a triangle's plane does not hit
/// it. A ray of zero length or with a NaN or infinite coordinate hits nothing.
/// The crossing test is watertight (`ray_triangle_fraction`: Woop, Benthin & Wald 2013): a ray
/// through a shared edge or vertex of a closed mesh hits at least one triangle there; which one
/// is reported then is deterministic for a given mesh. Which side was hit: compare `normal` with
/// the triangle's own normal (counter-clockwise winding, `triangle_normal`), rotated by xf.
/// - Triangle: the crossing test directly.
/// - TriangleMesh: the nearest crossing through its BVH (`TriangleBvh::ray_cast`).
/// - HeightField: the cells under the ray's path in order (`HeightField::ray_cast`); holes have
///   no triangles.
[[nodiscard]] RayHit3 raycast(const Triangle& triangle, const Transform3& xf, const Ray3& ray) noexcept;
[[nodiscard]] RayHit3 raycast(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray) noexcept;
[[nodiscard]] RayHit3 raycast(const HeightField& field, const Transform3& xf, const Ray3& ray) noexcept;

/// `raycast`'s hit and fraction alone for the triangle shapes (see the 2D `raycast_fraction`),
/// bit for bit `raycast`'s: the nearest crossing, without turning its triangle's normal to face
/// the ray and into the world.
[[nodiscard]] RayFraction raycast_fraction(const Triangle& triangle, const Transform3& xf, const Ray3& ray) noexcept;
[[nodiscard]] RayFraction raycast_fraction(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray) noexcept;
[[nodiscard]] RayFraction raycast_fraction(const HeightField& field, const Transform3& xf, const Ray3& ray) noexcept;

/// Called by the callback ray casts below with each crossing (a full world-space RayHit3 as
/// `raycast` returns it: hit true, fraction, point, normal facing the ray's origin, sub_shape =
/// triangle). Returns the new maximum fraction (TriangleRayCallback's convention): `hit.fraction`
/// to keep only nearer crossings, 1 (or the current maximum) for every crossing, 0 to stop.
using RayHitCallback = FunctionRef<float(const RayHit3& hit)>;

/// Every crossing of `ray` (world space) with the mesh or height field placed by `xf`, reported
/// to `visit` (which may clip or stop the ray), with the same rules as `raycast`. A mesh reports
/// nearer boxes first but its crossings in no set order; a height field in the order of the
/// cells under the ray. Each triangle at most once. No allocation; what `visit` throws propagates.
void raycast(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray, RayHitCallback visit);
void raycast(const HeightField& field, const Transform3& xf, const Ray3& ray, RayHitCallback visit);

/// `direction` mirrored about the plane with unit normal `normal`: d - 2 (d . n) n.
[[nodiscard]] constexpr Vec2 reflect(Vec2 direction, Vec2 normal) noexcept {
  return direction - 2.0f * (direction.x * normal.x + direction.y * normal.y) * normal;
}

/// The ray that continues a laser after it hits a mirror: it starts at the hit point and keeps
/// the length the incoming ray had left, mirrored about the hit normal. `hit` must be a hit of
/// `ray`. Rounding can put the new start a hair behind the mirror, so a laser loop should not
/// cast the reflected ray at the mirror it just left (a convex mirror cannot be hit again).
[[nodiscard]] constexpr Ray reflect(const Ray& ray, const RayHit& hit) noexcept {
  return Ray{hit.point, (1.0f - hit.fraction) * reflect(ray.translation, hit.normal)};
}

/// `direction` mirrored about the plane with unit normal `normal`: d - 2 (d . n) n (3D).
[[nodiscard]] constexpr Vec3 reflect(Vec3 direction, Vec3 normal) noexcept {
  return direction -
         2.0f * (direction.x * normal.x + direction.y * normal.y + direction.z * normal.z) * normal;
}

/// The 3D ray that continues a laser after it hits a mirror (see the 2D `reflect`): it starts
/// at the hit point with the length the incoming ray had left, mirrored about the hit normal.
[[nodiscard]] constexpr Ray3 reflect(const Ray3& ray, const RayHit3& hit) noexcept {
  return Ray3{hit.point, (1.0f - hit.fraction) * reflect(ray.translation, hit.normal)};
}

}  // namespace collide
