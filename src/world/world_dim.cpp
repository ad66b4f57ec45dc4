// The world's geometry that differs by dimension (world_dim.hpp): 2D pieces are convex shapes;
// 3D statics may also be level shapes, met triangle by triangle.

#include "world_dim.hpp"

#include <collide/broad/broad_phase.hpp>  // ray_box_fraction
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/polygon.hpp>
#include <collide/shape/triangle.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>
#include <variant>

namespace collide::detail {

namespace {

/// A sweep against a level shape sorts at most this many of the triangles its box meets by
/// their entry fraction (triangle_entry) on the stack; the rest are queried as they come.
constexpr int kSortedTriangles = 64;
/// triangle_entry's answer for a triangle the piece never comes near: beyond every fraction.
constexpr float kNeverEntered = 2.0f;

/// A lower bound on the fraction at which a piece whose points all stay within `reach` of its
/// centre of rotation, the centre moving from `from` by `motion`, can first touch the triangle
/// `c`: the first fraction at which the centre comes within `reach` of the triangle (the ray
/// from + s motion, s in [0, 1], entering the triangle grown by `reach`, the rounded triangle);
/// kNeverEntered when it never does within the step. A cull and an order for the exact time of
/// impact per triangle. First the cheap rejections: the centre missing the triangle's box grown
/// by `reach` (slab test), or staying beyond `reach` on one side of its plane. Then the exact
/// entry, as a ray cast into a rounded hull (raycast3.cpp): the rounded triangle is the union
/// of the prism of the triangle pushed out by `reach` along its normal each way and the three
/// capsules of radius `reach` around its edges (a prism's sides lie inside the capsules), so a
/// ray from outside enters it first through a prism top (its entry point above the triangle)
/// or a capsule. A bullet coming down onto a floor of coplanar triangles reaches their plane at
/// the same time over every one of them: the plane alone kept them all for the exact query, the
/// rounded triangle keeps those near where it comes down (`collide run --3d --bodies 1000`:
/// time of impact queries 546 -> 267 a frame, the motion with continuous collision 1.06 ->
/// 0.92 ms a frame on one thread; the same hits, state hashes unchanged).
float triangle_entry(Vec3 from, Vec3 motion, float reach, const std::array<Vec3, 3>& c) {
  const Aabb3 grown{glm::min(glm::min(c[0], c[1]), c[2]) - Vec3(reach), glm::max(glm::max(c[0], c[1]), c[2]) + Vec3(reach)};
  const float enter = ray_box_fraction(Ray3{from, motion}, grown, 1.0f);
  if (enter < 0.0f) return kNeverEntered;
  // (in double, triangle_normal: a sliver's plane made in float turns by FLT_EPSILON times its
  // length over width, enough to cull a triangle the centre does reach)
  const Vec3 n = triangle_normal(c[0], c[1], c[2]);
  if (n == Vec3(0.0f)) return enter;  // a degenerate triangle: its box's entry
  const float d0 = dot(n, from - c[0]);
  const float d1 = d0 + dot(n, motion);
  if (std::fabs(d0) > reach && (d0 > 0.0f) == (d1 > 0.0f) && std::fabs(d1) > reach) return kNeverEntered;
  // Already within reach at the start (only possible within the slab).
  if (std::fabs(d0) <= reach &&
      distance_squared(from, closest_point_on_triangle(from, c[0], c[1], c[2]).point) <= reach * reach) {
    return 0.0f;
  }
  const Ray3 ray{from, motion};
  float entry = kNeverEntered;
  // The prism top on the start's side, if the centre reaches it within the step.
  const float side = d0 > 0.0f ? 1.0f : -1.0f;
  if (std::fabs(d0) > reach && side * (d0 - d1) > 0.0f) {  // outside the slab, moving towards the plane
    const float s = (side * d0 - reach) / (side * (d0 - d1));
    if (s <= 1.0f) {
      const Vec3 q = from + s * motion - side * reach * n;  // below the entry point, in the plane
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) inside = dot(cross(c[(k + 1) % 3] - c[k], q - c[k]), n) >= 0.0f;
      if (inside) return std::max(enter, std::max(s, 0.0f));  // the face is met before any edge
    }
  }
  // The edges' capsules, each after a test of its bounding ball (the edge's middle, radius half
  // its length plus the reach) against the centre's path.
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = c[k], b = c[(k + 1) % 3];
    if (!path_reaches<3>(from, from + motion, 0.5f * (a + b), 0.5f * length(b - a) + reach)) continue;
    const RayHit3 h = raycast(Capsule3{a, b, reach}, Transform3{}, ray);
    if (h.hit) entry = std::min(entry, h.fraction);
  }
  return entry == kNeverEntered ? entry : std::max(enter, entry);
}

