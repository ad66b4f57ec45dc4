#pragma once
// Independent answers for the GJK distance and overlap tests: brute-force distances between
// the cores of placed shapes in double precision, Box2D 2.4's b2Distance as a peer, and random
// shapes of every 2D type.

#include <collide/shape/shape2d.hpp>

#include <box2d/box2d.h>
#include <box2d/b2_distance.h>
#include <glm/vec2.hpp>

#include "support/test_util.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace collide::test {

using DVec2 = glm::dvec2;

/// A shape placed in the world, in double: the convex hull of `points` (1, 2 or n >= 3
/// counter-clockwise) grown by `radius`.
struct WorldCore {
  std::vector<DVec2> points;
  double radius = 0.0;
};

inline DVec2 place(const Transform& xf, Vec2 p) {
  const double c = xf.q.c, s = xf.q.s;
  return {double(xf.p.x) + c * p.x - s * p.y, double(xf.p.y) + s * p.x + c * p.y};
}

inline WorldCore world_core(const Shape2D& shape, const Transform& xf) {
  WorldCore w;
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Circle>) {
          w.points = {place(xf, s.center)};
          w.radius = s.radius;
        } else if constexpr (std::is_same_v<S, Capsule>) {
          w.points = {place(xf, s.a), place(xf, s.b)};
          w.radius = s.radius;
        } else if constexpr (std::is_same_v<S, Segment>) {
          w.points = {place(xf, s.a), place(xf, s.b)};
        } else {
          for (int i = 0; i < s.count; ++i) w.points.push_back(place(xf, s.vertices[i]));
          w.radius = s.radius;
        }
      },
      shape);
  return w;
}

inline double dcross(DVec2 a, DVec2 b) { return a.x * b.y - a.y * b.x; }
inline double ddot(DVec2 a, DVec2 b) { return a.x * b.x + a.y * b.y; }

/// Distance from x to segment [p, q] (double).
inline double point_segment_distance(DVec2 x, DVec2 p, DVec2 q) {
  const DVec2 d = q - p;
  const double dd = ddot(d, d);
  const double t = dd > 0.0 ? std::clamp(ddot(x - p, d) / dd, 0.0, 1.0) : 0.0;
  const DVec2 c = p + t * d;
  return std::hypot(x.x - c.x, x.y - c.y);
}

/// True when x is inside or on the convex counter-clockwise polygon (n >= 3).
inline bool polygon_contains(const std::vector<DVec2>& poly, DVec2 x) {
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    if (dcross(poly[(i + 1) % n] - poly[i], x - poly[i]) < 0.0) return false;
  }
  return true;
}

/// True when closed segments [p1, q1] and [p2, q2] properly cross (strict orientation test).
inline bool segments_cross(DVec2 p1, DVec2 q1, DVec2 p2, DVec2 q2) {
  const double o1 = dcross(q1 - p1, p2 - p1), o2 = dcross(q1 - p1, q2 - p1);
  const double o3 = dcross(q2 - p2, p1 - p2), o4 = dcross(q2 - p2, q1 - p2);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

/// Brute-force distance between the convex hulls of two point sets (double): 0 if they
/// intersect (an edge crosses an edge or a point lies inside the other polygon), else the
/// minimum over all point-vs-edge distances of both.
inline double brute_core_distance(const std::vector<DVec2>& a, const std::vector<DVec2>& b) {
  const size_t na = a.size(), nb = b.size();
  if (na >= 3) {
    for (DVec2 x : b) {
      if (polygon_contains(a, x)) return 0.0;
    }
  }
  if (nb >= 3) {
    for (DVec2 x : a) {
      if (polygon_contains(b, x)) return 0.0;
    }
  }
  for (size_t i = 0; i < na; ++i) {
    for (size_t j = 0; j < nb; ++j) {
      if (segments_cross(a[i], a[(i + 1) % na], b[j], b[(j + 1) % nb])) return 0.0;
    }
  }
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < na; ++i) {
    for (size_t j = 0; j < nb; ++j) {
      best = std::min(best, point_segment_distance(a[i], b[j], b[(j + 1) % nb]));
      best = std::min(best, point_segment_distance(b[j], a[i], a[(i + 1) % na]));
    }
  }
  return best;
}

/// Distance from a point to the hull of a point set (0 inside).
inline double brute_point_distance(const std::vector<DVec2>& hull, DVec2 x) {
  return brute_core_distance(hull, {x});
}

