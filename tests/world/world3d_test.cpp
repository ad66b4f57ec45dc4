// World3D: the step pipeline (motion, continuous collision against convex statics and level
// meshes, push-out, body pairs, events), the queries and the independent check, each checked
// against an analytic answer or a brute-force pass over every collider (a level's triangles one
// by one) with the library's pairwise functions.
#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/debug_draw.hpp>
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include "support/body_churn.hpp"
#include "support/random.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr float kTol = 1e-4f;  // float noise on unit-size geometry

using test::random_rotation;
using test::uniform;

/// A closed box room [-half, half]^3 as one mesh of 12 triangles, its faces looking inside.
std::shared_ptr<const TriangleMesh> room_mesh(float half) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.push_back({(i & 1) ? half : -half, (i & 2) ? half : -half, (i & 4) ? half : -half});
  const std::vector<glm::uvec3> t{{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                                  {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  return std::make_shared<const TriangleMesh>(make_triangle_mesh(v, t));
}

/// A flat square floor y = 0 of half size `half`, as two triangles.
std::shared_ptr<const TriangleMesh> floor_mesh(float half) {
  const std::vector<Vec3> v{{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
  const std::vector<glm::uvec3> t{{0, 2, 1}, {0, 3, 2}};
  return std::make_shared<const TriangleMesh>(make_triangle_mesh(v, t));
}

Shape3D random_shape(std::mt19937& rng, float size) {
  switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0: return make_sphere(Vec3(0.0f), uniform(rng, 0.5f, 1.0f) * size);
    case 1: return make_capsule(Vec3(0, -0.5f * size, 0), Vec3(0, 0.5f * size, 0), 0.4f * size);
    case 2: return make_box(Vec3(uniform(rng, 0.4f, 1.0f), uniform(rng, 0.4f, 1.0f), uniform(rng, 0.4f, 1.0f)) * size);
    default: {
      std::vector<Vec3> points;
      for (int i = 0; i < 12; ++i) points.push_back(size * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)));
      return make_convex_hull(points);
    }
  }
}

/// `count` bodies of mixed shapes at random places inside [-spread, spread]^3, turning, at up to
/// `speed`; each 8th one a bullet.
void add_random_bodies(World3D& world, int count, float spread, float size, float speed, unsigned seed) {
  std::mt19937 rng(seed);
  for (int i = 0; i < count; ++i) {
    BodyDef3 def;
    def.shapes = {random_shape(rng, size)};
    def.transform = Transform3{Vec3(uniform(rng, -spread, spread), uniform(rng, -spread, spread), uniform(rng, -spread, spread)),
                               random_rotation(rng)};
    def.velocity = speed * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    def.angular_velocity = Vec3(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3));
    def.user_id = 100 + std::uint64_t(i);
    def.bullet = i % 8 == 0;
    world.add_body(def);
  }
}

/// Every static piece as triangles or convex shapes and every body piece, for brute force.
struct Candidate {
  ColliderRef ref;
  std::optional<Triangle> triangle;  ///< a level's triangle (world space), else a convex piece
};

std::vector<Candidate> all_candidates(const World3D& world) {
  std::vector<Candidate> out;
  const Aabb3 everything{Vec3(-1e6f), Vec3(1e6f)};
  for (int i = 0; i < world.static_count(); ++i) {
    const StaticDef3& def = world.static_def(StaticId{std::uint32_t(i)});
    for (std::size_t k = 0; k < def.shapes.size(); ++k) {
      const ColliderRef ref{true, std::uint32_t(i), std::uint16_t(k)};
      if (const auto* mesh = std::get_if<std::shared_ptr<const TriangleMesh>>(&def.shapes[k])) {
        for_each_triangle(**mesh, def.transform, everything, [&](std::uint32_t, const std::array<Vec3, 3>& c) {
          out.push_back({ref, Triangle{c}});
          return true;
        });
      } else if (const auto* field = std::get_if<std::shared_ptr<const HeightField>>(&def.shapes[k])) {
        for_each_triangle(**field, def.transform, everything, [&](std::uint32_t, const std::array<Vec3, 3>& c) {
          out.push_back({ref, Triangle{c}});
          return true;
        });
      } else {
        out.push_back({ref, std::nullopt});
      }
    }
  }
  for (const BodyId id : world.body_ids()) {
    for (std::size_t k = 0; k < world.shapes(id).size(); ++k) out.push_back({{false, id.index, std::uint16_t(k)}, std::nullopt});
  }
  return out;
}

/// A convex static piece as a Shape3D (the convex alternatives of StaticShape3D).
Shape3D convex_piece(const StaticShape3D& s) {
  return std::visit(
      [](const auto& x) -> Shape3D {
        using S = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<S, std::shared_ptr<const TriangleMesh>> ||
                      std::is_same_v<S, std::shared_ptr<const HeightField>>) {
          ADD_FAILURE() << "a level shape is not convex";
          return Sphere{};
        } else {
          return x;
        }
      },
      s);
}

