// A game's collision work per frame in 3D, collide against Jolt Physics in one run, over
// recast's dungeon.obj (a static level of 10k triangles: collide's TriangleMesh with its BVH,
// Jolt's MeshShape).
//
// BM_Step / BM_StepJolt (1e3 and 1e4 bodies): one step of moving bodies over the level.
//  - The bodies: mixed spheres, capsules, boxes and 12-point hulls, 1.5 times as large as
//    `collide run`'s on an OBJ level (kBodySizeFraction of the level's box diagonal: 0.78 units
//    on dungeon.obj, so that they meet more often), spawned at free places in the level's box
//    with random velocities and spins, slow enough that no body needs continuous collision
//    unless a collision pushed it (counter `ccd`: bodies per step), no gravity, dt 1/60 s.
//  - collide: World3D::step(dt) with the level as a static and the default temporal broad phase:
//    integrate, body-level contacts (statics' tree, early out, the merged level manifold with
//    active edges) with push-out and bounce, body-body pairs (temporal broad phase, early out,
//    contact manifold) with an elastic response, contact events. The world's independent
//    end-of-step check (WorldOptions3::check_each_step, a brute-force tunnelling test) is turned
//    off: it is a test harness, not collision work, and Jolt has none.
//  - Jolt (jolt_world.hpp): the collision half of PhysicsSystem::Update on the same poses: the
//    bodies are kinematic bodies, each step put at the pose collide's world had before the same
//    step (recorded once, outside the timing) and moved by the same velocities as Jolt's
//    integration moves a body (AddRotationStep, AddPositionStep: the pose collide's world
//    reaches too, unless it pushed the body out of a contact: counter `j_pose_off`, bodies per
//    step farther than kPoseOffFraction of their size), their bounds updated and the
//    BroadPhaseQuadTree told; the quad tree updated; FindCollidingPairs; and each pair
//    CollideShape with faces collected and active edges, each result made a manifold
//    (ManifoldBetweenTwoFaces) and merged by normal, pruned to 4 points, as PhysicsSystem's
//    manifold reduction does. No solver, no constraints, no contact cache (PhysicsSystem would
//    reuse last step's contacts for pairs that barely moved), no events.
//  - Comparable: the same bodies at the same poses each step, the same level, dt and counts;
//    both touching-only (collide's contacts have margin 0; Jolt's speculative distance and
//    mMaxSeparationDistance are 0, its default being 0.02), triangles two-sided on both sides.
//    collide does more than Jolt: the bounce and push-out response and the contact events;
//    Jolt's side copies each recorded pose into its body before moving it, which its own step
//    would not (a store and a rotation per body). Each
//    benchmark runs kWarmupSteps untimed (the broad phases and the early-out chains settle),
//    then exactly kTimedSteps timed steps, so both sides see the recorded poses; collide's final
//    state hash is checked against the recording.
//
// BM_CharacterMove / BM_CharacterMoveJolt: kCharacters capsules walking the level for
// kCharacterFrames frames, one move each per frame: collide's move_character against Jolt's
// CharacterVirtual::ExtendedUpdate (Update plus stick to floor and stair walking, as
// move_character steps and sticks to the ground). Same capsule (sized as `collide run`'s
// characters), start (on walkable floor, found by a ray down), max slope (50 degrees), step
// height, skin (Jolt: mCharacterPadding), forward test for steps, gravity and dt; each frame the
// same desired horizontal velocity per character (a heading redrawn every kTurnFrames frames
// from a seeded generator), the same vertical velocity rule on both sides (zero when grounded
// after the last move, gravity added each frame), each side from its own grounded state.
// dungeon.obj's floors have open edges: a character that falls a character height below the
// level starts again at its start, on both sides alike (counters `fell`, `j_fell`). The
// time is per move (`per_move`); the counters come from an untimed run of both: grounded
// fraction per side, moves that ended inside the level (judged by collide's exact contact
// against the level, deeper than kTunnelDepthFraction of the radius) and the deepest overlap per
// side, the characters stuck in place at the end (`stuck`: see kStuckFraction) and the mean
// distance between the two sides' final positions.
//
// BM_RayCast / BM_RayCastJolt (1e3 and 1e4 bodies, rays of L units): a game's ray casts into
// that world (a laser, a line of sight, a pick): World3D::raycast (the level through its
// TriangleMesh BVH, the bodies through the body broad phase, each candidate's exact cast, the
// nearest hit with point and normal) against Jolt's NarrowPhaseQuery::CastRay over the same
// BroadPhaseQuadTree and bodies, with the hit body's GetWorldSpaceSurfaceNormal
// (jolt_queries::cast_ray). Both worlds at the same poses: collide's after kWarmupSteps steps
// of BM_Step's run, Jolt's bodies put at those recorded poses (a step of dt 0: the quad tree
// updated). kRays rays, the same on both sides: origins uniform in the level's box, directions
// uniform, L = 5 (a pick, a ground probe: 2.4 character heights) and 50 units (a line of sight
// across rooms; the level's diagonal is 130); each iteration casts the next. Counters, once,
// outside the timing: `hit_rate`, `j_hit_rate` and `agree` (both hit within kRayAgreeUnits of
// each other, or both miss; Jolt's hit at fraction 0 for a ray starting inside a body is where
// the two differ: collide's world skips a collider the ray starts in).
//
// Counters are computed once, outside the timing, and the same on both sides' rows. Instruction
// sets are in the context block (collide's build, Jolt's own).
//
// Run: ./build/release/bench/bench_world3d --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/world/character.hpp>
#include <collide/world/world3d.hpp>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"
#include "support/jolt/jolt_convert.hpp"
#include "support/jolt/jolt_queries.hpp"
#include "support/jolt/jolt_world.hpp"
#include "support/random.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using test::jolt_vec;  // support/jolt/jolt_convert.hpp
using test::jolt_pose;  // support/jolt/jolt_convert.hpp
using test::from_jolt;  // support/jolt/jolt_convert.hpp
using test::uniform;

