// The picture of a shape cast: the same question seen in the world (two moving shapes) and in
// configuration space (a ray from the origin into the fixed Minkowski difference A - B), which
// is how shape_cast answers it (see ccd/shape_cast.hpp).

#include "cast.hpp"

#include <collide/core/error.hpp>
#include <collide/shape/draw_shape.hpp>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

namespace collide::cli {
namespace {

/// Length of a drawn normal arrow, as a fraction of the larger side of its panel's content.
constexpr float kNormalArrowFraction = 0.15f;

/// `xf` moved by `t` times `v`.
Transform moved(const Transform& xf, Vec2 v, float t) { return {xf.p + t * v, xf.q}; }

std::string number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", static_cast<double>(v));
  return buf;
}

Aabb merge_all(std::initializer_list<Aabb> boxes) {
  Aabb out = *boxes.begin();
  for (const Aabb& b : boxes) out = merge(out, b);
  return out;
}

float larger_side(const Aabb& box) {
  const Vec2 size = box.size();
  return std::max(size.x, size.y);
}

}  // namespace

Polygon core_polygon(const Shape2D& shape) noexcept {
  return std::visit(
      [](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Polygon>) {
          return s;
        } else {
          Polygon p;
          if constexpr (std::is_same_v<S, Circle>) {
            p.count = 1;
            p.vertices[0] = s.center;
            p.radius = s.radius;
            p.centroid = s.center;
          } else {
            p.count = 2;
            p.vertices[0] = s.a;
            p.vertices[1] = s.b;
            p.normals[0] = right_perp(normalize_or_zero(s.b - s.a));
            p.normals[1] = -p.normals[0];
            p.centroid = 0.5f * (s.a + s.b);
            if constexpr (std::is_same_v<S, Capsule>) p.radius = s.radius;
          }
          return p;
        }
      },
      shape);
}

std::string describe(const ShapeCastResult& r) {
  const std::string how = " (GJK ray cast, " + std::to_string(r.iterations) + " iteration" +
                          (r.iterations == 1 ? "" : "s") + ")";
  switch (r.status) {
    case QueryStatus::hit: return "shape cast: hit at t = " + number(r.fraction) + how;
    case QueryStatus::separated: return "shape cast: separated over the whole step" + how;
    case QueryStatus::overlapped: return "shape cast: overlapped at t = 0" + how;
    case QueryStatus::max_iterations: return "shape cast: failed, no contact before t = " + number(r.fraction) + how;
  }
  return "shape cast";
}

CastPicture draw_cast(Picture& picture, const CastQuestion& q) {
  CastPicture cast;
  cast.result = shape_cast(q.a, q.xa, q.va, q.b, q.xb, q.vb);
  cast.difference = minkowski_difference(core_polygon(q.a), q.xa, core_polygon(q.b), q.xb);
  // Cores of 1 or 2 points (circles, capsules, segments) make the edge merge repeat a vertex
  // where an edge of length zero meets another: keep one of each run of equal vertices.
  std::vector<Vec2>& v = cast.difference.vertices;
  v.erase(std::unique(v.begin(), v.end()), v.end());
  while (v.size() > 1 && v.back() == v.front()) v.pop_back();
  cast.ray = q.vb - q.va;
  const ShapeCastResult& r = cast.result;
  const bool touched = r.status == QueryStatus::hit || r.status == QueryStatus::overlapped;
  picture.set_title(describe(r));

  // 1. The motion, world space.
  picture.begin_panel("motion: t = 0, first touch, end");
  const Transform xa1 = moved(q.xa, q.va, 1.0f), xb1 = moved(q.xb, q.vb, 1.0f);
  // A shape that does not move is drawn once, as itself.
  const bool a_moves = q.va != Vec2{0.0f, 0.0f}, b_moves = q.vb != Vec2{0.0f, 0.0f};
  if (a_moves) draw_shape(picture, q.a, xa1, DrawRole::path);
  if (b_moves) draw_shape(picture, q.b, xb1, DrawRole::path);
  draw_shape(picture, q.a, q.xa, DrawRole::shape_a);
  draw_shape(picture, q.b, q.xb, DrawRole::shape_b);
  if (a_moves) picture.draw_arrow(q.xa.p, xa1.p, DrawRole::path);
  if (b_moves) picture.draw_arrow(q.xb.p, xb1.p, DrawRole::path);
  const Aabb a0 = compute_aabb(q.a, q.xa), b0 = compute_aabb(q.b, q.xb);
  picture.draw_label(a0.center(), "A", DrawRole::shape_a);
  picture.draw_label(b0.center(), "B", DrawRole::shape_b);
  if (touched) {
    if (a_moves) draw_shape(picture, q.a, moved(q.xa, q.va, r.fraction), DrawRole::highlight);
    if (b_moves) draw_shape(picture, q.b, moved(q.xb, q.vb, r.fraction), DrawRole::highlight);
    const float arrow = kNormalArrowFraction *
                        larger_side(merge_all({a0, b0, compute_aabb(q.a, xa1), compute_aabb(q.b, xb1)}));
    if (r.normal != Vec2{0.0f, 0.0f}) {
      picture.draw_arrow(r.point, r.point + arrow * r.normal, DrawRole::contact_normal);
    }
    picture.draw_point(r.point, DrawRole::contact_point);
  }

  // 2. Configuration space: the ray from the origin along vb - va into A - B.
  picture.begin_panel("A - B and the ray t (vb - va)");
  const MinkowskiPolygon& md = cast.difference;
  picture.draw_polygon(md.vertices, md.radius, DrawRole::minkowski);
  const Vec2 origin{0.0f, 0.0f};
  if (cast.ray != origin) picture.draw_arrow(origin, cast.ray, DrawRole::path);
  picture.draw_point(origin, DrawRole::origin);
  picture.draw_label(origin, "0", DrawRole::origin);
  if (touched) {
    const Vec2 entry = r.fraction * cast.ray;
    Aabb box{origin, origin};
    box = merge(box, Aabb{cast.ray, cast.ray});
    for (const Vec2 v : md.vertices) box = merge(box, Aabb{v, v});
    const float arrow = kNormalArrowFraction * larger_side(fatten(box, md.radius));
    if (r.normal != Vec2{0.0f, 0.0f}) picture.draw_arrow(entry, entry + arrow * r.normal, DrawRole::contact_normal);
    picture.draw_point(entry, DrawRole::highlight);
    picture.draw_label(entry, "t = " + number(r.fraction), DrawRole::highlight);
  }
  return cast;
}

}  // namespace collide::cli
