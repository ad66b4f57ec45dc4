// Convex shapes against a level mesh: `contact` (merged manifold, active edges) and
// `shape_cast` of a box, a capsule and a hull against recast's dungeon.obj (TriangleMesh with
// its BVH), on 1024 placements near the surface per batch: A is put on a random triangle's
// centre, offset by up to 0.5 units (contact: about half touch), and cast by up to 3 units
// (shape cast). Collide only for now; the peers (Jolt's MeshShape) are for the lead to add.
// Counters (computed once, outside the timing): touching / hits per query.
//
// Run: ./build/release/bench/bench_narrow_mesh --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/ccd/shape_cast.hpp>
#include <collide/io/obj.hpp>
#include <collide/narrow/contact.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;

constexpr int kQueries = 1024;

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

Vec3 random_point(std::mt19937& rng, float extent) {
  return {uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent)};
}

Quat random_rotation(std::mt19937& rng) {
  const float pi = std::numbers::pi_v<float>;
  const float u1 = uniform(rng, 0.0f, 1.0f), u2 = uniform(rng, 0.0f, 2.0f * pi), u3 = uniform(rng, 0.0f, 2.0f * pi);
  const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
  return Quat{a * std::cos(u2), a * std::sin(u2), b * std::sin(u3), b * std::cos(u3)};
}

const TriangleMesh& dungeon() {
  static const TriangleMesh mesh = io::load_triangle_mesh(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj");
  return mesh;
}

/// kind 0: box of half extents 0.3..0.6; 1: capsule 0.6..1.2 long, radius 0.2..0.4; 2: a hull of 24 points.
Shape3D make_shape(std::mt19937& rng, int kind) {
  if (kind == 0) return make_box({uniform(rng, 0.3f, 0.6f), uniform(rng, 0.3f, 0.6f), uniform(rng, 0.3f, 0.6f)});
  if (kind == 1) {
    const float h = uniform(rng, 0.3f, 0.6f);
    return make_capsule(Vec3(0, -h, 0), Vec3(0, h, 0), uniform(rng, 0.2f, 0.4f));
  }
  std::vector<Vec3> points;
  while (points.size() < 24) {
    const Vec3 p = random_point(rng, 0.5f);
    if (length(p) <= 0.5f) points.push_back(p);
  }
  return make_convex_hull(points);
}

struct Query {
  Shape3D shape;
  Transform3 xf;
  Vec3 translation;
};

std::vector<Query> make_queries(int kind) {
  const TriangleMesh& mesh = dungeon();
  std::mt19937 rng(7 + kind);
  std::vector<Query> q;
  for (int i = 0; i < kQueries; ++i) {
    const auto t = std::uniform_int_distribution<std::uint32_t>(0, mesh.triangle_count() - 1)(rng);
    const Vec3 c = mesh.origin + (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0f;
    q.push_back({make_shape(rng, kind), Transform3{c + random_point(rng, 0.5f), random_rotation(rng)},
                 random_point(rng, 3.0f)});
  }
  return q;
}

const char* kind_name(int kind) { return kind == 0 ? "box" : kind == 1 ? "capsule" : "hull"; }

void BM_Contact(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const TriangleMesh& mesh = dungeon();
  const std::vector<Query> queries = make_queries(kind);
  int touching = 0;
  for (const Query& q : queries) touching += contact(q.shape, q.xf, mesh, Transform3{}).touching();
  for (auto _ : state) {
    for (const Query& q : queries) benchmark::DoNotOptimize(contact(q.shape, q.xf, mesh, Transform3{}));
  }
  state.SetLabel(kind_name(kind));
  state.SetItemsProcessed(state.iterations() * kQueries);
  state.counters["touching"] = double(touching) / kQueries;
}

void BM_ShapeCast(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const TriangleMesh& mesh = dungeon();
  const std::vector<Query> queries = make_queries(kind);
  int hits = 0;
  for (const Query& q : queries) hits += shape_cast(q.shape, q.xf, q.translation, mesh, Transform3{}, Vec3(0.0f)).hit;
  for (auto _ : state) {
    for (const Query& q : queries) {
      benchmark::DoNotOptimize(shape_cast(q.shape, q.xf, q.translation, mesh, Transform3{}, Vec3(0.0f)));
    }
  }
  state.SetLabel(kind_name(kind));
  state.SetItemsProcessed(state.iterations() * kQueries);
  state.counters["hits"] = double(hits) / kQueries;
}

}  // namespace

BENCHMARK(BM_Contact)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShapeCast)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
