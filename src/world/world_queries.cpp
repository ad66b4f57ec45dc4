// The world's queries, 2D and 3D: ray casts and lasers, AABB and point queries (mouse picks),
// shape casts and the ground check. Statics are found through their tree (a level shape then
// answers through its own BVH or grid); bodies through the body broad phase when it holds their
// current boxes (after a step), else by a scan of the bodies.

#include "hit_order.hpp"
#include "world_impl.hpp"

#include <collide/ccd/sweep.hpp>
#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace collide {

namespace {

/// Smallest range of rays one task of raycast_batch casts.
constexpr int kRaysPerTask = 64;
/// A ray cut at a hit for the bodies' broad phase reaches this much further (relative), so
/// that the rounding of the cut ray's box tests never drops a body hit at the same fraction.
constexpr float kRayCutSlack = 1e-4f;

bool visible(const QueryFilter& f, CollisionFilter cf, bool sensor) {
  return (cf.layer & f.mask) != 0u && (f.sensors || !sensor);
}

using detail::better;

/// Calls `visit(ColliderRef)` for every collider (passing `filter`) whose box may meet the
/// query: statics through `static_query`, bodies through `body_query` on the broad phase when
/// current, else each body piece whose box passes `box_test`.
template <int D, class StaticQuery, class BodyQuery, class BoxTest, class Visit>
void for_candidates(const typename WorldN<D>::Impl& w, const QueryFilter& filter,
                    StaticQuery&& static_query, BodyQuery&& body_query, BoxTest&& box_test,
                    Visit&& visit) {
  bool go_on = true;
  if (filter.statics) {
    static_query([&](int id) {
      const detail::StaticPieceN<D>& sp = w.static_pieces[id];
      const StaticDefN<D>& st = w.statics[sp.owner];
      if (visible(filter, st.filter, st.sensor)) go_on = visit(ColliderRef{true, sp.owner, sp.piece});
      return go_on;
    });
  }
  if (!go_on || !filter.bodies) return;
  const auto body_piece = [&](std::uint32_t index, std::uint16_t piece) {
    const detail::BodyN<D>& b = w.bodies[index];
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
    const detail::BodyN<D>& b = w.bodies[i];
    if (!b.alive) continue;
    for (std::size_t k = 0; k < b.shapes.size() && go_on; ++k) {
      if (box_test(w.piece_box(b, static_cast<int>(k)))) body_piece(i, static_cast<std::uint16_t>(k));
    }
  }
}

/// The contact of `shape` placed by `xf` with one collider (normal from the shape to it).
template <int D>
ManifoldN<D> collider_contact(const typename WorldN<D>::Impl& w, const BodyShapeN<D>& shape, const TransformN<D>& xf,
                              const ColliderRef& c) {
  if (c.is_static) return detail::piece_contact(shape, xf, w.static_piece(c), w.transform(c));
  return contact(shape, xf, w.body_shape(c), w.transform(c));
}

/// The ray cast of one collider: a static piece (a level shape too) or a body piece.
template <int D>
RayHitN<D> collider_raycast(const typename WorldN<D>::Impl& w, const ColliderRef& c, const RayN<D>& ray) {
  if (c.is_static) return detail::piece_raycast(w.static_piece(c), w.transform(c), ray);
  return raycast(w.body_shape(c), w.transform(c), ray);
}

template <int D>
std::optional<WorldRayHitN<D>> cast_ray(const typename WorldN<D>::Impl& w, const RayN<D>& ray,
                                        const QueryFilter& filter, std::optional<ColliderRef> skip) {
  std::optional<WorldRayHitN<D>> best;
  float limit = 1.0f;
  const auto visit = [&](const ColliderRef& c) {
    if (skip && *skip == c) return true;
    const RayHitN<D> h = collider_raycast<D>(w, c, ray);
    if (h.hit && better(h.fraction, c, best.has_value(), limit, best ? best->collider : c)) {
      best = WorldRayHitN<D>{c, w.user_id(c), h};
      limit = h.fraction;
    }
    return true;
  };
  // The structures clip the ray to `limit` through their callback's return value. The bodies'
  // broad phase gets the ray cut at the nearest hit so far (a static's): its grid walk then
  // stops there instead of at the ray's end (the cut is loosened by kRayCutSlack for rounding,
  // and its fractions scaled back; the exact casts, on the whole ray, decide).
  const auto padded = [](float fraction) { return std::min(1.0f, fraction * (1.0f + kRayCutSlack)); };
  for_candidates<D>(
      w, filter,
      [&](auto&& each) { w.static_tree.ray_cast(ray, [&](int id, float) { each(id); return limit; }); },
      [&](auto&& each) {
        const float reach = padded(limit);
        if (!(reach > 0.0f && reach < 1.0f)) {
          w.body_broad.ray_cast(ray, [&](int id, float) { each(id); return limit; });
          return;
        }
        const RayN<D> cut{ray.origin, ray.translation * reach};
        w.body_broad.ray_cast(cut, [&](int id, float) { each(id); return padded(limit) / reach; });
      },
      [&](const AabbN<D>& box) { return ray_box_fraction(ray, box, limit) >= 0.0f; }, visit);
  return best;
}

}  // namespace