// ---- the workload ----------------------------------------------------------------------------------

/// Step length, seconds (both benchmarks).
constexpr float kDt = 1.0f / 60.0f;
/// A body's size (about its bounding radius) against the level's box diagonal: 1.5 times
/// `collide run`'s 0.004, so that more of them meet.
constexpr float kBodySizeFraction = 0.006f;
/// Tries per body to find a free place in the level's box.
constexpr int kSpawnAttempts = 60;
/// Bodies start at up to this many of their sizes per second, spinning up to kMaxSpin radians
/// per second about each axis: slow enough that no body needs continuous collision (a body moves
/// so when a step takes it further than kCcdMotionFraction of its narrowest piece's inner size;
/// the counter `ccd` says how many did: only bodies that a collision pushed).
constexpr float kMaxBodySpeed = 2.0f;
constexpr float kMaxSpin = 0.5f;

/// Untimed steps before the timed ones, and timed steps per benchmark run.
constexpr int kWarmupSteps = 30;
constexpr int kTimedSteps = 100;
/// Seed of the bodies and of the characters' starts and headings.
constexpr std::uint32_t kSeed = 1;

/// Characters: count, frames, and their capsule per character height (as `collide run`: radius
/// and core half height in the ratio 1.2 : 1.6), the height `collide run`'s: 4 body sizes of
/// its own (0.004 of the level's diagonal), 2.08 units on dungeon.obj.
constexpr int kCharacters = 32;
constexpr int kCharacterFrames = 600;
constexpr float kCharacterHeightPerDiagonal = 4.0f * 0.004f;
constexpr float kCharacterRadius = 1.2f / 5.6f;      ///< of the height
constexpr float kCharacterHalfHeight = 1.6f / 5.6f;  ///< of the height
/// Walking speed and gravity in character heights per second (squared), step height and skin
/// in heights (`collide run`'s).
constexpr float kWalkSpeed = 1.0f;
constexpr float kCharacterGravity = 5.5f;
constexpr float kStepHeight = 0.17f;
constexpr float kSkin = 0.005f;
/// A character draws a new heading every kTurnFrames frames (each at its own phase).
constexpr int kTurnFrames = 120;

