#include <collide/core/error.hpp>
#include <collide/shape/polygon.hpp>

#include "support/test_util.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace collide {
namespace {

TEST(MakePolygon, HullOfShuffledPointsIsCounterClockwiseAndConvex) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec2> pts;
    const int n = 3 + static_cast<int>(rng() % 40);
    for (int i = 0; i < n; ++i) pts.push_back(test::random_point(rng, 10.0f));
    Polygon p;
    try {
      p = make_polygon(pts);
    } catch (const InvalidInput&) {
      continue;  // collinear draws are legitimately rejected
    }
    ASSERT_GE(p.count, 3);
    for (int i = 0; i < p.count; ++i) {
      const Vec2 a = p.vertex(i), b = p.vertex(i + 1), c = p.vertex(i + 2);
      EXPECT_GT(cross(b - a, c - b), 0.0f) << "corner " << i + 1 << " not a left turn";
      EXPECT_NEAR(length(p.normals[i]), 1.0f, 1e-5f);
      EXPECT_NEAR(dot(p.normals[i], b - a), 0.0f, 1e-4f);
    }
    // Every input point is inside the hull (brute force against each edge).
    for (Vec2 q : pts) {
      for (int i = 0; i < p.count; ++i) {
        EXPECT_LE(dot(p.normals[i], q - p.vertices[i]), 1e-4f);
      }
    }
  }
}

TEST(MakePolygon, EveryEdgeHasAUnitNormalAtAnyScale) {
  // A triangle and a box scaled from 1e-21 to 1e18: an edge's squared length leaves float's
  // normal range below about 1e-19 and above about 1e19 (fuzz_shapes found a 4e-21 triangle
  // with a zero normal, and a zero contact normal after it). Each normal is unit length and
  // perpendicular to its edge, checked in double.
  const std::vector<Vec2> shape = {{0.0f, 0.0f}, {1.0f, 0.1f}, {0.3f, 0.9f}, {-0.2f, 0.5f}};
  for (const float scale : {4e-21f, 1e-19f, 1e-12f, 1.0f, 1e12f, 1e18f}) {
    SCOPED_TRACE(scale);
    std::vector<Vec2> pts;
    for (const Vec2 q : shape) pts.push_back(q * scale);
    const Polygon p = make_polygon(pts);
    ASSERT_EQ(p.count, 4);
    for (int i = 0; i < p.count; ++i) {
      const Vec2 n = p.normals[i];
      const double ex = double(p.vertex(i + 1).x) - p.vertex(i).x;
      const double ey = double(p.vertex(i + 1).y) - p.vertex(i).y;
      const double len = std::hypot(ex, ey);
      EXPECT_NEAR(std::hypot(double(n.x), double(n.y)), 1.0, 1e-6) << "edge " << i;
      EXPECT_NEAR((n.x * ex + n.y * ey) / len, 0.0, 1e-6) << "edge " << i;
      EXPECT_GT(n.x * ey - n.y * ex, 0.0) << "edge " << i << ": the normal points inwards";
    }
  }
}

TEST(MakePolygon, RejectsBadInputWithMessage) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<Vec2> two = {{0, 0}, {1, 0}};
  const std::vector<Vec2> dup = {{0, 0}, {1, 0}, {1, 0}, {0, 0}};
  const std::vector<Vec2> line = {{0, 0}, {1, 1}, {2, 2}, {3, 3}};
  const std::vector<Vec2> with_nan = {{0, 0}, {1, 0}, {nan, 1}};
  const std::vector<Vec2> with_inf = {{0, 0}, {inf, 0}, {0, 1}};
  const std::vector<Vec2> tri = {{0, 0}, {1, 0}, {0, 1}};
  EXPECT_THROW((void)make_polygon(two), InvalidInput);
  EXPECT_THROW((void)make_polygon(dup), InvalidInput);
  EXPECT_THROW((void)make_polygon(line), InvalidInput);
  EXPECT_THROW((void)make_polygon(with_inf), InvalidInput);
  EXPECT_THROW((void)make_polygon(tri, -1.0f), InvalidInput);
  EXPECT_THROW((void)make_polygon(tri, nan), InvalidInput);
  try {
    (void)make_polygon(with_nan);
    FAIL() << "NaN accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
  }
}

