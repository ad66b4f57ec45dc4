// A world step at scale (issue 20): collide's World2D against Box2D v3 on the same bodies and
// statics, 1e3 .. 1e6 bodies, 1 and 2 threads, side by side in one run.
//
// The scene: `collide run`'s embedded default scene (cli::make_scene: tiles of concave obstacles,
// thin walls and sensor zones; circles, boxes, capsules, convex polygons and L-shaped compounds
// of convex pieces, 1% bullets; the world grows with the body count at constant density).
//
// BM_Spawn/N: cli::make_scene with N bodies (1 thread): the time to build the scene, per body
// placed.
//
// BM_CollideStep/N/T: World2D::step(1/60) on the scene make_scene gives (RunOptions::threads =
// T, its own oneTBB scheduler), as `collide run` steps it: integrate with continuous collision,
// statics (tree, early out, contact, push-out), body broad phase, body pairs (early out,
// contact, elastic response), contact events, and the world's independent end-of-step check
// (WorldOptions::check_each_step: on in make_scene; a brute-force tunnelling test, no peer has
// it). Counters: `ns_body` (ns per body per frame, everything), `ns_body_nocheck` (the same
// without StepStats::time_check), the phases per body, `bodies` placed, `workers` (the
// scheduler's worker count: 1 when the scene has none, i.e. `threads` is ignored).
//
// BM_CollideSpeedup/N (1e3 and 1e4): the two-thread speed-up measured within one process: three
// copies of the scene stepped in turn, 20 frames each per iteration, one on one thread pinned to
// each of the first two CPUs and one on two threads. Counters: ns_body_nocheck_cpu0 / _cpu1 /
// _2t, speedup_cpu0 / _cpu1 (each one-thread time over the two-thread time) and `speedup`, the
// harmonic mean of the one-thread times over the two-thread time (twice the parallel
// efficiency: the plain speed-up on two equal cores); probe_ps_cpu0 / _cpu1, each CPU's dispatch
// probe (instruction_set.hpp) before its one-thread block, averaged: above about 55 ps on the
// Zen 5 VM another tenant shares that CPU's core, and the row reads slow, the two-thread time
// most (rows with clean probes can read slow too: docs/performance.md, stop 94). The unpaired
// rows put BM_CollideStep/N/1 and /N/2 seconds apart, on whichever CPU the stepping thread had,
// and the VM's two vCPUs are not equally fast at a given moment (see the function).
//
// BM_Box2DStep/N/T: Box2D v3's b2World_Step(1/60, 4 substeps) on a world built from the same
// collide scene (its statics via static_def, its bodies via body_ids / shapes / transform /
// velocity / angular_velocity, before collide steps it). The bodies are dynamic (v3's kinematic
// bodies do not collide with statics), zero gravity, density 1, friction 0, restitution 1 (the
// elastic bounce collide's world does), sleeping off (collide has no sleep), contact and sensor
// events on (collide's world always reports them), maximum speed 1000 m/s (v3's default 400 would
// clamp the 600 m/s bullets), bullets flagged isBullet. Polygons keep their rounding radius;
// a static piece of more than 8 vertices (v3's limit) is split into a fan of convex pieces.
// T = 1: v3's serial fallback (no callbacks); T = 2: its task callbacks on oneTBB (a task_arena
// of T threads, one task_group per enqueued task; the stepping thread waits in finishTask and
// helps). BM_Box2DStepOwnScheduler/N/2: v3's built-in scheduler (workerCount 2, no callbacks),
// the reference for what the oneTBB callbacks cost or save.
// v3's size limit (found at stop 61): its solver cuts the bodies (and each colour's contacts)
// into at most 4 blocks a worker, a block's length in 16 bits (solver.c b2InitBlocks, checked by
// an assertion only), so above 4 x 65535 awake bodies a worker the lengths wrap and most bodies
// are never moved: on one worker 37,864 of 300,000 bodies and 213,578 of 1e6 moved in a step.
// Such a world does a fraction of the work. So v3 gets at least v3_workers(N) workers (4 at
// 1e6), run on T threads: for T = 1 by callbacks that run each task at once (v3's serial
// fallback forces one worker), for T = 2 on the same oneTBB arena (v3 guarantees progress with
// fewer threads than workers: the stepping thread takes worker 0's part); its built-in scheduler
// would start a thread a worker, so that row is skipped there. The counter `moved`: the share of
// v3's bodies whose position changed in one untimed step after the timed ones (1 when v3 moves
// them all; the scene's bodies all have speed).
//   Counters from b2World_GetProfile, per body per frame:
//    `ns_body`       the whole b2World_Step (our clock), solver included;
//    `b2_collision`  pairs + collide + transforms + refit + bullets + sensors: the step without
//                    the constraint solver (solverSetup, constraints, island split/sleep, events):
//                    broad-phase pair finding and proxy refit, narrow phase (every contact's
//                    manifold), continuous collision (fast bodies in transforms, bullets),
//                    sensor overlaps, and the integration of transforms and AABBs. The figure to
//                    set beside collide's `ns_body_nocheck`;
//    `b2_broad_narrow` pairs + collide: pair finding and narrow phase alone, beside collide's
//                    `statics` + `broad` + `pairs` (which also hold collide's push-out and bounce);
//    `b2_solver`     solverSetup + constraints (what collide does not do).
//   What is not the same: the trajectories (v3 solves contacts with a soft-step solver and
//   turns bodies about their centre of mass; collide bounces and pushes out), so after the first
//   frames the two worlds hold different states of similar density; the counters `contacts`
//   (collide: touching pairs incl. sensors; v3: contact pairs whose fat boxes overlap,
//   b2Counters::contactCount) say how much pair work each side saw.
//
// BM_CollideRayCast/N/L and BM_Box2DRayCast/N/L: a game's ray casts into the world (lasers, line
// of sight, picks): World2D::raycast (statics through their tree, bodies through the body broad
// phase, the exact cast of each candidate, the nearest hit with point and normal) against v3's
// b2World_CastRay with the closest-hit callback v3's b2World_CastRayClosest uses (sensors skipped
// in it: collide's default filter skips them too). Both worlds at the same poses: the collide
// scene stepped kRayWarmupFrames (so that its broad phase holds every body's box, as in a game
// between steps), then v3's world built from it, which casts against its trees as created (its
// bodies' boxes enlarged by its margin, as its step leaves them). kRays rays, the same on both
// sides: origins uniform in the scene's bounds, directions uniform, length L world units (10: a
// pick or a ground probe; 100: a laser or line of sight, a third of a 320 x 180 tile); each
// iteration casts the next ray. Counters, computed once outside the timing and the same on both
// rows: `hit_rate` (collide's), `v3_hit_rate`, and `agree`, the share of rays where both sides
// hit the same collider position within kRayAgreeUnits (or both miss).
//
// Memory: `heap_per_body` (glibc's heap in use, before and after building the world: collide's
// whole scene in BM_Spawn, v3's world from the same description in BM_Box2DStep), bytes.
//
// Each step benchmark runs kWarmupFrames untimed first (broad phases, caches, contacts settle),
// then a fixed number of timed frames (fewer at larger N). Real time (UseRealTime): T = 2 runs
// on two threads.
//
// Instruction sets: in the context block (collide's build; Box2D v3's as compiled by
// cmake/peers.cmake, COLLIDE_BOX2D_V3_ISA).
//
// Run: build/release/bench/bench_world_scale  (about 5-10 minutes on 2 cores; filter a size with
//      --benchmark_filter=/100000/ and so on). bench/world_scale_ratios.py prints the table.

