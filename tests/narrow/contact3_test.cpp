// 3D contact manifolds: analytic cases (resting boxes, spheres and capsules on boxes, crossed
// edges), and under random rigid motions the property: moving B along the reported
// normal by the reported depth plus a little takes the shapes apart, by the depth minus a
// little keeps them overlapping (checked with the brute-force reference), with every point
// lying on both shapes.

#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>

#include "support/brute_convex3.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <random>

namespace collide {
namespace {

const Quat kIdentity{1.0f, 0.0f, 0.0f, 0.0f};

Transform3 at(Vec3 p) { return Transform3::from(p, kIdentity); }

TEST(Contact3, BoxRestingOnABoxGivesFourFacePoints) {
  const Box ground = make_box({5.0f, 0.5f, 5.0f});
  const Box crate = make_box({0.5f, 0.5f, 0.5f});
  const Manifold3 m = contact(ground, Transform3{}, crate, at({1.0f, 0.99f, -2.0f}));
  ASSERT_EQ(m.count, 4);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-6f);
  for (int i = 0; i < m.count; ++i) {
    EXPECT_NEAR(m.points[i].depth, 0.01f, 1e-5f);
    EXPECT_NEAR(m.points[i].point.y, 0.495f, 1e-5f);  // midway between the surfaces
    EXPECT_NEAR(std::fabs(m.points[i].point.x - 1.0f), 0.5f, 1e-5f);
    EXPECT_NEAR(std::fabs(m.points[i].point.z + 2.0f), 0.5f, 1e-5f);
    // Ground's top face (face 3: +y) against a corner of the crate.
    EXPECT_EQ(m.points[i].id.type_a, FeatureType::face);
    EXPECT_EQ(m.points[i].id.index_a, 3u);
    EXPECT_EQ(m.points[i].id.type_b, FeatureType::vertex);
  }
  // Swapped: the same contact seen from the crate.
  const Manifold3 r = contact(crate, at({1.0f, 0.99f, -2.0f}), ground, Transform3{});
  ASSERT_EQ(r.count, 4);
  EXPECT_VEC3_NEAR(r.normal, Vec3(0, -1, 0), 1e-6f);
  EXPECT_NEAR(r.max_depth(), 0.01f, 1e-5f);
}

TEST(Contact3, TurnedBoxOnABoxIsReducedToFourPointsSpanningTheOverlap) {
  const Box a = make_box({1.0f, 1.0f, 1.0f});
  const Box b = make_box({1.0f, 1.0f, 1.0f});
  // B turned 45 degrees about y, resting 0.02 deep: the clip is an octagon, reduced to 4.
  const Transform3 xb = Transform3::from_axis_angle({0.0f, 1.98f, 0.0f}, {0, 1, 0}, 0.25f * test::kPi);
  const Manifold3 m = contact(a, Transform3{}, b, xb);
  ASSERT_EQ(m.count, 4);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-5f);
  float min_r = 1e9f;
  for (int i = 0; i < m.count; ++i) {
    EXPECT_NEAR(m.points[i].depth, 0.02f, 1e-4f);
    min_r = std::min(min_r, std::hypot(m.points[i].point.x, m.points[i].point.z));
  }
  EXPECT_GT(min_r, 0.9f);  // points on the octagon's boundary, spread around it
}