TEST(MakeConvexPolygon, KeepsOrderAndRejectsClockwiseOrConcave) {
  const std::vector<Vec2> ccw = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  const Polygon p = make_convex_polygon(ccw);
  ASSERT_EQ(p.count, 4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(p.vertices[i], ccw[i]);
  EXPECT_VEC2_NEAR(p.centroid, Vec2(1.0f, 0.5f), 1e-6f);

  const std::vector<Vec2> cw = {{0, 0}, {0, 1}, {2, 1}, {2, 0}};
  EXPECT_THROW((void)make_convex_polygon(cw), InvalidInput);
  const std::vector<Vec2> concave = {{0, 0}, {2, 0}, {1, 0.5f}, {2, 1}, {0, 1}};
  try {
    (void)make_convex_polygon(concave);
    FAIL() << "concave accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
  }
  const std::vector<Vec2> straight = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_THROW((void)make_convex_polygon(straight), InvalidInput);
  // A pentagram's outline turns left at every corner but winds twice.
  std::vector<Vec2> star;
  for (int i = 0; i < 5; ++i) {
    const float a = 2.0f * test::kPi * static_cast<float>(2 * i) / 5.0f;
    star.push_back({std::cos(a), std::sin(a)});
  }
  EXPECT_THROW((void)make_convex_polygon(star), InvalidInput);
}

TEST(MakePolygon, SixtyFourVerticesFit) {
  std::vector<Vec2> pts;
  for (int i = 0; i < kMaxPolygonVertices; ++i) {
    const float a = 2.0f * test::kPi * static_cast<float>(i) / kMaxPolygonVertices;
    pts.push_back({std::cos(a), std::sin(a)});
  }
  EXPECT_EQ(make_polygon(pts).count, kMaxPolygonVertices);
  EXPECT_EQ(make_convex_polygon(pts).count, kMaxPolygonVertices);
  pts.push_back({1.5f, 0.2f});
  pts.push_back({0.2f, 1.5f});
  pts.push_back({-1.5f, -0.2f});
  // Hull has at most 64 + 3 vertices minus whatever the new points swallow: still checked.
  try {
    const Polygon p = make_polygon(pts);
    EXPECT_LE(p.count, kMaxPolygonVertices);
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("kMaxPolygonVertices"), std::string::npos);
  }
}

// Small polygons stay compact (the layout issue 19 asked for); large ones keep every vertex
// through copies and assignments in either direction between inline and heap storage.
static_assert(sizeof(Polygon) <= 192, "a polygon of up to 8 vertices fits three cache lines");
static_assert(alignof(Polygon) == 64, "polygons start on a cache line");

TEST(PolygonStorage, AFourGonReadsTwoCacheLines) {
  const Polygon box = make_box({1.0f, 2.0f});
  const auto offset = [&box](const void* p) {
    return static_cast<const char*>(p) - reinterpret_cast<const char*>(&box);
  };
  // Header, vertex block pointer and vertices 0..3 in line 0; normals with theirs in line 1.
  EXPECT_LE(offset(&box.vertices[3] + 1), 64);
  EXPECT_GE(offset(&box.normals), 64);
  EXPECT_LE(offset(&box.normals[3] + 1), 128);
}

