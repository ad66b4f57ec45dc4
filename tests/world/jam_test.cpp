// A body driven into a gap narrower than itself: pushing it out of one static pushes it into the
// other. It must never end a step inside either: a jammed body goes back to its pose at the start
// of the step (StepStats::jammed). Found by `collide run --bodies 48000`, where a thin wall across
// an obstacle's notch made such a gap.

#include <collide/narrow/contact.hpp>
#include <collide/world/world2d.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace collide {
namespace {

TEST(World2DJam, BodyDrivenIntoANarrowWedgeNeverEndsInsideAStatic) {
  for (const float half_angle : {0.05f, 0.1f, 0.2f}) {
    World2D world(WorldOptions{.bounds = Aabb{{-50.0f, -50.0f}, {50.0f, 50.0f}}});
    // Two thin walls meeting at the origin, opening towards -x by 2 * half_angle.
    for (const float side : {1.0f, -1.0f}) {
      StaticDef wall;
      wall.shapes = {make_box({10.0f, 0.05f})};
      const float a = std::numbers::pi_v<float> + side * half_angle;
      wall.transform = Transform::from({10.0f * std::cos(a), 10.0f * std::sin(a)}, a);
      world.add_static(wall);
    }
    // A box that fits the mouth but not the throat, driven in along +x at 0.2 per step.
    BodyDef body;
    body.shapes = {make_box({0.5f, 0.45f})};
    body.transform = Transform::from({-24.0f, 0.0f}, 0.3f);
    body.velocity = {12.0f, 0.0f};
    const BodyId id = world.add_body(body);
    for (int step = 0; step < 600; ++step) {
      world.step(1.0f / 60.0f);
      world.set_velocity(id, {12.0f, 0.0f});  // keep driving it in, as a game's input would
    }
    const StepStats& total = world.total_stats();
    EXPECT_EQ(total.tunnelled, 0) << "half angle " << half_angle << ", deepest " << total.max_static_depth;
    // Its end pose overlaps neither wall by more than the check's tolerance.
    for (int s = 0; s < 2; ++s) {
      const StaticDef& wall = world.static_def(StaticId{static_cast<std::uint32_t>(s)});
      const Manifold m = contact(world.shapes(id)[0], world.transform(id), wall.shapes[0], wall.transform);
      EXPECT_LE(m.max_depth(), kTunnelDepthFraction * 0.45f) << "half angle " << half_angle;
    }
  }
}

TEST(World2DJam, BodyPushedIntoASlotNarrowerThanItselfGoesBackToItsStartPose) {
  // Two walls 3.1 apart; a box 3.2 tall and 4 long moves 0.35 (slow for its size: no continuous
  // collision) from just outside into the slot's mouth, overlapping each wall by 0.05 across and
  // 0.34 along: each push out of one wall (across, the shallower axis) is a push into the other.
  World2D world;
  for (const float side : {1.0f, -1.0f}) {
    StaticDef wall;
    wall.shapes = {make_box({5.0f, 0.5f})};
    wall.transform = Transform::from({5.0f, side * (1.55f + 0.5f)}, 0.0f);
    world.add_static(wall);
  }
  BodyDef body;
  body.shapes = {make_box({2.0f, 1.6f})};
  body.transform = Transform::from({-2.01f, 0.0f}, 0.0f);
  body.velocity = {0.35f * 60.0f, 0.0f};
  const BodyId id = world.add_body(body);
  world.step(1.0f / 60.0f);
  const StepStats& s = world.last_step_stats();
  EXPECT_EQ(s.ccd_bodies, 0);
  EXPECT_EQ(s.jammed, 1);
  EXPECT_EQ(s.tunnelled, 0);
  EXPECT_EQ(world.transform(id).p, body.transform.p);  // back where it started
  EXPECT_LT(world.velocity(id).x, 0.0f);               // and turned around
}

}  // namespace
}  // namespace collide