// ---- input ---------------------------------------------------------------------------------

TEST(World3DInput, RejectsBadDefinitionsNamingTheField) {
  World3D world;
  StaticDef3 null_level;
  null_level.shapes = {std::shared_ptr<const TriangleMesh>{}};
  try {
    world.add_static(null_level);
    FAIL() << "a null level shape was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("static 0 shapes[0]: null level shape"), std::string::npos) << e.what();
  }
  EXPECT_THROW(world.add_static(StaticDef3{}), InvalidInput);  // no shapes
  BodyDef3 bad;
  bad.shapes = {make_sphere(Vec3(0.0f), 1.0f)};
  bad.transform.q = Quat{2.0f, 0.0f, 0.0f, 0.0f};
  EXPECT_THROW(world.add_body(bad), InvalidInput);  // not a unit quaternion
  bad.transform = Transform3{Vec3(0.0f, 3e9f, 0.0f)};
  try {
    world.add_body(bad);
    FAIL() << "a body beyond the coordinate range was accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("kMaxWorldCoordinate"), std::string::npos) << e.what();
  }
  bad.transform = Transform3{};
  bad.angular_velocity = Vec3(0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f);
  EXPECT_THROW(world.add_body(bad), InvalidInput);
  bad.angular_velocity = Vec3(0.0f, 2.0f * kMaxWorldAngularSpeed, 0.0f);
  EXPECT_THROW(world.add_body(bad), InvalidInput);
  bad.angular_velocity = Vec3(0.0f);
  EXPECT_NO_THROW(world.add_body(bad));
  EXPECT_THROW(world.step(-1.0f), InvalidInput);
  EXPECT_THROW(World3D(WorldOptions3{.gravity = Vec3(0, std::numeric_limits<float>::infinity(), 0)}), InvalidInput);
}

TEST(World3DInput, RemovedBodiesShapeSlotsServeNewBodiesWithTheirOwnShapes) {
  // The world keeps every body's shapes in one pool, a removed body's slots serving the next
  // body with as many shapes. Hulls hold their vertices, faces and edges in heap arrays: each
  // live body reads back exactly its own (and the sanitize preset sees no leak or double free
  // when the slots are released and reused).
  const auto hull = [](int i) {
    const float s = 0.3f + 0.05f * static_cast<float>(i % 5);
    std::vector<Vec3> points;
    for (int k = 0; k < 8; ++k) {
      points.push_back({(k & 1) != 0 ? s : -s, (k & 2) != 0 ? 0.5f * s : -0.5f * s, (k & 4) != 0 ? s : -0.7f * s});
    }
    points.push_back({0.0f, s + 0.1f * static_cast<float>(i % 3), 0.0f});  // a roof: 9 vertices
    return make_convex_hull(points);
  };
  const auto def = [&](int i) {
    BodyDef3 d;
    d.transform = Transform3{Vec3(static_cast<float>(i % 10) * 3.0f, 0.0f, static_cast<float>(i / 10) * 3.0f)};
    switch (i % 3) {
      case 0: d.shapes = {hull(i)}; break;
      case 1: d.shapes = {make_sphere(Vec3(0.0f), 0.2f + 0.01f * static_cast<float>(i))}; break;
      default: d.shapes = {hull(i), make_sphere(Vec3(0.0f, 0.8f, 0.0f), 0.3f)}; break;
    }
    return d;
  };
  World3D world;
  const test::BodyChurn churn = test::churn_bodies(world, def, 45, 2, 80);  // 23 slots reused
  test::expect_churned_shapes(world, churn, def, [](const Shape3D& a, const Shape3D& b) {
    if (a.index() != b.index()) return false;
    if (const auto* h = std::get_if<ConvexHull>(&a)) {
      const auto& g = std::get<ConvexHull>(b);
      return h->vertices == g.vertices && h->faces.size() == g.faces.size() && h->edges.size() == g.edges.size();
    }
    const auto& sa = std::get<Sphere>(a);
    const auto& sb = std::get<Sphere>(b);
    return sa.center == sb.center && sa.radius == sb.radius;
  });
  world.step(1.0f / 60.0f);
  EXPECT_EQ(world.body_count(), 57);
}

// ---- the step --------------------------------------------------------------------------------

