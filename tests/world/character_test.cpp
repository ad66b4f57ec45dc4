// move_character on analytic levels, 3D and 2D: a flat floor, a 30 and a 60 degree ramp, a step
// of 0.2 and of 0.6, a corridor narrower than the capsule, gaps; after every move the capsule
// overlaps nothing (the world's exact contact finds no depth beyond rounding).
#include <collide/ccd/raycast.hpp>
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/world/character.hpp>
#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace collide {
namespace {

constexpr float kRadius = 0.3f;
constexpr float kHalfHeight = 0.5f;  // the core segment's half length
constexpr int kFrames = 240;
constexpr float kSpeed = 3.0f;       // units per second, walking along +x
constexpr float kDt = 1.0f / 60.0f;
constexpr float kFall = 0.02f;       // per frame, pressing down (gravity's share)
constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

/// A quad as two triangles (corners counter-clockwise seen from above).
std::shared_ptr<const TriangleMesh> quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const std::vector<Vec3> v{a, b, c, d};
  const std::vector<glm::uvec3> t{{0, 1, 2}, {0, 2, 3}};
  return std::make_shared<const TriangleMesh>(make_triangle_mesh(v, t));
}

/// A floor y = 0 over x in [x0, x1], z in [-5, 5].
std::shared_ptr<const TriangleMesh> floor_strip(float x0, float x1) {
  return quad({x0, 0, 5}, {x1, 0, 5}, {x1, 0, -5}, {x0, 0, -5});
}

Shape3D capsule3() { return make_capsule(Vec3(0, -kHalfHeight, 0), Vec3(0, kHalfHeight, 0), kRadius); }

/// Height of the capsule's centre standing on flat ground at y = 0 (the skin kept below it).
float standing_height(const CharacterSettings3& s) { return kHalfHeight + kRadius + s.skin; }

struct Walk3 {
  std::vector<CharacterMove3> moves;
  Transform3 end;
  float max_depth = 0.0f;  ///< deepest overlap after any move
};

/// Walks the capsule along +x from `start` for kFrames frames, pressing down by kFall a frame.
Walk3 walk(const World3D& world, Vec3 start, const CharacterSettings3& s = {}, Vec3 step = Vec3(kSpeed * kDt, -kFall, 0.0f)) {
  Walk3 w;
  Transform3 xf{start};
  for (int i = 0; i < kFrames; ++i) {
    const CharacterMove3 m = move_character(world, capsule3(), xf, step, s);
    xf = m.transform;
    world.collide_shape(capsule3(), xf, QueryFilter{}, [&](const ColliderRef&, const Manifold3& c) {
      w.max_depth = std::max(w.max_depth, c.max_depth());
      return true;
    });
    w.moves.push_back(m);
  }
  w.end = xf;
  return w;
}

TEST(Character3D, WalksAcrossAFlatFloorOnTheGround) {
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}, .user_id = 1});
  const CharacterSettings3 s;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_NEAR(w.end.p.x, kFrames * kSpeed * kDt, 1e-3f);   // the whole way
  EXPECT_NEAR(w.end.p.y, standing_height(s), 2e-3f);       // on the floor, the skin below
  for (const CharacterMove3& m : w.moves) {
    ASSERT_TRUE(m.grounded);
    EXPECT_EQ(m.ground_user_id, 1u);
    EXPECT_NEAR(m.ground_normal.y, 1.0f, 1e-4f);
  }
  EXPECT_LE(w.max_depth, 1e-4f);
}

// Walking under gravity (the fall speed growing each frame until the move ends on the ground,
// as a game steps it), the character keeps its skin above the floor: the ground it stands on
// is the slide's first plane, so gravity is taken out before any cast. (Before, each frame's
// fall was cast into the floor and the gap shrank to a third of the skin.)
TEST(Character3D, KeepsItsSkinWalkingUnderGravity) {
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  const CharacterSettings3 s;
  Transform3 xf{Vec3(0.0f, standing_height(s), 0.0f)};
  float vy = 0.0f;
  float min_gap = 1e9f, max_gap = 0.0f;
  std::optional<CharacterMove3> last;
  for (int frame = 0; frame < kFrames; ++frame) {
    vy -= 9.81f * kDt;
    const CharacterMove3 m = move_character(world, capsule3(), xf, Vec3(kSpeed * kDt, vy * kDt, 0.0f), s,
                                            last ? &*last : nullptr);
    ASSERT_TRUE(m.grounded) << frame;
    if (m.grounded) vy = 0.0f;
    last = m;
    xf = m.transform;
    const float gap = xf.p.y - kHalfHeight - kRadius;
    min_gap = std::min(min_gap, gap);
    max_gap = std::max(max_gap, gap);
  }
  EXPECT_NEAR(xf.p.x, kFrames * kSpeed * kDt, 1e-3f);  // the whole way
  EXPECT_GE(min_gap, 0.9f * s.skin);
  EXPECT_LE(max_gap, (1.0f + kCharacterSkinSlack) * s.skin + 1e-4f);
}

