#pragma once
/// @file
/// `shape_cast`: when do two translating shapes first touch? The lesson's "Continuous Collision
/// Detection": A moving by `va` and B moving by `vb` over the step t in [0, 1] touch at time t
/// exactly when (A + t va) - (B + t vb) = (A - B) - t (vb - va) contains the origin, i.e. when
/// the ray from the origin along r = vb - va enters the Minkowski difference A - B. The first
/// touch is where that ray enters A - B.
///
/// Two ways to trace that ray:
///  - `gjk_shape_cast` (the fast path, every shape pair): GJK ray casting on support functions
///    (van den Bergen, "Ray Casting against General Convex Objects with Application to
///    Continuous Collision Detection", 2004). A - B is never built: each step asks A and B for
///    one support point, and the ray's start only moves forward past planes that A - B lies
///    behind, so the reported time is never later than the true first touch. No allocation.
///  - `shape_cast_minkowski` (the explicit path, polygons): build A - B with
///    `minkowski_difference` and cast the ray into it with `raycast`. Slower and allocating;
///    kept as the readable reference the fast path is tested against, and for pictures.

#include <collide/core/status.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <cstdint>

namespace collide {

/// A hit is reported once the shapes are within this fraction of the smaller shape's size of
/// each other (the target separation of the cast; rounding of large coordinates adds to it, see
/// kShapeCastRounding). Exact contact is then at most this far away in distance.
inline constexpr float kShapeCastTolerance = 1e-4f;

/// Float rounding allowance of the cast, as a fraction of the largest coordinate involved (the
/// length of the relative motion plus the shapes' offset and sizes): below this, distances are
/// noise. About 8 float epsilons.
inline constexpr float kShapeCastRounding = 1e-6f;

/// Iteration cap of the GJK ray cast. Convex pairs of up to kMaxPolygonVertices vertices take
/// far fewer (typically under 10); reaching it reports `QueryStatus::max_iterations`.
inline constexpr int kShapeCastMaxIterations = 64;

/// Result of a shape cast in D dimensions. World space throughout.
template <int D>
struct ShapeCastResultN {
  /// True when the shapes touch during the step: status hit or overlapped.
  bool hit = false;
  /// Fraction of the step at first touch, in [0, 1] (0 when overlapped): each shape is then at
  /// its start moved by fraction times its translation. On `separated`: 1, the shapes move the
  /// whole step freely. On `max_iterations`: the fraction reached, before which there is no
  /// contact.
  float fraction = 1.0f;
  /// Contact point at `fraction`, world space: midway between the two surfaces (which are
  /// within the cast tolerance of each other). Zero unless `hit`.
  VecN<D> point{0.0f};
  /// Unit contact normal from A to B at `fraction`, world space. Zero unless `hit`; also zero
  /// when overlapped with the cores (the shapes without their radii) overlapping, where no
  /// single normal is meaningful.
  VecN<D> normal{0.0f};
  int iterations = 0;  ///< GJK iterations used
  /// hit: first touch at `fraction` in (0, 1]; separated: apart over the whole step;
  /// overlapped: touching or overlapping at the start (within the tolerance); max_iterations:
  /// the iteration cap was reached, `fraction` is a safe time (no contact before it), not a hit.
  QueryStatus status = QueryStatus::separated;
};

using ShapeCastResult = ShapeCastResultN<2>;   ///< 2D shape cast result
using ShapeCastResult3 = ShapeCastResultN<3>;  ///< 3D shape cast result

/// Time of first touch of proxy A placed by `xa` and translating by `va` (world units over the
/// step) and proxy B placed by `xb` translating by `vb`, as a fraction of the step in [0, 1], by
/// GJK ray casting into A - B (van den Bergen 2004), in 2D or 3D. Radii are handled exactly
/// (the cast stops at the radius sum). Works in A's frame, so large coordinates cancel first.
/// Never allocates. Proxies must hold 1..kMaxPolygonVertices (2D) / kMaxProxyPoints3 (3D) finite
/// points; transforms and velocities must be finite (checked by COLLIDE_ASSERT only: validated
/// entry points are `shape_cast`).
template <int D>
[[nodiscard]] ShapeCastResultN<D> gjk_shape_cast(const ConvexProxyN<D>& a,
                                                 const TransformN<D>& xa, VecN<D> va,
                                                 const ConvexProxyN<D>& b,
                                                 const TransformN<D>& xb, VecN<D> vb) noexcept;

extern template ShapeCastResultN<2> gjk_shape_cast<2>(const ConvexProxyN<2>&, const Transform&,
                                                      Vec2, const ConvexProxyN<2>&,
                                                      const Transform&, Vec2) noexcept;
extern template ShapeCastResultN<3> gjk_shape_cast<3>(const ConvexProxyN<3>&, const Transform3&,
                                                      Vec3, const ConvexProxyN<3>&,
                                                      const Transform3&, Vec3) noexcept;

/// The validation of the shape-cast entry points: throws InvalidInput naming the field ("xa",
/// "va", "xb", "vb") if a transform is not finite rigid (unit rotation) or a translation is not
/// finite.
void check_cast_input(const Transform& xa, Vec2 va, const Transform& xb, Vec2 vb);
/// The same for 3D: throws InvalidInput naming "xa", "va", "xb" or "vb" (a quaternion must be
/// unit length within 1e-3).
void check_cast_input(const Transform3& xa, Vec3 va, const Transform3& xb, Vec3 vb);

/// Time of first touch of shape A (placed by `xa`, translating by `va` over the step) and shape
/// B (placed by `xb`, translating by `vb`), any pair of 2D shape types; see `gjk_shape_cast`.
/// Swapping A and B gives the same t and point and the flipped normal. Throws InvalidInput if a
/// transform or velocity is not finite (shapes must come from the make_* functions).
template <Shape2DType A, Shape2DType B>
[[nodiscard]] ShapeCastResult shape_cast(const A& a, const Transform& xa, Vec2 va, const B& b,
                                         const Transform& xb, Vec2 vb) {
  check_cast_input(xa, va, xb, vb);
  return gjk_shape_cast<2>(ConvexProxy(a), xa, va, ConvexProxy(b), xb, vb);
}

/// `shape_cast` for two polygons. Sharp polygons of up to 8 vertices each take the ray into
/// A - B without building it: Cyrus-Beck clipping by both polygons' edge normals, which are
/// exactly A - B's (Ericson, Real-Time Collision Detection, 5.3.8): the exact time of first
/// touch (up to rounding), with the contact point in the middle of the touching features as
/// in `shape_cast_minkowski`, and `iterations` 0. Rounded or larger polygons, and answers
/// within the cast tolerance of another (touching at the start, grazing), take
/// `gjk_shape_cast`. Throws InvalidInput if a transform or velocity is not finite.
[[nodiscard]] ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va,
                                         const Polygon& b, const Transform& xb, Vec2 vb);

