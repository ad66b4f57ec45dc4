// Convex shapes against a level mesh: `contact` (merged manifold, active edges) and
// `shape_cast` of a box, a capsule and a hull against recast's dungeon.obj (TriangleMesh with
// its BVH), on 1024 placements near the surface per batch: A is put on a random triangle's
// centre, offset by up to 0.5 units (contact: about half touch), and cast by up to 3 units
// (shape cast). Beside each, Jolt's MeshShape on the same placements (jolt_queries.hpp: the
// convex shape with convex radius 0, CollideShape with faces collected and each triangle's
// result made a manifold as PhysicsSystem does; CastShape with its default settings). Jolt
// answers per triangle (one result each, not merged), collide merges a level's manifolds into
// one of up to 4 points: the work differs in that, and the counters say how. Contact runs with
// margin 0 (BM_Contact/K/0) and with a speculative margin of 0.05 (BM_Contact/K/1) on both sides.
// Counters (computed once, outside the timing): touching / hits per query; for contact the
// queries where the two disagree on touching (`disagree`, a graze within 1e-4 of the margin
// counts as either), Jolt's mean results per touching query (`results`) and each side's mean
// points; for casts the queries where one hits and the other does not (`disagree`) and the
// largest fraction difference where both hit (`max_fraction_diff`, in units of the cast).
// Instruction sets are in the context block (collide's build, Jolt's own).
//
// Run: ./build/release/bench/bench_narrow_mesh --benchmark_enable_random_interleaving=true \
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <collide/ccd/shape_cast.hpp>
#include <collide/io/obj.hpp>
#include <collide/narrow/contact.hpp>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"
#include "support/jolt/jolt_convert.hpp"
#include "support/jolt/jolt_queries.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using test::jolt_vec;  // support/jolt/jolt_convert.hpp
using test::jolt_pose;  // support/jolt/jolt_convert.hpp

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