std::string dungeon_path() { return std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj"; }

/// The level on both sides.
struct Level {
  std::shared_ptr<const TriangleMesh> mesh;
  jolt_queries::MeshPtr jolt;
  Aabb3 box;
  float diagonal = 0.0f;
};

const Level& level() {
  static const Level l = [] {
    jolt_queries::init();
    Level out;
    out.mesh = std::make_shared<const TriangleMesh>(io::load_triangle_mesh(dungeon_path()));
    out.box = compute_aabb(*out.mesh, Transform3{});
    out.diagonal = length(out.box.max - out.box.min);
    const TriangleSoup soup = io::load_obj(dungeon_path());
    std::vector<jolt_queries::Vec> positions;
    for (const Vec3& p : soup.positions) positions.push_back(jolt_vec(p));
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (const glm::uvec3& t : soup.triangles) triangles.push_back({t.x, t.y, t.z});
    out.jolt = jolt_queries::make_mesh(positions, triangles);
    if (!out.jolt) {
      std::fprintf(stderr, "Jolt refused dungeon.obj\n");
      std::abort();
    }
    return out;
  }();
  return l;
}

float body_size() { return kBodySizeFraction * level().diagonal; }
float character_height() { return kCharacterHeightPerDiagonal * level().diagonal; }

/// collide's world with the level as its one static. The world's independent end-of-step check
/// is off (see the file comment).
World3D level_world() {
  World3D world(WorldOptions3{.check_each_step = false});
  world.add_static({.shapes = {level().mesh}, .user_id = 1});
  return world;
}

/// True when `shape` at `xf` touches nothing in `world`.
bool free_at(const World3D& world, const Shape3D& shape, const Transform3& xf) {
  bool clear = true;
  world.collide_shape(shape, xf, QueryFilter{}, [&](const ColliderRef&, const Manifold3&) { return clear = false; });
  return clear;
}

// ---- ray casts into the world -----------------------------------------------------------------------

/// Rays a set (more than the caches and the branch predictor learn), and how close two hit
/// points must be to agree (world units; the level's box is 130 across).
constexpr int kRays = 4096;
constexpr float kRayAgreeUnits = 1e-3f;

// ---- the step -------------------------------------------------------------------------------------

/// A mixed body shape of about `size` (bounding radius), as `collide run` makes them.
Shape3D random_shape(std::mt19937& rng, float size) {
  switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
    case 0: return make_sphere(Vec3(0.0f), uniform(rng, 0.5f, 1.0f) * size);
    case 1: return make_capsule(Vec3(0, -0.5f * size, 0), Vec3(0, 0.5f * size, 0), uniform(rng, 0.3f, 0.5f) * size);
    case 2: return make_box(size * Vec3(uniform(rng, 0.35f, 0.7f), uniform(rng, 0.35f, 0.7f), uniform(rng, 0.35f, 0.7f)));
    default: {
      std::vector<Vec3> points;
      for (int i = 0; i < 12; ++i) points.push_back(size * test::random_point3(rng, 0.7f));
      return make_convex_hull(points);
    }
  }
}

/// The same solid in Jolt (convex radius 0; the capsule's core along y about the origin, as
/// random_shape makes them; a hull from the hull's own vertices).
jolt_queries::ConvexPtr jolt_shape(const Shape3D& shape) {
  if (const auto* s = std::get_if<Sphere>(&shape)) return jolt_queries::make_sphere(s->radius);
  if (const auto* c = std::get_if<Capsule3>(&shape)) return jolt_queries::make_capsule(c->b.y, c->radius);
  if (const auto* b = std::get_if<Box>(&shape)) return jolt_queries::make_box(jolt_vec(b->half));
  const auto& hull = std::get<ConvexHull>(shape);
  std::vector<jolt_queries::Vec> corners;
  for (const Vec3& v : hull.vertices) corners.push_back(jolt_vec(v));
  jolt_queries::ConvexPtr c = jolt_queries::make_convex(corners);
  if (!c) {
    std::fprintf(stderr, "Jolt refused a hull\n");
    std::abort();
  }
  return c;
}

/// Per step means of what each side's work found.
struct StepCounters {
  double body_pairs = 0, static_candidates = 0, narrow_tests = 0;  // collide's broad phase and early out
  double touching_bodies = 0, touching_level = 0, points = 0;      // collide's contacts
  double ccd = 0, pushes = 0;
  /// collide's own per-phase clock (StepStats, microseconds per step, in the untimed run): motion,
  /// body-level contacts, body broad phase, body pairs, events.
  double us_motion = 0, us_statics = 0, us_broad = 0, us_pairs = 0, us_events = 0;
  double jolt_body_pairs = 0, jolt_level_pairs = 0;
  double jolt_touching_bodies = 0, jolt_touching_level = 0, jolt_manifolds = 0, jolt_points = 0;
  double jolt_pose_off = 0;  ///< bodies whose pose after the step is off collide's (see kPoseOffFraction)
};

/// A Jolt body's position after a step counts as off collide's when farther than this many body
/// sizes from it.
constexpr float kPoseOffFraction = 1e-3f;

/// One workload of `count` bodies: their definitions, collide's run of it (each body's pose and
/// velocity before each step, the final hash) and both sides' counters over the timed steps.
struct StepRun {
  std::vector<BodyDef3> bodies;
  std::vector<jolt_queries::ConvexPtr> jolt_shapes;
  std::vector<const jolt_queries::Convex*> jolt_shape_ptrs;
  std::vector<std::vector<jolt_queries::Pose>> poses;  ///< [step][body], before the step
  std::vector<std::vector<jolt_queries::Vec>> velocities;  ///< [step][body], before the step
  std::vector<jolt_queries::Vec> spins;  ///< [body]: angular velocities (a kinematic world keeps them)
  std::uint64_t final_hash = 0;
  int spawned = 0;
  StepCounters counters;
};

World3D step_world(const StepRun& run) {
  World3D world = level_world();
  for (const BodyDef3& def : run.bodies) world.add_body(def);
  return world;
}

jolt_queries::StepWorldPtr jolt_step_world(const StepRun& run) {
  return jolt_queries::make_step_world(*level().jolt, run.jolt_shape_ptrs, run.poses[0]);
}

