// Bullet 3 (Debian) as a second oracle for collide's GJK distance and EPA penetration on real
// hulls: btGjkEpaSolver2 on btConvexHullShape (margin 0, the same vertices), on pairs of the
// clouds of Jolt's convex_hulls.bin (support/hull_pairs.hpp). Bullet works in float with its
// own tolerances; where it answers, the two libraries must agree within them, and the exact
// reference says which is closer when they do not.

#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>

#include "support/hull_pairs.hpp"
#include "support/test_util.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace collide {
namespace {

constexpr int kHulls = 300;
constexpr int kPairs = 300;
constexpr float kSize = 1.0f;  ///< the hulls' size (longest side of the bounding box)
/// Bullet's GJK and EPA stop within 1e-4 of the answer (btGjkEpa2.cpp: GJK_ACCURACY,
/// EPA_ACCURACY), in float: their agreement with collide, in units of the hull size.
constexpr double kBulletSlack = 2e-4 * kSize;
/// collide's own bound against the exact reference (tests/oracles/jolt_oracle_test.cpp).
constexpr double kCollideSlack = 2e-5 * kSize;

btTransform bullet_transform(const Transform3& xf) {
  return btTransform(btQuaternion(xf.q.x, xf.q.y, xf.q.z, xf.q.w),
                     btVector3(xf.p.x, xf.p.y, xf.p.z));
}

struct Hulls {
  std::vector<ConvexHull> collide;
  std::vector<std::unique_ptr<btConvexHullShape>> bullet;
};

const Hulls& hulls() {
  static const Hulls h = [] {
    Hulls out;
    out.collide = test::scaled_jolt_hulls(kSize, kHulls);
    for (const ConvexHull& c : out.collide) {
      auto shape = std::make_unique<btConvexHullShape>();
      for (const Vec3& v : c.vertices) shape->addPoint(btVector3(v.x, v.y, v.z), false);
      shape->recalcLocalAabb();
      shape->setMargin(0.0f);
      out.bullet.push_back(std::move(shape));
    }
    return out;
  }();
  return h;
}

TEST(BulletOracle, DistancesAgreeOnRealHulls) {
  const Hulls& h = hulls();
  ASSERT_EQ(static_cast<int>(h.collide.size()), kHulls) << "convex_hulls.bin missing?";
  int answered = 0;
  double worst = 0.0;
  for (const test::HullPair& p :
       test::make_hull_pairs(h.collide, kPairs, test::Placement::separated, 31)) {
    const btTransform ta = bullet_transform(p.xa), tb = bullet_transform(p.xb);
    btGjkEpaSolver2::sResults r;
    const bool ok = btGjkEpaSolver2::Distance(h.bullet[p.a].get(), ta, h.bullet[p.b].get(), tb,
                                              tb.getOrigin() - ta.getOrigin(), r);
    if (!ok) continue;
    ++answered;
    const double c = distance(h.collide[p.a], p.xa, h.collide[p.b], p.xb).distance;
    const double truth = test::brute_core_distance(test::brute_core(h.collide[p.a], p.xa),
                                                   test::brute_core(h.collide[p.b], p.xb));
    worst = std::max(worst, std::fabs(c - truth));
    // Bullet's distance is an upper bound of the truth within its slack, never much below.
    EXPECT_GT(r.distance, truth - kBulletSlack);
    if (std::fabs(c - r.distance) > kBulletSlack) {
      // Disagreement: collide must be the one at the truth.
      EXPECT_LT(std::fabs(c - truth), kCollideSlack) << "Bullet " << r.distance;
    }
  }
  std::printf("distance: Bullet answered %d of %d; collide's max error %.2e\n", answered, kPairs,
              worst);
  EXPECT_GE(answered, kPairs * 99 / 100);
  EXPECT_LT(worst, kCollideSlack);
}

TEST(BulletOracle, EpaPenetrationAgreesOnRealHulls) {
  const Hulls& h = hulls();
  ASSERT_EQ(static_cast<int>(h.collide.size()), kHulls) << "convex_hulls.bin missing?";
  int answered = 0, disagree = 0;
  double worst = 0.0;
  for (const test::HullPair& p :
       test::make_hull_pairs(h.collide, kPairs, test::Placement::overlapping, 32)) {
    const btTransform ta = bullet_transform(p.xa), tb = bullet_transform(p.xb);
    btGjkEpaSolver2::sResults r;
    const bool ok = btGjkEpaSolver2::Penetration(h.bullet[p.a].get(), ta, h.bullet[p.b].get(),
                                                 tb, tb.getOrigin() - ta.getOrigin(), r);
    const PenetrationResult3 c = penetration(h.collide[p.a], p.xa, h.collide[p.b], p.xb);
    ASSERT_EQ(c.status, QueryStatus::overlapped);
    const double truth = test::minkowski_reference(h.collide[p.a], p.xa, h.collide[p.b], p.xb).depth();
    worst = std::max(worst, std::fabs(c.depth - truth));
    if (!ok) continue;  // Bullet's EPA gives up on a few pairs (2 in 1024 in bench_narrow3)
    ++answered;
    const double bullet_depth = -r.distance;
    if (std::fabs(c.depth - bullet_depth) > kBulletSlack) {
      ++disagree;
      std::printf("pair %d-%d: true depth %.6f, collide %.6f, Bullet %.6f\n", p.a, p.b, truth,
                  double(c.depth), bullet_depth);
    }
  }
  std::printf("penetration: Bullet answered %d of %d, disagreed on %d; collide's max error %.2e\n",
              answered, kPairs, disagree, worst);
  EXPECT_GE(answered, kPairs * 98 / 100);
  EXPECT_LE(disagree, kPairs / 100);
  EXPECT_LT(worst, kCollideSlack);
}

}  // namespace
}  // namespace collide
