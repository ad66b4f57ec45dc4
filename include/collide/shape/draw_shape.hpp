#pragma once
/// @file
/// Shapes drawn through the debug-draw interfaces (core/debug_draw.hpp): 2D shapes through
/// DebugDraw, 3D shapes and levels as triangles through DebugDraw3. It lives with the
/// shapes because core, where the interface is, sits below them.

#include <collide/core/debug_draw.hpp>
#include <collide/core/transform.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

namespace collide {

/// Draws any 2D shape placed by `xf` (local to world) through the matching DebugDraw call:
/// draw_circle, draw_capsule, draw_segment, or draw_polygon with the world-space vertices
/// (counter-clockwise, as the polygon stores them) and its rounding radius. Never allocates.
void draw_shape(DebugDraw& draw, const Shape2D& shape, const Transform& xf, DrawRole role);

/// Rings (latitude bands) of a drawn sphere: its triangles approximate it within
/// 1 - cos(pi / (2 kDrawSphereRings)) of its radius (2% for 8); a capsule's caps get half as
/// many each, and twice as many segments around.
inline constexpr int kDrawSphereRings = 8;

/// Draws any 3D shape placed by `xf` (local to world) as triangles through DebugDraw3 (world
/// space): a sphere as kDrawSphereRings bands of 2 kDrawSphereRings segments, a capsule as its
/// two caps and the cylinder between, a segment as draw_segment, a triangle as itself, a box's
/// faces as 12 triangles and a hull's polygonal faces as fans. Never allocates.
void draw_shape(DebugDraw3& draw, const Shape3D& shape, const Transform3& xf, DrawRole role);

/// Draws every triangle of a level mesh placed by `xf`, world space.
void draw_shape(DebugDraw3& draw, const TriangleMesh& mesh, const Transform3& xf, DrawRole role);

/// Draws every triangle of a height field placed by `xf` (holes have none), world space.
void draw_shape(DebugDraw3& draw, const HeightField& field, const Transform3& xf, DrawRole role);

}  // namespace collide