#include <collide/core/task_scheduler.hpp>
#include <collide/world/world2d.hpp>

#include "run.hpp"

#include <benchmark/benchmark.h>
#include <box2d/box2d.h>
#include <box2d/constants.h>  // B2_MAX_TASKS
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>

#include "instruction_set.hpp"
#include "world_step_timing.hpp"

#include <malloc.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <random>
#include <utility>
#include <stdexcept>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#ifndef COLLIDE_BOX2D_V3_ISA
#define COLLIDE_BOX2D_V3_ISA "unknown"
#endif

namespace {

using namespace collide;
using bench::ns_per;
using Clock = std::chrono::steady_clock;

constexpr float kDt = 1.0f / 60.0f;
constexpr int kBox2DSubSteps = 4;  // v3's recommended count; it changes the solver, not collision
constexpr int kWarmupFrames = 3;
/// Bullets are the only bodies this fast in the default scene (600 m/s; the others 2..15 m/s):
/// how a body is recognised as one, since World2D does not give a body's filter or bullet flag.
constexpr float kBulletSpeed = 100.0f;
// The default scene's collision layers (apps/collide/run_scene.cpp): World2D gives statics'
// filters (static_def) but not bodies', so bodies get the scene's rule again here.
constexpr std::uint32_t kLayerWorld = 1u;
constexpr std::uint32_t kLayerBodies = 2u;
constexpr std::uint32_t kLayerGhosts = 4u;

/// Timed frames per size: about the same work per benchmark, and the whole run in minutes.
/// (At 1e3 a frame is under half a millisecond: 200 frames varied 2x from run to run.)
int timed_frames(int n) {
  if (n <= 1000) return 1000;
  if (n <= 10000) return 150;
  if (n <= 100000) return 20;
  return 5;
}
/// Repetitions where they are cheap: the small sizes are the noisy ones. The table takes medians.
int repetitions(int n) { return n <= 10000 ? 3 : 1; }

/// Bytes of glibc's heap in use, the blocks it maps for large requests included (v3's big arrays
/// are such blocks: without them a 1e6 world looked like 129 bytes per body). The same ruler as
/// bench_broad_phase's heap_in_use.
double heap_bytes() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd);
}

cli::RunOptions scene_options(int n, int threads) {
  cli::RunOptions o;
  o.bodies = n;
  o.threads = threads;
  o.progress = false;
  return o;
}

// ---- Box2D v3: the collide scene as v3 shapes --------------------------------------------------

using V3Shape = std::variant<b2Circle, b2Capsule, b2Polygon, b2Segment>;

