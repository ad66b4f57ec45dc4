// Ray casts: collide vs Box2D v3 (b2RayCastPolygon / Circle / Capsule; rows *_box2d_v3, the
// first rival, box2d_v3/queries.cpp: v3 casts in the shape's frame, the conversions are timed)
// and Box2D 2.4 on the same pre-generated shapes, transforms and rays. Polygons of 4 and 8
// vertices (b2PolygonShape::RayCast, m_radius = 0), circles (b2CircleShape::RayCast) and
// capsules (v3 only: 2.4 has none). Each run reports the inputs' hit rate, which shapes the cost
// (misses can stop early). Cases are visited in a pseudo-random order that does not repeat
// with their count (case_order.hpp: replayed in order, a long-history branch predictor learns
// them). Run with
//   bench_ray_cast --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// and compare medians (ratio = Box2D time / collide time).

#include <collide/ccd/raycast.hpp>
#include <collide/shape/capsule.hpp>

#include <benchmark/benchmark.h>

#include "box2d_v3/queries.hpp"
#include "case_order.hpp"
#include "support/random.hpp"
#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace {

using namespace collide;
using namespace collide::test;  // uniform, random points, rotations and transforms

constexpr int kCases = 4096;  // power of two: index with a mask

b2Vec2 b2(Vec2 v) { return {v.x, v.y}; }
b2Transform b2(const Transform& xf) {
  b2Transform t;
  t.p = b2(xf.p);
  t.q.c = xf.q.c;
  t.q.s = xf.q.s;
  return t;
}

/// One ray-cast input: a shape index, its placement and the ray, in both libraries' types.
struct Case {
  Transform xf;
  Ray ray;
  b2Transform b2_xf;
  b2RayCastInput b2_ray;
};

/// Rays start within `reach` of the shape and aim at a point near it, stopping short or
/// overshooting: about half of them hit.
std::vector<Case> make_cases(std::mt19937& rng, float reach) {
  std::vector<Case> cases(kCases);
  for (Case& c : cases) {
    c.xf = Transform::from(random_point(rng, 100.0f), uniform(rng, -3.14f, 3.14f));
    const Vec2 origin = c.xf.p + random_point(rng, reach);
    const Vec2 target = c.xf.p + random_point(rng, 0.6f * reach);
    c.ray = Ray{origin, (target - origin) * uniform(rng, 0.5f, 2.0f)};
    c.b2_xf = b2(c.xf);
    c.b2_ray.p1 = b2(c.ray.origin);
    c.b2_ray.p2 = b2(c.ray.origin + c.ray.translation);
    c.b2_ray.maxFraction = 1.0f;
  }
  return cases;
}

/// Random convex polygons with exactly `n` vertices (jittered regular polygons), both types.
struct PolygonSet {
  std::vector<Polygon> ours;
  std::vector<b2PolygonShape> theirs;
  std::vector<Case> cases;
};

PolygonSet make_polygons(int n) {
  std::mt19937 rng(1234 + n);
  PolygonSet set;
  while (static_cast<int>(set.ours.size()) < kCases) {
    std::vector<Vec2> pts;
    const float start = uniform(rng, 0.0f, 6.28f);
    const float size = uniform(rng, 0.5f, 2.0f);
    for (int i = 0; i < n; ++i) {
      const float a =
          start + 6.2831853f * (static_cast<float>(i) + uniform(rng, -0.25f, 0.25f)) / n;
      const float r = size * uniform(rng, 0.7f, 1.0f);
      pts.push_back({r * std::cos(a), r * std::sin(a)});
    }
    const Polygon p = make_polygon(pts);
    if (p.count != n) continue;
    b2PolygonShape q;
    std::vector<b2Vec2> v;
    for (int i = 0; i < p.count; ++i) v.push_back(b2(p.vertices[i]));
    q.Set(v.data(), p.count);
    q.m_radius = 0.0f;
    if (q.m_count != n) continue;
    set.ours.push_back(p);
    set.theirs.push_back(q);
  }
  set.cases = make_cases(rng, 3.0f);
  return set;
}

