#pragma once
// Seeded random inputs shared by the tests and the benchmarks (no GoogleTest here, so bench/
// can include it): points, rotations, transforms and convex polygons. Every function draws from
// the caller's std::mt19937, so a fixed seed gives a fixed workload.

#include <collide/core/transform.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/polygon.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace collide::test {

inline constexpr float kPi = std::numbers::pi_v<float>;

/// Uniform float in [lo, hi).
inline float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

inline Vec2 random_point(std::mt19937& rng, float extent) {
  return {uniform(rng, -extent, extent), uniform(rng, -extent, extent)};
}

inline Transform random_transform(std::mt19937& rng, float extent) {
  return Transform::from(random_point(rng, extent), uniform(rng, -kPi, kPi));
}

inline Vec3 random_point3(std::mt19937& rng, float extent) {
  return {uniform(rng, -extent, extent), uniform(rng, -extent, extent),
          uniform(rng, -extent, extent)};
}

/// A uniformly distributed random rotation (Shoemake, "Uniform random rotations", Graphics
/// Gems III, 1992).
inline Quat random_rotation(std::mt19937& rng) {
  const float u1 = uniform(rng, 0.0f, 1.0f);
  const float u2 = uniform(rng, 0.0f, 2.0f * kPi);
  const float u3 = uniform(rng, 0.0f, 2.0f * kPi);
  const float a = std::sqrt(1.0f - u1);
  const float b = std::sqrt(u1);
  return Quat{a * std::cos(u2), a * std::sin(u2), b * std::sin(u3), b * std::cos(u3)};
}

/// A uniformly distributed random unit vector (rejection from the unit ball).
inline Vec3 random_unit3(std::mt19937& rng) {
  for (;;) {
    const Vec3 v = random_point3(rng, 1.0f);
    const float l = length(v);
    if (l > 0.1f && l <= 1.0f) return v / l;
  }
}

/// A sliver: corners a, b `length` apart in a random direction from a random a within `extent`,
/// and c `width` to the side of the line ab (the float nearest to it, so the width is about
/// that): a cap (c beside ab between its ends) or a needle (c beside a, within 2% of the length).
inline std::array<Vec3, 3> random_sliver(std::mt19937& rng, float extent, float length, float width, bool needle) {
  const Vec3 a = random_point3(rng, extent);
  const Vec3 along = random_unit3(rng) * length;
  Vec3 side = random_unit3(rng);
  side = normalize(side - (dot(side, along) / dot(along, along)) * along);
  const float t = needle ? uniform(rng, 0.0f, 0.02f) : uniform(rng, 0.1f, 0.9f);
  return {a, a + along, a + t * along + width * side};
}

/// A point `height` off the plane of triangle `t` (along its unit normal, made in double),
/// above a random point well inside it (each barycentric weight at least 0.05): over the face,
/// so the nearest point of the triangle is that inside point, |height| away.
inline Vec3 random_point_over(std::mt19937& rng, const std::array<Vec3, 3>& t, double height) {
  const glm::dvec3 a(t[0]), b(t[1]), c(t[2]);
  double u = uniform(rng, 0.05f, 0.9f), v = uniform(rng, 0.05f, 0.9f);
  if (u + v > 0.95) u = 0.95 - u, v = 0.95 - v;  // (then both in [0.05, 0.9] again)
  const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
  return Vec3(a + u * (b - a) + v * (c - a) + height * n);
}

inline Transform3 random_transform3(std::mt19937& rng, float extent) {
  return Transform3::from(random_point3(rng, extent), random_rotation(rng));
}

/// A random convex polygon with `n` vertices on a jittered circle of radius ~`size`.
inline Polygon random_polygon(std::mt19937& rng, int n, float size, float radius = 0.0f) {
  std::vector<Vec2> pts;
  const float start = uniform(rng, 0.0f, 2.0f * kPi);
  for (int i = 0; i < n; ++i) {
    const float angle = start + 2.0f * kPi * (static_cast<float>(i) + uniform(rng, -0.3f, 0.3f)) /
                                    static_cast<float>(n);
    const float r = size * uniform(rng, 0.6f, 1.0f);
    pts.push_back({r * std::cos(angle), r * std::sin(angle)});
  }
  return make_polygon(pts, radius);
}

}  // namespace collide::test