// Walking into a wall at a grazing angle under gravity, the character slides along it the
// whole way and never enters it. (Its skin is kept along the motion there, not along the
// wall's normal: a wall first seen within the cast's skin at cosine c is kept about c skins
// away, 7e-5 at 0.1 degrees for a skin of 0.01. The casts' target separation is 1e-4 of the
// capsule's size, so the exact touch of a face, as level casts compute it, must still leave it
// free to slide: it does.)
TEST(Character3D, SlidesAlongAWallMetAtAGrazingAngle) {
  for (const float degrees : {0.1f, 0.5f, 2.0f, 20.0f}) {
    SCOPED_TRACE(testing::Message() << degrees << " degrees");
    // A wall z = 1 (facing -z) beside the floor; the character walks along +x, turned into it.
    World3D world;
    world.add_static({.shapes = {floor_strip(-5.0f, 30.0f), quad({-5, 0, 1}, {-5, 3, 1}, {30, 3, 1}, {30, 0, 1})}});
    const CharacterSettings3 s;
    Transform3 xf{Vec3(0.0f, standing_height(s), 1.0f - kRadius - 3.0f * s.skin)};
    float vy = 0.0f;
    float min_gap = 1e9f;
    std::optional<CharacterMove3> last;
    const Vec3 v = kSpeed * Vec3(std::cos(degrees * kDeg), 0.0f, std::sin(degrees * kDeg));
    for (int frame = 0; frame < 2 * kFrames; ++frame) {
      vy -= 9.81f * kDt;
      const CharacterMove3 m = move_character(world, capsule3(), xf, Vec3(v.x, vy, v.z) * kDt, s, last ? &*last : nullptr);
      ASSERT_TRUE(m.grounded) << frame;
      vy = 0.0f;
      // Along the wall at least the motion's part along it, less the skin's share.
      EXPECT_GT(m.transform.p.x - xf.p.x, 0.99f * v.x * kDt) << frame;
      last = m;
      xf = m.transform;
      min_gap = std::min(min_gap, 1.0f - kRadius - xf.p.z);
    }
    EXPECT_GT(min_gap, 0.0f);
  }
}

/// A floor for x < 2 and a ramp rising along +x from x = 2 at `degrees`.
World3D ramp_world(float degrees) {
  World3D world;
  const float rise = 12.0f * std::tan(degrees * kDeg);
  world.add_static({.shapes = {floor_strip(-5.0f, 2.0f), quad({2, 0, 5}, {14, rise, 5}, {14, rise, -5}, {2, 0, -5})}});
  return world;
}

TEST(Character3D, WalksUpAThirtyDegreeRamp) {
  const World3D world = ramp_world(30.0f);
  const CharacterSettings3 s;  // walkable up to 50 degrees
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  ASSERT_GT(w.end.p.x, 6.0f);  // well onto the ramp
  // The lower sphere rests on the slope: its centre r / cos(30) above the slope, vertically.
  const float slope_y = (w.end.p.x - 2.0f) * std::tan(30.0f * kDeg);
  EXPECT_NEAR(w.end.p.y, slope_y + kHalfHeight + (kRadius + s.skin) / std::cos(30.0f * kDeg), 0.02f);
  EXPECT_TRUE(w.moves.back().grounded);
  EXPECT_NEAR(w.moves.back().ground_normal.x, -std::sin(30.0f * kDeg), 1e-3f);
  EXPECT_NEAR(w.moves.back().ground_normal.y, std::cos(30.0f * kDeg), 1e-3f);
  EXPECT_LE(w.max_depth, 1e-4f);
}

