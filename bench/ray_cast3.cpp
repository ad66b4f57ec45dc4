// 3D ray casts against single shapes, collide vs Jolt (the 3D rival) in the same run: sphere,
// capsule, box, rounded box, convex hull (16 and 64 points, sharp; rounded hulls collide only:
// Jolt's convex radius shrinks a hull before rounding it, so its rounded hull is another shape).
// Pre-generated shapes, placements and rays, about half of them hitting (each row reports its
// hit rate), visited in the same pseudo-random order on both sides (case_order.hpp: replayed in
// order, a few thousand cases are learnt by the branch predictor).
//
// Both sides answer in world space from a world-space placement and ray, like with like in two
// pairs of rows: the fraction alone (`collide_fraction`, raycast_fraction, against `jolt`,
// TransformedShape::CastRay's work: the ray taken into the shape's centre-of-mass frame,
// Shape::CastRay, closest hit), and the fraction with the point and unit normal (`collide`,
// raycast, against `jolt_normal`: CastRay, then the point on the ray and
// TransformedShape::GetWorldSpaceSurfaceNormal, as Jolt's documentation tells a user who wants
// the normal to ask for it). Until stop 79 only `collide` against `jolt` was run: collide's
// answer held the point and normal, Jolt's the fraction alone. A ray that starts inside a shape is a hit
// at fraction 0 for Jolt and a miss for collide (the first entry), so Jolt's hit rate is a
// little higher. `max_fraction_gap`: the largest difference between the two sides' fractions
// over the cases both hit from outside; `max_normal_gap` (jolt_normal rows): the largest length
// of the difference of the two unit normals there (both computed once, untimed).
//
// Instruction sets: collide SSE2 (plain x86-64), Jolt its own (AVX2, FMA, ...: jolt_queries);
// both in the context block.
//   bench_ray_cast3 --benchmark_enable_random_interleaving=true --benchmark_repetitions=7 \
//     --benchmark_report_aggregates_only=true

#include <collide/ccd/raycast.hpp>

#include <benchmark/benchmark.h>

#include "case_order.hpp"
#include "instruction_set.hpp"
#include "support/jolt/jolt_convert.hpp"
#include "support/jolt/jolt_queries.hpp"
#include "support/random.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using namespace collide::test;  // uniform, random points, rotations and transforms
namespace jq = jolt_queries;

constexpr int kCases = 4096;  // power of two: index with a mask
constexpr int kShapes = 64;   // shapes cycled through (a few KiB: in cache, the arithmetic alone)

/// One ray-cast input: a placement and a ray that starts within `reach` of the shape and aims
/// at a point near it, stopping short or overshooting; and the same placement for Jolt's shape.
struct Case {
  Transform3 xf;
  Ray3 ray;
  jq::Pose jolt;  ///< xf composed with the Jolt shape's frame within collide's shape
};

/// A collide shape, the same geometry as a Jolt shape (none: no Jolt row), and where the Jolt
/// shape's own frame sits in the collide shape's (a capsule's axis, a sphere's centre).
template <class S>
struct Shape {
  S collide;
  jq::ConvexPtr jolt;
  Transform3 jolt_frame;
};

template <class S>
struct Set {
  std::vector<Shape<S>> shapes;
  std::vector<Case> cases;
  float max_fraction_gap = 0.0f;
  float max_normal_gap = 0.0f;  ///< largest |n_collide - n_jolt| (jolt_normal) where both hit from outside
};

