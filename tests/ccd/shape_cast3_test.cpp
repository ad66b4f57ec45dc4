// 3D shape casts (the lesson's ray into the Minkowski difference A - B, by the one GJK loop)
// against the brute-force reference: the distance between translating convex shapes is convex
// in time, so the first touch is found by a ternary search for the closest approach and a
// bisection before it.

#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>

#include "support/brute_convex3.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <random>

namespace collide {
namespace {


/// The brute-force first touch of two translating shapes.
struct CastTruth {
  Shape3D a, b;
  Transform3 xa, xb;
  Vec3 va, vb;

  [[nodiscard]] double distance_at(double t) const {
    Transform3 ya = xa;
    Transform3 yb = xb;
    ya.p += float(t) * va;
    yb.p += float(t) * vb;
    const auto ca = test::brute_core_of(a, ya);
    const auto cb = test::brute_core_of(b, yb);
    return test::brute_distance(ca, cb);
  }
  /// First t in [0, 1] with distance 0, or -1 when they never touch (closest approach > 0).
  [[nodiscard]] double first_touch(double& min_distance) const {
    return test::brute_first_touch([this](double t) { return distance_at(t); }, min_distance);
  }
};

TEST(ShapeCast3, SphereIntoBoxFaceIsAnalytic) {
  const Box box = make_box({1, 1, 1});
  const Sphere ball = make_sphere({0, 0, 0}, 0.5f);
  // The ball starts 4 above the box's centre and falls 4: it touches the top face at 2.5 / 4.
  const ShapeCastResult3 r = shape_cast(box, Transform3{}, Vec3(0.0f), ball,
                                        Transform3::from({0.3f, 4.0f, -0.2f}, Quat{1, 0, 0, 0}),
                                        Vec3(0, -4, 0));
  EXPECT_EQ(r.status, QueryStatus::hit);
  EXPECT_NEAR(r.fraction, 2.5f / 4.0f, 1e-4f);
  EXPECT_VEC3_NEAR(r.normal, Vec3(0, 1, 0), 1e-4f);
  EXPECT_VEC3_NEAR(r.point, Vec3(0.3f, 1.0f, -0.2f), 1e-3f);
}

TEST(ShapeCast3, OverlappingAtTheStartAndMissingAreReported) {
  const Box box = make_box({1, 1, 1});
  const Sphere ball = make_sphere({0, 0, 0}, 0.5f);
  const ShapeCastResult3 over = shape_cast(box, Transform3{}, Vec3(0.0f), ball,
                                           Transform3::from({0.5f, 0.5f, 0.5f}, Quat{1, 0, 0, 0}), Vec3(1, 0, 0));
  EXPECT_EQ(over.status, QueryStatus::overlapped);
  EXPECT_EQ(over.fraction, 0.0f);
  const ShapeCastResult3 miss = shape_cast(box, Transform3{}, Vec3(0.0f), ball,
                                           Transform3::from({0, 4, 0}, Quat{1, 0, 0, 0}), Vec3(5, 0, 0));
  EXPECT_EQ(miss.status, QueryStatus::separated);
  EXPECT_FALSE(miss.hit);
  EXPECT_EQ(miss.fraction, 1.0f);
  EXPECT_THROW((void)shape_cast(box, Transform3{}, Vec3(NAN, 0, 0), ball, Transform3{}, Vec3(0.0f)),
               InvalidInput);
}

void check_random_casts(float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  int hits = 0;
  int misses = 0;
  for (int k = 0; k < 800; ++k) {
    CastTruth c{test::random_shape3(rng, 1.0f), test::random_shape3(rng, 1.0f), {}, {}, {}, {}};
    const Vec3 base(offset, 0.5f * offset, -offset);
    c.xa = Transform3::from(base + test::random_point3(rng, 1.0f), test::random_rotation(rng));
    c.xb = Transform3::from(base + test::random_point3(rng, 5.0f), test::random_rotation(rng));
    c.va = test::random_point3(rng, 3.0f);
    c.vb = (c.xa.p - c.xb.p) * test::uniform(rng, 0.0f, 2.0f) + test::random_point3(rng, 2.0f);
    const ShapeCastResult3 r = shape_cast(c.a, c.xa, c.va, c.b, c.xb, c.vb);
    double min_distance = 0.0;
    const double truth = c.first_touch(min_distance);
    const float tol = 1e-3f + 4e-6f * offset;  // distance at the reported time
    SCOPED_TRACE(testing::Message() << "case " << k << " " << type_name(c.a) << "-" << type_name(c.b)
                                    << " truth " << truth << " min d " << min_distance << " got "
                                    << r.fraction << " " << to_string(r.status));
    ASSERT_NE(r.status, QueryStatus::max_iterations);
    if (truth < 0.0) {
      if (min_distance > tol) {
        EXPECT_EQ(r.status, QueryStatus::separated);
        ++misses;
      }
      continue;
    }
    if (truth == 0.0) {
      EXPECT_EQ(r.status, QueryStatus::overlapped);
      continue;
    }
    ASSERT_TRUE(r.hit);
    // Never late; at the reported time the shapes are within the tolerance of touching.
    const double speed = length(c.vb - c.va);
    EXPECT_LE(r.fraction, truth + 1e-5 + tol / std::max(speed, 1e-3));
    EXPECT_LE(c.distance_at(r.fraction), tol);
    // The normal points from A to B: moving B along it by a little takes the shapes apart.
    EXPECT_NEAR(length(r.normal), 1.0f, 1e-4f) << "normal";
    ++hits;
  }
  EXPECT_GT(hits, 100) << misses;
  EXPECT_GT(misses, 100) << hits;
}

TEST(ShapeCast3, RandomCastsMatchBruteForce) { check_random_casts(0.0f, 21); }
TEST(ShapeCast3, RandomCastsFarFromTheOriginMatchBruteForce) { check_random_casts(1e4f, 22); }

}  // namespace
}  // namespace collide