TEST(Character3D, CannotClimbASixtyDegreeRamp) {
  const World3D world = ramp_world(60.0f);
  const CharacterSettings3 s;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  // It walks to the foot of the ramp and gets no higher than a step.
  EXPECT_LT(w.end.p.y, standing_height(s) + s.step_height + 0.05f);
  EXPECT_LT(w.end.p.x, 2.5f);
  EXPECT_TRUE(w.moves.back().blocked);
  EXPECT_LE(w.max_depth, 1e-4f);
}

// Placed on a 60 degree ramp under gravity (not walkable), a character slides down it to the
// floor, as Jolt's CharacterVirtual does: the ramp's own plane takes the fall along the slope,
// and only the vertical plane beside it keeps walking from climbing. (Treating a steep surface
// as a vertical wall alone held characters in place on it: bench_world3d found 11 of 32 stuck
// on dungeon.obj.)
TEST(Character3D, SlidesDownASixtyDegreeRampUnderGravity) {
  const World3D world = ramp_world(60.0f);
  const CharacterSettings3 s;
  const float angle = 60.0f * kDeg;
  // Resting on the slope at x = 4: the lower sphere's centre r + skin from the plane.
  const Vec3 n(-std::sin(angle), std::cos(angle), 0.0f);
  const Vec3 on_slope(4.0f, 2.0f * std::tan(angle), 0.0f);
  Transform3 xf{on_slope + (kRadius + 2.0f * s.skin) * n + Vec3(0.0f, kHalfHeight, 0.0f)};
  const float start_y = xf.p.y;
  float vy = 0.0f;
  float max_depth = 0.0f;
  bool grounded = false;
  for (int i = 0; i < 120; ++i) {
    vy = (grounded ? 0.0f : vy) - 9.8f * kDt;
    const CharacterMove3 m = move_character(world, capsule3(), xf, Vec3(0.0f, vy * kDt, 0.0f), s);
    xf = m.transform;
    grounded = m.grounded;
    world.collide_shape(capsule3(), xf, QueryFilter{}, [&](const ColliderRef&, const Manifold3& c) {
      max_depth = std::max(max_depth, c.max_depth());
      return true;
    });
  }
  EXPECT_LT(xf.p.y, start_y - 2.0f);                  // came down most of the 3.5 units
  EXPECT_LT(xf.p.x, 2.5f);                            // to the foot of the ramp
  EXPECT_NEAR(xf.p.y, standing_height(s), 0.05f);     // standing on the floor
  EXPECT_TRUE(grounded);
  EXPECT_LE(max_depth, 1e-4f);
}

/// A floor, and from x = 3 a block of height `h` (a box static).
World3D step_world(float h) {
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  world.add_static({.shapes = {make_box(Vec3(5.0f, 0.5f * h, 5.0f))}, .transform = Transform3{Vec3(8.0f, 0.5f * h, 0.0f)}, .user_id = 2});
  return world;
}

TEST(Character3D, StepsUpAStepOfPointTwo) {
  const World3D world = step_world(0.2f);
  const CharacterSettings3 s;  // step height 0.3
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_GT(w.end.p.x, 5.0f);
  EXPECT_NEAR(w.end.p.y, 0.2f + standing_height(s), 3e-3f);
  EXPECT_EQ(w.moves.back().ground_user_id, 2u);
  bool stepped = false;
  for (const CharacterMove3& m : w.moves) stepped = stepped || m.stepped;
  EXPECT_TRUE(stepped);
  EXPECT_LE(w.max_depth, 1e-4f);
}

TEST(Character3D, IsStoppedByAStepOfPointSix) {
  const World3D world = step_world(0.6f);
  const CharacterSettings3 s;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_NEAR(w.end.p.x, 3.0f - kRadius - (1.0f + kCharacterSkinSlack) * s.skin, 2e-3f);  // the skin from the step's face
  EXPECT_NEAR(w.end.p.y, standing_height(s), 2e-3f);
  EXPECT_TRUE(w.moves.back().blocked);
  EXPECT_TRUE(w.moves.back().grounded);
  EXPECT_FALSE(w.moves.back().stepped);
  // Pressed against the face, a move casts: the ground probe, into the face, the step's try up
  // and forward (which goes nowhere, so the try ends without probing for ground to land on),
  // and the end's ground probe.
  EXPECT_EQ(w.moves.back().casts, 5);
  EXPECT_LE(w.max_depth, 1e-4f);
}

