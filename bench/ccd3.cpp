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

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;

constexpr int kPairs = 1024;
constexpr float kPi = std::numbers::pi_v<float>;

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

Vec3 random_point(std::mt19937& rng, float extent) {
  return {uniform(rng, -extent, extent), uniform(rng, -extent, extent),
          uniform(rng, -extent, extent)};
}

Vec3 random_unit(std::mt19937& rng) {
  for (;;) {
    const Vec3 v = random_point(rng, 1.0f);
    const float l = length(v);
    if (l > 0.1f && l <= 1.0f) return v / l;
  }
}

Quat random_rotation(std::mt19937& rng) {
  const float u1 = uniform(rng, 0.0f, 1.0f);
  const float u2 = uniform(rng, 0.0f, 2.0f * kPi);
  const float u3 = uniform(rng, 0.0f, 2.0f * kPi);
  const float a = std::sqrt(1.0f - u1);
  const float b = std::sqrt(u1);
  return Quat{a * std::cos(u2), a * std::sin(u2), b * std::sin(u3), b * std::cos(u3)};
}

/// kind 0: a box of half extents 0.2..0.8; kind 1: a capsule 0.4..1.6 long, radius 0.1..0.4.
Shape3D make_shape(std::mt19937& rng, int kind) {
  if (kind == 0) {
    return make_box({uniform(rng, 0.2f, 0.8f), uniform(rng, 0.2f, 0.8f), uniform(rng, 0.2f, 0.8f)});
  }
  const Vec3 h = uniform(rng, 0.2f, 0.8f) * random_unit(rng);
  return make_capsule(-h, h, uniform(rng, 0.1f, 0.4f));
}

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
    p.a = make_shape(rng, ka);
    p.b = make_shape(rng, 0);
    const Vec3 ca = random_point(rng, 50.0f);
    const Vec3 dir = random_unit(rng);
    const Vec3 cb = ca + uniform(rng, 2.0f, 5.0f) * dir;
    const Vec3 aim = normalize(dir + uniform(rng, 0.0f, 0.6f) * random_unit(rng));
    const Vec3 va = uniform(rng, 2.0f, 10.0f) * aim;
    const Vec3 vb = random_point(rng, 1.0f);
    p.sa = Sweep3{Vec3(0.0f), ca, ca + va, random_rotation(rng),
                  uniform(rng, 0.0f, max_turn) * random_unit(rng)};
    p.sb = Sweep3{Vec3(0.0f), cb, cb + vb, random_rotation(rng),
                  uniform(rng, 0.0f, max_turn) * random_unit(rng)};
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
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
