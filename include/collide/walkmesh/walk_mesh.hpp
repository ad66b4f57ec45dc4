#pragma once
/// @file
/// Walk meshes, the lesson's "Valid Spaces": instead of testing a walking player against the
/// level, keep its position on a triangle mesh of valid positions. A 3D question (does the
/// player hit anything?) becomes a 2D one (is the point still in the same triangle, and if not,
/// which neighbour is it in?). The design follows the WalkMesh of CMU 15-466 (McCann), which the
/// lesson leads to, made robust for real level meshes.
///
/// Conventions: a `WalkPoint` names a triangle by its three vertex indices, counter-clockwise
/// seen from the mesh's up side, and barycentric weights of those vertices. "World" means the
/// caller's coordinates; the mesh stores its vertices relative to a local origin (the centre of
/// its bounds) so that meshes far from the origin keep float precision.

#include <collide/core/aabb.hpp>
#include <collide/shape/triangle_bvh.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace collide {

struct WalkAgent;  // make_walk_mesh.hpp

/// No neighbour across this edge: a boundary (wall) of the walk mesh.
inline constexpr std::uint32_t kNoNeighbor = 0xffffffffu;
/// Vertices closer than this fraction of the mesh's size are welded into one. Building's length
/// tolerances (this, T-junctions, headroom) take the size as at most kWalkScaleMedianEdges median
/// edge lengths.
inline constexpr float kWalkWeldTolerance = 1e-5f;
/// The size building tolerances are fractions of is at most this many median edge lengths: a floor
/// kilometres away from the rest of a level must not weld the level at centimetres.
inline constexpr float kWalkScaleMedianEdges = 100.0f;
/// A soup whose float rounding in its local frame (size * 2^-24) exceeds this fraction of its
/// median edge length is refused: its pieces lie too far apart for one float frame.
inline constexpr float kWalkPrecisionFraction = 1e-3f;
/// A triangle whose area is below this fraction of its longest edge squared is degenerate
/// (collinear corners): it has no usable plane and is dropped.
inline constexpr float kWalkDegenerateTolerance = 1e-6f;
/// An island whose area-weighted normal has an up component below this fraction of its area has
/// no clear up side (a closed surface, a wall): it keeps the winding most of its input had.
inline constexpr double kIslandUpTolerance = 1e-3;
/// A barycentric rate smaller than this fraction of the largest rate of a step is zero: a step
/// along an edge keeps the point exactly on that edge.
inline constexpr float kBarycentricRateTolerance = 1e-6f;
/// A walk ends when less than this fraction of the mesh's size is left to walk.
inline constexpr float kWalkLengthTolerance = 1e-7f;
/// Neighbouring normals with 1 + cos(angle) below this are folded back on each other: the
/// rotation over their edge is the half-turn about the edge.
inline constexpr float kFoldBackTolerance = 1e-6f;
/// At a wall, a slide that keeps less than this fraction of the step counts as running straight
/// into the wall: the walk stops there (`WalkStatus::blocked`) instead of creeping along.
inline constexpr float kWallSlideTolerance = 1e-4f;
/// A walk that visits this many triangles in a row without moving (turning around a vertex) stops
/// as blocked: the step points out of the mesh at that vertex.
inline constexpr int kMaxIdleIterations = 64;
/// Two triangles over an edge whose far corners lie in directions with a cosine above this
/// (folded back onto each other within about 2.5 degrees: overlapping geometry) are not linked.
inline constexpr float kFoldBackLinkCos = 0.999f;
/// Passes of T-junction splitting in build_walk_mesh (a pass cuts one unshared edge of each
/// triangle at every vertex on it; a triangle with T-junctions on k edges needs k passes).
inline constexpr int kMaxTJunctionPasses = 16;
/// Most triangles one `walk` visits (edge crossings plus wall slides); a walk that needs more
/// stops and says so (`WalkStatus::iteration_limit`).
inline constexpr int kMaxWalkIterations = 1024;

/// A point on a walk mesh: a triangle and barycentric weights. On an edge the conventional form
/// (as returned by `walk_in_triangle`) has the edge as (indices.x, indices.y) and weights.z == 0.
struct WalkPoint {
  glm::uvec3 indices{0u, 0u, 0u};    ///< vertex indices of the triangle, counter-clockwise from up
  Vec3 weights{1.0f, 0.0f, 0.0f};    ///< barycentric weights of those vertices: >= 0, sum 1
  std::uint32_t triangle = 0;        ///< which triangle of the mesh (indices is a rotation of it)
};

