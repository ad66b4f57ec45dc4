// EPA penetration depth (narrow/epa.hpp): analytic cases, the degenerate endings of GJK (a point,
// a segment or a flat triangle through the origin), touching and nearly touching pairs (GJK and
// EPA agree on the sign), and on random pairs the brute-force minimum translation (moving B by
// depth + eps along the normal separates, by depth - eps does not) and agreement with the
// specialised `contact` (SAT) on depth and normal, near the origin and 1e4 away. A support map
// that is not a collide shape runs through run_epa too.

#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>

#include "support/brute_convex3.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

const Quat kIdentity{1.0f, 0.0f, 0.0f, 0.0f};

Transform3 at(Vec3 p) { return Transform3::from(p, kIdentity); }

test::BruteCore brute(const Shape3D& s, const Transform3& xf) {
  return std::visit([&](const auto& v) { return test::brute_core(v, xf); }, s);
}

/// The property of a minimum translation: B moved by depth + eps along the normal is apart,
/// by depth - eps still overlapping (when the depth leaves room for that).
void expect_minimum_translation(const Shape3D& a, const Transform3& xa, const Shape3D& b,
                                const Transform3& xb, const PenetrationResult3& r, float eps) {
  Transform3 moved = xb;
  moved.p = xb.p + (r.depth + eps) * r.normal;
  EXPECT_GT(test::brute_distance(brute(a, xa), brute(b, moved)), 0.0) << "depth + eps overlaps";
  if (r.depth > 2.0f * eps) {
    moved.p = xb.p + (r.depth - eps) * r.normal;
    EXPECT_EQ(test::brute_distance(brute(a, xa), brute(b, moved)), 0.0) << "depth - eps apart";
  }
}

TEST(Epa, BoxesOverlappingOnAFace) {
  const Box a = make_box({1.0f, 1.0f, 1.0f});
  const Box b = make_box({0.5f, 0.5f, 0.5f});
  const PenetrationResult3 r = penetration(a, Transform3{}, b, at({1.3f, 0.2f, -0.1f}));
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.2f, 1e-5f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(1, 0, 0), 1e-5f);
  // A's deepest point is on A's +x face, B's on B's -x face: 0.2 apart along the normal.
  EXPECT_NEAR(r.point_a.x, 1.0f, 1e-5f);
  EXPECT_NEAR(r.point_b.x, 0.8f, 1e-5f);
  EXPECT_VEC3_NEAR(r.point_a - r.point_b, r.depth * r.normal, 1e-5f);
  // Swapped: the same depth, the normal flipped.
  const PenetrationResult3 s = penetration(b, at({1.3f, 0.2f, -0.1f}), a, Transform3{});
  EXPECT_NEAR(s.depth, 0.2f, 1e-5f);
  EXPECT_VEC3_NEAR(s.normal, Vec3(-1, 0, 0), 1e-5f);
}

TEST(Epa, SpheresCapsulesAndRoundedBoxes) {
  const Sphere ball = make_sphere({0, 0, 0}, 0.5f);
  // Sphere pair: depth ra + rb - d along the centres' line (GJK's closest points, no EPA).
  PenetrationResult3 r = penetration(ball, Transform3{}, ball, at({0.6f, 0.0f, 0.8f}));
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.0f, 1e-6f);  // exactly touching: |c| = 1
  EXPECT_VEC3_NEAR(r.normal, Vec3(0.6f, 0.0f, 0.8f), 1e-6f);
  r = penetration(ball, Transform3{}, ball, at({0.3f, 0.0f, 0.4f}));
  EXPECT_NEAR(r.depth, 0.5f, 1e-6f);
  // Deep: a sphere whose centre is inside a box, 0.1 below the +y face.
  const Box box = make_box({1.0f, 1.0f, 1.0f});
  r = penetration(box, Transform3{}, make_sphere({0, 0, 0}, 0.3f), at({0.2f, 0.9f, -0.1f}));
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.4f, 1e-5f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(0, 1, 0), 1e-5f);
  EXPECT_VEC3_NEAR(r.point_a, Vec3(0.2f, 1.0f, -0.1f), 1e-5f);
  // A rounded box: the radius adds to the depth of the cores.
  r = penetration(make_box({1.0f, 1.0f, 1.0f}, 0.2f), Transform3{}, box, at({0.0f, 0.0f, 2.1f}));
  EXPECT_NEAR(r.depth, 0.1f, 1e-5f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(0, 0, 1), 1e-5f);
  r = penetration(make_box({1.0f, 1.0f, 1.0f}, 0.2f), Transform3{}, box, at({0.0f, 0.0f, 1.6f}));
  EXPECT_NEAR(r.depth, 0.6f, 1e-5f);  // cores overlap by 0.4: EPA, then the radius
  // Apart: separated, minus the distance.
  r = penetration(box, Transform3{}, ball, at({0.0f, 2.0f, 0.0f}));
  EXPECT_EQ(r.status, QueryStatus::separated);
  EXPECT_NEAR(r.depth, -0.5f, 1e-6f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(0, 1, 0), 1e-6f);
  EXPECT_VEC3_NEAR(r.point_a - r.point_b, r.depth * r.normal, 1e-6f);
}

