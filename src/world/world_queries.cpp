// World2D's queries: ray casts and lasers, AABB and point queries (mouse picks), shape casts and
// the ground check. Statics are found through their tree; bodies through the body broad phase
// when it holds their current boxes (after a step), else by a scan of the bodies.

#include "world_impl.hpp"

#include <collide/ccd/sweep.hpp>
#include <collide/core/error.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>

#include <cmath>
#include <optional>

namespace collide {

namespace {

bool visible(const QueryFilter& f, CollisionFilter cf, bool sensor) {
  return (cf.layer & f.mask) != 0u && (f.sensors || !sensor);
}

/// Is candidate `c` (fraction t) better than the best so far? Earlier wins; ties go to the
/// smaller collider key, so results do not depend on the order structures visit candidates.
bool better(float t, const ColliderRef& c, bool have_best, float best_t, const ColliderRef& best) {
  return !have_best || t < best_t || (t == best_t && c.key() < best.key());
}

/// The box as a shape, for exact overlap tests: a polygon, or a segment or point when flat.
Shape2D box_shape(const Aabb& box) {
  const Vec2 half = box.extents();
  if (half.x > 0.0f && half.y > 0.0f) return make_box(half, box.center(), 0.0f);
  if (half.x > 0.0f || half.y > 0.0f) return Segment{box.min, box.max};
  return Circle{box.min, 0.0f};
}

}  // namespace

/// Calls `visit(ColliderRef)` for every collider (passing `filter`, minus `skip`) whose box may
/// meet the query: statics through `static_query`, bodies through `body_query` on the broad
/// phase when current, else each body piece whose box passes `box_test`.
template <class StaticQuery, class BodyQuery, class BoxTest, class Visit>
static void for_candidates(const World2D::Impl& w, const QueryFilter& filter, StaticQuery&& static_query,
                           BodyQuery&& body_query, BoxTest&& box_test, Visit&& visit) {
  bool go_on = true;
  if (filter.statics) {
    static_query([&](int id) {
      const detail::StaticPiece& sp = w.static_pieces[id];
      const StaticDef& st = w.statics[sp.owner];
      if (visible(filter, st.filter, st.sensor)) go_on = visit(ColliderRef{true, sp.owner, sp.piece});
      return go_on;
    });
  }
  if (!go_on || !filter.bodies) return;
  const auto body_piece = [&](std::uint32_t index, std::uint16_t piece) {
    const detail::Body& b = w.bodies[index];
    if (filter.ignore && filter.ignore->index == index) return true;
    if (!visible(filter, b.filter, b.sensor)) return true;
    go_on = visit(ColliderRef{false, index, piece});
    return go_on;
  };
  if (w.body_boxes_current) {
    body_query([&](int id) { return body_piece(w.proxies[id].body, w.proxies[id].piece); });
    return;
  }
  for (std::uint32_t i = 0; i < w.bodies.size() && go_on; ++i) {
    const detail::Body& b = w.bodies[i];
    if (!b.alive) continue;
    for (std::size_t k = 0; k < b.shapes.size() && go_on; ++k) {
      if (box_test(w.piece_box(b, static_cast<int>(k)))) body_piece(i, static_cast<std::uint16_t>(k));
    }
  }
}

namespace {

std::optional<WorldRayHit> cast_ray(const World2D::Impl& w, const Ray& ray,
                                    const QueryFilter& filter, std::optional<ColliderRef> skip) {
  std::optional<WorldRayHit> best;
  float limit = 1.0f;
  const auto visit = [&](const ColliderRef& c) {
    if (skip && *skip == c) return true;
    const RayHit h = raycast(w.shape(c), w.transform(c), ray);
    if (h.hit && better(h.fraction, c, best.has_value(), limit, best ? best->collider : c)) {
      best = WorldRayHit{c, w.user_id(c), h};
      limit = h.fraction;
    }
    return true;
  };
  // The structures clip the ray to `limit` through their callback's return value.
  for_candidates(
      w, filter,
      [&](auto&& each) { w.static_tree.ray_cast(ray, [&](int id, float) { each(id); return limit; }); },
      [&](auto&& each) { w.body_broad.ray_cast(ray, [&](int id, float) { each(id); return limit; }); },
      [&](const Aabb& box) { return ray_box_fraction(ray, box, limit) >= 0.0f; }, visit);
  return best;
}

}  // namespace

std::optional<WorldRayHit> World2D::raycast(const Ray& ray, const QueryFilter& filter) const {
  if (!is_finite(ray.origin) || !is_finite(ray.translation)) throw InvalidInput("ray: not finite");
  impl_->refresh_static_tree();
  return cast_ray(*impl_, ray, filter, std::nullopt);
}

LaserPath World2D::cast_laser(const Ray& ray, int max_bounces, const QueryFilter& filter) const {
  if (!is_finite(ray.origin) || !is_finite(ray.translation)) {
    throw InvalidInput("laser ray: not finite");
  }
  if (max_bounces < 0 || max_bounces > kMaxLaserBounces) {
    throw InvalidInput("laser max_bounces: must be in [0, " + std::to_string(kMaxLaserBounces) + "]");
  }
  impl_->refresh_static_tree();
  LaserPath path;
  path.points[0] = ray.origin;
  Ray r = ray;
  std::optional<ColliderRef> mirror;  // the surface just left: rounding may put r behind it
  for (int bounce = 0; bounce <= max_bounces; ++bounce) {
    const std::optional<WorldRayHit> hit = cast_ray(*impl_, r, filter, mirror);
    if (!hit) {
      path.points[++path.segments] = r.origin + r.translation;
      break;
    }
    path.points[++path.segments] = hit->hit.point;
    path.hits[path.hit_count++] = *hit;
    if (bounce == max_bounces) break;
    r = reflect(r, hit->hit);
    mirror = hit->collider;
  }
  return path;
}

void World2D::query_aabb(const Aabb& box, const QueryFilter& filter,
                         const ColliderCallback& callback) const {
  if (!is_valid(box)) throw InvalidInput("query box: not finite or min > max");
  impl_->refresh_static_tree();
  const Shape2D probe = box_shape(box);
  const Impl& w = *impl_;
  for_candidates(
      w, filter, [&](auto&& each) { w.static_tree.query(box, [&](int id) { return each(id); }); },
      [&](auto&& each) {
        w.body_broad.query(box, [&](int id) {
          return !collide::overlap(w.piece_box(w.bodies[w.proxies[id].body], w.proxies[id].piece), box) ||
                 each(id);
        });
      },
      [&](const Aabb& b) { return collide::overlap(b, box); },
      [&](const ColliderRef& c) {
        return !collide::overlap(probe, Transform{}, w.shape(c), w.transform(c)) || callback(c);
      });
}

void World2D::query_point(Vec2 point, const QueryFilter& filter,
                          const ColliderCallback& callback) const {
  if (!is_finite(point)) throw InvalidInput("query point: not finite");
  query_aabb(Aabb{point, point}, filter, callback);
}

WorldCastHit World2D::shape_cast(const Shape2D& shape, const Transform& xf, Vec2 translation,
                                 const QueryFilter& filter) const {
  if (!is_valid(xf) || !is_finite(translation)) {
    throw InvalidInput("shape cast: transform or translation not finite");
  }
  impl_->refresh_static_tree();
  const Impl& w = *impl_;
  const Aabb swept = swept_aabb(shape, xf, translation);
  WorldCastHit best;
  const auto visit = [&](const ColliderRef& c) {
    const ShapeCastResult r =
        collide::shape_cast(shape, xf, translation, w.shape(c), w.transform(c), Vec2{0.0f, 0.0f});
    if (!r.hit || !better(r.fraction, c, best.hit, best.fraction, best.collider)) return true;
    Vec2 normal = r.normal;
    Vec2 point = r.point;
    if (normal == Vec2{0.0f, 0.0f}) {  // overlapping cores at the start: the contact says where
      const Manifold m = contact(shape, xf, w.shape(c), w.transform(c));
      normal = m.normal;
      point = m.count > 0 ? m.points[0].point : xf.p;
    }
    best = WorldCastHit{true, c, w.user_id(c), r.fraction, point, normal};
    return true;
  };
  for_candidates(
      w, filter, [&](auto&& each) { w.static_tree.query(swept, [&](int id) { return each(id); }); },
      [&](auto&& each) { w.body_broad.query(swept, [&](int id) { return each(id); }); },
      [&](const Aabb& b) { return collide::overlap(b, swept); }, visit);
  return best;
}

WorldCastHit World2D::ground_check(BodyId id, Vec2 down) const {
  const detail::Body& b = impl_->body(id);
  QueryFilter filter;
  filter.mask = b.filter.mask;
  filter.ignore = id;
  WorldCastHit best;
  for (const Shape2D& s : b.shapes) {
    const WorldCastHit h = shape_cast(s, b.xf, down, filter);
    if (h.hit && better(h.fraction, h.collider, best.hit, best.fraction, best.collider)) best = h;
  }
  return best;
}

}  // namespace collide