/// Jolt's step `s`: from collide's pose before it, by collide's velocities.
jolt_queries::StepCounts jolt_step(jolt_queries::StepWorld& jolt, const StepRun& run, int s) {
  return jolt_queries::step(jolt, run.poses[s], run.velocities[s], run.spins, kDt, 0.0f);
}

/// A free place for `shape` in the level's box (false when none was found), its velocity and
/// spin.
bool spawn_body(const World3D& world, const Shape3D& shape, std::mt19937& rng, BodyDef3& def) {
  const Level& l = level();
  const float size = body_size();
  for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
    const Transform3 xf{Vec3(uniform(rng, l.box.min.x, l.box.max.x), uniform(rng, l.box.min.y, l.box.max.y),
                             uniform(rng, l.box.min.z, l.box.max.z)),
                        test::random_rotation(rng)};
    if (!free_at(world, shape, xf)) continue;
    def = BodyDef3{.shapes = {shape}, .transform = xf,
                   .velocity = uniform(rng, 0.0f, kMaxBodySpeed * size) * test::random_unit3(rng),
                   .angular_velocity = kMaxSpin * test::random_point3(rng, 1.0f)};
    return true;
  }
  return false;
}

StepRun make_step_run(int count) {
  StepRun run;
  std::mt19937 rng(kSeed);
  World3D spawn = level_world();
  for (int i = 0; i < count; ++i) {
    const Shape3D shape = random_shape(rng, body_size());
    BodyDef3 def;
    if (spawn_body(spawn, shape, rng, def)) {
      def.user_id = std::uint64_t(i);
      spawn.add_body(def);
      run.bodies.push_back(def);
      run.jolt_shapes.push_back(jolt_shape(shape));
      run.jolt_shape_ptrs.push_back(run.jolt_shapes.back().get());
      run.spins.push_back(jolt_vec(def.angular_velocity));
    }
  }
  run.spawned = static_cast<int>(run.bodies.size());

  // collide's run, recorded; its counters over the timed steps.
  World3D world = step_world(run);
  const std::vector<BodyId> ids = world.body_ids();
  StepCounters& c = run.counters;
  for (int s = 0; s < kWarmupSteps + kTimedSteps; ++s) {
    std::vector<jolt_queries::Pose> poses;
    std::vector<jolt_queries::Vec> velocities;
    for (const BodyId id : ids) {
      poses.push_back(jolt_pose(world.transform(id)));
      velocities.push_back(jolt_vec(world.velocity(id)));
    }
    run.poses.push_back(std::move(poses));
    run.velocities.push_back(std::move(velocities));
    world.step(kDt);
    if (s < kWarmupSteps) continue;
    const StepStats& st = world.last_step_stats();
    c.body_pairs += double(st.body_pairs);
    c.static_candidates += double(st.static_candidates);
    c.narrow_tests += double(st.narrow_tests);
    c.ccd += double(st.ccd_bodies);
    c.pushes += double(st.pushes);
    c.us_motion += 1e6 * st.time_integrate;
    c.us_statics += 1e6 * st.time_statics;
    c.us_broad += 1e6 * st.time_broad;
    c.us_pairs += 1e6 * st.time_bodies;
    c.us_events += 1e6 * st.time_events;
    for (const Contact3& contact : world.contacts()) {
      (contact.b.is_static ? c.touching_level : c.touching_bodies) += 1.0;
      c.points += contact.manifold.count;
    }
  }
  run.final_hash = world.state_hash();

  // Jolt's replay, for its counters, and how far its poses are from collide's after each step
  // (collide pushes a body out of what it touched; Jolt's kinematic motion has no push).
  jolt_queries::StepWorldPtr jolt = jolt_step_world(run);
  const float off = kPoseOffFraction * body_size();
  for (int s = 0; s < kWarmupSteps + kTimedSteps; ++s) {
    const jolt_queries::StepCounts j = jolt_step(*jolt, run, s);
    if (s < kWarmupSteps) continue;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const Vec3 p = s + 1 < kWarmupSteps + kTimedSteps ? from_jolt(run.poses[s + 1][i].p) : world.transform(ids[i]).p;
      c.jolt_pose_off += length(from_jolt(jolt_queries::pose(*jolt, static_cast<int>(i)).p) - p) > off;
    }
    c.jolt_body_pairs += j.body_pairs;
    c.jolt_level_pairs += j.level_pairs;
    c.jolt_touching_bodies += j.touching_bodies;
    c.jolt_touching_level += j.touching_level;
    c.jolt_manifolds += j.manifolds;
    c.jolt_points += j.points;
  }
  for (double* v : {&c.body_pairs, &c.static_candidates, &c.narrow_tests, &c.touching_bodies, &c.touching_level,
                    &c.points, &c.ccd, &c.pushes, &c.jolt_body_pairs, &c.jolt_level_pairs, &c.jolt_touching_bodies,
                    &c.jolt_touching_level, &c.jolt_manifolds, &c.jolt_points, &c.jolt_pose_off, &c.us_motion,
                    &c.us_statics, &c.us_broad, &c.us_pairs, &c.us_events}) {
    *v /= kTimedSteps;
  }
  return run;
}

