// time_of_impact for rotating motion against an analytic case, brute-force sub-stepping with
// Box2D distances, and Box2D 2.4's b2TimeOfImpact on the same inputs.

#include <collide/ccd/time_of_impact.hpp>
#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include "ccd/ccd_oracle.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

/// The sweep moved rigidly by `m`.
Sweep moved(const Sweep& s, const Transform& m) {
  const float turn = m.q.angle();
  return {s.local_center, transform_point(m, s.c0), transform_point(m, s.c1), s.a0 + turn,
          s.a1 + turn};
}

// 1. A rod (segment from (-2, 0) to (2, 0)) turning a quarter turn about its centre towards a
// circle of radius r at (1, 1). The rod's line at angle th is |sin th - cos th| from the
// centre, so the shapes are `target` apart when that equals r + target:
// th = pi/4 - asin((r + target) / sqrt 2), t = th / (pi/2). Re-run under rigid motions,
// including far from the origin.
TEST(TimeOfImpact, TurningRodAnalytic) {
  const Segment rod = make_segment({-2.0f, 0.0f}, {2.0f, 0.0f});
  const float r = 0.2f;
  const Circle ball = make_circle({0.0f, 0.0f}, r);
  const Sweep rod_sweep{{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.5f * kPi};
  const Sweep ball_sweep{{0.0f, 0.0f}, {1.0f, 1.0f}, {1.0f, 1.0f}, 0.0f, 0.0f};
  const float t_touch = (0.25f * kPi - std::asin(r / std::sqrt(2.0f))) / (0.5f * kPi);
  std::mt19937 rng(41);
  for (int k = 0; k < 60; ++k) {
    // Far from the origin the target must stay above float resolution (kToiRoundingTarget:
    // about 0.06 at 1.4e4), so those cases ask for 0.1.
    const bool far = k >= 30;
    const float target = far ? 0.1f : 0.01f;
    const float t_target =
        (0.25f * kPi - std::asin((r + target) / std::sqrt(2.0f))) / (0.5f * kPi);
    // d(separation)/dt is about |P| * pi/2 = 2.2 per unit t: the tolerance 0.25 target in time.
    const float tol_t = 0.25f * target / 2.0f;
    const Transform m = k == 0 ? Transform{} : test::random_transform(rng, far ? 1e4f : 10.0f);
    const ToiResult res =
        time_of_impact(rod, moved(rod_sweep, m), ball, moved(ball_sweep, m), target);
    ASSERT_EQ(res.status, QueryStatus::hit) << k;
    EXPECT_NEAR(res.fraction, t_target, tol_t) << k;
    EXPECT_LT(res.fraction, t_touch) << "never late";
    EXPECT_NEAR(res.separation, target, 0.25f * target + (far ? 5e-3f : 1e-5f));
    // Normal from the rod towards the ball: the rod's left normal at that angle.
    const float th = res.fraction * 0.5f * kPi;
    EXPECT_VEC2_NEAR(res.normal, rotate(m.q, {-std::sin(th), std::cos(th)}), 2e-3f);
  }
}

// 2. Without rotation the answer matches the shape cast, stopped at the target separation.
TEST(TimeOfImpact, TranslationMatchesShapeCast) {
  const Polygon box = make_box({0.5f, 0.5f});
  const Circle ball = make_circle({0.0f, 0.0f}, 0.5f);
  const Sweep sa = Sweep::from_motion(Transform{}, {0.0f, 0.0f}, {10.0f, 0.0f}, 0.0f);
  const Sweep sb = Sweep::from_motion(Transform{{6.0f, 0.0f}, {}}, {0.0f, 0.0f}, {}, 0.0f);
  const ToiResult res = time_of_impact(box, sa, ball, sb, 0.02f);
  ASSERT_EQ(res.status, QueryStatus::hit);
  // Faces meet at 10 t = 5; 0.02 apart at 10 t = 4.98.
  EXPECT_NEAR(res.fraction, 0.498f, 1e-4f);
  EXPECT_NEAR(res.separation, 0.02f, 1e-3f);
  EXPECT_VEC2_NEAR(res.normal, Vec2(1.0f, 0.0f), 1e-4f);
  EXPECT_VEC2_NEAR(res.point, Vec2(5.49f, 0.0f), 1e-3f);  // between x = 5.48 and 5.5
}

// 3. Overlapping at the start, moving apart, and spinning in place without reaching.
TEST(TimeOfImpact, OverlappedSeparatedAndSpinning) {
  const Polygon box = make_box({1.0f, 0.2f});
  const Circle ball = make_circle({0.0f, 0.0f}, 0.3f);
  const Sweep spin{{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 6.0f * kPi};
  // The box's far corner reaches sqrt(1.04) = 1.02 from its centre; the ball stays 1.5 + 0.3
  // away in one case (never touches) and 1.0 + 0.3 in the other (touches within the first
  // turn).
  const Sweep far_ball{{0.0f, 0.0f}, {0.0f, 1.5f + 0.3f}, {0.0f, 1.5f + 0.3f}, 0.0f, 0.0f};
  const ToiResult apart = time_of_impact(box, spin, ball, far_ball);
  EXPECT_EQ(apart.status, QueryStatus::separated);
  EXPECT_EQ(apart.fraction, 1.0f);
  const Sweep near_ball{{0.0f, 0.0f}, {0.0f, 1.0f + 0.3f}, {0.0f, 1.0f + 0.3f}, 0.0f, 0.0f};
  const ToiResult hit = time_of_impact(box, spin, ball, near_ball);
  EXPECT_EQ(hit.status, QueryStatus::hit);
  EXPECT_GT(hit.fraction, 0.0f);
  EXPECT_LT(hit.fraction, 1.0f / 6.0f);
  {
    // The reason time_of_impact does not use the separating-axis root finder: Box2D 2.4's
    // b2TimeOfImpact checks its axis only at the interval's ends and, with the box back at its
    // start angle after three turns, misses this contact.
    const test::B2Proxy bb(ConvexProxy{box});
    const test::B2Proxy bc(ConvexProxy{ball});
    const b2TOIOutput box2d = test::b2_time_of_impact(bb, spin, bc, near_ball);
    EXPECT_EQ(box2d.state, b2TOIOutput::e_separated);
  }
  const Sweep inside{{0.0f, 0.0f}, {0.5f, 0.0f}, {5.0f, 0.0f}, 0.0f, 1.0f};
  const ToiResult over = time_of_impact(box, spin, ball, inside);
  EXPECT_EQ(over.status, QueryStatus::overlapped);
  EXPECT_EQ(over.fraction, 0.0f);
}

// 3b. Regression: the step ends with the shapes inside the target band. A ball spinning about
// its own centre (the rotating path, same geometry) slides to `target` from a still box at
// t = 1 exactly: that is a hit at t = 1 (b2TimeOfImpact also reports it), not "separated"
// because the last safe step reached the end of the interval.
TEST(TimeOfImpact, EndsInsideTargetBandAtOne) {
  const Polygon box = make_box({0.5f, 0.5f});
  const Circle ball = make_circle({0.0f, 0.0f}, 0.5f);
  const float target = 0.01f;
  const Sweep still{{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.0f};
  for (const float end_gap : {0.0f, 0.2f, -0.2f}) {  // in units of the tolerance, 0.25 target
    const float x1 = 1.0f + target + end_gap * 0.25f * target;
    const Sweep ball_sweep{{0.0f, 0.0f}, {5.0f, 0.0f}, {x1, 0.0f}, 0.0f, 3.0f};
    const ToiResult res = time_of_impact(box, still, ball, ball_sweep, target);
    ASSERT_EQ(res.status, QueryStatus::hit) << end_gap;
    // Within the band [0.75, 1.25] target: at t = 1 (end_gap >= 0) or at the time the ball is
    // that far ((x - 1) = target (1 + 0.25 f) for some f in [-1, 1], x = 5 - (5 - x1) t).
    EXPECT_NEAR(res.separation, target, 0.25f * target) << end_gap;
    EXPECT_NEAR(res.fraction, 1.0f, 0.25f * target / (5.0f - x1) + 1e-6f) << end_gap;
  }
  // Ending farther than the band: separated.
  const Sweep short_of{{0.0f, 0.0f}, {5.0f, 0.0f}, {1.0f + 1.5f * target, 0.0f}, 0.0f, 3.0f};
  EXPECT_EQ(time_of_impact(box, still, ball, short_of, target).status, QueryStatus::separated);
}

/// A random sweep for a shape of about `size`: centre near `at`, moving up to `reach`, turning
/// up to `max_turn`.
Sweep random_sweep(std::mt19937& rng, Vec2 at, float reach, float max_turn) {
  const Vec2 c0 = at + test::random_point(rng, 1.0f);
  const float a0 = uniform(rng, -kPi, kPi);
  return {test::random_point(rng, 0.3f), c0, c0 + test::random_point(rng, reach), a0,
          a0 + uniform(rng, -max_turn, max_turn)};
}

// 4. Random pairs of every shape kind, rotating and translating, against brute-force
// sub-stepping: a hit is never after the first sampled touch and leaves the shapes at the
// target separation; a miss means no sample touches.
TEST(TimeOfImpact, RandomRotatingPairsAgainstSubStepping) {
  std::mt19937 rng(77);
  int hits = 0;
  int total = 0;
  int failed = 0;
  for (int ka = 0; ka < test::kShapeKinds; ++ka) {
    for (int kb = 0; kb < test::kShapeKinds; ++kb) {
      for (int k = 0; k < 16; ++k) {
        const Shape2D sa = test::random_shape(rng, ka, uniform(rng, 0.3f, 1.5f));
        const Shape2D sb = test::random_shape(rng, kb, uniform(rng, 0.3f, 1.5f));
        const Sweep wa = random_sweep(rng, {0.0f, 0.0f}, 6.0f, 3.0f);
        Sweep wb = random_sweep(rng, {uniform(rng, 2.0f, 5.0f), 0.0f}, 6.0f, 3.0f);
        if (k % 2 == 0) wb.c1 = wa.c1 + test::random_point(rng, 1.0f);  // aim at each other
        const ConvexProxy pa(sa);
        const ConvexProxy pb(sb);
        const ToiResult res = time_of_impact(sa, wa, sb, wb);
        const test::SweepTruth truth = test::sweep_truth(pa, wa, pb, wb);
        ++total;
        SCOPED_TRACE(testing::Message() << "kinds " << ka << "," << kb << " case " << k
                                        << " t " << res.fraction << " status " << int(res.status)
                                        << " truth " << truth.t_first << " touches "
                                        << truth.touches << " min " << truth.min_distance);
        if (res.status == QueryStatus::max_iterations) {
          ++failed;
          continue;
        }
        if (truth.touches) {
          ASSERT_NE(res.status, QueryStatus::separated) << "missed a collision";
          EXPECT_LE(res.fraction, truth.t_first + 1e-5f) << "late";
        }
        if (res.status == QueryStatus::separated) continue;
        ++hits;
        const test::B2Proxy ba(pa);
        const test::B2Proxy bb(pb);
        const float sep = test::b2_distance(ba, wa.at(res.fraction), bb, wb.at(res.fraction));
        if (res.status == QueryStatus::hit) {
          // The default target is 1e-3 of the smaller size (0.3 .. 1.5 here).
          EXPECT_GT(sep, 0.0f);
          EXPECT_LE(sep, 1.25e-3f * 1.5f * 2.0f + 1e-5f);
          EXPECT_NEAR(sep, res.separation, 1e-4f);
          EXPECT_NEAR(length(res.normal), 1.0f, 1e-3f);
        }
      }
    }
  }
  EXPECT_EQ(failed, 0);
  EXPECT_GT(hits, total * 3 / 10);
  EXPECT_LT(hits, total * 8 / 10);
}

// 5. Against Box2D 2.4's b2TimeOfImpact on the same polygons and segments (exact core points,
// radius 0) and sweeps, at Box2D's own target (b2_linearSlop core separation, tolerance a
// quarter of it): the same outcome, and both stop inside the target band. Box2D may miss
// some grazing collisions (its documentation says so); those are counted, not failed.
TEST(TimeOfImpact, AgreesWithBox2D) {
  std::mt19937 rng(88);
  const float target = b2_linearSlop;
  const float band = 0.25f * b2_linearSlop + 1e-4f;
  int both_hit = 0;
  int disagree = 0;
  const int total = 400;
  for (int k = 0; k < total; ++k) {
    const Shape2D sa = test::random_shape(rng, k % 2 == 0 ? 2 : 3, uniform(rng, 0.3f, 1.5f));
    const Shape2D sb = test::random_shape(rng, 2, uniform(rng, 0.3f, 1.5f));
    const Sweep wa = random_sweep(rng, {0.0f, 0.0f}, 6.0f, 2.0f);
    Sweep wb = random_sweep(rng, {uniform(rng, 2.0f, 5.0f), 0.0f}, 6.0f, 2.0f);
    if (k % 2 == 0) wb.c1 = wa.c1 + test::random_point(rng, 1.0f);
    const ConvexProxy pa(sa);
    const ConvexProxy pb(sb);
    const test::B2Proxy ba(pa);
    const test::B2Proxy bb(pb);
    const ToiResult ours = time_of_impact(sa, wa, sb, wb, target);
    const b2TOIOutput theirs = test::b2_time_of_impact(ba, wa, bb, wb);
    const bool our_hit = ours.status == QueryStatus::hit;
    const bool their_hit = theirs.state == b2TOIOutput::e_touching;
    SCOPED_TRACE(testing::Message() << "case " << k << " ours " << ours.fraction << " box2d "
                                    << theirs.t << " state " << int(theirs.state));
    ASSERT_NE(ours.status, QueryStatus::max_iterations);
    if (ours.status == QueryStatus::overlapped) {
      // Box2D: overlapped (cores overlap) or touching at t = 0.
      EXPECT_TRUE(theirs.state == b2TOIOutput::e_overlapped ||
                  (theirs.state == b2TOIOutput::e_touching && theirs.t == 0.0f));
      continue;
    }
    if (our_hit != their_hit) {
      ++disagree;
      // Only a graze near the target may split them: the closest approach is near the band.
      const test::SweepTruth truth = test::sweep_truth(pa, wa, pb, wb, 2000);
      EXPECT_LE(truth.min_distance, target + 4.0f * band);
      continue;
    }
    if (!our_hit) continue;
    ++both_hit;
    const float our_sep = test::b2_distance(ba, wa.at(ours.fraction), bb, wb.at(ours.fraction));
    const float their_sep = test::b2_distance(ba, wa.at(theirs.t), bb, wb.at(theirs.t));
    EXPECT_NEAR(our_sep, target, band);
    EXPECT_NEAR(their_sep, target, band);
  }
  EXPECT_GT(both_hit, total * 3 / 10);
  EXPECT_LE(disagree, total / 50);
}

// 5b. No tunnelling with spin: small bullets (circle off its centre of rotation, capsule, box;
// size 0.05) spinning up to two turns per step and flying at up to 1e4 times their size per
// step through thin walls (a segment, a 0.01-thick box), from many angles. Each shot's centre
// crosses the wall, so the shapes must meet before that moment: the hit comes no later than
// the crossing and leaves the bullet at the target separation from the wall.
TEST(TimeOfImpact, NoTunnellingWithSpin) {
  std::mt19937 rng(17);
  const Segment seg_wall = make_segment({0.0f, -50.0f}, {0.0f, 50.0f});
  const Polygon thin_wall = make_box({0.005f, 50.0f});
  const float size = 0.05f;
  int shots = 0;
  for (int kind = 0; kind < 3; ++kind) {
    Shape2D bullet;
    if (kind == 0) bullet = make_circle({0.5f * size, 0.0f}, 0.5f * size);
    if (kind == 1) bullet = make_capsule({-size, 0.0f}, {size, 0.0f}, 0.3f * size);
    if (kind == 2) bullet = make_box({size, 0.5f * size});
    for (int w = 0; w < 2; ++w) {
      const Shape2D wall = w == 0 ? Shape2D(seg_wall) : Shape2D(thin_wall);
      const Sweep still{{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}, 0.0f, 0.0f};
      for (int k = 0; k < 200; ++k) {
        const float speed = size * std::pow(10.0f, uniform(rng, 1.0f, 4.0f));
        const float angle = uniform(rng, -1.4f, 1.4f);
        const Vec2 dir{std::cos(angle), std::sin(angle)};
        const float before = uniform(rng, 0.05f, 0.95f) * speed;  // to the crossing
        if (before * dir.x < 0.15f) continue;  // would start touching (bullet reach <= 0.11)
        const Vec2 start = Vec2{0.0f, uniform(rng, -40.0f, 40.0f)} - before * dir;
        const float a0 = uniform(rng, -kPi, kPi);
        const Sweep shot{{0.0f, 0.0f}, start, start + speed * dir, a0,
                         a0 + uniform(rng, -4.0f * kPi, 4.0f * kPi)};
        const float t_cross = before / speed;  // the centre of rotation crosses x = 0
        const ToiResult r = time_of_impact(bullet, shot, wall, still);
        ++shots;
        ASSERT_EQ(r.status, QueryStatus::hit)
            << "tunnelled: kind " << kind << " wall " << w << " shot " << k;
        EXPECT_LE(r.fraction, t_cross) << "late";
        const test::B2Proxy bb(ConvexProxy{bullet});
        const test::B2Proxy bw(ConvexProxy{wall});
        const float sep = test::b2_distance(bb, shot.at(r.fraction), bw, still.at(r.fraction));
        // Target: 1e-3 of the smaller size (the bullet, at most 0.11), or the float floors at
        // these coordinates (the shot travels up to 500; the wall is 100 long).
        const float magnitude = std::max(length(shot.c0), length(shot.c1)) + 100.0f + 0.11f;
        const float target = std::max({1e-3f * 0.11f, kToiRoundingTarget * magnitude,
                                       2.0f * kRelativeTolerance * 100.11f});
        EXPECT_GT(sep, 0.0f);
        EXPECT_LE(sep, 1.25f * target + 1e-5f) << "early: kind " << kind << " shot " << k;
      }
    }
  }
  EXPECT_GT(shots, 3 * 2 * 200 * 3 / 4);
}

// 6. Non-finite sweeps and targets are rejected by name.
TEST(TimeOfImpact, RejectsBadInput) {
  const Circle c = make_circle({0.0f, 0.0f}, 1.0f);
  Sweep s;
  Sweep bad;
  bad.c1.x = std::numeric_limits<float>::infinity();
  try {
    (void)time_of_impact(c, s, c, bad);
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "sweep_b c1: not finite");
  }
  EXPECT_THROW((void)time_of_impact(Shape2D(c), bad, Shape2D(c), s), InvalidInput);
  EXPECT_THROW((void)time_of_impact(c, s, c, s, std::numeric_limits<float>::quiet_NaN()),
               InvalidInput);
}

}  // namespace
}  // namespace collide
