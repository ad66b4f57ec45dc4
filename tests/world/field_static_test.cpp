// A signed distance field as a static collider of World2D and World3D (StaticDefN::fields),
// checked against the same world with the exact shapes the field was built from as its
// statics: the independent truth. Each answer must agree within about a voxel (the field's own
// error); tunnelling must stay 0; runs are deterministic.
#include <collide/core/error.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/world/character.hpp>
#include <collide/world/world2d.hpp>
#include <collide/world/world3d.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <variant>
#include <vector>

namespace collide {
namespace {

constexpr float kDt = 1.0f / 60.0f;
constexpr float kVoxel = 0.05f;   // 2D fields
constexpr float kVoxel3 = 0.1f;   // 3D fields
constexpr int kFrames = 150;

// ---- the levels ------------------------------------------------------------------------------

/// The 2D level: a floor (top y = 0, x in [-10, 10]), a wall (x in [4, 4.5], y in [0, 4]) and a
/// round rock of radius 1 at (-4, 1.5).
std::vector<PlacedShape> level2() {
  return {{make_box({10.0f, 0.5f}), Transform::from({0.0f, -0.5f}, 0.0f)},
          {make_box({0.25f, 2.0f}), Transform::from({4.25f, 2.0f}, 0.0f)},
          {make_circle({0.0f, 0.0f}, 1.0f), Transform::from({-4.0f, 1.5f}, 0.0f)}};
}

/// The 3D level: a floor (top y = 0, x and z in [-5, 5]), a wall (x in [3, 3.4]) and a ball of
/// radius 1 at (-2.5, 1, 0).
std::vector<PlacedShape3> level3() {
  return {{make_box(Vec3(5.0f, 0.5f, 5.0f)), Transform3{Vec3(0.0f, -0.5f, 0.0f)}},
          {make_box(Vec3(0.2f, 1.5f, 5.0f)), Transform3{Vec3(3.2f, 1.5f, 0.0f)}},
          {make_sphere(Vec3(0.0f), 1.0f), Transform3{Vec3(-2.5f, 1.0f, 0.0f)}}};
}

FieldOptions options(float voxel) {
  FieldOptions o;
  o.voxel = voxel;
  return o;
}

/// Sparse fields: a band wider than the bodies' radii (0.4). Beyond the band a sparse field
/// holds +band, so a circle or sphere sampled at its centre would touch everywhere with a
/// narrower one (see the report: a limit of the field's `contact`).
FieldOptions sparse_options(float voxel) {
  FieldOptions o = options(voxel);
  o.band = 0.5f / voxel;
  return o;
}

/// A placed shape as a static piece (3D: the convex alternative of StaticShape3D).
Shape2D static_piece(const Shape2D& s) { return s; }
StaticShape3D static_piece(const Shape3D& s) {
  return std::visit([](const auto& x) -> StaticShape3D { return x; }, s);
}

/// The world with each placed shape as a static of its own (user ids 1, 2, 3).
template <int D>
void add_exact(WorldN<D>& world, const std::vector<PlacedShapeN<D>>& level) {
  for (std::size_t i = 0; i < level.size(); ++i) {
    StaticDefN<D> def;
    def.shapes = {static_piece(level[i].shape)};
    def.transform = level[i].xf;
    def.user_id = i + 1;
    world.add_static(def);
  }
}

/// The world with `field` as its only static (user id 7).
template <int D>
void add_field(WorldN<D>& world, StaticFieldN<D> field, TransformN<D> xf = {}) {
  StaticDefN<D> def;
  def.fields = {std::move(field)};
  def.transform = xf;
  def.user_id = 7;
  world.add_static(def);
}

WorldOptions gravity2() {
  WorldOptions o;
  o.gravity = {0.0f, -9.81f};
  return o;
}
WorldOptions3 gravity3() {
  WorldOptions3 o;
  o.gravity = Vec3(0.0f, -9.81f, 0.0f);
  return o;
}

/// What a run of a world records per body: its first contact with a static (normal from the
/// body, points) and its velocity at the end of that step (the bounce), and the end state.
template <int D>
struct Record {
  std::vector<ManifoldN<D>> first_contact;
  std::vector<VecN<D>> bounce;
  std::vector<VecN<D>> end;
  std::int64_t tunnelled = 0;
  std::uint64_t hash = 0;
};

template <int D>
Record<D> run(WorldN<D>& world, int frames) {
  const std::vector<BodyId> ids = world.body_ids();
  Record<D> r;
  r.first_contact.assign(ids.size(), ManifoldN<D>{});
  r.bounce.assign(ids.size(), VecN<D>(0.0f));
  for (int f = 0; f < frames; ++f) {
    world.step(kDt);
    for (const ContactN<D>& c : world.contacts()) {
      if (!c.b.is_static) continue;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        if (ids[i].index == c.a.index && !r.first_contact[i].touching()) {
          r.first_contact[i] = c.manifold;
          r.bounce[i] = world.velocity(ids[i]);
        }
      }
    }
  }
  for (const BodyId id : ids) r.end.push_back(world.transform(id).p);
  r.tunnelled = world.total_stats().tunnelled;
  r.hash = world.state_hash();
  return r;
}

/// The deepest point of a manifold.
template <int D>
VecN<D> deepest_point(const ManifoldN<D>& m) {
  int best = 0;
  for (int i = 1; i < m.count; ++i) {
    if (m.points[i].depth > m.points[best].depth) best = i;
  }
  return m.points[best].point;
}

/// Both runs agree per body on its first bounce: the static contact's normal within ~8 degrees,
/// its contact plane (the deepest point along the normal) within `tolerance`, the velocity
/// after the bounce as far from the exact one as the normals' difference explains (a normal
/// turned by a turns the reflected velocity by up to 2a: 2 sin a of its size, plus 2% for the
/// step the bounce falls in). Neither
/// run tunnels, and every body is still above the floor at the end.
template <int D>
void expect_runs_agree(const Record<D>& exact, const Record<D>& field, float tolerance, const char* what) {
  ASSERT_EQ(exact.first_contact.size(), field.first_contact.size());
  EXPECT_EQ(exact.tunnelled, 0);
  EXPECT_EQ(field.tunnelled, 0);
  float worst_angle = 0.0f, worst_plane = 0.0f, worst_bounce = 0.0f;
  for (std::size_t i = 0; i < exact.first_contact.size(); ++i) {
    const ManifoldN<D>& e = exact.first_contact[i];
    const ManifoldN<D>& f = field.first_contact[i];
    ASSERT_TRUE(e.touching()) << "body " << i;
    ASSERT_TRUE(f.touching()) << "body " << i;
    const float cosine = dot(f.normal, e.normal);
    const float plane = std::fabs(dot(deepest_point(f) - deepest_point(e), e.normal));
    const float bounce = distance(field.bounce[i], exact.bounce[i]) / length(exact.bounce[i]);
    EXPECT_GT(cosine, 0.99f) << "body " << i;
    EXPECT_LE(plane, tolerance) << "body " << i;
    EXPECT_LE(bounce, 2.0f * std::sqrt(std::max(1.0f - cosine * cosine, 0.0f)) + 0.02f) << "body " << i;
    EXPECT_GT(field.end[i][1], 0.0f) << "body " << i;
    EXPECT_GT(exact.end[i][1], 0.0f) << "body " << i;
    worst_angle = std::max(worst_angle, std::acos(std::min(cosine, 1.0f)) * 57.29578f);
    worst_plane = std::max(worst_plane, plane);
    worst_bounce = std::max(worst_bounce, bounce);
  }
  std::printf("%s: first contacts agree: normals within %.2f deg, planes within %.4f, bounce velocity within %.1f%%\n",
              what, worst_angle, worst_plane, 100.0f * worst_bounce);
}

BodyDef body2(Shape2D shape, Vec2 at, float angle = 0.0f) {
  BodyDef def;
  def.shapes = {std::move(shape)};
  def.transform = Transform::from(at, angle);
  return def;
}

BodyDef3 body3(Shape3D shape, Vec3 at, Quat q = Quat{1.0f, 0.0f, 0.0f, 0.0f}) {
  BodyDef3 def;
  def.shapes = {std::move(shape)};
  def.transform = Transform3{at, q};
  return def;
}

/// Bodies dropped onto the floor and the rock (one lands on its side), 2D.
void drop_bodies2(World2D& world) {
  world.add_body(body2(make_circle({0.0f, 0.0f}, 0.4f), {0.0f, 3.0f}));
  world.add_body(body2(make_box({0.3f, 0.3f}), {2.0f, 2.5f}));
  world.add_body(body2(make_box({0.5f, 0.2f}), {-1.5f, 3.5f}, 0.4f));
  world.add_body(body2(make_capsule({-0.3f, 0.0f}, {0.3f, 0.0f}, 0.2f), {-4.5f, 4.0f}));
}

void drop_bodies3(World3D& world) {
  world.add_body(body3(make_sphere(Vec3(0.0f), 0.4f), Vec3(0.0f, 3.0f, 0.0f)));
  world.add_body(body3(make_box(Vec3(0.3f)), Vec3(1.5f, 2.5f, 1.0f)));
  world.add_body(body3(make_box(Vec3(0.4f, 0.2f, 0.3f)), Vec3(0.5f, 3.5f, -2.0f),
                       glm::angleAxis(0.4f, glm::normalize(Vec3(1.0f, 0.0f, 1.0f)))));
  world.add_body(body3(make_capsule(Vec3(-0.3f, 0.0f, 0.0f), Vec3(0.3f, 0.0f, 0.0f), 0.2f), Vec3(-2.8f, 4.0f, 0.1f)));
}

// ---- 2D --------------------------------------------------------------------------------------

TEST(FieldStatic2D, DroppedBodiesBounceAsOffTheExactShapes) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact(gravity2()), sdf(gravity2());
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  drop_bodies2(exact);
  drop_bodies2(sdf);
  expect_runs_agree(run(exact, kFrames), run(sdf, kFrames), kVoxel, "2D dense");
}