TEST(Contact3, SphereOnABoxFaceEdgeAndCorner) {
  const Box box = make_box({1.0f, 1.0f, 1.0f});
  const Sphere ball = make_sphere({0, 0, 0}, 0.5f);
  // Face.
  Manifold3 m = contact(box, Transform3{}, ball, at({0.2f, 1.4f, 0.3f}));
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-6f);
  EXPECT_NEAR(m.points[0].depth, 0.1f, 1e-6f);
  EXPECT_VEC3_NEAR(m.points[0].point, Vec3(0.2f, 0.95f, 0.3f), 1e-6f);
  // Feature ids: the box's +y face (2 * 1 + 1, box.hpp) and the sphere's one feature, face 0.
  EXPECT_EQ(m.points[0].id.feature_a().type, FeatureType::face);
  EXPECT_EQ(m.points[0].id.feature_a().index, 3u);
  EXPECT_EQ(m.points[0].id.feature_b().type, FeatureType::face);
  EXPECT_EQ(m.points[0].id.feature_b().index, 0u);
  // The same with the sphere as A (the box's face clips the sphere as the incident core).
  const Manifold3 swapped = contact(ball, at({0.2f, 1.4f, 0.3f}), box, Transform3{});
  ASSERT_EQ(swapped.count, 1);
  EXPECT_EQ(swapped.points[0].id.feature_a().type, FeatureType::face);
  EXPECT_EQ(swapped.points[0].id.feature_a().index, 0u);
  // Edge (the x-aligned edge at y = z = 1): normal along the diagonal of y and z.
  m = contact(box, Transform3{}, ball, at({0.2f, 1.3f, 1.3f}));
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, normalize_or_zero(Vec3(0, 1, 1)), 1e-5f);
  EXPECT_NEAR(m.points[0].depth, 0.5f - 0.3f * std::sqrt(2.0f), 1e-5f);
  // Corner.
  m = contact(box, Transform3{}, ball, at({1.2f, 1.2f, 1.2f}));
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, normalize_or_zero(Vec3(1, 1, 1)), 1e-5f);
  // Deep: the centre inside the box, nearest the +x face.
  m = contact(box, Transform3{}, ball, at({0.8f, 0.1f, -0.2f}));
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, Vec3(1, 0, 0), 1e-6f);
  EXPECT_NEAR(m.points[0].depth, 0.7f, 1e-5f);
  // Apart.
  EXPECT_EQ(contact(box, Transform3{}, ball, at({0.0f, 1.6f, 0.0f})).count, 0);
  // Apart but within the margin: a speculative point with negative depth.
  m = contact(box, Transform3{}, ball, at({0.0f, 1.6f, 0.0f}), 0.2f);
  ASSERT_EQ(m.count, 1);
  EXPECT_NEAR(m.points[0].depth, -0.1f, 1e-5f);
}

TEST(Contact3, CapsuleLyingOnABoxGivesTwoPoints) {
  const Box box = make_box({2.0f, 0.5f, 2.0f});
  const Capsule3 capsule = make_capsule({-1, 0, 0}, {1, 0, 0}, 0.25f);
  const Manifold3 m = contact(box, Transform3{}, capsule, at({0.5f, 0.7f, 0.0f}));
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-6f);
  EXPECT_NEAR(m.points[0].depth, 0.05f, 1e-5f);
  EXPECT_NEAR(m.points[1].depth, 0.05f, 1e-5f);
  EXPECT_NEAR(std::fabs(m.points[0].point.x - m.points[1].point.x), 2.0f, 1e-4f);
  // Hanging over the box's edge at x = 2: clipped there.
  const Manifold3 over = contact(box, Transform3{}, capsule, at({2.5f, 0.7f, 0.0f}));
  ASSERT_EQ(over.count, 2);
  float max_x = -1e9f;
  for (int i = 0; i < 2; ++i) max_x = std::max(max_x, over.points[i].point.x);
  EXPECT_NEAR(max_x, 2.0f, 1e-5f);
}

TEST(Contact3, CapsulesParallelGiveTwoPointsCrossedOne) {
  const Capsule3 c = make_capsule({-1, 0, 0}, {1, 0, 0}, 0.25f);
  Manifold3 m = contact(c, Transform3{}, c, at({0.5f, 0.4f, 0.0f}));
  ASSERT_EQ(m.count, 2);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-6f);
  EXPECT_NEAR(m.points[0].depth, 0.1f, 1e-6f);
  const Transform3 crossed = Transform3::from_axis_angle({0.3f, 0.4f, 0.0f}, {0, 1, 0}, 0.5f * test::kPi);
  m = contact(c, Transform3{}, c, crossed);
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-5f);
  EXPECT_VEC3_NEAR(m.points[0].point, Vec3(0.3f, 0.2f, 0.0f), 1e-5f);
}

