// World2D: the step pipeline (motion, continuous collision, push-out, body pairs, events) and
// the queries, each checked against an analytic answer or a brute-force pass over every
// collider with the library's pairwise functions.
#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/error.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/world/world2d.hpp>

#include <gtest/gtest.h>

#include "support/body_churn.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr float kTol = 1e-4f;  // float noise on unit-size geometry

StaticDef box_static(Vec2 center, Vec2 half, std::uint64_t user = 0) {
  StaticDef def;
  def.shapes = {make_box(half)};
  def.transform = Transform::from(center, 0.0f);
  def.user_id = user;
  return def;
}

BodyDef circle_body(Vec2 at, float radius, Vec2 velocity, std::uint64_t user = 0) {
  BodyDef def;
  def.shapes = {make_circle({0.0f, 0.0f}, radius)};
  def.transform = Transform::from(at, 0.0f);
  def.velocity = velocity;
  def.user_id = user;
  return def;
}

BodyDef box_body(Vec2 at, Vec2 half, Vec2 velocity, float angle = 0.0f) {
  BodyDef def;
  def.shapes = {make_box(half)};
  def.transform = Transform::from(at, angle);
  def.velocity = velocity;
  return def;
}

// A closed room: four thick walls around [-half, half]^2.
void add_room(World2D& world, float half, float thickness = 1.0f) {
  const float t = thickness;
  world.add_static(box_static({0.0f, -half - t}, {half + 2 * t, t}, 1));
  world.add_static(box_static({0.0f, half + t}, {half + 2 * t, t}, 2));
  world.add_static(box_static({-half - t, 0.0f}, {t, half + 2 * t}, 3));
  world.add_static(box_static({half + t, 0.0f}, {t, half + 2 * t}, 4));
}

struct Collider {
  ColliderRef ref;
  const Shape2D* shape;
  Transform xf;
  bool sensor;
};

// Every piece in the world, for brute-force answers.
std::vector<Collider> all_colliders(const World2D& world) {
  std::vector<Collider> out;
  for (int i = 0; i < world.static_count(); ++i) {
    const StaticDef& def = world.static_def(StaticId{std::uint32_t(i)});
    for (std::size_t k = 0; k < def.shapes.size(); ++k) {
      out.push_back({{true, std::uint32_t(i), std::uint16_t(k)}, &def.shapes[k], def.transform, def.sensor});
    }
  }
  for (const BodyId id : world.body_ids()) {
    const auto shapes = world.shapes(id);
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      out.push_back({{false, id.index, std::uint16_t(k)}, &shapes[k], world.transform(id), false});
    }
  }
  return out;
}

// A mixed scene: a room with obstacles (one concave, as convex pieces) and `n` bodies of every
// shape type with random velocities, none overlapping a static at the start.
World2D random_scene(const WorldOptions& options, int n, std::uint32_t seed) {
  World2D world(options);
  add_room(world, 20.0f);
  const std::vector<Vec2> ell = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 4}, {0, 4}};
  StaticDef concave;
  concave.shapes = convex_pieces(ell, "L obstacle");
  concave.transform = Transform::from({-10.0f, -10.0f}, 0.3f);
  world.add_static(concave);
  world.add_static(box_static({8.0f, 6.0f}, {2.0f, 0.5f}));
  StaticDef seg;
  seg.shapes = {make_segment({-5.0f, 12.0f}, {5.0f, 14.0f})};
  world.add_static(seg);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-18.0f, 18.0f), vel(-8.0f, 8.0f), size(0.2f, 0.7f),
      angle(-3.0f, 3.0f);
  const auto statics = all_colliders(world);
  int added = 0;
  while (added < n) {
    BodyDef def;
    const int kind = added % 4;
    const float s = size(rng);
    if (kind == 0) def.shapes = {make_circle({0, 0}, s)};
    if (kind == 1) def.shapes = {make_box({s, 0.6f * s})};
    if (kind == 2) def.shapes = {make_capsule({-s, 0}, {s, 0}, 0.4f * s)};
    if (kind == 3) def.shapes = {make_box({s, 0.3f * s}, {0, 0}, 0.0f), make_circle({s, 0}, 0.5f * s)};
    def.transform = Transform::from({pos(rng), pos(rng)}, angle(rng));
    def.velocity = {vel(rng), vel(rng)};
    def.angular_velocity = angle(rng);
    def.user_id = 100 + added;
    def.bullet = added % 17 == 0;
    bool clear = true;
    for (const Collider& c : statics) {
      for (const Shape2D& shape : def.shapes) {
        if (overlap(shape, def.transform, *c.shape, c.xf)) clear = false;
      }
    }
    if (!clear) continue;
    world.add_body(def);
    ++added;
  }
  return world;
}

// ---- Bad input --------------------------------------------------------------------------------

