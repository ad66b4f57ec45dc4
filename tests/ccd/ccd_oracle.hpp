#pragma once
// Independent truths for the continuous collision tests: Box2D 2.4's GJK distance on proxies
// built from our shapes' exact core points (b2PolygonShape would add b2_polygonRadius), dense
// sampling of the motion, and random shapes of every 2D type.

#include <collide/ccd/sweep.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/shape2d.hpp>

#include "support/test_util.hpp"

#include <box2d/b2_distance.h>
#include <box2d/b2_time_of_impact.h>
#include <box2d/box2d.h>

#include <algorithm>
#include <array>
#include <random>

namespace collide::test {

/// A Box2D distance proxy with the same core points and radius as a collide proxy.
struct B2Proxy {
  std::array<b2Vec2, kMaxPolygonVertices> points{};
  b2DistanceProxy proxy;

  explicit B2Proxy(const ConvexProxy& p) {
    for (int i = 0; i < p.count(); ++i) points[i].Set(p.point(i).x, p.point(i).y);
    proxy.Set(points.data(), p.count(), p.radius());
  }
  B2Proxy(const B2Proxy&) = delete;
  B2Proxy& operator=(const B2Proxy&) = delete;
};

inline b2Transform to_b2(const Transform& xf) {
  b2Transform x;
  x.p.Set(xf.p.x, xf.p.y);
  x.q.s = xf.q.s;
  x.q.c = xf.q.c;
  return x;
}

/// Distance between the two shapes (radii applied, 0 when they touch or overlap), Box2D's GJK.
inline float b2_distance(const B2Proxy& a, const Transform& xa, const B2Proxy& b,
                         const Transform& xb) {
  b2DistanceInput in;
  in.proxyA = a.proxy;
  in.proxyB = b.proxy;
  in.transformA = to_b2(xa);
  in.transformB = to_b2(xb);
  in.useRadii = true;
  b2SimplexCache cache;
  cache.count = 0;
  b2DistanceOutput out;
  b2Distance(&out, &cache, &in);
  return out.distance;
}

/// The truth about two translating shapes, from Box2D distances: dense samples, then golden
/// section on the distance (convex in t for translating convex shapes), then bisection for the
/// first time the shapes touch. Works in a frame where A starts at the origin (the offset taken
/// in double) so the oracle stays precise far from the origin.
struct TranslationTruth {
  bool touches = false;     ///< the distance reaches 0 during [0, 1]
  float t_first = 1.0f;     ///< first time the distance is 0 (when touches)
  float min_distance = 0;   ///< smallest distance over [0, 1]
  Transform xa;             ///< A's start, shifted frame
  Transform xb;             ///< B's start, shifted frame
  Vec2 va;
  Vec2 vb;