// GJK stops as soon as the origin is on its simplex, which may be a point, a segment or a
// triangle deep inside A - B. EPA grows it first.
TEST(Epa, GrowsTheSimplexsThatGjkEndsWith) {
  const Box box = make_box({1.0f, 2.0f, 3.0f});
  const Sphere ball = make_sphere({0, 0, 0}, 0.25f);
  // The ball at the box's centre: A - B is the box about the origin, and GJK's first segment
  // (corner to opposite corner) passes through the origin.
  PenetrationResult3 r = penetration(box, Transform3{}, ball, Transform3{});
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 1.25f, 1e-5f);
  EXPECT_NEAR(std::fabs(r.normal.x), 1.0f, 1e-5f);
  // Concentric spheres: A - B is a point: depth ra + rb in any direction.
  r = penetration(ball, at({3, 4, 5}), make_sphere({0, 0, 0}, 0.5f), at({3, 4, 5}));
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.75f, 1e-6f);
  EXPECT_NEAR(length(r.normal), 1.0f, 1e-6f);
  // Crossed capsules whose core segments intersect: A - B is flat (a parallelogram through the
  // origin): the cores touch, depth ra + rb along the plane's normal (the side towards B's
  // origin when there is one).
  const Capsule3 cap = make_capsule({-1, 0, 0}, {1, 0, 0}, 0.2f);
  const Transform3 crossed = Transform3::from_axis_angle({0.3f, 0.0f, 0.0f}, {0, 1, 0}, 0.5f * kPi);
  r = penetration(cap, Transform3{}, cap, crossed);
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.4f, 1e-5f);
  EXPECT_NEAR(std::fabs(r.normal.y), 1.0f, 1e-5f);
  // A sphere's centre on a capsule's core segment: A - B is a segment through the origin.
  r = penetration(cap, Transform3{}, ball, at({0.4f, 0.0f, 0.0f}));
  EXPECT_NEAR(r.depth, 0.45f, 1e-5f);
  EXPECT_NEAR(r.normal.x, 0.0f, 1e-5f);
  // Two segments crossing: flat A - B, both radii zero: touching, depth 0.
  const Segment3 seg = make_segment({-1, 0, 0}, {1, 0, 0});
  r = penetration(seg, Transform3{}, seg, crossed);
  EXPECT_EQ(r.status, QueryStatus::overlapped);
  EXPECT_NEAR(r.depth, 0.0f, 1e-5f);
  // A segment through a box: it must leave through the nearer side of the box.
  r = penetration(box, Transform3{}, make_segment({0, -5, 0}, {0, 5, 0}), at({0.7f, 0.0f, 0.0f}));
  EXPECT_NEAR(r.depth, 0.3f, 1e-5f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(1, 0, 0), 1e-5f);
}