TEST(World3DStep, FreeBodiesMoveAndTurnByTheirVelocities) {
  World3D world;
  BodyDef3 def;
  def.shapes = {make_box(Vec3(1.0f, 0.5f, 0.25f))};
  def.velocity = Vec3(1.0f, 2.0f, -3.0f);
  def.angular_velocity = Vec3(0.0f, 0.0f, 1.5f);  // about z, right-handed
  const BodyId id = world.add_body(def);
  world.step(0.5f);
  const Transform3& xf = world.transform(id);
  EXPECT_NEAR(xf.p.x, 0.5f, kTol);
  EXPECT_NEAR(xf.p.y, 1.0f, kTol);
  EXPECT_NEAR(xf.p.z, -1.5f, kTol);
  // The local x axis turned by 0.75 rad about z.
  const Vec3 x = rotate(xf.q, Vec3(1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(x.x, std::cos(0.75f), kTol);
  EXPECT_NEAR(x.y, std::sin(0.75f), kTol);
  EXPECT_NEAR(std::fabs(length(xf.q) - 1.0f), 0.0f, 1e-6f);
}

TEST(World3DStep, BallBouncesOffAFloorMeshWithEventsNamingItsTriangle) {
  World3D world;
  world.add_static({.shapes = {floor_mesh(5.0f)}, .user_id = 1});
  const BodyId ball = world.add_body({.shapes = {make_sphere(Vec3(0.0f), 0.5f)},
                                      .transform = Transform3{Vec3(0.3f, 2.0f, 0.2f)},
                                      .velocity = Vec3(0.0f, -3.0f, 0.0f), .user_id = 7});
  int begins = 0, ends = 0;
  float lowest = 10.0f;
  for (int i = 0; i < 120; ++i) {
    world.step(1.0f / 30.0f);
    lowest = std::min(lowest, world.transform(ball).p.y);
    for (const ContactEvent3& e : world.events()) {
      EXPECT_EQ(e.user_a, 7u);
      EXPECT_EQ(e.user_b, 1u);
      if (e.type == ContactEventType::begin) {
        ++begins;
        ASSERT_GT(e.manifold.count, 0);
        EXPECT_NEAR(e.manifold.normal.y, -1.0f, kTol);  // from the ball to the floor
        // The floor's feature is a triangle of the mesh (its face, or an edge or vertex of it).
        const ContactId id = e.manifold.points[0].id;
        if (id.type_b == FeatureType::face) EXPECT_LT(id.index_b, 2u);
      }
      if (e.type == ContactEventType::end) ++ends;
    }
    ASSERT_EQ(world.last_step_stats().tunnelled, 0);
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(ends, 1);
  EXPECT_GE(lowest, 0.5f - 1e-3f);           // never through the floor
  EXPECT_GT(world.velocity(ball).y, 2.9f);   // bounced: going up at the speed it came down
}

// World3D::draw and draw_laser through DebugDraw3: the level's triangles, each body's solid in
// its role, and one point per contact point and one normal arrow per touching pair of the last
// step; the laser's segments and hits.
TEST(World3DDraw, DrawsTheLevelBodiesContactsAndLaser) {
  struct Counter final : DebugDraw3 {
    std::map<DrawRole, int> triangles, segments, arrows, points;
    void draw_triangle(const Vec3&, const Vec3&, const Vec3&, DrawRole r) override { ++triangles[r]; }
    void draw_segment(const Vec3&, const Vec3&, DrawRole r) override { ++segments[r]; }
    void draw_arrow(const Vec3& from, const Vec3& to, DrawRole r) override {
      ++arrows[r];
      EXPECT_NEAR(length(to - from), 0.25f, 1e-4f);  // WorldDrawOptions::normal_length
    }
    void draw_point(const Vec3&, DrawRole r) override { ++points[r]; }
  };
  World3D world;
  world.add_static({.shapes = {floor_mesh(5.0f)}, .user_id = 1});
  world.add_static({.shapes = {make_box(Vec3(0.5f))}, .transform = Transform3{Vec3(3.0f, 0.5f, 0.0f)}});
  world.add_body({.shapes = {make_sphere(Vec3(0.0f), 0.5f)}, .transform = Transform3{Vec3(0.0f, 0.45f, 0.0f)}});
  world.add_body({.shapes = {make_box(Vec3(0.3f))}, .transform = Transform3{Vec3(-2.0f, 2.0f, 0.0f)},
                  .velocity = Vec3(0.0f, 0.0f, 1.0f), .bullet = true});
  world.step(kDt);
  ASSERT_GT(world.contacts().size(), 0u);
  int points = 0, pairs = 0;
  for (const Contact3& c : world.contacts()) {
    points += c.manifold.count;
    pairs += c.manifold.count > 0 ? 1 : 0;
  }
  Counter draw;
  world.draw(draw, WorldDrawOptions{.normal_length = 0.25f});
  EXPECT_EQ(draw.triangles[DrawRole::static_geometry], 2 + 12);  // the floor mesh and the box
  EXPECT_GT(draw.triangles[DrawRole::body], 12);                  // the sphere, tessellated
  EXPECT_EQ(draw.triangles[DrawRole::fast_body], 12);             // the bullet box
  EXPECT_EQ(draw.points[DrawRole::contact_point], points);
  EXPECT_EQ(draw.arrows[DrawRole::contact_normal], pairs);
  Counter none;
  world.draw(none, WorldDrawOptions{.statics = false, .bodies = false, .contacts = false});
  EXPECT_TRUE(none.triangles.empty() && none.points.empty() && none.arrows.empty());
  const LaserPath3 laser = world.cast_laser(Ray3{Vec3(-4.0f, 3.0f, 0.0f), Vec3(6.0f, -4.0f, 0.0f)}, 4, QueryFilter{.bodies = false});
  ASSERT_GT(laser.hit_count, 0);
  Counter l;
  World3D::draw_laser(l, laser);
  EXPECT_EQ(l.segments[DrawRole::laser], laser.segments);
  EXPECT_EQ(l.points[DrawRole::laser_hit], laser.hit_count);
}

TEST(World3DStep, GravityPullsAndTheFloorHoldsBodiesUp) {
  World3D world(WorldOptions3{.gravity = Vec3(0.0f, -9.81f, 0.0f)});
  world.add_static({.shapes = {floor_mesh(20.0f)}});
  std::mt19937 rng(3);
  std::vector<BodyId> ids;
  for (int i = 0; i < 30; ++i) {
    ids.push_back(world.add_body({.shapes = {random_shape(rng, 0.3f)},
                                  .transform = Transform3{Vec3(uniform(rng, -8, 8), uniform(rng, 1, 5), uniform(rng, -8, 8)), random_rotation(rng)}}));
  }
  for (int i = 0; i < 300; ++i) {
    world.step(kDt);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << i;
  }
  // Every body is above the floor (its box's bottom within the contact tolerance), none fell
  // through, and something touched the floor.
  for (const BodyId id : ids) {
    const Aabb3 box = compute_aabb(world.shapes(id)[0], world.transform(id));
    EXPECT_GT(box.min.y, -0.05f);
  }
  EXPECT_GT(world.total_stats().begin_events, 0);
}

TEST(World3DStep, FastBodiesNeverLeaveAClosedRoomMesh) {
  // Bodies at 500 units/s in a room 10 units across: several bounces per step, only continuous
  // collision keeps them in.
  const float half = 5.0f;
  World3D world(WorldOptions3{.bounds = Aabb3{Vec3(-half), Vec3(half)}});
  world.add_static({.shapes = {room_mesh(half)}, .user_id = 1});
  add_random_bodies(world, 40, 3.0f, 0.2f, 500.0f, 11);
  for (int i = 0; i < 240; ++i) {
    world.step(kDt);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << i;
    ASSERT_EQ(world.last_step_stats().escaped, 0) << "step " << i;
  }
  EXPECT_GT(world.total_stats().toi_hits, 100);
  for (const BodyId id : world.body_ids()) {
    const Vec3 p = world.transform(id).p;
    EXPECT_LT(max_abs(p), half) << "body " << id.index;
  }
}

// A spinning body that hits a wall every step keeps a unit orientation: each step's sweep starts
// from the last pose, and without renormalising at the hit |q|^2 drifted to 1 - 1.7e-5 in 3 s,
// which put a wall 20 units out 7e-4 off in the body's frame (a box went through it). A
// transform the caller gives within is_valid's allowance is kept renormalised too.
TEST(World3DStep, OrientationsStayUnitThroughHitsEveryStep) {
  const float half = 3.0f;
  World3D world(WorldOptions3{.bounds = Aabb3{Vec3(-half), Vec3(half)}});
  world.add_static({.shapes = {room_mesh(half)}, .user_id = 1});
  const Quat off_unit = Quat{1.0f, 0.0f, 0.0f, 0.0f} * std::sqrt(1.0f - 5e-4f);  // |q|^2 = 1 - 5e-4: valid
  ASSERT_TRUE(is_valid(Transform3{Vec3(0.0f), off_unit}));
  std::vector<BodyId> ids;
  for (int i = 0; i < 8; ++i) {
    ids.push_back(world.add_body({.shapes = {make_box(Vec3(0.3f, 0.2f, 0.25f))},
                                  .transform = Transform3{Vec3(-2.0f + 0.5f * static_cast<float>(i), 0.0f, 0.0f), off_unit},
                                  .velocity = Vec3(400.0f, 230.0f, -310.0f + 20.0f * static_cast<float>(i)),
                                  .angular_velocity = Vec3(7.0f, -11.0f, 5.0f),
                                  .bullet = true}));
  }
  for (const BodyId id : ids) EXPECT_NEAR(glm::length(world.transform(id).q), 1.0f, 1e-6f);
  for (int step = 0; step < 600; ++step) {
    world.step(kDt);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << step;
    ASSERT_EQ(world.last_step_stats().escaped, 0) << "step " << step;
  }
  EXPECT_GT(world.total_stats().toi_hits, 8 * 600);  // every body hits a wall every step, or more
  for (const BodyId id : ids) EXPECT_NEAR(glm::length(world.transform(id).q), 1.0f, 1e-6f) << id.index;
  world.set_transform(ids[0], Transform3{Vec3(0.0f), off_unit});
  EXPECT_NEAR(glm::length(world.transform(ids[0]).q), 1.0f, 1e-6f);
}

TEST(World3DStep, BodiesOnAHeightFieldStayAboveTheTerrain) {
  constexpr int n = 33;
  std::vector<float> heights;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) heights.push_back(1.5f * std::sin(0.35f * i) * std::cos(0.3f * j));
  }
  auto field = std::make_shared<const HeightField>(make_height_field(n, n, heights, Vec2(1.0f), Vec3(-16.0f, 0.0f, -16.0f)));
  World3D world(WorldOptions3{.gravity = Vec3(0.0f, -9.81f, 0.0f)});
  world.add_static({.shapes = {field}});
  std::mt19937 rng(5);
  std::vector<BodyId> ids;
  for (int i = 0; i < 40; ++i) {
    ids.push_back(world.add_body({.shapes = {random_shape(rng, 0.4f)},
                                  .transform = Transform3{Vec3(uniform(rng, -12, 12), uniform(rng, 3, 8), uniform(rng, -12, 12)), random_rotation(rng)},
                                  .velocity = Vec3(uniform(rng, -4, 4), uniform(rng, -20, 0), uniform(rng, -4, 4)),
                                  .bullet = i % 4 == 0}));
  }
  for (int i = 0; i < 240; ++i) {
    world.step(kDt);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << i;
  }
  // Each body's lowest point is above the terrain under its centre, within the contact slop.
  for (const BodyId id : ids) {
    const Vec3 c = world.transform(id).p;
    if (std::fabs(c.x) > 15.0f || std::fabs(c.z) > 15.0f) continue;  // rolled off the edge
    const auto down = raycast(*field, Transform3{}, Ray3{Vec3(c.x, 50.0f, c.z), Vec3(0.0f, -100.0f, 0.0f)});
    ASSERT_TRUE(down.hit);
    EXPECT_GT(c.y, down.point.y - 0.05f) << "body " << id.index;
  }
}

// The static clearance (a body's distance to every static, measured when it touched none, lets
// later steps skip its static contacts until it has moved that far) must never skip a contact:
// a sphere sinking slowly onto a mesh floor, a height field and a box begins touching on the
// step the analytic motion says, after many skipped steps; a static added next to a body that
// was clear of the others is met on the next step.
TEST(World3DStep, StaticClearanceNeverSkipsAContact) {
  const float radius = 0.5f, start = 3.0f, speed = 1.3f;
  // Centre height after k steps: start - speed k dt; touching once it is at most the radius.
  const int expected = static_cast<int>(std::ceil((start - radius) / (speed * kDt)));
  ASSERT_GT(start - speed * kDt * static_cast<float>(expected - 1) - radius, 1e-3f);  // clearly apart before
  std::vector<StaticShape3D> floors{floor_mesh(8.0f)};
  floors.push_back(std::make_shared<const HeightField>(
      make_height_field(17, 17, std::vector<float>(17 * 17, 0.0f), Vec2(1.0f), Vec3(-8.0f, 0.0f, -8.0f))));
  floors.push_back(make_box(Vec3(8.0f, 1.0f, 8.0f)));
  for (std::size_t f = 0; f < floors.size(); ++f) {
    World3D world;
    const bool is_box = f == 2;
    world.add_static({.shapes = {floors[f]}, .transform = Transform3{Vec3(0.0f, is_box ? -1.0f : 0.0f, 0.0f)}, .user_id = 1});
    const BodyId ball = world.add_body({.shapes = {make_sphere(Vec3(0.0f), radius)},
                                        .transform = Transform3{Vec3(0.2f, start, -0.1f)},
                                        .velocity = Vec3(0.0f, -speed, 0.0f)});
    int begin_step = -1;
    for (int k = 1; k <= expected + 5 && begin_step < 0; ++k) {
      world.step(kDt);
      for (const ContactEvent3& e : world.events()) {
        if (e.type == ContactEventType::begin) begin_step = k;
      }
    }
    EXPECT_EQ(begin_step, expected) << "floor " << f;
    EXPECT_GT(world.total_stats().static_clear_skips, expected / 2) << "floor " << f;  // it did skip
    (void)ball;
  }

  // A static added beside a body that is clear of the others.
  World3D world;
  world.add_static({.shapes = {floor_mesh(8.0f)}});
  const BodyId ball = world.add_body({.shapes = {make_sphere(Vec3(0.0f), radius)},
                                      .transform = Transform3{Vec3(0.0f, 4.0f, 0.0f)},
                                      .velocity = Vec3(0.1f, 0.0f, 0.0f)});
  for (int k = 0; k < 10; ++k) world.step(kDt);
  ASSERT_GT(world.total_stats().static_clear_skips, 5);
  world.add_static({.shapes = {make_box(Vec3(0.5f))}, .transform = Transform3{world.transform(ball).p + Vec3(0.0f, 0.0f, 0.9f)},
                    .user_id = 9});
  world.step(kDt);
  bool met = false;
  for (const ContactEvent3& e : world.events()) met = met || (e.type == ContactEventType::begin && e.user_b == 9u);
  EXPECT_TRUE(met);
}

TEST(World3DStep, EqualSpheresCollidingHeadOnSwapVelocities) {
  World3D world;
  const BodyId a = world.add_body({.shapes = {make_sphere(Vec3(0.0f), 0.5f)}, .transform = Transform3{Vec3(-2, 0, 0)}, .velocity = Vec3(3, 0, 0)});
  const BodyId b = world.add_body({.shapes = {make_sphere(Vec3(0.0f), 0.5f)}, .transform = Transform3{Vec3(2, 0, 0)}, .velocity = Vec3(-1, 0, 0)});
  for (int i = 0; i < 120; ++i) world.step(kDt);
  EXPECT_NEAR(world.velocity(a).x, -1.0f, kTol);
  EXPECT_NEAR(world.velocity(b).x, 3.0f, kTol);
}

// ---- determinism ------------------------------------------------------------------------------

TEST(World3DDeterminism, EveryBroadPhaseGivesTheSameStateBitForBit) {
  std::optional<std::uint64_t> reference;
  for (const WorldBroadPhase bp : {WorldBroadPhase::temporal, WorldBroadPhase::hierarchical_grid,
                                   WorldBroadPhase::sorted_grid, WorldBroadPhase::loose_grid,
                                   WorldBroadPhase::hash_grid, WorldBroadPhase::dynamic_tree,
                                   WorldBroadPhase::sweep_and_prune, WorldBroadPhase::brute_force}) {
    World3D world(WorldOptions3{.broad_phase = bp, .gravity = Vec3(0.0f, -5.0f, 0.0f)});
    world.add_static({.shapes = {room_mesh(6.0f)}});
    world.add_static({.shapes = {make_box(Vec3(1.0f, 2.0f, 1.0f))}, .transform = Transform3{Vec3(2, -4, 1)}});
    add_random_bodies(world, 120, 4.5f, 0.35f, 8.0f, 21);
    for (int i = 0; i < 90; ++i) world.step(kDt);
    EXPECT_EQ(world.total_stats().tunnelled, 0) << to_string(bp);
    EXPECT_GT(world.total_stats().body_pairs, 0) << to_string(bp);
    if (!reference) {
      reference = world.state_hash();
    } else {
      EXPECT_EQ(world.state_hash(), *reference) << to_string(bp);
    }
  }
}

// ---- queries -------------------------------------------------------------------------------

/// A world with a room mesh, convex statics and bodies, stepped once so the broad phase holds
/// the bodies' boxes.
World3D query_world() {
  World3D world;
  world.add_static({.shapes = {room_mesh(6.0f)}, .user_id = 1});
  world.add_static({.shapes = {make_box(Vec3(1.0f, 0.5f, 2.0f)), make_sphere(Vec3(0, 2, 0), 0.7f)},
                    .transform = Transform3{Vec3(-2, -3, 1), random_rotation(*std::make_unique<std::mt19937>(9))},
                    .user_id = 2});
  add_random_bodies(world, 25, 4.0f, 0.5f, 0.0f, 31);
  world.step(0.0f);
  return world;
}

TEST(World3DQueries, RaycastFindsTheSameFirstHitAsBruteForce) {
  const World3D world = query_world();
  const std::vector<Candidate> all = all_candidates(world);
  std::mt19937 rng(41);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const Vec3 o(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
    const Ray3 ray{o, 20.0f * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1))};
    float best = 2.0f;
    for (const Candidate& c : all) {
      const Transform3 xf = world.collider_transform(c.ref);
      const RayHit3 h = c.triangle   ? raycast(*c.triangle, Transform3{}, ray)
                        : c.ref.is_static ? raycast(convex_piece(world.static_shape(c.ref)), xf, ray)
                                          : raycast(world.body_shape(c.ref), xf, ray);
      if (h.hit) best = std::min(best, h.fraction);
    }
    const auto hit = world.raycast(ray);
    ASSERT_EQ(hit.has_value(), best <= 1.0f) << "ray " << i;
    if (hit) {
      ++hits;
      EXPECT_NEAR(hit->hit.fraction, best, kTol) << "ray " << i;
      EXPECT_NEAR(length(hit->hit.normal), 1.0f, kTol);
    }
  }
  EXPECT_GT(hits, 350);  // the room surrounds every origin
}

