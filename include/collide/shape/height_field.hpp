#pragma once
/// @file
/// Height fields: terrain as a regular grid of heights, y up, two triangles per cell, optional
/// holes, with per-block height ranges so that box queries and ray casts skip empty air.

#include <collide/core/aabb.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/triangle.hpp>

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Cells per side of a height-field block: each block of up to 8 x 8 cells keeps the lowest and
/// highest height of its (non-hole) cells, which queries test before any cell.
inline constexpr int kHeightFieldBlockCells = 8;

/// Called with the index of each triangle a query finds. Return true to go on, false to stop.
using TriangleQueryCallback = FunctionRef<bool(std::uint32_t triangle)>;

/// A height field in local space, y up.
///
/// Mapping: sample (column i, row j), 0 <= i < samples_x, 0 <= j < samples_z, is the local point
///   origin + (i * spacing.x, heights[j * samples_x + i], j * spacing.y),
/// so rows run along +z, columns along +x, and heights are measured from origin.y.
///
/// Cells: cell (i, j) is the square between samples i, i + 1 and rows j, j + 1; its index is
/// c = j * (samples_x - 1) + i. With corners p00 = (i, j), p10 = (i + 1, j), p01 = (i, j + 1),
/// p11 = (i + 1, j + 1), it is split along the diagonal p00 - p11 into
///   triangle 2 c     = (p00, p01, p11),
///   triangle 2 c + 1 = (p00, p11, p10),
/// both counter-clockwise seen from +y (normals up). Feature ids follow the mesh naming
/// (DESIGN.md): vertex = sample index j * samples_x + i; edge 3 t + k from corner k to corner
/// k + 1 of triangle t as listed; face = triangle index t. A hole cell has no triangles for
/// queries (its indices stay reserved, so the numbering never shifts).
///
/// Queries work relative to `origin` ("grid space": corners (i * spacing.x, h, j * spacing.y)),
/// so a terrain tile far from the local origin keeps float precision.
///
/// Build with `make_height_field` and treat the fields as read-only afterwards.
struct HeightField {
  int samples_x = 0;              ///< samples per row (along x), >= 2
  int samples_z = 0;              ///< rows (along z), >= 2
  Vec2 spacing{1.0f, 1.0f};       ///< distance between samples along x (spacing.x) and z (spacing.y), > 0
  Vec3 origin{0.0f};              ///< local position of sample (0, 0) at height 0
  std::vector<float> heights;     ///< [j * samples_x + i], above origin.y
  std::vector<std::uint8_t> holes;  ///< [cell]: non-zero for a hole; empty when there are none
  int blocks_x = 0, blocks_z = 0;   ///< blocks of kHeightFieldBlockCells^2 cells per row / column
  /// [block by * blocks_x + bx]: lowest and highest height of the block's non-hole cells'
  /// corners; +inf / -inf when every cell is a hole.
  std::vector<std::array<float, 2>> block_range;
  float min_height = 0.0f, max_height = 0.0f;  ///< over every sample

  [[nodiscard]] int cells_x() const noexcept { return samples_x - 1; }
  [[nodiscard]] int cells_z() const noexcept { return samples_z - 1; }
  [[nodiscard]] std::uint32_t triangle_count() const noexcept {
    return 2u * static_cast<std::uint32_t>(cells_x()) * static_cast<std::uint32_t>(cells_z());
  }
  [[nodiscard]] float height(int i, int j) const noexcept {
    return heights[static_cast<std::size_t>(j) * static_cast<std::size_t>(samples_x) + static_cast<std::size_t>(i)];
  }
  [[nodiscard]] bool is_hole(std::uint32_t cell) const noexcept { return !holes.empty() && holes[cell] != 0; }
  /// Sample (i, j) relative to `origin`.
  [[nodiscard]] Vec3 grid_point(int i, int j) const noexcept {
    return {static_cast<float>(i) * spacing.x, height(i, j), static_cast<float>(j) * spacing.y};
  }
  /// Corners of triangle t relative to `origin` (grid space), in the order above.
  [[nodiscard]] std::array<Vec3, 3> grid_corners(std::uint32_t t) const noexcept;
  /// Triangle t in local space (origin added).
  [[nodiscard]] Triangle triangle(std::uint32_t t) const noexcept;
  /// Sample index (j * samples_x + i, its vertex feature id) of corner k of triangle t.
  [[nodiscard]] std::uint32_t corner_sample(std::uint32_t t, int k) const noexcept;
  /// Active edges of triangle t, bit active_edge_bit(k, side) for edge k seen from above (side 0,
  /// the side every triangle faces) and from below (side 1), by the rule of
  /// TriangleMesh::active_edges computed on the fly from the neighbouring cells (the windings
  /// agree): an edge on the field's border or next to a hole is active from both sides; an
  /// internal edge is active from the side where it is convex (a ridge from above, a valley from
  /// below) when the normals turn by more than the angle whose cosine is `cos_threshold`
  /// (kActiveEdgeCosAngle by default).
  [[nodiscard]] std::uint8_t active_edges(std::uint32_t t, float cos_threshold = kActiveEdgeCosAngle) const noexcept;

