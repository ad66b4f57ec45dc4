#pragma once
// Private to src/decompose: the triangulation and merge steps on caller-owned scratch memory,
// so decompose_convex can try several triangulations without allocating for each.

#include <collide/decompose/convex_decomposition.hpp>

#include <vector>

namespace collide::detail {

/// Working arrays of the two steps; their capacity is reused from call to call.
struct DecompositionScratch {
  std::vector<int> ring_prev, ring_next;  // ear clipping: the remaining polygon
  std::vector<int> ring_twin;  // ear clipping: half-edge behind ring edge v -> next(v), or -1
  std::vector<unsigned char> convex;      // ear clipping: corner strictly convex
  std::vector<int> next, prev, twin;      // merge: half-edge rings and diagonal partners
  std::vector<int> bucket_start, bucket_fill, by_origin;  // merge: half-edges by origin
  std::vector<int> parent, size;          // merge: union-find of triangles into pieces
  std::vector<unsigned char> removed, visited;
};

/// Convex pieces, flattened: piece k is vertices[start[k] .. start[k + 1]).
struct FlatPieces {
  std::vector<int> start;
  std::vector<int> vertices;
  [[nodiscard]] size_t count() const noexcept { return start.empty() ? 0 : start.size() - 1; }
};

/// triangulate_ear_clipping into `out` (cleared first). Also leaves in `scratch.twin` the
/// partner of every half-edge (3 t + j runs from corner j of triangle t to corner j + 1; -1 on
/// the outline), which merge_triangles can use instead of searching.
void ear_clip(std::span<const Vec2> outline, std::string_view name, int first_corner,
              DecompositionScratch& scratch, std::vector<TriangleIndices>& out,
              TurnScale scale = TurnScale::outline);

/// merge_hertel_mehlhorn into `out` (cleared first). `twins_known`: scratch.twin already holds
/// the half-edge partners (from ear_clip on the same triangles).
void merge_triangles(std::span<const Vec2> outline, std::span<const TriangleIndices> triangles,
                     DecompositionScratch& scratch, FlatPieces& out, bool twins_known);

}  // namespace collide::detail
