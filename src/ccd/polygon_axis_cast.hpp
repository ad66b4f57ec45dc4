#pragma once
/// @file
/// The separating-axis cast of two translating sharp polygons (the lesson's ray into the
/// Minkowski difference, clipped by its edges' half-planes), shared by `shape_cast` (stop at
/// touching) and `time_of_impact` (stop at a target separation). Internal.

#include <collide/shape/polygon.hpp>

namespace collide::detail {

/// Largest polygons the separating-axis cast takes: O(n m) work, cheaper than GJK's iterations
/// up to here (the size Box2D v3 caps polygons at); larger ones take GJK.
inline constexpr int kAxisCastMaxVertices = kInlinePolygonVertices;

/// What `polygon_axis_cast` found.
enum class AxisCastEnd {
  undecided,  ///< not for this method (rounded or large polygons, no relative motion), or the
              ///< answer is within the tolerance of another (start at the stop gap, a graze)
  separated,  ///< the separation stays above `gap` over the whole step
  hit,        ///< the separation first comes down to `gap` at `fraction`
};

/// Result of `polygon_axis_cast`, in A's frame at t = 0.
struct AxisCast {
  AxisCastEnd end = AxisCastEnd::undecided;
  float fraction = 1.0f;  ///< when the separation reaches `gap` (hit), else 1
  Vec2 normal{0.0f};      ///< the axis that closes last, unit, from A to B (hit only)
  Transform b_in_a{};     ///< B's pose in A's frame at t = 0
  Vec2 ray{0.0f};         ///< B's motion relative to A over the step, A's frame
};

/// Sharp polygon A placed by `xa` moving by `va` over the step and sharp polygon B placed by
/// `xb` moving by `vb` (world space, no rotation): the first time t in [0, 1] at which their
/// separation comes down to `gap` (>= 0, world units), by Cyrus-Beck clipping of [0, 1] with
/// the edge normals of A - B, each axis's separation moved by `gap` (Cyrus & Beck 1978;
/// Ericson, Real-Time Collision Detection, 5.3.8 and 5.5). Along those axes the distance is
/// the largest separation only where the closest features include an edge; at a corner of
/// A - B it may be larger at `fraction` (the polygons grown by `gap` with sharp corners touch
/// there), which `time_of_impact` checks. Answers within `tolerance` (world units) of another
/// are `undecided`, left to GJK with its tolerance semantics. Never allocates.
[[nodiscard]] AxisCast polygon_axis_cast(const Polygon& a, const Transform& xa, Vec2 va,
                                         const Polygon& b, const Transform& xb, Vec2 vb, float gap,
                                         float tolerance) noexcept;

}  // namespace collide::detail