Polygon regular_polygon(int n, float r) {
  std::vector<Vec2> pts;
  for (int i = 0; i < n; ++i) {
    const float a = 2.0f * test::kPi * static_cast<float>(i) / static_cast<float>(n);
    pts.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return make_convex_polygon(pts);
}

void expect_same_points(const Polygon& a, const Polygon& b) {
  ASSERT_EQ(a.count, b.count);
  for (int i = 0; i < a.count; ++i) {
    EXPECT_EQ(a.vertices[i], b.vertices[i]) << i;
    EXPECT_EQ(a.normals[i], b.normals[i]) << i;
  }
}

TEST(PolygonStorage, CopiesAndAssignmentsKeepEveryVertexInlineOrOnTheHeap) {
  const Polygon big = regular_polygon(kMaxPolygonVertices, 2.0f);
  const Polygon nine = regular_polygon(kInlinePolygonVertices + 1, 3.0f);
  const Polygon small = regular_polygon(kInlinePolygonVertices, 1.0f);
  EXPECT_EQ(big.vertices.capacity(), kMaxPolygonVertices);
  EXPECT_EQ(small.vertices.capacity(), kInlinePolygonVertices);

  Polygon copy = big;  // deep copy: its own block
  expect_same_points(copy, big);
  EXPECT_NE(copy.vertices.data(), big.vertices.data());
  copy = small;  // heap -> inline
  expect_same_points(copy, small);
  EXPECT_EQ(copy.vertices.capacity(), kInlinePolygonVertices);
  copy = nine;  // inline -> heap
  expect_same_points(copy, nine);
  copy = big;  // heap -> larger heap
  expect_same_points(copy, big);
  Polygon moved = std::move(copy);
  expect_same_points(moved, big);
  // Every vertex of the 64-gon is on its circle, in order: none came from a stale slot.
  for (int i = 0; i < moved.count; ++i) {
    EXPECT_NEAR(glm::length(moved.vertices[i]), 2.0f, 1e-5f);
    EXPECT_GT(cross(moved.vertex(i + 1) - moved.vertices[i], moved.vertex(i + 2) - moved.vertex(i + 1)), 0.0f);
  }
}

TEST(MakeBox, RotatedBoxAabbMatchesCorners) {
  const Polygon box = make_box({2.0f, 1.0f}, {1.0f, 1.0f}, test::kPi / 2.0f);
  const Aabb aabb = compute_aabb(box, Transform::from({10.0f, 0.0f}, 0.0f));
  EXPECT_NEAR(aabb.min.x, 10.0f, 1e-5f);
  EXPECT_NEAR(aabb.max.x, 12.0f, 1e-5f);
  EXPECT_NEAR(aabb.min.y, -1.0f, 1e-5f);
  EXPECT_NEAR(aabb.max.y, 3.0f, 1e-5f);
  EXPECT_THROW((void)make_box({0.0f, 1.0f}), InvalidInput);
  EXPECT_NEAR(signed_area(std::span(box.vertices.data(), 4)), 8.0f, 1e-4f);
}

// fuzz_shapes (fuzz/regressions/shapes/box_corners_round_together_at_far_centre.bin): a box
// 1.5e-37 wide at x = 2.16e8, whose four corners rounded onto two points of a vertical line
// while its normals stayed the rotated axes; `distance` warm-started from a corner then followed
// the normal of an edge that was not there (3.5e7 against the cold call's 2.1e8). Every edge
// with a length now runs along its normal's perpendicular (below), this box's included.
TEST(MakeBox, CornersRoundedOntoALineTakeTheLinesNormals) {
  const Polygon box = make_box({7.49377593e-38f, 6.5f}, {216006640.0f, 2.39807434e-35f}, -2.48292005e+38f, 1e7f);
  int sides = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec2 edge = box.vertices[static_cast<std::size_t>(next_vertex(i, 4))] - box.vertices[static_cast<std::size_t>(i)];
    if (edge == Vec2{0.0f, 0.0f}) continue;
    ++sides;
    EXPECT_EQ(box.normals[static_cast<std::size_t>(i)].y, 0.0f) << "edge " << i;  // the line is vertical
    EXPECT_EQ(std::abs(box.normals[static_cast<std::size_t>(i)].x), 1.0f) << "edge " << i;
  }
  EXPECT_EQ(sides, 2);
}

TEST(MakeBox, EveryEdgeRunsAlongItsNormalsPerpendicularAtAnyCentre) {
  int built = 0;
  for (const float centre : {0.0f, 1.0f, 1e4f, 3e6f, 2e8f}) {
    for (const float half : {1e-3f, 0.1f, 1.0f, 7.0f, 40.0f, 1e3f}) {
      for (const float angle : {0.0f, 0.3f, 1.0f, 2.5f}) {
        const Polygon box = make_box({half, 0.5f * half}, {centre, -0.5f * centre}, angle);
        for (int i = 0; i < 4; ++i) {
          const Vec2 n = box.normals[static_cast<std::size_t>(i)];
          const Vec2 edge = box.vertices[static_cast<std::size_t>(next_vertex(i, box.count))] -
                            box.vertices[static_cast<std::size_t>(i)];
          if (edge == Vec2{0.0f, 0.0f}) continue;  // corners rounded together: the axis stays
          ++built;
          const float along = dot(edge, left_perp(n));
          EXPECT_NEAR(length(n), 1.0f, 1e-5f);
          EXPECT_GT(along, 0.0f) << "centre " << centre << " half " << half << " angle " << angle << " edge " << i;
          EXPECT_LE(std::abs(dot(edge, n)), 0.1f * along)
              << "centre " << centre << " half " << half << " angle " << angle << " edge " << i;
        }
      }
    }
  }
  EXPECT_GT(built, 400);  // edges with a length, of 480
  // An ordinary box keeps the rotated axes as its normals, to the bit.
  const Polygon box = make_box({0.5f, 0.25f}, {1e4f, -1e4f}, 0.3f);
  const Rot2 q = Transform::from({1e4f, -1e4f}, 0.3f).q;
  EXPECT_EQ(box.normals[1].x, rotate(q, Vec2{1.0f, 0.0f}).x);
  EXPECT_EQ(box.normals[1].y, rotate(q, Vec2{1.0f, 0.0f}).y);
}

}  // namespace
}  // namespace collide