/// Jolt's MeshShape of the same level.
const jolt_queries::Mesh& jolt_dungeon() {
  static const jolt_queries::MeshPtr mesh = [] {
    jolt_queries::init();
    const TriangleSoup soup = io::load_obj(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj");
    std::vector<jolt_queries::Vec> positions;
    for (const Vec3& p : soup.positions) positions.push_back(jolt_vec(p));
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (const glm::uvec3& t : soup.triangles) triangles.push_back({t.x, t.y, t.z});
    return jolt_queries::make_mesh(positions, triangles);
  }();
  if (!mesh) {
    std::fprintf(stderr, "Jolt refused dungeon.obj\n");
    std::abort();
  }
  return *mesh;
}

/// One convex shape on both sides.
struct Convex {
  Shape3D shape;
  jolt_queries::ConvexPtr jolt;
};

/// kind 0: box of half extents 0.3..0.6; 1: capsule 0.6..1.2 long, radius 0.2..0.4; 2: a hull of 24 points.
Convex make_shape(std::mt19937& rng, int kind) {
  if (kind == 0) {
    const Vec3 half(uniform(rng, 0.3f, 0.6f), uniform(rng, 0.3f, 0.6f), uniform(rng, 0.3f, 0.6f));
    return {make_box(half), jolt_queries::make_box(jolt_vec(half))};
  }
  if (kind == 1) {
    const float h = uniform(rng, 0.3f, 0.6f);
    const float r = uniform(rng, 0.2f, 0.4f);
    return {make_capsule(Vec3(0, -h, 0), Vec3(0, h, 0), r), jolt_queries::make_capsule(h, r)};
  }
  std::vector<Vec3> points;
  while (points.size() < 24) {
    const Vec3 p = random_point(rng, 0.5f);
    if (length(p) <= 0.5f) points.push_back(p);
  }
  const ConvexHull hull = make_convex_hull(points);
  // Jolt gets the hull's own vertices, so both sides have the same solid.
  std::vector<jolt_queries::Vec> corners;
  for (const Vec3& v : hull.vertices) corners.push_back(jolt_vec(v));
  return {hull, jolt_queries::make_convex(corners)};
}

struct Query {
  Convex convex;
  Transform3 xf;
  jolt_queries::Pose pose;
  Vec3 translation;
};

std::vector<Query> make_queries(int kind) {
  const TriangleMesh& mesh = dungeon();
  std::mt19937 rng(7 + kind);
  std::vector<Query> q;
  for (int i = 0; i < kQueries; ++i) {
    const auto t = std::uniform_int_distribution<std::uint32_t>(0, mesh.triangle_count() - 1)(rng);
    const Vec3 c = mesh.origin + (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3.0f;
    Convex convex = make_shape(rng, kind);
    const Transform3 xf{c + random_point(rng, 0.5f), random_rotation(rng)};
    const jolt_queries::Pose pose = jolt_pose(xf);
    q.push_back({std::move(convex), xf, pose, random_point(rng, 3.0f)});
  }
  return q;
}

/// The queries of each kind, made once (Jolt's hulls take a while to build).
const std::vector<Query>& queries(int kind) {
  static std::array<std::vector<Query>, 3> all;
  if (all[kind].empty()) all[kind] = make_queries(kind);
  return all[kind];
}

/// Contact margins (second argument): touching only, and speculative contacts within 5 cm, as
/// a world stepping with a margin asks (Jolt: mMaxSeparationDistance, the same value).
constexpr std::array<float, 2> kContactMargins = {0.0f, 0.05f};

const char* kind_name(int kind) { return kind == 0 ? "box" : kind == 1 ? "capsule" : "hull"; }

/// Counters of one contact benchmark, both sides compared (outside the timing).
void contact_counters(benchmark::State& state, int kind, float margin) {
  const TriangleMesh& mesh = dungeon();
  const jolt_queries::Mesh& jmesh = jolt_dungeon();
  int touching = 0, jolt_touching = 0, disagree = 0, results = 0, points = 0, jolt_points = 0;
  for (const Query& q : queries(kind)) {
    const Manifold3 m = contact(q.convex.shape, q.xf, mesh, Transform3{}, margin);
    const jolt_queries::MeshContactOut j = jolt_queries::mesh_contact(*q.convex.jolt, q.pose, jmesh, margin);
    touching += m.touching();
    jolt_touching += j.hits > 0;
    points += m.count;
    results += j.hits;
    jolt_points += j.points;
    if (m.touching() != (j.hits > 0)) {
      // A graze: the one that touches does so by less than 1e-4 (within the margin).
      const float depth = m.touching() ? m.max_depth() : j.depth;
      if (!(depth + margin <= 1e-4f)) ++disagree;
    }
  }
  state.counters["touching"] = double(touching) / kQueries;
  state.counters["jolt_touching"] = double(jolt_touching) / kQueries;
  state.counters["disagree"] = disagree;
  state.counters["points"] = touching ? double(points) / touching : 0.0;
  state.counters["jolt_results"] = jolt_touching ? double(results) / jolt_touching : 0.0;
  state.counters["jolt_points"] = jolt_touching ? double(jolt_points) / jolt_touching : 0.0;
}

void BM_Contact(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const float margin = kContactMargins[state.range(1)];
  const TriangleMesh& mesh = dungeon();
  const std::vector<Query>& qs = queries(kind);
  for (auto _ : state) {
    for (const Query& q : qs) benchmark::DoNotOptimize(contact(q.convex.shape, q.xf, mesh, Transform3{}, margin));
  }
  state.SetLabel(std::string(kind_name(kind)) + (margin > 0.0f ? ", margin " + std::to_string(margin).substr(0, 4) : ""));
  state.SetItemsProcessed(state.iterations() * kQueries);
  contact_counters(state, kind, margin);
}

void BM_ContactJolt(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const float margin = kContactMargins[state.range(1)];
  const jolt_queries::Mesh& jmesh = jolt_dungeon();
  const std::vector<Query>& qs = queries(kind);
  for (auto _ : state) {
    for (const Query& q : qs) benchmark::DoNotOptimize(jolt_queries::mesh_contact(*q.convex.jolt, q.pose, jmesh, margin));
  }
  state.SetLabel(std::string(kind_name(kind)) + (margin > 0.0f ? ", margin " + std::to_string(margin).substr(0, 4) : ""));
  state.SetItemsProcessed(state.iterations() * kQueries);
  contact_counters(state, kind, margin);
}

/// Counters of one cast benchmark, both sides compared (outside the timing).
void cast_counters(benchmark::State& state, int kind) {
  const TriangleMesh& mesh = dungeon();
  const jolt_queries::Mesh& jmesh = jolt_dungeon();
  int hits = 0, jolt_hits = 0, disagree = 0;
  double max_diff = 0.0;
  for (const Query& q : queries(kind)) {
    const ShapeCastResult3 r = shape_cast(q.convex.shape, q.xf, q.translation, mesh, Transform3{}, Vec3(0.0f));
    const jolt_queries::CastOut j = jolt_queries::mesh_cast(*q.convex.jolt, q.pose, jolt_vec(q.translation), jmesh);
    hits += r.hit;
    jolt_hits += j.hit;
    if (r.hit != j.hit) {
      ++disagree;
    } else if (r.hit) {
      max_diff = std::max(max_diff, std::fabs(double(r.fraction) - double(j.fraction)));
    }
  }
  state.counters["hits"] = double(hits) / kQueries;
  state.counters["jolt_hits"] = double(jolt_hits) / kQueries;
  state.counters["disagree"] = disagree;
  state.counters["max_fraction_diff"] = max_diff;
}

void BM_ShapeCast(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const TriangleMesh& mesh = dungeon();
  const std::vector<Query>& qs = queries(kind);
  for (auto _ : state) {
    for (const Query& q : qs) {
      benchmark::DoNotOptimize(shape_cast(q.convex.shape, q.xf, q.translation, mesh, Transform3{}, Vec3(0.0f)));
    }
  }
  state.SetLabel(kind_name(kind));
  state.SetItemsProcessed(state.iterations() * kQueries);
  cast_counters(state, kind);
}

void BM_ShapeCastJolt(benchmark::State& state) {
  const int kind = static_cast<int>(state.range(0));
  const jolt_queries::Mesh& jmesh = jolt_dungeon();
  const std::vector<Query>& qs = queries(kind);
  for (auto _ : state) {
    for (const Query& q : qs) {
      benchmark::DoNotOptimize(jolt_queries::mesh_cast(*q.convex.jolt, q.pose, jolt_vec(q.translation), jmesh));
    }
  }
  state.SetLabel(kind_name(kind));
  state.SetItemsProcessed(state.iterations() * kQueries);
  cast_counters(state, kind);
}

}  // namespace

BENCHMARK(BM_Contact)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ContactJolt)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShapeCast)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ShapeCastJolt)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  jolt_queries::init();
  collide::bench::add_instruction_sets("jolt", jolt_queries::instruction_set());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