/// The bounding sphere of a box (a level shape's facts): its centre and half diagonal.
PieceInfoN<3> box_info(const Aabb3& box) {
  return {0.5f * (box.min + box.max), 0.5f * length(box.max - box.min), 0.0f};
}

}  // namespace

// ---- pieces ---------------------------------------------------------------------------------

PieceInfoN<2> piece_info(const Shape2D& shape) {
  return std::visit(
      [](const auto& s) -> PieceInfoN<2> {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Circle>) {
          return {s.center, s.radius, s.radius};
        } else if constexpr (std::is_same_v<S, Capsule>) {
          return {0.5f * (s.a + s.b), 0.5f * distance(s.a, s.b) + s.radius, s.radius};
        } else if constexpr (std::is_same_v<S, Segment>) {
          return {0.5f * (s.a + s.b), 0.5f * distance(s.a, s.b), 0.0f};
        } else {
          float reach = 0.0f;
          float inner = std::numeric_limits<float>::infinity();
          for (int i = 0; i < s.count; ++i) {
            reach = std::max(reach, distance(s.vertices[i], s.centroid));
            inner = std::min(inner, dot(s.normals[i], s.vertices[i] - s.centroid));
          }
          return {s.centroid, reach + s.radius, std::max(inner, 0.0f) + s.radius};
        }
      },
      shape);
}

PieceInfoN<3> piece_info(const Shape3D& shape) {
  return std::visit(
      [](const auto& s) -> PieceInfoN<3> {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere>) {
          return {s.center, s.radius, s.radius};
        } else if constexpr (std::is_same_v<S, Capsule3>) {
          return {0.5f * (s.a + s.b), 0.5f * distance(s.a, s.b) + s.radius, s.radius};
        } else if constexpr (std::is_same_v<S, Segment3>) {
          return {0.5f * (s.a + s.b), 0.5f * distance(s.a, s.b), 0.0f};
        } else if constexpr (std::is_same_v<S, Box>) {
          return {Vec3(0.0f), length(s.half) + s.radius,
                  std::min({s.half.x, s.half.y, s.half.z}) + s.radius};
        } else {
          // A hull: reach from its centroid, and the nearest face plane inside (the largest
          // sphere about the centroid that fits).
          float reach = 0.0f;
          for (const Vec3& v : s.vertices) reach = std::max(reach, distance(v, s.centroid));
          float inner = std::numeric_limits<float>::infinity();
          for (const HullFace& f : s.faces) inner = std::min(inner, f.offset - dot(f.normal, s.centroid));
          return {s.centroid, reach + s.radius, std::max(inner, 0.0f) + s.radius};
        }
      },
      shape);
}

PieceInfoN<3> piece_info(const StaticShape3D& shape) {
  return std::visit(
      [](const auto& s) -> PieceInfoN<3> {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return box_info(compute_aabb(*s, Transform3{}));
        } else {
          return piece_info(Shape3D(s));
        }
      },
      shape);
}

float shape_measure(const Shape2D& shape) {
  constexpr float pi = std::numbers::pi_v<float>;
  return std::visit(
      [](const auto& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Circle>) {
          return pi * s.radius * s.radius;
        } else if constexpr (std::is_same_v<S, Capsule>) {
          return 2.0f * s.radius * distance(s.a, s.b) + pi * s.radius * s.radius;
        } else if constexpr (std::is_same_v<S, Segment>) {
          return 0.0f;
        } else {
          float perimeter = 0.0f;
          for (int i = 0; i < s.count; ++i) perimeter += distance(s.vertices[i], s.vertex(i + 1));
          return signed_area({s.vertices.data(), static_cast<size_t>(s.count)}) +
                 perimeter * s.radius + pi * s.radius * s.radius;
        }
      },
      shape);
}