// Touching and nearly touching: the sign of the depth agrees with GJK's distance on both
// sides, down to float rounding. Pairs of random shapes under random rotations are first
// separated along EPA's normal to touching, then moved by +-delta.
TEST(Epa, TouchingAndNearlyTouchingAgreeWithGjk) {
  std::mt19937 rng(61);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    const Shape3D a = k % 2 ? Shape3D(make_box({uniform(rng, 0.2f, 1.0f), uniform(rng, 0.2f, 1.0f),
                                                uniform(rng, 0.2f, 1.0f)}))
                            : Shape3D(make_capsule(test::random_point3(rng, 1.0f),
                                                   test::random_point3(rng, 1.0f), 0.2f));

    const Shape3D b = make_box({uniform(rng, 0.2f, 1.0f), uniform(rng, 0.2f, 1.0f), uniform(rng, 0.2f, 1.0f)},
                               k % 3 == 0 ? 0.1f : 0.0f);
    const Transform3 xa = Transform3::from(test::random_point3(rng, 0.3f), test::random_rotation(rng));
    Transform3 xb = Transform3::from(test::random_point3(rng, 0.3f), test::random_rotation(rng));
    const PenetrationResult3 deep = penetration(a, xa, b, xb);
    if (deep.status != QueryStatus::overlapped) continue;
    const Transform3 touch{xb.p + deep.depth * deep.normal, xb.q};
    const PenetrationResult3 at_touch = penetration(a, xa, b, touch);
    EXPECT_NEAR(at_touch.depth, 0.0f, 1e-4f) << k;
    for (const float delta : {1e-3f, 1e-4f}) {
      xb = Transform3{touch.p + delta * deep.normal, touch.q};
      const PenetrationResult3 out = penetration(a, xa, b, xb);
      const DistanceResult3 d = distance(a, xa, b, xb);
      EXPECT_EQ(out.status, QueryStatus::separated) << k << " " << delta;
      EXPECT_NEAR(out.depth, -d.distance, 1e-6f);
      EXPECT_NEAR(out.depth, -delta, 0.2f * delta);
      xb = Transform3{touch.p - delta * deep.normal, touch.q};
      const PenetrationResult3 in = penetration(a, xa, b, xb);
      EXPECT_EQ(in.status, QueryStatus::overlapped) << k << " " << delta;
      EXPECT_NEAR(in.depth, delta, 0.2f * delta) << k;
      ++checked;
    }
  }
  EXPECT_GT(checked, 400);
}

// Boxes on a grid, turned by multiples of 90 degrees: A - B has many coplanar support points
// (every corner pair on a face), exact touching, and exact ties between planes.
TEST(Epa, GridAlignedBoxesWithTiesAndExactTouching) {
  // Regression: a polytope face with another normal but the same plane distance (0.25) as the
  // nearest face of A - B was reported, because its triangle was nearer the origin than the
  // nearest plane's triangle (the origin projects into another triangle of that plane).
  const PenetrationResult3 tie = penetration(make_box({1.0f, 0.25f, 0.75f}), Transform3{},
                                             make_box({0.25f, 0.5f, 1.0f}), at({-0.25f, -0.5f, 0.25f}));
  EXPECT_NEAR(tie.depth, 0.25f, 1e-6f);
  EXPECT_VEC3_NEAR(tie.normal, Vec3(0, -1, 0), 1e-6f);
  EXPECT_VEC3_NEAR(tie.point_a - tie.point_b, tie.depth * tie.normal, 1e-6f);

  std::mt19937 rng(65);
  const auto quarter = [&] { return 0.25f * float(std::uniform_int_distribution<int>(1, 4)(rng)); };
  const auto grid = [&] { return 0.25f * float(std::uniform_int_distribution<int>(-4, 4)(rng)); };
  const auto turn = [&] {
    const float h = 0.25f * kPi * float(std::uniform_int_distribution<int>(0, 3)(rng));
    Vec3 axis(0.0f);
    axis[std::uniform_int_distribution<int>(0, 2)(rng)] = 1.0f;
    return Quat{std::cos(h), std::sin(h) * axis.x, std::sin(h) * axis.y, std::sin(h) * axis.z};
  };
  int touching = 0;
  int overlapping = 0;
  for (int k = 0; k < 1000; ++k) {
    const Shape3D a = make_box({quarter(), quarter(), quarter()});
    const Shape3D b = make_box({quarter(), quarter(), quarter()});
    const Transform3 xa{Vec3(0.0f), turn()};
    const Transform3 xb{{grid(), grid(), grid()}, turn()};
    const PenetrationResult3 r = penetration(a, xa, b, xb);
    const double truth = test::brute_distance(brute(a, xa), brute(b, xb));
    SCOPED_TRACE(testing::Message() << "case " << k << " truth " << truth << " depth " << r.depth);
    ASSERT_NE(r.status, QueryStatus::max_iterations);
    if (truth > 1e-5) {
      EXPECT_EQ(r.status, QueryStatus::separated);
      EXPECT_NEAR(-r.depth, truth, 1e-5);
      continue;
    }
    if (truth > 0.0) {
      // Touching within the rounding of the turned boxes' corners (1e-8): either side of 0.
      EXPECT_LE(std::fabs(r.depth), 1e-5f);
      continue;
    }
    ASSERT_EQ(r.status, QueryStatus::overlapped);
    EXPECT_VEC3_NEAR(r.point_a - r.point_b, r.depth * r.normal, 1e-5f);
    if (r.depth < 1e-5f) {
      ++touching;
      continue;
    }
    ++overlapping;
    expect_minimum_translation(a, xa, b, xb, r, 1e-4f);
    EXPECT_LE(test::brute_point_distance(brute(a, xa), test::DVec3(r.point_a)), 1e-5);
    EXPECT_LE(test::brute_point_distance(brute(b, xb), test::DVec3(r.point_b)), 1e-5);
  }
  EXPECT_GT(touching, 50);
  EXPECT_GT(overlapping, 400);
}