const PolygonSet& polygons(int n) {
  static const PolygonSet four = make_polygons(4);
  static const PolygonSet eight = make_polygons(8);
  return n == 4 ? four : eight;
}

struct CircleSet {
  std::vector<Circle> ours;
  std::vector<b2CircleShape> theirs;
  std::vector<Case> cases;
};

const CircleSet& circles() {
  static const CircleSet set = [] {
    std::mt19937 rng(99);
    CircleSet s;
    for (int i = 0; i < kCases; ++i) {
      const Circle c = make_circle(random_point(rng, 0.5f), uniform(rng, 0.5f, 2.0f));
      b2CircleShape q;
      q.m_p = b2(c.center);
      q.m_radius = c.radius;
      s.ours.push_back(c);
      s.theirs.push_back(q);
    }
    s.cases = make_cases(rng, 3.0f);
    return s;
  }();
  return set;
}

/// Capsules (segment half length 0.3..1.5, radius 0.1..0.6): collide and v3 only.
struct CapsuleSet {
  std::vector<Capsule> ours;
  std::vector<Case> cases;
};

const CapsuleSet& capsules() {
  static const CapsuleSet set = [] {
    std::mt19937 rng(77);
    CapsuleSet s;
    for (int i = 0; i < kCases; ++i) {
      const float half = uniform(rng, 0.3f, 1.5f);
      const float angle = uniform(rng, -3.14f, 3.14f);
      const Vec2 d = half * Vec2{std::cos(angle), std::sin(angle)};
      s.ours.push_back(make_capsule(-d, d, uniform(rng, 0.1f, 0.6f)));
    }
    s.cases = make_cases(rng, 3.0f);
    return s;
  }();
  return set;
}

/// Shapes visited: kHot cycles through a few shapes that stay in L1 (the arithmetic alone);
/// kCold through all kCases shapes, as a broad phase handing over scattered candidates would
/// (collide's Polygon is 192 bytes with 8 vertices inline, Box2D's about 150 bytes, so this also
/// measures the memory layout).
constexpr int kHot = 16 - 1;
constexpr int kCold = kCases - 1;