TEST(FieldStatic2D, SparseFieldAgreesToo) {
  const auto field = std::make_shared<const SparseDistanceField>(make_sparse_distance_field(level2(), sparse_options(kVoxel)));
  World2D exact(gravity2()), sdf(gravity2());
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  drop_bodies2(exact);
  drop_bodies2(sdf);
  expect_runs_agree(run(exact, kFrames), run(sdf, kFrames), kVoxel, "2D sparse");
}

TEST(FieldStatic2D, RayCastsAndPointQueriesAgreeWithinAVoxel) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact, sdf;
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> x(-9.0f, 9.0f), y(0.2f, 6.0f), angle(0.0f, 6.2831853f);
  int hits = 0, both = 0, turned = 0, grazed = 0, rays = 400;
  float worst = 0.0f;
  for (int i = 0; i < rays; ++i) {
    const Vec2 origin{x(rng), y(rng)};
    const float a = angle(rng);
    const Ray ray{origin, 12.0f * Vec2{std::cos(a), std::sin(a)}};
    // (A ray starting in an exact shape leaves it and may hit another; the field is one solid
    // and reports no hit for a start inside it: the two are not comparable there.)
    bool inside = false;
    exact.query_point(origin, {}, [&](const ColliderRef&) { return !(inside = true); });
    if (inside) continue;
    const auto he = exact.raycast(ray);
    const auto hf = sdf.raycast(ray);
    hits += he.has_value();
    if (he.has_value() != hf.has_value()) {
      // Only a ray grazing a corner may disagree (the field rounds corners over a voxel): the
      // exact ray moved a voxel sideways either way answers otherwise.
      const Vec2 side = kVoxel * glm::normalize(Vec2{-ray.translation.y, ray.translation.x});
      const bool grazing = exact.raycast({origin + side, ray.translation}).has_value() != he.has_value() ||
                           exact.raycast({origin - side, ray.translation}).has_value() != he.has_value();
      const RayHit& h = he ? he->hit : hf->hit;
      EXPECT_TRUE(grazing) << "ray " << i << " hit in one world only at " << h.point.x << ", " << h.point.y;
      ++grazed;
      continue;
    }
    if (!he) continue;
    ++both;
    worst = std::max(worst, distance(he->hit.point, hf->hit.point));
    EXPECT_LE(distance(he->hit.point, hf->hit.point), kVoxel) << "ray " << i;
    turned += dot(he->hit.normal, hf->hit.normal) < 0.95f;
    EXPECT_EQ(hf->user_id, 7u);
  }
  EXPECT_GT(hits, rays / 4);  // the rays really meet the level
  // Normals agree within 18 degrees but near a corner, which the field rounds over a voxel.
  EXPECT_LE(turned, both / 20);
  EXPECT_LE(grazed, rays / 50);
  RecordProperty("worst_ray_point_error", std::to_string(worst));
  std::printf("2D rays: %d hits in both worlds, worst point error %.4f (voxel %.3f), %d normals off by > 18 deg, "
              "%d grazing a corner hit in one world only\n", both, worst, kVoxel, turned, grazed);
  // Point queries: inside the field iff inside an exact shape, a voxel away from the surface.
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p{x(rng), std::uniform_real_distribution<float>(-1.0f, 5.0f)(rng)};
    float nearest = 1e30f;
    for (const PlacedShape& s : level2()) nearest = std::min(nearest, std::fabs(closest_point(s.shape, s.xf, p).distance));
    if (nearest < kVoxel) continue;
    bool in_exact = false, in_field = false;
    exact.query_point(p, {}, [&](const ColliderRef&) { return !(in_exact = true); });
    sdf.query_point(p, {}, [&](const ColliderRef&) { return !(in_field = true); });
    EXPECT_EQ(in_exact, in_field) << p.x << ", " << p.y;
    checked += in_exact;
  }
  EXPECT_GT(checked, 100);
}

