#include <collide/core/aabb.hpp>
#include <collide/core/error.hpp>
#include <collide/core/transform.hpp>

#include "support/test_util.hpp"

namespace collide {
namespace {

TEST(Transform, InverseUndoesTransformUnderRandomRigidMotions) {
  std::mt19937 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Transform a = test::random_transform(rng, 1e4f);
    const Transform b = test::random_transform(rng, 10.0f);
    const Vec2 p = test::random_point(rng, 10.0f);
    const float kTol = 4e-7f * 2e4f;  // a few ulps at coordinates up to 2e4
    EXPECT_VEC2_NEAR(inv_transform_point(a, transform_point(a, p)), p, kTol);
    // (a^-1 b) applied to p equals a^-1 (b p).
    EXPECT_VEC2_NEAR(transform_point(inv_mul(a, b), p),
                     inv_transform_point(a, transform_point(b, p)), kTol);
    EXPECT_VEC2_NEAR(transform_point(mul(a, b), p), transform_point(a, transform_point(b, p)),
                     kTol);
  }
}

TEST(Transform, AngleRoundTripsAndValidityRejectsNaN) {
  const Rot2 q = Rot2::from_angle(1.25f);
  EXPECT_NEAR(q.angle(), 1.25f, 1e-6f);
  EXPECT_TRUE(is_valid(Transform::from({1, 2}, 0.3f)));
  Transform bad;
  bad.p.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(is_valid(bad));
  bad = Transform{};
  bad.q.c = 2.0f;
  EXPECT_FALSE(is_valid(bad));
}

TEST(Aabb, ClosedOverlapCountsTouchingAndNaNFailsSafe) {
  const Aabb a{{0, 0}, {1, 1}};
  EXPECT_TRUE(overlap(a, Aabb{{1, 1}, {2, 2}}));
  EXPECT_FALSE(overlap(a, Aabb{{1.0001f, 0}, {2, 1}}));
  EXPECT_FALSE(overlap(a, Aabb{{std::numeric_limits<float>::quiet_NaN(), 0}, {2, 1}}));
  const Aabb3 b{{0, 0, 0}, {1, 2, 3}};
  EXPECT_FLOAT_EQ(surface_metric(b), 2.0f * (2 + 6 + 3));
  EXPECT_TRUE(contains(b, Vec3(1, 2, 3)));
  EXPECT_FALSE(is_valid(Aabb{{1, 0}, {0, 1}}));
}

bool g_called = false;
bool counting_handler(const char*, const char*, const char*, int) {
  g_called = true;
  return true;
}

TEST(Assert, HandlerCanBeReplaced) {
  const AssertHandler old = set_assert_handler(&counting_handler);
  EXPECT_TRUE(report_assert_failure("x", "y", __FILE__, __LINE__));
  EXPECT_TRUE(g_called);
  EXPECT_EQ(set_assert_handler(old), &counting_handler);
}

TEST(Transform3, ComposesInvertsAndMatchesItsMatrixForm) {
  std::mt19937 rng(7);
  for (int i = 0; i < 200; ++i) {
    const Transform3 a = test::random_transform3(rng, 100.0f);
    const Transform3 b = test::random_transform3(rng, 100.0f);
    const Vec3 p = test::random_point3(rng, 10.0f);
    // (a * b) p == a (b p); a^-1 b == the frame of b seen from a.
    EXPECT_VEC3_NEAR(transform_point(mul(a, b), p), transform_point(a, transform_point(b, p)), 1e-3f);
    EXPECT_VEC3_NEAR(transform_point(inv_mul(a, b), p),
                     inv_transform_point(a, transform_point(b, p)), 1e-3f);
    EXPECT_VEC3_NEAR(inv_transform_point(a, transform_point(a, p)), p, 1e-4f);
    const Frame3 f = Frame3::from(a);
    EXPECT_VEC3_NEAR(transform_point(f, p), transform_point(a, p), 1e-4f);
    EXPECT_VEC3_NEAR(inv_transform_point(f, transform_point(a, p)), p, 1e-4f);
    EXPECT_VEC3_NEAR(inv_rotate(f, rotate(a.q, p)), p, 1e-5f);
    EXPECT_TRUE(is_valid(a));
  }
}

TEST(Transform3, AxisAngleTurnsCounterClockwiseAndValidityRejectsBadInput) {
  // A quarter turn about +z takes +x to +y (right-handed).
  const Transform3 q = Transform3::from_axis_angle({1, 2, 3}, {0, 0, 1}, 0.5f * test::kPi);
  EXPECT_VEC3_NEAR(transform_point(q, Vec3(1, 0, 0)), Vec3(1, 3, 3), 1e-6f);
  Transform3 bad;
  bad.p.y = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(is_valid(bad));
  bad = Transform3{};
  bad.q = Quat{1.0f, 0.1f, 0.0f, 0.0f};  // |q|^2 = 1.01
  EXPECT_FALSE(is_valid(bad));
  bad.q.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(is_valid(bad));
}

TEST(Math3, CrossIsRightHandedAndNormalizeOrZeroHandlesZero) {
  EXPECT_EQ(cross(Vec3(1, 0, 0), Vec3(0, 1, 0)), Vec3(0, 0, 1));
  EXPECT_FLOAT_EQ(dot(Vec3(1, 2, 3), Vec3(4, 5, 6)), 32.0f);
  EXPECT_EQ(normalize_or_zero(Vec3(0.0f)), Vec3(0.0f));
  EXPECT_FLOAT_EQ(length(normalize_or_zero(Vec3(3, 4, 12))), 1.0f);
  EXPECT_FLOAT_EQ(max_abs(Vec3(1, -7, 3)), 7.0f);
}

}  // namespace
}  // namespace collide