TEST(World3DQueries, PointAndBoxQueriesEqualBruteForce) {
  const World3D world = query_world();
  const std::vector<Candidate> all = all_candidates(world);
  std::mt19937 rng(43);
  int found = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 c(uniform(rng, -6, 6), uniform(rng, -6, 6), uniform(rng, -6, 6));
    const Vec3 half(uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f), uniform(rng, 0.0f, 1.0f));
    const Aabb3 box{c - half, c + half};
    const Box probe{half, 0.0f};
    const Transform3 at{c};
    std::vector<std::uint64_t> expected;
    for (const Candidate& k : all) {
      const Transform3 xf = world.collider_transform(k.ref);
      const bool touch = k.triangle       ? overlap(probe, at, *k.triangle, Transform3{})
                         : k.ref.is_static ? overlap(Shape3D(probe), at, convex_piece(world.static_shape(k.ref)), xf)
                                           : overlap(Shape3D(probe), at, world.body_shape(k.ref), xf);
      if (touch && (expected.empty() || expected.back() != k.ref.key())) expected.push_back(k.ref.key());
    }
    std::sort(expected.begin(), expected.end());
    expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
    std::vector<std::uint64_t> got;
    world.query_aabb(box, QueryFilter{}, [&](const ColliderRef& r) {
      got.push_back(r.key());
      return true;
    });
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, expected) << "box " << i;
    found += static_cast<int>(got.size());
  }
  EXPECT_GT(found, 50);
  // A point inside a body's shape picks it.
  const BodyId first = world.body_ids().front();
  const Vec3 centre = world.transform(first).p;
  bool picked = false;
  world.query_point(centre, QueryFilter{}, [&](const ColliderRef& r) {
    picked = picked || (!r.is_static && r.index == first.index);
    return true;
  });
  EXPECT_TRUE(picked);
}

