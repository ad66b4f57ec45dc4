#pragma once
// Internal: the separating axis test on a structure of arrays, four edges at a time (sat.cpp).
// `contact` lays both polygons out this way once, in A's frame, and runs both passes on them.

#include <collide/narrow/sat.hpp>

namespace collide::detail {

/// Edges the separating axis test handles at once.
inline constexpr int kSatLanes = 4;

/// A polygon's vertices and edge normals as separate x and y arrays, padded to a multiple of
/// kSatLanes by repeating the last entry (padded lanes are never reported).
struct SoaPolygon {
  static constexpr int kCapacity = kMaxPolygonVertices + kSatLanes;
  alignas(16) float x[kCapacity];
  alignas(16) float y[kCapacity];
  alignas(16) float nx[kCapacity];
  alignas(16) float ny[kCapacity];
  int count = 0;   ///< real vertices (= edges)
  int padded = 0;  ///< count rounded up to a multiple of kSatLanes

  [[nodiscard]] Vec2 vertex(int i) const noexcept { return {x[i], y[i]}; }
  [[nodiscard]] Vec2 normal(int i) const noexcept { return {nx[i], ny[i]}; }
  [[nodiscard]] int next(int i) const noexcept { return i + 1 == count ? 0 : i + 1; }

  void set_vertex(int i, Vec2 v) noexcept {
    x[i] = v.x;
    y[i] = v.y;
  }
  void set_normal(int i, Vec2 n) noexcept {
    nx[i] = n.x;
    ny[i] = n.y;
  }
  /// After the first n vertices are set: sets the count and pads the vertex arrays.
  void finish_vertices(int n) noexcept {
    count = n;
    padded = (n + kSatLanes - 1) & ~(kSatLanes - 1);
    for (int i = n; i < padded; ++i) {
      x[i] = x[n - 1];
      y[i] = y[n - 1];
    }
  }
  /// After the normals are set (and finish_vertices): pads the normal arrays.
  void finish_normals() noexcept {
    for (int i = count; i < padded; ++i) {
      nx[i] = nx[count - 1];
      ny[i] = ny[count - 1];
    }
  }
};

/// find_max_separation over the edges of `p1` (vertices and normals set) against the vertices
/// of `p2` (normals not needed). `support` is left 0: see deepest_vertex.
[[nodiscard]] EdgeSeparation find_max_separation_soa(const SoaPolygon& p1, const SoaPolygon& p2,
                                                     float early_exit) noexcept;

/// Index of the vertex of `p` with the smallest dot(n, vertex) (ties: the lowest index).
[[nodiscard]] int deepest_vertex(const SoaPolygon& p, Vec2 n) noexcept;

}  // namespace collide::detail