template <int D>
std::optional<WorldRayHitN<D>> WorldN<D>::raycast(const RayN<D>& ray, const QueryFilter& filter) const {
  if (!is_finite(ray.origin) || !is_finite(ray.translation)) throw InvalidInput("ray: not finite");
  impl_->refresh_static_index();
  return cast_ray<D>(*impl_, ray, filter, std::nullopt);
}

template <int D>
void WorldN<D>::raycast_batch(std::span<const RayN<D>> rays, std::span<std::optional<WorldRayHitN<D>>> hits,
                              const QueryFilter& filter) const {
  if (rays.size() != hits.size()) {
    throw InvalidInput("raycast batch: " + std::to_string(rays.size()) + " rays, " + std::to_string(hits.size()) +
                       " hit slots");
  }
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!is_finite(rays[i].origin) || !is_finite(rays[i].translation)) {
      throw InvalidInput("raycast batch: ray " + std::to_string(i) + " not finite");
    }
  }
  Impl& w = *impl_;
  w.refresh_static_index();
  w.prepare_workers();
  w.parallel(static_cast<int>(rays.size()), kRaysPerTask, [&](int begin, int end, int) {
    for (int i = begin; i < end; ++i) {
      hits[static_cast<std::size_t>(i)] = cast_ray<D>(w, rays[static_cast<std::size_t>(i)], filter, std::nullopt);
    }
  });
}

template <int D>
LaserPathN<D> WorldN<D>::cast_laser(const RayN<D>& ray, int max_bounces, const QueryFilter& filter) const {
  if (!is_finite(ray.origin) || !is_finite(ray.translation)) {
    throw InvalidInput("laser ray: not finite");
  }
  if (max_bounces < 0 || max_bounces > kMaxLaserBounces) {
    throw InvalidInput("laser max_bounces: must be in [0, " + std::to_string(kMaxLaserBounces) + "]");
  }
  impl_->refresh_static_index();
  LaserPathN<D> path;
  path.points[0] = ray.origin;
  RayN<D> r = ray;
  std::optional<ColliderRef> mirror;  // the surface just left: rounding may put r behind it
  for (int bounce = 0; bounce <= max_bounces; ++bounce) {
    const std::optional<WorldRayHitN<D>> hit = cast_ray<D>(*impl_, r, filter, mirror);
    if (!hit) {
      path.points[++path.segments] = r.origin + r.translation;
      break;
    }
    path.points[++path.segments] = hit->hit.point;
    path.hits[path.hit_count++] = *hit;
    if (bounce == max_bounces) break;
    r = reflect(r, hit->hit);
    // A convex mirror cannot be hit again by the reflected ray, which skips it. A level shape
    // can (another of its triangles), so it is not skipped; the reflected ray starts a rounding
    // step off its surface instead, on the side the laser came from: from the hit point itself
    // (on the plane within rounding), a two-sided triangle is hit again from behind at fraction
    // 0, which sent the laser out through the wall. A field can be hit again too (a concave
    // solid); its ray starts off the surface by more than sphere tracing's hit threshold.
    const detail::StaticPieceRefN<D> piece =
        hit->collider.is_static ? impl_->static_piece(hit->collider) : detail::StaticPieceRefN<D>{};
    const bool level = piece.field != nullptr || (piece.shape != nullptr && detail::is_level(*piece.shape));
    if (level) {
      float step = kRelativeTolerance * (max_abs(hit->hit.point) + length(r.translation));
      if (piece.field != nullptr) step += detail::field_laser_offset<D>(*piece.field);
      r.origin += step * hit->hit.normal;  // the normal faces the incoming laser
    }
    mirror = level ? std::nullopt : std::optional<ColliderRef>(hit->collider);
  }
  return path;
}

template <int D>
void WorldN<D>::query_aabb(const AabbN<D>& box, const QueryFilter& filter,
                           const ColliderCallback& callback) const {
  if (!is_valid(box)) throw InvalidInput("query box: not finite or min > max");
  impl_->refresh_static_index();
  const detail::Probe<D> probe = detail::box_probe(box);
  const Impl& w = *impl_;
  for_candidates<D>(
      w, filter, [&](auto&& each) { w.static_tree.query(box, [&](int id) { return each(id); }); },
      [&](auto&& each) {
        w.body_broad.query(box, [&](int id) {
          return !collide::overlap(w.piece_box(w.bodies[w.proxies[id].body], w.proxies[id].piece), box) ||
                 each(id);
        });
      },
      [&](const AabbN<D>& b) { return collide::overlap(b, box); },
      [&](const ColliderRef& c) {
        const bool touch = c.is_static
                               ? detail::piece_overlap(probe.shape, probe.xf, w.static_piece(c), w.transform(c))
                               : collide::overlap(probe.shape, probe.xf, w.body_shape(c), w.transform(c));
        return !touch || callback(c);
      });
}

