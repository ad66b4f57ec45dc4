// Convex hulls: building (collide's make_convex_hull vs Jolt's ConvexHullBuilder) and support
// queries (ConvexHull::support_index with SSE2 over vertex blocks, the plain scalar loop it
// replaced, hill climbing with support_index_from, and Jolt's ConvexHullShape support function).
// Jolt runs on its default instruction set (AVX2, FMA; SSE2 with -DCOLLIDE_JOLT_SSE2=ON,
// cmake/peers.cmake) behind tests/support/jolt/jolt_queries.hpp, collide on the x86-64 baseline
// (SSE2): both are in the context block.
//
// Builds: every cloud of Jolt's convex_hulls.bin (the 6729 that are not flat) per iteration, and
// balls of 100..10000 points; both libraries get the same tolerance (collide's, per cloud) and
// the same cap of 256 vertices. Counters give the faces and vertices each library made. Jolt
// three ways: "jolt" its ConvexHullBuilder alone (no check that the points lie inside, no
// queryable hull), "jolt_verified" the builder then its check of every point against every face
// (DetermineMaxError; make_convex_hull's final sweep is that check), "jolt_shape" the
// ConvexHullShape a game queries (the builder, the check, then the shape's tables and mass
// properties), the counterpart of make_convex_hull, which returns a checked, queryable hull.
// Supports: 1024 random directions per iteration over hulls of 8..256 vertices (points on a
// sphere, capped) and over all Jolt-cloud hulls; the climb follows a slowly turning direction
// from its previous answer, as GJK does between iterations.
//
// Run: ./build/release/bench/bench_convex_hull --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/core/error.hpp>
#include <collide/shape/convex_hull.hpp>

#include "instruction_set.hpp"
#include "support/jolt/jolt_queries.hpp"

#include <benchmark/benchmark.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace collide;
using Cloud = std::vector<Vec3>;

constexpr int kDirections = 1024;

/// Jolt's convex_hulls.bin without the clouds make_convex_hull rejects as flat.
const std::vector<Cloud>& jolt_clouds() {
  static const std::vector<Cloud> clouds = [] {
    std::ifstream in(std::string(COLLIDE_DATA_DIR) + "/meshes/jolt/convex_hulls.bin",
                     std::ios::binary);
    std::vector<Cloud> out;
    std::uint32_t n = 0;
    while (in.read(reinterpret_cast<char*>(&n), sizeof n)) {
      Cloud cloud(n);
      in.read(reinterpret_cast<char*>(cloud.data()), static_cast<std::streamsize>(n * 12));
      try {
        (void)make_convex_hull(cloud);
        out.push_back(std::move(cloud));
      } catch (const InvalidInput&) {
      }
    }
    return out;
  }();
  return clouds;
}

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g(0.0f, 1.0f);
  for (;;) {
    const Vec3 v{g(rng), g(rng), g(rng)};
    const float len = length(v);
    if (len > 1e-3f) return v / len;
  }
}

Cloud ball(int n, unsigned seed) {
  std::mt19937 rng(seed);
  Cloud c;
  for (int i = 0; i < n; ++i) {
    c.push_back(random_unit(rng) * std::cbrt(std::uniform_real_distribution<float>(0, 1)(rng)));
  }
  return c;
}

/// A hull of about `vertices` vertices: points on a unit sphere, capped.
ConvexHull sphere_hull(int vertices) {
  std::mt19937 rng(static_cast<unsigned>(vertices));
  Cloud c;
  for (int i = 0; i < 4 * vertices; ++i) c.push_back(random_unit(rng));
  HullOptions o;
  o.max_vertices = vertices;
  return make_convex_hull(c, o);
}

std::vector<Vec3> directions() {
  std::mt19937 rng(42);
  std::vector<Vec3> d(kDirections);
  for (Vec3& v : d) v = random_unit(rng);
  return d;
}