TEST(FieldStatic2D, AabbQueriesAgreeWithTheExactShapes) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact, sdf;
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  const auto finds = [](const World2D& w, const Aabb& box) {
    bool found = false;
    w.query_aabb(box, {}, [&](const ColliderRef&) { return !(found = true); });
    return found;
  };
  // A box around the whole rock, clear of the floor: no sample of the box's outline touches.
  EXPECT_TRUE(finds(sdf, Aabb{{-5.5f, 0.2f}, {-2.5f, 3.0f}}));
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> x(-9.0f, 9.0f), y(-0.5f, 5.0f), size(0.01f, 2.0f);
  int checked = 0, found = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec2 c{x(rng), y(rng)}, half{size(rng), size(rng)};
    const Aabb box{c - half, c + half};
    // Clear-cut cases only: the exact answer is the same for the box grown and shrunk by a voxel.
    const Vec2 v(kVoxel);
    const bool in = finds(exact, box);
    if (finds(exact, {box.min - v, box.max + v}) != in) continue;
    if (glm::all(glm::lessThan(box.min + v, box.max - v)) && finds(exact, {box.min + v, box.max - v}) != in) continue;
    EXPECT_EQ(finds(sdf, box), in) << "box " << i;
    ++checked;
    found += in;
  }
  EXPECT_GT(checked, 500);
  EXPECT_GT(found, 100);
  EXPECT_LT(found, checked - 100);
}