template <int D>
void WorldN<D>::query_point(Vec point, const QueryFilter& filter, const ColliderCallback& callback) const {
  if (!is_finite(point)) throw InvalidInput("query point: not finite");
  query_aabb(AabbN<D>{point, point}, filter, callback);
}

template <int D>
void WorldN<D>::collide_shape(const BodyShape& shape, const Xf& xf, const QueryFilter& filter,
                              const ContactCallbackN<D>& callback) const {
  if (!is_valid(xf)) throw InvalidInput("collide shape: transform not finite or not unit");
  impl_->refresh_static_index();
  const Impl& w = *impl_;
  const AabbN<D> box = compute_aabb(shape, xf);
  for_candidates<D>(
      w, filter, [&](auto&& each) { w.static_tree.query(box, [&](int id) { return each(id); }); },
      [&](auto&& each) { w.body_broad.query(box, [&](int id) { return each(id); }); },
      [&](const AabbN<D>& b) { return collide::overlap(b, box); },
      [&](const ColliderRef& c) {
        const ManifoldN<D> m = collider_contact<D>(w, shape, xf, c);
        return !m.touching() || callback(c, m);
      });
}

template <int D>
WorldCastHitN<D> WorldN<D>::shape_cast(const BodyShape& shape, const Xf& xf, Vec translation,
                                       const QueryFilter& filter) const {
  if (!is_valid(xf) || !is_finite(translation)) {
    throw InvalidInput("shape cast: transform or translation not finite");
  }
  impl_->refresh_static_index();
  const Impl& w = *impl_;
  const AabbN<D> swept = swept_aabb(shape, xf, translation);
  WorldCastHitN<D> best;
  const auto visit = [&](const ColliderRef& c) {
    const auto r = c.is_static
                       ? detail::piece_shape_cast(shape, xf, translation, w.static_piece(c), w.transform(c))
                       : collide::shape_cast(shape, xf, translation, w.body_shape(c), w.transform(c), Vec(0.0f));
    if (!r.hit || !better(r.fraction, c, best.hit, best.fraction, best.collider)) return true;
    Vec normal = r.normal;
    Vec point = r.point;
    if (normal == Vec(0.0f)) {  // overlapping cores at the start: the contact says where
      const ManifoldN<D> m = collider_contact<D>(w, shape, xf, c);
      normal = m.normal;
      point = m.count > 0 ? m.points[0].point : xf.p;
    }
    best = WorldCastHitN<D>{true, c, w.user_id(c), r.fraction, point, normal};
    return true;
  };
  for_candidates<D>(
      w, filter, [&](auto&& each) { w.static_tree.query(swept, [&](int id) { return each(id); }); },
      [&](auto&& each) { w.body_broad.query(swept, [&](int id) { return each(id); }); },
      [&](const AabbN<D>& b) { return collide::overlap(b, swept); }, visit);
  return best;
}

template <int D>
WorldCastHitN<D> WorldN<D>::ground_check(BodyId id, Vec down) const {
  const detail::BodyN<D>& b = impl_->body(id);
  QueryFilter filter;
  filter.mask = b.filter.mask;
  filter.ignore = id;
  WorldCastHitN<D> best;
  for (const BodyShape& s : b.shapes) {
    const WorldCastHitN<D> h = shape_cast(s, b.xf, down, filter);
    if (h.hit && better(h.fraction, h.collider, best.hit, best.fraction, best.collider)) best = h;
  }
  return best;
}

#define COLLIDE_WORLD_QUERIES(D)                                                                      \
  template std::optional<WorldRayHitN<D>> WorldN<D>::raycast(const RayN<D>&, const QueryFilter&) const; \
  template void WorldN<D>::raycast_batch(std::span<const RayN<D>>, std::span<std::optional<WorldRayHitN<D>>>, \
                                         const QueryFilter&) const; \
  template LaserPathN<D> WorldN<D>::cast_laser(const RayN<D>&, int, const QueryFilter&) const;          \
  template void WorldN<D>::query_aabb(const AabbN<D>&, const QueryFilter&, const ColliderCallback&) const; \
  template void WorldN<D>::query_point(VecN<D>, const QueryFilter&, const ColliderCallback&) const;     \
  template WorldCastHitN<D> WorldN<D>::shape_cast(const BodyShapeN<D>&, const TransformN<D>&, VecN<D>,  \
                                                  const QueryFilter&) const;                          \
  template WorldCastHitN<D> WorldN<D>::ground_check(BodyId, VecN<D>) const;                            \
  template void WorldN<D>::collide_shape(const BodyShapeN<D>&, const TransformN<D>&, const QueryFilter&, \
                                         const ContactCallbackN<D>&) const;
COLLIDE_WORLD_QUERIES(2)
COLLIDE_WORLD_QUERIES(3)
#undef COLLIDE_WORLD_QUERIES

}  // namespace collide
