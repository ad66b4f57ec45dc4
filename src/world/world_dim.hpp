#pragma once
// What the world's step and queries need to know about their dimension: pieces' bounding
// circles or spheres and sizes, a body's motion and sweep, and the narrow-phase calls between a
// body piece and a static piece (a convex shape, or in 3D a level shape met triangle by
// triangle). Everything else in src/world is written once for both dimensions.

#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/sweep.hpp>
#include <collide/ccd/time_of_impact.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/world/world.hpp>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <type_traits>

namespace collide::detail {

/// True for the level shapes a 3D static's variant may hold (a mesh, a height field).
template <class T>
inline constexpr bool kIsMesh = std::is_same_v<T, std::shared_ptr<const TriangleMesh>>;
template <class T>
inline constexpr bool kIsField = std::is_same_v<T, std::shared_ptr<const HeightField>>;

/// Precomputed facts about one piece, in its owner's local frame.
template <int D>
struct PieceInfoN {
  VecN<D> center{0.0f};  ///< bounding circle or sphere (the early-out pretest)
  float radius = 0.0f;
  /// Radius of the largest circle or sphere that fits inside (0 for a segment or a level
  /// shape): how far the piece can move in one step before it could pass through a thin wall.
  float inner_size = 0.0f;
};

/// A reach measured for a cull of time of impact queries (a piece's points about its centre of
/// rotation, plus what it may meet) is grown by this fraction of itself (room for the time of
/// impact's target separation, 1e-3 of the smaller size, and its tolerance: a query calls a hit
/// a little before contact) and by kReachRounding of the coordinates' magnitude.
inline constexpr float kReachSlack = 0.01f;
inline constexpr float kReachRounding = 1e-5f;

/// Whether a body's centre of rotation, moving from `c0` to `c1` over the step, comes within
/// `reach` of `center` (reach grown by kReachSlack of itself and kReachRounding of the
/// coordinates). With `reach` the body's reach about its centre plus the bounding radius of a
/// static about `center`, a pair whose centre never comes that near cannot touch within the
/// step, and its time of impact query would say separated: move_with_ccd's pretest (a
/// bullet's swept box holds statics its path passes far from).
template <int D>
[[nodiscard]] bool path_reaches(VecN<D> c0, VecN<D> c1, VecN<D> center, float reach) noexcept {
  const VecN<D> m = c1 - c0;
  const float mm = dot(m, m);
  const float s = mm > 0.0f ? std::clamp(dot(center - c0, m) / mm, 0.0f, 1.0f) : 0.0f;
  const float grown = reach * (1.0f + kReachSlack) + kReachRounding * (max_abs(c0) + max_abs(c1) + reach);
  return !(length_squared(c0 + s * m - center) > grown * grown);
}

/// Facts about a shape: bounding circle or sphere and inner size (local space).
PieceInfoN<2> piece_info(const Shape2D& shape);
PieceInfoN<3> piece_info(const Shape3D& shape);
PieceInfoN<3> piece_info(const StaticShape3D& shape);
/// Area (2D) or volume (3D) of a shape, radius included: the weight of its centre in a body's
/// centre of rotation.
float shape_measure(const Shape2D& shape);
float shape_measure(const Shape3D& shape);

/// A lower bound of the distance from world point `p` to static piece `shape` placed by `xf`, or
/// `cap` when nothing of it is nearer than `cap`: the signed distance for convex solids
/// (negative inside; closest_point), the distance to the nearest triangle for level shapes,
/// which are surfaces (the mesh's BVH branch and bound; the height field's cells near `p`).
/// The world's static clearance stands on it (BodyN::clearance).
float static_distance(const Shape2D& shape, const Transform& xf, Vec2 p, float cap) noexcept;
float static_distance(const StaticShape3D& shape, const Transform3& xf, Vec3 p, float cap) noexcept;

/// The transform after moving the centre of rotation `local_center` by `d` and turning by
/// `rot` (2D: radians; 3D: a rotation vector, world frame).
Transform moved(const Transform& xf, Vec2 local_center, Vec2 d, float rot);
Transform3 moved(const Transform3& xf, Vec3 local_center, Vec3 d, Vec3 rot);

/// A level's triangle (world corners) as a Triangle placed at its first corner. Queries
/// against it then see coordinates as small as the triangle and its distance to the other
/// shape, not as large as the level's distance from the origin: a pair query allows for
/// rounding in proportion to the coordinates it is given (kRelativeTolerance), and a capsule
/// 9000 units out got a contact 0.047 deep from a triangle placed at the origin that it was
/// 0.016 away from.
struct PlacedTriangle {
  Triangle shape;
  Transform3 xf;
};
[[nodiscard]] inline PlacedTriangle placed_triangle(const std::array<Vec3, 3>& c) noexcept {
  return {Triangle{{Vec3(0.0f), c[1] - c[0], c[2] - c[0]}}, Transform3{c[0]}};
}

/// A caller's transform as the world keeps it: a 3D orientation renormalised (is_valid lets
/// |q|^2 stray 1e-3 from 1, which scales every rotated offset by as much: 2 cm at 20 m). 2D
/// transforms are kept as given.
[[nodiscard]] inline Transform unit_pose(const Transform& xf) noexcept { return xf; }
[[nodiscard]] inline Transform3 unit_pose(const Transform3& xf) noexcept {
  return {xf.p, glm::normalize(xf.q)};
}

/// The sweep's pose at time t, as a body keeps it: the 3D orientation renormalised, since each
/// step's sweep starts from the last one's pose and rounding would otherwise drift it off unit
/// length (a box hit every step for 3 s had |q|^2 = 1 - 1.7e-5; in its frame a wall 20 units
/// from the origin then sat 7e-4 off, its speculative contact was lost and the box went
/// through). The 2D sweep builds its rotation from an angle and needs nothing.
[[nodiscard]] inline Transform pose_at(const Sweep& sweep, float t) noexcept { return sweep.at(t); }
[[nodiscard]] inline Transform3 pose_at(const Sweep3& sweep, float t) noexcept {
  const Quat q = glm::normalize(sweep.orientation(t));
  return {sweep.c0 + t * (sweep.c1 - sweep.c0) - rotate(q, sweep.local_center), q};
}

/// Magnitude of a turn (radians): |rot| in both dimensions.
[[nodiscard]] inline float turn_size(float rot) noexcept { return std::fabs(rot); }
[[nodiscard]] inline float turn_size(Vec3 rot) noexcept { return length(rot); }
/// `rot` scaled by s.
[[nodiscard]] inline float scaled_turn(float rot, float s) noexcept { return rot * s; }
[[nodiscard]] inline Vec3 scaled_turn(Vec3 rot, float s) noexcept { return rot * s; }

/// The sweep of a body moving its centre by `d` and turning by `rot` from `xf`.
[[nodiscard]] inline Sweep sweep_of(const Transform& xf, Vec2 local_center, Vec2 d, float rot) noexcept {
  return Sweep::from_motion(xf, local_center, d, rot);
}
[[nodiscard]] inline Sweep3 sweep_of(const Transform3& xf, Vec3 local_center, Vec3 d, Vec3 rot) noexcept {
  return Sweep3::from_motion(xf, local_center, d, rot);
}

/// World box of a static piece.
[[nodiscard]] inline Aabb piece_box(const Shape2D& shape, const Transform& xf) noexcept {
  return compute_aabb(shape, xf);
}
[[nodiscard]] inline Aabb3 piece_box(const StaticShape3D& shape, const Transform3& xf) noexcept {
  return compute_aabb(shape, xf);
}
[[nodiscard]] inline Aabb3 piece_box(const Shape3D& shape, const Transform3& xf) noexcept {
  return compute_aabb(shape, xf);
}

/// True for a level shape (a triangle mesh or a height field), met triangle by triangle.
[[nodiscard]] inline bool is_level(const Shape2D&) noexcept { return false; }
[[nodiscard]] bool is_level(const StaticShape3D& shape) noexcept;
/// True for a level shape whose pointer is null (add_static refuses it).
[[nodiscard]] bool is_null_level(const StaticShape3D& shape) noexcept;

/// The contact of body piece `a` (placed by `xa`) and static piece `b` (placed by `xb`): the
/// convex pair's manifold, or a level shape's merged manifold (active edges applied).
[[nodiscard]] Manifold piece_contact(const Shape2D& a, const Transform& xa, const Shape2D& b,
                                     const Transform& xb) noexcept;
[[nodiscard]] Manifold3 piece_contact(const Shape3D& a, const Transform3& xa, const StaticShape3D& b,
                                      const Transform3& xb) noexcept;

/// The earliest impact of body piece `a` moving along `sweep` with static piece `b` (placed by
/// `xb`, still), the pieces' `box` the sweep's box: one time of impact for a convex piece, one
/// per triangle whose box meets the sweep's for a level shape (the earliest wins; a triangle
/// the piece already touches at the start is an `overlapped` answer, as for a convex piece).
/// `queries` counts the time-of-impact queries run.
[[nodiscard]] ToiResult piece_impact(const Shape2D& a, const Sweep& sweep, const Aabb& box,
                                     const Shape2D& b, const Transform& xb, std::int64_t& queries);
[[nodiscard]] ToiResult3 piece_impact(const Shape3D& a, const Sweep3& sweep, const Aabb3& box,
                                      const StaticShape3D& b, const Transform3& xb, std::int64_t& queries);

/// Ray cast against a static piece (a level shape: its nearest triangle, normal facing the ray).
[[nodiscard]] inline RayHit piece_raycast(const Shape2D& s, const Transform& xf, const Ray& ray) noexcept {
  return raycast(s, xf, ray);
}
[[nodiscard]] RayHit3 piece_raycast(const StaticShape3D& s, const Transform3& xf, const Ray3& ray) noexcept;
/// Shape cast of body shape `a` against a static piece (still).
[[nodiscard]] ShapeCastResult piece_shape_cast(const Shape2D& a, const Transform& xa, Vec2 v,
                                               const Shape2D& b, const Transform& xb) noexcept;
[[nodiscard]] ShapeCastResult3 piece_shape_cast(const Shape3D& a, const Transform3& xa, Vec3 v,
                                                const StaticShape3D& b, const Transform3& xb) noexcept;
/// Overlap of body shape `a` and a static piece.
[[nodiscard]] bool piece_overlap(const Shape2D& a, const Transform& xa, const Shape2D& b,
                                 const Transform& xb) noexcept;
[[nodiscard]] bool piece_overlap(const Shape3D& a, const Transform3& xa, const StaticShape3D& b,
                                 const Transform3& xb) noexcept;

/// The box as a body shape and its placement, for exact overlap tests (2D: a polygon, or a
/// segment or point when flat; 3D: a box about the box's centre, flat ones too, or a point).
template <int D>
struct Probe {
  BodyShapeN<D> shape;
  TransformN<D> xf;
};
[[nodiscard]] Probe<2> box_probe(const Aabb& box);
[[nodiscard]] Probe<3> box_probe(const Aabb3& box);

}  // namespace collide::detail
