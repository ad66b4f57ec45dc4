#pragma once
// Shared test helpers: glm-aware EXPECT macros and seeded random shapes.

#include <collide/core/transform.hpp>
#include <collide/shape/polygon.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#define EXPECT_VEC2_NEAR(a, b, tol)                                         \
  do {                                                                      \
    const ::collide::Vec2 ev_a = (a);                                       \
    const ::collide::Vec2 ev_b = (b);                                       \
    EXPECT_LE(::collide::distance(ev_a, ev_b), (tol))                       \
        << #a " = (" << ev_a.x << ", " << ev_a.y << "), " #b " = (" << ev_b.x \
        << ", " << ev_b.y << ")";                                           \
  } while (false)

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