std::vector<jolt_queries::Vec> to_jolt(const Cloud& c) {
  std::vector<jolt_queries::Vec> out;
  out.reserve(c.size());
  for (Vec3 p : c) out.push_back({p.x, p.y, p.z});
  return out;
}

jolt_queries::CloudPtr jolt_cloud(const Cloud& c) { return jolt_queries::make_cloud(to_jolt(c)); }

// ---- building ----------------------------------------------------------------------------------

void BM_BuildJoltClouds_collide(benchmark::State& state) {
  const std::vector<Cloud>& clouds = jolt_clouds();
  std::int64_t faces = 0;
  std::int64_t vertices = 0;
  for (auto _ : state) {
    faces = vertices = 0;
    for (const Cloud& c : clouds) {
      const ConvexHull h = make_convex_hull(c);
      faces += static_cast<std::int64_t>(h.faces.size());
      vertices += h.vertex_count();
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(clouds.size()));
  state.counters["faces"] = static_cast<double>(faces);
  state.counters["vertices"] = static_cast<double>(vertices);
}
BENCHMARK(BM_BuildJoltClouds_collide)->Name("BM_BuildJoltClouds/collide")->Unit(benchmark::kMillisecond);

/// collide's tolerance for each of jolt_clouds(): Jolt builds each cloud to the same one.
const std::vector<float>& cloud_tolerances() {
  static const std::vector<float> tolerances = [] {
    std::vector<float> out;
    for (const Cloud& c : jolt_clouds()) out.push_back(make_convex_hull(c).tolerance);
    return out;
  }();
  return tolerances;
}

/// Times `build(i)` (Jolt on cloud i, returning whether it succeeded and the count it makes)
/// over every cloud per iteration; `counted` names the count's counter.
template <class Build>
void time_jolt_clouds(benchmark::State& state, const char* counted, Build&& build) {
  const std::size_t clouds = jolt_clouds().size();
  std::int64_t count = 0;
  std::int64_t failed = 0;
  for (auto _ : state) {
    count = failed = 0;
    for (std::size_t i = 0; i < clouds; ++i) {
      const auto [ok, made] = build(i);
      failed += !ok;
      count += made;
    }
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(clouds));
  state.counters[counted] = static_cast<double>(count);
  state.counters["failed"] = static_cast<double>(failed);
}

/// Jolt's builder alone (`verify` false) or followed by its check of every point against every
/// face (DetermineMaxError, which ConvexHullShape runs before it keeps a hull: the counterpart of
/// make_convex_hull's final sweep, which the builder alone skips).
void build_jolt_clouds(benchmark::State& state, bool verify) {
  jolt_queries::init();
  const std::vector<float>& tolerance = cloud_tolerances();
  std::vector<jolt_queries::CloudPtr> points;
  for (const Cloud& c : jolt_clouds()) points.push_back(jolt_cloud(c));
  time_jolt_clouds(state, "faces", [&](std::size_t i) {
    const jolt_queries::HullBuild b = jolt_queries::build_hull(*points[i], kMaxHullVertices, tolerance[i], verify);
    return std::pair{b.ok, b.faces};
  });
}
void BM_BuildJoltClouds_jolt(benchmark::State& state) { build_jolt_clouds(state, false); }
void BM_BuildJoltClouds_jolt_verified(benchmark::State& state) { build_jolt_clouds(state, true); }
BENCHMARK(BM_BuildJoltClouds_jolt)->Name("BM_BuildJoltClouds/jolt")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildJoltClouds_jolt_verified)->Name("BM_BuildJoltClouds/jolt_verified")->Unit(benchmark::kMillisecond);