TEST(Contact3, CrossedCapsulesMeetAlikeAtEveryScale) {
  // Two capsules crossing at 70 degrees, 0.1 deep, scaled by powers of two from 2^-60 to 2^40:
  // the contact scales with them exactly (a power of two changes no rounding). The closest
  // points of their cores solve a denominator of fourth powers of the lengths, which underflowed
  // below about 1e-10 (the cores read as parallel: depth and normal of their first ends) and
  // overflows above about 1e9 (finding 26's open part, docs/fuzzing.md).
  const Quat turn = glm::angleAxis(70.0f * test::kPi / 180.0f, Vec3(0.0f, 1.0f, 0.0f));
  const auto meet = [&](int e) {
    const float s = std::ldexp(1.0f, e);
    const Capsule3 a = make_capsule(Vec3(-s, 0.0f, 0.0f), Vec3(s, 0.0f, 0.0f), 0.25f * s);
    const Capsule3 b = make_capsule(Vec3(-s, 0.0f, 0.0f), Vec3(s, 0.0f, 0.0f), 0.25f * s);
    return contact(a, Transform3{}, b, Transform3{Vec3(0.3f * s, 0.4f * s, 0.2f * s), turn});
  };
  const Manifold3 unit = meet(0);
  ASSERT_EQ(unit.count, 1);
  EXPECT_NEAR(unit.points[0].depth, 0.1f, 1e-5f);
  EXPECT_VEC3_NEAR(unit.normal, Vec3(0.0f, 1.0f, 0.0f), 1e-5f);
  for (const int e : {-60, -43, -30, -20, 20, 30, 40}) {
    const float s = std::ldexp(1.0f, e);
    const Manifold3 m = meet(e);
    ASSERT_EQ(m.count, 1) << "at 2^" << e;
    EXPECT_EQ(m.normal, unit.normal) << "at 2^" << e;
    EXPECT_EQ(m.points[0].depth / s, unit.points[0].depth) << "at 2^" << e;
    EXPECT_EQ(m.points[0].point / s, unit.points[0].point) << "at 2^" << e;
  }
}

TEST(Contact3, CrossedBoxEdgesGiveOneEdgeEdgePoint) {
  // Two long bars, one along x on top of the other along z, both turned 45 degrees about their
  // long axis so that their ridges cross: an edge-edge contact.
  const Box bar = make_box({2.0f, 0.3f, 0.3f});
  const Transform3 xa = Transform3::from_axis_angle({0, 0, 0}, {1, 0, 0}, 0.25f * test::kPi);
  const Quat qb = glm::angleAxis(0.5f * test::kPi, Vec3(0, 1, 0)) * glm::angleAxis(0.25f * test::kPi, Vec3(1, 0, 0));
  const float ridge = 0.3f * std::sqrt(2.0f);
  const Transform3 xb = Transform3::from({0.0f, 2.0f * ridge - 0.01f, 0.0f}, qb);
  const Manifold3 m = contact(bar, xa, bar, xb);
  ASSERT_EQ(m.count, 1);
  EXPECT_VEC3_NEAR(m.normal, Vec3(0, 1, 0), 1e-4f);
  EXPECT_NEAR(m.points[0].depth, 0.01f, 1e-4f);
  EXPECT_EQ(m.points[0].id.type_a, FeatureType::edge);
  EXPECT_EQ(m.points[0].id.type_b, FeatureType::edge);
}



TEST(Contact3, ACubeHullMakesTheSameContactsAsABox) {
  const Box box = make_box({0.5f, 0.7f, 0.9f});
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box.vertex(i));
  const ConvexHull cube = make_convex_hull(corners);
  ASSERT_EQ(cube.faces.size(), 6u);
  std::mt19937 rng(41);
  int touching = 0;
  for (int k = 0; k < 500; ++k) {
    const Box other = make_box({test::uniform(rng, 0.2f, 1.0f), test::uniform(rng, 0.2f, 1.0f), test::uniform(rng, 0.2f, 1.0f)});
    const Transform3 xa = test::random_transform3(rng, 0.3f);
    const Transform3 xb = Transform3::from(xa.p + test::random_point3(rng, 1.2f), test::random_rotation(rng));
    const Manifold3 from_box = contact(box, xa, other, xb);
    const Manifold3 from_hull = contact(cube, xa, other, xb);
    ASSERT_EQ(from_box.count, from_hull.count) << k;
    if (from_box.count == 0) continue;
    ++touching;
    EXPECT_VEC3_NEAR(from_box.normal, from_hull.normal, 1e-4f);
    EXPECT_NEAR(from_box.max_depth(), from_hull.max_depth(), 1e-4f);
  }
  EXPECT_GT(touching, 100);
}

