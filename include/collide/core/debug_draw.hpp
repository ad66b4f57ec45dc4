#pragma once
/// @file
/// The debug-draw interface: how worlds, casts and pictures describe themselves to a renderer,
/// without knowing whether it writes SVG, a PNG, or a game's own debug lines (the idea of Box2D's
/// b2Draw and Jolt's DebugRenderer).
///
/// Callers say what a thing *is* (a `DrawRole`), not which colour it has: each renderer maps the
/// roles to one consistent palette and can draw a legend of exactly the roles that appeared, so a
/// picture reads without looking anything up. Coordinates are world space; the renderer maps
/// them to its image.
///
/// Only the interface lives here, in core, so every layer can draw itself; `draw_shape` (a shape
/// through these calls) is in shape/draw_shape.hpp, and the renderers that make pictures (SVG,
/// PNG) are in the separate target collide_draw.

#include <collide/core/math.hpp>

#include <span>
#include <string_view>
#include <type_traits>

namespace collide {

/// What a drawn thing is. Renderers give each role one style and name it in their legend.
enum class DrawRole : unsigned char {
  static_geometry,  ///< immovable colliders (walls, floors, map objects)
  sensor,           ///< sensor colliders: report overlaps, never push
  body,             ///< a moving body
  fast_body,        ///< a moving body fast enough to need continuous collision (a bullet)
  contact_point,    ///< a contact manifold point
  contact_normal,   ///< a contact normal, drawn as an arrow from A towards B
  laser,            ///< a ray and its reflections (the lesson's laser and mirror)
  laser_hit,        ///< where a ray hit something
  path,             ///< a trajectory or a swept motion
  shape_a,          ///< shape A of a pairwise query picture
  shape_b,          ///< shape B of a pairwise query picture
  minkowski,        ///< a Minkowski sum or difference
  origin,           ///< the origin of a configuration space (A - B contains it iff A, B overlap)
  highlight,        ///< anything the picture is about (the time-of-impact pose, a picked shape)
};

/// Number of DrawRole values.
inline constexpr int kDrawRoleCount = static_cast<int>(DrawRole::highlight) + 1;

/// Short lower-case legend name of a role ("static geometry", "fast body", ...).
[[nodiscard]] const char* to_string(DrawRole role) noexcept;

/// A renderer of debug geometry. All coordinates are world space, world units. Solids (polygon,
/// circle, capsule) are filled and outlined; segments, arrows and points are strokes and dots of
/// the renderer's chosen width. Calls may come in any number and order; later ones paint over
/// earlier ones.
class DebugDraw {
 public:
  virtual ~DebugDraw() = default;

  /// A solid convex polygon, counter-clockwise vertices, grown by `radius` (>= 0: rounded).
  virtual void draw_polygon(std::span<const Vec2> vertices, float radius, DrawRole role) = 0;
  /// A solid circle.
  virtual void draw_circle(Vec2 center, float radius, DrawRole role) = 0;
  /// A solid capsule: every point within `radius` of the segment a-b.
  virtual void draw_capsule(Vec2 a, Vec2 b, float radius, DrawRole role) = 0;
  /// A line segment (a wall of zero thickness, a ray, a path piece).
  virtual void draw_segment(Vec2 a, Vec2 b, DrawRole role) = 0;
  /// An arrow from `from` to `to` (a normal, a velocity).
  virtual void draw_arrow(Vec2 from, Vec2 to, DrawRole role) = 0;
  /// A dot at `p` (a contact point, a hit).
  virtual void draw_point(Vec2 p, DrawRole role) = 0;
  /// A short caption at world point `at` (renderers that cannot draw text may ignore it).
  virtual void draw_label(Vec2 at, std::string_view text, DrawRole role) = 0;
};

/// A renderer of 3D debug geometry, the 3D counterpart of DebugDraw (Jolt's DebugRenderer has
/// the same few calls). All coordinates are world space, world units. Solids come as triangles
/// (shape/draw_shape.hpp tessellates spheres, capsules, boxes, hulls and levels), which a
/// renderer shades on both sides; segments, arrows and points are strokes and dots of the
/// renderer's chosen width. Calls may come in any number and order.
class DebugDraw3 {
 public:
  virtual ~DebugDraw3() = default;

  /// A solid triangle, either winding.
  virtual void draw_triangle(const Vec3& a, const Vec3& b, const Vec3& c, DrawRole role) = 0;
  /// A line segment (a ray, a path piece).
  virtual void draw_segment(const Vec3& a, const Vec3& b, DrawRole role) = 0;
  /// An arrow from `from` to `to` (a normal, a velocity).
  virtual void draw_arrow(const Vec3& from, const Vec3& to, DrawRole role) = 0;
  /// A dot at `p` (a contact point, a hit).
  virtual void draw_point(const Vec3& p, DrawRole role) = 0;
};

/// The debug-draw interface of D dimensions: DebugDraw (2D) or DebugDraw3.
template <int D>
using DebugDrawN = std::conditional_t<D == 2, DebugDraw, DebugDraw3>;

}  // namespace collide