Shape3D random_shape3(std::mt19937& rng) {
  switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
    case 0: return make_sphere(test::random_point3(rng, 0.2f), uniform(rng, 0.1f, 1.0f));
    case 1:
      return make_capsule(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f),
                          uniform(rng, 0.05f, 0.5f));
    case 2: return make_segment(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f));
    case 3:
    case 4:
      return make_box({uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f)});
    default:
      return make_box({uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f)},
                      uniform(rng, 0.01f, 0.3f));
  }
}

/// Size of a shape for the tolerances: its bounding box's largest extent.
float size_of(const Shape3D& s) {
  const Aabb3 box = compute_aabb(s, Transform3{});
  return max_abs(box.max - box.min);
}

/// Random pairs: the minimum-translation property against the brute force, the same depth and
/// (up to ties between axes) the same normal as `contact`, the points on the shapes, and the
/// swapped pair.
void check_random_pairs(float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const Vec3 base(offset, -offset, 0.5f * offset);
  int overlapping = 0;
  int apart = 0;
  int same_normal = 0;
  int compared = 0;
  int with_epa = 0;
  int contact_shallower = 0;
  for (int k = 0; k < 2000; ++k) {
    const Shape3D sa = random_shape3(rng);
    const Shape3D sb = random_shape3(rng);
    const Transform3 xa = Transform3::from(base + test::random_point3(rng, 0.5f), test::random_rotation(rng));
    const Transform3 xb = Transform3::from(base + test::random_point3(rng, 1.5f), test::random_rotation(rng));
    const PenetrationResult3 r = penetration(sa, xa, sb, xb);
    const double truth = test::brute_distance(brute(sa, xa), brute(sb, xb));
    const float tol = 2e-4f + 4e-6f * offset;
    SCOPED_TRACE(testing::Message() << "pair " << k << " " << type_name(sa) << "-" << type_name(sb)
                                    << " truth " << truth << " depth " << r.depth << " "
                                    << to_string(r.status) << " iterations " << r.iterations);
    ASSERT_NE(r.status, QueryStatus::max_iterations);
    EXPECT_NEAR(length(r.normal), 1.0f, 1e-5f);
    EXPECT_VEC3_NEAR(r.point_a - r.point_b, r.depth * r.normal, 1e-5f + 2e-6f * offset);
    if (truth > tol) {
      EXPECT_EQ(r.status, QueryStatus::separated);
      EXPECT_NEAR(-r.depth, truth, tol);
      ++apart;
      continue;
    }
    if (truth > 0.0) continue;  // within rounding of touching: either sign
    ASSERT_EQ(r.status, QueryStatus::overlapped);
    ++overlapping;
    // EPA ran when the cores overlap: GJK's distance of the cores is zero.
    if (distance(sa, xa, sb, xb).status == QueryStatus::overlapped) ++with_epa;
    const float eps = 1e-4f + 4e-6f * offset;
    expect_minimum_translation(sa, xa, sb, xb, r, eps);
    // The points: A's lies in A (on its surface), B's in B.
    EXPECT_LE(test::brute_point_distance(brute(sa, xa), test::DVec3(r.point_a)), 4.0 * tol);
    EXPECT_LE(test::brute_point_distance(brute(sb, xb), test::DVec3(r.point_b)), 4.0 * tol);
    // contact's SAT depth is the minimum too, up to its preference for face axes (within
    // kEdgeContactTolerance of the smaller size, so it may be deeper) and the clipping of the
    // incident feature (a clipped point is shallower than the axis' overlap, so it may be less
    // deep than the minimum translation: counted, and bounded).
    const Manifold3 m = contact(sa, xa, sb, xb);
    ASSERT_GT(m.count, 0);
    const float smaller = std::min(size_of(sa), size_of(sb));
    if (r.depth > m.max_depth() + tol) {
      ++contact_shallower;
      EXPECT_LE(r.depth, m.max_depth() + kEdgeContactTolerance * smaller);
    }
    EXPECT_GE(r.depth, m.max_depth() - 2.0f * kEdgeContactTolerance * smaller - tol);
    ++compared;
    if (dot(r.normal, m.normal) > 0.999f) {
      ++same_normal;
    } else {
      // A different normal is a tie: contact's normal moves B out by its depth as well.
      const PenetrationResult3 as_contact{QueryStatus::overlapped, m.max_depth(), m.normal,
                                          r.point_a, r.point_b, 0};
      expect_minimum_translation(sa, xa, sb, xb, as_contact, eps + 2.0f * kEdgeContactTolerance * smaller);
    }
    // Swapped: the same depth, the opposite normal (up to ties).
    const PenetrationResult3 s = penetration(sb, xb, sa, xa);
    EXPECT_NEAR(s.depth, r.depth, tol);
  }
  EXPECT_GT(overlapping, 500) << apart;
  EXPECT_GT(apart, 400) << overlapping;
  EXPECT_GT(with_epa, 300);
  EXPECT_GT(same_normal, compared * 95 / 100) << compared;
  EXPECT_LT(contact_shallower, compared / 100) << compared;
}

