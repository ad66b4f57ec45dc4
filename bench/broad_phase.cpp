// The broad phase race: per frame (update the structure with the moved boxes, find every
// overlapping pair) for N = 1e3 .. 1e6 moving boxes, collide's structures and the peers side by
// side on the same boxes in the same run.
//
// 2D world (against Box2D v3's b2DynamicTree as its broad phase drives it, Box2D 2.4 and
// Chipmunk 7): boxes of half size 0.25..0.75, 4 square units of
// world per object; 3D world (against Bullet 3 and FCL 0.7): the same sizes, 8 cubic units per
// object. Each object keeps a random velocity of up to 0.05 units per frame per axis and bounces
// off the world's edge. Every contender produces the full set of overlapping pairs each frame
// (the peers' candidates are filtered by the exact test, as a game would), with two
// exceptions: Bullet's pair cache holds the pairs of its margin-grown boxes (a superset, ~30%
// more; counted, not filtered), and "Box2D_b2BroadPhase_new_pairs", Box2D's own incremental
// scheme, reports only the pairs new this frame and leaves the rest to its contact list: it
// does less work, is shown, but is not used for the ratios. The "pairs" counter is taken from
// the same untimed warm-up frame for everyone, as a check that the sets agree.
//
// The motion itself (the game's integration step, before the broad phase) runs between frames
// outside the timing, as the issue defines a frame: update + pair finding. It costs 1-4 ns per
// object (more at 1e6, where it streams the boxes from memory); "move/<D>D/N" times it alone,
// so that the figures with the motion inside can be read off too. A paused timer costs a
// fraction of a microsecond per frame, for every contender alike (under 4% of the fastest
// frame at 1e3, under 0.5% from 1e4).
// Slow peers are not run where one frame would take many seconds (listed at registration).
//
// A structure with a combined call (LooseGrid: update_and_find_pairs, build_and_find_pairs; the
// same pairs in the same order) is timed through it, as a game would call it.
//
// "full_rebuild/...": collide's grids, build from a fresh span of boxes + find_pairs, the
// per-object figure the broad-phase issue sets a target for; "rebuild_build_only/...": the
// build alone (see rebuild_benchmark). The one peer that rebuilds from scratch each frame,
// Chipmunk's cpSpaceHash (2D), runs beside them (chipmunk_rebuild_benchmark); the 3D peers
// update incrementally and have no rebuild to compare.
//
// Memory per object: "heap_per_object" for every contender, from glibc's count of the heap in
// use before the contender is made and after its first frame.
//
// Run: bench_broad_phase --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/hierarchical_grid.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/broad/sweep_and_prune.hpp>
#include <collide/broad/temporal_broad_phase.hpp>

#include "box2d_v3/queries.hpp"

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"
#include <box2d/b2_broad_phase.h>
#include <box2d/b2_dynamic_tree.h>
#include <btBulletCollisionCommon.h>
#include <chipmunk/chipmunk.h>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/broadphase/broadphase_spatialhash.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/narrowphase/collision_object.h>

#include <malloc.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace {

using namespace collide;

// ---- the moving world ------------------------------------------------------------------------

template <int D>
struct World {
  std::vector<AabbN<D>> boxes;
  std::vector<VecN<D>> velocity;
  float half_extent = 0.0f;  // the world is [-half_extent, half_extent]^D

  void step() {
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const VecN<D> c = boxes[i].center() + velocity[i];
      for (int k = 0; k < D; ++k) {
        if (c[k] > half_extent || c[k] < -half_extent) velocity[i][k] = -velocity[i][k];
      }
      boxes[i].min += velocity[i];
      boxes[i].max += velocity[i];
    }
  }
};

constexpr float kMaxSpeed = 0.05f;  // units per frame per axis

template <int D>
World<D> make_world(int n) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  World<D> w;
  const float per_object = D == 2 ? 4.0f : 8.0f;
  w.half_extent = 0.5f * std::pow(per_object * static_cast<float>(n), 1.0f / D);
  for (int i = 0; i < n; ++i) {
    VecN<D> c, h, v;
    for (int k = 0; k < D; ++k) {
      c[k] = unit(rng) * w.half_extent;
      h[k] = 0.5f + 0.25f * unit(rng);
      v[k] = kMaxSpeed * unit(rng);
    }
    w.boxes.push_back({c - h, c + h});
    w.velocity.push_back(v);
  }
  return w;
}

