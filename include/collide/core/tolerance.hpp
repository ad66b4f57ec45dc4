#pragma once
/// @file
/// Named tolerances. Geometry in collide is in "world units" (metres or pixels, the caller's
/// choice); tolerances that must scale with the scene are relative to a shape's size and say so.

#include <limits>

namespace collide {

/// Relative tolerance of single-precision geometry: results are exact to about this fraction of
/// the size of the shapes involved (the query spec promises 1e-4 of the scene's size).
inline constexpr float kRelativeTolerance = 1e-5f;

/// Two polygon vertices closer than this fraction of the polygon's size are the same vertex.
inline constexpr float kWeldTolerance = 1e-5f;

/// A polygon whose area is below this fraction of its squared size is degenerate (collinear).
inline constexpr float kDegenerateAreaTolerance = 1e-6f;

/// Smallest squared length a direction is taken from: the smallest normal float. Below it the
/// vector has underflowed to denormals (its digits lost) or to zero, and a unit vector made from
/// it is noise, infinite or NaN. A ray cast that enters a round piece dead on within rounding of
/// its centre (a tiny radius, or a ray from far away) faces the ray instead.
inline constexpr float kMinDirectionLengthSquared = std::numeric_limits<float>::min();

/// Contact points within this fraction of the shapes' size of each other are merged.
inline constexpr float kContactMergeTolerance = 1e-4f;

/// GJK stops when the distance improves by less than this fraction of the current distance
/// (van den Bergen 2003, 4.3.4).
inline constexpr float kGjkRelativeTolerance = 1e-6f;

/// GJK iteration cap: far above what convex polygons of kMaxPolygonVertices need.
inline constexpr int kGjkMaxIterations = 40;

/// When deciding which polygon provides the reference face, prefer A unless B's separation is
/// larger by this fraction of the shapes' size: keeps the choice stable across frames
/// (Catto, "Contact Manifolds", GDC 2007).
inline constexpr float kReferenceFaceTolerance = 1e-3f;

/// Faces closer to parallel than this sine of angle are treated as parallel.
inline constexpr float kParallelTolerance = 1e-4f;

/// 3D contact: an edge-edge axis is chosen over the best face axis only when its separation is
/// larger by this fraction of the smaller shape's size (Gregorius, "The Separating Axis Test
/// between Convex Polyhedra", GDC 2013, prefers faces the same way): faces give several stable
/// points, edges one.
inline constexpr float kEdgeContactTolerance = 1e-3f;

/// 3D contact of cores that are apart (rounded shapes, speculative contact): when the normal
/// between their closest points is within this sine of angle of a face normal, the face makes
/// the contact (clipped, up to 4 points); otherwise the closest points make one point.
inline constexpr float kFaceContactSine = 0.05f;

}  // namespace collide
