// 3D ray casts against single shapes: sphere, capsule, box, rounded box, convex hull (16 and 64
// points, rounded or not), on pre-generated shapes, placements and rays, about half of them
// hitting (each run reports its hit rate). The peer (Jolt's RayCast against the same shapes
// with convex radius 0) joins once the Jolt build is in cmake/peers.cmake. Run with
//   bench_ray_cast3 --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <collide/ccd/raycast.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using namespace collide;

constexpr int kCases = 4096;  // power of two: index with a mask
constexpr int kShapes = 64;   // shapes cycled through (a few KiB: in cache, the arithmetic alone)

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}
Vec3 random_point(std::mt19937& rng, float extent) {
  return {uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent)};
}
Quat random_rotation(std::mt19937& rng) {
  const float u1 = uniform(rng, 0.0f, 1.0f);
  const float u2 = uniform(rng, 0.0f, 6.2831853f);
  const float u3 = uniform(rng, 0.0f, 6.2831853f);
  const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
  return Quat{a * std::cos(u2), a * std::sin(u2), b * std::sin(u3), b * std::cos(u3)};
}

/// One ray-cast input: a placement and a ray that starts within `reach` of the shape and aims
/// at a point near it, stopping short or overshooting.
struct Case {
  Transform3 xf;
  Ray3 ray;
};

std::vector<Case> make_cases(std::mt19937& rng, float reach) {
  std::vector<Case> cases(kCases);
  for (Case& c : cases) {
    c.xf = Transform3{random_point(rng, 100.0f), random_rotation(rng)};
    const Vec3 origin = c.xf.p + random_point(rng, reach);
    const Vec3 target = c.xf.p + random_point(rng, 0.5f * reach);
    c.ray = Ray3{origin, (target - origin) * uniform(rng, 0.5f, 2.0f)};
  }
  return cases;
}

template <class S>
struct Set {
  std::vector<S> shapes;
  std::vector<Case> cases;
};

template <class Make>
auto make_set(unsigned seed, float reach, Make make) {
  std::mt19937 rng(seed);
  Set<decltype(make(rng))> set;
  for (int i = 0; i < kShapes; ++i) set.shapes.push_back(make(rng));
  set.cases = make_cases(rng, reach);
  return set;
}

ConvexHull random_hull(std::mt19937& rng, int n, float radius) {
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < n) {
    const Vec3 p = random_point(rng, 1.0f);
    if (dot(p, p) <= 1.0f) points.push_back(1.5f * p);
  }
  return make_convex_hull(points, HullOptions{radius});
}

template <class S>
void run(benchmark::State& state, const Set<S>& set) {
  int i = 0;
  int64_t hits = 0, casts = 0;
  for (auto _ : state) {
    const Case& c = set.cases[i];
    const RayHit3 h = raycast(set.shapes[i & (kShapes - 1)], c.xf, c.ray);
    benchmark::DoNotOptimize(h);
    hits += h.hit;
    ++casts;
    i = (i + 1) & (kCases - 1);
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
}

void BM_SphereRaycast3_collide(benchmark::State& state) {
  static const auto set = make_set(1, 3.0f, [](std::mt19937& rng) {
    return make_sphere(random_point(rng, 0.3f), uniform(rng, 0.5f, 1.5f));
  });
  run(state, set);
}

void BM_CapsuleRaycast3_collide(benchmark::State& state) {
  static const auto set = make_set(2, 3.0f, [](std::mt19937& rng) {
    return make_capsule(random_point(rng, 1.0f), random_point(rng, 1.0f), uniform(rng, 0.3f, 1.0f));
  });
  run(state, set);
}

void BM_BoxRaycast3_collide(benchmark::State& state) {
  const bool rounded = state.range(0) != 0;
  static const auto sharp = make_set(3, 3.0f, [](std::mt19937& rng) {
    return make_box({uniform(rng, 0.5f, 1.5f), uniform(rng, 0.5f, 1.5f), uniform(rng, 0.5f, 1.5f)});
  });
  static const auto round = make_set(3, 3.0f, [](std::mt19937& rng) {
    return make_box({uniform(rng, 0.3f, 1.2f), uniform(rng, 0.3f, 1.2f), uniform(rng, 0.3f, 1.2f)},
                    uniform(rng, 0.1f, 0.4f));
  });
  run(state, rounded ? round : sharp);
}

void BM_HullRaycast3_collide(benchmark::State& state) {
  const int points = static_cast<int>(state.range(0));
  const bool rounded = state.range(1) != 0;
  static const auto sets = [] {
    std::vector<Set<ConvexHull>> v;
    for (const int n : {16, 64}) {
      for (const float r : {0.0f, 0.2f}) {
        v.push_back(make_set(4 + n, 3.0f, [n, r](std::mt19937& rng) { return random_hull(rng, n, r); }));
      }
    }
    return v;
  }();
  run(state, sets[(points == 16 ? 0 : 2) + (rounded ? 1 : 0)]);
}

BENCHMARK(BM_SphereRaycast3_collide);
BENCHMARK(BM_CapsuleRaycast3_collide);
// Argument: rounded (0 or 1).
BENCHMARK(BM_BoxRaycast3_collide)->Arg(0)->Arg(1);
// Arguments: points in the hull's cloud, rounded (0 or 1).
BENCHMARK(BM_HullRaycast3_collide)->ArgsProduct({{16, 64}, {0, 1}});

}  // namespace

BENCHMARK_MAIN();
