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

// 5c. Translating sharp polygons take the separating-axis cast into A - B (no iterations):
// against the GJK ray cast on the same shapes (the proxies' path) and dense sampling with Box2D
// distances. Both stop inside the target band; the axis cast is never late (no sample before
// its time is closer than the band's low end); their outcomes differ only for grazes.
TEST(TimeOfImpact, TranslatingPolygonsTakeTheAxisCast) {
  std::mt19937 rng(2026);
  const float target = 0.01f;
  const float band = 0.25f * target;
  int hits = 0;
  int axis_hits = 0;
  int disagree = 0;
  const int total = 600;
  for (int k = 0; k < total; ++k) {
    const Polygon a = std::get<Polygon>(test::random_shape(rng, 2, uniform(rng, 0.3f, 1.5f)));
    const Polygon b = std::get<Polygon>(test::random_shape(rng, 2, uniform(rng, 0.3f, 1.5f)));
    const bool far = k % 5 == 4;  // some far from the origin (target raised to the float floor)
    const Vec2 at = far ? test::random_point(rng, 2e3f) : Vec2{0.0f, 0.0f};
    const Sweep wa = random_sweep(rng, at, 6.0f, 0.0f);
    Sweep wb = random_sweep(rng, at + Vec2{uniform(rng, 2.0f, 5.0f), 0.0f}, 6.0f, 0.0f);
    if (k % 2 == 0) wb.c1 = wa.c1 + test::random_point(rng, 1.0f);  // aim at each other
    const ToiResult ours = time_of_impact(a, wa, b, wb, target);
    const ToiResult gjk = time_of_impact(ConvexProxy(a), wa, ConvexProxy(b), wb, target);
    SCOPED_TRACE(testing::Message() << "case " << k << " ours " << ours.fraction << " status "
                                    << int(ours.status) << " gjk " << gjk.fraction << " status "
                                    << int(gjk.status));
    ASSERT_NE(ours.status, QueryStatus::max_iterations);
    const test::B2Proxy ba{ConvexProxy(a)};
    const test::B2Proxy bb{ConvexProxy(b)};
    // The target actually used: raised to the float floor far from the origin.
    const float magnitude = std::max({length(wa.c0), length(wa.c1), length(wb.c0), length(wb.c1)});
    const float used = std::max(target, kToiRoundingTarget * (magnitude + 6.0f));
    if (ours.status != gjk.status) {
      ++disagree;
      // Only a graze may split them: the closest approach is near the band.
      const test::SweepTruth truth = test::sweep_truth(ConvexProxy(a), wa, ConvexProxy(b), wb, 2000);
      EXPECT_LE(truth.min_distance, 2.0f * used);
      continue;
    }
    if (ours.status != QueryStatus::hit) continue;
    ++hits;
    if (ours.iterations == 0) ++axis_hits;
    const float sep = test::b2_distance(ba, wa.at(ours.fraction), bb, wb.at(ours.fraction));
    EXPECT_NEAR(sep, used, 0.25f * used + (far ? 2e-3f : 1e-5f));
    EXPECT_NEAR(sep, ours.separation, far ? 2e-3f : 1e-4f);
    EXPECT_NEAR(length(ours.normal), 1.0f, 1e-3f);
    // Never late: no earlier sample is closer than the band's low end.
    for (int i = 0; i < 64; ++i) {
      const float t = ours.fraction * float(i) / 64.0f;
      ASSERT_GT(test::b2_distance(ba, wa.at(t), bb, wb.at(t)), 0.75f * used - (far ? 2e-3f : 1e-5f))
          << "late, t " << t;
    }
    if (!far) EXPECT_NEAR(sep, test::b2_distance(ba, wa.at(gjk.fraction), bb, wb.at(gjk.fraction)),
                          2.0f * band);
  }
  EXPECT_GT(hits, total / 5);
  EXPECT_GT(axis_hits, hits * 3 / 4) << "the axis cast answers most translating hits";
  EXPECT_LE(disagree, total / 50);
}

// 5d. Face to face the axis cast's time is exact; corners meeting first are farther apart at
// that time than the target (the polygons grown by the target with sharp corners touch there),
// so those go to the GJK ray cast: two diamonds (boxes turned 45 degrees) meet corner to corner
// at the analytic time.
TEST(TimeOfImpact, CornersMeetingTakeTheGjkPath) {
  const Polygon box = make_box({0.5f, 0.5f});
  const float target = 0.02f;
  const Sweep still = Sweep::from_motion(Transform{}, {0.0f, 0.0f}, {}, 0.0f);
  {
    // Faces 4 apart, closing at 10 per step: target apart at t = (4 - target) / 10.
    const Sweep in = Sweep::from_motion(Transform{{5.0f, 0.0f}, {}}, {0.0f, 0.0f},
                                        {-10.0f, 0.0f}, 0.0f);
    const ToiResult r = time_of_impact(box, still, box, in, target);
    ASSERT_EQ(r.status, QueryStatus::hit);
    EXPECT_EQ(r.iterations, 0) << "the separating-axis cast";
    EXPECT_NEAR(r.fraction, (4.0f - target) / 10.0f, 1e-6f);
    EXPECT_NEAR(r.separation, target, 1e-5f);
    EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-5f);
  }
  {
    // Diamonds: corners at x = +-sqrt(1/2) from each centre, 5 - sqrt 2 apart.
    const Rot2 q = Rot2::from_angle(0.25f * kPi);
    const Sweep a = Sweep::from_motion(Transform{{0.0f, 0.0f}, q}, {0.0f, 0.0f}, {}, 0.0f);
    const Sweep b = Sweep::from_motion(Transform{{5.0f, 0.0f}, q}, {0.0f, 0.0f},
                                       {-10.0f, 0.0f}, 0.0f);
    const ToiResult r = time_of_impact(box, a, box, b, target);
    ASSERT_EQ(r.status, QueryStatus::hit);
    EXPECT_GT(r.iterations, 0) << "the GJK ray cast";
    const float t = (5.0f - std::sqrt(2.0f) - target) / 10.0f;
    EXPECT_NEAR(r.fraction, t, 0.25f * target / 10.0f);
    EXPECT_LE(r.fraction, t + 1e-6f) << "never late";
    EXPECT_NEAR(r.separation, target, 0.25f * target);
    EXPECT_VEC2_NEAR(r.normal, Vec2(1.0f, 0.0f), 1e-3f);
  }
}