float shape_measure(const Shape3D& shape) {
  constexpr float pi = std::numbers::pi_v<float>;
  return std::visit(
      [](const auto& s) -> float {
        using S = std::decay_t<decltype(s)>;
        const auto ball = [&](float r) { return 4.0f / 3.0f * pi * r * r * r; };
        if constexpr (std::is_same_v<S, Sphere>) {
          return ball(s.radius);
        } else if constexpr (std::is_same_v<S, Capsule3>) {
          return pi * s.radius * s.radius * distance(s.a, s.b) + ball(s.radius);
        } else if constexpr (std::is_same_v<S, Segment3>) {
          return 0.0f;
        } else if constexpr (std::is_same_v<S, Box>) {
          // The core box, its faces pushed out by the radius, its edges' quarter cylinders and
          // its corners' ball (Steiner's formula for a rounded box).
          const Vec3 h = s.half;
          const float r = s.radius;
          return 8.0f * h.x * h.y * h.z + 8.0f * r * (h.x * h.y + h.y * h.z + h.z * h.x) +
                 2.0f * pi * r * r * (h.x + h.y + h.z) + ball(r);
        } else {
          return s.volume;  // the core's (a rounded hull's rim is left out: the weight of a centre)
        }
      },
      shape);
}

// ---- motion ---------------------------------------------------------------------------------

Transform moved(const Transform& xf, Vec2 local_center, Vec2 d, float rot) {
  if (rot == 0.0f) return {xf.p + d, xf.q};
  const Vec2 c = transform_point(xf, local_center) + d;
  const Rot2 q = mul(Rot2::from_angle(rot), xf.q);
  return {c - rotate(q, local_center), q};
}

Transform3 moved(const Transform3& xf, Vec3 local_center, Vec3 d, Vec3 rot) {
  if (rot == Vec3(0.0f)) return {xf.p + d, xf.q};
  // The turn as Sweep3 makes it (one home for the rotation vector's quaternion), renormalised
  // so rounding never drifts the orientation off unit length over many steps.
  const Quat q = glm::normalize(Sweep3::from_motion(xf, local_center, d, rot).orientation(1.0f));
  const Vec3 c = transform_point(xf, local_center) + d;
  return {c - rotate(q, local_center), q};
}

// ---- static pieces ---------------------------------------------------------------------------

float static_distance(const Shape2D& shape, const Transform& xf, Vec2 p, float cap) noexcept {
  return std::min(closest_point(shape, xf, p).distance, cap);
}

float static_distance(const StaticShape3D& shape, const Transform3& xf, Vec3 p, float cap) noexcept {
  return std::visit(
      [&](const auto& s) -> float {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S>) {
          const BvhNearest n = s->bvh.nearest(inv_transform_point(xf, p) - s->origin, cap * cap);
          return n.triangle == std::numeric_limits<std::uint32_t>::max() ? cap : std::min(std::sqrt(n.distance_squared), cap);
        } else if constexpr (kIsField<S>) {
          const Vec3 local = inv_transform_point(xf, p);
          const Vec3 grid = local - s->origin;
          float nearest = cap;
          s->query(Aabb3{local - Vec3(cap), local + Vec3(cap)}, [&](std::uint32_t t) -> bool {
            const std::array<Vec3, 3> c = s->grid_corners(t);
            nearest = std::min(nearest, distance(grid, closest_point_on_triangle(grid, c[0], c[1], c[2]).point));
            return nearest > 0.0f;
          });
          return nearest;
        } else {
          return std::min(closest_point(s, xf, p).distance, cap);
        }
      },
      shape);
}

bool is_level(const StaticShape3D& shape) noexcept {
  return shape.index() >= 5;  // the mesh and the height field come after the convex shapes
}

bool is_null_level(const StaticShape3D& shape) noexcept {
  return std::visit(
      [](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return s == nullptr;
        } else {
          return false;
        }
      },
      shape);
}

Manifold piece_contact(const Shape2D& a, const Transform& xa, const Shape2D& b,
                       const Transform& xb) noexcept {
  return contact(a, xa, b, xb);
}

Manifold3 piece_contact(const Shape3D& a, const Transform3& xa, const StaticShape3D& b,
                        const Transform3& xb) noexcept {
  return std::visit(
      [&](const auto& s) -> Manifold3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return contact(a, xa, *s, xb);
        } else {
          return contact(a, xa, Shape3D(s), xb);
        }
      },
      b);
}

