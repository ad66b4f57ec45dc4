// ConvexProxy::support_index (the scan GJK spends its time in, SIMD for 8+ points) against a
// plain scalar scan: same index for every size 1..64, including ties (lowest index wins).

#include <collide/narrow/support.hpp>

#include "support/test_util.hpp"

#include <vector>

namespace collide {
namespace {

/// The definition: the first index maximising dot(p[i], d).
int reference_support(const std::vector<Vec2>& p, Vec2 d) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(p.size()); ++i) {
    if (dot(p[i], d) > dot(p[best], d)) best = i;
  }
  return best;
}

TEST(GjkSupport, MatchesScalarScanForEverySize) {
  std::mt19937 rng(1);
  for (int n = 1; n <= kMaxPolygonVertices; ++n) {
    for (int trial = 0; trial < 50; ++trial) {
      std::vector<Vec2> pts;
      for (int i = 0; i < n; ++i) pts.push_back(test::random_point(rng, 10.0f));
      const ConvexProxy proxy(pts.data(), n, 0.0f);
      const Vec2 d = test::random_point(rng, 1.0f);
      EXPECT_EQ(proxy.support_index(d), reference_support(pts, d)) << "n " << n;
    }
  }
}

TEST(GjkSupport, TiesGoToTheLowestIndex) {
  // Points on a small integer grid, directions along the axes and diagonals: many exact ties.
  std::mt19937 rng(2);
  const Vec2 dirs[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1}, {-1, 1}};
  int tied = 0;
  for (int n = 1; n <= kMaxPolygonVertices; ++n) {
    std::vector<Vec2> pts;
    for (int i = 0; i < n; ++i) {
      pts.push_back({static_cast<float>(rng() % 3), static_cast<float>(rng() % 3)});
    }
    const ConvexProxy proxy(pts.data(), n, 0.0f);
    for (Vec2 d : dirs) {
      const int ref = reference_support(pts, d);
      EXPECT_EQ(proxy.support_index(d), ref) << "n " << n;
      for (int i = ref + 1; i < n; ++i) tied += dot(pts[i], d) == dot(pts[ref], d) ? 1 : 0;
    }
  }
  EXPECT_GT(tied, 100);  // the ties really happened
}

TEST(GjkSupport, WalkFromAnyStartReachesTheMaximumOnPolygons) {
  // support_index_from walks the outline of a polygon; it must end at a farthest point from
  // every start, for polygons of every size, including boxes whose faces tie.
  std::mt19937 rng(3);
  int walked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 3 + trial % 62;
    const Polygon poly = trial % 10 == 0 ? make_box({1.0f, 0.5f})
                                         : test::random_polygon(rng, n, 1.0f + trial * 0.1f);
    const ConvexProxy proxy(poly);
    std::vector<Vec2> pts(poly.vertices.begin(), poly.vertices.begin() + poly.count);
    const Vec2 dirs[] = {test::random_point(rng, 1.0f), {1, 0}, {0, -1}};
    for (Vec2 d : dirs) {
      const float top = dot(pts[reference_support(pts, d)], d);
      for (int start = 0; start < poly.count; ++start) {
        const int i = proxy.support_index_from(d, start);
        ASSERT_GE(i, 0);
        ASSERT_LT(i, poly.count);
        EXPECT_EQ(dot(pts[i], d), top) << "n " << poly.count << " start " << start;
        walked += i != start ? 1 : 0;
      }
    }
  }
  EXPECT_GT(walked, 1000);
  // A raw point set is not known to be an outline: the walk falls back to the full scan.
  std::vector<Vec2> cloud;
  for (int i = 0; i < 20; ++i) cloud.push_back(test::random_point(rng, 5.0f));
  const ConvexProxy raw(cloud.data(), 20, 0.0f);
  for (int start = 0; start < 20; ++start) {
    EXPECT_EQ(raw.support_index_from({0.3f, 0.7f}, start), reference_support(cloud, {0.3f, 0.7f}));
  }
}

}  // namespace
}  // namespace collide