const StepRun& step_run(const benchmark::State& state) {
  static std::map<int, StepRun> runs;
  const int count = static_cast<int>(state.range(0));
  auto it = runs.find(count);
  if (it == runs.end()) it = runs.emplace(count, make_step_run(count)).first;
  return it->second;
}

/// Both sides' counters on a row; a workload whose two sides disagree by more than
/// kCountersAgreeFactor on the touching pairs is flagged as an error (not the same work).
constexpr double kCountersAgreeFactor = 2.0;

bool step_counters(benchmark::State& state, const StepRun& run) {
  const StepCounters& c = run.counters;
  state.counters["bodies"] = run.spawned;
  state.counters["pairs"] = c.body_pairs;
  state.counters["level_cand"] = c.static_candidates;
  state.counters["narrow"] = c.narrow_tests;
  state.counters["touch_bb"] = c.touching_bodies;
  state.counters["touch_bl"] = c.touching_level;
  state.counters["points"] = c.points;
  state.counters["ccd"] = c.ccd;
  state.counters["pushes"] = c.pushes;
  state.counters["us_motion"] = c.us_motion;
  state.counters["us_statics"] = c.us_statics;
  state.counters["us_broad"] = c.us_broad;
  state.counters["us_pairs"] = c.us_pairs;
  state.counters["us_events"] = c.us_events;
  state.counters["j_pairs"] = c.jolt_body_pairs;
  state.counters["j_level_pairs"] = c.jolt_level_pairs;
  state.counters["j_touch_bb"] = c.jolt_touching_bodies;
  state.counters["j_touch_bl"] = c.jolt_touching_level;
  state.counters["j_manifolds"] = c.jolt_manifolds;
  state.counters["j_points"] = c.jolt_points;
  state.counters["j_pose_off"] = c.jolt_pose_off;
  const auto agree = [](double a, double b) {
    return a + b < 10.0 || (a <= kCountersAgreeFactor * b && b <= kCountersAgreeFactor * a);
  };
  if (!agree(c.touching_bodies, c.jolt_touching_bodies) || !agree(c.touching_level, c.jolt_touching_level)) {
    state.SkipWithError("collide and Jolt disagree on the touching pairs: not the same work");
    return false;
  }
  return true;
}

void BM_Step(benchmark::State& state) {
  const StepRun& run = step_run(state);
  World3D world = step_world(run);
  for (int s = 0; s < kWarmupSteps; ++s) world.step(kDt);
  for (auto _ : state) world.step(kDt);
  if (!step_counters(state, run)) return;
  if (world.state_hash() != run.final_hash) state.SkipWithError("collide's world left the recorded path");
}

void BM_StepJolt(benchmark::State& state) {
  const StepRun& run = step_run(state);
  jolt_queries::StepWorldPtr jolt = jolt_step_world(run);
  for (int s = 0; s < kWarmupSteps; ++s) jolt_step(*jolt, run, s);
  int s = kWarmupSteps;
  for (auto _ : state) benchmark::DoNotOptimize(jolt_step(*jolt, run, s++));
  step_counters(state, run);
}

// ---- the character ----------------------------------------------------------------------------------

Capsule3 character_capsule() {
  const float h = character_height();
  const float half = kCharacterHalfHeight * h;
  return make_capsule(Vec3(0, -half, 0), Vec3(0, half, 0), kCharacterRadius * h);
}

CharacterSettings3 collide_character_settings() {
  const float h = character_height();
  return CharacterSettings3{.step_height = kStepHeight * h, .skin = kSkin * h};
}

jolt_queries::CharacterSettings jolt_character_settings() {
  const Capsule3 capsule = character_capsule();
  const CharacterSettings3 s = collide_character_settings();
  jolt_queries::CharacterSettings j;
  j.radius = capsule.radius;
  j.half_height = capsule.b.y;
  j.max_slope = s.max_slope;
  j.step_height = s.step_height;
  j.step_forward_test = s.step_forward_test;
  j.padding = s.skin;
  return j;
}

/// The characters' starts and each frame's desired horizontal velocity ([frame][character]).
struct Walk {
  std::vector<Vec3> start;
  std::vector<std::vector<Vec3>> desired;
};