/// Jolt's hull as a game gets a queryable one: ConvexHullShapeSettings::Create (the builder, then
/// the shape's planes, faces, vertex faces, inner radius and mass properties; convex radius 0),
/// the counterpart of make_convex_hull, which also returns a queryable hull (its planes, faces,
/// edges, adjacency, SIMD blocks, volume and centroid; no inertia).
void BM_BuildJoltClouds_jolt_shape(benchmark::State& state) {
  jolt_queries::init();
  const std::vector<float>& tolerance = cloud_tolerances();
  std::vector<std::vector<jolt_queries::Vec>> points;
  for (const Cloud& c : jolt_clouds()) points.push_back(to_jolt(c));
  time_jolt_clouds(state, "vertices", [&](std::size_t i) {
    const jolt_queries::HullPtr h = jolt_queries::make_hull(points[i], tolerance[i]);
    return std::pair{h != nullptr, h != nullptr ? jolt_queries::vertex_count(*h) : 0};
  });
}
BENCHMARK(BM_BuildJoltClouds_jolt_shape)->Name("BM_BuildJoltClouds/jolt_shape")->Unit(benchmark::kMillisecond);

void BM_BuildBall_collide(benchmark::State& state) {
  const Cloud c = ball(static_cast<int>(state.range(0)), 7);
  int vertices = 0;
  for (auto _ : state) {
    const ConvexHull h = make_convex_hull(c);
    vertices = h.vertex_count();
    benchmark::DoNotOptimize(h.faces.data());
  }
  state.counters["vertices"] = vertices;
}
BENCHMARK(BM_BuildBall_collide)->Name("BM_BuildBall/collide")->Arg(100)->Arg(1000)->Arg(10000)
    ->Unit(benchmark::kMicrosecond);

/// Times `build(input, tolerance)` per iteration: Jolt on the ball of state.range(0) points,
/// given as `prepare` makes it before the timing, at collide's tolerance for it, returning the
/// vertices it made.
template <class Prepare, class Build>
void time_jolt_ball(benchmark::State& state, Prepare&& prepare, Build&& build) {
  jolt_queries::init();
  const Cloud c = ball(static_cast<int>(state.range(0)), 7);
  const auto input = prepare(c);
  const float tolerance = make_convex_hull(c).tolerance;
  int vertices = 0;
  for (auto _ : state) {
    vertices = build(input, tolerance);
    benchmark::DoNotOptimize(vertices);
  }
  state.counters["vertices"] = vertices;
}

/// As build_jolt_clouds, on one ball.
void build_jolt_ball(benchmark::State& state, bool verify) {
  time_jolt_ball(state, jolt_cloud, [&](const jolt_queries::CloudPtr& points, float tolerance) {
    return jolt_queries::build_hull(*points, kMaxHullVertices, tolerance, verify).vertices;
  });
}
void BM_BuildBall_jolt(benchmark::State& state) { build_jolt_ball(state, false); }
void BM_BuildBall_jolt_verified(benchmark::State& state) { build_jolt_ball(state, true); }
BENCHMARK(BM_BuildBall_jolt)->Name("BM_BuildBall/jolt")->Arg(100)->Arg(1000)->Arg(10000)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BuildBall_jolt_verified)->Name("BM_BuildBall/jolt_verified")->Arg(100)->Arg(1000)->Arg(10000)
    ->Unit(benchmark::kMicrosecond);

/// As BM_BuildJoltClouds/jolt_shape: Jolt's ConvexHullShape made from the ball.
void BM_BuildBall_jolt_shape(benchmark::State& state) {
  time_jolt_ball(state, to_jolt, [](const std::vector<jolt_queries::Vec>& points, float tolerance) {
    const jolt_queries::HullPtr h = jolt_queries::make_hull(points, tolerance);
    return h != nullptr ? jolt_queries::vertex_count(*h) : -1;
  });
}
BENCHMARK(BM_BuildBall_jolt_shape)->Name("BM_BuildBall/jolt_shape")->Arg(100)->Arg(1000)->Arg(10000)
    ->Unit(benchmark::kMicrosecond);

// ---- support queries ---------------------------------------------------------------------------