// ---- collide ---------------------------------------------------------------------------------

// A structure with a combined update + find_pairs (LooseGrid), which a game would call.
template <class BP, int D>
constexpr bool kHasCombined = requires(BP& bp, std::span<const AabbN<D>> boxes, PairList& pairs) {
  bp.update_and_find_pairs(boxes, pairs);
  bp.build_and_find_pairs(boxes, pairs);
};

template <int D, class BP>
struct Collide {
  BP bp;
  PairList pairs;
  void init(const World<D>& w) { bp.build(w.boxes); }
  std::size_t frame(const World<D>& w) {
    if constexpr (kHasCombined<BP, D>) {
      bp.update_and_find_pairs(w.boxes, pairs);
    } else {
      bp.update(w.boxes);
      bp.find_pairs(pairs);
    }
    return pairs.size();
  }
  [[nodiscard]] std::size_t memory() const { return bp.memory_bytes() + pairs.capacity() * sizeof(BroadPair); }
};

template <int D>
struct CollideTemporal {
  TemporalBroadPhaseN<D> bp;
  PairList pairs;
  double time = 0.0;
  void init(const World<D>& w) {
    // Bound: the largest per-axis step, plus the float rounding of a step at the world's edge.
    const float bound = kMaxSpeed * 1.01f + 4e-7f * w.half_extent;
    bp.build(w.boxes, std::vector<float>(w.boxes.size(), bound), time);
  }
  std::size_t frame(const World<D>& w) {
    time += 1.0;
    bp.update(w.boxes, time);
    bp.find_pairs(pairs);
    return pairs.size();
  }
  [[nodiscard]] std::size_t memory() const { return bp.memory_bytes() + pairs.capacity() * sizeof(BroadPair); }
};

// ---- Box2D 2.4 -------------------------------------------------------------------------------

b2AABB to_b2(const Aabb& b) {
  b2AABB a;
  a.lowerBound.Set(b.min.x, b.min.y);
  a.upperBound.Set(b.max.x, b.max.y);
  return a;
}

// b2DynamicTree with fat AABBs, moved each frame; then every object queries the tree, and the
// exact boxes decide: the full pair set, as collide produces.
struct Box2DTree {
  b2DynamicTree tree;
  std::vector<int32> proxy;
  const World<2>* world = nullptr;
  int current = 0;
  std::size_t count = 0;

  void init(const World<2>& w) {
    world = &w;
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      proxy.push_back(tree.CreateProxy(to_b2(w.boxes[i]),
                                       reinterpret_cast<void*>(static_cast<std::uintptr_t>(i))));
    }
  }
  bool QueryCallback(int32 proxy_id) {
    const int j = static_cast<int>(reinterpret_cast<std::uintptr_t>(tree.GetUserData(proxy_id)));
    if (j > current && overlap(world->boxes[current], world->boxes[j])) ++count;
    return true;
  }
  std::size_t frame(const World<2>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      tree.MoveProxy(proxy[i], to_b2(w.boxes[i]), b2Vec2(w.velocity[i].x, w.velocity[i].y));
    }
    count = 0;
    for (current = 0; current < static_cast<int>(w.boxes.size()); ++current) {
      tree.Query(this, to_b2(w.boxes[current]));
    }
    return count;
  }
};

// b2BroadPhase as b2World uses it: only proxies that left their fat AABB are re-queried, and only
// new pairs are reported (the contact list keeps the others). Less output than the rest.
struct Box2DBroadPhaseNewPairs {
  b2BroadPhase bp;
  std::vector<int32> proxy;
  std::size_t count = 0;

  void init(const World<2>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      proxy.push_back(bp.CreateProxy(to_b2(w.boxes[i]), nullptr));
    }
    bp.UpdatePairs(this);
  }
  void AddPair(void*, void*) { ++count; }
  std::size_t frame(const World<2>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      bp.MoveProxy(proxy[i], to_b2(w.boxes[i]), b2Vec2(w.velocity[i].x, w.velocity[i].y));
    }
    count = 0;
    bp.UpdatePairs(this);
    return count;
  }
};

// ---- Box2D v3 --------------------------------------------------------------------------------