/// A triangle soup: what a level file holds. Any winding, shared or repeated vertices.
struct TriangleSoup {
  std::string name;                      ///< where it came from (file name), used in error messages
  std::vector<Vec3> positions;           ///< vertex positions, world space
  std::vector<glm::uvec3> triangles;     ///< vertex indices per triangle
};

/// How `build_walk_mesh` cleans a soup.
struct WalkMeshOptions {
  Vec3 up{0.0f, 1.0f, 0.0f};               ///< up direction: triangles are wound counter-clockwise seen from it
  float weld_tolerance = kWalkWeldTolerance;  ///< fraction of `tolerance_scale`; 0 welds only equal positions
  /// The length (world units) the weld and T-junction tolerances are fractions of; 0 (the
  /// default) takes the soup's own: its size, at most kWalkScaleMedianEdges median edge lengths,
  /// rounded down to a power of two.
  /// make_walk_mesh passes the level's, so that refined pieces do not shrink it.
  float tolerance_scale = 0.0f;
};

/// What `build_walk_mesh` did to its input, and what the mesh looks like.
struct WalkMeshStats {
  std::size_t input_triangles = 0;       ///< triangles in the soup
  std::size_t triangles = 0;             ///< triangles kept
  std::size_t vertices = 0;              ///< distinct vertices kept (after welding)
  std::size_t welded_vertices = 0;       ///< input vertices merged into an earlier one
  std::size_t degenerate_triangles = 0;  ///< dropped: repeated corner after welding, or no area (make_walk_mesh: level triangles too)
  std::size_t duplicate_triangles = 0;   ///< dropped: same three vertices as an earlier triangle
  std::size_t t_junction_splits = 0;     ///< triangles split where a vertex lay inside an unshared edge
  std::size_t non_manifold_edges = 0;    ///< edges shared by more than two triangles
  std::size_t flipped_triangles = 0;     ///< triangles whose winding was reversed to agree with neighbours and up
  std::size_t orientation_conflicts = 0; ///< links cut because no consistent winding exists (Moebius-like)
  std::size_t boundary_edges = 0;        ///< edges without a neighbour (walls)
  std::size_t islands = 0;               ///< connected pieces
  std::size_t too_steep_triangles = 0;   ///< make_walk_mesh: dropped, steeper than the agent's max slope
  std::size_t low_headroom_triangles = 0;  ///< make_walk_mesh: level triangles with some part dropped, geometry within the agent's height above
  std::size_t headroom_refined_triangles = 0;  ///< make_walk_mesh: level triangles split, with the parts that have headroom kept (partly under an obstacle)
};

/// Result of `walk_in_triangle`.
struct TriangleWalk {
  /// Where the walk stopped. When `hit_edge`, in the conventional edge form: the edge reached is
  /// (indices.x, indices.y) and weights.z == 0 exactly.
  WalkPoint end{};
  float time = 1.0f;      ///< fraction of the step used, [0, 1]; 1 when no edge was reached
  bool hit_edge = false;  ///< the step reached an edge of the triangle before its end
};

/// Result of `cross_edge`.
struct EdgeCrossing {
  /// The same world point, expressed in the neighbouring triangle, in edge form:
  /// indices (y, x, z') for an edge (x, y), weights (w.y, w.x, 0).
  WalkPoint end{};
  /// Rotation about the shared edge that takes the old triangle's normal to the new one's;
  /// apply it to a direction of travel to carry it over the edge.
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
};

/// How a `walk` ended.
enum class WalkStatus {
  completed,        ///< walked the whole step (possibly sliding along walls)
  blocked,          ///< a wall (or corner) absorbed what was left of the step
  iteration_limit,  ///< visited kMaxWalkIterations triangles; stopped on the mesh where it was
  invalid_step,     ///< the step was not finite (NaN or infinite): nothing walked, `end` is the start
};

/// Result of `walk`.
struct WalkResult {
  WalkPoint end{};                ///< where the walk ended; always a valid point of the mesh
  /// The step as it was carried to the end: the start's tangent step, rotated over every edge
  /// crossed and reduced to its along-edge part at every wall. World direction and length.
  /// Walking `-end_step` from `end` retraces an unobstructed walk.
  Vec3 end_step{0.0f};
  float distance = 0.0f;          ///< length walked over the surface, world units
  int edges_crossed = 0;          ///< triangles entered
  int walls_hit = 0;              ///< boundary edges reached (each one slid along or stopped at)
  WalkStatus status = WalkStatus::completed;
};

