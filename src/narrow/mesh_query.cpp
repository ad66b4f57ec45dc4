// Convex shapes against the level shapes (TriangleMesh, HeightField): overlap, distance and
// contact, one triangle at a time through the level's spatial query.
//
// Frames: a level's triangles are stored relative to its origin (the "stored frame": a mesh's
// vertices, a height field's grid space). A's box is taken in that frame for the spatial query;
// each candidate triangle is moved into A's local frame (one 3x3 rotation and a translation per
// corner) and meets A there through the convex-triangle routines (overlap.cpp, distance.cpp,
// contact3.cpp), so large world coordinates cancel once, before anything else.

#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "contact3_triangle.hpp"
#include "polytope3.hpp"
#include "scratch_array.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

namespace collide {
namespace {

constexpr std::uint32_t kNoTriangle = std::numeric_limits<std::uint32_t>::max();
constexpr float kInf = std::numeric_limits<float>::infinity();
/// Multiples of a shape's rounding allowance (slop) by which the per-triangle early out of a
/// contact reaches past the margin: the contact's own allowance is at most about two of them.
constexpr float kPretestSlack = 4.0f;

/// A mesh as the queries see it.
struct MeshLevel {
  const TriangleMesh& mesh;
  [[nodiscard]] Vec3 offset() const noexcept { return mesh.origin; }
  template <class Visit>
  void query(const Aabb3& stored_box, Visit&& visit) const {
    mesh.bvh.query(stored_box, visit);
  }
  [[nodiscard]] std::array<Vec3, 3> corners(std::uint32_t t) const noexcept {
    return {mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)};
  }
  [[nodiscard]] std::uint8_t active_edges(std::uint32_t t) const noexcept {
    return mesh.active_edges[t];
  }
  [[nodiscard]] std::uint32_t vertex_id(std::uint32_t t, int k) const noexcept {
    return mesh.triangles[t][k];
  }
  /// A triangle near stored point `p` to start the distance search from.
  [[nodiscard]] std::uint32_t seed(Vec3 p) const noexcept { return mesh.bvh.nearest(p).triangle; }
};

/// A height field as the queries see it (stored frame: grid space).
struct FieldLevel {
  const HeightField& field;
  [[nodiscard]] Vec3 offset() const noexcept { return field.origin; }
  template <class Visit>
  void query(const Aabb3& stored_box, Visit&& visit) const {
    field.query(Aabb3{stored_box.min + field.origin, stored_box.max + field.origin},
                [&](std::uint32_t t) -> bool { return visit(t); });
  }
  [[nodiscard]] std::array<Vec3, 3> corners(std::uint32_t t) const noexcept {
    return field.grid_corners(t);
  }
  [[nodiscard]] std::uint8_t active_edges(std::uint32_t t) const noexcept {
    return field.active_edges(t);
  }
  [[nodiscard]] std::uint32_t vertex_id(std::uint32_t t, int k) const noexcept {
    return field.corner_sample(t, k);
  }
  /// A triangle of the cell under stored point `p` (clamped to the grid), unless it is a hole.
  [[nodiscard]] std::uint32_t seed(Vec3 p) const noexcept {
    if (!std::isfinite(p.x) || !std::isfinite(p.z)) return kNoTriangle;
    const int cx = field.cells_x(), cz = field.cells_z();
    const int i = static_cast<int>(std::clamp(std::floor(p.x / field.spacing.x), 0.0f, float(cx - 1)));
    const int j = static_cast<int>(std::clamp(std::floor(p.z / field.spacing.y), 0.0f, float(cz - 1)));
    const auto cell = static_cast<std::uint32_t>(j * cx + i);
    return field.is_hole(cell) ? kNoTriangle : 2 * cell;
  }
};

/// The frames of one query: the level's stored frame placed in A's frame, and A placed in the
/// stored frame.
struct Placement {
  Frame3 stored_to_a;
  Transform3 a_in_stored;

