#include <collide/shape/capsule.hpp>

#include "axis_length.hpp"

#include <collide/core/error.hpp>

#include <cmath>
#include <string>

namespace collide {

Capsule make_capsule(Vec2 a, Vec2 b, float radius) {
  if (!is_finite(a)) throw InvalidInput("capsule a: not finite");
  if (!is_finite(b)) throw InvalidInput("capsule b: not finite");
  if (!std::isfinite(radius)) throw InvalidInput("capsule radius: not finite");
  if (radius < 0.0f) {
    throw InvalidInput("capsule radius: negative (" + std::to_string(radius) + ")");
  }
  detail::check_axis(a, b, "capsule", " (use a circle)");
  return {a, b, radius};
}

Aabb compute_aabb(const Capsule& capsule, const Transform& xf) noexcept {
  const Vec2 a = transform_point(xf, capsule.a);
  const Vec2 b = transform_point(xf, capsule.b);
  const Vec2 r{capsule.radius, capsule.radius};
  return {glm::min(a, b) - r, glm::max(a, b) + r};
}

}  // namespace collide