TEST(World3DQueries, ShapeCastFindsTheEarliestTouchLikeBruteForce) {
  const World3D world = query_world();
  const std::vector<Candidate> all = all_candidates(world);
  std::mt19937 rng(47);
  for (int i = 0; i < 150; ++i) {
    const Shape3D shape = make_sphere(Vec3(0.0f), uniform(rng, 0.1f, 0.4f));
    const Transform3 xf{Vec3(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5))};
    const Vec3 v = 8.0f * Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    float best = 2.0f;
    for (const Candidate& c : all) {
      const Transform3 cx = world.collider_transform(c.ref);
      const ShapeCastResult3 r =
          c.triangle       ? shape_cast(std::get<Sphere>(shape), xf, v, *c.triangle, Transform3{}, Vec3(0.0f))
          : c.ref.is_static ? shape_cast(shape, xf, v, convex_piece(world.static_shape(c.ref)), cx, Vec3(0.0f))
                            : shape_cast(shape, xf, v, world.body_shape(c.ref), cx, Vec3(0.0f));
      if (r.hit) best = std::min(best, r.fraction);
    }
    const WorldCastHit3 hit = world.shape_cast(shape, xf, v);
    ASSERT_EQ(hit.hit, best <= 1.0f) << "cast " << i;
    if (hit.hit) EXPECT_NEAR(hit.fraction, best, 1e-3f) << "cast " << i;
  }
}