TEST(Epa, RandomPairsAreMinimumTranslationsAndAgreeWithContact) { check_random_pairs(0.0f, 62); }
TEST(Epa, RandomPairsFarFromTheOrigin) { check_random_pairs(1e4f, 63); }

TEST(Epa, HullPairsTakeTheHullSupportMapWithTheProxysAnswerBitForBit) {
  // penetration(hull, hull) runs on HullSupportMap; epa_penetration on ConvexProxy3 is the
  // general route. Same support points, so the same answer to the bit.
  std::mt19937 rng(64);
  int overlapping = 0;
  for (int i = 0; i < 300; ++i) {
    std::vector<Vec3> ca, cb;
    const int na = 4 + i % 30, nb = 4 + (i * 7) % 40;
    for (int k = 0; k < na; ++k) ca.push_back({uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)});
    for (int k = 0; k < nb; ++k) cb.push_back({uniform(rng, -1, 1), uniform(rng, -0.5f, 0.5f), uniform(rng, -1, 1)});
    const ConvexHull a = make_convex_hull(ca, HullOptions{.radius = i % 3 == 0 ? 0.1f : 0.0f});
    const ConvexHull b = make_convex_hull(cb);
    const Transform3 xa = Transform3::from({uniform(rng, -1, 1), 0.0f, 0.0f}, test::random_rotation(rng));
    const Transform3 xb = Transform3::from({uniform(rng, -1, 1), uniform(rng, -1, 1), 0.0f}, test::random_rotation(rng));
    const PenetrationResult3 fast = penetration(a, xa, b, xb);
    const PenetrationResult3 general = epa_penetration(ConvexProxy3(a), xa, ConvexProxy3(b), xb);
    ASSERT_EQ(fast.status, general.status);
    ASSERT_EQ(fast.depth, general.depth);
    ASSERT_EQ(fast.normal, general.normal);
    ASSERT_EQ(fast.point_a, general.point_a);
    ASSERT_EQ(fast.point_b, general.point_b);
    ASSERT_EQ(fast.iterations, general.iterations);
    overlapping += fast.depth > 0.0f;
  }
  EXPECT_GT(overlapping, 150);
}