// 5e. A translating circle or capsule against a polygon (either order) takes the shape cast of
// the rounded shape grown by the target: against the GJK path on proxies and Box2D distances.
// Both stop inside the target band at the same outcome (but for grazes), never late; the
// point lies midway (half the target from each shape), the normal is the GJK path's.
TEST(TimeOfImpact, TranslatingRoundShapesCastGrownByTheTarget) {
  std::mt19937 rng(4242);
  const float target = 0.01f;
  int hits = 0;
  int disagree = 0;
  const int total = 800;
  for (int k = 0; k < total; ++k) {
    const Shape2D round = test::random_shape(rng, k % 4 < 2 ? 0 : 1, uniform(rng, 0.3f, 1.5f));
    const Shape2D poly = test::random_shape(rng, 2, uniform(rng, 0.3f, 1.5f));
    const bool round_first = k % 2 == 0;
    const Shape2D& sa = round_first ? round : poly;
    const Shape2D& sb = round_first ? poly : round;
    const Sweep wa = random_sweep(rng, {0.0f, 0.0f}, 6.0f, 0.0f);
    Sweep wb = random_sweep(rng, {uniform(rng, 2.0f, 5.0f), 0.0f}, 6.0f, 0.0f);
    if (k % 3 != 2) wb.c1 = wa.c1 + test::random_point(rng, 1.0f);  // aim at each other
    const ToiResult ours = time_of_impact(sa, wa, sb, wb, target);
    const ToiResult gjk = time_of_impact(ConvexProxy(sa), wa, ConvexProxy(sb), wb, target);
    SCOPED_TRACE(testing::Message() << "case " << k << " ours " << ours.fraction << " status "
                                    << int(ours.status) << " gjk " << gjk.fraction << " status "
                                    << int(gjk.status));
    const test::B2Proxy ba{ConvexProxy(sa)};
    const test::B2Proxy bb{ConvexProxy(sb)};
    if (ours.status != gjk.status) {
      ++disagree;
      const test::SweepTruth truth = test::sweep_truth(ConvexProxy(sa), wa, ConvexProxy(sb), wb,
                                                       2000);
      EXPECT_LE(truth.min_distance, 2.0f * target);
      continue;
    }
    if (ours.status != QueryStatus::hit) continue;
    ++hits;
    const Transform xa = wa.at(ours.fraction);
    const Transform xb = wb.at(ours.fraction);
    const float sep = test::b2_distance(ba, xa, bb, xb);
    EXPECT_NEAR(sep, target, 0.25f * target);
    EXPECT_NEAR(ours.separation, target, 0.25f * target);
    for (int i = 0; i < 64; ++i) {
      const float t = ours.fraction * float(i) / 64.0f;
      ASSERT_GT(test::b2_distance(ba, wa.at(t), bb, wb.at(t)), 0.75f * target) << "late " << t;
    }
    // The point: half the separation from each shape.
    const Vec2 point = ours.point;
    const test::B2Proxy bp{ConvexProxy(&point, 1, 0.0f)};
    EXPECT_NEAR(test::b2_distance(ba, xa, bp, Transform{}), 0.5f * sep, 1e-3f);
    EXPECT_NEAR(test::b2_distance(bb, xb, bp, Transform{}), 0.5f * sep, 1e-3f);
    EXPECT_NEAR(dot(ours.normal, gjk.normal), 1.0f, 2e-3f);
  }
  EXPECT_GT(hits, total / 4);
  EXPECT_LE(disagree, total / 50);
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
  // The typed overloads that answer from the other shape's side still name the caller's sweep.
  const Polygon box = make_box({0.5f, 0.5f});
  const Capsule cap = make_capsule({-1.0f, 0.0f}, {1.0f, 0.0f}, 0.2f);
  for (int k = 0; k < 3; ++k) {
    try {
      if (k == 0) (void)time_of_impact(box, bad, c, s);
      if (k == 1) (void)time_of_impact(box, bad, cap, s);
      if (k == 2) (void)time_of_impact(box, bad, box, s);
      FAIL() << "expected InvalidInput " << k;
    } catch (const InvalidInput& e) {
      EXPECT_STREQ(e.what(), "sweep_a c1: not finite") << k;
    }
  }
  EXPECT_THROW((void)time_of_impact(c, s, c, s, std::numeric_limits<float>::quiet_NaN()),
               InvalidInput);
}

}  // namespace
}  // namespace collide