  [[nodiscard]] std::array<Vec3, 3> to_a(const std::array<Vec3, 3>& c) const noexcept {
    return {transform_point(stored_to_a, c[0]), transform_point(stored_to_a, c[1]),
            transform_point(stored_to_a, c[2])};
  }
};

Placement place(const Transform3& xa, const Transform3& xl, Vec3 offset) noexcept {
  const Transform3 level_in_a = inv_mul(xa, xl, offset);
  return {Frame3::from(level_in_a), inv_mul(level_in_a, Transform3{})};
}

/// Rounding allowance of a box at this place: touching within it counts.
[[nodiscard]] float slop(const Aabb3& box) noexcept {
  return kRelativeTolerance * (max_abs(box.max - box.min) + max_abs(box.min) + max_abs(box.max));
}

/// Distance between two boxes (0 when they overlap): a lower bound of the distance between
/// anything inside them.
[[nodiscard]] float box_gap(const Aabb3& a, const Aabb3& b) noexcept {
  const Vec3 d = glm::max(glm::max(a.min - b.max, b.min - a.max), Vec3(0.0f));
  return length(d);
}

[[nodiscard]] Aabb3 triangle_box(const std::array<Vec3, 3>& c) noexcept {
  return {glm::min(glm::min(c[0], c[1]), c[2]), glm::max(glm::max(c[0], c[1]), c[2])};
}

// ---- overlap -------------------------------------------------------------------------------

template <Shape3DType A, class Level>
bool overlap_level(const A& a, const Transform3& xa, const Level& level,
                   const Transform3& xl) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xl), "overlap: transforms must be finite rigid");
  const Placement pl = place(xa, xl, level.offset());
  const Aabb3 box = compute_aabb(a, pl.a_in_stored);
  const Aabb3 query = fatten(box, slop(box));
  bool hit = false;
  level.query(query, [&](std::uint32_t t) -> bool {
    const Triangle tri{pl.to_a(level.corners(t))};
    if (overlap(a, Transform3{}, tri, Transform3{})) {
      hit = true;
      return false;
    }
    return true;
  });
  return hit;
}

// ---- distance ------------------------------------------------------------------------------

template <Shape3DType A, class Level>
DistanceResult3 distance_level(const A& a, const Transform3& xa, const Level& level,
                               const Transform3& xl, float max_distance,
                               std::uint32_t* triangle) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xl), "distance: transforms must be finite rigid");
  const Placement pl = place(xa, xl, level.offset());
  const ConvexProxy3 proxy(a);
  const Aabb3 box = compute_aabb(a, pl.a_in_stored);
  const float bound = max_distance >= 0.0f ? max_distance : 0.0f;  // NaN: 0
  DistanceResult3 best;
  best.distance = kInf;
  std::uint32_t best_t = kNoTriangle;
  const auto test = [&](std::uint32_t t) -> bool {
    const std::array<Vec3, 3> stored = level.corners(t);
    if (box_gap(box, triangle_box(stored)) > std::min(best.distance, bound)) return true;
    const ConvexProxy3 tri(Triangle{pl.to_a(stored)});
    const DistanceResult3 d = gjk_distance<3>(proxy, Transform3{}, tri, Transform3{});
    if (d.distance <= bound && (d.distance < best.distance || best_t == kNoTriangle)) {
      best = d;
      best_t = t;
    }
    return best.distance > 0.0f;  // touching: nothing is nearer
  };
  const std::uint32_t seed = level.seed(0.5f * (box.min + box.max));
  if (seed != kNoTriangle) test(seed);
  if (best.distance > 0.0f) {
    const float grow = std::min(best.distance, bound);
    // (the seed is tested already: the same answer again)
    level.query(fatten(box, grow + slop(box)), [&](std::uint32_t t) -> bool { return t == seed || test(t); });
  }
  if (triangle != nullptr) *triangle = best_t;
  if (best_t == kNoTriangle) {
    DistanceResult3 none;
    none.distance = kInf;
    return none;
  }
  best.point_a = transform_point(xa, best.point_a);
  best.point_b = transform_point(xa, best.point_b);
  best.normal = rotate(xa.q, best.normal);
  return best;
}

