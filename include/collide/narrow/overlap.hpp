#pragma once
/// @file
/// `overlap`: do two 2D shapes share at least one point? The cheapest question; each pair takes
/// its cheapest exact path (no manifold, no closest points are built).

#include <collide/core/transform3.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

namespace collide {

/// True when shape A placed by `xa` and shape B placed by `xb` share at least one point.
/// Touching counts: shapes whose gap is within float rounding (kRelativeTolerance of the
/// coordinates' size, in A's frame) overlap. Pairs of circles, capsules and segments are
/// analytic: the closest points of a point or segment to a segment (Ericson, Real-Time Collision
/// Detection, 5.1.2 and 5.1.9) against the sum of the radii. Two polygons of up to 8 vertices
/// each first take the separating axis test over both polygons' edge normals, four at a time
/// (Ericson 5.2.1): an axis separating the cores by more than the radii proves them apart, no
/// separating axis proves the cores overlap; a gap in between goes on to GJK. Other pairs with
/// a polygon use GJK with early exit (Gilbert, Johnson & Keerthi 1988), which stops as soon as
/// either bound decides: the simplex's distance to the origin within the radii (overlap), or
/// the support point's separating-axis lower bound beyond them (apart; van den Bergen 2003,
/// 4.3.4). Shapes must be
/// valid (built by the make_* functions); transforms finite. Swapping A and B gives the same
/// answer except possibly for gaps within the rounding band.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] bool overlap(const A& a, const Transform& xa, const B& b,
                           const Transform& xb) noexcept;

/// `overlap` for shapes of types known only at run time.
[[nodiscard]] bool overlap(const Shape2D& a, const Transform& xa, const Shape2D& b,
                           const Transform& xb) noexcept;

/// True when 3D shape A placed by `xa` and shape B placed by `xb` share at least one point;
/// touching counts, as in 2D. Sphere pairs are analytic; every other pair runs boolean GJK with
/// early exit on the cores (the 2D routine above, in 3D). Shapes must be valid; transforms
/// finite with unit quaternions (COLLIDE_ASSERT).
template <Shape3DType A, Shape3DType B>
[[nodiscard]] bool overlap(const A& a, const Transform3& xa, const B& b,
                           const Transform3& xb) noexcept;

/// `overlap` for 3D shapes of types known only at run time.
[[nodiscard]] bool overlap(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                           const Transform3& xb) noexcept;

/// True when convex shape A placed by `xa` touches or overlaps a triangle of the mesh placed by
/// `xm` (touching within rounding counts, as above). A's bounding box, taken in the mesh's
/// stored frame, queries the BVH; each triangle whose box it meets takes the convex-triangle
/// `overlap`, and the first that overlaps ends the query. Triangles are two-sided surfaces: a
/// shape wholly inside a closed mesh does not overlap it. Allocates nothing (src/narrow/
/// mesh_query.cpp). The order is convex first; the overloads below take the level first.
template <ConvexShape3DType A>
[[nodiscard]] bool overlap(const A& a, const Transform3& xa, const TriangleMesh& mesh,
                           const Transform3& xm) noexcept;

/// The same against a height field placed by `xf`, through its cell query (holes have no
/// triangles).
template <ConvexShape3DType A>
[[nodiscard]] bool overlap(const A& a, const Transform3& xa, const HeightField& field,
                           const Transform3& xf) noexcept;

/// `overlap` with the level shape first: the same answer.
template <ConvexShape3DType B>
[[nodiscard]] bool overlap(const TriangleMesh& mesh, const Transform3& xm, const B& b,
                           const Transform3& xb) noexcept {
  return overlap(b, xb, mesh, xm);
}
/// `overlap` with the height field first: the same answer.
template <ConvexShape3DType B>
[[nodiscard]] bool overlap(const HeightField& field, const Transform3& xf, const B& b,
                           const Transform3& xb) noexcept {
  return overlap(b, xb, field, xf);
}

}  // namespace collide
