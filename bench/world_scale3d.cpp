// A 3D world step at scale (issue 20, its 3D half): collide's World3D against Jolt's
// PhysicsSystem on the same statics and bodies, 1e3 .. 1e6 bodies, 1 and 2 threads, side by
// side in one run. The 2D half, World2D against Box2D v3, is bench_world_scale.
//
// The scene: `collide run --3d`'s embedded scene (cli::make_scene3d), grown with the body count:
// rooms of 40 x 12 x 40 on a grid, 500 bodies per room, each room a height-field floor (81 x 81
// samples), a shell of walls, ceiling and bottom (a triangle mesh facing in), two ramps (a mesh
// quad and a box) with a box platform each, 8 stair boxes, 12 rocks (convex hulls), 6 pillars
// (capsules) and 4 thin boxes. Bodies: spheres, capsules, boxes and 12-point hulls of about 0.35
// units, at up to 2.8 units/s with random spins of up to 2 rad/s on each axis; each 10th body a
// bullet at 420 units/s (20 of its sizes per frame). No characters, no gravity.
//
// BM_CollideStep3/N/T: World3D::step(1/60) on that scene (RunOptions::threads = T: T = 1 the
// serial scheduler, else oneTBB with T workers), as `collide run --3d` steps it: integrate with
// continuous collision (bullets), statics (tree, early out, contact, push-out), body broad phase,
// body pairs (early out, contact, elastic response), contact events, and the world's
// independent end-of-step check (a brute-force tunnelling test; no peer has it). Counters:
// `ns_body` (ns per body per frame, everything), `ns_body_nocheck` (the same without
// StepStats::time_check), the phases per body (`integrate` is the motion with continuous
// collision), `contacts` (touching pairs per body per frame, a bullet's hits included),
// `ccd_bodies` and `toi_queries` (per body per frame: bodies moved by continuous collision and
// the time-of-impact queries they ran), `bodies` placed, `workers` (the scheduler's worker
// count).
//
// BM_JoltStep3/N/T: PhysicsSystem::Update(1/60, 1 collision step) on a world built from the same
// collide scene (tests/support/jolt/jolt_scale_world.hpp): every static piece of the World3D a
// static Jolt body (TriangleMesh -> MeshShape, HeightField -> HeightFieldShape with the same
// sample layout and triangle split, Box -> BoxShape, ConvexHull -> ConvexHullShape of its
// vertices, Capsule3 -> CapsuleShape turned onto its segment, Sphere -> SphereShape; convex radius
// 0 on all: exact geometry, as collide's), every body a KINEMATIC body of the same shape, pose and
// velocities with mCollideKinematicVsNonDynamic, so that Jolt runs its integration, broad phase
// (BroadPhaseQuadTree, level and moving layers), narrow phase and contact callbacks (a listener
// counts the manifolds) but has nothing to solve (no contact constraints between non-dynamic
// bodies). Gravity 0, sleeping off, discrete motion quality, speeds unclamped; PhysicsSystem
// capacities and the temporary allocator sized per body (ScaleCapacity; an overflow is reported
// as an error). Threads: a JobSystemThreadPool of T - 1 worker threads; Update's own thread runs
// jobs while it waits, so T threads work at once, and at T = 1 Update runs every job itself.
// Counters: `ns_body` (the whole Update), `contacts` (manifolds added + persisted per body per
// frame), `bodies`, `workers`.
//
// Lockstep: Jolt's kinematic bodies never bounce, so left alone they would fly out of the rooms
// (a bullet leaves its room in six frames) and Jolt would be timed on an emptying world. So the
// Jolt benchmark steps its own copy of the collide scene too, untimed (PauseTiming), and before
// each timed Update puts every Jolt body at the pose and velocities collide's body has at the
// start of that frame (set_bodies: a no-op for the broad phase unless the body bounced in
// collide). Each Update then does the collision work of the same frame collide's step does.
//
// What is not the same: collide also pushes bodies out of statics, bounces them (elastic
// response), runs continuous collision (for the bullets and for every body moving far enough in
// a frame: most of the scene's bodies, see `ccd_bodies`; Jolt has none for kinematic bodies, its
// linear cast moves dynamic bodies only, so a bullet's hits are mostly missed: its 7 units a
// frame cross a wall) and matches contact events; Jolt keeps a body pair
// contact cache (a pair whose relative pose barely changed reuses last frame's manifolds) and
// turns bodies about their centre of mass (collide about the body origin; the same point for
// every shape here but the hulls, whose centroid is near it). Jolt ignores a triangle's back face
// (PhysicsSystem's default), collide's triangles are two-sided; Jolt quantises height-field
// heights (8 bits within each 2 x 2 block's range: at most 0.002 units here). Contacts are
// counted differently (collide: touching pairs; Jolt: manifolds, a body on a mesh may have
// several); they say how much pair work each side saw.
//
// Each step benchmark runs kWarmupFrames untimed first (broad phases, caches, contacts settle),
// then a fixed number of timed frames (fewer at larger N). Real time (UseRealTime): T = 2 runs
// on two threads.
//
// Instruction sets: in the context block (collide's build; Jolt's as jolt_queries reports it).
//
// Run: build/release/bench/bench_world_scale3d --benchmark_filter='/(1000|10000|100000)/'
//      (about 3 minutes on 2 cores). 1e6 is registered too, a scene of 2000 rooms: run one
//      thread count at a time (--benchmark_filter=/1000000/1/, then /1000000/2/; 3.5 minutes
//      and 6.2 GB each, as each thread count keeps its own collide scene).
//      bench/world_scale_ratios.py prints the table.