// ---- contact -------------------------------------------------------------------------------

/// Each triangle's manifold (A's frame, B's ids named by the level) to `visit(t, m)`; stops when
/// it returns false.
template <Shape3DType A, class Level, class Visit>
void contact_each(const A& a, const Transform3& xa, const Level& level, const Transform3& xl,
                  float margin, Visit&& visit) noexcept {
  COLLIDE_ASSERT(is_valid(xa) && is_valid(xl), "contact: transforms must be finite rigid");
  margin = margin > 0.0f ? margin : 0.0f;
  const Placement pl = place(xa, xl, level.offset());
  const Aabb3 box = compute_aabb(a, pl.a_in_stored);
  // A's view, its local box and the early out's reach are made at the first candidate
  // triangle: most queries of a world step (bodies in free space) meet none, and a hull's view
  // and box each cost a pass over its vertices.
  detail::Polytope3 pa;
  const ConvexProxy3 proxy(a);
  Aabb3 local;
  float reach = 0.0f;
  bool ready = false;
  // One manifold for every triangle: each sets its count and the points below it (zeroing a
  // fresh one per candidate triangle showed in the profile).
  Manifold3 m;
  level.query(fatten(box, margin + slop(box)), [&](std::uint32_t t) -> bool {
    if (!ready) {
      detail::make_polytope(pa, a);
      local = compute_aabb(a, Transform3{});
      // The early out's reach: the margin plus more than the contact's rounding allowance
      // (which scales with the smaller core and the coordinates, here A's frame: near A's size).
      reach = margin + kPretestSlack * slop(local);
      ready = true;
    }
    const std::array<Vec3, 3> corners = pl.to_a(level.corners(t));
    const float triangle_reach = reach + kRelativeTolerance * max_abs(corners[0]);
    const auto edges = [&]() -> std::uint8_t { return level.active_edges(t); };
    detail::contact_level_triangle(pa, proxy, local, corners, triangle_reach, edges, margin, m);
    if (m.count == 0) return true;
    for (int i = 0; i < m.count; ++i) {
      ContactId& id = m.points[i].id;
      switch (id.type_b) {
        case FeatureType::vertex: id.index_b = level.vertex_id(t, static_cast<int>(id.index_b)); break;
        case FeatureType::edge: id.index_b = 3 * t + id.index_b; break;
        case FeatureType::face: id.index_b = t; break;
      }
    }
    return visit(t, m);
  });
}

/// Manifold from A's frame to the world.
void to_world(const Transform3& xa, Manifold3& m) noexcept {
  m.normal = rotate(xa.q, m.normal);
  for (int i = 0; i < m.count; ++i) m.points[i].point = transform_point(xa, m.points[i].point);
  if (m.count == 0) m.normal = Vec3(0.0f);
}

/// The points of the triangles' manifolds gathered for one merged manifold (see contact.hpp).
class LevelPoints {
 public:
  /// Points closer than `merge_distance` merge; set before the first add.
  void set_merge_distance(float merge_distance) noexcept {
    merge_ = merge_distance;
    merge2_ = merge_distance * merge_distance;
  }

  void add(const Manifold3& m) noexcept {
    for (int i = 0; i < m.count; ++i) {
      if (count_ == kMaxLevelContactPoints) compact();
      points_[count_] = m.points[i];
      normals_[count_] = m.normal;
      if (m.points[i].depth > deepest_depth_) {
        deepest_depth_ = m.points[i].depth;
        normal_ = m.normal;
      }
      ++count_;
    }
  }

