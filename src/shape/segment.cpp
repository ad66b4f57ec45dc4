#include <collide/shape/segment.hpp>

#include "axis_length.hpp"

#include <collide/core/error.hpp>

namespace collide {

Segment make_segment(Vec2 a, Vec2 b) {
  if (!is_finite(a)) throw InvalidInput("segment a: not finite");
  if (!is_finite(b)) throw InvalidInput("segment b: not finite");
  detail::check_axis(a, b, "segment");
  return {a, b};
}

Aabb compute_aabb(const Segment& segment, const Transform& xf) noexcept {
  const Vec2 a = transform_point(xf, segment.a);
  const Vec2 b = transform_point(xf, segment.b);
  return {glm::min(a, b), glm::max(a, b)};
}

}  // namespace collide
