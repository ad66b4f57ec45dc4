#pragma once
// `collide cast`: the picture of a shape cast (the lesson's continuous collision, issue 4's
// "pictures of the Minkowski path"), drawn through the DebugDraw interface.

#include "query.hpp"

#include <collide/ccd/shape_cast.hpp>
#include <collide/draw/picture.hpp>
#include <collide/narrow/minkowski.hpp>

#include <string>

namespace collide::cli {

/// The shape's core as a polygon for `minkowski_difference`: a circle is its centre (1 vertex),
/// a capsule or segment its two ends (2 vertices, the in-library convention of polygon.hpp),
/// with the shape's radius; a polygon is itself.
[[nodiscard]] Polygon core_polygon(const Shape2D& shape) noexcept;

/// A shape cast answered and explained: the GJK ray cast's result, and the explicit Minkowski
/// difference A - B at t = 0 (world space) that its ray r = vb - va from the origin enters at
/// `t * r` on a hit.
struct CastPicture {
  ShapeCastResult result;
  MinkowskiPolygon difference;
  Vec2 ray{0.0f, 0.0f};  ///< vb - va, world units over the step
};

/// Answers `q` with `shape_cast` and draws it on `picture` in two new panels (fitted to their
/// content unless the picture's options fix a world rectangle), with short labels:
///  1. "motion": A at t = 0 (shape_a) and B at t = 0 (shape_b); for each shape that moves, its
///     end-of-step pose as a dashed outline and its motion as an arrow (both role path) and, on
///     a hit, its pose at the time of first touch (highlight); on a hit, the contact point
///     (contact_point) and the normal from A to B (contact_normal);
///  2. "A - B": the Minkowski difference at t = 0 (minkowski), the origin (origin), the ray
///     r = vb - va from the origin (path), and on a hit its entry point t r (highlight, labelled
///     with t) with the normal there (contact_normal), which is A - B's outward normal.
/// Sets the picture's title to `describe(result)`. Throws InvalidInput from shape_cast
/// (non-finite input).
CastPicture draw_cast(Picture& picture, const CastQuestion& q);

/// One line describing the result: "hit at t = 0.25 (GJK ray cast, 3 iterations)", ...
[[nodiscard]] std::string describe(const ShapeCastResult& r);

}  // namespace collide::cli