  /// The merged manifold (A's frame).
  void finish(Manifold3& m) noexcept {
    const int n = select();
    m.normal = normal_;
    detail::reduce_contact_points(selected_.data(), n, normal_, m, merge_);
  }

 private:
  /// Points that join the deepest normal's manifold, depth along it, near-duplicates merged,
  /// into selected_; returns their number.
  int select() noexcept {
    int n = 0;
    for (int i = 0; i < count_; ++i) {
      const float c = dot(normals_[i], normal_);
      if (!(c >= kLevelContactMergeCos)) continue;
      ManifoldPoint3 p = points_[i];
      p.depth /= c;
      bool merged = false;
      for (int j = 0; j < n; ++j) {
        if (distance_squared(selected_[j].point, p.point) <= merge2_) {
          if (p.depth > selected_[j].depth) selected_[j] = p;
          merged = true;
          break;
        }
      }
      if (!merged) selected_[n++] = p;
    }
    return n;
  }
  /// Full: keep the 4 the merged manifold would keep now.
  void compact() noexcept {
    Manifold3 m;
    m.normal = normal_;
    detail::reduce_contact_points(selected_.data(), select(), normal_, m, merge_);
    count_ = m.count;
    for (int i = 0; i < m.count; ++i) {
      points_[i] = m.points[i];
      normals_[i] = normal_;
    }
  }

  // Filled before they are read (count_, select's n): not zeroed for every query.
  detail::ScratchArray<ManifoldPoint3, kMaxLevelContactPoints> points_;
  detail::ScratchArray<Vec3, kMaxLevelContactPoints> normals_;
  detail::ScratchArray<ManifoldPoint3, kMaxLevelContactPoints> selected_;
  int count_ = 0;
  float deepest_depth_ = -kInf;
  Vec3 normal_{0.0f};
  float merge_ = 0.0f;
  float merge2_ = 0.0f;
};

template <Shape3DType A, class Level>
Manifold3 contact_level(const A& a, const Transform3& xa, const Level& level,
                        const Transform3& xl, float margin) noexcept {
  LevelPoints points;
  bool touched = false;
  contact_each(a, xa, level, xl, margin, [&](std::uint32_t, const Manifold3& m) -> bool {
    if (!touched) {  // (A's size sets the merge distance: taken once something touches)
      const Aabb3 local = compute_aabb(a, Transform3{});
      points.set_merge_distance(kContactMergeTolerance * max_abs(local.max - local.min));
      touched = true;
    }
    points.add(m);
    return true;
  });
  Manifold3 m;
  if (!touched) return m;  // as finish and to_world leave it: no points, normal zero
  points.finish(m);
  to_world(xa, m);
  return m;
}

template <class Level>
void contact_visit_world(const auto& a, const Transform3& xa, const Level& level,
                         const Transform3& xl, float margin,
                         TriangleContactCallback visit) noexcept {
  contact_each(a, xa, level, xl, margin, [&](std::uint32_t t, Manifold3& m) -> bool {
    to_world(xa, m);
    return visit(t, m);
  });
}

}  // namespace

// ---- public entry points: concrete types, and Shape3D dispatched once ----------------------

template <ConvexShape3DType A>
bool overlap(const A& a, const Transform3& xa, const TriangleMesh& mesh,
             const Transform3& xm) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit([&](const auto& s) { return overlap_level(s, xa, MeshLevel{mesh}, xm); }, a);
  } else {
    return overlap_level(a, xa, MeshLevel{mesh}, xm);
  }
}

template <ConvexShape3DType A>
bool overlap(const A& a, const Transform3& xa, const HeightField& field,
             const Transform3& xf) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit([&](const auto& s) { return overlap_level(s, xa, FieldLevel{field}, xf); }, a);
  } else {
    return overlap_level(a, xa, FieldLevel{field}, xf);
  }
}

