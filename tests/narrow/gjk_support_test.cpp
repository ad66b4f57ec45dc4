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

}  // namespace
}  // namespace collide