#include <collide/world/world3d.hpp>

#include "scene3d.hpp"

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"
#include "world_step_timing.hpp"
#include "support/jolt/jolt_convert.hpp"
#include "support/jolt/jolt_scale_world.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

namespace {

using namespace collide;
using test::jolt_vec;  // support/jolt/jolt_convert.hpp
using test::jolt_pose;  // support/jolt/jolt_convert.hpp
using bench::ns_per;
namespace jq = jolt_queries;
using Clock = std::chrono::steady_clock;

constexpr float kDt = 1.0f / 60.0f;
constexpr int kWarmupFrames = 3;
/// Two unit vectors closer to opposite than this (cosine) get a half turn about a perpendicular
/// axis when one is turned onto the other.
constexpr float kOppositeCos = -0.9999f;

/// Timed frames per size: about the same work per benchmark, and the whole run in minutes.
int timed_frames(int n) {
  if (n <= 1000) return 500;
  if (n <= 10000) return 100;
  if (n <= 100000) return 15;
  return 4;
}
/// Repetitions where they are cheap: the small sizes are the noisy ones. The table takes medians.
int repetitions(int n) { return n <= 10000 ? 3 : 1; }

cli::RunOptions scene_options(int n, int threads) {
  cli::RunOptions o;
  o.bodies = n;
  o.threads = threads;
  o.three_d = true;
  o.characters = 0;
  o.progress = false;
  return o;
}

// ---- the collide scene as Jolt shapes -------------------------------------------------------------

/// The rotation that turns +y onto the unit vector `to` (Jolt's capsules lie along y).
Quat y_onto(Vec3 to) {
  const Vec3 y(0.0f, 1.0f, 0.0f);
  const float c = glm::dot(y, to);
  if (c < kOppositeCos) return Quat{0.0f, 1.0f, 0.0f, 0.0f};  // a half turn about x
  const Vec3 axis = glm::cross(y, to);
  return glm::normalize(Quat{1.0f + c, axis.x, axis.y, axis.z});
}

/// A Jolt shape and where its own frame sits in the collide shape's frame.
struct JoltConvex {
  jq::ConvexPtr shape;
  Transform3 local;
};

/// A collide convex shape as a Jolt shape with convex radius 0. Rounded boxes and hulls and
/// segments do not occur in the scene and are refused.
JoltConvex jolt_convex(const Shape3D& shape) {
  return std::visit(
      [](const auto& s) -> JoltConvex {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Sphere>) {
          return {jq::make_sphere(s.radius), Transform3{s.center}};
        } else if constexpr (std::is_same_v<T, Capsule3>) {
          const Vec3 axis = s.b - s.a;
          const float length = glm::length(axis);
          return {jq::make_capsule(0.5f * length, s.radius), Transform3{0.5f * (s.a + s.b), y_onto(axis / length)}};
        } else if constexpr (std::is_same_v<T, Box>) {
          if (s.radius != 0.0f) throw std::runtime_error("world_scale3d: a rounded box (not in the scene)");
          return {jq::make_box(jolt_vec(s.half)), Transform3{}};
        } else if constexpr (std::is_same_v<T, ConvexHull>) {
          if (s.radius != 0.0f) throw std::runtime_error("world_scale3d: a rounded hull (not in the scene)");
          std::vector<jq::Vec> points;
          points.reserve(s.vertices.size());
          for (const Vec3 v : s.vertices) points.push_back(jolt_vec(v));
          jq::ConvexPtr hull = jq::make_convex(points);
          if (!hull) throw std::runtime_error("world_scale3d: Jolt refused a convex hull");
          return {std::move(hull), Transform3{}};
        } else {
          throw std::runtime_error("world_scale3d: a segment (not in the scene)");
        }
      },
      shape);
}