  /// Calls `visit(triangle)` for each triangle of a non-hole cell whose bounding box overlaps
  /// `local_box` (local space), row by row; stops when `visit` returns false. Blocks whose height
  /// range misses the box's y range are skipped whole. No allocation.
  void query(const Aabb3& local_box, TriangleQueryCallback visit) const;

  /// Every triangle `local_ray` (local space) crosses within `max_fraction`, reported to `visit`
  /// with the fraction of the crossing, which may clip the ray (TriangleRayCallback), in order
  /// of the cells the ray passes over (so a closest-hit callback clips after the first cell that
  /// is hit). The ray is clipped to the field's box, then its path over the xz plane is walked
  /// block by block, skipping blocks whose height range the ray passes above or below over
  /// them, and cell by cell in the others (a 2D digital differential analyser: Amanatides & Woo,
  /// "A Fast Voxel Traversal Algorithm for Ray Tracing", Eurographics 1987). Triangles are tested
  /// with `ray_triangle_fraction`'s watertight test (two-sided; fraction 0 does not count).
  /// No allocation; nothing for a ray of zero length or with a non-finite coordinate.
  void ray_cast(const Ray3& local_ray, TriangleRayCallback visit, float max_fraction = 1.0f) const;

  /// The first triangle `local_ray` crosses within `max_fraction` (normal in local space, the
  /// triangle's geometric normal, up for the top side). A miss has triangle == max().
  [[nodiscard]] TriangleRayHit ray_cast(const Ray3& local_ray, float max_fraction = 1.0f) const noexcept;
};

/// A validated height field of samples_x by samples_z samples (see HeightField for the
/// mapping). `heights` holds samples_x * samples_z values, row by row ([j * samples_x + i]);
/// `holes` is empty or holds one flag per cell ((samples_x - 1) * (samples_z - 1), non-zero for
/// a hole). Throws InvalidInput naming the field: fewer than 2 x 2 samples ("height field:
/// samples_x 1 and samples_z 4: need at least 2 x 2"), a wrong count ("height field heights: 11
/// given, expected 12 (samples_x 4 * samples_z 3)"), a non-finite height ("height field height at
/// row 2, column 3: not finite"), spacing not finite or <= 0 ("height field spacing.x: ..."),
/// a non-finite origin, a wrong hole count, more triangles than a mesh can name
/// (kMaxMeshTriangles).
[[nodiscard]] HeightField make_height_field(int samples_x, int samples_z, std::span<const float> heights, Vec2 spacing,
                                            Vec3 origin = Vec3(0.0f), std::span<const std::uint8_t> holes = {});

/// Bounding box of the height field placed by `xf`, world space (its local box rotated:
/// tight for rotations about the axes by multiples of 90 degrees).
[[nodiscard]] Aabb3 compute_aabb(const HeightField& field, const Transform3& xf) noexcept;

/// Each triangle of `field` placed by `xf` whose bounding box meets `box` (world space), with its
/// corners in world space (holes have none), as `for_each_triangle` of a TriangleMesh. No
/// allocation.
void for_each_triangle(const HeightField& field, const Transform3& xf, const Aabb3& box,
                       TriangleCornersCallback visit);

}  // namespace collide
