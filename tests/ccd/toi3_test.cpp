// 3D time_of_impact (conservative advancement with rotation, Sweep3) against an analytic case,
// dense sub-stepping with the double-precision brute-force distance (tests/support), the
// translation path (shape_cast), spinners that an end-of-step check misses, and far from the
// origin.

#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/time_of_impact.hpp>
#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "support/brute_convex3.hpp"
#include "support/test_util.hpp"

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace collide {
namespace {

using test::kPi;
using test::uniform;
using DQuat = glm::dquat;
using test::DVec3;

/// The shape at time t of its sweep, as a brute-force core in double precision: the pose is
/// evaluated in double (centre on its line, orientation exp(t w) q0), so the oracle does not
/// inherit the float rounding of Sweep3::at far from the origin.
test::BruteCore brute_at(const Shape3D& shape, const Sweep3& s, double t) {
  test::BruteCore core =
      std::visit([](const auto& v) { return test::brute_core(v, Transform3{}); }, shape);
  const DVec3 w(s.rotation);
  const double turn = glm::length(w);
  DQuat q(s.q0.w, s.q0.x, s.q0.y, s.q0.z);
  if (turn > 0.0) q = glm::angleAxis(t * turn, w / turn) * q;
  const DVec3 c = DVec3(s.c0) + t * (DVec3(s.c1) - DVec3(s.c0));
  for (DVec3& p : core.points) p = c + q * (p - DVec3(s.local_center));
  return core;
}

double distance_at(const Shape3D& a, const Sweep3& wa, const Shape3D& b, const Sweep3& wb,
                   double t) {
  return test::brute_distance(brute_at(a, wa, t), brute_at(b, wb, t));
}

Shape3D random_shape3(std::mt19937& rng, int kind, float size) {
  switch (kind) {
    case 0: return make_sphere(test::random_point3(rng, 0.2f * size), uniform(rng, 0.3f, 0.6f) * size);
    case 1:
      return make_capsule(test::random_point3(rng, 0.6f * size), test::random_point3(rng, 0.6f * size),
                          uniform(rng, 0.1f, 0.3f) * size);
    case 2: return make_segment(test::random_point3(rng, 0.7f * size), test::random_point3(rng, 0.7f * size));
    case 3:
      return make_box({uniform(rng, 0.1f, 0.6f) * size, uniform(rng, 0.1f, 0.6f) * size,
                       uniform(rng, 0.1f, 0.6f) * size});
    default:
      return make_box({uniform(rng, 0.1f, 0.5f) * size, uniform(rng, 0.1f, 0.5f) * size,
                       uniform(rng, 0.1f, 0.5f) * size},
                      uniform(rng, 0.02f, 0.15f) * size);
  }
}
constexpr int kKinds3 = 5;

Vec3 random_unit(std::mt19937& rng) {
  for (;;) {
    const Vec3 v = test::random_point3(rng, 1.0f);
    const float l = length(v);
    if (l > 0.1f && l <= 1.0f) return v / l;
  }
}

/// A random sweep near `at`: moving up to `reach`, turning by up to `max_turn` radians about a
/// random axis, centre of rotation up to 0.3 off the shape's origin.
Sweep3 random_sweep3(std::mt19937& rng, Vec3 at, float reach, float max_turn) {
  const Vec3 c0 = at + test::random_point3(rng, 1.0f);
  return {test::random_point3(rng, 0.3f), c0, c0 + test::random_point3(rng, reach),
          test::random_rotation(rng), uniform(rng, 0.0f, max_turn) * random_unit(rng)};
}

/// `s` moved rigidly by `m` (the whole motion seen from another frame).
Sweep3 moved(const Sweep3& s, const Transform3& m) {
  return {s.local_center, transform_point(m, s.c0), transform_point(m, s.c1), m.q * s.q0,
          rotate(m.q, s.rotation)};
}

// 1. A rod (segment from (-2, 0, 0) to (2, 0, 0)) turning a quarter turn about z towards a
// sphere of radius r at (1, 1, 0): the rod's line at angle th is |sin th - cos th| from the
// sphere's centre, so they are `target` apart at th = pi/4 - asin((r + target) / sqrt 2). Re-run
// under random rigid motions (the axis turns with them), including far from the origin.
TEST(TimeOfImpact3, TurningRodAnalytic) {
  const Segment3 rod = make_segment({-2.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f});
  const float r = 0.2f;
  const Sphere ball = make_sphere({0.0f, 0.0f, 0.0f}, r);
  const Sweep3 rod_sweep{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, Quat{1, 0, 0, 0}, {0, 0, 0.5f * kPi}};
  const Sweep3 ball_sweep{{0, 0, 0}, {1, 1, 0}, {1, 1, 0}, Quat{1, 0, 0, 0}, {0, 0, 0}};
  const float t_touch = (0.25f * kPi - std::asin(r / std::sqrt(2.0f))) / (0.5f * kPi);
  std::mt19937 rng(43);
  for (int k = 0; k < 60; ++k) {
    const bool far = k >= 30;
    const float target = far ? 0.1f : 0.01f;
    const float t_target = (0.25f * kPi - std::asin((r + target) / std::sqrt(2.0f))) / (0.5f * kPi);
    const float tol_t = 0.25f * target / 2.0f;  // separation changes at about 2.2 per unit t
    const Transform3 m = k == 0 ? Transform3{} : test::random_transform3(rng, far ? 1e4f : 10.0f);
    const ToiResult3 res =
        time_of_impact(rod, moved(rod_sweep, m), ball, moved(ball_sweep, m), target);
    ASSERT_EQ(res.status, QueryStatus::hit) << k;
    EXPECT_NEAR(res.fraction, t_target, tol_t) << k;
    EXPECT_LT(res.fraction, t_touch) << "never late";
    EXPECT_NEAR(res.separation, target, 0.25f * target + (far ? 5e-3f : 1e-5f));
    const float th = res.fraction * 0.5f * kPi;
    EXPECT_VEC3_NEAR(res.normal, rotate(m.q, Vec3(-std::sin(th), std::cos(th), 0.0f)), 2e-3f);
    // The point lies midway between the surfaces: on the rod's side of the ball, r + half the
    // separation from its centre.
    const Vec3 ball_centre = transform_point(m, Vec3(1.0f, 1.0f, 0.0f));
    EXPECT_NEAR(distance(res.point, ball_centre), r + 0.5f * res.separation, far ? 5e-3f : 1e-4f);
  }
}

// 2. Sweep3 and the rotation vector: a plank spinning one full turn per step about its centre
// ends where it started, apart from a ball within its reach. An end-of-step check, or the
// shorter-arc sweep between the end poses (no turn at all), sees nothing; the spin meets the
// ball an eighth of a turn in (+z) or three eighths (-z, the plank's other end gets there).
TEST(TimeOfImpact3, SpinnerThatEndOfStepChecksMiss) {
  const Box plank = make_box({2.0f, 0.1f, 0.1f});
  const Sphere ball = make_sphere({0.0f, 0.0f, 0.0f}, 0.3f);
  const float target = 0.01f;
  std::mt19937 rng(44);
  int hits = 0;
  for (int k = 0; k < 40; ++k) {
    const Transform3 m = k == 0 ? Transform3{} : test::random_transform3(rng, k % 2 ? 1e3f : 10.0f);
    const float sign = k % 4 < 2 ? 1.0f : -1.0f;
    const Sweep3 spin{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, Quat{1, 0, 0, 0}, {0, 0, sign * 2.0f * kPi}};
    // The ball at 45 degrees in the +x +y quadrant, 1.3 from the centre (the plank reaches 2).
    const Vec3 at = 1.3f * Vec3(std::sqrt(0.5f), std::sqrt(0.5f), 0.0f);
    const Sweep3 still{{0, 0, 0}, at, at, Quat{1, 0, 0, 0}, {0, 0, 0}};
    const Sweep3 ws = moved(spin, m);
    const Sweep3 wb = moved(still, m);
    ASSERT_GT(distance_at(plank, ws, ball, wb, 0.0), 0.3);
    ASSERT_GT(distance_at(plank, ws, ball, wb, 1.0), 0.3);
    const Sweep3 short_arc = Sweep3::from_transforms(ws.at(0.0f), ws.at(1.0f), Vec3(0.0f));
    EXPECT_LT(length(short_arc.rotation), 1e-3f);
    EXPECT_EQ(time_of_impact(plank, short_arc, ball, wb, target).status, QueryStatus::separated);

    const ToiResult3 res = time_of_impact(plank, ws, ball, wb, target);
    ASSERT_EQ(res.status, QueryStatus::hit) << k;
    ++hits;
    double first = 2.0;
    for (int i = 0; i <= 2000 && first > 1.0; ++i) {
      if (distance_at(plank, ws, ball, wb, i / 2000.0) <= 0.0) first = i / 2000.0;
    }
    EXPECT_LE(res.fraction, first) << k;
    // The plank's half-width and the ball's radius are 0.4 at 1.3 from the centre: contact
    // asin(0.4 / 1.3) = 0.31 radians before the plank points at the ball.
    const float lead = std::asin(0.4f / 1.3f) / (2.0f * kPi);
    EXPECT_NEAR(res.fraction, (sign > 0.0f ? 0.125f : 0.375f) - lead, 0.01f) << k;
    EXPECT_NEAR(distance_at(plank, ws, ball, wb, res.fraction), target, 0.25 * target + 2e-5);
  }
  EXPECT_EQ(hits, 40);
}

/// Dense samples of the brute-force distance over [0, until].
struct Sampled {
  double first_touch = 2.0;   ///< first sampled time with distance 0 (2: none)
  double min_distance = 1e9;  ///< smallest sampled distance
};

Sampled sample(const Shape3D& a, const Sweep3& wa, const Shape3D& b, const Sweep3& wb,
               int samples, double until = 1.0) {
  Sampled s;
  for (int i = 0; i <= samples; ++i) {
    const double t = until * i / samples;
    const double d = distance_at(a, wa, b, wb, t);
    s.min_distance = std::min(s.min_distance, d);
    if (d <= 0.0 && s.first_touch > 1.0) s.first_touch = t;
  }
  return s;
}

/// Random rotating pairs of every kind against dense sub-stepping: a hit is never after the
/// first sampled touch, no sample before it comes closer than the target band, and at the
/// reported time the brute-force separation is within the band; separated means no sample
/// comes within the band.
void check_random_rotating_pairs(float offset, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const Vec3 base(offset, -0.5f * offset, 0.25f * offset);
  const float target = offset > 0.0f ? 0.1f : 0.01f;
  const float band = 0.25f * target;
  const double slack = offset > 0.0f ? 2e-3 : 1e-5;  // float rounding of the query
  int hits = 0;
  int separated = 0;
  int overlapped = 0;
  int failed = 0;
  int total = 0;
  for (int ka = 0; ka < kKinds3; ++ka) {
    for (int kb = 0; kb < kKinds3; ++kb) {
      for (int k = 0; k < 10; ++k) {
        const Shape3D sa = random_shape3(rng, ka, uniform(rng, 0.5f, 1.5f));
        const Shape3D sb = random_shape3(rng, kb, uniform(rng, 0.5f, 1.5f));
        const float max_turn = k % 3 == 0 ? 10.0f : 3.0f;
        const Sweep3 wa = random_sweep3(rng, base, 6.0f, max_turn);
        Sweep3 wb = random_sweep3(rng, base + Vec3(uniform(rng, 2.0f, 5.0f), 0.0f, 0.0f), 6.0f, max_turn);
        if (k % 3 != 2) wb.c1 = wa.c1 + test::random_point3(rng, 1.0f);  // aim at each other
        const ToiResult3 res = time_of_impact(sa, wa, sb, wb, target);
        ++total;
        SCOPED_TRACE(testing::Message() << "kinds " << ka << "," << kb << " case " << k << " t "
                                        << res.fraction << " " << to_string(res.status)
                                        << " iterations " << res.iterations);
        if (res.status == QueryStatus::max_iterations) {
          ++failed;
          // Still safe: nothing touches before the reported fraction.
          EXPECT_GT(sample(sa, wa, sb, wb, 200, res.fraction).min_distance, 0.0);
          continue;
        }
        const int samples = 300;
        const Sampled truth = sample(sa, wa, sb, wb, samples);
        if (res.status == QueryStatus::overlapped) {
          ++overlapped;
          EXPECT_EQ(res.fraction, 0.0f);
          EXPECT_LE(distance_at(sa, wa, sb, wb, 0.0), target + band + slack);
          continue;
        }
        if (res.status == QueryStatus::separated) {
          ++separated;
          EXPECT_EQ(res.fraction, 1.0f);
          EXPECT_GT(truth.min_distance, target - band - slack) << "missed a collision";
          continue;
        }
        ASSERT_EQ(res.status, QueryStatus::hit);
        ++hits;
        EXPECT_LE(res.fraction, truth.first_touch) << "late";
        // No sample before the reported time is already inside the band.
        const Sampled before = sample(sa, wa, sb, wb, 100, res.fraction);
        EXPECT_GT(before.min_distance, target - band - slack) << "late for the target";
        const double sep = distance_at(sa, wa, sb, wb, res.fraction);
        EXPECT_NEAR(sep, target, band + slack);
        EXPECT_NEAR(res.separation, sep, offset > 0.0f ? 5e-3 : 1e-4);
        EXPECT_NEAR(length(res.normal), 1.0f, 1e-4f);
      }
    }
  }
  EXPECT_EQ(failed, 0);
  EXPECT_GT(hits, total * 3 / 10) << separated << " " << overlapped;
  EXPECT_GT(separated, total / 10) << hits;
}

TEST(TimeOfImpact3, RandomRotatingPairsAgainstSubStepping) { check_random_rotating_pairs(0.0f, 71); }
TEST(TimeOfImpact3, RandomRotatingPairsFarFromTheOrigin) { check_random_rotating_pairs(1e4f, 72); }

// 3. Without rotation the translation path (the GJK ray cast of shape_cast on shapes grown by
// half the target each) answers; a tiny turn sends the same motion through conservative
// advancement: both land in the target band, and never after shape_cast's first touch.
TEST(TimeOfImpact3, TranslationAgreesWithShapeCastAndAdvancement) {
  std::mt19937 rng(73);
  const float target = 0.01f;
  int hits = 0;
  int misses = 0;
  const int total = 300;
  for (int k = 0; k < total; ++k) {
    const Shape3D sa = random_shape3(rng, k % kKinds3, uniform(rng, 0.5f, 1.5f));
    const Shape3D sb = random_shape3(rng, (k / kKinds3) % kKinds3, uniform(rng, 0.5f, 1.5f));
    Sweep3 wa = random_sweep3(rng, Vec3(0.0f), 6.0f, 0.0f);
    Sweep3 wb = random_sweep3(rng, Vec3(uniform(rng, 3.0f, 6.0f), 0.0f, 0.0f), 6.0f, 0.0f);
    wa.rotation = Vec3(0.0f);
    wb.rotation = Vec3(0.0f);
    if (k % 3 != 2) wb.c1 = wa.c1 + test::random_point3(rng, 0.3f);
    const ToiResult3 plain = time_of_impact(sa, wa, sb, wb, target);
    const ShapeCastResult3 cast =
        shape_cast(sa, wa.at(0.0f), wa.c1 - wa.c0, sb, wb.at(0.0f), wb.c1 - wb.c0);
    Sweep3 turning = wb;
    turning.rotation = 1e-6f * random_unit(rng);
    const ToiResult3 advanced = time_of_impact(sa, wa, sb, turning, target);
    SCOPED_TRACE(testing::Message() << "case " << k << " plain " << plain.fraction << " "
                                    << to_string(plain.status) << " cast " << cast.fraction << " "
                                    << to_string(cast.status) << " advanced " << advanced.fraction
                                    << " " << to_string(advanced.status));
    ASSERT_NE(plain.status, QueryStatus::max_iterations);
    ASSERT_NE(advanced.status, QueryStatus::max_iterations);
    if (cast.status == QueryStatus::hit) {
      EXPECT_EQ(plain.status, QueryStatus::hit);
      EXPECT_EQ(advanced.status, QueryStatus::hit);
      EXPECT_LE(plain.fraction, cast.fraction);
      EXPECT_LE(advanced.fraction, cast.fraction);
      ++hits;
    }
    if (plain.status == QueryStatus::hit) {
      EXPECT_NEAR(distance_at(sa, wa, sb, wb, plain.fraction), target, 0.25 * target + 1e-5);
      EXPECT_NEAR(plain.separation, target, 0.25f * target + 1e-5f);
    }
    if (advanced.status == QueryStatus::hit) {
      EXPECT_NEAR(distance_at(sa, wa, sb, turning, advanced.fraction), target, 0.25 * target + 1e-5);
    }
    if (plain.status == QueryStatus::separated) {
      ++misses;
      EXPECT_EQ(cast.status, QueryStatus::separated);
      // A graze within the band may go either way; farther misses agree.
      if (advanced.status != QueryStatus::separated) {
        EXPECT_LE(sample(sa, wa, sb, wb, 400).min_distance, target + 0.5 * target);
      }
    }
  }
  EXPECT_GT(hits, total / 3) << misses;
  EXPECT_GT(misses, total / 5) << hits;
}

// 4. No tunnelling with spin: small bullets (a sphere off its centre of rotation, a capsule, a
// box; size 0.05) spinning up to two turns per step about random axes and flying at up to 1e4
// times their size per step through a thin wall (a box 0.01 thick and 100 wide), from many
// angles. The centre of rotation crosses the wall's mid-plane, so the
// shapes must meet before that moment.
TEST(TimeOfImpact3, NoTunnellingWithSpin) {
  std::mt19937 rng(74);
  const Box wall = make_box({0.005f, 50.0f, 50.0f});
  const float size = 0.05f;
  int shots = 0;
  for (int kind = 0; kind < 3; ++kind) {
    Shape3D bullet;
    if (kind == 0) bullet = make_sphere({0.5f * size, 0.0f, 0.0f}, 0.5f * size);
    if (kind == 1) bullet = make_capsule({-size, 0.0f, 0.0f}, {size, 0.0f, 0.0f}, 0.3f * size);
    if (kind == 2) bullet = make_box({size, 0.5f * size, 0.3f * size});
    const Sweep3 still{};
    for (int k = 0; k < 150; ++k) {
      const float speed = size * std::pow(10.0f, uniform(rng, 1.0f, 4.0f));
      Vec3 dir = random_unit(rng);
      dir.x = std::max(std::fabs(dir.x), 0.2f);
      dir = normalize(dir);
      const float before = uniform(rng, 0.05f, 0.95f) * speed;  // to the crossing
      if (before * dir.x < 0.15f) continue;  // would start touching (bullet reach <= 0.11)
      const Vec3 start = Vec3{0.0f, uniform(rng, -40.0f, 40.0f), uniform(rng, -40.0f, 40.0f)} - before * dir;
      const Sweep3 shot{{0, 0, 0}, start, start + speed * dir, test::random_rotation(rng),
                        uniform(rng, 0.0f, 4.0f * kPi) * random_unit(rng)};
      const float t_cross = before / speed;
      const ToiResult3 r = time_of_impact(bullet, shot, Shape3D(wall), still);
      ++shots;
      ASSERT_EQ(r.status, QueryStatus::hit) << "tunnelled: kind " << kind << " shot " << k;
      EXPECT_LE(r.fraction, t_cross) << "late";
      // The effective target: 1e-3 of the bullet's size, or the float floors at these
      // coordinates (the shot travels up to 500; the wall's size is 141).
      const float magnitude = std::max(length(shot.c0), length(shot.c1)) + 142.0f;
      const float target = std::max({1e-3f * 0.11f, kToiRoundingTarget * magnitude,
                                     2.0f * kRelativeTolerance * 142.0f});
      const double sep = distance_at(bullet, shot, Shape3D(wall), still, r.fraction);
      EXPECT_GT(sep, 0.0);
      EXPECT_LE(sep, 1.3 * target + 1e-4) << "early: kind " << kind << " shot " << k;
    }
  }
  EXPECT_GT(shots, 3 * 150 * 3 / 4);
}

// 5. Overlapping at the start, spinning in place without reaching, and bad input by name.
TEST(TimeOfImpact3, OverlappedSeparatedAndBadInput) {
  const Box box = make_box({1.0f, 0.2f, 0.2f});
  const Sphere ball = make_sphere({0.0f, 0.0f, 0.0f}, 0.3f);
  const Sweep3 spin{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, Quat{1, 0, 0, 0}, {0, 0, 6.0f * kPi}};
  // The box's corners reach sqrt(1.08) = 1.04 from its centre; the ball stays 1.5 + 0.3 away.
  const Sweep3 far_ball{{0, 0, 0}, {0, 1.8f, 0}, {0, 1.8f, 0}, Quat{1, 0, 0, 0}, {0, 0, 0}};
  const ToiResult3 apart = time_of_impact(box, spin, ball, far_ball);
  EXPECT_EQ(apart.status, QueryStatus::separated);
  EXPECT_EQ(apart.fraction, 1.0f);
  const Sweep3 inside{{0, 0, 0}, {0.5f, 0, 0}, {5, 0, 0}, Quat{1, 0, 0, 0}, {1, 0, 0}};
  const ToiResult3 over = time_of_impact(box, spin, ball, inside);
  EXPECT_EQ(over.status, QueryStatus::overlapped);
  EXPECT_EQ(over.fraction, 0.0f);

  Sweep3 bad = spin;
  bad.q0 = Quat{2, 0, 0, 0};
  try {
    (void)time_of_impact(box, spin, ball, bad);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "sweep_b q0: not finite or not unit length");
  }
  bad = spin;
  bad.rotation.y = std::numeric_limits<float>::infinity();
  try {
    (void)time_of_impact(Shape3D(box), bad, Shape3D(ball), spin);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "sweep_a rotation: not finite");
  }
  EXPECT_THROW((void)time_of_impact(box, spin, ball, far_ball, std::numeric_limits<float>::quiet_NaN()),
               InvalidInput);
}

}  // namespace
}  // namespace collide
