// 3D penetration depth: `penetration` (GJK, then EPA on the overlapping cores) on random pairs
// whose cores overlap (box-box, capsule-box, 50 units from the origin), and `contact` (SAT and
// clipping, the specialised routine) on the same pairs for scale; collide only for now (Jolt's
// EPA to come). Each benchmark iteration is a batch of 1024 pairs.
// Counters (computed once, outside the timing): iters, support points per query (GJK + EPA);
// depth_gap, the mean |EPA depth - contact's max_depth|.
//
// Run: ./build/release/bench/bench_penetration --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/epa.hpp>

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

// ---- penetration ----------------------------------------------------------------------------

struct OverlapPair {
  Shape3D a;
  Shape3D b;
  Transform3 xa;
  Transform3 xb;
};

/// Pairs whose cores overlap (so EPA runs), A of kind `ka`, B a box, 50 units from the origin.
std::vector<OverlapPair> make_overlapping(int ka, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<OverlapPair> pairs;
  while (pairs.size() < kPairs) {
    const Vec3 base = random_point3(rng, 50.0f);
    OverlapPair p{random_box_or_capsule(rng, ka), random_box_or_capsule(rng, 0),
                  Transform3{base, random_rotation(rng)},
                  Transform3{base + random_point3(rng, 0.8f), random_rotation(rng)}};
    if (distance(p.a, p.xa, p.b, p.xb).status != QueryStatus::overlapped) continue;
    pairs.push_back(p);
  }
  return pairs;
}

void penetration_epa(benchmark::State& state, const std::vector<OverlapPair>* pairs) {
  std::vector<float> depth(pairs->size());
  double iterations = 0.0;
  for (auto _ : state) {
    int iters = 0;
    for (size_t i = 0; i < pairs->size(); ++i) {
      const OverlapPair& p = (*pairs)[i];
      const PenetrationResult3 r = penetration(p.a, p.xa, p.b, p.xb);
      depth[i] = r.depth;
      iters += r.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(depth.data());
  }
  double gap = 0.0;
  for (size_t i = 0; i < pairs->size(); ++i) {
    const OverlapPair& p = (*pairs)[i];
    gap += std::fabs(depth[i] - contact(p.a, p.xa, p.b, p.xb).max_depth());
  }
  state.counters["iters"] = iterations / double(pairs->size());
  state.counters["depth_gap"] = gap / double(pairs->size());
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
}

void penetration_contact(benchmark::State& state, const std::vector<OverlapPair>* pairs) {
  std::vector<float> depth(pairs->size());
  for (auto _ : state) {
    for (size_t i = 0; i < pairs->size(); ++i) {
      const OverlapPair& p = (*pairs)[i];
      depth[i] = contact(p.a, p.xa, p.b, p.xb).max_depth();
    }
    benchmark::DoNotOptimize(depth.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
}

}  // namespace

int main(int argc, char** argv) {
  static std::vector<std::vector<OverlapPair>> overlapping;
  overlapping.reserve(2);
  const char* names[2] = {"box_box", "capsule_box"};
  for (int ka = 0; ka < 2; ++ka) {
    overlapping.push_back(make_overlapping(ka, 1u + unsigned(ka)));
    const std::string n = names[ka];
    benchmark::RegisterBenchmark(("BM_Penetration/" + n + "/epa").c_str(), penetration_epa,
                                 &overlapping.back());
    benchmark::RegisterBenchmark(("BM_Penetration/" + n + "/contact").c_str(),
                                 penetration_contact, &overlapping.back());
  }
  benchmark::Initialize(&argc, argv);
  collide::bench::add_collide_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