/// A mesh of valid positions, cleaned and connected for walking. Build it with
/// `build_walk_mesh` (from any triangle soup) or `make_walk_mesh` (from a level, for an agent).
/// Queries are const and allocate nothing; the mesh is immutable once built.
class WalkMesh {
 public:
  WalkMesh() = default;

  // ---- conversions -----------------------------------------------------------------------

  /// World position of a walk point.
  [[nodiscard]] Vec3 to_world_point(const WalkPoint& p) const noexcept;
  /// Unit normal of the point's triangle (the up side), world space.
  [[nodiscard]] Vec3 to_world_triangle_normal(const WalkPoint& p) const noexcept;
  /// Unit normal interpolated from the area-weighted vertex normals (Phong), world space:
  /// continuous across edges, for smooth camera and model orientation.
  [[nodiscard]] Vec3 to_world_smooth_normal(const WalkPoint& p) const noexcept;
  /// The walk point nearest to a world point: exact (closest point on every triangle: the plane
  /// projection when it falls inside, else the nearest edge point; Ericson 5.1.5's regions),
  /// found through the BVH, however far the point is. Throws InvalidInput when `world`
  /// is not finite, is so far from the mesh that squared distances overflow float (beyond about
  /// 1e18), or the mesh is empty.
  [[nodiscard]] WalkPoint nearest_walk_point(Vec3 world) const;
  /// The walk point nearest to a world point among those within `max_distance` of it
  /// (inclusive, a ball; Detour's findNearestPoly searches a box for the same purpose), or
  /// nullopt when there is none. The same answer as the unbounded query whenever that one is
  /// within reach, found faster when the bound is tight: a game snapping a player or a click to
  /// the floor knows how far the floor can be. Throws InvalidInput when `world` is not finite,
  /// `max_distance` is negative or not finite, or the mesh is empty.
  [[nodiscard]] std::optional<WalkPoint> nearest_walk_point(Vec3 world, float max_distance) const;
  /// The walk point in triangle `triangle` with barycentric `weights` of its stored corners.
  /// Throws InvalidInput if the triangle is out of range or the weights are not finite,
  /// non-negative and of positive sum (they are normalised to sum 1).
  [[nodiscard]] WalkPoint walk_point(std::uint32_t triangle, Vec3 weights) const;

  // ---- movement --------------------------------------------------------------------------

  /// Moves `start` by `step` (world vector, projected onto the triangle's plane) inside its
  /// triangle, stopping at the first edge reached. `start` must be a walk point of this mesh.
  /// A step that is not finite moves nothing: `end` is `start`, time 0, no edge.
  [[nodiscard]] TriangleWalk walk_in_triangle(const WalkPoint& start, Vec3 step) const noexcept;
  /// Re-expresses a point on edge (indices.x, indices.y) (weights.z == 0) in the triangle across
  /// that edge. Empty when the edge is a boundary, or when `start` is not in edge form.
  [[nodiscard]] std::optional<EdgeCrossing> cross_edge(const WalkPoint& start) const noexcept;
  /// The whole move: `step` (world vector) is projected onto the start triangle's plane, then
  /// walked triangle by triangle, rotated over each edge crossed (so it keeps its length), and
  /// at a boundary edge reduced to its component along that edge (sliding along the wall). The
  /// result never leaves the mesh. `start` must be a walk point of this mesh. A step that is not
  /// finite is refused: status `invalid_step`, `end` is `start`, nothing walked.
  [[nodiscard]] WalkResult walk(const WalkPoint& start, Vec3 step) const noexcept;

  // ---- the mesh --------------------------------------------------------------------------