struct V3Body {
  b2Vec2 position;
  b2Rot rotation;
  b2Vec2 velocity;
  float angular_velocity;
  bool bullet;
  std::uint32_t first_shape, shape_count;  // into V3Scene::shapes
};

struct V3Static {
  b2Vec2 position;
  b2Rot rotation;
  bool sensor;
  CollisionFilter filter;
  std::uint32_t first_shape, shape_count;
};

/// The scene in v3's own shape types, a few hundred bytes per body (collide's Polygon holds 64
/// vertex slots: copies of collide's bodies would take gigabytes at 1e6).
struct V3Scene {
  std::vector<V3Shape> shapes;
  std::vector<V3Body> bodies;
  std::vector<V3Static> statics;
  int bullets = 0;
  int split_pieces = 0;  ///< static pieces of more than 8 vertices split for v3
};

b2Vec2 v3(Vec2 v) { return {v.x, v.y}; }

/// A v3 polygon from the vertices [first, first + count) of `p` (count <= 8, convex, CCW).
b2Polygon v3_polygon(const Polygon& p, int first, int count, const int* index = nullptr) {
  b2Vec2 points[B2_MAX_POLYGON_VERTICES];
  for (int i = 0; i < count; ++i) points[i] = v3(p.vertices[static_cast<std::size_t>(index ? index[i] : first + i)]);
  const b2Hull hull = b2ComputeHull(points, count);
  if (hull.count < 3) throw std::runtime_error("Box2D v3: b2ComputeHull refused a collide polygon");
  return b2MakePolygon(&hull, p.radius);
}

/// Appends `shape` as v3 shapes: one, or a fan of pieces for a polygon over v3's 8 vertices
/// (fan triangles grouped 6 at a time: pieces 0, i, ..., i + 6; convex as the polygon is).
int append_v3(std::vector<V3Shape>& out, const Shape2D& shape, int* split) {
  return std::visit(
      [&](const auto& s) -> int {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Circle>) {
          out.emplace_back(b2Circle{v3(s.center), s.radius});
        } else if constexpr (std::is_same_v<T, Capsule>) {
          out.emplace_back(b2Capsule{v3(s.a), v3(s.b), s.radius});
        } else if constexpr (std::is_same_v<T, Segment>) {
          out.emplace_back(b2Segment{v3(s.a), v3(s.b)});
        } else {
          if (s.count <= B2_MAX_POLYGON_VERTICES) {
            out.emplace_back(v3_polygon(s, 0, s.count));
            return 1;
          }
          int pieces = 0;
          for (int i = 1; i + 1 < s.count; i += B2_MAX_POLYGON_VERTICES - 2) {
            int index[B2_MAX_POLYGON_VERTICES];
            int k = 0;
            index[k++] = 0;
            for (int j = i; j < s.count && k < B2_MAX_POLYGON_VERTICES; ++j) index[k++] = j;
            out.emplace_back(v3_polygon(s, 0, k, index));
            ++pieces;
          }
          ++*split;
          return pieces;
        }
        return 1;
      },
      shape);
}

/// The collide world's statics and (unstepped) bodies as v3 definitions.
V3Scene v3_scene(const World2D& world) {
  V3Scene out;
  out.statics.reserve(static_cast<std::size_t>(world.static_count()));
  for (int i = 0; i < world.static_count(); ++i) {
    const StaticDef& def = world.static_def(StaticId{static_cast<std::uint32_t>(i)});
    V3Static st{v3(def.transform.p), {def.transform.q.c, def.transform.q.s}, def.sensor, def.filter,
                static_cast<std::uint32_t>(out.shapes.size()), 0};
    for (const Shape2D& s : def.shapes) st.shape_count += static_cast<std::uint32_t>(append_v3(out.shapes, s, &out.split_pieces));
    out.statics.push_back(st);
  }
  const std::vector<BodyId> ids = world.body_ids();
  out.bodies.reserve(ids.size());
  for (const BodyId id : ids) {
    const Transform& xf = world.transform(id);
    const Vec2 v = world.velocity(id);
    const bool bullet = std::hypot(v.x, v.y) > kBulletSpeed;
    V3Body b{v3(xf.p), {xf.q.c, xf.q.s}, v3(v), world.angular_velocity(id), bullet,
             static_cast<std::uint32_t>(out.shapes.size()), 0};
    for (const Shape2D& s : world.shapes(id)) b.shape_count += static_cast<std::uint32_t>(append_v3(out.shapes, s, &out.split_pieces));
    out.bodies.push_back(b);
    out.bullets += bullet ? 1 : 0;
  }
  return out;
}

void create_v3_shape(b2BodyId body, const b2ShapeDef& def, const V3Shape& shape) {
  std::visit(
      [&](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, b2Circle>) b2CreateCircleShape(body, &def, &s);
        else if constexpr (std::is_same_v<T, b2Capsule>) b2CreateCapsuleShape(body, &def, &s);
        else if constexpr (std::is_same_v<T, b2Polygon>) b2CreatePolygonShape(body, &def, &s);
        else b2CreateSegmentShape(body, &def, &s);
      },
      shape);
}