template <class Make>
auto make_set(unsigned seed, float reach, Make make) {
  std::mt19937 rng(seed);
  using S = decltype(make(rng).collide);
  Set<S> set;
  for (int i = 0; i < kShapes; ++i) set.shapes.push_back(make(rng));
  set.cases.resize(kCases);
  for (int i = 0; i < kCases; ++i) {
    Case& c = set.cases[i];
    c.xf = Transform3{random_point3(rng, 100.0f), random_rotation(rng)};
    const Vec3 origin = c.xf.p + random_point3(rng, reach);
    const Vec3 target = c.xf.p + random_point3(rng, 0.5f * reach);
    c.ray = Ray3{origin, (target - origin) * uniform(rng, 0.5f, 2.0f)};
    c.jolt = jolt_pose(mul(c.xf, set.shapes[i & (kShapes - 1)].jolt_frame));
  }
  // The two sides' answers, once: the fractions where both hit from outside.
  for (int i = 0; i < kCases; ++i) {
    const Shape<S>& s = set.shapes[i & (kShapes - 1)];
    if (!s.jolt) break;
    const Case& c = set.cases[i];
    const RayHit3 h = raycast(s.collide, c.xf, c.ray);
    const float f = jq::cast_ray(*s.jolt, c.jolt, jolt_vec(c.ray.origin), jolt_vec(c.ray.translation));
    if (h.hit && f > 0.0f) set.max_fraction_gap = std::max(set.max_fraction_gap, std::abs(h.fraction - f));
    const jq::RayOut j = jq::cast_ray_normal(*s.jolt, c.jolt, jolt_vec(c.ray.origin), jolt_vec(c.ray.translation));
    if (h.hit && j.fraction > 0.0f) {
      const Vec3 gap = h.normal - Vec3{j.normal.x, j.normal.y, j.normal.z};
      set.max_normal_gap = std::max(set.max_normal_gap, glm::length(gap));
    }
  }
  return set;
}

ConvexHull random_hull(std::mt19937& rng, int n, float radius) {
  std::vector<Vec3> points;
  while (static_cast<int>(points.size()) < n) {
    const Vec3 p = random_point3(rng, 1.0f);
    if (dot(p, p) <= 1.0f) points.push_back(1.5f * p);
  }
  return make_convex_hull(points, HullOptions{radius});
}

