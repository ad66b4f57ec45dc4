#pragma once
/// @file
/// Closest points on segments: of a segment to a point, and of two segments to each other
/// (Ericson, Real-Time Collision Detection, 5.1.2 and 5.1.9). Internal to the narrow phase:
/// the analytic overlap tests of circles, capsules and segments are built on these, and any
/// other narrow-phase code that needs closest points of segments should use them too.

#include <collide/core/aabb.hpp>

namespace collide::detail {

/// Closest point of segment [p, q] to a point, in D dimensions.
template <int D>
struct PointSegmentClosest {
  float t = 0.0f;              ///< fraction along p -> q, [0, 1]
  VecN<D> point{0.0f};         ///< p + t (q - p)
  float distance_squared = 0;  ///< squared distance from the query point to `point`
};

/// Closest point of the segment [p, q] to `x`: project, then clamp the fraction to [0, 1].
/// A segment of zero length is treated as the point p. Ericson 5.1.2.
template <int D>
[[nodiscard]] PointSegmentClosest<D> closest_on_segment(VecN<D> x, VecN<D> p, VecN<D> q) noexcept;

/// Closest points of two segments, in D dimensions.
template <int D>
struct SegmentSegmentClosest {
  float s = 0.0f;              ///< fraction along the first segment, [0, 1]
  float t = 0.0f;              ///< fraction along the second segment, [0, 1]
  VecN<D> point1{0.0f};        ///< closest point on the first segment
  VecN<D> point2{0.0f};        ///< closest point on the second segment
  float distance_squared = 0;  ///< |point2 - point1|^2
};

/// Closest points of segments [p1, q1] and [p2, q2]: minimise |(p1 + s d1) - (p2 + t d2)|^2
/// over the unit square by solving for s, clamping, recomputing t for the clamped s and
/// clamping again (Ericson 5.1.9). Parallel segments take s = 0 (any pair on the overlap is
/// equally close); zero-length segments are treated as points. If the segments cross, the
/// distance is zero up to rounding.
template <int D>
[[nodiscard]] SegmentSegmentClosest<D> closest_between_segments(VecN<D> p1, VecN<D> q1,
                                                                VecN<D> p2, VecN<D> q2) noexcept;

}  // namespace collide::detail