/// v3's task callbacks on oneTBB. v3 enqueues tasks from the stepping thread only (parallel-for
/// chunks, the solver's workers, the tree rebuild, the island split) and finishes each exactly
/// once; a task_group per enqueued task, taken from a pool reset before each step, so finishing
/// one waits for that task alone (the stepping thread helps with queued work while it waits).
/// The step runs inside the arena so that its tasks go to the arena's T threads.
class TbbTasks {
 public:
  explicit TbbTasks(int threads) : arena_(threads) {}

  static void* enqueue(b2TaskCallback* task, void* task_context, void* user_context) {
    auto& self = *static_cast<TbbTasks*>(user_context);
    const int slot = self.next_.fetch_add(1, std::memory_order_relaxed);
    if (slot >= kSlots) {  // pool exhausted: run it here (v3: a null handle means "done")
      task(task_context);
      return nullptr;
    }
    tbb::task_group& group = self.groups_[static_cast<std::size_t>(slot)];
    group.run([task, task_context] { task(task_context); });
    return &group;
  }
  static void finish(void* handle, void* /*user_context*/) { static_cast<tbb::task_group*>(handle)->wait(); }

  template <class F>
  void step(F&& f) {
    next_.store(0, std::memory_order_relaxed);
    arena_.execute(f);
  }

 private:
  // v3 caps a step's parallel-for tasks at B2_MAX_TASKS; the solver's and the tree's come on top.
  static constexpr int kSlots = 2 * B2_MAX_TASKS;
  tbb::task_arena arena_;
  std::atomic<int> next_{0};
  std::array<tbb::task_group, kSlots> groups_;
};

struct V3World {
  b2WorldId id{};
  std::vector<b2BodyId> bodies;  ///< the scene's bodies, in its order
  std::unique_ptr<TbbTasks> tasks;
  V3World() = default;
  V3World(const V3World&) = delete;
  V3World& operator=(const V3World&) = delete;
  ~V3World() {
    if (b2World_IsValid(id)) b2DestroyWorld(id);
  }
  void step() {
    if (tasks) {
      tasks->step([this] { b2World_Step(id, kDt, kBox2DSubSteps); });
    } else {
      b2World_Step(id, kDt, kBox2DSubSteps);
    }
  }
};

/// Blocks a worker and the longest block of v3's solver (solver.c: maxBlockCount = 4 *
/// workerCount; a block's count is a uint16_t).
constexpr std::size_t kV3BlocksPerWorker = 4;
constexpr std::size_t kV3MaxBlockLength = 65535;

/// The fewest workers with which v3 moves every one of `bodies` awake bodies (see the file
/// comment), and never fewer than `threads`.
int v3_workers(std::size_t bodies, int threads) {
  const std::size_t per_worker = kV3BlocksPerWorker * kV3MaxBlockLength;
  return std::max(threads, static_cast<int>((bodies + per_worker - 1) / per_worker));
}

/// v3's task callbacks for one thread with more than one worker: each task runs at once (a
/// null handle tells v3 it is done), as v3's serial fallback does with its single worker.
void* run_now(b2TaskCallback* task, void* task_context, void* /*user_context*/) {
  task(task_context);
  return nullptr;
}
void finish_nothing(void* /*handle*/, void* /*user_context*/) {}

/// `own_scheduler`: v3's built-in scheduler for threads > 1 instead of the oneTBB callbacks.
std::unique_ptr<V3World> make_v3_world(const V3Scene& scene, int threads, bool own_scheduler) {
  auto w = std::make_unique<V3World>();
  b2WorldDef def = b2DefaultWorldDef();
  def.gravity = {0.0f, 0.0f};
  def.enableSleep = false;
  def.maximumLinearSpeed = 1000.0f;
  def.workerCount = v3_workers(scene.bodies.size(), threads);
  if (threads > 1 && !own_scheduler) {
    w->tasks = std::make_unique<TbbTasks>(threads);
    def.enqueueTask = &TbbTasks::enqueue;
    def.finishTask = &TbbTasks::finish;
    def.userTaskContext = w->tasks.get();
  } else if (threads == 1 && def.workerCount > 1) {
    def.enqueueTask = &run_now;
    def.finishTask = &finish_nothing;
  }
  w->id = b2CreateWorld(&def);

  for (const V3Static& st : scene.statics) {
    b2BodyDef bd = b2DefaultBodyDef();
    bd.type = b2_staticBody;
    bd.position = st.position;
    bd.rotation = st.rotation;
    const b2BodyId body = b2CreateBody(w->id, &bd);
    b2ShapeDef sd = b2DefaultShapeDef();
    sd.filter.categoryBits = st.filter.layer;
    sd.filter.maskBits = st.filter.mask;
    sd.isSensor = st.sensor;
    sd.enableSensorEvents = st.sensor;
    for (std::uint32_t k = 0; k < st.shape_count; ++k) create_v3_shape(body, sd, scene.shapes[st.first_shape + k]);
  }
  for (const V3Body& b : scene.bodies) {
    b2BodyDef bd = b2DefaultBodyDef();
    bd.type = b2_dynamicBody;
    bd.position = b.position;
    bd.rotation = b.rotation;
    bd.linearVelocity = b.velocity;
    bd.angularVelocity = b.angular_velocity;
    bd.isBullet = b.bullet;
    bd.enableSleep = false;
    const b2BodyId body = b2CreateBody(w->id, &bd);
    w->bodies.push_back(body);
    b2ShapeDef sd = b2DefaultShapeDef();
    sd.density = 1.0f;
    sd.material.friction = 0.0f;
    sd.material.restitution = 1.0f;
    sd.filter.categoryBits = b.bullet ? kLayerGhosts : kLayerBodies;
    sd.filter.maskBits = b.bullet ? kLayerWorld : 0xffffffffu;
    sd.enableContactEvents = true;
    sd.enableSensorEvents = true;
    for (std::uint32_t k = 0; k < b.shape_count; ++k) create_v3_shape(body, sd, scene.shapes[b.first_shape + k]);
  }
  return w;
}

