// A small polygon resting on, or sinking into, a long wall (the boundary of a large world): the
// manifold's normal is the wall's and its depth the analytic penetration, in both argument
// orders, however long the wall. A 1288 m wall once made a box touching it by a hair (below the
// rounding of coordinates near 360 m) report 7 m of depth along the box's own axis: the incident
// edge clipped to nothing and the fallback for deep many-gon overlaps clipped against the box's
// face instead, and `collide run --bodies 48000` pushed that box through the wall.

#include <collide/narrow/contact.hpp>
#include <collide/shape/shape2d.hpp>

#include "support/random.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace collide {
namespace {

/// Depth error allowed: float rounding of coordinates near 360 m, plus the tolerance by which
/// the contact counts sharp shapes apart by a hair as touching.
constexpr float kDepthSlack = 2e-3f;

TEST(ContactLongWall, SmallPolygonOnLongWall) {
  std::mt19937 rng(48000);
  const float wall_top = -360.0f;
  int touching = 0;
  for (const float half_length : {10.0f, 100.0f, 300.0f, 644.0f, 2000.0f}) {
    const Polygon wall = make_box({half_length, 2.0f});
    const Transform wall_xf = Transform::from({0.0f, wall_top - 2.0f}, 0.0f);
    for (int i = 0; i < 2000; ++i) {
      const Polygon body = i % 2 == 0 ? make_box({test::uniform(rng, 0.2f, 1.2f), test::uniform(rng, 0.2f, 1.2f)})
                                      : test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 1.0f, 0.0f);
      const float angle = test::uniform(rng, -std::numbers::pi_v<float>, std::numbers::pi_v<float>);
      // Lowest point of the body at this angle, relative to its origin.
      Transform xf = Transform::from({test::uniform(rng, -5.0f, 5.0f), 0.0f}, angle);
      float lowest = INFINITY;
      for (int v = 0; v < body.count; ++v) lowest = std::min(lowest, rotate(xf.q, body.vertices[v]).y);
      // Apart by less than the long wall's tolerance (a hair: the case that failed), or up to a
      // quarter of a metre into it.
      const float penetration = i % 4 < 2 ? test::uniform(rng, -1e-4f, 0.0f) : test::uniform(rng, 0.0f, 0.25f);
      xf.p.y = wall_top - penetration - lowest;
      for (const bool body_first : {true, false}) {
        const Manifold m = body_first ? contact(Shape2D{body}, xf, Shape2D{wall}, wall_xf)
                                      : contact(Shape2D{wall}, wall_xf, Shape2D{body}, xf);
        if (penetration > kDepthSlack) {
          ASSERT_TRUE(m.touching()) << "wall " << half_length << " case " << i;
        }
        if (!m.touching()) continue;
        ++touching;
        const Vec2 down{0.0f, body_first ? -1.0f : 1.0f};  // from A to B
        EXPECT_GT(dot(m.normal, down), 0.999f) << "wall " << half_length << " case " << i << " body first "
                                                << body_first;
        EXPECT_NEAR(m.max_depth(), std::max(penetration, 0.0f), kDepthSlack)
            << "wall " << half_length << " case " << i << " body first " << body_first;
      }
    }
  }
  EXPECT_GT(touching, 10000);
}

// fuzz_shapes (fuzz/regressions/shapes/polygon_far_corner_rounds_onto_box_normal_nan.bin): a
// rounded polygon 2.7e7 long whose corner at the origin touches a small box. The contact works
// in a frame at the polygon's vertex 0, 2.7e7 away, where a float step is 2 units: the box's
// face separated the cores by 2 there, the closest-feature walk then found the two corners
// rounded onto one point, and the normal was their offset over its zero length (NaN). Within
// kFiniteQueryRange the answer must be finite: a unit normal from the polygon towards the box
// (+x), one point, a depth within the radius sum.
TEST(ContactLongWall, HugePolygonsCornerAgainstSmallBoxHasUnitNormal) {
  const std::vector<Vec2> outline{{-26738582.0f, -6677989.5f}, {-26711958.0f, -26711958.0f},
                                  {-26646422.0f, -26711958.0f}, {-2.86848396e-16f, -720.84729f},
                                  {1.17549435e-38f, 1.17549435e-38f}};
  const float radius = 5.25f;
  const Polygon huge = make_convex_polygon(outline, radius);
  const Polygon box = make_box({0.75f, 0.5f});
  const Transform box_xf = Transform::from({0.5f, 0.25f}, 0.3f);
  for (const bool swap : {false, true}) {
    const Manifold m = swap ? contact(box, box_xf, huge, Transform{}) : contact(huge, Transform{}, box, box_xf);
    ASSERT_GE(m.count, 1) << "swap " << swap;
    ASSERT_TRUE(std::isfinite(m.normal.x) && std::isfinite(m.normal.y)) << "swap " << swap;
    EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f) << "swap " << swap;
    EXPECT_GT((swap ? -1.0f : 1.0f) * m.normal.x, 0.7f) << "swap " << swap;  // A to B: the box lies at +x
    for (int k = 0; k < m.count; ++k) {
      EXPECT_TRUE(std::isfinite(m.points[k].point.x) && std::isfinite(m.points[k].point.y));
      EXPECT_GT(m.points[k].depth, 0.0f);
      EXPECT_LE(m.points[k].depth, radius + 1.0f);
    }
  }
}

}  // namespace
}  // namespace collide
