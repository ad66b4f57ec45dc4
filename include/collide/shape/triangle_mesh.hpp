#pragma once
/// @file
/// Static triangle meshes for level geometry: indexed triangles with their BVH, stored relative
/// to a local origin, and the active edges that keep bodies sliding over flat or concave seams
/// from catching on them (no "ghost" contacts at internal edges).

#include <collide/core/aabb.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/triangle.hpp>
#include <collide/shape/triangle_bvh.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Most triangles a TriangleMesh holds: floor(2^30 / 3), so that every feature index of a mesh,
/// edge 3 * triangle + k included, stays below 2^30 (DESIGN.md "Feature ids").
inline constexpr std::size_t kMaxMeshTriangles = (std::size_t{1} << 30) / 3;

/// How `make_triangle_mesh` builds.
struct TriangleMeshOptions {
  /// Cosine of the normals' turning angle above which a convex internal edge is inactive
  /// (kActiveEdgeCosAngle); in [-1, 1]. 1 makes every convex edge with any turn active; -1 makes
  /// only boundary, non-manifold and folded-back edges active.
  float active_edge_cos_angle = kActiveEdgeCosAngle;
};

/// What `make_triangle_mesh` found in its input. Edges are counted once each, between vertices
/// welded where positions are exactly equal.
struct TriangleMeshStats {
  std::size_t input_triangles = 0;       ///< triangles given
  std::size_t degenerate_triangles = 0;  ///< dropped: no area in float (see make_triangle_mesh)
  std::size_t boundary_edges = 0;        ///< edges of one triangle
  std::size_t non_manifold_edges = 0;    ///< edges of three or more triangles
  std::size_t active_edges = 0;          ///< distinct edges active from the front (boundary and non-manifold included)
  std::size_t active_edges_from_behind = 0;  ///< distinct edges active from behind (the same, for concave ones)
};

/// A static triangle mesh in local space ("mesh space", the caller's coordinates), two-sided.
/// Triangle t has corners `vertices[triangles[t][k]]`, k = 0, 1, 2; edge k runs from corner k to
/// corner k + 1 (mod 3); its geometric normal is (c1 - c0) x (c2 - c0).
///
/// Local origin: coordinates are stored relative to `origin` (the per-axis median of the
/// vertices the triangles use), mesh space = origin + vertices[i]. A level mesh far from the
/// world origin (recast's undulating.obj sits at x, z ~ 5000) then keeps float precision in the
/// BVH and in every query, which moves its query into these coordinates first (one subtraction).
///
/// Feature ids (DESIGN.md): vertex i = index into `vertices`; edge 3 * t + k; face t.
///
/// Build meshes with `make_triangle_mesh` (or io::load_triangle_mesh) and treat the fields as
/// read-only afterwards: the BVH and the active edges are computed from them.
struct TriangleMesh {
  Vec3 origin{0.0f};                          ///< mesh space point the stored coordinates are relative to
  std::vector<Vec3> vertices;                 ///< relative to `origin`, all given vertices (used or not)
  std::vector<glm::uvec3> triangles;          ///< the input's non-degenerate triangles, in input order
  /// Per triangle, bits active_edge_bit(k, side) for its active edges, seen from its front (side
  /// 0, bits 0-2) and from behind (side 1, bits 3-5): boundary (one triangle), non-manifold (three
  /// or more) and folded-back (kFoldBackCosAngle) edges from both sides, others from the side
  /// where they are convex when the normals turn by more than the options' angle
  /// (active_edge_sides). Contact generation, for a body on either side, uses only the edges
  /// active from its side with their own normals (and vertices whose edges are all inactive
  /// never push sideways).
  std::vector<std::uint8_t> active_edges;
  /// Input indices of the triangles dropped as degenerate (ascending): triangle t of the mesh is
  /// input triangle t + (the number of these below it), so per-triangle data can be remapped.
  std::vector<std::uint32_t> dropped_triangles;
  TriangleBvh bvh;                            ///< over `triangles`, in the stored (local) coordinates
  TriangleMeshStats stats{};

  [[nodiscard]] std::uint32_t triangle_count() const noexcept { return static_cast<std::uint32_t>(triangles.size()); }
  /// Corner k of triangle t, local (relative to `origin`).
  [[nodiscard]] Vec3 corner(std::uint32_t t, int k) const noexcept { return vertices[triangles[t][k]]; }
  /// True when edge k of triangle t is active seen from `side` (0 its front, 1 behind it).
  [[nodiscard]] bool is_edge_active(std::uint32_t t, int k, int side = 0) const noexcept {
    return (active_edges[t] & active_edge_bit(k, side)) != 0;
  }
};

/// A triangle mesh from indexed triangles (any winding; each triangle's own winding fixes its
/// geometric normal). Vertices are welded where their positions are exactly equal to find the
/// triangles that share an edge (so a soup with three vertices per triangle gets its adjacency),
/// without changing `vertices` or the indices. Triangles with no area in float (the cross product
/// of their local edges has no direction in float: repeated or collinear corners) are dropped,
/// counted in `stats` and listed in `dropped_triangles`, not refused: real levels have them.
/// Active edges: pairs over each edge compare normals; convex means the second normal turns
/// away about the edge direction of the first, (n1 x n2) . e > 0 (the idea of Jolt's
/// ActiveEdges.h and Bullet's btInternalEdgeUtility, written here from the definition). Where
/// the two windings disagree over an edge no side is the outside (convex from one side is
/// concave from the other): such an edge is active unless flat within the threshold.
/// Throws InvalidInput naming the field: "triangle mesh vertex 7: not finite", "triangle mesh
/// triangle 12: vertex index 90 out of range (40 vertices)", more than kMaxMeshTriangles
/// triangles, no triangles, every triangle degenerate, a vertex span beyond float range (no float
/// frame holds it; an unused vertex too: "triangle mesh vertex 9: beyond float range of the
/// triangles' vertices ..."), options.active_edge_cos_angle not in [-1, 1].
[[nodiscard]] TriangleMesh make_triangle_mesh(std::span<const Vec3> vertices, std::span<const glm::uvec3> triangles,
                                              const TriangleMeshOptions& options = {});

/// Bounding box of the mesh placed by `xf`, world space (the rotated local bounds of the
/// triangles: tight for rotations about the axes by multiples of 90 degrees).
[[nodiscard]] Aabb3 compute_aabb(const TriangleMesh& mesh, const Transform3& xf) noexcept;

/// Each triangle of `mesh` placed by `xm` whose bounding box meets `box` (world space), with its
/// corners in world space, through the BVH: the box goes into mesh space as the box of its
/// rotated corners (a rotated mesh sees a larger box, never a smaller one). Stops when `visit`
/// returns false. No allocation. For code that works on a level's triangles one at a time (a
/// world's continuous collision and its independent check).
void for_each_triangle(const TriangleMesh& mesh, const Transform3& xm, const Aabb3& box,
                       TriangleCornersCallback visit);

/// Per-axis median of the vertices `triangles` use (each counted once per corner): a local
/// origin that one piece of a level far from the rest does not drag away (the centre of the
/// bounds would). `triangles` must be non-empty with indices in range.
[[nodiscard]] Vec3 median_vertex(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles);

}  // namespace collide
