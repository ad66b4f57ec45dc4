// The raster canvas against analytic pixel counts: a shape covers about its area in pixels.
#include <collide/core/error.hpp>
#include <collide/draw/canvas.hpp>

#include <gtest/gtest.h>

#include <array>
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

/// Ink of a black-on-white picture, in pixels: the sum of per-pixel coverage.
float coverage(const Canvas& c) {
  float sum = 0.0f;
  for (int y = 0; y < c.height(); ++y) {
    for (int x = 0; x < c.width(); ++x) sum += static_cast<float>(255 - c.pixel(x, y).r) / 255.0f;
  }
  return sum;
}

// Anti-aliased convex fills: the summed coverage is the shape's area (the disc, the capsule,
// the rounded box: core area + perimeter * r + pi r^2), to a small fraction of the perimeter.
TEST(Canvas, ConvexFillsCoverTheirExactAreas) {
  constexpr float kPi = 3.14159265f;
  const Color black{0, 0, 0, 255};
  {
    Canvas c(100, 100);
    const Vec2 centre{50.3f, 49.6f};
    c.fill_convex({&centre, 1}, 30.0f, black);
    EXPECT_NEAR(coverage(c), kPi * 900.0f, 0.05f * 2.0f * kPi * 30.0f);
  }
  {
    Canvas c(120, 80);
    const std::array<Vec2, 2> ends{Vec2{20.2f, 30.7f}, Vec2{90.1f, 50.3f}};
    c.fill_convex(ends, 10.0f, black);
    const float len = distance(ends[0], ends[1]);
    EXPECT_NEAR(coverage(c), 2.0f * 10.0f * len + kPi * 100.0f, 0.05f * (2.0f * len + 2.0f * kPi * 10.0f));
  }
  for (const bool clockwise : {false, true}) {
    Canvas c(120, 120);
    std::array<Vec2, 4> box{Vec2{30.5f, 30.5f}, Vec2{80.5f, 30.5f}, Vec2{80.5f, 70.5f}, Vec2{30.5f, 70.5f}};
    if (clockwise) std::swap(box[1], box[3]);
    c.fill_convex(box, 8.0f, black);
    const float area = 50.0f * 40.0f + 2.0f * (50.0f + 40.0f) * 8.0f + kPi * 64.0f;
    EXPECT_NEAR(coverage(c), area, 0.05f * 2.0f * (50.0f + 40.0f + kPi * 8.0f)) << clockwise;
    EXPECT_EQ(c.pixel(55, 50), black);
    EXPECT_EQ(c.pixel(23, 23), (Color{255, 255, 255, 255}));  // 9.9 from the corner vertex: outside the rounding
  }
}

TEST(Canvas, ConvexFillStrokesItsOutlineCentredOnTheBoundary) {
  Canvas c(100, 100);
  const Vec2 centre{50.5f, 50.5f};
  const Color fill{200, 200, 255, 255}, stroke{0, 0, 0, 255};
  c.fill_convex({&centre, 1}, 20.0f, fill, stroke, 3.0f);
  EXPECT_EQ(c.pixel(50, 50), fill);
  EXPECT_EQ(c.pixel(50 + 20, 50), stroke);    // on the boundary
  EXPECT_EQ(c.pixel(50 + 17, 50), fill);      // inside the band
  EXPECT_EQ(c.pixel(50 + 23, 50), (Color{255, 255, 255, 255}));
  // Degenerate and bad cores draw what makes sense or nothing, never crash.
  const std::array<Vec2, 3> collinear{Vec2{10, 10}, Vec2{20, 20}, Vec2{30, 30}};
  c.fill_convex(collinear, 1.0f, stroke);  // a capsule from (10,10) to (30,30)
  EXPECT_EQ(c.pixel(20, 20), stroke);
  const std::array<Vec2, 2> bad{Vec2{NAN, 0}, Vec2{1, 1}};
  c.fill_convex(bad, 1.0f, stroke);
  c.fill_convex({}, 1.0f, stroke);
  c.fill_convex(collinear, -1.0f, stroke);
  c.fill_convex(collinear, INFINITY, stroke);
}

TEST(Canvas, ClipBoxLimitsEveryDrawing) {
  Canvas c(50, 50);
  c.set_clip({10, 10, 20, 20});
  EXPECT_EQ(c.clip(), (PixelBox{10, 10, 20, 20}));
  const Vec2 centre{25, 25};
  c.fill_convex({&centre, 1}, 100.0f, kInk);
  c.fill_circle(centre, 100.0f, kInk);
  c.fill_rect(-100, -100, 1000, 1000, kInk);
  c.draw_line({0, 25}, {50, 25}, kInk, 5.0f);
  c.fill_triangle({-100, -100}, {200, -100}, {0, 200}, kInk);
  EXPECT_EQ(count(c, kInk), 400);
  EXPECT_EQ(c.pixel(10, 10), kInk);
  EXPECT_EQ(c.pixel(29, 29), kInk);
  EXPECT_NE(c.pixel(30, 29), kInk);
  c.set_clip({40, 40, 2147483647, 100});  // clamped to the canvas, no overflow
  EXPECT_EQ(c.clip(), (PixelBox{40, 40, 10, 10}));
  c.reset_clip();
  EXPECT_EQ(c.clip(), (PixelBox{0, 0, 50, 50}));
}

}  // namespace
}  // namespace collide