TEST(World3DQueries, LaserReflectsOffTheRoomWallsAtEqualAngles) {
  World3D world;
  world.add_static({.shapes = {room_mesh(5.0f)}});
  const Ray3 ray{Vec3(0.5f, -1.0f, 0.25f), 60.0f * normalize(Vec3(0.7f, 0.45f, -0.3f))};
  const LaserPath3 path = world.cast_laser(ray, 8);
  ASSERT_GE(path.hit_count, 4);
  float total = 0.0f;
  for (int i = 0; i < path.segments; ++i) total += distance(path.points[i], path.points[i + 1]);
  for (int i = 0; i + 1 < path.segments && i < path.hit_count; ++i) {
    const Vec3 in = normalize(path.points[i + 1] - path.points[i]);
    const Vec3 out = normalize(path.points[i + 2] - path.points[i + 1]);
    const Vec3 n = path.hits[i].hit.normal;
    EXPECT_NEAR(max_abs(path.points[i + 1]), 5.0f, 1e-3f);      // on a wall
    EXPECT_NEAR(dot(in, n), -dot(out, n), 1e-3f);               // angle of incidence = reflection
    EXPECT_LT(dot(in, n), 0.0f);                                 // the normal faces the laser
  }
  if (path.hit_count < path.segments) EXPECT_NEAR(total, length(ray.translation), 1e-2f);
}

