// Pictures of signed distance fields (draw/field_picture.hpp): the marching-squares contour of an
// analytic circle lies on the circle, saddles and flat fields come out right, and the PNG has the
// inside colour inside, the outside colour outside, the zero contour's ink on the circle (y up and
// y down), and the size it reports. Bad slices throw.
#include "support/picture_checks.hpp"

#include <collide/core/error.hpp>
#include <collide/draw/field_picture.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace collide {
namespace {

/// A circle's exact signed distance sampled on a grid: |p - centre| - radius.
struct CircleField {
  Vec2 centre{0.0f};
  float radius = 1.0f;
  std::vector<float> values;
  FieldSlice slice;

  CircleField(Vec2 c, float r, Vec2 origin, float spacing, int width, int height) : centre(c), radius(r) {
    for (int j = 0; j < height; ++j) {
      for (int i = 0; i < width; ++i) {
        const Vec2 p = origin + spacing * Vec2{static_cast<float>(i), static_cast<float>(j)};
        values.push_back(glm::length(p - c) - r);
      }
    }
    slice = FieldSlice{values, width, height, spacing, origin};
  }
};

TEST(FieldPicture, TheContourOfACircleFieldLiesOnTheCircle) {
  const CircleField f({1.0f, -2.0f}, 3.0f, {-4.0f, -7.0f}, 0.25f, 41, 41);
  const auto segments = contour_segments(f.slice, 0.0f);
  // The circle's circumference in cells: about 2 pi r / spacing segments.
  EXPECT_GT(segments.size(), 60u);
  // Between samples the distance is bilinear, not exact: the chord sag of a cell, spacing^2 / (8 r)
  // per axis, bounds the error of a crossing.
  const float tolerance = 0.25f * 0.25f / (8.0f * 3.0f) * 2.0f;
  for (const auto& s : segments) {
    for (const Vec2 p : s) EXPECT_NEAR(glm::length(p - f.centre), f.radius, tolerance) << p.x << " " << p.y;
  }
  // The contour at a level is the circle of radius r + level.
  for (const auto& s : contour_segments(f.slice, 1.0f)) {
    EXPECT_NEAR(glm::length(s[0] - f.centre), f.radius + 1.0f, tolerance);
  }
}

TEST(FieldPicture, SaddleCellsAndFlatFields) {
  // Opposite corners below zero; the centre (mean 0.25 > 0) is above: two segments, each cutting
  // off one corner below.
  const std::vector<float> values = {-1.0f, 1.5f, 1.5f, -1.0f};  // (0,0) (1,0) / (0,1) (1,1)
  const FieldSlice s{values, 2, 2, 1.0f, {0.0f, 0.0f}};
  const auto segments = contour_segments(s, 0.0f);
  ASSERT_EQ(segments.size(), 2u);
  for (const auto& seg : segments) {
    // Each segment stays near its corner (0,0) or (1,1): both ends within 0.5 of it.
    const Vec2 corner = glm::length(seg[0]) < 1.0f ? Vec2{0.0f, 0.0f} : Vec2{1.0f, 1.0f};
    EXPECT_LE(glm::length(seg[0] - corner), 0.5f);
    EXPECT_LE(glm::length(seg[1] - corner), 0.5f);
  }
  const std::vector<float> flat(9, 2.0f);
  EXPECT_TRUE(contour_segments(FieldSlice{flat, 3, 3, 1.0f, {0.0f, 0.0f}}, 0.0f).empty());
  EXPECT_THROW((void)contour_segments(FieldSlice{flat, 4, 3, 1.0f, {0.0f, 0.0f}}, 0.0f), InvalidInput);
  EXPECT_THROW((void)contour_segments(FieldSlice{flat, 3, 3, 0.0f, {0.0f, 0.0f}}, 0.0f), InvalidInput);
}

/// True when `c` is closer to `a` than to `b` in the sum of channel differences.
bool nearer(Color c, Color a, Color b) {
  const auto gap = [&](Color x) { return std::abs(c.r - x.r) + std::abs(c.g - x.g) + std::abs(c.b - x.b); };
  return gap(a) < gap(b);
}

TEST(FieldPicture, InsideIsBlueOutsideOrangeAndTheSurfaceInkedWhereTheCircleIs) {
  for (const bool down : {false, true}) {
    // A circle off the slice's centre, so y up and y down differ.
    const CircleField f({3.0f, 6.5f}, 2.0f, {0.0f, 0.0f}, 0.1f, 101, 101);
    FieldPictureOptions o;
    o.title = "circle";
    o.size = 400;
    o.vertical_down = down;
    const std::string path = ::testing::TempDir() + "collide_field_picture_test.png";
    std::filesystem::remove(path);
    const FieldPictureSize size = save_field_picture(f.slice, o, path);
    const test::PngImage image = test::read_png(path);
    ASSERT_EQ(image.width, size.width);
    ASSERT_EQ(image.height, size.height);
    ASSERT_EQ(size.plot_width, 400);
    ASSERT_EQ(size.plot_height, 400);
    const float scale = 400.0f / 10.0f;  // pixels per unit: the slice is 10 x 10
    const auto pixel = [&](Vec2 w) {
      const float y = down ? w.y * scale : 400.0f - w.y * scale;
      return Vec2{static_cast<float>(size.plot_left) + w.x * scale, static_cast<float>(size.plot_top) + y};
    };
    EXPECT_TRUE(nearer(image.at(pixel(f.centre)), kFieldInside, kFieldOutside)) << "down " << down;
    EXPECT_TRUE(nearer(image.at(pixel({3.0f, 3.0f})), kFieldOutside, kFieldInside)) << "down " << down;
    EXPECT_TRUE(nearer(image.at(pixel({8.0f, 9.0f})), kFieldOutside, kFieldInside)) << "down " << down;
    // The zero contour's dark ink on the circle, at 8 points around it.
    for (int k = 0; k < 8; ++k) {
      const float a = static_cast<float>(k) * 0.785398f;
      const Color c = image.at(pixel(f.centre + f.radius * Vec2{std::cos(a), std::sin(a)}));
      EXPECT_LT(c.r + c.g + c.b, 3 * 110) << "angle " << a << " down " << down;
    }
  }
}

TEST(FieldPicture, BadSizesAndPathsThrow) {
  const CircleField f({0.0f, 0.0f}, 1.0f, {-2.0f, -2.0f}, 0.5f, 9, 9);
  FieldPictureOptions o;
  o.size = 8;
  EXPECT_THROW((void)save_field_picture(f.slice, o, ::testing::TempDir() + "x.png"), InvalidInput);
  o.size = 100;
  EXPECT_THROW((void)save_field_picture(f.slice, o, "/no/such/folder/x.png"), InvalidInput);
}

}  // namespace
}  // namespace collide
