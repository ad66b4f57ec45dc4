// Sweeps and swept AABBs against brute force: the boxes of the shape at densely sampled times.

#include <collide/ccd/sweep.hpp>
#include <collide/core/error.hpp>

#include "ccd/ccd_oracle.hpp"
#include "support/test_util.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <string>

namespace collide {
namespace {

using test::kPi;
using test::uniform;

/// check_sweep's message for `sweep` (2D or 3D) named "sweep_a", or "no throw".
template <class SweepT>
std::string check_message(const SweepT& sweep) {
  try {
    check_sweep(sweep, "sweep_a");
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no throw";
}

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

// 4. Non-finite sweeps are rejected naming the field, each field alone (the check's fast test
// and its message are separate code).
TEST(Sweep, CheckRejectsNonFinite) {
  Sweep s;
  s.local_center = {0.25f, -0.5f};
  s.c0 = {1.0f, 2.0f};
  s.c1 = {3.0f, -4.0f};
  s.a0 = 0.5f;
  s.a1 = -2.0f;
  EXPECT_NO_THROW(check_sweep(s, "sweep_a"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  Sweep bad = s;
  bad.a1 = nan;
  EXPECT_EQ(check_message(bad), "sweep_a a1: not finite");
  bad = s;
  bad.a0 = -inf;
  EXPECT_EQ(check_message(bad), "sweep_a a0: not finite");
  bad = s;
  bad.c0.y = nan;
  EXPECT_EQ(check_message(bad), "sweep_a c0: not finite");
  bad = s;
  bad.c1.x = inf;
  EXPECT_EQ(check_message(bad), "sweep_a c1: not finite");
  bad = s;
  bad.local_center.x = nan;
  EXPECT_EQ(check_message(bad), "sweep_a local_center: not finite");
  bad.a1 = nan;  // two bad fields: the first in the order above is named
  EXPECT_EQ(check_message(bad), "sweep_a local_center: not finite");
}


// ---- 3D ---------------------------------------------------------------------------------------

/// Union of the 3D shape's boxes at `samples` + 1 evenly spaced times of the sweep.
Aabb3 sampled_union3(const Shape3D& shape, const Sweep3& sweep, int samples) {
  Aabb3 box = compute_aabb(shape, sweep.at(0.0f));
  for (int k = 1; k <= samples; ++k) {
    box = merge(box, compute_aabb(shape, sweep.at(float(k) / float(samples))));
  }
  return box;
}

Shape3D random_shape3(std::mt19937& rng, int kind) {
  switch (kind) {
    case 0: return make_sphere(test::random_point3(rng, 0.3f), uniform(rng, 0.1f, 0.8f));
    case 1: return make_capsule(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f), uniform(rng, 0.05f, 0.4f));
    case 2: return make_segment(test::random_point3(rng, 1.0f), test::random_point3(rng, 1.0f));
    default:
      return make_box({uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f), uniform(rng, 0.1f, 1.0f)},
                      uniform(rng, 0.0f, 0.2f));
  }
}

/// The rotation of `v` by `angle` about the unit `axis` (Rodrigues), in double.
Vec3 rodrigues(Vec3 v, Vec3 axis, double angle) {
  const glm::dvec3 k(axis);
  const glm::dvec3 x(v);
  const glm::dvec3 r = x * std::cos(angle) + glm::cross(k, x) * std::sin(angle) +
                       k * glm::dot(k, x) * (1.0 - std::cos(angle));
  return Vec3(r);
}

// 5. A 3D sweep moves its centre on a line and turns at a constant rate about a fixed world
// axis, any number of turns: a point of the body at time t is the centre plus the start
// offset turned by t times the rotation vector (Rodrigues), in double as the reference.
TEST(Sweep3, InterpolatesCentreAndTurnsAboutAFixedAxis) {
  std::mt19937 rng(7);
  for (int k = 0; k < 200; ++k) {
    const Transform3 start = test::random_transform3(rng, 10.0f);
    const Vec3 centre = test::random_point3(rng, 1.0f);
    const Vec3 axis = normalize(test::random_point3(rng, 1.0f) + Vec3(0.0f, 0.0f, 0.01f));
    const float turn = uniform(rng, -4.0f * kPi, 4.0f * kPi);  // beyond pi: several turns
    const Vec3 move = test::random_point3(rng, 5.0f);
    const Sweep3 s = Sweep3::from_motion(start, centre, move, turn * axis);
    const Vec3 body_point = test::random_point3(rng, 2.0f);
    const Vec3 offset0 = rotate(start.q, body_point - centre);  // from the centre, world
    for (float t : {0.0f, 0.3f, 0.5f, 1.0f}) {
      const Transform3 x = s.at(t);
      EXPECT_NEAR(length(x.q), 1.0f, 1e-5f);
      EXPECT_VEC3_NEAR(transform_point(x, centre), s.c0 + t * move, 2e-5f);
      const Vec3 expected = s.c0 + t * move + rodrigues(offset0, axis, double(t) * turn);
      EXPECT_VEC3_NEAR(transform_point(x, body_point), expected, 1e-4f);
    }
    EXPECT_VEC3_NEAR(s.at(0.0f).p, start.p, 2e-5f);
  }
}

// 6. from_transforms: the shorter arc between two poses (at most a half turn), ending at the
// second pose.
TEST(Sweep3, FromTransformsTakesTheShorterArc) {
  std::mt19937 rng(8);
  for (int k = 0; k < 200; ++k) {
    const Transform3 a = test::random_transform3(rng, 10.0f);
    const Transform3 b = test::random_transform3(rng, 10.0f);
    const Vec3 centre = test::random_point3(rng, 1.0f);
    const Sweep3 s = Sweep3::from_transforms(a, b, centre);
    EXPECT_LE(length(s.rotation), kPi + 1e-5f);
    const Transform3 end = s.at(1.0f);
    const Vec3 p = test::random_point3(rng, 2.0f);
    EXPECT_VEC3_NEAR(transform_point(end, p), transform_point(b, p), 1e-4f);
    EXPECT_VEC3_NEAR(transform_point(s.at(0.0f), p), transform_point(a, p), 1e-4f);
  }
}

// 7. Swept boxes in 3D: exact under translation; conservative with rotation (turns from tiny to
// two full spins about random axes, centres off the shape) and close for small turns.
TEST(Sweep3, SweptBoxesAreExactOrConservative) {
  std::mt19937 rng(9);
  int small_turns = 0;
  for (int k = 0; k < 300; ++k) {
    const Shape3D shape = random_shape3(rng, k % 4);
    const Transform3 xf = test::random_transform3(rng, k % 2 ? 1e3f : 10.0f);
    const Vec3 move = test::random_point3(rng, 20.0f);
    const Aabb3 moved_box = swept_aabb(shape, xf, move);
    const Sweep3 straight = Sweep3::from_motion(xf, Vec3(0.0f), move, Vec3(0.0f));
    const Aabb3 straight_truth = sampled_union3(shape, straight, 64);
    const float tol = 4e-6f * (1.0f + length(xf.p) + length(move));
    EXPECT_VEC3_NEAR(moved_box.min, straight_truth.min, tol);
    EXPECT_VEC3_NEAR(moved_box.max, straight_truth.max, tol);
    EXPECT_VEC3_NEAR(swept_aabb(shape, straight).min, straight_truth.min, tol);
    EXPECT_VEC3_NEAR(swept_aabb(shape, straight).max, straight_truth.max, tol);

    const float turn = k % 3 == 0 ? uniform(rng, 0.0f, 0.2f) : uniform(rng, 0.0f, 4.0f * kPi);
    const Vec3 axis = normalize(test::random_point3(rng, 1.0f) + Vec3(0.0f, 0.01f, 0.0f));
    const Sweep3 s = Sweep3::from_motion(xf, test::random_point3(rng, 1.5f), move, turn * axis);
    const Aabb3 swept = swept_aabb(shape, s);
    const Aabb3 truth = sampled_union3(shape, s, 4000);
    const float rtol = 3e-4f + 4e-6f * length(xf.p);
    for (int i = 0; i < 3; ++i) {
      EXPECT_LE(swept.min[i], truth.min[i] + rtol) << k;
      EXPECT_GE(swept.max[i], truth.max[i] - rtol) << k;
    }
    if (turn < 0.2f) {
      ++small_turns;
      // Looser than the truth by at most reach * turn^2 / 8 per side (reach < 4.5 here).
      const float slack = 4.5f * turn * turn * 0.125f + rtol;
      for (int i = 0; i < 3; ++i) {
        EXPECT_GE(swept.min[i], truth.min[i] - slack) << k;
        EXPECT_LE(swept.max[i], truth.max[i] + slack) << k;
      }
    }
  }
  EXPECT_GT(small_turns, 50);
}

// 8. Non-finite or non-unit 3D sweeps are rejected naming the field.
TEST(Sweep3, CheckRejectsBadNumbers) {
  Sweep3 s;
  EXPECT_NO_THROW(check_sweep(s, "sweep_a"));
  Sweep3 bad = s;
  bad.c1.z = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(check_message(bad), "sweep_a c1: not finite");
  bad = s;
  bad.q0 = Quat{0.5f, 0.0f, 0.0f, 0.0f};
  EXPECT_EQ(check_message(bad), "sweep_a q0: not finite or not unit length");
  bad = s;
  bad.rotation.x = std::numeric_limits<float>::infinity();
  EXPECT_EQ(check_message(bad), "sweep_a rotation: not finite");
  bad = s;
  bad.local_center.y = std::numeric_limits<float>::infinity();
  EXPECT_EQ(check_message(bad), "sweep_a local_center: not finite");
  bad = s;
  bad.c0.x = -std::numeric_limits<float>::infinity();
  EXPECT_EQ(check_message(bad), "sweep_a c0: not finite");
}

}  // namespace
}  // namespace collide
