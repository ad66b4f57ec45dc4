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
    const Vec3 base = random_point(rng, 50.0f);
    OverlapPair p{make_shape(rng, ka), make_shape(rng, 0),
                  Transform3{base, random_rotation(rng)},
                  Transform3{base + random_point(rng, 0.8f), random_rotation(rng)}};
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
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
