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
#include <collide/core/transform3.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <cstdint>
#include <span>

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

/// One pair of a batched polygon-circle `contact`: the shapes by pointer (not copied; they must
/// outlive the call) and their placements. A is the polygon, B the circle.
struct PolygonCirclePair {
  const Polygon* polygon = nullptr;  ///< A (a valid polygon, as `contact` takes)
  Transform polygon_xf{};            ///< A's placement, world space
  const Circle* circle = nullptr;    ///< B
  Transform circle_xf{};             ///< B's placement, world space
};

/// The manifolds of many polygon-circle pairs: `manifolds[i]` is `contact(*pairs[i].polygon,
/// pairs[i].polygon_xf, *pairs[i].circle, pairs[i].circle_xf)`, bit for bit (normal from the
/// polygon to the circle, world space, one point). For a game's many small shapes against
/// level tiles (particles, bullets, debris): the same steps as the single call (the edge of
/// greatest separation, then the Voronoi region of the centre; Ericson 5.2.7), worked for four
/// pairs side by side in SIMD lanes, every branch of the single call a select, so a stream of
/// unrelated pairs costs no mispredicted branches and one pair's long chain of dependent steps
/// overlaps three others'. Pairs are taken four at a time; the rest (fewer than four) one by
/// one. Any polygon size up to kMaxPolygonVertices (a group runs as many edge steps as its
/// largest polygon has edges).
///
/// Writes min(pairs.size(), manifolds.size()) manifolds (a shorter output span is a caller's
/// error, caught by COLLIDE_ASSERT in debug builds). Pointers must be non-null and shapes and
/// transforms valid, as for `contact`. Allocates nothing, throws nothing.
void contact(std::span<const PolygonCirclePair> pairs, std::span<Manifold> manifolds) noexcept;

/// The contact manifold between 3D shape A placed by `xa` and shape B placed by `xb`: normal
/// unit from A to B (world space), up to 4 world points midway between the surfaces, each with
/// its depth along the normal and the features that made it (ContactId; box, hull and triangle
/// numbering in manifold.hpp). Empty when the shapes are apart by more than `margin`.
///
/// `margin` (world units, >= 0; negative counts as 0): shapes apart by less than it get
/// speculative points with negative depth (minus the gap), as a solver wants for stable
/// stacking and fast approach; 0 reports only touching or overlapping shapes (touching exactly:
/// depth 0, within float rounding of the coordinates).
///
/// Method (src/narrow/contact3.cpp): cores that overlap get the separating axis test over the
/// face normals of both and the edge pairs pruned by the Gauss map (Gregorius, "The Separating
/// Axis Test between Convex Polyhedra", GDC 2013): a face axis clips the other shape's most
/// anti-parallel face against the reference face's side planes (Sutherland & Hodgman 1974), an
/// edge axis gives the closest points of the two edges. Rounded shapes whose cores are apart
/// get the normal from GJK's closest points (a sphere or capsule against a triangle: the core's
/// closest points in closed form, Ericson 5.1.10), and a face contact where a face faces along it.
/// More than 4 points are reduced to the deepest and the three that span the largest area.
/// Swapping A and B gives the reversed manifold up to the choice of reference face. Works in
/// A's frame (B moved there once). Allocates nothing; shapes must be valid and transforms
/// finite with unit quaternions (COLLIDE_ASSERT).
template <Shape3DType A, Shape3DType B>
[[nodiscard]] Manifold3 contact(const A& a, const Transform3& xa, const B& b,
                                const Transform3& xb, float margin = 0.0f) noexcept;

/// `contact` for 3D shapes of types known only at run time.
[[nodiscard]] Manifold3 contact(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                                const Transform3& xb, float margin = 0.0f) noexcept;

/// 3D `contact` of two polyhedra (boxes, hulls, triangles) whose edge test would cost more
/// than this many edge pairs takes its axis from GJK and EPA (epa.hpp) and keeps EPA's normal
/// and depth; cheaper pairs take the exact separating axis test, which prefers a face axis to
/// an edge axis within kEdgeContactTolerance (a steadier manifold for resting contacts). The
/// edge test's cost is the product of the two edge counts, each pair pruned on the Gauss map
/// (Gregorius 2013): two solids' pairs count one each, and pairs that are not pruned (a
/// triangle against a triangle or a segment) count the two cores' vertex count each. Box-box
/// (144) keeps the SAT, two 30-point hulls (about 7000 pairs) take EPA. A box or a hull against
/// a triangle (a level's) always takes the SAT: one pass over the solid's edges finds those on
/// its silhouettes along the triangle's edges (sign bits of the face normals, four faces at a
/// time), and the hull's faces are tested four at a time; a hull of 24, 64 and 256 points in a
/// ball on dungeon.obj cost 83k, 141k and 279k instructions per level contact against
/// EPA's 147k, 175k and 386k (callgrind; 27 against 35 us, 49 against 74 us). Where the face
/// clip leaves out the solid's deepest vertex (a small hull face over a large triangle), the
/// vertex joins the manifold when its axis is the minimum translation. Chosen by bench_narrow3
/// on the shared real hulls and bench_narrow_mesh on dungeon.obj.
inline constexpr int kSatEdgePairLimit = 256;