const Walk& walk() {
  static const Walk w = [] {
    const Level& l = level();
    const World3D world = level_world();
    const Capsule3 capsule = character_capsule();
    const Shape3D shape = capsule;
    const float stand = capsule.b.y + capsule.radius + 2.0f * collide_character_settings().skin;
    const float cos_slope = std::cos(collide_character_settings().max_slope);
    std::mt19937 rng(kSeed + 1);
    Walk out;
    while (static_cast<int>(out.start.size()) < kCharacters) {
      const Vec3 top(uniform(rng, l.box.min.x, l.box.max.x), l.box.max.y, uniform(rng, l.box.min.z, l.box.max.z));
      const auto hit = world.raycast(Ray3{top, Vec3(0.0f, l.box.min.y - top.y - 1.0f, 0.0f)});
      if (!hit || hit->hit.normal.y < cos_slope) continue;
      const Vec3 p = hit->hit.point + Vec3(0.0f, stand, 0.0f);
      if (free_at(world, shape, Transform3{p})) out.start.push_back(p);
    }
    std::vector<float> heading(kCharacters);
    for (float& h : heading) h = uniform(rng, 0.0f, 2.0f * std::numbers::pi_v<float>);
    const float speed = kWalkSpeed * character_height();
    for (int f = 0; f < kCharacterFrames; ++f) {
      std::vector<Vec3> v;
      for (int k = 0; k < kCharacters; ++k) {
        if (f > 0 && f % kTurnFrames == k % kTurnFrames) heading[k] = uniform(rng, 0.0f, 2.0f * std::numbers::pi_v<float>);
        v.push_back(speed * Vec3(std::cos(heading[k]), 0.0f, std::sin(heading[k])));
      }
      out.desired.push_back(std::move(v));
    }
    return out;
  }();
  return w;
}

/// The vertical velocity rule both sides follow: zero once grounded, gravity added each frame.
float next_vertical(float vy, bool grounded) {
  return (grounded ? 0.0f : vy) - kCharacterGravity * character_height() * kDt;
}

/// One character's state on either side.
struct Walker {
  Vec3 p{0.0f};
  float vy = 0.0f;
  bool grounded = true;
  int fell = 0;  ///< times it fell off the level's open edges and started again
  /// collide's last move, handed to the next (as Jolt's CharacterVirtual keeps its state).
  std::optional<CharacterMove3> last;
};

/// A character that fell this far below the level's box (dungeon.obj has open edges) starts
/// again where it started, on both sides alike.
bool fell_off(const Walker& w) { return w.p.y < level().box.min.y - character_height(); }

/// A frame of collide's characters.
void collide_frame(const World3D& world, const Shape3D& shape, const CharacterSettings3& settings, int frame,
                   std::vector<Walker>& walkers) {
  const std::vector<Vec3>& desired = walk().desired[frame];
  for (std::size_t k = 0; k < walkers.size(); ++k) {
    Walker& w = walkers[k];
    w.vy = next_vertical(w.vy, w.grounded);
    const Vec3 v(desired[k].x, w.vy, desired[k].z);
    const CharacterMove3 m =
        move_character(world, shape, Transform3{w.p}, v * kDt, settings, w.last ? &*w.last : nullptr);
    w.last = m;
    w.p = m.transform.p;
    w.grounded = m.grounded;
    if (fell_off(w)) w = {walk().start[k], 0.0f, true, w.fell + 1};
  }
}

/// A frame of Jolt's characters.
void jolt_frame(std::vector<jolt_queries::CharacterPtr>& characters, int frame, std::vector<Walker>& walkers) {
  const std::vector<Vec3>& desired = walk().desired[frame];
  const jolt_queries::Vec gravity{0.0f, -kCharacterGravity * character_height(), 0.0f};
  for (std::size_t k = 0; k < walkers.size(); ++k) {
    Walker& w = walkers[k];
    w.vy = next_vertical(w.vy, w.grounded);
    const jolt_queries::CharacterOut out =
        jolt_queries::move(*characters[k], {desired[k].x, w.vy, desired[k].z}, kDt, gravity);
    w.p = from_jolt(out.position);
    w.grounded = out.grounded;
    if (fell_off(w)) {
      w = {walk().start[k], 0.0f, true, w.fell + 1};
      jolt_queries::place(*characters[k], jolt_vec(w.p));
    }
  }
}

std::vector<Walker> start_walkers() {
  std::vector<Walker> walkers;
  for (const Vec3& p : walk().start) walkers.push_back({p, 0.0f, true});
  return walkers;
}

std::vector<jolt_queries::CharacterPtr> jolt_characters(jolt_queries::CharacterWorld& world) {
  std::vector<jolt_queries::CharacterPtr> characters;
  for (const Vec3& p : walk().start) {
    characters.push_back(jolt_queries::make_character(world, jolt_character_settings(), jolt_vec(p)));
  }
  return characters;
}