/// `shape_cast` for a circle and a polygon (either order): the ray from the circle's centre
/// into the polygon grown by the circle's radius, which is the Minkowski difference (Ericson,
/// Real-Time Collision Detection, 5.3.8 into the pushed-out edges, 5.3.2 at the corners'
/// discs): exact up to rounding, `iterations` 0. A start touching or near touching (the centre
/// within the polygon of edges pushed out by the radii) takes `gjk_shape_cast`. Throws
/// InvalidInput if a transform or velocity is not finite.
[[nodiscard]] ShapeCastResult shape_cast(const Circle& a, const Transform& xa, Vec2 va,
                                         const Polygon& b, const Transform& xb, Vec2 vb);
/// `shape_cast` for a polygon and a circle: the circle-polygon cast with the normal flipped.
[[nodiscard]] ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va,
                                         const Circle& b, const Transform& xb, Vec2 vb);

/// `shape_cast` for a capsule and a polygon (either order): the ray along the capsule's motion
/// relative to the polygon into the polygon minus the capsule's segment (a polygon of up to two
/// more edges, built on the stack) grown by both radii: the Minkowski difference, rounded
/// (Ericson, Real-Time Collision Detection, 5.3.8 and 5.3.2; the sum of a polygon and a
/// segment, de Berg et al., Computational Geometry, 13.3). Exact up to rounding, `iterations`
/// 0. A start touching or near touching (within the difference's edges pushed out by the
/// radii) takes `gjk_shape_cast`. Throws InvalidInput if a transform or velocity is not finite.
[[nodiscard]] ShapeCastResult shape_cast(const Capsule& a, const Transform& xa, Vec2 va,
                                         const Polygon& b, const Transform& xb, Vec2 vb);
/// `shape_cast` for a polygon and a capsule: the capsule-polygon cast with the normal flipped.
[[nodiscard]] ShapeCastResult shape_cast(const Polygon& a, const Transform& xa, Vec2 va,
                                         const Capsule& b, const Transform& xb, Vec2 vb);

/// `shape_cast` for shapes whose types are known only at run time (the query tool's `toi`).
[[nodiscard]] ShapeCastResult shape_cast(const Shape2D& a, const Transform& xa, Vec2 va,
                                         const Shape2D& b, const Transform& xb, Vec2 vb);