jq::MeshPtr jolt_mesh(const TriangleMesh& mesh) {
  std::vector<jq::Vec> positions;
  positions.reserve(mesh.vertices.size());
  for (const Vec3 v : mesh.vertices) positions.push_back(jolt_vec(mesh.origin + v));
  std::vector<std::array<std::uint32_t, 3>> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const glm::uvec3& t : mesh.triangles) triangles.push_back({t.x, t.y, t.z});
  jq::MeshPtr out = jq::make_mesh(positions, triangles);
  if (!out) throw std::runtime_error("world_scale3d: Jolt refused a triangle mesh");
  return out;
}

jq::MeshPtr jolt_height_field(const HeightField& field) {
  if (field.samples_x != field.samples_z || !field.holes.empty()) {
    throw std::runtime_error("world_scale3d: a height field that is not square or has holes (not in the scene)");
  }
  jq::MeshPtr out = jq::make_height_field(field.samples_x, field.heights, field.spacing.x, field.spacing.y,
                                          jolt_vec(field.origin));
  if (!out) throw std::runtime_error("world_scale3d: Jolt refused a height field");
  return out;
}

/// The collide world's statics and bodies as Jolt shapes and placements (the handles stay
/// here; the Jolt worlds hold the shapes by reference count).
struct JoltScene {
  std::vector<jq::MeshPtr> levels;
  std::vector<jq::ConvexPtr> convexes;
  std::vector<jq::ScaleStatic> statics;
  std::vector<BodyId> ids;                ///< the collide bodies, in the Jolt bodies' order
  std::vector<Transform3> body_local;     ///< each body's Jolt shape frame in its collide frame
  std::vector<jq::ScaleBody> bodies;      ///< the bodies as the collide world holds them now

  /// `bodies` refreshed from `world`'s current poses and velocities.
  void read_bodies(const World3D& world) {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      jq::ScaleBody& b = bodies[i];
      b.pose = jolt_pose(mul(world.transform(ids[i]), body_local[i]));
      b.velocity = jolt_vec(world.velocity(ids[i]));
      b.angular = jolt_vec(world.angular_velocity(ids[i]));
    }
  }
};

JoltScene jolt_scene(const World3D& world) {
  JoltScene out;
  for (int i = 0; i < world.static_count(); ++i) {
    const StaticDef3& def = world.static_def(StaticId{static_cast<std::uint32_t>(i)});
    if (!def.fields.empty() || def.sensor) {
      throw std::runtime_error("world_scale3d: a field or sensor static (not in the scene)");
    }
    for (const StaticShape3D& piece : def.shapes) {
      if (const auto* mesh = std::get_if<std::shared_ptr<const TriangleMesh>>(&piece)) {
        out.levels.push_back(jolt_mesh(**mesh));
        out.statics.push_back({out.levels.back().get(), nullptr, jolt_pose(def.transform)});
      } else if (const auto* field = std::get_if<std::shared_ptr<const HeightField>>(&piece)) {
        out.levels.push_back(jolt_height_field(**field));
        out.statics.push_back({out.levels.back().get(), nullptr, jolt_pose(def.transform)});
      } else {
        JoltConvex c = std::visit(
            [](const auto& s) -> JoltConvex {
              using T = std::decay_t<decltype(s)>;
              if constexpr (std::is_constructible_v<Shape3D, T>) {
                return jolt_convex(Shape3D{s});
              } else {
                throw std::logic_error("world_scale3d: level pieces are handled above");
              }
            },
            piece);
        out.convexes.push_back(std::move(c.shape));
        out.statics.push_back({nullptr, out.convexes.back().get(), jolt_pose(mul(def.transform, c.local))});
      }
    }
  }
  out.ids = world.body_ids();
  for (const BodyId id : out.ids) {
    const std::span<const Shape3D> shapes = world.shapes(id);
    if (shapes.size() != 1) throw std::runtime_error("world_scale3d: a body of several shapes (not in the scene)");
    JoltConvex c = jolt_convex(shapes.front());
    out.convexes.push_back(std::move(c.shape));
    out.body_local.push_back(c.local);
    out.bodies.push_back({out.convexes.back().get(), {}, {}, {}});
  }
  out.read_bodies(world);
  return out;
}

