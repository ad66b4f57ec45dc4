// 3D time of impact: `time_of_impact` on Sweep3 pairs (box-box, capsule-box), A fired at B at
// 2..10 units per step, both turning about random axes by up to pi/2 per step ("turn"), up to
// 4 pi ("spin", fast spinners), or not at all ("translate": the shape-cast path); collide only
// for now (peers to come). Each benchmark iteration is a batch of 1024 pairs.
// Counters (computed once, outside the timing): iters, advancement steps per query (GJK ray
// cast iterations for "translate"); hits; sep_at_t, the mean distance between the shapes at the
// reported time of hits (gjk_distance): the accuracy, against the default target of 1e-3 of
// the smaller shape.
//
// Run: ./build/release/bench/bench_ccd3 --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/ccd/time_of_impact.hpp>
#include <collide/narrow/distance.hpp>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"

#include "support/random_shapes3.hpp"

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using namespace collide::test;  // uniform, random points, rotations and transforms

constexpr int kPairs = 1024;

// ---- time of impact -------------------------------------------------------------------------

struct MovingPair {
  Shape3D a;
  Shape3D b;
  Sweep3 sa;
  Sweep3 sb;
};

/// A of kind `ka`, B a box 2..5 units away; A fired at B at 2..10 units per step (aimed within
/// 0.6 radians), B drifting; both turning by up to `max_turn` radians about random axes.
std::vector<MovingPair> make_moving(int ka, float max_turn, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<MovingPair> pairs(kPairs);
  for (MovingPair& p : pairs) {
    p.a = random_box_or_capsule(rng, ka);
    p.b = random_box_or_capsule(rng, 0);
    const Vec3 ca = random_point3(rng, 50.0f);
    const Vec3 dir = random_unit3(rng);
    const Vec3 cb = ca + uniform(rng, 2.0f, 5.0f) * dir;
    const Vec3 aim = normalize(dir + uniform(rng, 0.0f, 0.6f) * random_unit3(rng));
    const Vec3 va = uniform(rng, 2.0f, 10.0f) * aim;
    const Vec3 vb = random_point3(rng, 1.0f);
    p.sa = Sweep3{Vec3(0.0f), ca, ca + va, random_rotation(rng),
                  uniform(rng, 0.0f, max_turn) * random_unit3(rng)};
    p.sb = Sweep3{Vec3(0.0f), cb, cb + vb, random_rotation(rng),
                  uniform(rng, 0.0f, max_turn) * random_unit3(rng)};
  }
  return pairs;
}

void toi3(benchmark::State& state, const std::vector<MovingPair>* pairs) {
  std::vector<ConvexProxy3> pa;
  std::vector<ConvexProxy3> pb;
  for (const MovingPair& p : *pairs) {
    pa.emplace_back(p.a);
    pb.emplace_back(p.b);
  }
  std::vector<float> times(pairs->size(), -1.0f);
  double iterations = 0.0;
  for (auto _ : state) {
    int iters = 0;
    for (size_t i = 0; i < pairs->size(); ++i) {
      const MovingPair& p = (*pairs)[i];
      const ToiResult3 r = time_of_impact(pa[i], p.sa, pb[i], p.sb);
      times[i] = r.status == QueryStatus::hit ? r.fraction : -1.0f;
      iters += r.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(times.data());
  }
  double sep = 0.0;
  int hits = 0;
  for (size_t i = 0; i < pairs->size(); ++i) {
    if (times[i] < 0.0f) continue;
    const MovingPair& p = (*pairs)[i];
    ++hits;
    sep += distance(p.a, p.sa.at(times[i]), p.b, p.sb.at(times[i])).distance;
  }
  state.counters["iters"] = iterations / double(pairs->size());
  state.counters["hits"] = hits;
  state.counters["sep_at_t"] = hits > 0 ? sep / hits : 0.0;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
}

}  // namespace

int main(int argc, char** argv) {
  static std::vector<std::vector<MovingPair>> moving;
  moving.reserve(6);
  const char* names[2] = {"box_box", "capsule_box"};
  const char* motions[3] = {"translate", "turn", "spin"};
  const float turns[3] = {0.0f, 0.5f * kPi, 4.0f * kPi};
  unsigned seed = 1;
  for (int ka = 0; ka < 2; ++ka) {
    for (int m = 0; m < 3; ++m) {
      moving.push_back(make_moving(ka, turns[m], seed++));
      benchmark::RegisterBenchmark(
          ("BM_Toi3/" + std::string(names[ka]) + "/" + motions[m]).c_str(), toi3, &moving.back());
    }
  }
  benchmark::Initialize(&argc, argv);
  collide::bench::add_collide_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
