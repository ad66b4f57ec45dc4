#pragma once
// Random convex 3D shapes for randomised tests, one home for every test folder.

#include <collide/shape/convex_hull.hpp>
#include <collide/shape/shape3d.hpp>

#include "support/random.hpp"

#include <random>
#include <vector>

namespace collide::test {

/// A random convex hull of `n` points in an ellipsoid of semi-axes about `size`, optionally
/// rounded.
inline ConvexHull random_hull(std::mt19937& rng, int n, float size, float radius = 0.0f) {
  const Vec3 axes(uniform(rng, 0.3f, 1.0f) * size, uniform(rng, 0.3f, 1.0f) * size,
                  uniform(rng, 0.3f, 1.0f) * size);
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < n) {
    const Vec3 p = random_point3(rng, 1.0f);
    if (dot(p, p) <= 1.0f) points.push_back(p * axes);
  }
  return make_convex_hull(points, HullOptions{radius});
}

/// The benchmarks' box-or-capsule: kind 0 a box of half extents 0.2..0.8; kind 1 a capsule
/// 0.4..1.6 long in a random direction, radius 0.1..0.4.
inline Shape3D random_box_or_capsule(std::mt19937& rng, int kind) {
  if (kind == 0) {
    return make_box({uniform(rng, 0.2f, 0.8f), uniform(rng, 0.2f, 0.8f), uniform(rng, 0.2f, 0.8f)});
  }
  const Vec3 h = uniform(rng, 0.2f, 0.8f) * random_unit3(rng);
  return make_capsule(-h, h, uniform(rng, 0.1f, 0.4f));
}

/// A random convex 3D shape of about `size` (centred near the local origin): sphere, capsule,
/// segment, box, rounded box, hull or rounded hull.
inline Shape3D random_shape3(std::mt19937& rng, float size = 1.0f) {
  switch (std::uniform_int_distribution<int>(0, 6)(rng)) {
    case 0: return make_sphere(random_point3(rng, 0.2f * size), uniform(rng, 0.1f, 1.0f) * size);
    case 1:
      return make_capsule(random_point3(rng, size), random_point3(rng, size),
                          uniform(rng, 0.05f, 0.5f) * size);
    case 2: return make_segment(random_point3(rng, size), random_point3(rng, size));
    case 3:
      return make_box({uniform(rng, 0.1f, 1.0f) * size, uniform(rng, 0.1f, 1.0f) * size,
                       uniform(rng, 0.1f, 1.0f) * size});
    case 4:
      return make_box({uniform(rng, 0.1f, 1.0f) * size, uniform(rng, 0.1f, 1.0f) * size,
                       uniform(rng, 0.1f, 1.0f) * size},
                      uniform(rng, 0.01f, 0.3f) * size);
    case 5: return random_hull(rng, std::uniform_int_distribution<int>(4, 40)(rng), size);
    default:
      return random_hull(rng, std::uniform_int_distribution<int>(4, 20)(rng), size,
                         uniform(rng, 0.01f, 0.2f) * size);
  }
}

}  // namespace collide::test