// ---- The scenes of one size, shared by its benchmarks -------------------------------------------

/// Scenes are built once per size and thread count (a 1e6 scene takes a while), the v3
/// description from the first, unstepped one; everything is dropped when the size changes.
struct SizeCache {
  int n = -1;
  std::map<int, std::unique_ptr<cli::Scene>> scenes;  // by threads
  std::unique_ptr<V3Scene> v3;
  int requested_bullets = 0;

  void reset(int size) {
    if (n == size) return;
    scenes.clear();
    v3.reset();
    n = size;
  }
  /// Takes a freshly made scene: the v3 description is read from it before anyone steps it.
  void adopt(int threads, std::unique_ptr<cli::Scene> scene) {
    if (!v3) {
      v3 = std::make_unique<V3Scene>(v3_scene(scene->world));
      requested_bullets = scene->bullets;
    }
    scenes[threads] = std::move(scene);
  }
  cli::Scene& scene(int threads) {
    auto it = scenes.find(threads);
    if (it == scenes.end()) {
      adopt(threads, std::make_unique<cli::Scene>(cli::make_scene(scene_options(n, threads))));
      it = scenes.find(threads);
    }
    return *it->second;
  }
  const V3Scene& v3_description() {
    if (!v3) scene(1);
    return *v3;
  }
};

SizeCache& cache() {
  static SizeCache c;
  return c;
}

// ---- World ray casts ------------------------------------------------------------------------------

/// Frames the ray casts' collide scene is stepped before casting (one makes the broad phase
/// current; more let the bodies leave their spawn places).
constexpr int kRayWarmupFrames = 3;
/// Rays a set: more than the branch predictor and the caches learn.
constexpr int kRays = 4096;
/// Two hits agree when their points are this close (world units; the scene's bodies are 1-4
/// units across).
constexpr float kRayAgreeUnits = 1e-3f;

/// Both worlds of the ray casts at the same poses, and the rays.
struct RayWorlds {
  int size = -1;  // the bodies asked for
  std::unique_ptr<cli::Scene> scene;
  std::unique_ptr<V3World> v3;
  std::map<int, std::vector<Ray>> rays;  // by length
  std::map<int, std::array<double, 3>> counters;  // by length: hit_rate, v3_hit_rate, agree
};

/// v3's closest-hit callback (b2RayCastClosestFcn: an initial overlap, fraction 0, is skipped),
/// skipping sensors as collide's default QueryFilter does.
struct V3Closest {
  b2Pos point{};
  float fraction = 1.0f;
  bool hit = false;
  static float report(b2ShapeId shape, b2Pos point, b2Vec2 /*normal*/, float fraction, void* context) {
    if (fraction == 0.0f || b2Shape_IsSensor(shape)) return -1.0f;
    auto& self = *static_cast<V3Closest*>(context);
    self.point = point;
    self.fraction = fraction;
    self.hit = true;
    return fraction;
  }
};

V3Closest v3_cast(const V3World& w, const Ray& ray) {
  V3Closest closest;
  b2World_CastRay(w.id, v3(ray.origin), v3(ray.translation), b2DefaultQueryFilter(), &V3Closest::report, &closest);
  return closest;
}

RayWorlds& ray_worlds(int n) {
  static RayWorlds r;
  if (r.size != n) {
    r = RayWorlds{.size = n};
    r.scene = std::make_unique<cli::Scene>(cli::make_scene(scene_options(n, 1)));
    for (int f = 0; f < kRayWarmupFrames; ++f) r.scene->world.step(kDt);
    r.v3 = make_v3_world(v3_scene(r.scene->world), 1, false);
  }
  return r;
}