TEST(FieldStatic2D, ARotatedFieldIsPlacedByItsTransform) {
  // The level built at the origin and placed turned by 0.5 rad and moved, against the exact
  // shapes placed the same way.
  const Transform place = Transform::from({1.0f, 2.0f}, 0.5f);
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact, sdf;
  std::vector<PlacedShape> moved = level2();
  for (PlacedShape& s : moved) s.xf = mul(place, s.xf);
  add_exact(exact, moved);
  add_field<2>(sdf, field, place);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-8.0f, 8.0f);
  int both = 0;
  for (int i = 0; i < 200; ++i) {
    const Ray ray{transform_point(place, Vec2{u(rng), 6.0f}), rotate(place.q, Vec2{0.3f * u(rng), -8.0f})};
    const auto he = exact.raycast(ray);
    const auto hf = sdf.raycast(ray);
    ASSERT_EQ(he.has_value(), hf.has_value()) << "ray " << i;
    if (!he) continue;
    ++both;
    EXPECT_LE(distance(he->hit.point, hf->hit.point), kVoxel) << "ray " << i;
    EXPECT_GT(dot(he->hit.normal, hf->hit.normal), 0.95f) << "ray " << i;
  }
  EXPECT_GT(both, 100);
  // The broad phase box follows the placement: a pick at the rotated floor's middle finds it.
  bool found = false;
  sdf.query_point(transform_point(place, Vec2{0.0f, -0.5f}), {}, [&](const ColliderRef&) { return !(found = true); });
  EXPECT_TRUE(found);
}

