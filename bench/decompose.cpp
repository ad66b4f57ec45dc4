// Convex decomposition of concave simple polygons: collide (ear clipping + Hertel-Mehlhorn,
// the best of kDecompositionStarts triangulations) against Chipmunk 7's
// cpPolylineConvexDecomposition (approximate decomposition, here with tolerance 0), on the same
// random star-shaped polygons. Counters report the mean number of pieces each produces.
//
//   ./build/release/bench/bench_decompose --benchmark_repetitions=5 \
//       --benchmark_report_aggregates_only=true

#include <collide/core/error.hpp>
#include <collide/decompose/convex_decomposition.hpp>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"
#include <chipmunk/chipmunk.h>
extern "C" {  // cpPolyline.h, unlike chipmunk.h, has no C++ guard
#include <chipmunk/cpPolyline.h>
}

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

namespace {

using collide::Vec2;

/// Fixed-seed star-shaped polygons with `n` vertices (simple by construction), counter-clockwise.
std::vector<std::vector<Vec2>> make_inputs(int n, int count) {
  std::mt19937 rng(1234 + n);
  std::uniform_real_distribution<float> angle(0.0f, 2.0f * std::numbers::pi_v<float>);
  std::uniform_real_distribution<float> radius(0.3f, 1.0f);
  std::vector<std::vector<Vec2>> out;
  while (static_cast<int>(out.size()) < count) {
    std::vector<float> angles(static_cast<size_t>(n));
    for (float& a : angles) a = angle(rng);
    std::sort(angles.begin(), angles.end());
    std::vector<Vec2> pts;
    for (float a : angles) {
      const float r = 10.0f * radius(rng);
      pts.push_back({r * std::cos(a), r * std::sin(a)});
    }
    try {
      (void)collide::make_simple_outline(pts);  // skip the rare degenerate draw
      out.push_back(std::move(pts));
    } catch (const collide::InvalidInput&) {
    }
  }
  return out;
}

void run_collide(benchmark::State& state, int triangulations) {
  const auto inputs = make_inputs(static_cast<int>(state.range(0)), 64);
  double pieces = 0.0;
  for (auto _ : state) {
    pieces = 0.0;
    for (const auto& poly : inputs) {
      const auto result = collide::decompose_convex(poly, "bench", triangulations);
      pieces += static_cast<double>(result.size());
      benchmark::DoNotOptimize(result.data());
    }
  }
  state.counters["pieces"] = pieces / static_cast<double>(inputs.size());
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(inputs.size()));
}

/// The default: best of kDecompositionStarts triangulations (fewest pieces).
void BM_Collide(benchmark::State& state) { run_collide(state, collide::kDecompositionStarts); }
/// One triangulation: the fastest setting.
void BM_CollideOneTriangulation(benchmark::State& state) { run_collide(state, 1); }

void BM_Chipmunk(benchmark::State& state) {
  const auto inputs = make_inputs(static_cast<int>(state.range(0)), 64);
  // Chipmunk wants a closed polyline (last vertex repeats the first), counter-clockwise.
  std::vector<cpPolyline*> lines;
  for (const auto& poly : inputs) {
    const int n = static_cast<int>(poly.size());
    auto* line = static_cast<cpPolyline*>(std::malloc(sizeof(cpPolyline) + sizeof(cpVect) * (n + 1)));
    line->count = n + 1;
    line->capacity = n + 1;
    for (int i = 0; i < n; ++i) line->verts[i] = cpv(poly[i].x, poly[i].y);
    line->verts[n] = line->verts[0];
    lines.push_back(line);
  }
  double pieces = 0.0;
  for (auto _ : state) {
    pieces = 0.0;
    for (cpPolyline* line : lines) {
      cpPolylineSet* set = cpPolylineConvexDecomposition(line, 0.0);
      pieces += set->count;
      cpPolylineSetFree(set, cpTrue);
    }
  }
  for (cpPolyline* line : lines) std::free(line);
  state.counters["pieces"] = pieces / static_cast<double>(inputs.size());
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(inputs.size()));
}

BENCHMARK(BM_Collide)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CollideOneTriangulation)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Chipmunk)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  return collide::bench::run_benchmarks(argc, argv, [] {
    collide::bench::add_instruction_sets("chipmunk", collide::bench::kDebianPackageIsa);
  });
}