const std::vector<Ray>& ray_set(RayWorlds& r, int length) {
  auto it = r.rays.find(length);
  if (it != r.rays.end()) return it->second;
  std::mt19937 rng(0x5eed0000u + static_cast<std::uint32_t>(length));
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const Aabb& b = r.scene->bounds;
  std::vector<Ray> rays;
  rays.reserve(kRays);
  for (int i = 0; i < kRays; ++i) {
    const Vec2 origin{b.min.x + unit(rng) * (b.max.x - b.min.x), b.min.y + unit(rng) * (b.max.y - b.min.y)};
    const float angle = 6.2831853f * unit(rng);
    rays.push_back(Ray{origin, static_cast<float>(length) * Vec2{std::cos(angle), std::sin(angle)}});
  }
  // The counters, once: both sides cast every ray.
  std::size_t hits = 0, v3_hits = 0, agree = 0;
  for (const Ray& ray : rays) {
    const auto h = r.scene->world.raycast(ray);
    const V3Closest v = v3_cast(*r.v3, ray);
    hits += h ? 1u : 0u;
    v3_hits += v.hit ? 1u : 0u;
    if (h.has_value() != v.hit) continue;
    if (!h || std::hypot(h->hit.point.x - v.point.x, h->hit.point.y - v.point.y) <= kRayAgreeUnits) ++agree;
  }
  const double count = static_cast<double>(rays.size());
  r.counters[length] = {hits / count, v3_hits / count, agree / count};
  return r.rays.emplace(length, std::move(rays)).first->second;
}

void ray_counters(benchmark::State& state, const RayWorlds& r, int length) {
  const std::array<double, 3>& c = r.counters.at(length);
  state.counters["hit_rate"] = c[0];
  state.counters["v3_hit_rate"] = c[1];
  state.counters["agree"] = c[2];
  state.counters["bodies"] = r.scene->world.body_count();
}

void BM_CollideRayCast(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int length = static_cast<int>(state.range(1));
  RayWorlds& r = ray_worlds(n);
  const std::vector<Ray>& rays = ray_set(r, length);
  const World2D& world = r.scene->world;
  std::size_t i = 0;
  for (auto _ : state) {
    auto h = world.raycast(rays[i]);
    benchmark::DoNotOptimize(h);
    i = (i + 1) % rays.size();
  }
  ray_counters(state, r, length);
}

void BM_Box2DRayCast(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int length = static_cast<int>(state.range(1));
  RayWorlds& r = ray_worlds(n);
  const std::vector<Ray>& rays = ray_set(r, length);
  std::size_t i = 0;
  for (auto _ : state) {
    V3Closest h = v3_cast(*r.v3, rays[i]);
    benchmark::DoNotOptimize(h);
    i = (i + 1) % rays.size();
  }
  ray_counters(state, r, length);
}

// ---- Benchmarks ---------------------------------------------------------------------------------

void BM_Spawn(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  cache().reset(n);
  cache().scenes.erase(1);  // time a fresh build; the last one stays for the step benchmarks
  std::unique_ptr<cli::Scene> scene;
  double seconds = 0.0, heap = 0.0;
  for (auto _ : state) {
    scene.reset();
    const double heap0 = heap_bytes();
    const auto t0 = Clock::now();
    scene = std::make_unique<cli::Scene>(cli::make_scene(scene_options(n, 1)));
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    heap = heap_bytes() - heap0;
  }
  const int placed = scene->world.body_count();
  state.counters["bodies"] = placed;
  state.counters["statics"] = scene->world.static_count();
  state.counters["ns_body"] = ns_per(seconds, static_cast<double>(state.iterations()), placed);
  state.counters["heap_per_body"] = heap / placed;
  if (placed < n * 9 / 10) {
    state.SetLabel("scene did not grow: " + std::to_string(placed) + " of " + std::to_string(n) + " placed");
  }
  cache().v3.reset();  // re-read from this scene
  cache().adopt(1, std::move(scene));
}

void BM_CollideStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  cache().reset(n);
  cli::Scene& scene = cache().scene(threads);
  bench::time_world_steps(state, scene.world, scene.scheduler.get(), kWarmupFrames, kDt);
}

/// Frames a world steps before the next takes its turn in BM_CollideSpeedup (about 5 ms at 1e3
/// bodies: the host's slow and fast phases last seconds, so every side of an iteration sees the
/// same phase; each world's own data is back in the cache after its first frame).
constexpr int kSpeedupBlockFrames = 20;

/// The calling thread's CPU affinity set to `cpus` (true when the system took it).
bool pin_this_thread(const cpu_set_t& cpus) {
  return pthread_setaffinity_np(pthread_self(), sizeof(cpu_set_t), &cpus) == 0;
}