ToiResult piece_impact(const Shape2D& a, const Sweep& sweep, const Aabb& /*box*/,
                       const Shape2D& b, const Transform& xb, std::int64_t& queries) {
  const Sweep still = Sweep::from_motion(xb, {0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f);
  ++queries;
  return time_of_impact(ConvexProxy(a), sweep, ConvexProxy(b), still);
}

namespace {

/// The normal (from A to B) of an `overlapped` time of impact, which is zero when GJK found the
/// cores within its touching tolerance: the contact's, with the time of impact's target as a
/// speculative margin (twice it), so that cores closer than the target but not touching, which
/// the separating axis test calls apart, still say which way B is. A body moving into such a
/// surface went through it without (a hull 6e-5 under a room's ceiling).
template <class B>
Vec3 overlap_normal(const Shape3D& a, const Transform3& xa, const B& b, const Transform3& xb) {
  const float size = piece_info(a).radius;
  const float margin = 2.0f * std::max(kToiTargetSeparation * size, kToiRoundingTarget * (max_abs(xa.p) + size));
  return std::visit([&](const auto& s) { return contact(s, xa, b, xb, margin).normal; }, a);
}

/// piece_impact against a level shape (a triangle mesh or a height field placed by `xb`): the
/// triangles the sweep's box `box` meets, one time of impact each (`queries` counts them).
template <class Level>
ToiResult3 level_impact(const Shape3D& a, const ConvexProxy3& proxy_a, const Sweep3& sweep, const Aabb3& box,
                        const Level& level, const Transform3& xb, std::int64_t& queries) {
  // Every triangle the sweep's box meets. A triangle the piece already touches at the
  // start and moves into is the answer (at fraction 0, `overlapped`, as a convex piece
  // answers): another triangle's later hit must not carry the piece through it. Else the
  // earliest hit; a touched triangle the piece moves away from stops nothing. Triangles
  // are queried in order of a lower bound on their hit (triangle_entry), and none whose
  // bound is past the earliest hit so far: a bullet into a floor meets one or two of
  // the dozens of triangles its box holds.
  const Sweep3 still = Sweep3::from_motion(Transform3{}, Vec3(0.0f), Vec3(0.0f), Vec3(0.0f));
  const Vec3 motion = sweep.c1 - sweep.c0;
  const Transform3 at_start = sweep.at(0.0f);
  float reach = 0.0f;
  for (int i = 0; i < proxy_a.count(); ++i) reach = std::max(reach, distance(proxy_a.point(i), sweep.local_center));
  reach = (reach + proxy_a.radius()) * (1.0f + kReachSlack) +
          kReachRounding * (max_abs(sweep.c0) + max_abs(sweep.c1) + reach);
  ToiResult3 best;
  best.status = QueryStatus::separated;
  best.fraction = 1.0f;
  int best_order = std::numeric_limits<int>::max();
  // The exact query of the triangle `order`-th in the walk; false when it is the answer
  // (nothing is earlier). Equal fractions go to the earlier triangle in the walk, so the
  // answer is the walk's whatever order the triangles are queried in.
  const auto query = [&](const std::array<Vec3, 3>& c, int order) -> bool {
    ++queries;
    const Triangle triangle{c};
    ToiResult3 r = time_of_impact(proxy_a, sweep, ConvexProxy3(triangle), still);
    if (r.status == QueryStatus::overlapped) {
      if (r.normal == Vec3(0.0f)) {
        const PlacedTriangle placed = placed_triangle(c);
        r.normal = overlap_normal(a, at_start, placed.shape, placed.xf);
      }
      if (dot(motion, r.normal) > 0.0f) {
        best = r;
        return false;
      }
    } else if ((r.status == QueryStatus::hit || r.status == QueryStatus::max_iterations) &&
               (r.fraction < best.fraction || (r.fraction == best.fraction && order < best_order))) {
      best = r;
      best_order = order;
    }
    return true;
  };
  struct Entry {
    float fraction;  // triangle_entry's lower bound on its hit
    int order;       // its place in the walk
    std::array<Vec3, 3> corners;
  };
  std::array<Entry, kSortedTriangles> entries;
  int count = 0;
  int walk = 0;
  bool at_once = false;  // more than kSortedTriangles: the walk's order, as they come
  bool answered = false;
  for_each_triangle(level, xb, box, [&](std::uint32_t, const std::array<Vec3, 3>& c) -> bool {
    const int order = walk++;
    const float entry = triangle_entry(sweep.c0, motion, reach, c);
    if (entry > best.fraction) return true;  // its hit, if any, is later than the earliest
    if (!at_once && count < kSortedTriangles) {
      entries[static_cast<std::size_t>(count++)] = {entry, order, c};
      return true;
    }
    if (!at_once) {  // the ones kept so far first, in the walk's order
      at_once = true;
      for (int k = 0; k < count && !answered; ++k) {
        const Entry& e = entries[static_cast<std::size_t>(k)];
        if (e.fraction <= best.fraction) answered = !query(e.corners, e.order);
      }
      if (answered) return false;
    }
    answered = !query(c, order);
    return !answered;
  });
  if (at_once) return best;
  std::sort(entries.begin(), entries.begin() + count, [](const Entry& x, const Entry& y) {
    return x.fraction < y.fraction || (x.fraction == y.fraction && x.order < y.order);
  });
  for (int k = 0; k < count; ++k) {
    const Entry& e = entries[static_cast<std::size_t>(k)];
    if (e.fraction > best.fraction) break;
    if (!query(e.corners, e.order)) break;
  }
  return best;
}

}  // namespace

ToiResult3 piece_impact(const Shape3D& a, const Sweep3& sweep, const Aabb3& box,
                        const StaticShape3D& b, const Transform3& xb, std::int64_t& queries) {
  const ConvexProxy3 proxy_a(a);
  return std::visit(
      [&](const auto& s) -> ToiResult3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return level_impact(a, proxy_a, sweep, box, *s, xb, queries);
        } else {
          const Sweep3 still = Sweep3::from_motion(xb, Vec3(0.0f), Vec3(0.0f), Vec3(0.0f));
          ++queries;
          ToiResult3 r = time_of_impact(proxy_a, sweep, ConvexProxy3(s), still);
          if (r.status == QueryStatus::overlapped && r.normal == Vec3(0.0f)) {
            r.normal = overlap_normal(a, sweep.at(0.0f), s, xb);
          }
          return r;
        }
      },
      b);
}