/// Box2D 2.4's core distance (radii not applied) between two shapes placed by xa and xb.
inline double box2d_core_distance(const Shape2D& a, const Transform& xa, const Shape2D& b,
                                  const Transform& xb) {
  auto verts = [](const Shape2D& s) {
    std::vector<b2Vec2> v;
    std::visit(
        [&](const auto& sh) {
          using S = std::decay_t<decltype(sh)>;
          if constexpr (std::is_same_v<S, Circle>) {
            v = {b2Vec2(sh.center.x, sh.center.y)};
          } else if constexpr (std::is_same_v<S, Polygon>) {
            for (int i = 0; i < sh.count; ++i) v.emplace_back(sh.vertices[i].x, sh.vertices[i].y);
          } else {
            v = {b2Vec2(sh.a.x, sh.a.y), b2Vec2(sh.b.x, sh.b.y)};
          }
        },
        s);
    return v;
  };
  const std::vector<b2Vec2> va = verts(a), vb = verts(b);
  b2DistanceInput in;
  in.proxyA.Set(va.data(), static_cast<int32>(va.size()), 0.0f);
  in.proxyB.Set(vb.data(), static_cast<int32>(vb.size()), 0.0f);
  in.transformA.p.Set(xa.p.x, xa.p.y);
  in.transformA.q.c = xa.q.c;
  in.transformA.q.s = xa.q.s;
  in.transformB.p.Set(xb.p.x, xb.p.y);
  in.transformB.q.c = xb.q.c;
  in.transformB.q.s = xb.q.s;
  in.useRadii = false;
  b2SimplexCache cache;
  cache.count = 0;
  b2DistanceOutput out;
  b2Distance(&out, &cache, &in);
  return out.distance;
}

/// Rounding radius of any shape (0 for a segment).
inline float shape_radius(const Shape2D& s) {
  return std::visit(
      [](const auto& sh) -> float {
        if constexpr (requires { sh.radius; }) {
          return sh.radius;
        } else {
          return 0.0f;
        }
      },
      s);
}

/// A random shape of the given type, about `size` across: circles and capsules with radius
/// in [0.1, 0.5] size, polygons with 3..8 vertices (a third of them rounded).
inline Shape2D random_shape(std::mt19937& rng, ShapeType2D type, float size) {
  switch (type) {
    case ShapeType2D::circle:
      return make_circle(random_point(rng, 0.2f * size), uniform(rng, 0.1f, 0.5f) * size);
    case ShapeType2D::capsule: {
      const Vec2 c = random_point(rng, 0.2f * size);
      const float ang = uniform(rng, -kPi, kPi);
      const Vec2 h = 0.5f * size * uniform(rng, 0.3f, 1.0f) * Vec2{std::cos(ang), std::sin(ang)};
      return make_capsule(c - h, c + h, uniform(rng, 0.1f, 0.4f) * size);
    }
    case ShapeType2D::segment: {
      const Vec2 c = random_point(rng, 0.2f * size);
      const float ang = uniform(rng, -kPi, kPi);
      const Vec2 h = 0.5f * size * uniform(rng, 0.5f, 1.0f) * Vec2{std::cos(ang), std::sin(ang)};
      return make_segment(c - h, c + h);
    }
    case ShapeType2D::polygon:
    default: {
      const int n = 3 + static_cast<int>(rng() % 6);
      const float r = rng() % 3 == 0 ? uniform(rng, 0.05f, 0.3f) * size : 0.0f;
      return random_polygon(rng, n, 0.5f * size, r);
    }
  }
}

inline constexpr ShapeType2D kAllTypes2D[] = {ShapeType2D::circle, ShapeType2D::capsule,
                                              ShapeType2D::polygon, ShapeType2D::segment};

inline const char* type_label(ShapeType2D t) {
  constexpr const char* names[] = {"circle", "capsule", "polygon", "segment"};
  return names[static_cast<int>(t)];
}

/// A pair placed so that about half the draws overlap.
struct Scene {
  Shape2D a, b;
  Transform xa, xb;
};

/// Rough reach of a random shape of each type from its origin: placement scales with it.
inline float reach(ShapeType2D t) {
  constexpr float kReach[] = {0.35f, 0.55f, 0.5f, 0.15f};
  return kReach[static_cast<int>(t)];
}

/// Shapes about 1 unit across (random_shape), B placed near A so that about half overlap.
inline Scene random_scene(std::mt19937& rng, ShapeType2D ta, ShapeType2D tb) {
  Scene s{random_shape(rng, ta, 1.0f), random_shape(rng, tb, 1.0f), {}, {}};
  s.xa = random_transform(rng, 1.0f);
  const float extent = reach(ta) + reach(tb);
  s.xb = Transform::from(s.xa.p + random_point(rng, extent), uniform(rng, -kPi, kPi));
  return s;
}

}  // namespace collide::test