void BM_CollideSpeedup(benchmark::State& state) {
  // Three copies of the scene stepped in turn, kSpeedupBlockFrames frames each per iteration:
  // one on one thread pinned to the first CPU of the process's set, one on one thread pinned
  // to the second, one on two threads (unpinned). Why: on the 2-vCPU AMD EPYC VM the two vCPUs
  // are not equally fast at a given moment (two one-thread runs at once, one pinned to each,
  // read 341 and 245 ns a body, later 307 and 303), and one thread runs on either, so the
  // one-thread time of a run, and the speed-up against it, depended on where the stepping
  // thread happened to be: 1.34-1.47x in processes whose one-thread frames were fast, 1.51-1.74x
  // where they were slow, about steady within each process. Counters: ns_body_nocheck_cpu0 /
  // _cpu1 / _2t, the speed-up against each (speedup_cpu0, speedup_cpu1), and `speedup`: the
  // harmonic mean of the two one-thread times over the two-thread time, which is twice the
  // parallel efficiency (two cores of speeds s0 and s1 can at best do the work in 1 / (s0 + s1)
  // of the time one of speed 1 takes) and equals the plain speed-up when the cores are alike.
  // All three worlds start alike and step the same frames (the step is deterministic for any
  // thread count: checked here by their state hashes).
  const int n = static_cast<int>(state.range(0));
  cpu_set_t all;
  CPU_ZERO(&all);
  if (pthread_getaffinity_np(pthread_self(), sizeof(cpu_set_t), &all) != 0 || CPU_COUNT(&all) < 2) {
    state.SkipWithError("needs two CPUs in the process's affinity set");
    return;
  }
  std::array<cpu_set_t, 2> single{};
  for (int cpu = 0, found = 0; cpu < CPU_SETSIZE && found < 2; ++cpu) {
    if (!CPU_ISSET(cpu, &all)) continue;
    CPU_ZERO(&single[static_cast<std::size_t>(found)]);
    CPU_SET(cpu, &single[static_cast<std::size_t>(found)]);
    ++found;
  }
  cli::Scene one_a = cli::make_scene(scene_options(n, 1));
  cli::Scene one_b = cli::make_scene(scene_options(n, 1));
  cli::Scene two = cli::make_scene(scene_options(n, 2));
  // (warm-up unpinned: oneTBB starts its worker here, with the whole affinity set)
  for (int f = 0; f < kWarmupFrames; ++f) {
    one_a.world.step(kDt);
    one_b.world.step(kDt);
    two.world.step(kDt);
  }
  const auto block = [](cli::Scene& scene, double& nocheck) {
    const auto t0 = Clock::now();
    double check = 0.0;
    for (int f = 0; f < kSpeedupBlockFrames; ++f) {
      scene.world.step(kDt);
      check += scene.world.last_step_stats().time_check;
    }
    nocheck += std::chrono::duration<double>(Clock::now() - t0).count() - check;
  };
  double a_nocheck = 0.0, b_nocheck = 0.0, two_nocheck = 0.0;
  // Each CPU's dispatch probe (one 2 ms run) before its block: the host's other tenants come
  // and go on either vCPU's core within minutes, and a shared CPU slows every side of a row
  // that runs on it (the two-thread world most: its serial parts and its last range wait on
  // whichever CPU is slow). Outside the blocks' clocks.
  double a_probe = 0.0, b_probe = 0.0;
  bool pinned = true;
  for (auto _ : state) {
    pinned &= pin_this_thread(single[0]);
    a_probe += bench::host_dispatch_probe_ps(1);
    block(one_a, a_nocheck);
    pinned &= pin_this_thread(single[1]);
    b_probe += bench::host_dispatch_probe_ps(1);
    block(one_b, b_nocheck);
    pinned &= pin_this_thread(all);
    block(two, two_nocheck);
  }
  pin_this_thread(all);
  const double frames = static_cast<double>(state.iterations()) * kSpeedupBlockFrames;
  const double bodies = two.world.body_count();
  state.counters["bodies"] = bodies;
  state.counters["workers"] = two.scheduler != nullptr ? two.scheduler->worker_count() : 1;
  state.counters["ns_body_nocheck_cpu0"] = ns_per(a_nocheck, frames, bodies);
  state.counters["ns_body_nocheck_cpu1"] = ns_per(b_nocheck, frames, bodies);
  state.counters["ns_body_nocheck_2t"] = ns_per(two_nocheck, frames, bodies);
  state.counters["probe_ps_cpu0"] = a_probe / static_cast<double>(state.iterations());
  state.counters["probe_ps_cpu1"] = b_probe / static_cast<double>(state.iterations());
  if (two_nocheck > 0.0) {
    state.counters["speedup_cpu0"] = a_nocheck / two_nocheck;
    state.counters["speedup_cpu1"] = b_nocheck / two_nocheck;
    const double harmonic = a_nocheck + b_nocheck > 0.0 ? 2.0 * a_nocheck * b_nocheck / (a_nocheck + b_nocheck) : 0.0;
    state.counters["speedup"] = harmonic / two_nocheck;
  }
  if (!pinned) state.SkipWithError("the system refused to pin the stepping thread to one CPU");
  const std::uint64_t hash = two.world.state_hash();
  if (one_a.world.state_hash() != hash || one_b.world.state_hash() != hash) {
    state.SkipWithError("the worlds' states differ");
  }
}