/// A support map that is not a collide shape: a regular octahedron of "radius" r (its six
/// vertices on the axes), scanning its points.
struct Octahedron {
  std::array<Vec3, 6> p;
  explicit Octahedron(float r)
      : p{Vec3(r, 0, 0), Vec3(-r, 0, 0), Vec3(0, r, 0), Vec3(0, -r, 0), Vec3(0, 0, r), Vec3(0, 0, -r)} {}
  [[nodiscard]] int support_index(Vec3 d) const {
    int best = 0;
    for (int i = 1; i < 6; ++i) {
      if (dot(p[i], d) > dot(p[best], d)) best = i;
    }
    return best;
  }
  [[nodiscard]] int support_index_from(Vec3 d, int) const { return support_index(d); }
  [[nodiscard]] Vec3 point(int i) const { return p[i]; }
  [[nodiscard]] int count() const { return 6; }
  [[nodiscard]] float radius() const { return 0.0f; }
};

test::BruteCore brute_octahedron(float r, const Transform3& xf) {
  test::BruteCore c;
  const Octahedron o(r);
  for (const Vec3& v : o.p) c.points.push_back(test::to_world(xf, v));
  // Faces: one per octant, wound outward (sx, sy, sz the signs).
  for (int sx = 0; sx < 2; ++sx) {
    for (int sy = 0; sy < 2; ++sy) {
      for (int sz = 0; sz < 2; ++sz) {
        const int x = sx, y = 2 + sy, z = 4 + sz;
        const bool odd = (sx + sy + sz) % 2 == 1;  // mirrored an odd number of times
        c.triangles.push_back(odd ? std::array<int, 3>{x, z, y} : std::array<int, 3>{x, y, z});
      }
    }
  }
  return c;
}

TEST(Epa, AnySupportMapThroughRunEpa) {
  std::mt19937 rng(64);
  const Octahedron octa(1.0f);
  const Box box = make_box({0.4f, 0.3f, 0.5f});
  const ConvexProxy3 pbox(box);
  int deep = 0;
  for (int k = 0; k < 200; ++k) {
    const Transform3 xb = Transform3::from(test::random_point3(rng, 0.8f), test::random_rotation(rng));
    const Frame3 b_in_a = to_frame(xb);  // A (the octahedron) at the identity
    GjkSimplexN<3> s;
    s.v[0] = gjk_seed_vertex<3>(octa, pbox, b_in_a);
    s.count = 1;
    const float scale = gjk_scale<3>(s.v[0], 0.0f);
    int iterations = 0;
    if (run_gjk<3>(octa, pbox, b_in_a, s, scale, GjkRunToEnd{}, iterations) != GjkEnd::overlapped) {
      continue;
    }
    const EpaResult e = run_epa(octa, pbox, b_in_a, s, scale);
    ASSERT_EQ(e.status, QueryStatus::overlapped);
    EXPECT_VEC3_NEAR(e.point_a - e.point_b, e.depth * e.normal, 1e-5f);
    // B moved by depth + eps along the normal separates, by depth - eps does not.
    const test::BruteCore oa = brute_octahedron(1.0f, Transform3{});
    const float eps = 2e-3f;
    Transform3 moved = xb;
    moved.p = xb.p + (e.depth + eps) * e.normal;
    EXPECT_GT(test::brute_core_distance(oa, test::brute_core(box, moved)), 0.0) << k;
    if (e.depth > 2.0f * eps) {
      moved.p = xb.p + (e.depth - eps) * e.normal;
      EXPECT_EQ(test::brute_core_distance(oa, test::brute_core(box, moved)), 0.0) << k;
      ++deep;
    }
  }
  EXPECT_GT(deep, 100);
}

}  // namespace
}  // namespace collide