/// The message of the InvalidInput `call` throws ("" and a failure when it throws none).
template <class Call>
std::string error_of(Call&& call) {
  try {
    call();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted";
  return "";
}

// Issue 15: finite but extreme coordinates (1e38 bounds, a level scaled by 1e10) were accepted
// and then failed the independent check (bodies escaping through walls from coordinates of
// 1e12 on, infinite boxes from 1e14). The world refuses anything beyond kMaxWorldCoordinate,
// naming the static or body, the shape and the range; up to the limit is accepted.
TEST(World2DInput, RefusesCoordinatesBeyondTheRangeNamingItAndTheLimit) {
  const std::string range = "beyond the coordinate range [-1073741824, 1073741824] (kMaxWorldCoordinate)";
  World2D world;
  world.add_static(box_static({0, 0}, {1, 1}));
  // A static's second shape far away; a body at 1e38; one whose radius reaches beyond.
  StaticDef far_static = box_static({0, 0}, {1, 1});
  far_static.shapes.push_back(make_circle({2e9f, 0.0f}, 1.0f));
  std::string e = error_of([&] { world.add_static(far_static); });
  EXPECT_NE(e.find("static 1 shapes[1]"), std::string::npos) << e;
  EXPECT_NE(e.find(range), std::string::npos) << e;
  e = error_of([&] { world.add_body(circle_body({1e38f, 0.0f}, 1.0f, {0, 0})); });
  EXPECT_NE(e.find("body 0 shapes[0]"), std::string::npos) << e;
  EXPECT_NE(e.find("reaches 1e+38"), std::string::npos) << e;
  EXPECT_NE(e.find(range), std::string::npos) << e;
  e = error_of([&] { world.add_body(circle_body({0.0f, -1e9f}, 2e8f, {0, 0})); });
  EXPECT_NE(e.find(range), std::string::npos) << e;
  e = error_of([] { World2D w(WorldOptions{.bounds = Aabb{{-1e38f, -1e38f}, {1e38f, 1e38f}}}); });
  EXPECT_NE(e.find("world options bounds"), std::string::npos) << e;
  EXPECT_NE(e.find(range), std::string::npos) << e;
  EXPECT_EQ(world.static_count(), 1);
  EXPECT_EQ(world.body_count(), 0);
  // Up to the limit itself is accepted, and a world 1e8 across steps with finite state.
  const float edge = kMaxWorldCoordinate;
  World2D big(WorldOptions{.bounds = Aabb{{-edge, -edge}, {edge, edge}}});
  big.add_static(box_static({0.0f, -edge + 1e6f}, {edge - 1e6f, 1e6f}));
  const BodyId body = big.add_body(circle_body({0.0f, 0.0f}, 1e6f, {0.0f, -1e9f}));
  for (int i = 0; i < 120; ++i) big.step(kDt);
  const Transform& xf = big.transform(body);
  EXPECT_TRUE(std::isfinite(xf.p.x) && std::isfinite(xf.p.y));
  EXPECT_GT(xf.p.y, -edge + 2e6f);  // bounced on the floor (it reached it within a second), not through it
  EXPECT_EQ(big.total_stats().tunnelled, 0);
  EXPECT_EQ(big.total_stats().escaped, 0);
}

// Issue 15, fuzz_scene_json's finding 8: a finite velocity of 1e25 was accepted, its length
// overflowed float, and the step threw from the temporal broad phase ("speed bound 0: negative
// or not finite"). Velocities beyond kMaxWorldSpeed (and angular ones beyond
// kMaxWorldAngularSpeed) are refused by name; up to the limit a world steps, and a tiny step
// whose push over dt overflows gives a saturated speed bound, not a throw.
TEST(World2DInput, RefusesSpeedsBeyondTheRangeAndStepsUpToIt) {
  const std::string range = "(kMaxWorldSpeed, world units per second)";
  World2D world;
  std::string e = error_of([&] { world.add_body(circle_body({0, 0}, 1.0f, {1e25f, 0.0f})); });
  EXPECT_NE(e.find("body 0 velocity"), std::string::npos) << e;
  EXPECT_NE(e.find(range), std::string::npos) << e;
  BodyDef spin = circle_body({0, 0}, 1.0f, {0, 0});
  spin.angular_velocity = -1e30f;
  e = error_of([&] { world.add_body(spin); });
  EXPECT_NE(e.find("angular velocity"), std::string::npos) << e;
  EXPECT_NE(e.find("kMaxWorldAngularSpeed"), std::string::npos) << e;
  EXPECT_EQ(world.body_count(), 0);
  const BodyId body = world.add_body(circle_body({0, 0}, 1.0f, {1.0f, 0.0f}));
  e = error_of([&] { world.set_velocity(body, {0.0f, -2e9f}); });
  EXPECT_NE(e.find(range), std::string::npos) << e;
  EXPECT_EQ(world.velocity(body).x, 1.0f);  // a refused velocity leaves the body as it was
  // At the limit, in a big world: the step runs and the state stays finite.
  const float edge = kMaxWorldCoordinate;
  World2D big(WorldOptions{.bounds = Aabb{{-edge, -edge}, {edge, edge}}});
  BodyDef fastest = circle_body({0.0f, 0.0f}, 1.0f, {kMaxWorldSpeed, -kMaxWorldSpeed});
  fastest.angular_velocity = kMaxWorldAngularSpeed;
  const BodyId f = big.add_body(fastest);
  for (int i = 0; i < 3; ++i) big.step(kDt);
  EXPECT_TRUE(std::isfinite(big.transform(f).p.x) && std::isfinite(big.transform(f).p.y));
  // Two bodies started overlapping get a push; a step of the smallest float then divides it by
  // dt (1e34 times the push overflows): the speed bound saturates and the step runs.
  World2D pushed;
  pushed.add_static(box_static({0.0f, -1.0f}, {10.0f, 1.0f}));
  pushed.add_body(circle_body({0.0f, 0.5f}, 1.0f, {0.0f, 0.0f}));
  pushed.add_body(circle_body({0.5f, 0.5f}, 1.0f, {0.0f, 0.0f}));
  pushed.step(kDt);
  EXPECT_NO_THROW(pushed.step(std::numeric_limits<float>::denorm_min()));
  EXPECT_NO_THROW(pushed.step(kDt));
}

TEST(World2DInput, RejectsBadDefinitionsAndSteps) {
  World2D world;
  StaticDef empty;
  EXPECT_THROW(world.add_static(empty), InvalidInput);
  StaticDef nan_static = box_static({0, 0}, {1, 1});
  nan_static.transform.p.x = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(world.add_static(nan_static), InvalidInput);
  BodyDef fast = circle_body({0, 0}, 1.0f, {std::numeric_limits<float>::infinity(), 0.0f});
  EXPECT_THROW(world.add_body(fast), InvalidInput);
  BodyDef spin = circle_body({0, 0}, 1.0f, {0, 0});
  spin.angular_velocity = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(world.add_body(spin), InvalidInput);
  EXPECT_EQ(world.body_count(), 0);
  EXPECT_EQ(world.static_count(), 0);
  EXPECT_THROW(world.step(-kDt), InvalidInput);
  EXPECT_THROW(world.step(std::numeric_limits<float>::quiet_NaN()), InvalidInput);
  EXPECT_THROW((void)world.static_def(StaticId{3}), InvalidInput);
  Aabb bad{{1, 1}, {0, 0}};
  EXPECT_THROW(World2D(WorldOptions{.bounds = bad}), InvalidInput);
  try {
    (void)world_broad_phase_from_string("octree");
    FAIL() << "accepted an unknown broad phase";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("temporal"), std::string::npos) << e.what();
  }
  for (int i = 0; i <= static_cast<int>(WorldBroadPhase::brute_force); ++i) {
    const auto bp = static_cast<WorldBroadPhase>(i);
    EXPECT_EQ(world_broad_phase_from_string(to_string(bp)), bp);
  }
  const std::vector<Vec2> bowtie = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  EXPECT_THROW((void)convex_pieces(bowtie, "bowtie"), InvalidInput);
  // Queries validate too.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW((void)world.raycast(Ray{{0, 0}, {nan, 1}}), InvalidInput);
  EXPECT_THROW((void)world.cast_laser(Ray{{nan, 0}, {1, 1}}, 2), InvalidInput);
  const auto none = [](const ColliderRef&) { return true; };
  EXPECT_THROW(world.query_aabb(Aabb{{0, 0}, {nan, 1}}, {}, none), InvalidInput);
  EXPECT_THROW(world.query_point({nan, 0}, {}, none), InvalidInput);
  const BodyId body = world.add_body(circle_body({0, 0}, 1.0f, {0, 0}));
  EXPECT_THROW((void)world.ground_check(body, {0, nan}), InvalidInput);
  world.remove_body(body);
  EXPECT_THROW((void)world.ground_check(body, {0, -1}), InvalidInput);
}

