// 3D GJK distance (one loop with 2D; signed-volume simplex solver) against analytic answers and
// the brute-force reference of support/brute_convex3.hpp, under random rigid transforms.

#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>
#include <collide/narrow/gjk.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/ccd/shape_cast.hpp>

#include "support/brute_convex3.hpp"
#include "support/brute_triangle.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <random>

namespace collide {
namespace {


TEST(Gjk3, SphereSphereIsAnalytic) {
  const Sphere a = make_sphere({0, 0, 0}, 1.0f);
  const Sphere b = make_sphere({0, 0, 0}, 0.5f);
  const DistanceResult3 d =
      distance(a, Transform3{}, b, Transform3::from({3, 4, 0}, Quat{1, 0, 0, 0}));
  EXPECT_EQ(d.status, QueryStatus::separated);
  EXPECT_NEAR(d.distance, 3.5f, 1e-6f);
  EXPECT_VEC3_NEAR(d.point_a, Vec3(0.6f, 0.8f, 0.0f), 1e-6f);
  EXPECT_VEC3_NEAR(d.point_b, Vec3(2.7f, 3.6f, 0.0f), 1e-6f);
  EXPECT_VEC3_NEAR(d.normal, Vec3(0.6f, 0.8f, 0.0f), 1e-6f);
}

TEST(Gjk3, BoxFaceEdgeAndVertexDistancesAreAnalytic) {
  const Box a = make_box({1, 2, 3});
  const Box b = make_box({0.5f, 0.5f, 0.5f});
  // Face: B above A's +y face.
  DistanceResult3 d = distance(a, Transform3{}, b, Transform3::from({0.2f, 4.0f, -0.3f}, Quat{1, 0, 0, 0}));
  EXPECT_NEAR(d.distance, 1.5f, 1e-5f);
  EXPECT_VEC3_NEAR(d.normal, Vec3(0, 1, 0), 1e-5f);
  // Vertex against vertex along the diagonal.
  d = distance(a, Transform3{}, b, Transform3::from({3.5f, 4.5f, 5.5f}, Quat{1, 0, 0, 0}));
  EXPECT_NEAR(d.distance, std::sqrt(3.0f) * 2.0f, 1e-5f);
  EXPECT_VEC3_NEAR(d.point_a, Vec3(1, 2, 3), 1e-5f);
  EXPECT_VEC3_NEAR(d.point_b, Vec3(3, 4, 5), 1e-5f);
  // Edge against edge: B turned 45 degrees about z, beside A's +x face, its edge along z.
  const Transform3 turned = Transform3::from_axis_angle({3.0f, 0.0f, 0.0f}, {0, 0, 1}, 0.25f * test::kPi);
  d = distance(a, Transform3{}, b, turned);
  EXPECT_NEAR(d.distance, 2.0f - 0.5f * std::sqrt(2.0f), 1e-5f);
  // Overlapping cores.
  d = distance(a, Transform3{}, b, Transform3::from({0.5f, 0.5f, 0.5f}, Quat{1, 0, 0, 0}));
  EXPECT_EQ(d.status, QueryStatus::overlapped);
  EXPECT_EQ(d.distance, 0.0f);
}

/// Random pairs of every kind against the brute-force reference, under random rigid motions at
/// the origin and 1e4 away from it; both outcomes exercised.
void check_random_pairs(float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  int separated = 0;
  int overlapped = 0;
  for (int k = 0; k < 3000; ++k) {
    const float size = 1.0f;
    const Shape3D sa = test::random_shape3(rng, size);
    const Shape3D sb = test::random_shape3(rng, size);
    const Vec3 base = Vec3(offset, -0.5f * offset, 0.25f * offset);
    const Transform3 xa = Transform3::from(base + test::random_point3(rng, 1.0f), test::random_rotation(rng));
    const Transform3 xb = Transform3::from(base + test::random_point3(rng, 2.0f), test::random_rotation(rng));
    const DistanceResult3 d = distance(sa, xa, sb, xb);
    const test::BruteCore ca = test::brute_core_of(sa, xa);
    const test::BruteCore cb = test::brute_core_of(sb, xb);
    const double truth = test::brute_distance(ca, cb);
    const double core_truth = test::brute_core_distance(ca, cb);
    // Float rounding of the coordinates (|offset| + sizes) bounds the attainable accuracy.
    const float tol = 4e-6f * offset + 2e-5f;
    SCOPED_TRACE(testing::Message() << "pair " << k << " " << type_name(sa) << "-" << type_name(sb)
                                    << " truth " << truth << " core " << core_truth << " got "
                                    << d.distance << " status " << to_string(d.status));
    ASSERT_NE(d.status, QueryStatus::max_iterations);
    EXPECT_NEAR(d.distance, truth, tol);
    // The boolean query agrees outside the rounding band.
    const bool touching = overlap(sa, xa, sb, xb);
    if (truth > 2.0 * tol) EXPECT_FALSE(touching);
    if (truth == 0.0) EXPECT_TRUE(touching);
    EXPECT_EQ(overlap(sb, xb, sa, xa), touching);
    if (core_truth > 10.0 * tol) {
      ASSERT_EQ(d.status, QueryStatus::separated);
      // The witnesses: their gap is the distance (apart), each on its own shape's surface.
      if (truth > 0.0) {
        EXPECT_NEAR(distance(d.point_a, d.point_b), d.distance, tol);
        EXPECT_NEAR(length(d.normal), 1.0f, 1e-5f);
        EXPECT_NEAR(dot(d.point_b - d.point_a, d.normal), d.distance, tol);
      }
      const test::DVec3 pa(d.point_a);
      const test::DVec3 pb(d.point_b);
      EXPECT_LE(test::brute_point_distance(ca, pa), tol);
      EXPECT_LE(test::brute_point_distance(cb, pb), tol);
      ++separated;
    } else if (core_truth == 0.0) {
      // Overlapping cores: GJK must find the origin inside A - B.
      EXPECT_EQ(d.status, QueryStatus::overlapped);
      ++overlapped;
    }
  }
  EXPECT_GT(separated, 600) << overlapped;
  EXPECT_GT(overlapped, 100) << separated;
}

TEST(Gjk3, RandomPairsMatchBruteForce) { check_random_pairs(0.0f, 11); }
TEST(Gjk3, RandomPairsFarFromTheOriginMatchBruteForce) { check_random_pairs(1e4f, 12); }

TEST(Gjk3, WarmStartGivesTheSameAnswerInFewerIterations) {
  std::mt19937 rng(5);
  int cold_total = 0;
  int warm_total = 0;
  for (int k = 0; k < 300; ++k) {
    const Box a = make_box({1.0f, 0.5f, 0.7f});
    const Box b = make_box({0.3f, 0.8f, 0.4f});
    Transform3 xb = Transform3::from(test::random_point3(rng, 3.0f) + Vec3(4, 0, 0), test::random_rotation(rng));
    SimplexCache3 cache;
    (void)distance(a, Transform3{}, b, xb, &cache);
    // Move B a little: the cached simplex is near the answer.
    xb.p += Vec3(0.01f, -0.02f, 0.015f);
    const DistanceResult3 cold = distance(a, Transform3{}, b, xb);
    const DistanceResult3 warm = distance(a, Transform3{}, b, xb, &cache);
    EXPECT_NEAR(warm.distance, cold.distance, 1e-4f);
    cold_total += cold.iterations;
    warm_total += warm.iterations;
  }
  EXPECT_LT(warm_total, cold_total);
}

TEST(Gjk3, SizeRatioOf1e4StaysAccurate) {
  std::mt19937 rng(3);
  for (int k = 0; k < 500; ++k) {
    const Box big = make_box({100.0f, 50.0f, 80.0f});
    const Sphere small = make_sphere({0, 0, 0}, 0.01f);
    const Transform3 xb = Transform3::from(test::random_point3(rng, 120.0f), Quat{1, 0, 0, 0});
    const DistanceResult3 d = distance(big, Transform3{}, small, xb);
    const double truth = test::brute_distance(test::brute_core(big, Transform3{}), test::brute_core(small, xb));
    EXPECT_NEAR(d.distance, truth, 2e-3f) << k;
  }
}

// GJK's search direction grows as the cube of the simplex's size (a segment's is |e|^2 times its
// perpendicular), its square as the sixth power: for a needle 4e8 long (within
// kFiniteQueryRange) the square overflowed, "origin on the simplex" followed, and a sphere 1e8
// away was reported overlapping; the cast reported a hit at fraction 0 (found by the fuzzer's
// cast check, stop 105). Needles and long triangles 1e5 to 1e9 long, a sphere a quarter of the
// way out: the distance against brute force in double, and a cast towards the nearest point
// touching when the distance says.
TEST(Gjk3, HugeSimplexesKeepTheirSearchDirection) {
  std::mt19937 rng(105);
  for (const float size : {1e5f, 1e6f, 1e7f, 1e8f, 4e8f, 1e9f}) {
    for (int k = 0; k < 40; ++k) {
      const Quat q = test::random_rotation(rng);
      const float width = k % 2 == 0 ? 8.0f : 0.3f * size;
      const std::array<Vec3, 3> corners{rotate(q, Vec3(0.0f)), rotate(q, Vec3(0.0f, width, -size)), rotate(q, Vec3(0.0f, 0.0f, 8.0f))};
      const test::DVec3 a(corners[0]), b(corners[1]), c(corners[2]);
      // A point off the triangle's middle, a quarter of its size out of its plane and beyond.
      const Vec3 centre = 0.5f * (corners[0] + corners[1]) + 0.25f * size * rotate(q, Vec3(1.0f, 0.3f, 0.1f));
      const test::DVec3 nearest = test::brute_closest_on_triangle(test::DVec3(centre), a, b, c);
      const double truth = glm::length(nearest - test::DVec3(centre));
      const float r = static_cast<float>(0.25 * truth);
      const Sphere s = make_sphere(Vec3(0.0f), r);
      const Transform3 xs{centre, Quat{1, 0, 0, 0}};
      const DistanceResult3 d = gjk_distance<3>(ConvexProxy3(s), xs, ConvexProxy3(Triangle{corners}), Transform3{});
      ASSERT_EQ(d.status, QueryStatus::separated) << size << " " << k;
      EXPECT_NEAR(d.distance, truth - r, 1e-5 * truth) << size << " " << k;
      // Towards the nearest point by twice the distance: touching at (truth - r) / |v|.
      const Vec3 v = 2.0f * Vec3(nearest - test::DVec3(centre));
      const ShapeCastResult3 cast =
          gjk_shape_cast<3>(ConvexProxy3(s), xs, v, ConvexProxy3(Triangle{corners}), Transform3{}, Vec3(0.0f));
      ASSERT_TRUE(cast.hit) << size << " " << k;
      EXPECT_NEAR(cast.fraction, 0.375, 1e-4) << size << " " << k;
    }
  }
}

// Two boxes, B turned off the axes, overlapping by 1.0 s and then 0.99 s apart, scaled by powers
// of two from 2^-60 to 2^20: distance, overlap and penetration scale with them. The simplex
// solver's sub-areas and sub-volumes are fourth and third powers of the size and EPA's face
// normals second powers: below about 2^-37 they underflowed, the overlapping pair read 0.32 s
// apart and the apart pair 1.45 s (finding 29, docs/fuzzing.md), and EPA's faces had no
// direction. The distance against brute force at unit size; every scale against the unit
// size, to float rounding (a power of two changes none, but the loops' absolute terms round at
// other bits).
TEST(Gjk3, BoxPairAnswersAlikeAtEveryScale) {
  const Quat turn = glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f});
  struct Answer {
    float penetration_depth, distance;
    Vec3 penetration_normal, distance_normal;
  };
  const auto ask = [&](int e) {
    const float s = std::ldexp(1.0f, e);
    const Box box = make_box(Vec3(s, 1.25f * s, 1.5f * s));
    const Transform3 in{Vec3(1.7f * s, 0.3f * s, 0.2f * s), turn};
    const Transform3 apart{Vec3(3.7f * s, 0.3f * s, 0.2f * s), turn};
    const PenetrationResult3 p = penetration(box, Transform3{}, box, in);
    EXPECT_EQ(p.status, QueryStatus::overlapped) << "at 2^" << e;
    const DistanceResult3 d = distance(box, Transform3{}, box, apart);
    EXPECT_EQ(d.status, QueryStatus::separated) << "at 2^" << e;
    EXPECT_GT(p.depth, 0.0f) << "at 2^" << e;
    EXPECT_LT(p.depth, 2.0f * s) << "at 2^" << e;
    EXPECT_TRUE(overlap(box, Transform3{}, box, in)) << "at 2^" << e;
    EXPECT_FALSE(overlap(box, Transform3{}, box, apart)) << "at 2^" << e;
    return Answer{p.depth / s, d.distance / s, p.normal, d.normal};
  };
  const Answer unit = ask(0);
  // At unit size, the distance against brute force (double; its own tolerances are absolute, so
  // it is asked there only).
  const Box box = make_box(Vec3(1.0f, 1.25f, 1.5f));
  const double truth = test::brute_distance(test::brute_core(box, Transform3{}),
                                            test::brute_core(box, Transform3{Vec3(3.7f, 0.3f, 0.2f), turn}));
  EXPECT_NEAR(double(unit.distance), truth, 1e-5);
  for (const int e : {-60, -55, -50, -45, -40, -35, -30, -20, 10, 20}) {
    const Answer a = ask(e);
    EXPECT_NEAR(a.penetration_depth, unit.penetration_depth, 1e-5f) << "at 2^" << e;
    EXPECT_NEAR(a.distance, unit.distance, 1e-5f) << "at 2^" << e;
    EXPECT_VEC3_NEAR(a.penetration_normal, unit.penetration_normal, 1e-5f);
    EXPECT_VEC3_NEAR(a.distance_normal, unit.distance_normal, 1e-5f);
  }
}

}  // namespace
}  // namespace collide