void box2d_step(benchmark::State& state, bool own_scheduler) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  cache().reset(n);
  const V3Scene& description = cache().v3_description();
  if (description.bullets != cache().requested_bullets) {
    state.SkipWithError("Box2D v3: bodies faster than kBulletSpeed are not the scene's bullets");
    return;
  }
  if (own_scheduler && v3_workers(description.bodies.size(), threads) > threads) {
    state.SkipWithError("Box2D v3's built-in scheduler would need a thread for each of the workers this size needs");
    return;
  }
  const double heap0 = heap_bytes();
  const std::unique_ptr<V3World> w = make_v3_world(description, threads, own_scheduler);
  const double heap = heap_bytes() - heap0;
  for (int f = 0; f < kWarmupFrames; ++f) w->step();

  b2Profile sum{};
  double seconds = 0.0;
  std::int64_t contacts = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    w->step();
    seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    const b2Profile p = b2World_GetProfile(w->id);
    sum.pairs += p.pairs;
    sum.collide += p.collide;
    sum.transforms += p.transforms;
    sum.refit += p.refit;
    sum.bullets += p.bullets;
    sum.sensors += p.sensors;
    sum.solverSetup += p.solverSetup;
    sum.constraints += p.constraints;
    contacts += b2World_GetCounters(w->id).contactCount;
  }
  // Did v3 move its bodies? One more step, untimed, position by position.
  std::vector<b2Vec2> before;
  before.reserve(w->bodies.size());
  for (const b2BodyId b : w->bodies) before.push_back(b2Body_GetPosition(b));
  w->step();
  std::size_t moved = 0;
  for (std::size_t i = 0; i < w->bodies.size(); ++i) {
    const b2Vec2 p = b2Body_GetPosition(w->bodies[i]);
    moved += (p.x != before[i].x || p.y != before[i].y) ? 1u : 0u;
  }
  const double frames = static_cast<double>(state.iterations());
  const double bodies = static_cast<double>(description.bodies.size());
  const auto ms = [](float milliseconds) { return 1e-3 * milliseconds; };
  state.counters["moved"] = static_cast<double>(moved) / bodies;
  state.counters["v3_workers"] = v3_workers(description.bodies.size(), threads);
  state.counters["bodies"] = bodies;
  state.counters["workers"] = threads;
  state.counters["heap_per_body"] = heap / bodies;
  state.counters["ns_body"] = ns_per(seconds, frames, bodies);
  state.counters["b2_collision"] = ns_per(
      ms(sum.pairs + sum.collide + sum.transforms + sum.refit + sum.bullets + sum.sensors), frames, bodies);
  state.counters["b2_broad_narrow"] = ns_per(ms(sum.pairs + sum.collide), frames, bodies);
  state.counters["b2_pairs"] = ns_per(ms(sum.pairs), frames, bodies);
  state.counters["b2_collide"] = ns_per(ms(sum.collide), frames, bodies);
  state.counters["b2_transforms"] = ns_per(ms(sum.transforms), frames, bodies);
  state.counters["b2_solver"] = ns_per(ms(sum.solverSetup + sum.constraints), frames, bodies);
  state.counters["contacts"] = static_cast<double>(contacts) / (frames * bodies);
  // The broad phase's shape: a degenerate tree would explain a pair time growing faster than N.
  const b2Counters counters = b2World_GetCounters(w->id);
  state.counters["tree_height"] = counters.treeHeight;
  state.counters["static_tree_height"] = counters.staticTreeHeight;
  if (description.split_pieces > 0) {
    state.SetLabel(std::to_string(description.split_pieces) + " static pieces split (over 8 vertices)");
  }
}

void BM_Box2DStep(benchmark::State& state) { box2d_step(state, false); }
void BM_Box2DStepOwnScheduler(benchmark::State& state) { box2d_step(state, true); }

void register_all() {
  for (const int n : {1000, 10000, 100000, 1000000}) {
    const int frames = timed_frames(n);
    benchmark::RegisterBenchmark("BM_Spawn", BM_Spawn)
        ->Arg(n)
        ->Iterations(n <= 10000 ? 5 : 1)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    for (const int threads : {1, 2}) {
      benchmark::RegisterBenchmark("BM_CollideStep", BM_CollideStep)
          ->Args({n, threads})
          ->Iterations(frames)
          ->Repetitions(repetitions(n))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark("BM_Box2DStep", BM_Box2DStep)
          ->Args({n, threads})
          ->Iterations(frames)
          ->Repetitions(repetitions(n))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    benchmark::RegisterBenchmark("BM_Box2DStepOwnScheduler", BM_Box2DStepOwnScheduler)
        ->Args({n, 2})
        ->Iterations(frames)
        ->Repetitions(repetitions(n))
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    if (n <= 100000) {
      for (const int length : {10, 100}) {
        for (const auto& [name, fn] : {std::pair{"BM_CollideRayCast", &BM_CollideRayCast},
                                       std::pair{"BM_Box2DRayCast", &BM_Box2DRayCast}}) {
          benchmark::RegisterBenchmark(name, fn)->Args({n, length})->Unit(benchmark::kNanosecond);
        }
      }
    }
    if (n <= 10000) {  // (from 1e4 up the unpaired rows read 1.8x or more; 1e3 is the question)
      benchmark::RegisterBenchmark("BM_CollideSpeedup", BM_CollideSpeedup)
          ->Arg(n)
          ->Iterations(frames / kSpeedupBlockFrames)
          ->Repetitions(repetitions(n))
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const b2Version version = b2GetVersion();
  collide::bench::add_instruction_sets("box2d v3", COLLIDE_BOX2D_V3_ISA);
  benchmark::AddCustomContext("box2d v3 version", std::to_string(version.major) + "." +
                                                      std::to_string(version.minor) + "." +
                                                      std::to_string(version.revision));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
