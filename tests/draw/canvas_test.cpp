// The raster canvas against analytic pixel counts: a shape covers about its area in pixels.
#include <collide/core/error.hpp>
#include <collide/draw/canvas.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace collide {
namespace {

constexpr Color kInk{200, 10, 10, 255};

int count(const Canvas& c, Color color) {
  int n = 0;
  for (int y = 0; y < c.height(); ++y) {
    for (int x = 0; x < c.width(); ++x) n += c.pixel(x, y) == color;
  }
  return n;
}

TEST(Canvas, FilledTriangleCoversItsAreaEitherWinding) {
  for (bool flip : {false, true}) {
    Canvas c(200, 200);
    const Vec2 a{10.3f, 20.7f}, b{180.2f, 40.1f}, d{60.5f, 170.9f};
    flip ? c.fill_triangle(a, d, b, kInk) : c.fill_triangle(a, b, d, kInk);
    const float area = 0.5f * std::fabs(cross(b - a, d - a));
    const float perimeter = distance(a, b) + distance(b, d) + distance(d, a);
    EXPECT_NEAR(static_cast<float>(count(c, kInk)), area, perimeter);  // error is at most the edge pixels
    EXPECT_EQ(c.pixel(83, 77), kInk);                  // near the centroid
    EXPECT_EQ(c.pixel(190, 190), (Color{255, 255, 255, 255}));  // outside
  }
}

TEST(Canvas, CircleAndLineCoverTheirAreas) {
  Canvas c(100, 100);
  c.fill_circle({50.0f, 50.0f}, 20.0f, kInk);
  EXPECT_NEAR(count(c, kInk), 3.14159f * 400.0f, 2.0f * 3.14159f * 20.0f);
  Canvas l(100, 100);
  l.draw_line({10.0f, 10.5f}, {90.0f, 10.5f}, kInk, 3.0f);  // 80 long, 3 wide, round caps
  EXPECT_NEAR(count(l, kInk), 80.0f * 3.0f + 3.14159f * 2.25f, 12.0f);
  EXPECT_EQ(l.pixel(10, 10), kInk);
  EXPECT_EQ(l.pixel(89, 10), kInk);
  EXPECT_NE(l.pixel(50, 14), kInk);
}

TEST(Canvas, ShapesAreClippedAndTranslucentInkBlends) {
  Canvas c(10, 10, {0, 0, 0, 255});
  c.fill_circle({-100.0f, -100.0f}, 500.0f, {255, 255, 255, 128});  // covers everything, off-canvas centre
  EXPECT_EQ(c.pixel(9, 9), (Color{128, 128, 128, 255}));
  c.draw_line({-1e30f, 5.5f}, {1e30f, 5.5f}, kInk);  // huge coordinates: clipped, no int overflow
  EXPECT_EQ(c.pixel(0, 5), kInk);
  c.fill_triangle({NAN, 0.0f}, {5.0f, 5.0f}, {0.0f, 5.0f}, kInk);  // NaN draws nothing, no crash
  EXPECT_THROW(Canvas(0, 10), InvalidInput);
  EXPECT_THROW(Canvas(10, kMaxCanvasSide + 1), InvalidInput);
}

}  // namespace
}  // namespace collide
