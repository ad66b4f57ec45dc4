#pragma once
/// @file
/// The overlap polygon of two convex polygons (the lesson's "convex/convex polygon
/// intersection"): clip A by each of B's edge half-planes (Sutherland & Hodgman 1974).

#include <collide/shape/polygon.hpp>

#include <array>

namespace collide {

/// Most vertices the overlap of two polygons can have.
inline constexpr int kMaxOverlapVertices = 2 * kMaxPolygonVertices;

/// The region shared by two convex polygons, world space. Empty (count 0, area 0) when they do
/// not overlap or share only a point or an edge: an area below kDegenerateAreaTolerance times
/// the larger input's squared size counts as zero.
struct OverlapPolygon {
  std::array<Vec2, kMaxOverlapVertices> vertices;  ///< counter-clockwise, world space
  int count = 0;                                   ///< number of vertices, 0 or >= 3
  float area = 0.0f;                               ///< world units squared, >= 0
  Vec2 centroid{0.0f, 0.0f};                       ///< area centroid; zero when empty
};

/// The overlap of A placed by `xa` and B placed by `xb`, with its area and centroid. Works in
/// A's local frame (B moved there once), so precision holds far from the world origin; at most
/// n + m vertices, on the stack, no allocation. Throws InvalidInput naming the polygon if either
/// has a rounding radius (the overlap of rounded polygons is not a polygon). Sutherland &
/// Hodgman 1974; Ericson, Real-Time Collision Detection, 8.3.4.
[[nodiscard]] OverlapPolygon intersect(const Polygon& a, const Transform& xa, const Polygon& b,
                                       const Transform& xb);

}  // namespace collide