template <class Set>
void run_collide(benchmark::State& state, const Set& set) {
  const int shape_mask = static_cast<int>(state.range(1));
  collide::bench::CaseOrder order(kCases - 1);
  int64_t hits = 0, casts = 0;
  for (auto _ : state) {
    const int i = static_cast<int>(order.next());
    const Case& c = set.cases[i];
    const RayHit h = raycast(set.ours[i & shape_mask], c.xf, c.ray);
    benchmark::DoNotOptimize(h);
    hits += h.hit;
    ++casts;
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
}

template <class Set>
void run_box2d(benchmark::State& state, const Set& set) {
  const int shape_mask = static_cast<int>(state.range(1));
  collide::bench::CaseOrder order(kCases - 1);
  int64_t hits = 0, casts = 0;
  for (auto _ : state) {
    const int i = static_cast<int>(order.next());
    const Case& c = set.cases[i];
    b2RayCastOutput out;
    const bool hit = set.theirs[i & shape_mask].RayCast(&out, c.b2_ray, c.b2_xf, 0);
    benchmark::DoNotOptimize(hit);
    benchmark::DoNotOptimize(out);
    hits += hit;
    ++casts;
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
}

/// The lesson's early out, measured: a bounding-circle pretest in front of the polygon cast.
/// collide's Polygon stores no bounding radius, so here it is precomputed per polygon (about the
/// local origin, where the generated polygons are centred). The pretest asks whether the ray
/// segment comes within the radius of the centre (closest point on the segment).
void BM_PolygonRaycast_collide_circle_pretest(benchmark::State& state) {
  const PolygonSet& set = polygons(static_cast<int>(state.range(0)));
  static std::vector<float> radius2[2];
  std::vector<float>& r2 = radius2[state.range(0) == 4 ? 0 : 1];
  if (r2.empty()) {
    for (const Polygon& p : set.ours) {
      float m = 0.0f;
      for (int i = 0; i < p.count; ++i) m = std::max(m, length_squared(p.vertices[i]));
      r2.push_back(m);
    }
  }
  const int shape_mask = static_cast<int>(state.range(1));
  collide::bench::CaseOrder order(kCases - 1);
  int64_t hits = 0, casts = 0, pretest_passes = 0;
  for (auto _ : state) {
    const int i = static_cast<int>(order.next());
    const Case& c = set.cases[i];
    const int s = i & shape_mask;
    const Vec2 m = c.xf.p - c.ray.origin;  // centre relative to the ray origin
    const float along =
        std::clamp(dot(m, c.ray.translation) / length_squared(c.ray.translation), 0.0f, 1.0f);
    RayHit h;
    if (distance_squared(m, along * c.ray.translation) <= r2[s]) {
      ++pretest_passes;
      h = raycast(set.ours[s], c.xf, c.ray);
    }
    benchmark::DoNotOptimize(h);
    hits += h.hit;
    ++casts;
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
  state.counters["pretest_pass_rate"] =
      static_cast<double>(pretest_passes) / static_cast<double>(casts);
}

void BM_PolygonRaycast_collide(benchmark::State& state) {
  run_collide(state, polygons(static_cast<int>(state.range(0))));
}
void BM_PolygonRaycast_box2d(benchmark::State& state) {
  run_box2d(state, polygons(static_cast<int>(state.range(0))));
}
void BM_CircleRaycast_collide(benchmark::State& state) { run_collide(state, circles()); }
void BM_CircleRaycast_box2d(benchmark::State& state) { run_box2d(state, circles()); }
void BM_CapsuleRaycast_collide(benchmark::State& state) { run_collide(state, capsules()); }

template <class Set>
void run_box2d_v3(benchmark::State& state, const Set& set) {
  std::vector<collide::bench::box2d_v3::RayCase> cases;
  for (const Case& c : set.cases) cases.push_back({c.xf, c.ray});
  collide::bench::box2d_v3::ray_cast(state, std::span(set.ours), cases);
}
void BM_PolygonRaycast_box2d_v3(benchmark::State& state) {
  run_box2d_v3(state, polygons(static_cast<int>(state.range(0))));
}
void BM_CircleRaycast_box2d_v3(benchmark::State& state) { run_box2d_v3(state, circles()); }
void BM_CapsuleRaycast_box2d_v3(benchmark::State& state) { run_box2d_v3(state, capsules()); }

// Arguments: vertex count (polygons), shape mask (kHot or kCold).
BENCHMARK(BM_PolygonRaycast_collide)->ArgsProduct({{4, 8}, {kHot, kCold}});
BENCHMARK(BM_PolygonRaycast_box2d_v3)->ArgsProduct({{4, 8}, {kHot, kCold}});
BENCHMARK(BM_PolygonRaycast_box2d)->ArgsProduct({{4, 8}, {kHot, kCold}});
BENCHMARK(BM_PolygonRaycast_collide_circle_pretest)->ArgsProduct({{4, 8}, {kHot, kCold}});
BENCHMARK(BM_CircleRaycast_collide)->Args({0, kHot})->Args({0, kCold});
BENCHMARK(BM_CircleRaycast_box2d_v3)->Args({0, kHot})->Args({0, kCold});
BENCHMARK(BM_CircleRaycast_box2d)->Args({0, kHot})->Args({0, kCold});
BENCHMARK(BM_CapsuleRaycast_collide)->Args({0, kHot})->Args({0, kCold});
BENCHMARK(BM_CapsuleRaycast_box2d_v3)->Args({0, kHot})->Args({0, kCold});

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::box2d_v3::add_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
