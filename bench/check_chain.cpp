// The early-out chain on real clock readings: three checks of different real cost and pass
// rate (busy work over a fixed array, outcomes from a fixed-seed table), run in their
// declaration order (the habit: cheapest first, bounding pretest always on) against a
// CheckChain that measures and reorders. No peer library has this; the comparison is the
// fixed order. Counter `saved` is the chain's own model estimate (CheckChainReport).
//
//   ./build/release/bench/bench_check_chain --benchmark_repetitions=5 \
//       --benchmark_report_aggregates_only=true

#include <collide/early_out/check_chain.hpp>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace {

constexpr int kPairs = 4096;

/// Busy work whose cost grows with `rounds`; the result feeds the outcome so it is not removed.
float work(int rounds, float seed) {
  float x = seed;
  for (int i = 0; i < rounds; ++i) x = std::sqrt(x * x + 1.0f) * 0.999f;
  return x;
}

struct Scene {
  // Declared as a programmer would: cheapest first, pretest in front of the dearest.
  // Check 0: 16 rounds, passes 98%. Check 1: 64 rounds, passes 90%. Check 2: 128 rounds,
  // passes 5%, behind an 8-round pretest that passes 95% (not worth it: t_pre > 0.05 t_exact).
  // Optimal: check 2 first without its pretest (t / (1 - p) is lowest there).
  std::array<int, 3> rounds{16, 64, 128};
  std::array<float, 3> pass_rate{0.98f, 0.90f, 0.05f};
  std::vector<std::array<unsigned char, 3>> outcome;
  std::vector<unsigned char> pretest;

  Scene() {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < kPairs; ++i) {
      std::array<unsigned char, 3> o{};
      for (int c = 0; c < 3; ++c) o[c] = u(rng) < pass_rate[c];
      outcome.push_back(o);
      pretest.push_back(o[2] || u(rng) < 0.947f);  // redundant: passes whenever check 2 passes
    }
  }
  bool run(int pair, int check, collide::CheckStage stage) const {
    const int r = stage == collide::CheckStage::pretest ? 8 : rounds[check];
    const float x = work(r, static_cast<float>(pair));
    const bool pass = stage == collide::CheckStage::pretest ? pretest[pair] : outcome[pair][check];
    return pass && x > -1.0f;  // x is always positive: keeps the work alive
  }
};

void BM_FixedOrder(benchmark::State& state) {
  const Scene scene;
  int hits = 0;
  for (auto _ : state) {
    for (int p = 0; p < kPairs; ++p) {
      const bool hit = scene.run(p, 0, collide::CheckStage::exact) &&
                       scene.run(p, 1, collide::CheckStage::exact) &&
                       scene.run(p, 2, collide::CheckStage::pretest) &&
                       scene.run(p, 2, collide::CheckStage::exact);
      hits += hit;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(state.iterations() * kPairs);
}

void BM_CheckChain(benchmark::State& state) {
  const Scene scene;
  const std::array<bool, 3> pretests{false, false, true};
  collide::CheckChainOptions options;
  options.timing_interval = static_cast<std::uint32_t>(state.range(0));
  collide::CheckChain<4> chain(pretests, options);
  int hits = 0;
  for (auto _ : state) {
    for (int p = 0; p < kPairs; ++p) {
      hits += chain.evaluate([&](int check, collide::CheckStage stage) { return scene.run(p, check, stage); });
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["saved"] = chain.report().saved_fraction();
  state.SetItemsProcessed(state.iterations() * kPairs);
}

BENCHMARK(BM_FixedOrder)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CheckChain)->Arg(1)->Arg(16)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  return collide::bench::run_benchmarks(argc, argv, [] { collide::bench::add_collide_context(); });
}