TEST(FieldStatic2D, ABulletDoesNotTunnelThroughAThinWall) {
  // A wall 0.1 thick (two voxels) and a small circle crossing 3.3 units a step towards it.
  const std::vector<PlacedShape> wall{{make_box({0.05f, 3.0f}), Transform::from({5.0f, 0.0f}, 0.0f)}};
  const auto field = std::make_shared<const DistanceField>(make_distance_field(wall, options(kVoxel)));
  for (const bool bullet : {false, true}) {
    World2D world;
    add_field<2>(world, field);
    BodyDef def = body2(make_circle({0.0f, 0.0f}, 0.1f), {0.0f, 0.0f});
    def.velocity = {200.0f, 1.0f};
    def.bullet = bullet;
    const BodyId id = world.add_body(def);
    for (int f = 0; f < 20; ++f) world.step(kDt);
    EXPECT_LT(world.transform(id).p.x, 5.0f - 0.05f) << "bullet " << bullet;  // still on its side
    EXPECT_EQ(world.total_stats().tunnelled, 0);
    EXPECT_GT(world.total_stats().toi_hits, 0);
  }
}

TEST(FieldStatic2D, TheCheckCountsABodyWedgedInTheField) {
  // A circle of radius 0.5 in a gap 0.6 wide: no push-out frees it, and the independent check
  // counts it in both worlds, with the same depth within a voxel.
  const std::vector<PlacedShape> gap{{make_box({1.0f, 2.0f}), Transform::from({-1.3f, 0.0f}, 0.0f)},
                                     {make_box({1.0f, 2.0f}), Transform::from({1.3f, 0.0f}, 0.0f)}};
  World2D exact, sdf;
  add_exact(exact, gap);
  add_field<2>(sdf, std::make_shared<const DistanceField>(make_distance_field(gap, options(kVoxel))));
  for (World2D* w : {&exact, &sdf}) {
    w->add_body(body2(make_circle({0.0f, 0.0f}, 0.5f), {0.0f, 0.0f}));
    w->step(kDt);
  }
  EXPECT_EQ(exact.last_step_stats().tunnelled, 1);
  EXPECT_EQ(sdf.last_step_stats().tunnelled, 1);
  EXPECT_NEAR(sdf.last_step_stats().max_static_depth, exact.last_step_stats().max_static_depth, kVoxel);
}

TEST(FieldStatic2D, TheGroundCheckFindsTheFieldFloor) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact(gravity2()), sdf(gravity2());
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  for (World2D* w : {&exact, &sdf}) w->add_body(body2(make_box({0.3f, 0.3f}), {1.0f, 0.31f}));
  for (int f = 0; f < 30; ++f) {
    exact.step(kDt);
    sdf.step(kDt);
  }
  const BodyId id = sdf.body_ids()[0];
  const WorldCastHit g = sdf.ground_check(id, {0.0f, -0.05f});
  const WorldCastHit ge = exact.ground_check(exact.body_ids()[0], {0.0f, -0.05f});
  ASSERT_TRUE(ge.hit);
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.user_id, 7u);
  EXPECT_GT(dot(g.normal, Vec2{0.0f, -1.0f}), 0.99f);
  EXPECT_NEAR(g.point.y, ge.point.y, kVoxel);
  // Lifted clear of the floor by more than the cast, nothing is found.
  sdf.set_transform(id, Transform::from({1.0f, 0.5f}, 0.0f));
  EXPECT_FALSE(sdf.ground_check(id, {0.0f, -0.05f}).hit);
}

TEST(FieldStatic2D, TheCharacterStopsAtAFieldWallAsAtTheExactWall) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  World2D exact, sdf;
  add_exact(exact, level2());
  add_field<2>(sdf, field);
  const Shape2D capsule = make_capsule({0.0f, -0.5f}, {0.0f, 0.5f}, 0.3f);
  const CharacterSettings s;
  std::array<Transform, 2> end{};
  std::array<float, 2> deepest{};
  std::array<bool, 2> grounded{};
  const std::array<const World2D*, 2> worlds{&exact, &sdf};
  for (int w = 0; w < 2; ++w) {
    Transform xf = Transform::from({0.0f, 0.5f + 0.3f + s.skin}, 0.0f);
    for (int f = 0; f < 120; ++f) {
      const CharacterMove m = move_character(*worlds[w], capsule, xf, {3.0f * kDt, -0.02f}, s);
      xf = m.transform;
      grounded[w] = m.grounded;
      worlds[w]->collide_shape(capsule, xf, {}, [&](const ColliderRef&, const Manifold& c) {
        deepest[w] = std::max(deepest[w], c.max_depth());
        return true;
      });
    }
    end[w] = xf;
  }
  std::printf("2D character: stops at x = %.4f (exact) and %.4f (field)\n", end[0].p.x, end[1].p.x);
  EXPECT_LT(end[0].p.x, 4.0f - 0.3f);
  EXPECT_NEAR(end[1].p.x, end[0].p.x, kVoxel);
  EXPECT_NEAR(end[1].p.y, end[0].p.y, kVoxel);
  EXPECT_TRUE(grounded[1]);
  EXPECT_LE(deepest[1], kVoxel);  // never into the field's solid beyond its error
}