TEST(World3DQueries, GroundCheckSeesTheFloorOnlyWhenStandingOnIt) {
  World3D world;
  world.add_static({.shapes = {floor_mesh(5.0f)}, .user_id = 3});
  const BodyId id = world.add_body({.shapes = {make_capsule(Vec3(0, -0.5f, 0), Vec3(0, 0.5f, 0), 0.3f)},
                                    .transform = Transform3{Vec3(1.0f, 0.81f, -1.0f)}});
  WorldCastHit3 g = world.ground_check(id, Vec3(0.0f, -0.05f, 0.0f));
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.user_id, 3u);
  EXPECT_NEAR(g.fraction, 0.2f, 1e-3f);          // 0.01 of the 0.05 down
  EXPECT_NEAR(g.normal.y, -1.0f, kTol);           // from the body to the ground
  world.set_transform(id, Transform3{Vec3(1.0f, 1.5f, -1.0f)});
  g = world.ground_check(id, Vec3(0.0f, -0.05f, 0.0f));
  EXPECT_FALSE(g.hit);
}

// ---- a real level -------------------------------------------------------------------------

TEST(World3DLevel, BodiesInDungeonObjNeverTunnel) {
  auto level = std::make_shared<const TriangleMesh>(
      io::load_triangle_mesh(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj"));
  World3D world(WorldOptions3{.gravity = Vec3(0.0f, -9.81f, 0.0f)});
  world.add_static({.shapes = {level}});
  // Bodies dropped from above the level's floor (a downward ray finds it), some fast.
  std::mt19937 rng(61);
  const Aabb3 box = compute_aabb(*level, Transform3{});
  int placed = 0;
  while (placed < 150) {
    const Vec3 p(uniform(rng, box.min.x, box.max.x), box.max.y + 1.0f, uniform(rng, box.min.z, box.max.z));
    const auto down = raycast(*level, Transform3{}, Ray3{p, Vec3(0.0f, -(box.max.y - box.min.y + 2.0f), 0.0f)});
    if (!down.hit) continue;
    const Vec3 at = down.point + Vec3(0.0f, uniform(rng, 0.8f, 2.0f), 0.0f);
    Shape3D s = random_shape(rng, 0.25f);
    if (overlap(s, Transform3{at}, *level, Transform3{})) continue;  // not inside a wall
    world.add_body({.shapes = {s}, .transform = Transform3{at, random_rotation(rng)},
                    .velocity = Vec3(uniform(rng, -6, 6), uniform(rng, -6, 6), uniform(rng, -6, 6)),
                    .bullet = placed % 5 == 0});
    ++placed;
  }
  // An oracle beside the world's own check: each step, each body's centre's move against every
  // triangle of the level (their boxes first), with the single-triangle ray cast. dungeon.obj
  // is an open level: bodies flying over its walls fall past its edges, which is no crossing.
  std::vector<Triangle> triangles;
  std::vector<Aabb3> boxes;
  for_each_triangle(*level, Transform3{}, Aabb3{Vec3(-1e6f), Vec3(1e6f)}, [&](std::uint32_t, const std::array<Vec3, 3>& c) {
    triangles.push_back(Triangle{c});
    boxes.push_back({glm::min(glm::min(c[0], c[1]), c[2]), glm::max(glm::max(c[0], c[1]), c[2])});
    return true;
  });
  std::vector<Vec3> before;
  for (const BodyId id : world.body_ids()) before.push_back(world.transform(id).p);
  int crossings = 0;
  for (int i = 0; i < 240; ++i) {
    world.step(kDt);
    ASSERT_EQ(world.last_step_stats().tunnelled, 0) << "step " << i;
    const std::vector<BodyId> ids = world.body_ids();
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const Vec3 now = world.transform(ids[k]).p;
      const Ray3 move{before[k], now - before[k]};
      const Aabb3 swept{glm::min(before[k], now), glm::max(before[k], now)};
      for (std::size_t t = 0; t < triangles.size(); ++t) {
        if (overlap(swept, boxes[t]) && raycast(triangles[t], Transform3{}, move).hit) {
          ++crossings;
          break;
        }
      }
      before[k] = now;
    }
  }
  EXPECT_EQ(crossings, 0);
  EXPECT_GT(world.total_stats().begin_events, 150);  // they did meet the level
}

}  // namespace
}  // namespace collide