TEST(Character3D, IsStoppedByABarAtChestHeightWithoutTryingAStep) {
  // A bar across the way at y in [0.6, 1.0] (x in [3, 4]): the capsule meets it higher above its
  // lowest point than a step (0.3), so no step is tried: a move pressed against it casts the
  // ground probe, into the bar, and the end's ground probe.
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  world.add_static({.shapes = {make_box(Vec3(0.5f, 0.2f, 5.0f))}, .transform = Transform3{Vec3(3.5f, 0.8f, 0.0f)}});
  const CharacterSettings3 s;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_NEAR(w.end.p.x, 3.0f - kRadius - (1.0f + kCharacterSkinSlack) * s.skin, 2e-3f);
  EXPECT_TRUE(w.moves.back().blocked);
  EXPECT_FALSE(w.moves.back().stepped);
  EXPECT_EQ(w.moves.back().casts, 3);
  EXPECT_LE(w.max_depth, 1e-4f);
}

// A step beside a wall, walked to while drifting 5 degrees into the wall (a stair between
// walls): the character slides along the wall and climbs the step. Two things kept it below:
// the one try a move gets was spent on the wall, and the try's move forward went into the
// wall as well as over the step, so the wall stopped it.
TEST(Character3D, ClimbsAStepBesideAWallItDriftsInto) {
  World3D world = step_world(0.2f);
  world.add_static({.shapes = {quad({-5, 0, 1}, {-5, 3, 1}, {30, 3, 1}, {30, 0, 1})}});
  const CharacterSettings3 s;
  const float drift = 5.0f * kDeg;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 1.0f - kRadius - 3.0f * s.skin), s,
                       Vec3(kSpeed * kDt * std::cos(drift), -kFall, kSpeed * kDt * std::sin(drift)));
  EXPECT_GT(w.end.p.x, 5.0f);
  EXPECT_NEAR(w.end.p.y, 0.2f + standing_height(s), 3e-3f);
  EXPECT_LT(w.end.p.z, 1.0f - kRadius);
  bool stepped = false;
  for (const CharacterMove3& m : w.moves) stepped = stepped || m.stepped;
  EXPECT_TRUE(stepped);
  EXPECT_LE(w.max_depth, 1e-4f);
}

// Walking up a 22 degree slope into a steep wall beside it (83 degrees, leaning back: its
// normal faces a little up): the character slides up the slope along the wall. The wall gives
// two planes, its own and the vertical one beside it; their crease is level and goes into the
// slope, so the slide must take the crease of the slope and the vertical plane, which climbs
// along the wall. (Taking the first crease found held a character still in bench_world3d.)
TEST(Character3D, SlidesUpASlopeAlongASteepWall) {
  const float slope = 22.0f * kDeg;
  const float lean = 7.0f * kDeg;  // the wall's tilt from the vertical
  const float rise = std::tan(slope);
  World3D world;
  // The slope y = -rise x (rising towards -x), for z up to the wall and beyond.
  world.add_static({.shapes = {quad({-10, 10 * rise, 5}, {10, -10 * rise, 5}, {10, -10 * rise, -5}, {-10, 10 * rise, -5})}});
  // The wall through z = 1 at y = 0, leaning back (z grows with y), facing -z and a little up.
  const float t = std::tan(lean);
  world.add_static({.shapes = {quad({-10, -8, 1 - 8 * t}, {-10, 8, 1 + 8 * t}, {10, 8, 1 + 8 * t}, {10, -8, 1 - 8 * t})}});
  const CharacterSettings3 s;
  const Vec3 n_slope(std::sin(slope), std::cos(slope), 0.0f);
  const float x0 = 3.0f;
  // On the slope, the lower sphere's centre r + skin from it, 3 skins from the wall.
  const Vec3 foot = Vec3(x0, -rise * x0, 1.0f - kRadius - 3.0f * s.skin);
  const Vec3 start = foot + (kRadius + s.skin) * n_slope + Vec3(0, kHalfHeight, 0);
  const Vec3 heading = normalize(Vec3(-0.46f, 0.0f, 0.89f));  // into the wall, up the slope
  const Vec3 step(kSpeed * kDt * heading.x, -kFall, kSpeed * kDt * heading.z);
  const Walk3 w = walk(world, start, s, step);
  // Each frame the step's part along the crease of the slope and the wall's vertical plane.
  Vec3 crease = normalize(cross(n_slope, Vec3(0.0f, 0.0f, -1.0f)));
  if (crease.y < 0.0f) crease = -crease;  // up the slope
  const Vec3 expected = start + float(kFrames) * dot(step, crease) * crease;
  EXPECT_LT(w.end.p.x, x0 - 2.5f);
  EXPECT_NEAR(w.end.p.x, expected.x, 0.05f * (x0 - expected.x));
  EXPECT_NEAR(w.end.p.y, expected.y, 0.05f * (expected.y - start.y));
  int grounded = 0;
  for (const CharacterMove3& m : w.moves) grounded += m.grounded;
  EXPECT_GT(grounded, kFrames * 9 / 10);
  EXPECT_LE(w.max_depth, 1e-4f);
}