// ---- the scenes of one size, shared by its benchmarks -------------------------------------------

/// A collide scene per thread count and the Jolt description of the size, built when first
/// needed (a 1e5 scene takes a while); everything is dropped when the size changes.
struct SizeCache {
  int n = -1;
  std::map<int, std::unique_ptr<cli::Scene3D>> scenes;  // by threads
  std::unique_ptr<JoltScene> jolt;

  void reset(int size) {
    if (n == size) return;
    jolt.reset();
    scenes.clear();
    n = size;
  }
  cli::Scene3D& scene(int threads) {
    auto it = scenes.find(threads);
    if (it == scenes.end()) {
      it = scenes.emplace(threads, std::make_unique<cli::Scene3D>(cli::make_scene3d(scene_options(n, threads)))).first;
    }
    return *it->second;
  }
  /// The Jolt shapes, made from the collide scene of `threads` (statics and bodies' shapes are
  /// the same in every scene of the size: the same seed).
  JoltScene& jolt_description(int threads) {
    if (!jolt) jolt = std::make_unique<JoltScene>(jolt_scene(scene(threads).world));
    return *jolt;
  }
};

SizeCache& cache() {
  static SizeCache c;
  return c;
}

// ---- benchmarks -----------------------------------------------------------------------------------

void BM_CollideStep3(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  cache().reset(n);
  cli::Scene3D& scene = cache().scene(threads);
  bench::time_world_steps(state, scene.world, scene.scheduler.get(), kWarmupFrames, kDt);
}

void BM_JoltStep3(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  cache().reset(n);
  JoltScene& description = cache().jolt_description(threads);
  cli::Scene3D& scene = cache().scene(threads);  // stepped untimed beside Jolt (lockstep)
  if (static_cast<std::size_t>(scene.world.body_count()) != description.ids.size()) {
    state.SkipWithError("the scenes of one size differ: the Jolt bodies cannot follow this one");
    return;
  }
  description.read_bodies(scene.world);
  const jq::ScaleWorldPtr jolt = jq::make_scale_world(description.statics, description.bodies, threads);
  const auto frame = [&] {  // collide's state at the start of the frame, then collide's frame
    description.read_bodies(scene.world);
    jq::set_bodies(*jolt, description.bodies);
    scene.world.step(kDt);
  };
  for (int f = 0; f < kWarmupFrames; ++f) {
    frame();
    jq::step(*jolt, kDt);
  }

  double seconds = 0.0;
  std::int64_t manifolds = 0;
  std::uint32_t errors = 0;
  for (auto _ : state) {
    state.PauseTiming();
    frame();
    state.ResumeTiming();
    const auto t0 = Clock::now();
    const jq::ScaleStepOut out = jq::step(*jolt, kDt);
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    manifolds += out.added + out.persisted;
    errors |= out.errors;
  }
  const double frames = static_cast<double>(state.iterations());
  const double bodies = static_cast<double>(description.bodies.size());
  state.counters["bodies"] = bodies;
  state.counters["workers"] = threads;
  state.counters["ns_body"] = ns_per(seconds, frames, bodies);
  state.counters["contacts"] = static_cast<double>(manifolds) / (frames * bodies);
  if (errors != 0) state.SetLabel("Jolt capacity overflow, EPhysicsUpdateError " + std::to_string(errors));
}

void register_all() {
  for (const int n : {1000, 10000, 100000, 1000000}) {
    for (const int threads : {1, 2}) {
      for (const auto& [name, function] : {std::pair{"BM_CollideStep3", &BM_CollideStep3},
                                           std::pair{"BM_JoltStep3", &BM_JoltStep3}}) {
        benchmark::RegisterBenchmark(name, function)
            ->Args({n, threads})
            ->Iterations(timed_frames(n))
            ->Repetitions(repetitions(n))
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  jq::init();
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::add_instruction_sets("jolt", jq::instruction_set());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
