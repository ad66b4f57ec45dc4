#pragma once
// A signed distance field as a static piece of the world, 2D and 3D (StaticDefN::fields): the
// world meets it through the field's own queries (sdf/distance_field.hpp), the field placed by
// its static's transform (any rigid transform: a query moves into the field's frame and its
// answer back). One look-up per sample point: a body's contact samples its surface, a ray
// sphere-traces, a point samples once. Written once for both dimensions and both field kinds.

#include "world_dim.hpp"

#include <collide/sdf/distance_field.hpp>
#include <collide/world/world.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>

namespace collide::detail {

/// The interpolated field's Lipschitz constant: node values are distances (at most one voxel
/// apart per voxel along an axis), so each component of the multilinear interpolant's gradient
/// is at most 1 and its length at most sqrt(D). A point whose sample is s > 0 is at least
/// s / sqrt(D) from every point the field calls solid: the lower bound the static clearance and
/// the conservative advancement stand on.
template <int D>
inline constexpr float kFieldLipschitz = D == 2 ? 1.41421356f : 1.73205081f;

/// Conservative advancement against a field (field_impact) creeps by at most this fraction of a
/// voxel of motion of any point of the piece once its bounding circle or sphere may touch the
/// solid, testing the piece's sampled contact at each stop: the samples the field's `contact`
/// takes are at most a voxel apart, so no solid thicker than this can be stepped over.
inline constexpr float kFieldToiCreepVoxels = 0.25f;
/// Most stops of the conservative advancement; beyond, it answers `max_iterations` at the last
/// stop known clear.
inline constexpr int kFieldToiMaxSteps = 256;
/// Halvings of the last creep step once a stop touches: the impact is then placed within
/// 1/2^this of a creep step (under a hundredth of a voxel) after the last pose known clear.
inline constexpr int kFieldToiBisections = 5;
/// A laser reflected by a field starts this many voxels off its surface (along the normal):
/// beyond sphere tracing's hit threshold (kRaymarchHitVoxels), so the reflected ray does not
/// stop where it starts, yet far below the field's own error (about a voxel).
inline constexpr float kFieldLaserOffsetVoxels = 4.0f * kRaymarchHitVoxels;

/// The sweep type of a dimension (2D: two angles; 3D: a rotation vector).
template <int D>
using SweepN = std::conditional_t<D == 2, Sweep, Sweep3>;

/// A static's piece as the step and the queries meet it: one of its shapes, or one of its
/// fields (exactly one pointer is set).
template <int D>
struct StaticPieceRefN {
  const StaticShapeN<D>* shape = nullptr;  ///< a shape piece
  const StaticFieldN<D>* field = nullptr;  ///< a field piece
};

/// True for a null field pointer (add_static refuses it).
template <int D>
[[nodiscard]] bool is_null_field(const StaticFieldN<D>& field) noexcept;
/// The voxel size of the field (world units).
template <int D>
[[nodiscard]] float field_voxel(const StaticFieldN<D>& field) noexcept;
/// The box of the field's solid in its own frame: the cells with a node at or below 0 (the only
/// ones where the interpolated field reaches 0), widened where the solid meets the grid's edge
/// by the depth there (a sample beyond the grid is the edge's value plus the distance to it).
/// False when no node is at or below 0 (a field without a solid).
template <int D>
[[nodiscard]] bool field_solid_box(const StaticFieldN<D>& field, AabbN<D>& box_out);
/// The box around `box` (field frame) placed by `xf`, world space.
template <int D>
[[nodiscard]] AabbN<D> placed_box(const AabbN<D>& box, const TransformN<D>& xf) noexcept;

/// The field sampled at world point `p` (field placed by `xf`): the signed distance, negative
/// inside the solid.
template <int D>
[[nodiscard]] float field_sample(const StaticFieldN<D>& field, const TransformN<D>& xf, VecN<D> p) noexcept;
/// Contact of body shape `a` (placed by `xa`) with the field's solid (placed by `xb`): the
/// field's `contact` (sampling A's surface) in the field's frame, brought back to world space.
/// Normal from A into the solid, as every body-static contact.
template <int D>
[[nodiscard]] ManifoldN<D> field_contact(const BodyShapeN<D>& a, const TransformN<D>& xa,
                                         const StaticFieldN<D>& field, const TransformN<D>& xb) noexcept;
/// Overlap of body shape `a` (placed by `xa`) with the field's solid: a sample of its surface
/// touches (field_contact), or a node of the solid lies inside it (a query box around a whole
/// rock; the nodes within A's box are visited, so a big A costs its box's nodes).
template <int D>
[[nodiscard]] bool field_overlap(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticFieldN<D>& field,
                                 const TransformN<D>& xb) noexcept;
/// How deep body shape `a` is in the field's solid, for the independent check: the deepest
/// sample of its surface (field_contact) or its bounding centre's depth, whichever is deeper (a
/// body wholly inside a thick solid counts by its centre too). 0 when clear.
template <int D>
[[nodiscard]] float field_depth(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticFieldN<D>& field,
                                const TransformN<D>& xb) noexcept;
/// Time of impact of body piece `a` moving along `sweep` with the still field placed by `xb`,
/// by conservative advancement (Mirtich 1996; the world's other statics use the GJK-based
/// `time_of_impact`): while the piece's bounding circle or sphere is clear of the solid (a
/// lower bound of its centre's distance, field_distance, beyond the radius), advance by that gap over the
/// bound on any point's motion per unit fraction (translation plus turn times reach); closer,
/// creep by kFieldToiCreepVoxels and test the sampled contact at each stop, then bisect the last
/// step kFieldToiBisections times between clear and touching. The same contract
/// as `time_of_impact`: `overlapped` (fraction 0) when touching at the start, with the
/// contact's normal; `hit` at the last pose known clear before the first touching one, with
/// the touching contact's normal (A to B) and point; `max_iterations` after kFieldToiMaxSteps
/// stops (fraction: clear up to there); else `separated`. `queries` counts the sampled
/// contacts taken.
template <int D>
[[nodiscard]] ToiResultN<D> field_impact(const BodyShapeN<D>& a, const SweepN<D>& sweep,
                                         const StaticFieldN<D>& field, const TransformN<D>& xb,
                                         std::int64_t& queries) noexcept;
/// Shape cast of `a` (placed by `xa`, translating by `v`) against the field: field_impact on the
/// translation, as a ShapeCastResult (hit for `hit` and `overlapped`).
template <int D>
[[nodiscard]] ShapeCastResultN<D> field_shape_cast(const BodyShapeN<D>& a, const TransformN<D>& xa, VecN<D> v,
                                                   const StaticFieldN<D>& field, const TransformN<D>& xb) noexcept;
/// Ray cast against the field by sphere tracing (`raymarch`) in its frame, from where the ray
/// enters the grid's box (beyond the grid the sample overestimates the distance, and a step by
/// it can jump over a corner of the solid); normal outward.
template <int D>
[[nodiscard]] RayHitN<D> field_raycast(const StaticFieldN<D>& field, const TransformN<D>& xb, const RayN<D>& ray) noexcept;
/// A lower bound of the distance from world point `p` to the field's solid (in the grid the
/// sample over kFieldLipschitz, negative inside; beyond it see distance_bound in the source),
/// at most `cap`.
template <int D>
[[nodiscard]] float field_distance(const StaticFieldN<D>& field, const TransformN<D>& xb, VecN<D> p, float cap) noexcept;
/// How far off a field's surface a reflected laser starts (kFieldLaserOffsetVoxels).
template <int D>
[[nodiscard]] float field_laser_offset(const StaticFieldN<D>& field) noexcept;
/// Draws the field placed by `xf`: 2D its zero contour (marching squares over the nodes, one
/// segment per cell crossing); 3D the edges of its solid's box.
template <int D>
void draw_field(DebugDrawN<D>& draw, const StaticFieldN<D>& field, const TransformN<D>& xf, DrawRole role);

// ---- a static piece, shape or field ------------------------------------------------------------
// Each call below sends a shape piece to its world_dim.hpp overload and a field piece to the
// field's, so the step and the queries are written once for both kinds of piece.

/// piece_contact for a shape or a field piece.
template <int D>
[[nodiscard]] ManifoldN<D> piece_contact(const BodyShapeN<D>& a, const TransformN<D>& xa,
                                         const StaticPieceRefN<D>& b, const TransformN<D>& xb) noexcept {
  return b.field != nullptr ? field_contact<D>(a, xa, *b.field, xb) : piece_contact(a, xa, *b.shape, xb);
}
/// The depth the independent check measures (a shape: its contact's deepest point).
template <int D>
[[nodiscard]] float piece_depth(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticPieceRefN<D>& b,
                                const TransformN<D>& xb) noexcept {
  return b.field != nullptr ? field_depth<D>(a, xa, *b.field, xb) : piece_contact(a, xa, *b.shape, xb).max_depth();
}
/// piece_impact for a shape or a field piece.
template <int D>
[[nodiscard]] ToiResultN<D> piece_impact(const BodyShapeN<D>& a, const SweepN<D>& sweep, const AabbN<D>& box,
                                         const StaticPieceRefN<D>& b, const TransformN<D>& xb,
                                         std::int64_t& queries) {
  return b.field != nullptr ? field_impact<D>(a, sweep, *b.field, xb, queries)
                            : piece_impact(a, sweep, box, *b.shape, xb, queries);
}
/// piece_raycast for a shape or a field piece.
template <int D>
[[nodiscard]] RayHitN<D> piece_raycast(const StaticPieceRefN<D>& b, const TransformN<D>& xb,
                                       const RayN<D>& ray) noexcept {
  return b.field != nullptr ? field_raycast<D>(*b.field, xb, ray) : piece_raycast(*b.shape, xb, ray);
}
/// piece_shape_cast for a shape or a field piece.
template <int D>
[[nodiscard]] ShapeCastResultN<D> piece_shape_cast(const BodyShapeN<D>& a, const TransformN<D>& xa, VecN<D> v,
                                                   const StaticPieceRefN<D>& b, const TransformN<D>& xb) noexcept {
  return b.field != nullptr ? field_shape_cast<D>(a, xa, v, *b.field, xb) : piece_shape_cast(a, xa, v, *b.shape, xb);
}
/// piece_overlap for a shape or a field piece (field_overlap).
template <int D>
[[nodiscard]] bool piece_overlap(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticPieceRefN<D>& b,
                                 const TransformN<D>& xb) noexcept {
  return b.field != nullptr ? field_overlap<D>(a, xa, *b.field, xb) : piece_overlap(a, xa, *b.shape, xb);
}
/// static_distance for a shape or a field piece.
template <int D>
[[nodiscard]] float static_distance(const StaticPieceRefN<D>& b, const TransformN<D>& xb, VecN<D> p,
                                    float cap) noexcept {
  return b.field != nullptr ? field_distance<D>(*b.field, xb, p, cap) : static_distance(*b.shape, xb, p, cap);
}

}  // namespace collide::detail