TEST(FieldStatic2D, RunsAreDeterministicAndTheFieldIsShared) {
  const auto field = std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel)));
  std::array<std::uint64_t, 2> hashes{};
  for (auto& h : hashes) {
    World2D sdf(gravity2());
    add_field<2>(sdf, field);
    drop_bodies2(sdf);
    h = run(sdf, 60).hash;
    // Shared, not copied: the world holds the same field.
    const auto& held = std::get<std::shared_ptr<const DistanceField>>(sdf.static_field({true, 0, 0}));
    EXPECT_EQ(held.get(), field.get());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(FieldStatic2D, RejectsANullFieldAFieldWithoutSolidAndShapeAccessToAField) {
  World2D world;
  StaticDef def;
  def.fields = {std::shared_ptr<const DistanceField>()};
  EXPECT_THROW(world.add_static(def), InvalidInput);
  // A field whose solid lies outside its grid has no node at or below 0.
  DistanceField empty = make_distance_field(level2(), options(kVoxel));
  std::fill(empty.distances.begin(), empty.distances.end(), 1.0f);
  def.fields = {std::make_shared<const DistanceField>(std::move(empty))};
  EXPECT_THROW(world.add_static(def), InvalidInput);
  add_field<2>(world, std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel))));
  EXPECT_THROW((void)world.static_shape({true, 0, 0}), InvalidInput);
  EXPECT_THROW((void)world.collider_shape({true, 0, 0}), InvalidInput);
  EXPECT_NO_THROW((void)world.static_field({true, 0, 0}));
  EXPECT_THROW((void)world.static_field({true, 0, 1}), InvalidInput);
  const BodyId body = world.add_body(body2(make_circle({0.0f, 0.0f}, 0.5f), {0.0f, 3.0f}));
  EXPECT_THROW((void)world.static_field({false, body.index, 0}), InvalidInput);
}

/// Records the segments a world draws.
struct Segments final : DebugDraw {
  std::vector<std::array<Vec2, 2>> segments;
  void draw_polygon(std::span<const Vec2>, float, DrawRole) override {}
  void draw_circle(Vec2, float, DrawRole) override {}
  void draw_capsule(Vec2, Vec2, float, DrawRole) override {}
  void draw_segment(Vec2 a, Vec2 b, DrawRole role) override {
    if (role == DrawRole::static_geometry) segments.push_back({a, b});
  }
  void draw_arrow(Vec2, Vec2, DrawRole) override {}
  void draw_point(Vec2, DrawRole) override {}
  void draw_label(Vec2, std::string_view, DrawRole) override {}
};

TEST(FieldStatic2D, DrawsTheZeroContourOnTheExactSurface) {
  const Transform place = Transform::from({1.0f, 2.0f}, 0.5f);
  World2D sdf;
  add_field<2>(sdf, std::make_shared<const DistanceField>(make_distance_field(level2(), options(kVoxel))), place);
  Segments draw;
  sdf.draw(draw);
  ASSERT_GT(draw.segments.size(), 500u);  // the outline's length over a voxel, about
  float worst = 0.0f;
  for (const auto& s : draw.segments) {
    for (const Vec2 p : s) {
      float nearest = 1e30f;
      for (const PlacedShape& shape : level2()) {
        nearest = std::min(nearest, std::fabs(closest_point(shape.shape, mul(place, shape.xf), p).distance));
      }
      worst = std::max(worst, nearest);
    }
  }
  EXPECT_LE(worst, 0.5f * kVoxel);
}

// ---- 3D --------------------------------------------------------------------------------------

TEST(FieldStatic3D, DroppedBodiesBounceAsOffTheExactShapes) {
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(level3(), options(kVoxel3)));
  World3D exact(gravity3()), sdf(gravity3());
  add_exact(exact, level3());
  add_field<3>(sdf, field);
  drop_bodies3(exact);
  drop_bodies3(sdf);
  expect_runs_agree(run(exact, kFrames), run(sdf, kFrames), kVoxel3, "3D dense");
}

