// collide/core/math.hpp: scaled_to_unit_magnitude, unit_from, normalize_or_zero.

#include <collide/core/math.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace collide {
namespace {

// Scaled by a power of two (so exactly: each component's ratio to the others kept to the bit)
// to a largest component in [1, 2), from subnormal to near-overflow magnitudes; NaN without a
// direction.
TEST(Math, ScaledToUnitMagnitudeKeepsTheDirectionExactly) {
  for (const float m : {1.4e-45f, 3e-39f, 1.35525672e-19f, 0.7f, 1.0f, 1.999f, 2.0f, 3e7f, 3e38f}) {
    const Vec3 a(m, -0.375f * m, 0.0625f * m);
    const Vec3 u = scaled_to_unit_magnitude(a);
    ASSERT_GE(max_abs(u), 1.0f) << m;
    ASSERT_LT(max_abs(u), 2.0f) << m;
    // The same power of two on every component: the ratios of a's representable components.
    const float scale = u.x / a.x;
    EXPECT_EQ(std::exp2(std::round(std::log2(double(scale)))), double(scale)) << m;
    if (a.y != 0.0f && std::isnormal(a.y)) EXPECT_EQ(u.y, a.y * scale) << m;
    if (a.z != 0.0f && std::isnormal(a.z)) EXPECT_EQ(u.z, a.z * scale) << m;
    const Vec2 u2 = scaled_to_unit_magnitude(Vec2(a.x, a.y));
    EXPECT_EQ(u2.x, u.x) << m;
  }
  EXPECT_TRUE(std::isnan(scaled_to_unit_magnitude(Vec3(0.0f)).x));
  EXPECT_TRUE(std::isnan(scaled_to_unit_magnitude(Vec3(1.0f, std::numeric_limits<float>::infinity(), 0.0f)).x));
  EXPECT_TRUE(std::isnan(scaled_to_unit_magnitude(Vec2(std::numeric_limits<float>::quiet_NaN(), 1.0f)).y));
  // In double: a float triangle's area normal can be 1e-90 or 1e77 long.
  for (const double m : {1e-300, 1e-90, 3e-39, 0.7, 1.0, 2.0, 1e77, 1.7e308}) {
    const glm::dvec3 a(-0.375 * m, m, 0.0625 * m);
    const glm::dvec3 u = scaled_to_unit_magnitude(a);
    ASSERT_GE(std::max({std::abs(u.x), std::abs(u.y), std::abs(u.z)}), 1.0) << m;
    ASSERT_LT(std::max({std::abs(u.x), std::abs(u.y), std::abs(u.z)}), 2.0) << m;
    const double scale = u.y / a.y;
    EXPECT_EQ(std::exp2(std::round(std::log2(scale))), scale) << m;
    if (std::isnormal(a.x)) EXPECT_EQ(u.x, a.x * scale) << m;
    if (std::isnormal(a.z)) EXPECT_EQ(u.z, a.z * scale) << m;
  }
  EXPECT_TRUE(std::isnan(scaled_to_unit_magnitude(glm::dvec3(0.0)).x));
  EXPECT_TRUE(std::isnan(scaled_to_unit_magnitude(glm::dvec3(1.0, std::numeric_limits<double>::infinity(), 0.0)).x));
}

// Unit to rounding at every magnitude: from a difference whose squared length is subnormal
// (finding 28: a closest-point difference about 1e-20 long came out 0.854 long) to one near
// float's largest (whose square overflows: it came out zero), against the direction in double.
TEST(Math, UnitFromIsUnitAtEveryMagnitude) {
  for (const float m : {1.4e-45f, 1e-40f, 3e-39f, 2.1e-20f, 1e-16f, 1e-15f, 0.7f, 1.0f, 3e7f, 1e15f, 2e19f, 3e38f}) {
    const Vec3 a(0.405174f * m, -2.98e-8f * m, 0.914239f * m);
    // (The direction of `a` as float holds it: at the smallest magnitudes its components round
    // to a few subnormal steps. normalize_or_zero gives zero within kNoDirectionLength.)
    const glm::dvec3 exact = glm::normalize(glm::dvec3(a));
    const bool has_direction = max_abs(a) > kNoDirectionLength;
    EXPECT_EQ(normalize_or_zero(a) == Vec3(0.0f), !has_direction) << m;
    for (const Vec3 u : {unit_from(a, length_squared(a)), has_direction ? normalize_or_zero(a) : unit_from(a, length_squared(a))}) {
      EXPECT_NEAR(double(length(u)), 1.0, 4.0 * FLT_EPSILON) << m;
      EXPECT_NEAR(double(u.x), exact.x, 4.0 * FLT_EPSILON) << m;
      EXPECT_NEAR(double(u.z), exact.z, 4.0 * FLT_EPSILON) << m;
    }
    const Vec2 a2(a.x, a.z);
    const glm::dvec2 exact2 = glm::normalize(glm::dvec2(a2));
    for (const Vec2 u : {unit_from(a2, length_squared(a2)), has_direction ? normalize_or_zero(a2) : unit_from(a2, length_squared(a2))}) {
      EXPECT_NEAR(double(u.x), exact2.x, 4.0 * FLT_EPSILON) << m;
      EXPECT_NEAR(double(u.y), exact2.y, 4.0 * FLT_EPSILON) << m;
    }
  }
  // No direction: within kNoDirectionLength, zero, or not finite.
  EXPECT_EQ(normalize_or_zero(Vec3(1e-31f, 0.0f, -1e-31f)), Vec3(0.0f));
  EXPECT_EQ(normalize_or_zero(Vec3(0.0f)), Vec3(0.0f));
  EXPECT_EQ(normalize_or_zero(Vec3(1.0f, std::numeric_limits<float>::infinity(), 0.0f)), Vec3(0.0f));
  EXPECT_EQ(normalize_or_zero(Vec2(std::numeric_limits<float>::quiet_NaN(), 1.0f)), Vec2(0.0f));
  EXPECT_EQ(normalize_or_zero(Vec3(0.0f, 2e-30f, 0.0f)), Vec3(0.0f, 1.0f, 0.0f));
}

}  // namespace
}  // namespace collide