TEST(World2DInput, ReserveRefusesANegativeCountAndChangesNoResult) {
  World2D w;
  EXPECT_THROW(w.reserve(-1), InvalidInput);
  // The same bodies with and without room reserved (a little, and enough for the array to go
  // on large pages, above 4 MiB): the same state after the same steps.
  constexpr int kReserves[] = {0, 100, 30000};
  std::uint64_t hashes[std::size(kReserves)] = {};
  for (std::size_t k = 0; k < std::size(kReserves); ++k) {
    World2D world;
    if (kReserves[k] > 0) world.reserve(kReserves[k]);
    world.add_static({.shapes = {make_box({10.0f, 0.5f})}, .transform = Transform::from({0.0f, -6.0f}, 0.0f)});
    for (int i = 0; i < 100; ++i) {
      const float x = static_cast<float>(i % 10) - 4.5f, y = static_cast<float>(i / 10) * 0.6f - 3.0f;
      world.add_body({.shapes = {make_circle({0.0f, 0.0f}, 0.2f)}, .transform = Transform::from({x, y}, 0.0f),
                      .velocity = {0.5f * x, -2.0f}});
    }
    for (int f = 0; f < 30; ++f) world.step(1.0f / 60.0f);
    hashes[k] = world.state_hash();
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
}

TEST(World2DInput, BodiesAddedPastTheLargePageSizeKeepTheirState) {
  // 25,000 bodies added one by one: the body array grows past 4 MiB, where each growth moves
  // the bodies into a block advised onto large pages. Every body keeps its pose and velocity,
  // and the world steps as one given the room up front.
  constexpr int kBodies = 25000;
  const auto def = [](int i) {
    const float x = static_cast<float>(i % 500) * 0.5f, y = static_cast<float>(i / 500) * 0.5f;
    return BodyDef{.shapes = {make_circle({0.0f, 0.0f}, 0.2f)}, .transform = Transform::from({x, y}, 0.1f * x),
                   .velocity = {1.0f, -0.5f * y}};
  };
  World2D grown, reserved;
  reserved.reserve(kBodies);
  std::vector<BodyId> ids;
  for (int i = 0; i < kBodies; ++i) {
    ids.push_back(grown.add_body(def(i)));
    (void)reserved.add_body(def(i));
  }
  for (int i = 0; i < kBodies; i += 997) {
    const BodyDef d = def(i);
    EXPECT_EQ(grown.transform(ids[static_cast<std::size_t>(i)]).p, d.transform.p) << "body " << i;
    EXPECT_EQ(grown.velocity(ids[static_cast<std::size_t>(i)]), d.velocity) << "body " << i;
  }
  grown.step(1.0f / 60.0f);
  reserved.step(1.0f / 60.0f);
  EXPECT_EQ(grown.state_hash(), reserved.state_hash());
}

// Shape `a` equals `b`: same type and the same numbers (polygons: every vertex and normal).
bool same_shape(const Shape2D& a, const Shape2D& b) {
  if (a.index() != b.index()) return false;
  if (const auto* pa = std::get_if<Polygon>(&a)) {
    const auto& pb = std::get<Polygon>(b);
    if (pa->count != pb.count || pa->radius != pb.radius) return false;
    for (int i = 0; i < pa->count; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (pa->vertices[k] != pb.vertices[k] || pa->normals[k] != pb.normals[k]) return false;
    }
    return true;
  }
  if (const auto* ca = std::get_if<Circle>(&a)) {
    return ca->center == std::get<Circle>(b).center && ca->radius == std::get<Circle>(b).radius;
  }
  if (const auto* ka = std::get_if<Capsule>(&a)) {
    const auto& kb = std::get<Capsule>(b);
    return ka->a == kb.a && ka->b == kb.b && ka->radius == kb.radius;
  }
  const auto& sa = std::get<Segment>(a);
  const auto& sb = std::get<Segment>(b);
  return sa.a == sb.a && sa.b == sb.b;
}

TEST(World2DInput, RemovedBodiesShapeSlotsServeNewBodiesWithTheirOwnShapes) {
  // The world keeps every body's shapes in one pool; a removed body's slots serve the next body
  // with as many shapes. Bodies of one, two and three pieces (a 12-gon holds its vertices on
  // the heap, a circle inline) are added, a third removed, more added: every live body reads
  // back exactly the shapes it was given, and removed ones are gone.
  std::vector<Vec2> ring;
  for (int i = 0; i < 12; ++i) {
    const float a = 2.0f * std::numbers::pi_v<float> * static_cast<float>(i) / 12.0f;
    ring.push_back({0.4f * std::cos(a), 0.4f * std::sin(a)});
  }
  const Polygon twelve = make_polygon(ring);
  const auto def = [&](int i) {
    BodyDef d;
    d.transform = Transform::from({static_cast<float>(i % 20) * 3.0f, static_cast<float>(i / 20) * 3.0f}, 0.0f);
    const float s = 0.2f + 0.01f * static_cast<float>(i % 7);
    switch (i % 4) {
      case 0: d.shapes = {make_circle({0.0f, 0.0f}, s)}; break;
      case 1: d.shapes = {twelve}; break;
      case 2: d.shapes = {make_box({s, s}), make_circle({0.5f, 0.0f}, s)}; break;
      default: d.shapes = {make_capsule({-s, 0.0f}, {s, 0.0f}, 0.5f * s), twelve, make_box({s, 0.5f * s})}; break;
    }
    return d;
  };
  World2D world;
  const test::BodyChurn churn = test::churn_bodies(world, def, 60, 3, 100);  // 20 slots reused
  test::expect_churned_shapes(world, churn, def, same_shape);
  world.step(1.0f / 60.0f);  // and the world steps with them
  EXPECT_EQ(world.body_count(), 80);
}

TEST(World2DInput, StaleBodyIdsAreRecognisedAfterSlotReuse) {
  World2D world;
  const BodyId a = world.add_body(circle_body({0, 0}, 1.0f, {0, 0}));
  world.remove_body(a);
  EXPECT_FALSE(world.contains(a));
  EXPECT_THROW((void)world.transform(a), InvalidInput);
  EXPECT_THROW(world.remove_body(a), InvalidInput);
  const BodyId b = world.add_body(circle_body({5, 0}, 1.0f, {0, 0}));
  EXPECT_EQ(b.index, a.index);  // the slot is reused...
  EXPECT_NE(b.generation, a.generation);  // ...under a new generation
  EXPECT_FALSE(world.contains(a));
  EXPECT_TRUE(world.contains(b));
  EXPECT_THROW(world.set_velocity(b, {std::numeric_limits<float>::quiet_NaN(), 0}), InvalidInput);
  EXPECT_EQ(world.velocity(b), (Vec2{0, 0}));
}

// ---- Motion and response ---------------------------------------------------------------------

TEST(World2DStep, FreeBodiesMoveAndTurnByVelocityTimesDt) {
  World2D world;
  BodyDef def = box_body({1, 2}, {0.5f, 0.25f}, {3, -4});
  def.angular_velocity = 2.0f;
  const BodyId id = world.add_body(def);
  for (int i = 0; i < 30; ++i) world.step(kDt);
  const Transform xf = world.transform(id);
  EXPECT_NEAR(xf.p.x, 1.0f + 3.0f * 30 * kDt, kTol);
  EXPECT_NEAR(xf.p.y, 2.0f - 4.0f * 30 * kDt, kTol);
  EXPECT_NEAR(xf.q.angle(), 2.0f * 30 * kDt, kTol);
  EXPECT_TRUE(world.contacts().empty());
  EXPECT_EQ(world.total_stats().steps, 30);
}

// A fast body that does not turn keeps its rotation bit for bit and moves by exactly
// velocity * dt, whether continuous collision swept it (no hit) or its clearance from the
// statics let it skip the query: its end pose is composed as a slow body's is, not rebuilt
// through its angle (atan2, then sin and cos, which could move the rotation by an ulp a step).
TEST(World2DStep, FastBodiesThatDoNotTurnKeepTheirRotationExactly) {
  World2D world;
  add_room(world, 10.0f);
  BodyDef def = box_body({-2.0f, 1.0f}, {0.5f, 0.25f}, {1.5f, -0.5f}, 0.3f);
  def.bullet = true;  // always fast: swept by continuous collision or cleared by the clearance
  const BodyId id = world.add_body(def);
  Transform expected = world.transform(id);
  for (int k = 0; k < 30; ++k) {
    world.step(kDt);
    expected.p = expected.p + def.velocity * kDt;
    const Transform xf = world.transform(id);
    ASSERT_EQ(xf.q.c, expected.q.c) << "step " << k;
    ASSERT_EQ(xf.q.s, expected.q.s) << "step " << k;
    ASSERT_EQ(xf.p, expected.p) << "step " << k;
  }
  EXPECT_GE(world.total_stats().ccd_bodies, 1);       // swept with no hit
  EXPECT_GE(world.total_stats().ccd_clear_skips, 20);  // cleared without a query
}

TEST(World2DStep, BallBouncesOffFloorWithBeginAndEndEvents) {
  World2D world;
  world.add_static(box_static({0, -1}, {10, 1}, 7));  // top face at y = 0
  const BodyId ball = world.add_body(circle_body({0, 2}, 0.5f, {0, -10}, 42));
  int begins = 0, ends = 0;
  float lowest = 1e9f;
  for (int i = 0; i < 60; ++i) {
    world.step(kDt);
    lowest = std::min(lowest, world.transform(ball).p.y);
    for (const ContactEvent& e : world.events()) {
      EXPECT_FALSE(e.a.is_static);
      EXPECT_TRUE(e.b.is_static);
      EXPECT_EQ(e.user_a, 42u);
      EXPECT_EQ(e.user_b, 7u);
      if (e.type == ContactEventType::begin) {
        ++begins;
        EXPECT_NEAR(e.manifold.normal.y, -1.0f, kTol);  // from the ball (A) down to the floor
      }
      if (e.type == ContactEventType::end) ++ends;
    }
    EXPECT_EQ(world.last_step_stats().tunnelled, 0);
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(ends, 1);
  EXPECT_GE(lowest, 0.5f - kTol);   // never sank into the floor
  EXPECT_NEAR(world.velocity(ball).y, 10.0f, kTol);  // kinematic bounce: speed kept, reversed
  EXPECT_GT(world.transform(ball).p.y, 2.0f);
}

TEST(World2DStep, SlidingBoxKeepsItsContactPointsByFeatureId) {
  World2D world;
  world.add_static(box_static({0, -1}, {50, 1}));
  const BodyId box = world.add_body(box_body({0, 0.5f}, {0.5f, 0.5f}, {2, 0}));  // resting on y = 0
  world.step(kDt);
  ASSERT_EQ(world.events().size(), 1u);
  EXPECT_EQ(world.events()[0].type, ContactEventType::begin);
  EXPECT_EQ(world.events()[0].manifold.count, 2);
  for (int i = 0; i < 20; ++i) {
    world.step(kDt);
    ASSERT_EQ(world.events().size(), 1u);
    const ContactEvent& e = world.events()[0];
    EXPECT_EQ(e.type, ContactEventType::persist);
    EXPECT_EQ(e.manifold.count, 2);
    EXPECT_EQ(e.persisted_points, 0b11);  // same box corners on the same floor face
  }
  EXPECT_NEAR(world.transform(box).p.y, 0.5f, kTol);
  EXPECT_NEAR(world.transform(box).p.x, 2.0f * 21 * kDt, kTol);
  world.remove_body(box);
  world.step(kDt);
  ASSERT_EQ(world.events().size(), 1u);
  EXPECT_EQ(world.events()[0].type, ContactEventType::end);
  world.step(kDt);
  EXPECT_TRUE(world.events().empty());
}

TEST(World2DStep, LayersAndMasksLetBodiesPassThrough) {
  World2D world;
  StaticDef floor = box_static({0, -1}, {10, 1});
  floor.filter = {.layer = 1u, .mask = 0xffffffffu};
  world.add_static(floor);
  BodyDef ghost = circle_body({0, 2}, 0.5f, {0, -10});
  ghost.filter = {.layer = 2u, .mask = 2u};  // sees only layer 2
  const BodyId g = world.add_body(ghost);
  for (int i = 0; i < 60; ++i) {
    world.step(kDt);
    EXPECT_TRUE(world.contacts().empty());
  }
  EXPECT_NEAR(world.transform(g).p.y, 2.0f - 10.0f * 60 * kDt, 1e-3f);
  EXPECT_GT(world.total_stats().filtered, 0);
  EXPECT_FALSE(should_collide({1u, 1u}, {2u, 0xffffffffu}));
  EXPECT_TRUE(should_collide({1u, 2u}, {2u, 1u}));
}

TEST(World2DStep, SensorsReportOverlapsWithoutPushing) {
  World2D world;
  StaticDef zone = box_static({0, 0}, {2, 2}, 9);
  zone.sensor = true;
  world.add_static(zone);
  const BodyId b = world.add_body(circle_body({-5, 0}, 0.5f, {6, 0}));
  std::vector<ContactEventType> seen;
  for (int i = 0; i < 120; ++i) {
    world.step(kDt);
    for (const ContactEvent& e : world.events()) {
      EXPECT_TRUE(e.sensor);
      EXPECT_EQ(e.user_b, 9u);
      if (seen.empty() || seen.back() != e.type) seen.push_back(e.type);
    }
  }
  EXPECT_EQ(seen, (std::vector<ContactEventType>{ContactEventType::begin, ContactEventType::persist,
                                                 ContactEventType::end}));
  EXPECT_NEAR(world.transform(b).p.x, -5.0f + 6.0f * 120 * kDt, 1e-3f);  // never pushed
  EXPECT_EQ(world.velocity(b), (Vec2{6, 0}));
  EXPECT_EQ(world.total_stats().pushes, 0);
}

TEST(World2DStep, BodyLayersDecideWhichBodyPairsMeet) {
  // A sees only layer 2; B is on layer 1: (B.layer & A.mask) == 0, so they pass through. C is
  // on layer 2 and meets A.
  World2D world;
  BodyDef a = circle_body({-2, 0}, 0.5f, {3, 0}, 1);
  a.filter = {.layer = 2u, .mask = 2u};
  BodyDef b = circle_body({2, 0}, 0.5f, {-3, 0}, 2);
  b.filter = {.layer = 1u, .mask = 0xffffffffu};
  const BodyId ia = world.add_body(a);
  const BodyId ib = world.add_body(b);
  for (int i = 0; i < 60; ++i) {
    world.step(kDt);
    EXPECT_TRUE(world.contacts().empty()) << "step " << i;
  }
  EXPECT_NEAR(world.transform(ia).p.x, -2.0f + 3.0f * 60 * kDt, 1e-3f);  // straight through
  EXPECT_NEAR(world.transform(ib).p.x, 2.0f - 3.0f * 60 * kDt, 1e-3f);
  EXPECT_GT(world.total_stats().filtered, 0);

  World2D other;
  BodyDef c = circle_body({2, 0}, 0.5f, {-3, 0}, 3);
  c.filter = {.layer = 2u, .mask = 0xffffffffu};
  const BodyId ja = other.add_body(a);
  const BodyId jc = other.add_body(c);
  int begins = 0;
  for (int i = 0; i < 60; ++i) {
    other.step(kDt);
    for (const ContactEvent& e : other.events()) begins += e.type == ContactEventType::begin;
  }
  EXPECT_EQ(begins, 1);
  EXPECT_NEAR(other.velocity(ja).x, -3.0f, kTol);  // they met and bounced
  EXPECT_NEAR(other.velocity(jc).x, 3.0f, kTol);
}

TEST(World2DStep, SensorBodiesReportWithoutPushingOrBeingPushed) {
  // A sensor body sweeps through a resting body and a wall: events for both, nobody moves
  // anybody, and the sensor keeps its velocity.
  World2D world;
  world.add_static(box_static({4, 0}, {0.25f, 3}, 8));
  const BodyId still = world.add_body(circle_body({0, 0}, 0.5f, {0, 0}, 5));
  BodyDef probe = circle_body({-3, 0}, 0.4f, {6, 0}, 6);
  probe.sensor = true;
  const BodyId sensor = world.add_body(probe);
  std::vector<std::pair<std::uint64_t, ContactEventType>> seen;  // (other user, type) changes
  for (int i = 0; i < 120; ++i) {
    world.step(kDt);
    for (const ContactEvent& e : world.events()) {
      EXPECT_TRUE(e.sensor);
      const std::uint64_t other = e.user_a == 6u ? e.user_b : e.user_a;
      if (seen.empty() || seen.back() != std::make_pair(other, e.type)) seen.emplace_back(other, e.type);
    }
  }
  using P = std::pair<std::uint64_t, ContactEventType>;
  EXPECT_EQ(seen, (std::vector<P>{{5, ContactEventType::begin}, {5, ContactEventType::persist}, {5, ContactEventType::end},
                                  {8, ContactEventType::begin}, {8, ContactEventType::persist}, {8, ContactEventType::end}}));
  EXPECT_EQ(world.transform(still).p, (Vec2{0, 0}));
  EXPECT_EQ(world.velocity(still), (Vec2{0, 0}));
  EXPECT_EQ(world.velocity(sensor), (Vec2{6, 0}));
  EXPECT_NEAR(world.transform(sensor).p.x, -3.0f + 6.0f * 120 * kDt, 1e-3f);
  EXPECT_EQ(world.total_stats().tunnelled, 0);  // a sensor inside a wall is not tunnelling
}

TEST(World2DStep, EqualCirclesCollidingHeadOnSwapVelocities) {
  World2D world;
  const BodyId a = world.add_body(circle_body({-2, 0}, 0.5f, {3, 0}));
  const BodyId b = world.add_body(circle_body({2, 0}, 0.5f, {-3, 0}));
  bool touched = false;
  for (int i = 0; i < 60; ++i) {
    world.step(kDt);
    touched = touched || !world.contacts().empty();
  }
  EXPECT_TRUE(touched);
  EXPECT_NEAR(world.velocity(a).x, -3.0f, kTol);
  EXPECT_NEAR(world.velocity(b).x, 3.0f, kTol);
  EXPECT_NEAR(world.velocity(a).y, 0.0f, kTol);
  // Symmetric motion stays symmetric.
  EXPECT_NEAR(world.transform(a).p.x, -world.transform(b).p.x, kTol);
  EXPECT_GE(world.transform(b).p.x - world.transform(a).p.x, 1.0f - kTol);
}

// The proof of continuous collision inside the world: small fast bodies fired at thin
// walls at up to 1e4 times their size per step, from many angles, never end up behind them.
TEST(World2DStep, FastBodiesNeverTunnelThroughThinWalls) {
  const float size = 0.02f;  // body diameter / width
  const float speed = 1e4f * size;  // per step (dt = 1)
  const std::vector<Shape2D> walls = {make_segment({0, -400}, {0, 400}), make_box({0.005f, 400.0f})};
  const std::vector<Shape2D> bullets = {make_circle({0, 0}, 0.5f * size),
                                        make_capsule({-0.25f * size, 0}, {0.25f * size, 0}, 0.25f * size),
                                        make_box({0.5f * size, 0.5f * size})};
  int fired = 0;
  for (const Shape2D& wall : walls) {
    for (const Shape2D& bullet : bullets) {
      for (int k = -6; k <= 6; ++k) {
        const float angle = float(k) * 0.2f;  // up to +-69 degrees off the wall's normal
        World2D world;
        StaticDef w;
        w.shapes = {wall};
        w.transform = Transform::from({5, 0}, 0.0f);
        world.add_static(w);
        BodyDef def;
        def.shapes = {bullet};
        def.transform = Transform::from({0, 0}, 0.3f * float(k));
        def.velocity = speed * Vec2{std::cos(angle), std::sin(angle)};
        def.angular_velocity = 5.0f;
        const BodyId id = world.add_body(def);
        for (int s = 0; s < 3; ++s) {
          world.step(1.0f);
          const Aabb box = compute_aabb(bullet, world.transform(id));
          EXPECT_LE(box.max.x, 5.0f + 0.005f + 1e-3f) << "wall " << wall.index() << " bullet "
                                                       << bullet.index() << " angle " << angle;
          EXPECT_EQ(world.last_step_stats().tunnelled, 0);
        }
        EXPECT_LT(world.velocity(id).x, 0.0f);  // it bounced back
        ++fired;
      }
    }
  }
  EXPECT_EQ(fired, 2 * 3 * 13);
}

TEST(World2DStep, CornersPushBodiesOutOfEveryWall) {
  World2D world(WorldOptions{.bounds = Aabb{{-5, -5}, {5, 5}}});
  add_room(world, 5.0f, 0.5f);
  // Bodies started overlapping walls and corners come out within the step.
  const BodyId corner = world.add_body(box_body({4.8f, 4.8f}, {0.5f, 0.5f}, {0, 0}, 0.4f));
  const BodyId side = world.add_body(circle_body({-4.9f, 0}, 0.5f, {0, 0}));
  world.step(kDt);
  for (const BodyId id : {corner, side}) {
    const Aabb box = compute_aabb(world.shapes(id)[0], world.transform(id));
    EXPECT_GE(box.min.x, -5.0f - 1e-3f);
    EXPECT_LE(box.max.x, 5.0f + 1e-3f);
    EXPECT_GE(box.min.y, -5.0f - 1e-3f);
    EXPECT_LE(box.max.y, 5.0f + 1e-3f);
  }
  EXPECT_GT(world.last_step_stats().pushes, 0);
  EXPECT_EQ(world.last_step_stats().escaped, 0);
  EXPECT_EQ(world.last_step_stats().tunnelled, 0);
}

// ---- Determinism -----------------------------------------------------------------------------

TEST(World2DDeterminism, EveryBroadPhaseGivesTheSameStateBitForBit) {
  std::vector<std::uint64_t> hashes;
  std::vector<std::int64_t> contacts;
  for (int i = 0; i <= static_cast<int>(WorldBroadPhase::brute_force); ++i) {
    WorldOptions options;
    options.broad_phase = static_cast<WorldBroadPhase>(i);
    options.bounds = Aabb{{-20, -20}, {20, 20}};
    World2D world = random_scene(options, 300, 5u);
    for (int s = 0; s < 120; ++s) world.step(kDt);
    hashes.push_back(world.state_hash());
    contacts.push_back(world.total_stats().contacts);
    const StepStats& total = world.total_stats();
    EXPECT_EQ(total.tunnelled, 0) << to_string(options.broad_phase);
    EXPECT_EQ(total.escaped, 0) << to_string(options.broad_phase);
    EXPECT_GT(total.contacts, 0);
    EXPECT_GT(total.ccd_bodies, 0);
  }
  for (std::size_t i = 1; i < hashes.size(); ++i) {
    EXPECT_EQ(hashes[i], hashes[0]) << to_string(static_cast<WorldBroadPhase>(i));
    EXPECT_EQ(contacts[i], contacts[0]) << to_string(static_cast<WorldBroadPhase>(i));
  }
  // The same run twice, and with the early-out chains fixed instead of adaptive.
  World2D again = random_scene({}, 300, 5u);
  WorldOptions fixed;
  fixed.adaptive_early_out = false;
  World2D unlearned = random_scene(fixed, 300, 5u);
  for (int s = 0; s < 120; ++s) {
    again.step(kDt);
    unlearned.step(kDt);
  }
  EXPECT_EQ(again.state_hash(), hashes[0]);
  EXPECT_EQ(unlearned.state_hash(), hashes[0]);
}

TEST(World2DDeterminism, BodyPairsMatchBruteForceEveryStep) {
  WorldOptions temporal;
  WorldOptions brute;
  brute.broad_phase = WorldBroadPhase::brute_force;
  World2D a = random_scene(temporal, 200, 11u);
  World2D b = random_scene(brute, 200, 11u);
  for (int s = 0; s < 60; ++s) {
    a.step(kDt);
    b.step(kDt);
    ASSERT_EQ(a.contacts().size(), b.contacts().size()) << "step " << s;
    for (std::size_t i = 0; i < a.contacts().size(); ++i) {
      EXPECT_EQ(a.contacts()[i].a, b.contacts()[i].a);
      EXPECT_EQ(a.contacts()[i].b, b.contacts()[i].b);
    }
  }
  EXPECT_GT(a.total_stats().broad_skipped_checks, 0);  // the temporal broad phase skipped work
}

// No touching body-static pair is missing from the contacts.
TEST(World2DDeterminism, ContactsIncludeEveryTouchingBodyStaticPair) {
  World2D world = random_scene({}, 300, 23u);
  std::size_t touching = 0;
  for (int s = 0; s < 60; ++s) {
    world.step(kDt);
    // Contacts are computed before the deferred body pushes move anyone, so compare against
    // body-static pairs only (bodies do not move after the static pass).
    const auto colliders = all_colliders(world);
    std::vector<std::pair<std::uint64_t, std::uint64_t>> expected;
    for (const Collider& body : colliders) {
      if (body.ref.is_static) continue;
      for (const Collider& st : colliders) {
        if (!st.ref.is_static) continue;
        if (contact(*body.shape, body.xf, *st.shape, st.xf).touching()) {
          expected.emplace_back(body.ref.key(), st.ref.key());
        }
      }
    }
    std::vector<std::pair<std::uint64_t, std::uint64_t>> got;
    for (const Contact& c : world.contacts()) {
      if (c.b.is_static) got.emplace_back(c.a.key(), c.b.key());
    }
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    // Every touching pair is reported; the extra ones are impacts of fast bodies during the
    // step (reported in the step they happen, though the body bounced away).
    EXPECT_TRUE(std::includes(got.begin(), got.end(), expected.begin(), expected.end())) << s;
    EXPECT_LE(got.size() - expected.size(), std::size_t(world.last_step_stats().toi_hits)) << s;
    touching += expected.size();
  }
  EXPECT_GE(touching, 5u);  // pushed-out bodies end a step exactly touching their wall
}

// ---- Queries ---------------------------------------------------------------------------------

TEST(World2DQueries, RaycastFindsTheSameFirstHitAsBruteForce) {
  for (const bool stepped : {false, true}) {
    World2D world = random_scene({}, 120, 3u);
    if (stepped) world.step(kDt);
    const auto colliders = all_colliders(world);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> pos(-25.0f, 25.0f);
    int hits = 0;
    for (int i = 0; i < 400; ++i) {
      const Ray ray{{pos(rng), pos(rng)}, {pos(rng), pos(rng)}};
      float best = 2.0f;
      for (const Collider& c : colliders) {
        if (c.sensor) continue;
        const RayHit h = raycast(*c.shape, c.xf, ray);
        if (h.hit) best = std::min(best, h.fraction);
      }
      const auto got = world.raycast(ray);
      ASSERT_EQ(got.has_value(), best <= 1.0f) << "ray " << i;
      if (!got) continue;
      ++hits;
      EXPECT_EQ(got->hit.fraction, best);
      EXPECT_EQ(got->user_id, world.user_id(got->collider));
      // Statics only: bodies are skipped.
      const auto statics_only = world.raycast(ray, QueryFilter{.bodies = false});
      if (statics_only) EXPECT_TRUE(statics_only->collider.is_static);
    }
    EXPECT_GT(hits, 100);
  }
}

TEST(World2DQueries, PointAndBoxQueriesEqualBruteForce) {
  World2D world = random_scene({}, 150, 4u);
  world.step(kDt);
  const auto colliders = all_colliders(world);
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> pos(-22.0f, 22.0f), half(0.0f, 4.0f);
  for (int i = 0; i < 300; ++i) {
    const Vec2 p{pos(rng), pos(rng)};
    std::vector<std::uint64_t> expected, got;
    for (const Collider& c : colliders) {
      if (!c.sensor && overlap(Shape2D{make_circle(p, 0.0f)}, Transform{}, *c.shape, c.xf)) {
        expected.push_back(c.ref.key());
      }
    }
    world.query_point(p, {}, [&](const ColliderRef& c) {
      got.push_back(c.key());
      return true;
    });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << "point " << i;

    const Vec2 h{half(rng), half(rng)};
    const Aabb box{p - h, p + h};
    expected.clear();
    got.clear();
    const Shape2D box_shape = make_box(h + Vec2{1e-9f, 1e-9f});
    for (const Collider& c : colliders) {
      if (!c.sensor && overlap(box_shape, Transform::from(p, 0.0f), *c.shape, c.xf)) {
        expected.push_back(c.ref.key());
      }
    }
    world.query_aabb(box, {}, [&](const ColliderRef& c) {
      got.push_back(c.key());
      return true;
    });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << "box " << i;
  }
  // A callback that returns false stops the query.
  int calls = 0;
  world.query_aabb(Aabb{{-30, -30}, {30, 30}}, {}, [&](const ColliderRef&) { return ++calls < 3; });
  EXPECT_EQ(calls, 3);
}

TEST(World2DQueries, ShapeCastFindsTheEarliestTouchLikeBruteForce) {
  World2D world = random_scene({}, 80, 6u);
  world.step(kDt);
  const auto colliders = all_colliders(world);
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> pos(-19.0f, 19.0f), move(-15.0f, 15.0f);
  const Shape2D probe = make_capsule({-0.3f, 0}, {0.3f, 0}, 0.2f);
  int hits = 0;
  for (int i = 0; i < 200; ++i) {
    const Transform xf = Transform::from({pos(rng), pos(rng)}, pos(rng));
    const Vec2 translation{move(rng), move(rng)};
    float best = 2.0f;
    for (const Collider& c : colliders) {
      if (c.sensor) continue;
      const ShapeCastResult r = shape_cast(probe, xf, translation, *c.shape, c.xf, {0, 0});
      if (r.hit) best = std::min(best, r.fraction);
    }
    const WorldCastHit got = world.shape_cast(probe, xf, translation);
    ASSERT_EQ(got.hit, best <= 1.0f) << "cast " << i;
    if (!got.hit) continue;
    ++hits;
    EXPECT_EQ(got.fraction, best);
    EXPECT_NEAR(length(got.normal), 1.0f, 1e-3f);
  }
  EXPECT_GT(hits, 50);
  Transform nan_xf;
  nan_xf.p.y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW((void)world.shape_cast(probe, nan_xf, {1, 0}), InvalidInput);
}

TEST(World2DQueries, GroundCheckSeesTheFloorOnlyWhenStandingOnIt) {
  World2D world;
  world.add_static(box_static({0, -1}, {10, 1}, 5));
  const BodyId standing = world.add_body(box_body({0, 0.52f}, {0.5f, 0.5f}, {0, 0}));
  const BodyId flying = world.add_body(box_body({3, 2.0f}, {0.5f, 0.5f}, {0, 0}));
  const WorldCastHit ground = world.ground_check(standing, {0, -0.05f});
  ASSERT_TRUE(ground.hit);
  EXPECT_EQ(ground.user_id, 5u);
  EXPECT_TRUE(ground.collider.is_static);
  EXPECT_NEAR(ground.fraction, 0.4f, 0.02f);  // 0.02 of 0.05 to go
  EXPECT_NEAR(ground.normal.y, -1.0f, 1e-3f);
  EXPECT_NEAR(ground.point.y, 0.0f, 1e-2f);
  EXPECT_FALSE(world.ground_check(flying, {0, -0.05f}).hit);
  // It never reports the body itself, even though its own shape overlaps its cast.
  EXPECT_NE(world.ground_check(flying, {0, -2.0f}).collider.index, flying.index);
}

// The lesson's laser in a mirrored room: unfold the reflections and the path is a straight line,
// so the end point is the straight end point folded back into the room.
TEST(World2DQueries, LaserReflectsLikeTheUnfoldedStraightLine) {
  World2D world;
  add_room(world, 5.0f);
  const auto fold = [](float v) {
    float u = std::fmod(v + 5.0f, 20.0f);
    if (u < 0) u += 20.0f;
    return (u > 10.0f ? 20.0f - u : u) - 5.0f;
  };
  const Vec2 dir = normalize(Vec2{1.0f, 0.5f});
  const Ray ray{{0, 0}, 100.0f * dir};
  const LaserPath path = world.cast_laser(ray, kMaxLaserBounces);
  // 9 crossings of x = +-5 (every 10 units of x up to 89.4), 4 of y = +-5 (up to 44.7).
  EXPECT_EQ(path.segments, 14);
  EXPECT_EQ(path.hit_count, 13);
  const Vec2 end = path.points[std::size_t(path.segments)];
  EXPECT_NEAR(end.x, fold(ray.translation.x), 1e-2f);
  EXPECT_NEAR(end.y, fold(ray.translation.y), 1e-2f);
  float total = 0.0f;
  for (int i = 0; i < path.segments; ++i) total += length(path.points[i + 1] - path.points[i]);
  EXPECT_NEAR(total, 100.0f, 1e-2f);
  for (int i = 0; i < path.hit_count; ++i) {
    const Vec2 p = path.hits[std::size_t(i)].hit.point;
    EXPECT_NEAR(std::max(std::fabs(p.x), std::fabs(p.y)), 5.0f, 1e-3f);
    // Angle of incidence equals angle of reflection.
    const Vec2 in = normalize(path.points[i + 1] - path.points[i]);
    const Vec2 out = normalize(path.points[i + 2] - path.points[i + 1]);
    const Vec2 n = path.hits[std::size_t(i)].hit.normal;
    EXPECT_NEAR(dot(out, n), -dot(in, n), 1e-3f);
  }
  const LaserPath short_path = world.cast_laser(ray, 2);
  EXPECT_EQ(short_path.segments, 3);
  EXPECT_EQ(short_path.hit_count, 3);  // the last segment ends on a wall, not out of length
  EXPECT_THROW((void)world.cast_laser(ray, kMaxLaserBounces + 1), InvalidInput);
}

// The static clearance in 2D (world.cpp's Body::clearance, one home for both dimensions): a
// circle drifting towards a wall begins touching on the analytic step after skipped steps, and
// a static added beside a circle that was clear of the others is met on the next step.
TEST(World2DStep, StaticClearanceNeverSkipsAContact) {
  World2D world;
  add_room(world, 10.0f);  // inner walls at x = +-10
  const float radius = 0.5f, speed = 1.3f, start = 6.0f;
  const int expected = static_cast<int>(std::ceil((10.0f - radius - start) / (speed * kDt)));
  ASSERT_GT(10.0f - radius - (start + speed * kDt * static_cast<float>(expected - 1)), 1e-3f);
  const BodyId ball = world.add_body(circle_body({start, 0.0f}, radius, {speed, 0.0f}, 5));
  int begin_step = -1;
  for (int k = 1; k <= expected + 5 && begin_step < 0; ++k) {
    world.step(kDt);
    for (const ContactEvent& e : world.events()) {
      if (e.type == ContactEventType::begin) begin_step = k;
    }
  }
  EXPECT_EQ(begin_step, expected);
  EXPECT_GT(world.total_stats().static_clear_skips, expected / 2);

  World2D open;
  add_room(open, 10.0f);
  const BodyId b = open.add_body(circle_body({0.0f, 0.0f}, radius, {0.1f, 0.0f}));
  for (int k = 0; k < 10; ++k) open.step(kDt);
  ASSERT_GT(open.total_stats().static_clear_skips, 5);
  open.add_static(box_static(open.transform(b).p + Vec2(0.0f, 0.9f), {0.5f, 0.5f}, 9));
  open.step(kDt);
  bool met = false;
  for (const ContactEvent& e : open.events()) met = met || (e.type == ContactEventType::begin && e.user_b == 9u);
  EXPECT_TRUE(met);
  (void)ball;
}

// ---- Early out -------------------------------------------------------------------------------

TEST(World2DEarlyOut, ChainsLearnAndReportWithoutChangingResults) {
  World2D world = random_scene({}, 300, 8u);
  for (int s = 0; s < 100; ++s) world.step(kDt);
  const auto reports = world.early_out_reports();
  const auto orders = world.early_out_orders();
  // Bodies in free space skip the static chain while within their static clearance.
  EXPECT_GT(world.total_stats().static_clear_skips, 0);
  for (int c = 0; c < 2; ++c) {
    EXPECT_GT(reports[std::size_t(c)].evaluations, 500u) << "chain " << c;
    EXPECT_GT(reports[std::size_t(c)].rejections, 0u);
    auto order = orders[std::size_t(c)];
    std::sort(order.begin(), order.end());
    EXPECT_EQ(order, (std::array<int, 3>{0, 1, 2}));
  }
  // Every candidate pair went through its chain exactly once.
  const StepStats& t = world.total_stats();
  EXPECT_EQ(reports[0].evaluations, std::uint64_t(t.static_candidates));
  EXPECT_EQ(reports[1].evaluations, std::uint64_t(t.body_pairs));
  EXPECT_LE(t.filtered + t.aabb_rejected + t.pretest_rejected,
            std::int64_t(reports[0].rejections + reports[1].rejections));
  // What the choices saved is measured on sampled pairs (every 97th evaluation replayed through
  // both orders), and the decision's inputs are visible: costs >= 0, pass rates in [0, 1].
  const auto stats = world.early_out_check_stats();
  for (int c = 0; c < 2; ++c) {
    const CheckChainReport& r = reports[std::size_t(c)];
    EXPECT_EQ(r.sampled_pairs, r.evaluations / 97) << "chain " << c;
    EXPECT_GT(r.sampled_fixed_order_cost, 0.0);
    EXPECT_GT(r.sampled_cost, 0.0);
    for (const CheckStats& s : stats[std::size_t(c)]) {
      EXPECT_GE(s.cost, 0.0);
      EXPECT_GE(s.pass_rate, 0.0);
      EXPECT_LE(s.pass_rate, 1.0);
    }
  }
  // The filter never rejects a body-static pair here (every body sees the world's layer), and
  // the chain knows it: its unconditional pass rate is 1.
  EXPECT_DOUBLE_EQ(stats[0][0].pass_rate, 1.0);
}

}  // namespace
}  // namespace collide