TEST(FieldStatic3D, SparseFieldAgreesToo) {
  const auto field = std::make_shared<const SparseDistanceField3>(make_sparse_distance_field(level3(), sparse_options(kVoxel3)));
  World3D exact(gravity3()), sdf(gravity3());
  add_exact(exact, level3());
  add_field<3>(sdf, field);
  drop_bodies3(exact);
  drop_bodies3(sdf);
  expect_runs_agree(run(exact, kFrames), run(sdf, kFrames), kVoxel3, "3D sparse");
}

TEST(FieldStatic3D, RayCastsAgreeWithinAVoxel) {
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(level3(), options(kVoxel3)));
  World3D exact, sdf;
  add_exact(exact, level3());
  add_field<3>(sdf, field);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-4.5f, 4.5f), h(0.2f, 4.0f), d(-1.0f, 1.0f);
  int both = 0, turned = 0;
  float worst = 0.0f;
  const int rays = 300;
  for (int i = 0; i < rays; ++i) {
    const Vec3 origin{u(rng), h(rng), u(rng)};
    bool inside = false;  // (as in 2D: a start inside an exact shape is not comparable)
    exact.query_point(origin, {}, [&](const ColliderRef&) { return !(inside = true); });
    if (inside) continue;
    Vec3 dir{d(rng), d(rng) - 0.5f, d(rng)};
    if (length(dir) < 0.1f) continue;
    const Ray3 ray{origin, 10.0f * glm::normalize(dir)};
    const auto he = exact.raycast(ray);
    const auto hf = sdf.raycast(ray);
    if (he.has_value() != hf.has_value()) {
      ADD_FAILURE() << "ray " << i << " hit in one world only";
      continue;
    }
    if (!he) continue;
    ++both;
    worst = std::max(worst, distance(he->hit.point, hf->hit.point));
    EXPECT_LE(distance(he->hit.point, hf->hit.point), kVoxel3) << "ray " << i;
    turned += dot(he->hit.normal, hf->hit.normal) < 0.95f;
  }
  EXPECT_GT(both, rays / 4);
  EXPECT_LE(turned, both / 20);  // (corners, rounded by the field over a voxel)
  std::printf("3D rays: %d hits in both worlds, worst point error %.4f (voxel %.3f), %d normals off by > 18 deg\n",
              both, worst, kVoxel3, turned);
  // A laser reflected by the field's wall and floor follows the exact one.
  const Ray3 laser{Vec3(0.0f, 2.0f, 2.0f), Vec3(20.0f, -6.0f, 0.0f)};
  const LaserPath3 pe = exact.cast_laser(laser, 3);
  const LaserPath3 pf = sdf.cast_laser(laser, 3);
  ASSERT_EQ(pe.hit_count, pf.hit_count);
  ASSERT_GE(pf.hit_count, 2);
  for (int i = 0; i < pe.hit_count; ++i) EXPECT_LE(distance(pe.hits[i].hit.point, pf.hits[i].hit.point), kVoxel3);
}

TEST(FieldStatic3D, ABulletDoesNotTunnelThroughAThinWall) {
  const std::vector<PlacedShape3> wall{{make_box(Vec3(0.1f, 3.0f, 3.0f)), Transform3{Vec3(5.0f, 0.0f, 0.0f)}}};
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(wall, options(kVoxel3)));
  World3D world;
  add_field<3>(world, field);
  BodyDef3 def = body3(make_sphere(Vec3(0.0f), 0.1f), Vec3(0.0f));
  def.velocity = Vec3(300.0f, 2.0f, -1.0f);
  const BodyId id = world.add_body(def);
  for (int f = 0; f < 20; ++f) world.step(kDt);
  EXPECT_LT(world.transform(id).p.x, 5.0f - 0.1f);
  EXPECT_EQ(world.total_stats().tunnelled, 0);
  EXPECT_GT(world.total_stats().toi_hits, 0);
}

