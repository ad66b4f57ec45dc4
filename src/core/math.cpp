// Out-of-line helpers of collide/core/math.hpp.

#include <collide/core/math.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace collide {

namespace {

/// The power of two that takes a largest component `m` (> 0, finite) into [1, 2).
[[nodiscard]] int unit_exponent(float m) noexcept { return -std::ilogb(m); }

}  // namespace

Vec2 scaled_to_unit_magnitude(Vec2 a) noexcept {
  const float m = max_abs(a);
  if (!(m > 0.0f) || !std::isfinite(m)) return Vec2(std::numeric_limits<float>::quiet_NaN());
  const int e = unit_exponent(m);
  return {std::scalbn(a.x, e), std::scalbn(a.y, e)};
}

Vec3 scaled_to_unit_magnitude(Vec3 a) noexcept {
  const float m = max_abs(a);
  if (!(m > 0.0f) || !std::isfinite(m)) return Vec3(std::numeric_limits<float>::quiet_NaN());
  const int e = unit_exponent(m);
  return {std::scalbn(a.x, e), std::scalbn(a.y, e), std::scalbn(a.z, e)};
}

glm::dvec3 scaled_to_unit_magnitude(const glm::dvec3& a) noexcept {
  const double m = std::max(std::max(std::abs(a.x), std::abs(a.y)), std::abs(a.z));
  if (!(m > 0.0) || !std::isfinite(m)) return glm::dvec3(std::numeric_limits<double>::quiet_NaN());
  const int e = -std::ilogb(m);
  return {std::scalbn(a.x, e), std::scalbn(a.y, e), std::scalbn(a.z, e)};
}

}  // namespace collide
