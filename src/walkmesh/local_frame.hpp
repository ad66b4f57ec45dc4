#pragma once
// The frame a walk mesh is built in: a local origin (float precision far from the world origin)
// and the length its building tolerances are fractions of (welding, T-junctions, headroom). Both
// are chosen so that one far-away piece of a level (a room kilometres off) does not coarsen the
// rest: the origin is the per-axis median of the vertices, not the centre of their bounds, and
// the length is at most kWalkScaleMedianEdges median edge lengths, not the whole span.

#include <collide/walkmesh/walk_mesh.hpp>

#include <string>

namespace collide::detail {

/// Per-axis median of the vertices the soup's triangles use (world): `median_vertex`, the
/// origin TriangleMesh takes too. The soup must have a triangle.
[[nodiscard]] Vec3 local_origin(const TriangleSoup& soup);

/// Throws InvalidInput naming `name` when the soup's triangles span `size` (largest extent of
/// their bounds) beyond float range (size is infinite: coordinates near +-3.4e38 on both sides),
/// where no float frame holds them: local coordinates would overflow to infinity (issue 15: the
/// infinite boxes then broke the BVH query's stack bound).
void check_float_span(float size, const std::string& name);

/// The tolerance scale of a soup whose triangles span `size` (largest extent of their bounds):
/// min(size, kWalkScaleMedianEdges * median edge length), the median over the non-zero edges of
/// every triangle (`size` when there is none), rounded down to a power of two (a few triangles
/// more or less must not move it). Throws InvalidInput naming `name` when float
/// precision at that size (size * 2^-24, the rounding of local coordinates) is coarser than
/// kWalkPrecisionFraction of the median edge: pieces too far apart for one float frame.
[[nodiscard]] float tolerance_scale(const TriangleSoup& soup, float size, const std::string& name);

}  // namespace collide::detail