template <ConvexShape3DType A>
DistanceResult3 distance(const A& a, const Transform3& xa, const TriangleMesh& mesh,
                         const Transform3& xm, float max_distance,
                         std::uint32_t* triangle) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit(
        [&](const auto& s) { return distance_level(s, xa, MeshLevel{mesh}, xm, max_distance, triangle); },
        a);
  } else {
    return distance_level(a, xa, MeshLevel{mesh}, xm, max_distance, triangle);
  }
}

template <ConvexShape3DType A>
DistanceResult3 distance(const A& a, const Transform3& xa, const HeightField& field,
                         const Transform3& xf, float max_distance,
                         std::uint32_t* triangle) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit(
        [&](const auto& s) { return distance_level(s, xa, FieldLevel{field}, xf, max_distance, triangle); },
        a);
  } else {
    return distance_level(a, xa, FieldLevel{field}, xf, max_distance, triangle);
  }
}

template <ConvexShape3DType A>
Manifold3 contact(const A& a, const Transform3& xa, const TriangleMesh& mesh, const Transform3& xm,
                  float margin) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit([&](const auto& s) { return contact_level(s, xa, MeshLevel{mesh}, xm, margin); },
                      a);
  } else {
    return contact_level(a, xa, MeshLevel{mesh}, xm, margin);
  }
}

template <ConvexShape3DType A>
Manifold3 contact(const A& a, const Transform3& xa, const HeightField& field,
                  const Transform3& xf, float margin) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    return std::visit(
        [&](const auto& s) { return contact_level(s, xa, FieldLevel{field}, xf, margin); }, a);
  } else {
    return contact_level(a, xa, FieldLevel{field}, xf, margin);
  }
}

template <ConvexShape3DType A>
void contact(const A& a, const Transform3& xa, const TriangleMesh& mesh, const Transform3& xm,
             float margin, TriangleContactCallback visit) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    std::visit([&](const auto& s) { contact_visit_world(s, xa, MeshLevel{mesh}, xm, margin, visit); },
               a);
  } else {
    contact_visit_world(a, xa, MeshLevel{mesh}, xm, margin, visit);
  }
}

template <ConvexShape3DType A>
void contact(const A& a, const Transform3& xa, const HeightField& field, const Transform3& xf,
             float margin, TriangleContactCallback visit) noexcept {
  if constexpr (std::is_same_v<A, Shape3D>) {
    std::visit(
        [&](const auto& s) { contact_visit_world(s, xa, FieldLevel{field}, xf, margin, visit); }, a);
  } else {
    contact_visit_world(a, xa, FieldLevel{field}, xf, margin, visit);
  }
}

#define COLLIDE_LEVEL_QUERIES(A, L)                                                              \
  template bool overlap<A>(const A&, const Transform3&, const L&, const Transform3&) noexcept;  \
  template DistanceResult3 distance<A>(const A&, const Transform3&, const L&, const Transform3&, \
                                       float, std::uint32_t*) noexcept;                          \
  template Manifold3 contact<A>(const A&, const Transform3&, const L&, const Transform3&,        \
                                float) noexcept;                                                 \
  template void contact<A>(const A&, const Transform3&, const L&, const Transform3&, float,      \
                           TriangleContactCallback) noexcept;
#define COLLIDE_LEVEL_ROW(A)                \
  COLLIDE_LEVEL_QUERIES(A, TriangleMesh) \
  COLLIDE_LEVEL_QUERIES(A, HeightField)
COLLIDE_LEVEL_ROW(Sphere)
COLLIDE_LEVEL_ROW(Capsule3)
COLLIDE_LEVEL_ROW(Segment3)
COLLIDE_LEVEL_ROW(Box)
COLLIDE_LEVEL_ROW(ConvexHull)
COLLIDE_LEVEL_ROW(Triangle)
COLLIDE_LEVEL_ROW(Shape3D)
#undef COLLIDE_LEVEL_ROW
#undef COLLIDE_LEVEL_QUERIES

}  // namespace collide