/// What an untimed run of both sides found.
struct WalkCounters {
  double grounded = 0, jolt_grounded = 0;  ///< fraction of moves ending grounded
  int inside = 0, jolt_inside = 0;         ///< moves ending inside the level
  double depth = 0, jolt_depth = 0;        ///< deepest overlap with the level after a move
  double mean_end_distance = 0;            ///< between the two sides' final positions
  double max_end_distance = 0;
  double travelled = 0, jolt_travelled = 0;  ///< mean distance from start to end
  int fell = 0, jolt_fell = 0;               ///< falls off the level's open edges
  /// Characters that moved less than kStuckFraction of their radius over the last kTurnFrames
  /// frames (a heading change among them): stuck, whichever way they are told to walk.
  int stuck = 0, jolt_stuck = 0;
};

/// See WalkCounters::stuck.
constexpr float kStuckFraction = 0.1f;

const WalkCounters& walk_counters() {
  static const WalkCounters c = [] {
    const World3D world = level_world();
    const Shape3D shape = character_capsule();
    const CharacterSettings3 settings = collide_character_settings();
    const float tolerance = kTunnelDepthFraction * character_capsule().radius;
    jolt_queries::CharacterWorldPtr jworld = jolt_queries::make_character_world(*level().jolt);
    std::vector<jolt_queries::CharacterPtr> characters = jolt_characters(*jworld);
    std::vector<Walker> ours = start_walkers(), theirs = start_walkers();
    WalkCounters out;
    const auto judge = [&](const std::vector<Walker>& walkers, double& grounded, int& inside, double& deepest) {
      for (const Walker& w : walkers) {
        grounded += w.grounded;
        float depth = 0.0f;
        world.collide_shape(shape, Transform3{w.p}, QueryFilter{}, [&](const ColliderRef&, const Manifold3& m) {
          depth = std::max(depth, m.max_depth());
          return true;
        });
        inside += depth > tolerance;
        deepest = std::max(deepest, double(depth));
      }
    };
    std::vector<Walker> ours_before, theirs_before;
    for (int f = 0; f < kCharacterFrames; ++f) {
      if (f == kCharacterFrames - kTurnFrames) {
        ours_before = ours;
        theirs_before = theirs;
      }
      collide_frame(world, shape, settings, f, ours);
      jolt_frame(characters, f, theirs);
      judge(ours, out.grounded, out.inside, out.depth);
      judge(theirs, out.jolt_grounded, out.jolt_inside, out.jolt_depth);
    }
    const double moves = double(kCharacters) * kCharacterFrames;
    out.grounded /= moves;
    out.jolt_grounded /= moves;
    for (int k = 0; k < kCharacters; ++k) {
      const double d = length(ours[k].p - theirs[k].p);
      out.mean_end_distance += d / kCharacters;
      out.max_end_distance = std::max(out.max_end_distance, d);
      out.travelled += length(ours[k].p - walk().start[k]) / kCharacters;
      out.jolt_travelled += length(theirs[k].p - walk().start[k]) / kCharacters;
      out.fell += ours[k].fell;
      out.jolt_fell += theirs[k].fell;
      const float still = kStuckFraction * character_capsule().radius;
      out.stuck += ours[k].fell == ours_before[k].fell && length(ours[k].p - ours_before[k].p) < still;
      out.jolt_stuck += theirs[k].fell == theirs_before[k].fell && length(theirs[k].p - theirs_before[k].p) < still;
    }
    return out;
  }();
  return c;
}

void walk_counters(benchmark::State& state, double moves) {
  const WalkCounters& c = walk_counters();
  state.counters["per_move"] = benchmark::Counter(moves, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["grounded"] = c.grounded;
  state.counters["j_grounded"] = c.jolt_grounded;
  state.counters["inside"] = c.inside;
  state.counters["j_inside"] = c.jolt_inside;
  state.counters["depth"] = c.depth;
  state.counters["j_depth"] = c.jolt_depth;
  state.counters["moved"] = c.travelled;
  state.counters["j_moved"] = c.jolt_travelled;
  state.counters["end_dist"] = c.mean_end_distance;
  state.counters["end_dist_max"] = c.max_end_distance;
  state.counters["fell"] = c.fell;
  state.counters["j_fell"] = c.jolt_fell;
  state.counters["stuck"] = c.stuck;
  state.counters["j_stuck"] = c.jolt_stuck;
  state.counters["height"] = character_height();
}

void BM_CharacterMove(benchmark::State& state) {
  const World3D world = level_world();
  const Shape3D shape = character_capsule();
  const CharacterSettings3 settings = collide_character_settings();
  std::vector<Walker> walkers = start_walkers();
  int frame = 0;
  for (auto _ : state) collide_frame(world, shape, settings, frame++, walkers);
  benchmark::DoNotOptimize(walkers.data());
  walk_counters(state, double(state.iterations()) * kCharacters);
}

void BM_CharacterMoveJolt(benchmark::State& state) {
  jolt_queries::CharacterWorldPtr jworld = jolt_queries::make_character_world(*level().jolt);
  std::vector<jolt_queries::CharacterPtr> characters = jolt_characters(*jworld);
  std::vector<Walker> walkers = start_walkers();
  int frame = 0;
  for (auto _ : state) jolt_frame(characters, frame++, walkers);
  benchmark::DoNotOptimize(walkers.data());
  walk_counters(state, double(state.iterations()) * kCharacters);
}

}  // namespace

