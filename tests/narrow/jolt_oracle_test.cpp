// Jolt Physics as an oracle for 3D contact on real hulls: collide's `contact` against Jolt's
// CollisionDispatch::sCollideShapeVsShape (EPA normal and depth, manifold as its PhysicsSystem
// builds it) on overlapping pairs of the clouds of Jolt's convex_hulls.bin, each disagreement
// judged by the exact reference of support/hull_pairs.hpp (A - B as half-spaces, double): the
// depth along a normal is exact for any normal, so the better of two normals is the one along
// which B must move less to separate.
//
// Jolt is built only with the benchmarks (cmake/peers.cmake); without it the test is skipped.

#include <collide/core/tolerance.hpp>
#include <collide/narrow/contact.hpp>

#include "support/hull_pairs.hpp"
#include "support/test_util.hpp"

#if COLLIDE_HAVE_JOLT
#include "support/jolt/jolt_queries.hpp"
#endif

#include <cstdio>

namespace collide {
namespace {

#if COLLIDE_HAVE_JOLT

constexpr int kHulls = 400;
constexpr int kPairs = 400;
constexpr float kSize = 1.0f;  ///< the hulls' size (longest side of the bounding box)
/// How much deeper than the true penetration collide's normal may be and still count as
/// agreeing: its SAT prefers faces to edges and A's face to B's within these fractions of the
/// size (contact.hpp), and may keep an axis that much worse.
constexpr double kAxisSlack = double(kEdgeContactTolerance + kReferenceFaceTolerance) * kSize;
/// Jolt's EPA stops within its penetration tolerance (1e-4, relative): its normal's exact depth
/// is within this of the true one.
constexpr double kJoltSlack = 1e-4 * kSize;

jolt_queries::Pose pose(const Transform3& xf) {
  return {{xf.p.x, xf.p.y, xf.p.z}, {xf.q.x, xf.q.y, xf.q.z, xf.q.w}};
}

glm::dvec3 unit(glm::dvec3 v) { return v / glm::length(v); }

TEST(JoltOracle, ContactNormalsAndDepthsAgreeOnRealHulls) {
  jolt_queries::init();
  const std::vector<ConvexHull> hulls = test::scaled_jolt_hulls(kSize, kHulls);
  ASSERT_EQ(static_cast<int>(hulls.size()), kHulls) << "convex_hulls.bin missing?";
  std::vector<jolt_queries::HullPtr> jolt;
  for (const ConvexHull& h : hulls) {
    std::vector<jolt_queries::Vec> points;
    for (const Vec3& v : h.vertices) points.push_back({v.x, v.y, v.z});
    jolt.push_back(jolt_queries::make_hull(points, h.tolerance));
    ASSERT_TRUE(jolt.back());
  }
  const std::vector<test::HullPair> pairs =
      test::make_hull_pairs(hulls, kPairs, test::Placement::overlapping, 14);

  int disagree = 0, collide_wrong = 0, jolt_wrong = 0, depth_beyond_normal = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const test::HullPair& p = pairs[i];
    const test::MinkowskiReference k =
        test::minkowski_reference(hulls[p.a], p.xa, hulls[p.b], p.xb);
    ASSERT_TRUE(k.overlapping());
    const double truth = k.depth();

    const Manifold3 m = contact(hulls[p.a], p.xa, hulls[p.b], p.xb);
    const jolt_queries::ContactOut j = jolt_queries::contact(
        jolt_queries::place(*jolt[p.a], pose(p.xa)), jolt_queries::place(*jolt[p.b], pose(p.xb)),
        0.0f);
    ASSERT_GT(m.count, 0) << "pair " << i;
    ASSERT_GT(j.count, 0) << "pair " << i;

    // Exact depths along each library's normal (>= truth; equal for the best axis).
    const glm::dvec3 nc = unit(glm::dvec3(m.normal));
    const glm::dvec3 nj = unit(glm::dvec3(j.normal.x, j.normal.y, j.normal.z));
    const double along_c = k.depth_along(nc);
    const double along_j = k.depth_along(nj);
    // No contact point is deeper than the shapes overlap along the normal.
    depth_beyond_normal += m.max_depth() > along_c + 1e-5 * kSize;

    const bool c_ok = along_c - truth <= kAxisSlack;
    const bool j_ok = along_j - truth <= kJoltSlack;
    const bool agree = std::fabs(along_c - along_j) <= kAxisSlack &&
                       std::fabs(m.max_depth() - j.depth) <= 0.25 * along_c + kAxisSlack;
    if (agree && c_ok && j_ok) continue;
    ++disagree;
    collide_wrong += !c_ok;
    jolt_wrong += !j_ok;
    std::printf("pair %zu (hulls %d, %d): true depth %.5f; collide depth %.5f, %d points, "
                "normal's depth %.5f%s; jolt depth %.5f, normal's depth %.5f%s\n",
                i, p.a, p.b, truth, double(m.max_depth()), m.count, along_c,
                c_ok ? "" : " (wrong axis)", double(j.depth), along_j, j_ok ? "" : " (wrong axis)");
  }
  std::printf("%d of %d pairs disagree: collide's axis wrong in %d, Jolt's in %d\n", disagree,
              kPairs, collide_wrong, jolt_wrong);
  // The oracle itself is right.
  EXPECT_EQ(jolt_wrong, 0);
  EXPECT_EQ(depth_beyond_normal, 0);
  // Disagreements are rare. Known cause of those seen (bench/narrow3.cpp on 1024 pairs: 8):
  // the best face axis clips to nothing (the deepest point of the other hull lies outside the
  // reference face), and contact falls back to the deeper edge-edge axis.
  EXPECT_LE(collide_wrong, kPairs / 100);
  EXPECT_LE(disagree, kPairs / 50);
}

#else

TEST(JoltOracle, ContactNormalsAndDepthsAgreeOnRealHulls) {
  GTEST_SKIP() << "Jolt is built with the benchmarks only (COLLIDE_BUILD_BENCH)";
}

#endif

}  // namespace
}  // namespace collide
