#pragma once
/// @file
/// The asset-pipeline step of the lesson's "Valid Spaces": from a level mesh, the walk mesh of
/// the places an agent can stand. A triangle is kept when its slope is walkable for the agent and
/// nothing of the level comes within the agent's height above it.

#include <collide/walkmesh/walk_mesh.hpp>

namespace collide {

/// Headroom tests treat geometry within this fraction of the level's size (at most
/// kWalkScaleMedianEdges median edge lengths, see WalkMeshOptions::tolerance_scale) of the space
/// above a triangle as touching, not blocking (walls standing on its edges, its neighbours).
inline constexpr float kHeadroomTolerance = 1e-5f;

/// A level triangle partly under an obstacle is split until its pieces are smaller than this
/// fraction of the agent's height; pieces with headroom are kept.
inline constexpr float kHeadroomRefineFraction = 0.25f;
/// Most rounds of four-way splitting of one level triangle for headroom (4^6 = 4096 pieces).
inline constexpr int kMaxHeadroomRefineDepth = 6;

/// The walking agent a walk mesh is made for.
struct WalkAgent {
  float max_slope = 0.785398f;  ///< steepest walkable slope, radians from horizontal, [0, pi/2)
  float height = 2.0f;          ///< free space needed above the ground, world units, >= 0
  Vec3 up{0.0f, 1.0f, 0.0f};    ///< up direction of the level (OBJ levels are usually +y up)
};

/// Filters a level to the triangles the agent can stand on, then builds the walk mesh from them
/// with `build_walk_mesh` (welded and cleaned, wound counter-clockwise seen from `agent.up`):
///  - slope: the triangle's plane is within `max_slope` of horizontal. Either winding counts
///    (levels wind inconsistently), so the underside of a thin floor is the same floor.
///  - headroom: no triangle of the level meets the prism swept by the triangle moved up by
///    `height` (exact separating-axis test of prism against triangle, Ericson 5.2.1 / 4.4, in
///    double on world coordinates; touching within kHeadroomTolerance does not count). A triangle that fails is split in four
///    at its edge midpoints, recursively, keeping the pieces that pass, down to pieces of
///    kHeadroomRefineFraction of the agent's height (kMaxHeadroomRefineDepth rounds at most):
///    the walk mesh follows obstacles to that resolution (no exact clipping).
/// Degenerate level triangles (no area: kWalkDegenerateTolerance) have no slope and are dropped
/// first. A piece of the level far from the rest changes nothing else (the tolerances and the
/// local origin are robust to it), unless it is so far that float precision cannot hold both
/// (kWalkPrecisionFraction): then InvalidInput. The stats count the level triangles degenerate, too steep, with some part dropped for
/// headroom, and split. Throws InvalidInput for what `validate_triangle_soup` rejects, a bad agent
/// field (named), or no walkable triangle (saying how many were too steep, degenerate, covered).
[[nodiscard]] WalkMesh make_walk_mesh(const TriangleSoup& level, const WalkAgent& agent = {});

}  // namespace collide