TEST(Character3D, DoesNotEnterACorridorNarrowerThanItself) {
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  // Walls from x = 3 to 13, 0.4 apart: the capsule is 0.6 across.
  for (const float z : {-0.2f - 0.5f, 0.2f + 0.5f}) {
    world.add_static({.shapes = {make_box(Vec3(5.0f, 1.5f, 0.5f))}, .transform = Transform3{Vec3(8.0f, 1.5f, z)}});
  }
  const CharacterSettings3 s;
  const Walk3 w = walk(world, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_LT(w.end.p.x, 3.0f);
  EXPECT_TRUE(w.moves.back().blocked);
  EXPECT_LE(w.max_depth, 1e-4f);
  // A corridor wider than the capsule lets it through.
  World3D wide;
  wide.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  for (const float z : {-0.4f - 0.5f, 0.4f + 0.5f}) {
    wide.add_static({.shapes = {make_box(Vec3(5.0f, 1.5f, 0.5f))}, .transform = Transform3{Vec3(8.0f, 1.5f, z)}});
  }
  const Walk3 through = walk(wide, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_GT(through.end.p.x, 11.0f);
  EXPECT_LE(through.max_depth, 1e-4f);
}

TEST(Character3D, FallsIntoAWideGapAndWalksOverANarrowOne) {
  const CharacterSettings3 s;
  World3D wide;
  wide.add_static({.shapes = {floor_strip(-5.0f, 3.0f), floor_strip(4.5f, 20.0f)}});
  const Walk3 fell = walk(wide, Vec3(0.0f, standing_height(s), 0.0f), s);
  bool airborne = false;
  for (const CharacterMove3& m : fell.moves) airborne = airborne || !m.grounded;
  EXPECT_TRUE(airborne);
  EXPECT_LT(fell.end.p.y, 0.0f);  // went down into it (pressed down by kFall each frame)
  // A gap narrower than the capsule's radius: it walks over, never dropping below a step.
  World3D narrow;
  narrow.add_static({.shapes = {floor_strip(-5.0f, 3.0f), floor_strip(3.2f, 20.0f)}});
  const Walk3 over = walk(narrow, Vec3(0.0f, standing_height(s), 0.0f), s);
  EXPECT_GT(over.end.p.x, 10.0f);
  float lowest = 10.0f;
  for (const CharacterMove3& m : over.moves) lowest = std::min(lowest, m.transform.p.y);
  EXPECT_GT(lowest, standing_height(s) - 0.1f);
  EXPECT_LE(over.max_depth, 1e-4f);
}

TEST(Character3D, StaysOnTheGroundGoingDownARamp) {
  const World3D world = ramp_world(20.0f);
  const CharacterSettings3 s;
  const float at = 11.0f * std::tan(20.0f * kDeg);  // the ramp's height at x = 13
  // Down the ramp (along -x) from near its top, without any fall per frame: sticking keeps it
  // on the ramp and then the floor.
  const Walk3 w = walk(world, Vec3(13.0f, at + kHalfHeight + (kRadius + s.skin) / std::cos(20.0f * kDeg) + 1e-3f, 0.0f), s,
                       Vec3(-kSpeed * kDt, 0.0f, 0.0f));
  int grounded = 0;
  for (const CharacterMove3& m : w.moves) grounded += m.grounded;
  EXPECT_EQ(grounded, kFrames);
  EXPECT_LT(w.end.p.x, 2.0f);  // reached the floor
  EXPECT_LE(w.max_depth, 1e-4f);
}

TEST(Character3D, IsPushedOutWhenItStartsInsideAWall) {
  World3D world;
  world.add_static({.shapes = {floor_strip(-5.0f, 20.0f)}});
  world.add_static({.shapes = {make_box(Vec3(1.0f, 2.0f, 1.0f))}, .transform = Transform3{Vec3(1.2f, 2.0f, 0.0f)}});
  const CharacterSettings3 s;
  const CharacterMove3 m = move_character(world, capsule3(), Transform3{Vec3(0.0f, standing_height(s), 0.0f)}, Vec3(0.0f), s);
  EXPECT_TRUE(m.pushed_out);
  EXPECT_LE(m.transform.p.x, 0.2f - kRadius + 1e-3f);  // out of the box's face at x = 0.2
  float depth = 0.0f;
  world.collide_shape(capsule3(), m.transform, QueryFilter{}, [&](const ColliderRef&, const Manifold3& c) {
    depth = std::max(depth, c.max_depth());
    return true;
  });
  EXPECT_LE(depth, 1e-4f);
}

TEST(Character3D, RejectsBadSettings) {
  World3D world;
  CharacterSettings3 s;
  s.up = Vec3(0.0f, 2.0f, 0.0f);
  EXPECT_THROW((void)move_character(world, capsule3(), Transform3{}, Vec3(1, 0, 0), s), InvalidInput);
  s = {};
  s.max_slope = 2.0f;
  EXPECT_THROW((void)move_character(world, capsule3(), Transform3{}, Vec3(1, 0, 0), s), InvalidInput);
  EXPECT_THROW((void)move_character(world, capsule3(), Transform3{}, Vec3(std::nanf(""), 0, 0)), InvalidInput);
}

// Handing a move the last one (`previous`) saves its ground probe and its push out against the
// statics and changes nothing: a character walking over a ramp world where boxes slide under
// its feet, one sweeps through it, and a static is added half way makes the same moves with
// and without it. And the probe is taken from `previous` indeed: a forged one (nothing under
// the feet) keeps a character from stepping up the step it climbs with the true one.
TEST(Character3D, PreviousMoveSavesTheGroundProbeAndChangesNothing) {
  World3D world = ramp_world(20.0f);
  for (int k = 0; k < 6; ++k) {
    world.add_body({.shapes = {make_box({0.3f, 0.1f, 0.3f})},
                    .transform = Transform3{{1.0f + 1.5f * float(k), 3.0f, -2.0f + 0.7f * float(k)}},
                    .velocity = {0.5f, -1.0f, 1.5f}});
  }
  // And one that sweeps through the character's circles at its height: it pushes it out.
  world.add_body({.shapes = {make_box({0.4f, 0.4f, 0.4f})}, .transform = Transform3{{-3.0f, 0.8f, -4.0f}},
                  .velocity = {0.0f, 0.0f, 1.0f}});
  const CharacterSettings3 s;
  Transform3 with{Vec3(-3.0f, standing_height(s), 0.0f)};
  Transform3 without = with;
  std::optional<CharacterMove3> last;
  Vec3 velocity(0.0f);
  int pushed = 0;
  for (int frame = 0; frame < 300; ++frame) {
    world.step(kDt);
    if (frame == 150) {
      // A new static right under the feet: a mat half way between the floor (y = 0, the
      // circles stay on it) and the capsule's bottom. The ground changes.
      ASSERT_LT(with.p.x, 2.0f);
      const float bottom = with.p.y - kHalfHeight - kRadius;
      const Vec3 feet(with.p.x, 0.5f * bottom, with.p.z);
      const auto mat = quad(feet + Vec3(-1, 0, 1), feet + Vec3(1, 0, 1), feet + Vec3(1, 0, -1), feet + Vec3(-1, 0, -1));
      world.add_static({.shapes = {mat}, .user_id = 7});
    }
    velocity.x = 0.5f * kSpeed * std::cos(0.03f * float(frame));  // circles of radius 0.8
    velocity.z = 0.5f * kSpeed * std::sin(0.03f * float(frame));
    velocity.y -= 9.81f * kDt;
    const CharacterMove3 a = move_character(world, capsule3(), with, velocity * kDt, s, last ? &*last : nullptr);
    const CharacterMove3 b = move_character(world, capsule3(), without, velocity * kDt, s);
    ASSERT_EQ(a.transform.p, b.transform.p) << frame;
    ASSERT_EQ(a.grounded, b.grounded) << frame;
    ASSERT_EQ(a.ground_normal, b.ground_normal) << frame;
    ASSERT_EQ(a.ground, b.ground) << frame;
    ASSERT_EQ(a.blocked, b.blocked) << frame;
    ASSERT_EQ(a.stepped, b.stepped) << frame;
    ASSERT_EQ(a.contact_count, b.contact_count) << frame;
    ASSERT_EQ(a.pushed_out, b.pushed_out) << frame;
    pushed += a.pushed_out;
    if (frame == 150) EXPECT_EQ(a.ground_user_id, 7u);
    last = a;
    with = a.transform;
    without = b.transform;
    if (a.grounded) velocity.y = 0.0f;
  }
  EXPECT_GT(pushed, 0);  // the sweeping box met the character

  World3D steps = step_world(0.2f);
  Transform3 xf{Vec3(0.0f, standing_height(s), 0.0f)};
  const Vec3 step(kSpeed * kDt, -kFall, 0.0f);
  std::optional<CharacterMove3> previous;
  for (int frame = 0; frame < kFrames; ++frame) {
    const CharacterMove3 m = move_character(steps, capsule3(), xf, step, s, previous ? &*previous : nullptr);
    if (m.stepped) {
      ASSERT_TRUE(previous.has_value());
      CharacterMove3 forged = *previous;
      forged.static_probe = {};  // "nothing under the feet": not supported, so no step
      EXPECT_FALSE(move_character(steps, capsule3(), xf, step, s, &forged).stepped);
      EXPECT_TRUE(move_character(steps, capsule3(), xf, step, s, &*previous).stepped);
      // A static added since (anywhere): the kept probe may miss it, so it is not used.
      steps.add_static({.shapes = {floor_strip(-20.0f, -10.0f)}});
      EXPECT_TRUE(move_character(steps, capsule3(), xf, step, s, &forged).stepped);
      return;
    }
    previous = m;
    xf = m.transform;
  }
  FAIL() << "never stepped";
}

TEST(Character3D, WandersDungeonObjWithoutEnteringIt) {
  // Characters walk in random directions over dungeon.obj's floors under gravity (the velocity
  // kept between frames, zeroed on the ground): after every move the capsule overlaps nothing.
  auto level = std::make_shared<const TriangleMesh>(
      io::load_triangle_mesh(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj"));
  World3D world;
  world.add_static({.shapes = {level}});
  const Aabb3 box = compute_aabb(*level, Transform3{});
  std::mt19937 rng(5);
  const auto uniform = [&](float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng); };
  const CharacterSettings3 s;
  int characters = 0, moves = 0, grounded = 0, stepped = 0;
  float max_depth = 0.0f;
  while (characters < 8) {
    // A start standing on a floor: a ray down from above the level, the capsule over its hit.
    const Vec3 top(uniform(box.min.x, box.max.x), box.max.y + 1.0f, uniform(box.min.z, box.max.z));
    const RayHit3 floor = raycast(*level, Transform3{}, Ray3{top, Vec3(0.0f, box.min.y - top.y - 1.0f, 0.0f)});
    if (!floor.hit || floor.normal.y < 0.9f) continue;
    Transform3 xf{floor.point + Vec3(0.0f, kHalfHeight + kRadius + 2.0f * s.skin, 0.0f)};
    bool clear = true;
    world.collide_shape(capsule3(), xf, QueryFilter{}, [&](const ColliderRef&, const Manifold3&) { return clear = false; });
    if (!clear) continue;
    ++characters;
    Vec3 velocity(0.0f);
    float heading = uniform(0.0f, 6.283f);
    for (int frame = 0; frame < 300; ++frame) {
      if (frame % 60 == 0) heading = uniform(0.0f, 6.283f);
      velocity.x = kSpeed * std::cos(heading);
      velocity.z = kSpeed * std::sin(heading);
      velocity.y -= 9.81f * kDt;
      const CharacterMove3 m = move_character(world, capsule3(), xf, velocity * kDt, s);
      xf = m.transform;
      if (m.grounded) velocity.y = 0.0f;
      ++moves;
      grounded += m.grounded;
      stepped += m.stepped;
      world.collide_shape(capsule3(), xf, QueryFilter{}, [&](const ColliderRef&, const Manifold3& c) {
        max_depth = std::max(max_depth, c.max_depth());
        return true;
      });
      if (xf.p.y < box.min.y - 5.0f) break;  // walked off an open edge of the level
    }
  }
  EXPECT_LE(max_depth, 1e-4f);
  EXPECT_GT(grounded, moves / 2);  // mostly on the floors
}

// ---- 2D: the same mover -----------------------------------------------------------------------

Shape2D capsule2() { return make_capsule({0.0f, -kHalfHeight}, {0.0f, kHalfHeight}, kRadius); }

struct Walk2 {
  std::vector<CharacterMove> moves;
  Transform end;
  float max_depth = 0.0f;
};

Walk2 walk2(const World2D& world, Vec2 start, const CharacterSettings& s = {}) {
  Walk2 w;
  Transform xf = Transform::from(start, 0.0f);
  for (int i = 0; i < kFrames; ++i) {
    const CharacterMove m = move_character(world, capsule2(), xf, Vec2{kSpeed * kDt, -kFall}, s);
    xf = m.transform;
    world.collide_shape(capsule2(), xf, QueryFilter{}, [&](const ColliderRef&, const Manifold& c) {
      w.max_depth = std::max(w.max_depth, c.max_depth());
      return true;
    });
    w.moves.push_back(m);
  }
  w.end = xf;
  return w;
}

TEST(Character2D, WalksTheFloorUpARampAndAStepButNotAWall) {
  const CharacterSettings s;
  const float stand = kHalfHeight + kRadius + s.skin;
  // A floor, a 30 degree ramp from x = 2 to 6, a plateau.
  World2D ramp;
  ramp.add_static({.shapes = {make_box({10.0f, 0.5f}, {0.0f, -0.5f}, 0.0f)}});
  const float top = 4.0f * std::tan(30.0f * kDeg);
  const std::vector<Vec2> wedge{{2.0f, 0.0f}, {6.0f, 0.0f}, {6.0f, top}};
  ramp.add_static({.shapes = {make_polygon(wedge), make_box({5.0f, 0.5f * top}, {11.0f, 0.5f * top}, 0.0f)}});
  const Walk2 up = walk2(ramp, {0.0f, stand}, s);
  EXPECT_GT(up.end.p.x, 8.0f);
  EXPECT_NEAR(up.end.p.y, top + stand, 3e-3f);  // on the plateau
  EXPECT_TRUE(up.moves.back().grounded);
  EXPECT_LE(up.max_depth, 1e-4f);
  // A step of 0.2 is climbed, one of 0.6 stops it.
  for (const float h : {0.2f, 0.6f}) {
    World2D world;
    world.add_static({.shapes = {make_box({20.0f, 0.5f}, {0.0f, -0.5f}, 0.0f)}});
    world.add_static({.shapes = {make_box({5.0f, 0.5f * h}, {8.0f, 0.5f * h}, 0.0f)}});
    const Walk2 w = walk2(world, {0.0f, stand}, s);
    if (h < s.step_height) {
      EXPECT_NEAR(w.end.p.y, h + stand, 3e-3f) << "step " << h;
      EXPECT_GT(w.end.p.x, 5.0f);
    } else {
      EXPECT_NEAR(w.end.p.x, 3.0f - kRadius - (1.0f + kCharacterSkinSlack) * s.skin, 2e-3f) << "step " << h;
      EXPECT_TRUE(w.moves.back().blocked);
    }
    EXPECT_LE(w.max_depth, 1e-4f);
  }
}

TEST(Character2D, StopsUnderACeilingLowerThanItself) {
  const CharacterSettings s;
  const float stand = kHalfHeight + kRadius + s.skin;
  World2D world;
  world.add_static({.shapes = {make_box({20.0f, 0.5f}, {0.0f, -0.5f}, 0.0f)}});
  // A ceiling from x = 3 at height 1.4: the capsule is 1.6 tall.
  world.add_static({.shapes = {make_box({5.0f, 0.5f}, {8.0f, 1.9f}, 0.0f)}});
  const Walk2 w = walk2(world, {0.0f, stand}, s);
  EXPECT_LT(w.end.p.x, 3.0f);
  EXPECT_TRUE(w.moves.back().blocked);
  EXPECT_LE(w.max_depth, 1e-4f);
}

}  // namespace
}  // namespace collide