/// The explicit path for polygons: builds the Minkowski difference A - B (world space, radius
/// ra + rb) with `minkowski_difference` and casts the ray from the origin along vb - va into it
/// with `raycast` (the lesson's picture, literally). Same result fields as `gjk_shape_cast`
/// (iterations 0); the contact point is the middle of the shapes' touching features (vertex
/// against edge: the vertex; edge against edge: the middle of the shared part). When the
/// shapes overlap at t = 0 it reports status overlapped, t 0, and no point or normal. Allocates:
/// a reference and a picture-maker, not for the hot path. Throws InvalidInput if a transform or
/// velocity is not finite, or A - B has more than kMaxPolygonVertices vertices.
[[nodiscard]] ShapeCastResult shape_cast_minkowski(const Polygon& a, const Transform& xa, Vec2 va,
                                                   const Polygon& b, const Transform& xb,
                                                   Vec2 vb);

/// Time of first touch of 3D shape A (placed by `xa`, translating by `va` over the step) and
/// shape B (placed by `xb`, translating by `vb`), any pair of convex 3D shape types: the GJK
/// ray cast into A - B of `gjk_shape_cast`. Swapping A and B gives the same fraction and point
/// and the flipped normal. Throws InvalidInput if a transform or velocity is not finite or a
/// rotation is not unit length (shapes must come from the make_* functions).
template <Shape3DType A, Shape3DType B>
[[nodiscard]] ShapeCastResult3 shape_cast(const A& a, const Transform3& xa, Vec3 va, const B& b,
                                          const Transform3& xb, Vec3 vb) {
  check_cast_input(xa, va, xb, vb);
  return gjk_shape_cast<3>(ConvexProxy3(a), xa, va, ConvexProxy3(b), xb, vb);
}

/// `shape_cast` for 3D shapes whose types are known only at run time.
[[nodiscard]] ShapeCastResult3 shape_cast(const Shape3D& a, const Transform3& xa, Vec3 va,
                                          const Shape3D& b, const Transform3& xb, Vec3 vb);

/// Time of first touch of convex shape A (placed by `xa`, translating by `va` over the step)
/// and the mesh (placed by `xm`, translating by `vm`), the earliest over its triangles, with
/// the `shape_cast` result fields (normal from A to the mesh); `triangle` (optional) receives
/// the triangle hit (UINT32_MAX when none). Convex first; the overloads below take the mesh
/// first.
///
/// Method (src/ccd/mesh_shape_cast.cpp): A's bounding box in the mesh's stored frame is swept
/// along the relative translation through the BVH (`TriangleBvh::box_cast`), nearer boxes first;
/// each triangle whose box it meets takes the GJK ray cast of `gjk_shape_cast` (van den Bergen
/// 2004), and the earliest hit so far clips the sweep, so boxes entered later are never opened.
/// A shape touching the mesh at the start reports overlapped at fraction 0. Allocates nothing.
/// Throws InvalidInput as `shape_cast` (naming "xa", "va", "xb" for the mesh's transform, "vb").
template <ConvexShape3DType A>
[[nodiscard]] ShapeCastResult3 shape_cast(const A& a, const Transform3& xa, Vec3 va,
                                          const TriangleMesh& mesh, const Transform3& xm, Vec3 vm,
                                          std::uint32_t* triangle = nullptr);

/// The same against a height field placed by `xf` moving by `vf`: the cells under A's box
/// swept over the step are the candidates (holes have none); a candidate whose box A's box,
/// swept only up to the best fraction so far, does not meet is skipped.
template <ConvexShape3DType A>
[[nodiscard]] ShapeCastResult3 shape_cast(const A& a, const Transform3& xa, Vec3 va,
                                          const HeightField& field, const Transform3& xf, Vec3 vf,
                                          std::uint32_t* triangle = nullptr);

/// `shape_cast` with the mesh first: the same fraction and point, the normal flipped.
template <ConvexShape3DType B>
[[nodiscard]] ShapeCastResult3 shape_cast(const TriangleMesh& mesh, const Transform3& xm, Vec3 vm,
                                          const B& b, const Transform3& xb, Vec3 vb,
                                          std::uint32_t* triangle = nullptr) {
  ShapeCastResult3 r = shape_cast(b, xb, vb, mesh, xm, vm, triangle);
  r.normal = -r.normal;
  return r;
}
/// `shape_cast` with the height field first: the same fraction and point, the normal flipped.
template <ConvexShape3DType B>
[[nodiscard]] ShapeCastResult3 shape_cast(const HeightField& field, const Transform3& xf, Vec3 vf,
                                          const B& b, const Transform3& xb, Vec3 vb,
                                          std::uint32_t* triangle = nullptr) {
  ShapeCastResult3 r = shape_cast(b, xb, vb, field, xf, vf, triangle);
  r.normal = -r.normal;
  return r;
}

}  // namespace collide