// v3's b2DynamicTree driven as its broad phase drives it (box2d_v3/queries.cpp: fat boxes,
// enlarge on leaving them, partial rebuild each frame), every box querying it: the full pair set.
struct Box2DV3Tree {
  std::unique_ptr<collide::bench::box2d_v3::DynamicTreeRace> race;
  void init(const World<2>& w) {
    race = std::make_unique<collide::bench::box2d_v3::DynamicTreeRace>(w.boxes);
  }
  std::size_t frame(const World<2>& w) { return race->frame(w.boxes); }
};

// ---- Chipmunk 7 ------------------------------------------------------------------------------

struct ChipmunkObject {
  cpBB bb;
  int id;
};

cpBB chipmunk_bb(void* obj) { return static_cast<ChipmunkObject*>(obj)->bb; }

cpCollisionID chipmunk_pair(void* a, void* b, cpCollisionID id, void* data) {
  // Chipmunk reports candidates (sharing a cell / fat box); the exact test decides, as cpSpace
  // does.
  if (cpBBIntersects(static_cast<ChipmunkObject*>(a)->bb, static_cast<ChipmunkObject*>(b)->bb)) {
    ++*static_cast<std::size_t*>(data);
  }
  return id;
}

template <bool kHash>
struct Chipmunk {
  std::vector<ChipmunkObject> objects;
  cpSpatialIndex* index = nullptr;

  void init(const World<2>& w) {
    objects.resize(w.boxes.size());
    // Space hash: cells of about the object size, ~4 cells per object (Chipmunk's advice).
    index = kHash ? cpSpaceHashNew(1.0, static_cast<int>(4 * w.boxes.size()), chipmunk_bb, nullptr)
                  : cpBBTreeNew(chipmunk_bb, nullptr);
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      const Aabb& b = w.boxes[i];
      objects[i] = {cpBBNew(b.min.x, b.min.y, b.max.x, b.max.y), static_cast<int>(i)};
      cpSpatialIndexInsert(index, &objects[i], static_cast<cpHashValue>(i));
    }
  }
  ~Chipmunk() {
    if (index) cpSpatialIndexFree(index);
  }
  std::size_t frame(const World<2>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      const Aabb& b = w.boxes[i];
      objects[i].bb = cpBBNew(b.min.x, b.min.y, b.max.x, b.max.y);
    }
    std::size_t count = 0;
    cpSpatialIndexReindexQuery(index, chipmunk_pair, &count);
    return count;
  }
};

// ---- Bullet 3 --------------------------------------------------------------------------------

btVector3 to_bt(const Vec3& v) { return {v.x, v.y, v.z}; }

template <class Broadphase>
struct Bullet {
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  std::unique_ptr<Broadphase> broadphase;
  std::vector<btBroadphaseProxy*> proxies;

  void init(const World<3>& w) {
    if constexpr (std::is_same_v<Broadphase, btDbvtBroadphase>) {
      broadphase = std::make_unique<btDbvtBroadphase>();
    } else {
      const btVector3 lo(-w.half_extent - 2.0f, -w.half_extent - 2.0f, -w.half_extent - 2.0f);
      broadphase = std::make_unique<Broadphase>(lo, -lo, static_cast<unsigned>(w.boxes.size() + 2));
    }
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      proxies.push_back(broadphase->createProxy(to_bt(w.boxes[i].min), to_bt(w.boxes[i].max),
                                                BOX_SHAPE_PROXYTYPE, nullptr, 1, -1, &dispatcher));
    }
    broadphase->calculateOverlappingPairs(&dispatcher);
  }
  ~Bullet() {
    if (!broadphase) return;
    for (btBroadphaseProxy* p : proxies) broadphase->destroyProxy(p, &dispatcher);
  }
  std::size_t frame(const World<3>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      broadphase->setAabb(proxies[i], to_bt(w.boxes[i].min), to_bt(w.boxes[i].max), &dispatcher);
    }
    broadphase->calculateOverlappingPairs(&dispatcher);
    // The persistent pair cache holds every pair whose boxes overlap.
    return static_cast<std::size_t>(broadphase->getOverlappingPairCache()->getNumOverlappingPairs());
  }
};

// ---- FCL 0.7 ---------------------------------------------------------------------------------

bool fcl_pair(fcl::CollisionObjectf* a, fcl::CollisionObjectf* b, void* data) {
  if (a->getAABB().overlap(b->getAABB())) ++*static_cast<std::size_t*>(data);
  return false;  // go on
}

