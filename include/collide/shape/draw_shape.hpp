#pragma once
/// @file
/// A 2D shape drawn through the DebugDraw interface (core/debug_draw.hpp). It lives with the
/// shapes because core, where the interface is, sits below them.

#include <collide/core/debug_draw.hpp>
#include <collide/core/transform.hpp>
#include <collide/shape/shape2d.hpp>

namespace collide {

/// Draws any 2D shape placed by `xf` (local to world) through the matching DebugDraw call:
/// draw_circle, draw_capsule, draw_segment, or draw_polygon with the world-space vertices
/// (counter-clockwise, as the polygon stores them) and its rounding radius. Never allocates.
void draw_shape(DebugDraw& draw, const Shape2D& shape, const Transform& xf, DrawRole role);

}  // namespace collide
