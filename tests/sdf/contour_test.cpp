// march_squares (sdf/contour.hpp) against an analytic circle: every segment's ends on the
// circle (to within the interpolation's error), the segments closing into one loop of the
// circle's length, a saddle cell resolved by its centre.
#include <collide/sdf/contour.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace collide {
namespace {

TEST(MarchSquares, ACircleComesBackAsOneClosedLoopOnTheCircle) {
  constexpr int kSide = 64;
  constexpr float kSpacing = 0.25f, kRadius = 5.0f;
  const Vec2 origin{-8.0f, -8.0f}, centre{0.3f, -0.2f};
  std::vector<float> values(kSide * kSide);
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i)
      values[j * kSide + i] = glm::length(origin + kSpacing * Vec2(i, j) - centre) - kRadius;
  std::vector<std::pair<Vec2, Vec2>> segments;
  march_squares(
      kSide, kSide, origin, kSpacing, 0.0f, [&](int i, int j) { return values[j * kSide + i]; },
      [&](Vec2 a, Vec2 b) { segments.emplace_back(a, b); });
  ASSERT_GT(segments.size(), 100u);
  float length = 0.0f;
  std::map<std::pair<long, long>, int> ends;  // each end point shared by exactly two segments
  const auto key = [](Vec2 p) { return std::pair{std::lround(p.x * 1e4f), std::lround(p.y * 1e4f)}; };
  for (const auto& [a, b] : segments) {
    // The chord of a circle between two grid lines stays within spacing^2 / (8 r) of it.
    EXPECT_NEAR(glm::length(a - centre), kRadius, 0.01f);
    EXPECT_NEAR(glm::length(b - centre), kRadius, 0.01f);
    length += glm::length(b - a);
    ++ends[key(a)];
    ++ends[key(b)];
  }
  EXPECT_NEAR(length, 2.0f * 3.14159265f * kRadius, 0.01f * kRadius);
  for (const auto& [point, count] : ends) EXPECT_EQ(count, 2);
}

TEST(MarchSquares, ASaddleIsResolvedByItsCentreAndALevelShiftsTheContour) {
  // One cell, corners 0 and 2 below: centre below joins them (segments around corners 1 and 3).
  const float below_centre[4] = {-1.0f, 0.5f, -1.0f, 0.5f};  // mean -0.25
  const float above_centre[4] = {-0.5f, 1.0f, -0.5f, 1.0f};  // mean +0.25
  for (const float* v : {below_centre, above_centre}) {
    std::vector<std::pair<Vec2, Vec2>> segments;
    const auto value = [&](int i, int j) { return v[j == 0 ? i : 3 - i]; };  // corners counter-clockwise
    march_squares(2, 2, Vec2{0.0f}, 1.0f, 0.0f, value, [&](Vec2 a, Vec2 b) { segments.emplace_back(a, b); });
    ASSERT_EQ(segments.size(), 2u);
    // Each segment cuts off one corner: the corner it cuts off lies on the other side of it
    // from the centre when that corner's sign differs from the centre's.
    const bool centre_below = v == below_centre;
    for (const auto& [a, b] : segments) {
      const Vec2 mid = 0.5f * (a + b);
      const Vec2 corner{std::round(mid.x), std::round(mid.y)};
      const float corner_value = value(static_cast<int>(corner.x), static_cast<int>(corner.y));
      EXPECT_NE(corner_value < 0.0f, centre_below) << "cut off a corner on the centre's side";
    }
  }
  // A level moves the contour: values 0..3 along x, level 1.5: the crossing at x = 1.5 of 3.
  int count = 0;
  march_squares(
      2, 2, Vec2{0.0f}, 3.0f, 1.5f, [](int i, int) { return 3.0f * static_cast<float>(i); },
      [&](Vec2 a, Vec2 b) {
        ++count;
        EXPECT_FLOAT_EQ(a.x, 1.5f);
        EXPECT_FLOAT_EQ(b.x, 1.5f);
      });
  EXPECT_EQ(count, 1);
}

}  // namespace
}  // namespace collide
