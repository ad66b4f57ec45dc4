#pragma once
// Internal: the separating axis test's inner loop on a structure of arrays, four vertices at a
// time (sat.cpp). `contact` lays B out this way once and runs both passes on it.

#include <collide/narrow/sat.hpp>

namespace collide::detail {

/// Lanes the inner loop handles at once.
inline constexpr int kSatLanes = 4;

/// A polygon's vertices as separate x and y arrays, padded to a multiple of kSatLanes by
/// repeating the last vertex (a repeat changes no minimum).
struct SoaVertices {
  alignas(16) float x[kMaxPolygonVertices + kSatLanes];
  alignas(16) float y[kMaxPolygonVertices + kSatLanes];
  int count = 0;   ///< real vertices
  int padded = 0;  ///< count rounded up to a multiple of kSatLanes

  /// Vertex i.
  [[nodiscard]] Vec2 vertex(int i) const noexcept { return {x[i], y[i]}; }
  /// Stores vertex i (0 <= i < count of the caller's polygon).
  void set(int i, Vec2 v) noexcept {
    x[i] = v.x;
    y[i] = v.y;
  }
  /// Sets the count and pads; call after the vertices are set.
  void finish(int n) noexcept {
    count = n;
    padded = (n + kSatLanes - 1) / kSatLanes * kSatLanes;
    for (int i = n; i < padded; ++i) {
      x[i] = x[n - 1];
      y[i] = y[n - 1];
    }
  }
};

/// find_max_separation of polygon 1 (vertices `v1`, unit outward normals `normals1`) against
/// polygon 2's vertices `v2`. `support` is left 0: see deepest_vertex.
[[nodiscard]] EdgeSeparation find_max_separation_soa(const SoaVertices& v1, const Vec2* normals1,
                                                     const SoaVertices& v2,
                                                     float early_exit) noexcept;

/// Index of the vertex of `v` with the smallest dot(n, vertex) (ties: the lowest index).
[[nodiscard]] int deepest_vertex(const SoaVertices& v, Vec2 n) noexcept;

}  // namespace collide::detail