/// A box against a triangle takes its own edge test (the nine axes named by their signs); a
/// cube hull takes the Gauss-map search: both must give the same contact.
TEST(Contact3, ACubeHullMakesTheSameTriangleContactsAsABox) {
  const Box box = make_box({0.5f, 0.7f, 0.9f});
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) corners.push_back(box.vertex(i));
  const ConvexHull cube = make_convex_hull(corners);
  std::mt19937 rng(43);
  int touching = 0, edge_normals = 0;
  for (int k = 0; k < 2000; ++k) {
    std::array<Vec3, 3> c;
    do {  // no slivers: make_triangle refuses the degenerate ones
      for (Vec3& p : c) p = test::random_point3(rng, 1.5f);
    } while (length(cross(c[1] - c[0], c[2] - c[0])) < 0.05f);
    const Triangle tri = make_triangle(c[0], c[1], c[2]);
    const Transform3 xa = test::random_transform3(rng, 0.3f);
    const Transform3 xb = test::random_transform3(rng, 0.3f);
    for (const float margin : {0.0f, 0.05f}) {
      const Manifold3 from_box = contact(box, xa, tri, xb, margin);
      const Manifold3 from_hull = contact(cube, xa, tri, xb, margin);
      ASSERT_EQ(from_box.touching(), from_hull.touching()) << k;
      if (!from_box.touching()) continue;
      ++touching;
      SCOPED_TRACE(k);
      EXPECT_VEC3_NEAR(from_box.normal, from_hull.normal, 1e-4f);
      EXPECT_NEAR(from_box.max_depth(), from_hull.max_depth(), 1e-4f) << k;
      // Normals along none of the box's or the triangle's face normals: edge axes were taken.
      const Vec3 n = inv_rotate(xa.q, from_box.normal);
      const float along_box = std::max({std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)});
      const float along_tri = std::fabs(dot(rotate(xb.q, triangle_normal(c[0], c[1], c[2])), from_box.normal));
      edge_normals += along_box < 0.999f && along_tri < 0.999f;
    }
  }
  EXPECT_GT(touching, 1000);
  EXPECT_GT(edge_normals, 100);
}

/// The property test, plus: every point lies in both shapes (its surface points, half
/// the depth each way, are within tolerance of the shapes), on random pairs.
void check_random_contacts(float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  int touching = 0;
  int apart = 0;
  int multi = 0;
  const Vec3 base(offset, -offset, 0.5f * offset);
  for (int k = 0; k < 2000; ++k) {
    const Shape3D sa = test::random_shape3(rng);
    const Shape3D sb = test::random_shape3(rng);
    const Transform3 xa = Transform3::from(base + test::random_point3(rng, 0.5f), test::random_rotation(rng));
    const Transform3 xb = Transform3::from(base + test::random_point3(rng, 1.5f), test::random_rotation(rng));
    const Manifold3 m = contact(sa, xa, sb, xb);
    const double truth = test::brute_distance(test::brute_core_of(sa, xa), test::brute_core_of(sb, xb));
    const float tol = 2e-4f + 4e-6f * offset;
    SCOPED_TRACE(testing::Message() << "pair " << k << " " << type_name(sa) << "-" << type_name(sb)
                                    << " truth " << truth << " count " << m.count
                                    << " depth " << m.max_depth());
    if (truth > tol) {
      EXPECT_EQ(m.count, 0);
      ++apart;
      continue;
    }
    if (truth > 0.0) continue;  // within rounding of touching: either answer
    // Overlapping: a manifold, whose normal and depth are the minimum translation.
    ASSERT_GT(m.count, 0);
    ++touching;
    if (m.count > 1) ++multi;
    EXPECT_NEAR(length(m.normal), 1.0f, 1e-5f);
    const float depth = m.max_depth();
    const float eps = 2e-3f + 4e-6f * offset;
    Transform3 moved = xb;
    moved.p = xb.p + (depth + eps) * m.normal;
    EXPECT_GT(test::brute_distance(test::brute_core_of(sa, xa), test::brute_core_of(sb, moved)), 0.0) << "depth + eps still overlaps";
    if (depth > 2.0f * eps) {
      moved.p = xb.p + (depth - eps) * m.normal;
      EXPECT_EQ(test::brute_distance(test::brute_core_of(sa, xa), test::brute_core_of(sb, moved)), 0.0) << "depth - eps apart";
    }
    for (int i = 0; i < m.count; ++i) {
      const ManifoldPoint3& p = m.points[i];
      EXPECT_LE(p.depth, depth + 1e-6f);
      const test::DVec3 on_a(p.point + 0.5f * p.depth * m.normal);
      const test::DVec3 on_b(p.point - 0.5f * p.depth * m.normal);
      EXPECT_LE(test::brute_point_distance(test::brute_core_of(sa, xa), on_a), 4.0 * tol) << "point " << i;
      EXPECT_LE(test::brute_point_distance(test::brute_core_of(sb, xb), on_b), 4.0 * tol) << "point " << i;
    }
  }
  EXPECT_GT(touching, 400) << apart;
  EXPECT_GT(apart, 400) << touching;
  EXPECT_GT(multi, 40);
}

TEST(Contact3, RandomPairsHaveMinimumTranslationNormalsAndDepths) { check_random_contacts(0.0f, 31); }
TEST(Contact3, RandomPairsFarFromTheOrigin) { check_random_contacts(1e4f, 32); }

}  // namespace
}  // namespace collide
