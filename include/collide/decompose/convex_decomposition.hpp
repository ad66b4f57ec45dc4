#pragma once
/// @file
/// Convex decomposition of simple polygons (the lesson, "Convexity": split a concave shape into
/// convex pieces so every convex query applies), and triangulation of planar polygons in 3D
/// (a level file's n-gon faces) by the same ear clipping. Three steps, each usable on its own:
///  1. `make_simple_outline`: validate and clean a user outline (either winding) into a
///     counter-clockwise simple polygon without duplicate or collinear vertices.
///  2. `triangulate_ear_clipping`: O(n^2) ear clipping of that outline.
///  3. `merge_hertel_mehlhorn`: remove triangulation diagonals while the union stays convex.
/// `decompose_convex` runs all three and returns `Polygon`s. `triangulate_planar_polygon` runs
/// the first two on a 3D polygon projected into its plane.
///
/// Runs at load time, not per frame: these functions allocate.

#include <collide/shape/polygon.hpp>

#include <array>
#include <span>
#include <string_view>
#include <vector>

namespace collide {

/// How many triangulations (ear-search starts, spread evenly around the outline)
/// `decompose_convex` tries before keeping the one with the fewest pieces.
inline constexpr int kDecompositionStarts = 8;

/// A 3D polygon whose corners lie farther than this fraction of its size (the longest side of
/// its bounding box) from its best-fit plane is not planar: `triangulate_planar_polygon` refuses
/// it, since its triangles would depend on the triangulation by more than that (a quad's two
/// diagonals give surfaces that far apart). Exporters' n-gons are planar to float rounding; 5 %
/// lets a 2 m face bend 10 cm.
inline constexpr float kPlanarityTolerance = 0.05f;

/// Three indices into an outline, counter-clockwise.
using TriangleIndices = std::array<int, 3>;

/// What `make_simple_outline` does with a straight corner (a vertex on the line through its
/// neighbours, turn within kDegenerateAreaTolerance of the squared size).
enum class StraightCorners {
  remove,  ///< drop it: fewer, larger pieces (decompose_convex)
  keep,    ///< keep it: every vertex is a corner of the triangulation (mesh faces, whose
           ///< neighbours may use the vertex: dropping it would leave a T-junction)
};

/// What the ear clipper compares a corner's turn (twice its triangle's signed area) with to call
/// it straight (not an ear's tip) and a vertex near a cut with to let it block the cut.
enum class TurnScale {
  /// kDegenerateAreaTolerance of the outline's size squared: every ear is a valid `Polygon`
  /// (make_convex_polygon applies the same rule), as decompose_convex needs.
  outline,
  /// kDegenerateAreaTolerance of the ear's longest edge squared, but never below the rounding
  /// of a turn computed from the outline's float coordinates (kTurnRoundingUlps): a fine outline
  /// (a round face of a thousand vertices, whose corners turn by less than the outline rule
  /// allows) still has ears, each a valid mesh triangle. triangulate_planar_polygon uses it.
  triangle,
};

/// The outline of a simple polygon, counter-clockwise, as `make_simple_outline` returns it.
struct SimpleOutline {
  std::vector<Vec2> vertices;  ///< counter-clockwise, no duplicates, no straight corners (unless kept)
  std::vector<int> source;     ///< source[i]: index in the caller's points of vertices[i]
  bool reversed = false;       ///< true when the input was clockwise and was reversed
};

/// Validates `points` as the outline of a simple polygon (either winding; the last point must
/// not repeat the first, but if it does it is dropped as a duplicate) and returns it cleaned:
/// consecutive duplicates (closer than kWeldTolerance of the outline's size) and straight
/// corners (turn below kDegenerateAreaTolerance of the squared size) removed unless `straight`
/// says keep, wound counter-clockwise. `name` labels every error message (e.g. "map1.tmx
/// object 12"). Throws InvalidInput, naming `name` and the vertex or edges, when: a coordinate
/// is not finite; fewer than 3 distinct vertices remain; the area is zero (all collinear); the
/// outline doubles back on itself (a zero-width spike); two non-adjacent edges touch or cross
/// (self-intersection, O(n^2) segment tests).
[[nodiscard]] SimpleOutline make_simple_outline(std::span<const Vec2> points,
                                                std::string_view name = "polygon",
                                                StraightCorners straight = StraightCorners::remove);

/// Triangulates a counter-clockwise simple outline (as from `make_simple_outline`) by ear
/// clipping: repeatedly cut off a strictly convex corner whose triangle holds no other vertex,
/// even on its boundary (Meisters 1975, two-ears theorem; Eberly, "Triangulation by Ear
/// Clipping", 2002). Straight corners are never an ear's tip, but may be its other corners, so
/// an outline with straight corners kept gets them all as triangle corners. Returns n - 2
/// triangles, fewer only when a clipped remainder is degenerate. O(n^2) per ear search in the worst case. Throws InvalidInput naming `name` if no
/// ear can be found (only possible for outlines that are nearly self-touching in float).
/// The search for ears starts at corner `first_corner`; other starts give other
/// triangulations of the same outline. `scale` sets what counts as straight (TurnScale).
[[nodiscard]] std::vector<TriangleIndices> triangulate_ear_clipping(
    std::span<const Vec2> outline, std::string_view name = "polygon", int first_corner = 0,
    TurnScale scale = TurnScale::outline);

/// Triangulates a planar (or nearly planar) simple polygon in 3D, such as an n-gon face of a
/// level mesh: its plane by Newell's method (the normal is the polygon's vector area, so it
/// follows the winding; Sutherland, Sproull & Schumacker 1974; Ericson, Real-Time Collision
/// Detection, 12.4.2) through the average of its corners, the corners projected into that plane
/// (scaled to unit size, so any float coordinates work) and then `make_simple_outline` with
/// straight corners kept and `triangulate_ear_clipping` with TurnScale::triangle. Returns indices into `points`, each
/// triangle wound as the polygon (counter-clockwise seen from the side its vector area points
/// to): n - 2 triangles, fewer only when consecutive duplicate corners were merged. Allocates;
/// O(n^2). Throws InvalidInput naming `name` (e.g. "level.obj:12: face 3") when: a coordinate is
/// not finite; fewer than 3 points; the polygon has no area (corners on one line, or fewer than
/// 3 distinct ones); a corner lies farther than kPlanarityTolerance of the polygon's size from
/// its plane (the message gives both); or as `make_simple_outline` (self-intersecting, doubling
/// back), the vertex numbers being indices into `points`.
[[nodiscard]] std::vector<TriangleIndices> triangulate_planar_polygon(std::span<const Vec3> points,
                                                                      std::string_view name = "polygon");

/// Merges the triangles of a triangulation of `outline` into convex pieces by removing each
/// diagonal whose removal leaves neither end corner reflex (a straight corner is allowed;
/// `decompose_convex` drops such vertices), and keeps the merged piece
/// within kMaxPolygonVertices (Hertel & Mehlhorn 1983; O'Rourke, "Computational Geometry in C",
/// 2.5). The result has at most 4 times the minimum number of convex pieces. Returns each
/// piece as counter-clockwise indices into `outline`.
[[nodiscard]] std::vector<std::vector<int>> merge_hertel_mehlhorn(
    std::span<const Vec2> outline, std::span<const TriangleIndices> triangles);

/// Convex pieces of the simple polygon `points` (either winding): `make_simple_outline`, then
/// ear clipping, then Hertel-Mehlhorn. Hertel-Mehlhorn's result depends on the triangulation,
/// so up to `triangulations` of them (ear searches starting at corners spread evenly around the
/// outline) are tried and the fewest pieces kept; each costs O(n^2) typical, O(n^3) worst.
/// Trying stops early when a result reaches the lower bound ceil(r / 2) + 1 (r reflex corners).
/// A convex input comes back as one piece. Each piece is a
/// valid Polygon (strictly convex, counter-clockwise, at most kMaxPolygonVertices vertices) in
/// the same frame as `points`; their union is the input and their interiors are disjoint.
/// Throws InvalidInput as `make_simple_outline`, every message starting with `name`.
/// Throws InvalidInput also if `triangulations` < 1.
[[nodiscard]] std::vector<Polygon> decompose_convex(std::span<const Vec2> points,
                                                    std::string_view name = "polygon",
                                                    int triangulations = kDecompositionStarts);

}  // namespace collide
