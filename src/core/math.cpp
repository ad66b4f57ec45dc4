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

namespace {

template <class V>
V unit_of_scaled_impl(V a) noexcept {
  const V s = scaled_to_unit_magnitude(a);  // NaN without a direction
  return s * (1.0f / std::sqrt(dot(s, s)));
}

template <class V>
V normalize_scaled_or_zero_impl(V a) noexcept {
  const float m = max_abs(a);
  if (!(m > kNoDirectionLength) || !std::isfinite(m)) return V(0.0f);
  return unit_of_scaled_impl(a);
}

}  // namespace

Vec2 unit_of_scaled(Vec2 a) noexcept { return unit_of_scaled_impl(a); }
Vec3 unit_of_scaled(Vec3 a) noexcept { return unit_of_scaled_impl(a); }
Vec2 normalize_scaled_or_zero(Vec2 a) noexcept { return normalize_scaled_or_zero_impl(a); }
Vec3 normalize_scaled_or_zero(Vec3 a) noexcept { return normalize_scaled_or_zero_impl(a); }

}  // namespace collide