  [[nodiscard]] std::size_t triangle_count() const noexcept { return triangles_.size(); }
  [[nodiscard]] std::size_t vertex_count() const noexcept { return positions_.size(); }
  /// Vertex indices of a triangle, counter-clockwise seen from up.
  [[nodiscard]] glm::uvec3 triangle(std::uint32_t t) const noexcept { return triangles_[t]; }
  /// Triangle across edge e (from corner e to corner e + 1) of triangle t, or kNoNeighbor.
  [[nodiscard]] std::uint32_t neighbor(std::uint32_t t, int e) const noexcept { return neighbors_[t][e]; }
  /// Which connected piece triangle t belongs to, [0, stats().islands).
  [[nodiscard]] std::uint32_t island(std::uint32_t t) const noexcept { return islands_[t]; }
  /// World position of vertex i.
  [[nodiscard]] Vec3 world_vertex(std::uint32_t i) const noexcept { return origin_ + positions_[i]; }
  /// The local origin: world = origin() + stored position.
  [[nodiscard]] Vec3 origin() const noexcept { return origin_; }
  /// World bounds of all vertices.
  [[nodiscard]] Aabb3 bounds() const noexcept { return {origin_ + local_bounds_.min, origin_ + local_bounds_.max}; }
  /// Largest extent of the bounds: the length tolerances are relative to it.
  [[nodiscard]] float size() const noexcept { return size_; }
  /// Area of triangle t, world units squared.
  [[nodiscard]] float triangle_area(std::uint32_t t) const noexcept;
  [[nodiscard]] const WalkMeshStats& stats() const noexcept { return stats_; }

  /// Independent validity check of a point against this mesh: triangle in range, indices a
  /// rotation of that triangle, weights finite, >= -tolerance and summing to 1 within it.
  [[nodiscard]] bool is_valid(const WalkPoint& p, float tolerance = 1e-4f) const noexcept;

 private:
  friend WalkMesh build_walk_mesh(const TriangleSoup& soup, const WalkMeshOptions& options);
  friend WalkMesh make_walk_mesh(const TriangleSoup& level, const WalkAgent& agent);

  /// How a step (world vector) changes the weights of p, in p's corner order.
  [[nodiscard]] Vec3 weight_rates(const WalkPoint& p, Vec3 step) const noexcept;
  /// Local edge index (0..2) of directed edge (u, v) in triangle t, or -1.
  [[nodiscard]] int local_edge(std::uint32_t t, std::uint32_t u, std::uint32_t v) const noexcept;

  Vec3 origin_{0.0f};
  float size_ = 0.0f;
  Aabb3 local_bounds_{};
  std::vector<Vec3> positions_;                       ///< relative to origin_
  std::vector<Vec3> vertex_normals_;                  ///< unit, area-weighted
  std::vector<glm::uvec3> triangles_;                 ///< counter-clockwise from up
  std::vector<Vec3> triangle_normals_;                ///< unit
  /// Per triangle, per corner: the gradient of that corner's barycentric weight, so that a step
  /// changes the weights by dot(gradient, step).
  std::vector<std::array<Vec3, 3>> weight_gradients_;
  std::vector<std::array<std::uint32_t, 3>> neighbors_;
  std::vector<std::array<std::uint8_t, 3>> neighbor_edges_;  ///< the same edge's index in the neighbour
  std::vector<std::uint32_t> islands_;
  TriangleBvh bvh_;
  WalkMeshStats stats_{};
};

/// Checks that every triangle of `soup` indexes existing, finite vertices and that there is at
/// least one triangle. Throws InvalidInput naming the soup and the triangle, e.g.
/// "level.obj: triangle 12: vertex index 900 out of range (512 vertices)".
void validate_triangle_soup(const TriangleSoup& soup);

/// Builds a walk mesh from any triangle soup, the robust way real level meshes need
/// (the failure modes behind recastnavigation issues #263, #377 and #556 in mind):
///  - welds vertices closer than `weld_tolerance` times the tolerance scale: the mesh's size, or
///    kWalkScaleMedianEdges median edge lengths if that is less (hash grid);
///  - drops degenerate triangles (repeated corners, no area) and duplicates;
///  - splits triangles at T-junctions (a vertex inside another triangle's unshared edge), so the
///    two sides link instead of leaving a wall between them;
///  - pairs triangles over each edge; an edge shared by more than two triangles links the pairs
///    that continue each other most flatly, the others see a wall there; triangles folded back
///    onto each other (kFoldBackLinkCos) are never linked;
///  - makes the winding consistent across links (breadth-first), then turns each island so its
///    area-weighted normal points up (ties keep the input's majority winding); links that admit
///    no consistent winding are cut;
///  - numbers islands, computes normals and the BVH.
/// Throws InvalidInput, naming the soup (its `name`) and the triangle, for an index out of range,
/// a non-finite vertex of a triangle, an invalid `options` field, a soup with no usable
/// triangle, or one spread too far for float precision (kWalkPrecisionFraction).
[[nodiscard]] WalkMesh build_walk_mesh(const TriangleSoup& soup, const WalkMeshOptions& options = {});

}  // namespace collide