/// Points of triangles whose normals are within this cosine (30 degrees) of the deepest
/// triangle's normal join its manifold in `contact` against a mesh or height field; the others
/// are left out (a body in a corner gets the deepest surface; visit every triangle's manifold
/// with the callback overload to see them all).
inline constexpr float kLevelContactMergeCos = 0.866025404f;

/// Most candidate points `contact` against a level holds before it reduces them: a shape over
/// many small triangles has its points reduced to 4 whenever this many have gathered.
inline constexpr int kMaxLevelContactPoints = 64;

/// Called by the per-triangle `contact` with each triangle that touches A (within the margin)
/// and its manifold (world space, as the merged `contact` reports it). Return true to go on,
/// false to stop.
using TriangleContactCallback = FunctionRef<bool(std::uint32_t triangle, const Manifold3& m)>;

/// The contact between convex shape A placed by `xa` and the mesh placed by `xm`: one manifold
/// of up to 4 world points, normal unit from A to the mesh, depths along it, empty when apart
/// by more than `margin` (as convex-convex `contact`). Convex first; the overloads below take the
/// mesh first and report the reversed manifold.
///
/// Method (src/narrow/mesh_query.cpp): A's bounding box grown by the margin, in the mesh's
/// stored frame, queries the BVH; each triangle it meets gets the convex-triangle contact of
/// contact3.cpp, corrected for active edges (TriangleMesh::active_edges): a normal that comes
/// from an edge inactive from A's side, or from a vertex whose edges are all inactive from it,
/// is replaced by the triangle's face contact (the face looking at A), so a body sliding over
/// the seams of a surface flat or concave from its side (either side: an edge concave from the
/// front is convex from behind) never meets a tilted "ghost" normal (the idea of Jolt's ActiveEdges and
/// Bullet's btAdjustInternalEdgeContacts). Then the normal of the deepest point is the
/// manifold's; points of triangles whose normal is within kLevelContactMergeCos of it join
/// with their depth along it (depth / cos), points closer than kContactMergeTolerance of A's
/// size to a deeper one are merged, and the rest are reduced to 4 as convex contact does.
///
/// Feature ids: B's (the mesh's) features are named globally (DESIGN.md): vertex = mesh vertex
/// index, edge 3 * triangle + k, face = triangle index, so ids stay stable across frames while
/// the same triangles touch. Triangles are two-sided. Allocates nothing.
template <ConvexShape3DType A>
[[nodiscard]] Manifold3 contact(const A& a, const Transform3& xa, const TriangleMesh& mesh,
                                const Transform3& xm, float margin = 0.0f) noexcept;

/// The same against a height field placed by `xf` (its cell query; active edges from the
/// neighbouring cells, HeightField::active_edges; vertex ids are sample indices).
template <ConvexShape3DType A>
[[nodiscard]] Manifold3 contact(const A& a, const Transform3& xa, const HeightField& field,
                                const Transform3& xf, float margin = 0.0f) noexcept;

/// Every triangle's own manifold (active edges applied), unmerged, to `visit`: a body touching
/// several surfaces at once (a floor and a wall) sees each.
template <ConvexShape3DType A>
void contact(const A& a, const Transform3& xa, const TriangleMesh& mesh, const Transform3& xm,
             float margin, TriangleContactCallback visit) noexcept;

/// Every triangle's own manifold against a height field.
template <ConvexShape3DType A>
void contact(const A& a, const Transform3& xa, const HeightField& field, const Transform3& xf,
             float margin, TriangleContactCallback visit) noexcept;

/// `contact` with the mesh first: the reversed manifold (normal from the mesh to B).
template <ConvexShape3DType B>
[[nodiscard]] Manifold3 contact(const TriangleMesh& mesh, const Transform3& xm, const B& b,
                                const Transform3& xb, float margin = 0.0f) noexcept {
  return reversed(contact(b, xb, mesh, xm, margin));
}
/// `contact` with the height field first: the reversed manifold.
template <ConvexShape3DType B>
[[nodiscard]] Manifold3 contact(const HeightField& field, const Transform3& xf, const B& b,
                                const Transform3& xb, float margin = 0.0f) noexcept {
  return reversed(contact(b, xb, field, xf, margin));
}

}  // namespace collide