/// The plain loop support_index replaced: first vertex with the largest dot product.
int scalar_support(const ConvexHull& h, Vec3 d) {
  int best = 0;
  float best_dot = dot(h.vertices[0], d);
  for (int i = 1; i < h.vertex_count(); ++i) {
    const float v = dot(h.vertices[i], d);
    if (v > best_dot) {
      best_dot = v;
      best = i;
    }
  }
  return best;
}

template <class Query>
void run_support(benchmark::State& state, const std::vector<ConvexHull>& hulls, Query query) {
  const std::vector<Vec3> dirs = directions();
  std::int64_t sum = 0;
  for (auto _ : state) {
    for (const ConvexHull& h : hulls) {
      for (const Vec3& d : dirs) sum += query(h, d);
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(hulls.size()) *
                          kDirections);
}

std::vector<ConvexHull> hulls_for(int vertices) {
  if (vertices > 0) return {sphere_hull(vertices)};
  std::vector<ConvexHull> hulls;
  const std::vector<Cloud>& clouds = jolt_clouds();
  for (size_t i = 0; i < clouds.size(); i += 16) hulls.push_back(make_convex_hull(clouds[i]));
  return hulls;  // 421 hulls, 17 vertices on average
}

void BM_Support_simd(benchmark::State& state) {
  run_support(state, hulls_for(static_cast<int>(state.range(0))),
              [](const ConvexHull& h, Vec3 d) { return h.support_index(d); });
}
void BM_Support_scalar(benchmark::State& state) {
  run_support(state, hulls_for(static_cast<int>(state.range(0))), scalar_support);
}

/// Hill climbing along a slowly turning direction (1 degree per query), from the last answer.
void BM_Support_climb(benchmark::State& state) {
  const std::vector<ConvexHull> hulls = hulls_for(static_cast<int>(state.range(0)));
  std::int64_t sum = 0;
  const Quat turn = glm::angleAxis(0.01745f, glm::normalize(Vec3(0.3f, 1.0f, 0.2f)));
  for (auto _ : state) {
    for (const ConvexHull& h : hulls) {
      Vec3 d{1.0f, 0.0f, 0.0f};
      int i = 0;
      for (int k = 0; k < kDirections; ++k) {
        i = h.support_index_from(d, i);
        sum += i;
        d = turn * d;
      }
    }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(hulls.size()) *
                          kDirections);
}

/// Jolt: ConvexHullShape (convex radius 0) support function, fetched once per hull as GJK does.
void BM_Support_jolt(benchmark::State& state) {
  jolt_queries::init();
  const std::vector<ConvexHull> hulls = hulls_for(static_cast<int>(state.range(0)));
  std::vector<jolt_queries::HullPtr> shapes;
  for (const ConvexHull& h : hulls) shapes.push_back(jolt_queries::make_hull(to_jolt(h.vertices), h.tolerance));
  const std::vector<jolt_queries::Vec> dirs = to_jolt(directions());
  float sum = 0.0f;
  for (auto _ : state) {
    for (const auto& shape : shapes) sum += jolt_queries::support_sum(*shape, dirs);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(shapes.size()) *
                          kDirections);
}

// Arg 0: all Jolt-cloud hulls (every 16th cloud); otherwise one hull of that many vertices.
#define SUPPORT_ARGS ->Arg(0)->Arg(8)->Arg(16)->Arg(32)->Arg(64)->Arg(128)->Arg(256)
BENCHMARK(BM_Support_simd)->Name("BM_Support/collide_simd") SUPPORT_ARGS;
BENCHMARK(BM_Support_scalar)->Name("BM_Support/collide_scalar_loop") SUPPORT_ARGS;
BENCHMARK(BM_Support_climb)->Name("BM_Support/collide_climb_coherent") SUPPORT_ARGS;
BENCHMARK(BM_Support_jolt)->Name("BM_Support/jolt") SUPPORT_ARGS;

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::add_instruction_sets("jolt", jolt_queries::instruction_set());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