  [[nodiscard]] float distance_at(const B2Proxy& a, const B2Proxy& b, float t) const {
    return b2_distance(a, Transform{xa.p + t * va, xa.q}, b, Transform{xb.p + t * vb, xb.q});
  }
};

inline TranslationTruth translation_truth(const ConvexProxy& pa, const Transform& xa, Vec2 va,
                                          const ConvexProxy& pb, const Transform& xb, Vec2 vb,
                                          int samples = 2048) {
  const B2Proxy a(pa);
  const B2Proxy b(pb);
  TranslationTruth truth;
  truth.xa = Transform{{0.0f, 0.0f}, xa.q};
  truth.xb = Transform{Vec2{static_cast<float>(double(xb.p.x) - double(xa.p.x)),
                            static_cast<float>(double(xb.p.y) - double(xa.p.y))},
                       xb.q};
  truth.va = va;
  truth.vb = vb;
  int best = 0;
  float best_d = truth.distance_at(a, b, 0.0f);
  for (int k = 1; k <= samples; ++k) {
    const float d = truth.distance_at(a, b, float(k) / float(samples));
    if (d < best_d) {
      best_d = d;
      best = k;
    }
  }
  // Golden section around the best sample (the distance is convex in t), remembering where the
  // smallest distance was seen.
  double t_best = best / double(samples);
  double lo = std::max(0, best - 1) / double(samples);
  double hi = std::min(samples, best + 1) / double(samples);
  const double g = 0.6180339887498949;
  for (int i = 0; i < 80 && best_d > 0.0f; ++i) {
    const double m1 = hi - g * (hi - lo);
    const double m2 = lo + g * (hi - lo);
    const float d1 = truth.distance_at(a, b, float(m1));
    const float d2 = truth.distance_at(a, b, float(m2));
    if (d1 < best_d) {
      best_d = d1;
      t_best = m1;
    }
    if (d2 < best_d) {
      best_d = d2;
      t_best = m2;
    }
    if (d1 <= d2) {
      hi = m2;
    } else {
      lo = m1;
    }
  }
  const double t_min = t_best;
  truth.min_distance = best_d;
  truth.touches = best_d == 0.0f;
  if (truth.touches) {
    // First zero: the distance is non-increasing on [0, t_min], so touching is monotone there.
    double l = 0.0;
    double h = t_min;
    if (truth.distance_at(a, b, 0.0f) == 0.0f) {
      h = 0.0;
    } else {
      for (int i = 0; i < 64; ++i) {
        const double m = 0.5 * (l + h);
        if (truth.distance_at(a, b, float(m)) == 0.0f) {
          h = m;
        } else {
          l = m;
        }
      }
    }
    truth.t_first = float(h);
  }
  return truth;
}

/// Largest separation of A and B along the unit axis n (A's support along n against B's along
/// -n): negative when the shapes' projections overlap. At a contact the true normal gives ~0.
inline float separation_along(const ConvexProxy& a, const Transform& xa, const ConvexProxy& b,
                              const Transform& xb, Vec2 n) {
  float max_a = -1e30f;
  for (int i = 0; i < a.count(); ++i) max_a = std::max(max_a, dot(transform_point(xa, a.point(i)), n));
  float min_b = 1e30f;
  for (int i = 0; i < b.count(); ++i) min_b = std::min(min_b, dot(transform_point(xb, b.point(i)), n));
  return (min_b - b.radius()) - (max_a + a.radius());
}

/// A random 2D shape of type `type` (0 circle, 1 capsule, 2 polygon, 3 segment, 4 rounded
/// polygon) of about `size`, centred near the local origin.
inline Shape2D random_shape(std::mt19937& rng, int type, float size) {
  switch (type) {
    case 0:
      return make_circle(random_point(rng, 0.2f * size), uniform(rng, 0.3f, 1.0f) * size);
    case 1: {
      const Vec2 d = random_point(rng, size);
      return make_capsule(-d, d + Vec2{0.01f * size, 0.0f}, uniform(rng, 0.1f, 0.5f) * size);
    }
    case 2:
      return random_polygon(rng, 3 + int(rng() % 6), size);
    case 3: {
      const Vec2 d = random_point(rng, size);
      return make_segment(-d, d + Vec2{0.01f * size, 0.0f});
    }
    default:
      return random_polygon(rng, 3 + int(rng() % 6), size, uniform(rng, 0.05f, 0.3f) * size);
  }
}

inline constexpr int kShapeKinds = 5;

}  // namespace collide::test

namespace collide::test {

/// The truth about two shapes moving along sweeps (rotation included), by sub-stepping: Box2D
/// distances at `samples` + 1 even times, the first touching sample refined by bisection
/// against the last apart one.
struct SweepTruth {
  bool touches = false;      ///< some sample has the shapes touching (distance 0)
  float t_first = 1.0f;      ///< first touch (when touches)
  float min_distance = 0.0f; ///< smallest sampled distance
};

inline SweepTruth sweep_truth(const ConvexProxy& pa, const Sweep& sa, const ConvexProxy& pb,
                              const Sweep& sb, int samples = 4000) {
  const B2Proxy a(pa);
  const B2Proxy b(pb);
  SweepTruth truth;
  truth.min_distance = 1e30f;
  for (int k = 0; k <= samples; ++k) {
    const float t = float(k) / float(samples);
    const float d = b2_distance(a, sa.at(t), b, sb.at(t));
    truth.min_distance = std::min(truth.min_distance, d);
    if (d == 0.0f && !truth.touches) {
      truth.touches = true;
      double lo = k == 0 ? 0.0 : double(k - 1) / samples;
      double hi = t;
      if (k == 0) {
        truth.t_first = 0.0f;
        continue;
      }
      for (int i = 0; i < 50; ++i) {
        const double m = 0.5 * (lo + hi);
        if (b2_distance(a, sa.at(float(m)), b, sb.at(float(m))) == 0.0f) {
          hi = m;
        } else {
          lo = m;
        }
      }
      truth.t_first = float(hi);
    }
  }
  return truth;
}

/// Box2D 2.4's b2TimeOfImpact on the same proxies (exact core points) and sweeps.
inline b2TOIOutput b2_time_of_impact(const B2Proxy& a, const Sweep& sa, const B2Proxy& b,
                                     const Sweep& sb) {
  auto to_b2_sweep = [](const Sweep& s) {
    b2Sweep w;
    w.localCenter.Set(s.local_center.x, s.local_center.y);
    w.c0.Set(s.c0.x, s.c0.y);
    w.c.Set(s.c1.x, s.c1.y);
    w.a0 = s.a0;
    w.a = s.a1;
    w.alpha0 = 0.0f;
    return w;
  };
  b2TOIInput in;
  in.proxyA = a.proxy;
  in.proxyB = b.proxy;
  in.sweepA = to_b2_sweep(sa);
  in.sweepB = to_b2_sweep(sb);
  in.tMax = 1.0f;
  b2TOIOutput out;
  b2TimeOfImpact(&out, &in);
  return out;
}

}  // namespace collide::test
