// Sweeps and swept AABBs against brute force: the boxes of the shape at densely sampled times.

#include <collide/ccd/sweep.hpp>
#include <collide/core/error.hpp>

#include "ccd/ccd_oracle.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

/// Union of the shape's boxes at `samples` + 1 evenly spaced times of the sweep.
Aabb sampled_union(const Shape2D& shape, const Sweep& sweep, int samples) {
  Aabb box = compute_aabb(shape, sweep.at(0.0f));
  for (int k = 1; k <= samples; ++k) {
    box = merge(box, compute_aabb(shape, sweep.at(float(k) / float(samples))));
  }
  return box;
}

// 1. The centre of rotation moves on the straight line c0 -> c1 and the angle interpolates.
TEST(Sweep, InterpolatesCentreAndAngle) {
  const Transform start = Transform::from({1.0f, 2.0f}, 0.3f);
  const Vec2 centre{0.5f, -0.25f};
  const Sweep s = Sweep::from_motion(start, centre, {4.0f, -2.0f}, 1.5f);
  EXPECT_VEC2_NEAR(s.at(0.0f).p, start.p, 1e-6f);
  EXPECT_NEAR(s.at(0.0f).q.angle(), 0.3f, 1e-6f);
  EXPECT_NEAR(s.at(1.0f).q.angle(), 1.8f, 1e-6f);
  for (float t : {0.0f, 0.25f, 0.5f, 1.0f}) {
    EXPECT_VEC2_NEAR(transform_point(s.at(t), centre),
                     (s.c0 + t * Vec2(4.0f, -2.0f)), 1e-5f);
  }
}

// 1b. Same motion as Box2D's b2Sweep (the oracle of the time of impact tests relies on it).
TEST(Sweep, MatchesBox2DSweep) {
  std::mt19937 rng(4);
  for (int k = 0; k < 100; ++k) {
    const Sweep s{test::random_point(rng, 1.0f), test::random_point(rng, 10.0f),
                  test::random_point(rng, 10.0f), uniform(rng, -kPi, kPi),
                  uniform(rng, -3.0f * kPi, 3.0f * kPi)};
    b2Sweep w;
    w.localCenter.Set(s.local_center.x, s.local_center.y);
    w.c0.Set(s.c0.x, s.c0.y);
    w.c.Set(s.c1.x, s.c1.y);
    w.a0 = s.a0;
    w.a = s.a1;
    w.alpha0 = 0.0f;
    const float t = uniform(rng, 0.0f, 1.0f);
    b2Transform x;
    w.GetTransform(&x, t);
    const Transform ours = s.at(t);
    EXPECT_VEC2_NEAR(ours.p, Vec2(x.p.x, x.p.y), 2e-5f);
    EXPECT_NEAR(ours.q.c, x.q.c, 1e-5f);
    EXPECT_NEAR(ours.q.s, x.q.s, 1e-5f);
  }
}

// 2. Pure translation: the swept box is exactly the union of the boxes along the way.
TEST(Sweep, TranslationBoxIsExact) {
  std::mt19937 rng(5);
  for (int k = 0; k < 200; ++k) {
    const Shape2D shape = test::random_shape(rng, k % test::kShapeKinds, 1.0f);
    const Transform xf = test::random_transform(rng, k % 2 ? 1e3f : 10.0f);
    const Vec2 move = test::random_point(rng, 20.0f);
    const Aabb swept = swept_aabb(shape, xf, move);
    const Sweep s = Sweep::from_motion(xf, {0.0f, 0.0f}, move, 0.0f);
    const Aabb truth = sampled_union(shape, s, 64);
    const float tol = 1e-6f * (1.0f + length(xf.p) + length(move)) * 4.0f;
    EXPECT_VEC2_NEAR(swept.min, truth.min, tol);
    EXPECT_VEC2_NEAR(swept.max, truth.max, tol);
    // The rotating overload agrees when nothing turns.
    const Aabb rot = swept_aabb(shape, s);
    EXPECT_VEC2_NEAR(rot.min, truth.min, tol);
    EXPECT_VEC2_NEAR(rot.max, truth.max, tol);
  }
}

// 3. Rotating sweeps (turns from tiny to two full spins, centres off the shape): the box holds
// the shape at every sampled time, and for small turns it is close to the sampled union.
TEST(Sweep, RotatingBoxIsConservativeAndTight) {
  std::mt19937 rng(6);
  int small_turns = 0;
  for (int k = 0; k < 300; ++k) {
    const Shape2D shape = test::random_shape(rng, k % test::kShapeKinds, 1.0f);
    const Transform xf = test::random_transform(rng, 10.0f);
    const float turn = k % 3 == 0 ? uniform(rng, -0.2f, 0.2f) : uniform(rng, -4.0f * kPi, 4.0f * kPi);
    const Vec2 centre = test::random_point(rng, 1.5f);
    const Sweep s = Sweep::from_motion(xf, centre, test::random_point(rng, 10.0f), turn);
    const Aabb swept = swept_aabb(shape, s);
    const Aabb truth = sampled_union(shape, s, 4000);
    const float tol = 1e-5f * 30.0f;
    EXPECT_LE(swept.min.x, truth.min.x + tol);
    EXPECT_LE(swept.min.y, truth.min.y + tol);
    EXPECT_GE(swept.max.x, truth.max.x - tol);
    EXPECT_GE(swept.max.y, truth.max.y - tol);
    if (std::fabs(turn) < 0.2f) {
      ++small_turns;
      // Looser than the truth by at most reach * turn^2 / 8 per side (reach < 3.5 here).
      const float slack = 3.5f * turn * turn * 0.125f + tol;
      EXPECT_GE(swept.min.x, truth.min.x - slack);
      EXPECT_LE(swept.max.y, truth.max.y + slack);
    }
  }
  EXPECT_GT(small_turns, 50);
}

// 4. Non-finite sweeps are rejected naming the field.
TEST(Sweep, CheckRejectsNonFinite) {
  Sweep s;
  EXPECT_NO_THROW(check_sweep(s, "sweep_a"));
  s.a1 = std::numeric_limits<float>::quiet_NaN();
  try {
    check_sweep(s, "sweep_a");
    FAIL() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_STREQ(e.what(), "sweep_a a1: not finite");
  }
}

}  // namespace
}  // namespace collide