template <bool kHash>
struct Fcl {
  std::vector<std::shared_ptr<fcl::Boxf>> shapes;
  std::vector<std::unique_ptr<fcl::CollisionObjectf>> objects;
  std::unique_ptr<fcl::BroadPhaseCollisionManagerf> manager;

  void init(const World<3>& w) {
    std::vector<fcl::CollisionObjectf*> raw;
    for (const Aabb3& b : w.boxes) {
      const Vec3 s = b.size(), c = b.center();
      shapes.push_back(std::make_shared<fcl::Boxf>(s.x, s.y, s.z));
      objects.push_back(std::make_unique<fcl::CollisionObjectf>(shapes.back()));
      objects.back()->setTranslation(fcl::Vector3f(c.x, c.y, c.z));
      objects.back()->computeAABB();
      raw.push_back(objects.back().get());
    }
    if constexpr (kHash) {
      const float e = w.half_extent + 2.0f;
      manager = std::make_unique<fcl::SpatialHashingCollisionManagerf<>>(
          2.0f, fcl::Vector3f(-e, -e, -e), fcl::Vector3f(e, e, e),
          static_cast<unsigned>(w.boxes.size()));
    } else {
      manager = std::make_unique<fcl::DynamicAABBTreeCollisionManagerf>();
    }
    manager->registerObjects(raw);
    manager->setup();
  }
  std::size_t frame(const World<3>& w) {
    for (std::size_t i = 0; i < w.boxes.size(); ++i) {
      const Vec3 c = w.boxes[i].center();
      objects[i]->setTranslation(fcl::Vector3f(c.x, c.y, c.z));
      objects[i]->computeAABB();
    }
    manager->update();
    std::size_t count = 0;
    manager->collide(&count, fcl_pair);
    return count;
  }
};