/// Both worlds of the ray casts at the same poses, the rays and the counters.
struct RayWorlds {
  std::optional<World3D> world;
  jolt_queries::StepWorldPtr jolt;
  std::map<int, std::vector<Ray3>> rays;               // by length
  std::map<int, std::array<double, 3>> counters;  // by length: hit_rate, j_hit_rate, agree
};

RayWorlds& ray_worlds(const benchmark::State& state) {
  static std::map<int, RayWorlds> all;
  const StepRun& run = step_run(state);
  RayWorlds& r = all[static_cast<int>(state.range(0))];
  if (!r.world) {
    r.world.emplace(step_world(run));
    for (int s = 0; s < kWarmupSteps; ++s) r.world->step(kDt);
    r.jolt = jolt_step_world(run);
    jolt_queries::step(*r.jolt, run.poses[kWarmupSteps], run.velocities[kWarmupSteps], run.spins, 0.0f, 0.0f);
  }
  const int ray_length = static_cast<int>(state.range(1));
  if (r.rays.count(ray_length) == 0) {
    std::mt19937 rng(0x5eed0000u + static_cast<std::uint32_t>(ray_length));
    const Aabb3& box = level().box;
    std::vector<Ray3> rays;
    std::size_t hits = 0, j_hits = 0, agree = 0;
    for (int i = 0; i < kRays; ++i) {
      const Vec3 origin(uniform(rng, box.min.x, box.max.x), uniform(rng, box.min.y, box.max.y),
                        uniform(rng, box.min.z, box.max.z));
      const Ray3 ray{origin, static_cast<float>(ray_length) * test::random_unit3(rng)};
      rays.push_back(ray);
      const auto h = r.world->raycast(ray);
      const jolt_queries::WorldRayHit j = jolt_queries::cast_ray(*r.jolt, jolt_vec(ray.origin), jolt_vec(ray.translation));
      hits += h ? 1u : 0u;
      j_hits += j.hit ? 1u : 0u;
      if (h.has_value() == j.hit && (!h || length(h->hit.point - from_jolt(j.point)) <= kRayAgreeUnits)) ++agree;
    }
    const double count = static_cast<double>(rays.size());
    r.counters[ray_length] = {hits / count, j_hits / count, agree / count};
    r.rays.emplace(ray_length, std::move(rays));
  }
  return r;
}

void ray_counters(benchmark::State& state, const RayWorlds& r) {
  const std::array<double, 3>& c = r.counters.at(static_cast<int>(state.range(1)));
  state.counters["hit_rate"] = c[0];
  state.counters["j_hit_rate"] = c[1];
  state.counters["agree"] = c[2];
  state.counters["bodies"] = static_cast<double>(r.world->body_count());
}

void BM_RayCast(benchmark::State& state) {
  RayWorlds& r = ray_worlds(state);
  const std::vector<Ray3>& rays = r.rays.at(static_cast<int>(state.range(1)));
  const World3D& world = *r.world;
  std::size_t i = 0;
  for (auto _ : state) {
    auto h = world.raycast(rays[i]);
    benchmark::DoNotOptimize(h);
    i = (i + 1) % rays.size();
  }
  ray_counters(state, r);
}

void BM_RayCastJolt(benchmark::State& state) {
  RayWorlds& r = ray_worlds(state);
  const std::vector<Ray3>& rays = r.rays.at(static_cast<int>(state.range(1)));
  const jolt_queries::StepWorld& jolt = *r.jolt;
  std::size_t i = 0;
  for (auto _ : state) {
    const Ray3& ray = rays[i];
    auto h = jolt_queries::cast_ray(jolt, jolt_vec(ray.origin), jolt_vec(ray.translation));
    benchmark::DoNotOptimize(h);
    i = (i + 1) % rays.size();
  }
  ray_counters(state, r);
}

// Fixed iteration counts: every run walks the same recorded steps and frames.
BENCHMARK(BM_Step)->Arg(1000)->Arg(10000)->Iterations(kTimedSteps)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StepJolt)->Arg(1000)->Arg(10000)->Iterations(kTimedSteps)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RayCast)->ArgsProduct({{1000, 10000}, {5, 50}})->Unit(benchmark::kNanosecond);
BENCHMARK(BM_RayCastJolt)->ArgsProduct({{1000, 10000}, {5, 50}})->Unit(benchmark::kNanosecond);
BENCHMARK(BM_CharacterMove)->Iterations(kCharacterFrames)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CharacterMoveJolt)->Iterations(kCharacterFrames)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  jolt_queries::init();
  collide::bench::add_instruction_sets("jolt", jolt_queries::instruction_set());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
