// A fast body in free space skips its continuous collision query while its whole motion stays
// within its static clearance (StepStats::ccd_clear_skips). The skip must never let it through
// a static: bodies racing at walls, spinning compounds whose outer piece sweeps an arc, in 2D
// and 3D, query again near the wall, never pass its face and bounce back.

#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include <numbers>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr int kFrames = 240;
/// The wall's face towards the bodies, and how far past it a body's surface may end (rounding
/// and the contacts' allowance; a tunnelling body ends a whole frame's motion past it).
constexpr float kWallFace = 29.95f;
constexpr float kSlop = 0.01f;

TEST(CcdClearance, FastBodiesSkipQueriesInFreeSpaceAndStillStopAtTheWall2D) {
  // A thin wall at x = 30; from x = 10, a small box at 9 per second (0.15 a frame, half its
  // size: continuous collision, but less than its clearance's reach), and a compound of two
  // circles of radius 0.5 2 apart spinning at 6 radians per second (each circle's centre
  // sweeps an arc of 0.1 a frame besides the motion: within the reach, so the arc term counts).
  for (const bool compound : {false, true}) {
    World2D world;
    world.add_static({.shapes = {make_box({0.05f, 20.0f})}, .transform = Transform::from({30.0f, 0.0f}, 0.0f)});
    BodyDef body;
    if (compound) {
      body.shapes = {make_circle({-1.0f, 0.0f}, 0.5f), make_circle({1.0f, 0.0f}, 0.5f)};
      body.velocity = {9.0f, 0.0f};
      body.angular_velocity = 6.0f;
    } else {
      body.shapes = {make_box({0.15f, 0.15f})};
      body.velocity = {9.0f, 0.0f};
    }
    body.transform = Transform::from({10.0f, 0.0f}, 0.0f);
    const BodyId id = world.add_body(body);
    for (int f = 0; f < kFrames; ++f) {
      world.step(kDt);
      // The body's farthest points along its own x axis (the box does not turn) stay before
      // the wall's face at 29.95, within the contacts' slop.
      const float reach = compound ? 1.5f : 0.15f;
      for (const Vec2& v : {Vec2{-reach, 0.0f}, Vec2{reach, 0.0f}}) {
        ASSERT_LT(transform_point(world.transform(id), v).x, kWallFace + kSlop) << "compound " << compound << ", frame " << f;
      }
    }
    const StepStats& total = world.total_stats();
    EXPECT_GT(total.ccd_clear_skips, 0) << "compound " << compound;
    EXPECT_GT(total.ccd_bodies, 0) << "compound " << compound;  // near the wall it queried
    EXPECT_EQ(total.tunnelled, 0) << "compound " << compound;
    EXPECT_LT(world.velocity(id).x, 0.0f) << "compound " << compound;  // bounced back
  }
}

TEST(CcdClearance, FastBodiesSkipQueriesInFreeSpaceAndStillStopAtTheWall3D) {
  // As in 2D; the sphere at 6 per second (0.1 a frame: under its clearance's reach of one
  // radius), the capsule spinning about y.
  for (const bool spinning : {false, true}) {
    World3D world;
    world.add_static({.shapes = {make_box(Vec3(0.05f, 20.0f, 20.0f))}, .transform = Transform3{Vec3(30.0f, 0.0f, 0.0f)}});
    BodyDef3 body;
    if (spinning) {
      body.shapes = {make_capsule(Vec3(-1.0f, 0.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f), 0.2f)};
      body.velocity = Vec3(9.0f, 0.0f, 0.0f);
      body.angular_velocity = Vec3(0.0f, 30.0f, 0.0f);
    } else {
      body.shapes = {make_sphere(Vec3(0.0f), 0.15f)};
      body.velocity = Vec3(6.0f, 0.0f, 0.0f);
    }
    body.transform = Transform3{Vec3(10.0f, 0.0f, 0.0f)};
    const BodyId id = world.add_body(body);
    for (int f = 0; f < kFrames; ++f) {
      world.step(kDt);
      const float reach = spinning ? 1.2f : 0.15f;
      for (const Vec3& v : {Vec3(-reach, 0.0f, 0.0f), Vec3(reach, 0.0f, 0.0f)}) {
        ASSERT_LT(transform_point(world.transform(id), v).x, kWallFace + kSlop) << "spinning " << spinning << ", frame " << f;
      }
    }
    const StepStats& total = world.total_stats();
    EXPECT_GT(total.ccd_clear_skips, 0) << "spinning " << spinning;
    EXPECT_GT(total.ccd_bodies, 0) << "spinning " << spinning;
    EXPECT_EQ(total.tunnelled, 0) << "spinning " << spinning;
    EXPECT_LT(world.velocity(id).x, 0.0f) << "spinning " << spinning;
  }
}

TEST(CcdClearance, AFullTurnThroughAWallIsNotSkipped) {
  // A compound of two circles 6 apart turning a whole revolution per frame: each step ends where
  // it started (both ends of each piece's centre inside its clearance), but the pieces sweep a
  // circle of radius 3 through a thin wall. The arc its offset from the centre of rotation
  // sweeps keeps it from skipping: the time of impact stops it at the wall.
  World2D world;
  world.add_static({.shapes = {make_box({0.05f, 0.3f})}, .transform = Transform::from({0.0f, 3.0f}, 0.0f)});
  const BodyId id = world.add_body({.shapes = {make_circle({-3.0f, 0.0f}, 0.5f), make_circle({3.0f, 0.0f}, 0.5f)}});
  world.step(kDt);  // at rest: measures the clearance (the wall is beyond its reach)
  world.set_velocity(id, {0.0f, 0.0f}, 2.0f * std::numbers::pi_v<float> / kDt);
  const StepStats before = world.total_stats();
  world.step(kDt);
  EXPECT_EQ(world.total_stats().ccd_clear_skips, before.ccd_clear_skips);
  EXPECT_GT(world.last_step_stats().toi_hits, 0);
}

}  // namespace
}  // namespace collide