TEST(FieldStatic3D, TheGroundCheckFindsTheFieldFloor) {
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(level3(), options(kVoxel3)));
  World3D sdf(gravity3());
  add_field<3>(sdf, field);
  const BodyId id = sdf.add_body(body3(make_box(Vec3(0.3f)), Vec3(0.5f, 0.31f, 0.5f)));
  for (int f = 0; f < 30; ++f) sdf.step(kDt);
  const WorldCastHit3 g = sdf.ground_check(id, Vec3(0.0f, -0.05f, 0.0f));
  ASSERT_TRUE(g.hit);
  EXPECT_EQ(g.user_id, 7u);
  EXPECT_GT(dot(g.normal, Vec3(0.0f, -1.0f, 0.0f)), 0.99f);
  EXPECT_NEAR(g.point.y, 0.0f, kVoxel3);
  sdf.set_transform(id, Transform3{Vec3(0.5f, 0.6f, 0.5f)});
  EXPECT_FALSE(sdf.ground_check(id, Vec3(0.0f, -0.05f, 0.0f)).hit);
}

TEST(FieldStatic3D, TheCharacterStopsAtAFieldWallAsAtTheExactWall) {
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(level3(), options(kVoxel3)));
  World3D exact, sdf;
  add_exact(exact, level3());
  add_field<3>(sdf, field);
  const Shape3D capsule = make_capsule(Vec3(0.0f, -0.5f, 0.0f), Vec3(0.0f, 0.5f, 0.0f), 0.3f);
  const CharacterSettings3 s;
  std::array<Transform3, 2> end{};
  std::array<bool, 2> grounded{};
  const std::array<const World3D*, 2> worlds{&exact, &sdf};
  for (int w = 0; w < 2; ++w) {
    Transform3 xf{Vec3(0.0f, 0.5f + 0.3f + s.skin, 1.0f)};
    for (int f = 0; f < 90; ++f) {
      const CharacterMove3 m = move_character(*worlds[w], capsule, xf, Vec3(3.0f * kDt, -0.02f, 0.0f), s);
      xf = m.transform;
      grounded[w] = m.grounded;
    }
    end[w] = xf;
  }
  std::printf("3D character: stops at x = %.4f (exact) and %.4f (field)\n", end[0].p.x, end[1].p.x);
  EXPECT_LT(end[0].p.x, 3.0f - 0.3f);
  EXPECT_NEAR(end[1].p.x, end[0].p.x, kVoxel3);
  EXPECT_NEAR(end[1].p.y, end[0].p.y, kVoxel3);
  EXPECT_TRUE(grounded[1]);
}

TEST(FieldStatic3D, RunsAreDeterministic) {
  const auto field = std::make_shared<const DistanceField3>(make_distance_field(level3(), options(kVoxel3)));
  std::array<std::uint64_t, 2> hashes{};
  for (auto& h : hashes) {
    World3D sdf(gravity3());
    add_field<3>(sdf, field);
    drop_bodies3(sdf);
    h = run(sdf, 60).hash;
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

/// Records the segments a 3D world draws.
struct Segments3 final : DebugDraw3 {
  std::vector<std::array<Vec3, 2>> segments;
  void draw_triangle(const Vec3&, const Vec3&, const Vec3&, DrawRole) override {}
  void draw_segment(const Vec3& a, const Vec3& b, DrawRole role) override {
    if (role == DrawRole::static_geometry) segments.push_back({a, b});
  }
  void draw_arrow(const Vec3&, const Vec3&, DrawRole) override {}
  void draw_point(const Vec3&, DrawRole) override {}
};

TEST(FieldStatic3D, DrawsTheBoxOfTheSolid) {
  // The ball alone: its solid's box is the ball's box widened by at most a voxel.
  const std::vector<PlacedShape3> ball{{make_sphere(Vec3(0.0f), 1.0f), Transform3{Vec3(1.0f, 2.0f, 3.0f)}}};
  World3D sdf;
  add_field<3>(sdf, std::make_shared<const DistanceField3>(make_distance_field(ball, options(kVoxel3))));
  Segments3 draw;
  sdf.draw(draw);
  ASSERT_EQ(draw.segments.size(), 12u);
  for (const auto& s : draw.segments) {
    for (const Vec3& p : s) {
      const Vec3 offset = glm::abs(p - Vec3(1.0f, 2.0f, 3.0f));
      for (int k = 0; k < 3; ++k) EXPECT_LE(offset[k], 1.0f + kVoxel3 + 1e-4f);
      EXPECT_GE(std::max({offset.x, offset.y, offset.z}), 1.0f - 1e-4f);
    }
  }
}

}  // namespace
}  // namespace collide