/// The timed loop of every row: `cast(shape, case)` on the cases in CaseOrder's order, its
/// answer kept from the optimiser; `hit(answer)` counts the hit rate.
template <class S, class Cast, class Hit>
void run_cases(benchmark::State& state, const Set<S>& set, Cast cast, Hit hit) {
  collide::bench::CaseOrder order(kCases - 1);
  int64_t hits = 0, casts = 0;
  for (auto _ : state) {
    const std::uint32_t i = order.next();
    const auto answer = cast(set.shapes[i & (kShapes - 1)], set.cases[i]);
    benchmark::DoNotOptimize(answer);
    hits += hit(answer);
    ++casts;
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
}

template <class S>
void run_collide(benchmark::State& state, const Set<S>& set) {
  run_cases(state, set, [](const Shape<S>& s, const Case& c) { return raycast(s.collide, c.xf, c.ray); },
            [](const RayHit3& h) { return h.hit; });
  state.counters["max_fraction_gap"] = set.max_fraction_gap;
}

template <class S>
void run_collide_fraction(benchmark::State& state, const Set<S>& set) {
  run_cases(state, set, [](const Shape<S>& s, const Case& c) { return raycast_fraction(s.collide, c.xf, c.ray); },
            [](const RayFraction& h) { return h.hit; });
  state.counters["max_fraction_gap"] = set.max_fraction_gap;
}

template <class S>
void run_jolt(benchmark::State& state, const Set<S>& set) {
  run_cases(
      state, set,
      [](const Shape<S>& s, const Case& c) {
        return jq::cast_ray(*s.jolt, c.jolt, jolt_vec(c.ray.origin), jolt_vec(c.ray.translation));
      },
      [](float f) { return f >= 0.0f; });
}

template <class S>
void run_jolt_normal(benchmark::State& state, const Set<S>& set) {
  run_cases(
      state, set,
      [](const Shape<S>& s, const Case& c) {
        return jq::cast_ray_normal(*s.jolt, c.jolt, jolt_vec(c.ray.origin), jolt_vec(c.ray.translation));
      },
      [](const jq::RayOut& h) { return h.fraction >= 0.0f; });
  state.counters["max_normal_gap"] = set.max_normal_gap;
}

/// The rotation taking +y to unit `d` (Jolt's capsule axis to collide's).
Quat y_to(Vec3 d) {
  const Vec3 y{0.0f, 1.0f, 0.0f};
  const float c = dot(y, d);
  if (c < -0.9999f) return Quat{0.0f, 1.0f, 0.0f, 0.0f};  // half a turn about x
  const Vec3 axis = cross(y, d);
  return glm::normalize(Quat{1.0f + c, axis.x, axis.y, axis.z});
}

const Set<Sphere>& spheres() {
  static const auto set = make_set(1, 3.0f, [](std::mt19937& rng) {
    const Sphere s = make_sphere(random_point3(rng, 0.3f), uniform(rng, 0.5f, 1.5f));
    return Shape<Sphere>{s, jq::make_sphere(s.radius), Transform3{s.center}};
  });
  return set;
}

const Set<Capsule3>& capsules() {
  static const auto set = make_set(2, 3.0f, [](std::mt19937& rng) {
    const Capsule3 c = make_capsule(random_point3(rng, 1.0f), random_point3(rng, 1.0f), uniform(rng, 0.3f, 1.0f));
    const Vec3 axis = c.b - c.a;
    const float length = glm::length(axis);
    return Shape<Capsule3>{c, jq::make_capsule(0.5f * length, c.radius),
                           Transform3{0.5f * (c.a + c.b), y_to(axis / length)}};
  });
  return set;
}

const Set<Box>& boxes(bool rounded) {
  static const auto sharp = make_set(3, 3.0f, [](std::mt19937& rng) {
    const Box b = make_box({uniform(rng, 0.5f, 1.5f), uniform(rng, 0.5f, 1.5f), uniform(rng, 0.5f, 1.5f)});
    return Shape<Box>{b, jq::make_box(jolt_vec(b.half)), Transform3{}};
  });
  static const auto round = make_set(3, 3.0f, [](std::mt19937& rng) {
    const Box b = make_box({uniform(rng, 0.3f, 1.2f), uniform(rng, 0.3f, 1.2f), uniform(rng, 0.3f, 1.2f)},
                           uniform(rng, 0.1f, 0.4f));
    // Jolt's box is given its outer extents and rounded inside them.
    return Shape<Box>{b, jq::make_box(jolt_vec(b.half + b.radius), b.radius), Transform3{}};
  });
  return rounded ? round : sharp;
}

const Set<ConvexHull>& hulls(int points, bool rounded) {
  static const auto sets = [] {
    std::vector<Set<ConvexHull>> v;
    for (const int n : {16, 64}) {
      for (const float r : {0.0f, 0.2f}) {
        v.push_back(make_set(4 + n, 3.0f, [n, r](std::mt19937& rng) {
          ConvexHull h = random_hull(rng, n, r);
          jq::ConvexPtr jolt;
          if (r == 0.0f) {
            std::vector<jq::Vec> vertices;
            for (const Vec3& p : h.vertices) vertices.push_back(jolt_vec(p));
            jolt = jq::make_convex(vertices);
          }
          return Shape<ConvexHull>{std::move(h), std::move(jolt), Transform3{}};
        }));
      }
    }
    return v;
  }();
  return sets[(points == 16 ? 0 : 2) + (rounded ? 1 : 0)];
}

template <class Get>
void add(const std::string& name, Get get, bool jolt = true) {
  benchmark::RegisterBenchmark((name + "/collide").c_str(), [get](benchmark::State& s) { run_collide(s, get()); });
  benchmark::RegisterBenchmark((name + "/collide_fraction").c_str(),
                               [get](benchmark::State& s) { run_collide_fraction(s, get()); });
  if (!jolt) return;
  benchmark::RegisterBenchmark((name + "/jolt").c_str(), [get](benchmark::State& s) { run_jolt(s, get()); });
  benchmark::RegisterBenchmark((name + "/jolt_normal").c_str(), [get](benchmark::State& s) { run_jolt_normal(s, get()); });
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  jq::init();
  collide::bench::add_instruction_sets("jolt", jq::instruction_set());
  add("BM_Raycast3/sphere", []() -> const auto& { return spheres(); });
  add("BM_Raycast3/capsule", []() -> const auto& { return capsules(); });
  add("BM_Raycast3/box", []() -> const auto& { return boxes(false); });
  add("BM_Raycast3/rounded_box", []() -> const auto& { return boxes(true); });
  add("BM_Raycast3/hull16", []() -> const auto& { return hulls(16, false); });
  add("BM_Raycast3/hull64", []() -> const auto& { return hulls(64, false); });
  add("BM_Raycast3/rounded_hull16", []() -> const auto& { return hulls(16, true); }, false);
  add("BM_Raycast3/rounded_hull64", []() -> const auto& { return hulls(64, true); }, false);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