RayHit3 piece_raycast(const StaticShape3D& s, const Transform3& xf, const Ray3& ray) noexcept {
  return std::visit(
      [&](const auto& shape) -> RayHit3 {
        using S = std::decay_t<decltype(shape)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return raycast(*shape, xf, ray);
        } else {
          return raycast(shape, xf, ray);
        }
      },
      s);
}

ShapeCastResult piece_shape_cast(const Shape2D& a, const Transform& xa, Vec2 v, const Shape2D& b,
                                 const Transform& xb) noexcept {
  return shape_cast(a, xa, v, b, xb, Vec2{0.0f, 0.0f});
}

ShapeCastResult3 piece_shape_cast(const Shape3D& a, const Transform3& xa, Vec3 v,
                                  const StaticShape3D& b, const Transform3& xb) noexcept {
  return std::visit(
      [&](const auto& s) -> ShapeCastResult3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return shape_cast(a, xa, v, *s, xb, Vec3(0.0f));
        } else {
          return shape_cast(a, xa, v, Shape3D(s), xb, Vec3(0.0f));
        }
      },
      b);
}

bool piece_overlap(const Shape2D& a, const Transform& xa, const Shape2D& b, const Transform& xb) noexcept {
  return overlap(a, xa, b, xb);
}

bool piece_overlap(const Shape3D& a, const Transform3& xa, const StaticShape3D& b,
                   const Transform3& xb) noexcept {
  return std::visit(
      [&](const auto& s) -> bool {
        using S = std::decay_t<decltype(s)>;
        if constexpr (kIsMesh<S> || kIsField<S>) {
          return overlap(a, xa, *s, xb);
        } else {
          return overlap(a, xa, Shape3D(s), xb);
        }
      },
      b);
}

Probe<2> box_probe(const Aabb& box) {
  const Vec2 half = box.extents();
  if (half.x > 0.0f && half.y > 0.0f) return {make_box(half, box.center(), 0.0f), Transform{}};
  if (half.x > 0.0f || half.y > 0.0f) return {Segment{box.min, box.max}, Transform{}};
  return {Circle{box.min, 0.0f}, Transform{}};
}

Probe<3> box_probe(const Aabb3& box) {
  // A box around the centre (a flat or empty one too: GJK takes zero half extents; make_box
  // would refuse them, and the probe never leaves the query).
  const Vec3 half = 0.5f * (box.max - box.min);
  if (half == Vec3(0.0f)) return {Sphere{Vec3(0.0f), 0.0f}, Transform3{box.min, Quat{1.0f, 0.0f, 0.0f, 0.0f}}};
  return {Box{half, 0.0f}, Transform3{0.5f * (box.min + box.max), Quat{1.0f, 0.0f, 0.0f, 0.0f}}};
}

}  // namespace collide::detail

namespace collide {

Aabb3 compute_aabb(const StaticShape3D& shape, const Transform3& xf) noexcept {
  return std::visit(
      [&](const auto& s) -> Aabb3 {
        using S = std::decay_t<decltype(s)>;
        if constexpr (detail::kIsMesh<S> || detail::kIsField<S>) {
          return s != nullptr ? compute_aabb(*s, xf) : Aabb3{xf.p, xf.p};
        } else {
          return compute_aabb(s, xf);
        }
      },
      shape);
}

}  // namespace collide