// A counter of CPU time per item (object or pair) of one iteration.
benchmark::Counter per_item(std::size_t items) {
  return benchmark::Counter(static_cast<double>(items),
                            benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---- the race --------------------------------------------------------------------------------

template <class C>
constexpr bool kHasMemory = requires(const C& c) { c.memory(); };

// Heap bytes in use (glibc's count: every malloc and operator new, C libraries included, and
// the blocks it maps for large requests): the same ruler for collide and the peers.
std::size_t heap_in_use() {
  const struct mallinfo2 info = mallinfo2();
  return info.uordblks + info.hblkhd;
}

template <int D, class C>
void frame_benchmark(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  World<D> world = make_world<D>(n);
  const std::size_t heap_before = heap_in_use();
  C contender;
  contender.init(world);
  world.step();
  // Warm-up frame, untimed; its pair count is the same world for every contender: a check.
  const std::size_t first_pairs = contender.frame(world);
  // Heap held after a frame (structure, pair list, caches, and what a peer needs per object:
  // FCL's collision objects, Chipmunk's objects): heap_per_object, for peers and collide
  // alike; bytes_per_object is collide's own count (memory_bytes + pair list capacity).
  const double heap_per_object = (static_cast<double>(heap_in_use()) - static_cast<double>(heap_before)) / n;
  for (auto _ : state) {
    state.PauseTiming();
    world.step();
    state.ResumeTiming();
    std::size_t pairs = contender.frame(world);
    benchmark::DoNotOptimize(pairs);
  }
  state.counters["pairs"] = static_cast<double>(first_pairs);
  state.counters["per_object"] = per_item(n);
  state.counters["heap_per_object"] = heap_per_object;
  if constexpr (kHasMemory<C>) {
    state.counters["bytes_per_object"] = static_cast<double>(contender.memory()) / n;
  }
}

// The motion alone (see the top): what the frames above would cost more with it inside.
template <int D>
void move_benchmark(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  World<D> world = make_world<D>(n);
  for (auto _ : state) {
    world.step();
    benchmark::DoNotOptimize(world.boxes.data());
    benchmark::ClobberMemory();
  }
  state.counters["per_object"] = per_item(n);
}

// A full rebuild, the figure of the broad-phase issue (target: 25 ns per object at 1e5, one
// thread): `build` from a fresh span of boxes (validation, the cell size chosen from the data,
// every box binned from scratch; nothing is kept from the previous call but the capacity of the
// buffers), then, for "full_rebuild", `find_pairs`: every overlapping pair once, into a pair
// list kept across iterations; "rebuild_build_only" times the build alone (the grid structure:
// cell keys, sort, cell ranges). The world moves between iterations outside the timing, so each
// build sees boxes it has not seen before. per_object is CPU time per object; per_pair (build
// + pairs only) is the same time per reported pair.
template <int D, class BP, bool kFindPairs>
void rebuild_benchmark(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  World<D> world = make_world<D>(n);
  BP bp;
  PairList pairs;
  bp.build(world.boxes);
  bp.find_pairs(pairs);
  const std::size_t first_pairs = pairs.size();
  for (auto _ : state) {
    state.PauseTiming();
    world.step();
    state.ResumeTiming();
    if constexpr (kFindPairs && kHasCombined<BP, D>) {
      bp.build_and_find_pairs(world.boxes, pairs);
      benchmark::DoNotOptimize(pairs.data());
    } else if constexpr (kFindPairs) {
      bp.build(world.boxes);
      bp.find_pairs(pairs);
      benchmark::DoNotOptimize(pairs.data());
    } else {
      bp.build(world.boxes);
      benchmark::ClobberMemory();
    }
  }
  state.counters["pairs"] = static_cast<double>(first_pairs);
  state.counters["per_object"] = per_item(n);
  if constexpr (kFindPairs) {
    state.counters["per_pair"] = per_item(first_pairs);
  }
  state.counters["bytes_per_object"] =
      static_cast<double>(bp.memory_bytes() + pairs.capacity() * sizeof(BroadPair)) / n;
}

template <int D, class C>
void add(const std::string& name, int max_n) {
  auto* b = benchmark::RegisterBenchmark((std::to_string(D) + "D/" + name).c_str(),
                                         frame_benchmark<D, C>);
  for (int n = 1000; n <= max_n; n *= 10) b->Arg(n);
  b->Unit(benchmark::kMillisecond)->MinTime(0.05);
}

// Chipmunk's own full rebuild, the peer of the above: cpSpaceHash clears its table and rehashes
// every object each call (cpSpatialIndexReindex: the build; cpSpatialIndexReindexQuery: rehash
// and query each object, the pairs filtered by the exact test as in the race). Cells of 1 unit
// and a table of 4n cells, as in the race. The boxes are handed over (copied to Chipmunk's
// objects) outside the timing.
template <bool kFindPairs>
void chipmunk_rebuild_benchmark(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  World<2> world = make_world<2>(n);
  Chipmunk<true> chipmunk;
  chipmunk.init(world);
  const auto hand_over = [&] {
    for (std::size_t i = 0; i < world.boxes.size(); ++i) {
      const Aabb& b = world.boxes[i];
      chipmunk.objects[i].bb = cpBBNew(b.min.x, b.min.y, b.max.x, b.max.y);
    }
  };
  std::size_t first_pairs = 0;
  cpSpatialIndexReindexQuery(chipmunk.index, chipmunk_pair, &first_pairs);
  for (auto _ : state) {
    state.PauseTiming();
    world.step();
    hand_over();
    state.ResumeTiming();
    if constexpr (kFindPairs) {
      std::size_t pairs = 0;
      cpSpatialIndexReindexQuery(chipmunk.index, chipmunk_pair, &pairs);
      benchmark::DoNotOptimize(pairs);
    } else {
      cpSpatialIndexReindex(chipmunk.index);
      benchmark::ClobberMemory();
    }
  }
  state.counters["pairs"] = static_cast<double>(first_pairs);
  state.counters["per_object"] = per_item(n);
  if constexpr (kFindPairs) {
    state.counters["per_pair"] = per_item(first_pairs);
  }
}

// "rebuild_build_only/<D>D/name" and "full_rebuild/<D>D/name" at n objects.
template <int D, class BP>
void add_rebuild(const std::string& name, int n) {
  const std::string suffix = std::to_string(D) + "D/" + name;
  benchmark::RegisterBenchmark(("rebuild_build_only/" + suffix).c_str(), rebuild_benchmark<D, BP, false>)
      ->Arg(n)->Unit(benchmark::kMillisecond)->MinTime(0.05);
  benchmark::RegisterBenchmark(("full_rebuild/" + suffix).c_str(), rebuild_benchmark<D, BP, true>)
      ->Arg(n)->Unit(benchmark::kMillisecond)->MinTime(0.05);
}

}  // namespace

int main(int argc, char** argv) {
  constexpr int k1e4 = 10000, k1e5 = 100000, k1e6 = 1000000;
  // Where one frame of a contender takes seconds (over ~2 us per object at 1e5, growing), it is
  // not run at 1e6; sweep and prune also stops at 1e5 (its sweep grows as n^1.5 in these worlds).
  // collide, 2D
  add<2, Collide<2, LooseGridN<2>>>("collide_loose_grid", k1e6);
  add<2, Collide<2, SortedGridN<2>>>("collide_sorted_grid", k1e6);
  add<2, Collide<2, HierarchicalGridN<2>>>("collide_hierarchical_grid", k1e6);
  add<2, Collide<2, HashGridN<2>>>("collide_hash_grid", k1e6);
  add<2, CollideTemporal<2>>("collide_temporal", k1e6);
  add<2, Collide<2, SweepAndPruneN<2>>>("collide_sweep_and_prune", k1e5);
  add<2, Collide<2, DynamicTreeN<2>>>("collide_dynamic_tree", k1e5);
  // peers, 2D
  add<2, Box2DV3Tree>("Box2Dv3_b2DynamicTree", k1e6);
  add<2, Box2DTree>("Box2D_b2DynamicTree", k1e5);
  add<2, Chipmunk<true>>("Chipmunk_cpSpaceHash", k1e6);
  add<2, Chipmunk<false>>("Chipmunk_cpBBTree", k1e5);
  add<2, Box2DBroadPhaseNewPairs>("Box2D_b2BroadPhase_new_pairs", k1e5);
  // collide, 3D
  add<3, Collide<3, LooseGridN<3>>>("collide_loose_grid", k1e6);
  add<3, Collide<3, SortedGridN<3>>>("collide_sorted_grid", k1e6);
  add<3, Collide<3, HierarchicalGridN<3>>>("collide_hierarchical_grid", k1e6);
  add<3, Collide<3, HashGridN<3>>>("collide_hash_grid", k1e6);
  add<3, CollideTemporal<3>>("collide_temporal", k1e6);
  add<3, Collide<3, SweepAndPruneN<3>>>("collide_sweep_and_prune", k1e5);
  add<3, Collide<3, DynamicTreeN<3>>>("collide_dynamic_tree", k1e5);
  // peers, 3D
  add<3, Fcl<false>>("FCL_DynamicAABBTree", k1e6);
  add<3, Bullet<btDbvtBroadphase>>("Bullet_btDbvtBroadphase", k1e5);
  add<3, Bullet<bt32BitAxisSweep3>>("Bullet_btAxisSweep3", k1e4);
  add<3, Fcl<true>>("FCL_SpatialHashing", k1e4);

  for (int n = 1000; n <= k1e6; n *= 10) {
    benchmark::RegisterBenchmark("move/2D", move_benchmark<2>)->Arg(n)->Unit(benchmark::kMillisecond)->MinTime(0.05);
    benchmark::RegisterBenchmark("move/3D", move_benchmark<3>)->Arg(n)->Unit(benchmark::kMillisecond)->MinTime(0.05);
  }
  for (const int n : {k1e4, k1e5, k1e6}) {
    add_rebuild<2, LooseGridN<2>>("collide_loose_grid", n);
    add_rebuild<2, SortedGridN<2>>("collide_sorted_grid", n);
    add_rebuild<2, HashGridN<2>>("collide_hash_grid", n);
    add_rebuild<2, HierarchicalGridN<2>>("collide_hierarchical_grid", n);
    for (const bool with_pairs : {false, true}) {
      benchmark::RegisterBenchmark(
          with_pairs ? "full_rebuild/2D/Chipmunk_cpSpaceHash" : "rebuild_build_only/2D/Chipmunk_cpSpaceHash",
          with_pairs ? chipmunk_rebuild_benchmark<true> : chipmunk_rebuild_benchmark<false>)
          ->Arg(n)->Unit(benchmark::kMillisecond)->MinTime(0.05);
    }
    add_rebuild<3, LooseGridN<3>>("collide_loose_grid", n);
    add_rebuild<3, SortedGridN<3>>("collide_sorted_grid", n);
    add_rebuild<3, HashGridN<3>>("collide_hash_grid", n);
    add_rebuild<3, HierarchicalGridN<3>>("collide_hierarchical_grid", n);
  }
  benchmark::Initialize(&argc, argv);
  collide::bench::box2d_v3::add_context();
  for (const char* peer : {"bullet", "chipmunk", "fcl"}) {
    collide::bench::add_instruction_sets(peer, collide::bench::kDebianPackageIsa);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
