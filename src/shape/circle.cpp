#include <collide/shape/circle.hpp>

#include <collide/core/error.hpp>

#include <cmath>
#include <string>

namespace collide {

Circle make_circle(Vec2 center, float radius) {
  if (!is_finite(center)) throw InvalidInput("circle center: not finite");
  if (!std::isfinite(radius)) throw InvalidInput("circle radius: not finite");
  if (radius < 0.0f) {
    throw InvalidInput("circle radius: negative (" + std::to_string(radius) + ")");
  }
  return {center, radius};
}

Aabb compute_aabb(const Circle& circle, const Transform& xf) noexcept {
  const Vec2 c = transform_point(xf, circle.center);
  const Vec2 r{circle.radius, circle.radius};
  return {c - r, c + r};
}

}  // namespace collide
