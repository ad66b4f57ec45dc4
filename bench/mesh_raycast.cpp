// Closest-hit ray casts against level meshes: collide vs Jolt (MeshShape::CastRay) and Embree 3
// (rtcIntersect1, single rays, the ceiling for CPU ray casting), side by side in one run on the
// same rays, every answer checked against an exact reference.
//
// Meshes (../shared/data/meshes, SOURCES.md): recast's dungeon.obj (10,133 triangles, a level),
// undulating.obj (5,202, terrain about 5000 units from the origin) and FCL's env.obj (2,180, a
// soup 6000 units across). Each library gets the file's positions and triangles (collide through
// io::load_triangle_mesh, the peers through io::load_obj's soup). Three sets of 2048 rays per
// mesh (fixed seed), lengths in units of the mesh's bounding-box diagonal:
//   short: from a random point of the box, a random direction, 1% to 20% of the diagonal long
//          (line of sight, bullets);
//   long:  between two random points of the box (across the level);
//   down:  straight down from above the box onto a random xz point (picking the ground).
// Each benchmark iteration casts every ray of a set once; `per_ray` is the time per ray.
//   collide:      raycast(mesh, xf, ray), the public entry point: world-space ray in, hit with
//                 point, unit normal facing the ray and triangle out;
//   collide_bvh:  TriangleBvh::ray_cast alone (fraction, triangle, unit normal; local frame);
//   jolt:         Shape::CastRay on a MeshShape (fraction and sub-shape id; a normal would cost
//                 a further GetSurfaceNormal call, not made);
//   embree:       rtcIntersect1 (fraction, unnormalised geometric normal, primitive).
// All hit both sides of a triangle. Accuracy, reported as counters (computed once per
// benchmark): the reference scans every triangle in double (tests/support/brute_ray_mesh.hpp)
// and bounds the right fraction by the nearest crossing clearly inside a triangle and the
// nearest one within rounding (1e-6 of the largest coordinate) of an edge;
//   misses:      a crossing clearly inside a triangle not found;
//   false_hits:  a hit where no triangle is within rounding of the ray;
//   wrong_fraction: a hit outside those bounds (a farther triangle, or a wrong fraction);
//   max_err:     the largest |hit point - exact nearest crossing| along the ray, world units;
//   hit_rate:    the share of the set's rays that hit (the reference's).
// BM_MeshBuild/<mesh>/<library>: building the ray-castable mesh from the level's positions and
// triangles in memory, one build per iteration, one thread each (what a game pays per level at
// load time; no accuracy counters: each build's casts are the rows above):
//   collide:      make_triangle_mesh (validation, degenerate triangles dropped, active edges,
//                 the four-wide BVH);
//   collide_bvh:  the TriangleBvh alone;
//   jolt:         MeshShapeSettings(vertices, triangles) and Create() (its sanitizing, active
//                 edges and tree);
//   embree:       rtcNewScene, one triangle geometry, rtcCommitScene (its default build quality)
//                 on a device made with "threads=1", the scene released after.
// Instruction sets are in the context block: collide's from its build (x86-64 baseline by
// default), Jolt's from its configuration string (AVX2/FMA by default, cmake/peers.cmake), and
// Embree's kernels, chosen at run time for the CPU.
//
// Run: ./build/release/bench/bench_mesh_raycast --benchmark_enable_random_interleaving=true \
//        --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <collide/ccd/raycast.hpp>
#include <collide/io/obj.hpp>

#include "instruction_set.hpp"
#include "support/brute_ray_mesh.hpp"
#include "support/jolt/jolt_queries.hpp"

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;

constexpr int kRays = 2048;
constexpr int kSets = 3;
const char* const kSetNames[kSets] = {"short", "long", "down"};
/// Rounding of the reference: world coordinates carry float error of a few ulps of the largest
/// coordinate (as tests/ccd/mesh_raycast_test.cpp).
constexpr double kRelativeRounding = 1e-6;
constexpr double kFractionRounding = 1e-5;

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

RTCDevice embree_device() {
  static RTCDevice device = rtcNewDevice(nullptr);
  return device;
}

/// A device whose builds run on one thread (BM_MeshBuild: every library builds on one).
RTCDevice embree_device_one_thread() {
  static RTCDevice device = rtcNewDevice("threads=1");
  return device;
}

/// One level in every library, with its rays and their reference answers.
struct Level {
  std::string name;
  TriangleMesh mesh;
  Transform3 xf;  ///< the mesh's placement (identity), stored as a world keeps a static's
  RTCScene embree = nullptr;
  jolt_queries::MeshPtr jolt;
  TriangleSoup soup;  ///< the file's positions and triangles, as every library gets them
  std::vector<jolt_queries::Vec> jolt_positions;
  std::vector<std::array<std::uint32_t, 3>> jolt_triangles;
  Aabb3 box;
  double diagonal = 0.0;
  double eps = 0.0;  ///< rounding of world coordinates
  std::vector<test::WorldTriangle> triangles;
  std::array<std::vector<Ray3>, kSets> rays;
  std::array<std::optional<std::vector<test::RayTruth>>, kSets> truth;  ///< made when needed
};

RTCScene make_embree_scene(const TriangleSoup& soup, RTCDevice device = embree_device()) {
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), soup.positions.size()));
  for (std::size_t i = 0; i < soup.positions.size(); ++i) {
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = soup.positions[i][k];
  }
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), soup.triangles.size()));
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = soup.triangles[t][k];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene);
  return scene;
}

std::vector<Ray3> make_rays(const Level& l, int set) {
  std::mt19937 rng(2024 + set);
  const Aabb3& box = l.box;
  auto in_box = [&] {
    return Vec3(uniform(rng, box.min.x, box.max.x), uniform(rng, box.min.y, box.max.y),
                uniform(rng, box.min.z, box.max.z));
  };
  const float diagonal = static_cast<float>(l.diagonal);
  std::vector<Ray3> rays(kRays);
  for (Ray3& r : rays) {
    if (set == 0) {
      Vec3 d;
      do {
        d = Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
      } while (dot(d, d) < 1e-4f || dot(d, d) > 1.0f);
      r = {in_box(), normalize(d) * (diagonal * uniform(rng, 0.01f, 0.2f))};
    } else if (set == 1) {
      const Vec3 a = in_box();
      r = {a, in_box() - a};
    } else {
      const Vec3 a = in_box();
      const float height = box.max.y - box.min.y;
      r = {Vec3(a.x, box.max.y + 0.01f * diagonal, a.z), Vec3(0.0f, -height - 0.02f * diagonal, 0.0f)};
    }
  }
  return rays;
}

Level load_level(const std::string& name, const std::string& file) {
  const std::string path = std::string(COLLIDE_DATA_DIR) + "/meshes/" + file;
  Level l;
  l.name = name;
  l.mesh = io::load_triangle_mesh(path);
  l.soup = io::load_obj(path);
  l.embree = make_embree_scene(l.soup);
  for (const Vec3& p : l.soup.positions) l.jolt_positions.push_back({p.x, p.y, p.z});
  for (const glm::uvec3& t : l.soup.triangles) l.jolt_triangles.push_back({t.x, t.y, t.z});
  l.jolt = jolt_queries::make_mesh(l.jolt_positions, l.jolt_triangles);
  if (!l.jolt) std::fprintf(stderr, "Jolt refused %s\n", file.c_str());
  l.box = compute_aabb(l.mesh, Transform3{});
  l.diagonal = glm::length(glm::dvec3(l.box.max) - glm::dvec3(l.box.min));
  l.eps = kRelativeRounding * std::max(max_abs(l.box.min), max_abs(l.box.max));
  l.triangles = test::world_triangles(l.mesh, Transform3{});
  for (int set = 0; set < kSets; ++set) l.rays[set] = make_rays(l, set);
  return l;
}

std::vector<Level>& levels() {
  static std::vector<Level> all = [] {
    jolt_queries::init();
    std::vector<Level> out;
    out.push_back(load_level("dungeon", "recast/dungeon.obj"));
    out.push_back(load_level("undulating", "recast/undulating.obj"));
    out.push_back(load_level("fcl_env", "fcl/env.obj"));
    return out;
  }();
  return all;
}

const std::vector<test::RayTruth>& truth(Level& l, int set) {
  if (!l.truth[set]) {
    std::vector<test::RayTruth> t;
    t.reserve(kRays);
    for (const Ray3& r : l.rays[set]) {
      t.push_back(test::brute_ray_truth(l.triangles, r, l.eps, kFractionRounding));
    }
    l.truth[set] = std::move(t);
  }
  return *l.truth[set];
}

// ---- the libraries: fraction of the closest hit, or -1 ------------------------------------------

float cast_collide(const Level& l, const Ray3& r) {
  const RayHit3 hit = raycast(l.mesh, l.xf, r);
  return hit.hit ? hit.fraction : -1.0f;
}

float cast_collide_bvh(const Level& l, const Ray3& r) {
  const TriangleRayHit hit = l.mesh.bvh.ray_cast(Ray3{r.origin - l.mesh.origin, r.translation});
  return hit.triangle != std::numeric_limits<std::uint32_t>::max() ? hit.fraction : -1.0f;
}

float cast_jolt(const Level& l, const Ray3& r) {
  return jolt_queries::cast_ray(*l.jolt, {r.origin.x, r.origin.y, r.origin.z},
                                {r.translation.x, r.translation.y, r.translation.z});
}

float cast_embree(const Level& l, const Ray3& r) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit h;
  h.ray.org_x = r.origin.x;
  h.ray.org_y = r.origin.y;
  h.ray.org_z = r.origin.z;
  h.ray.dir_x = r.translation.x;
  h.ray.dir_y = r.translation.y;
  h.ray.dir_z = r.translation.z;
  h.ray.tnear = 0.0f;
  h.ray.tfar = 1.0f;
  h.ray.time = 0.0f;
  h.ray.mask = 0xffffffffu;
  h.ray.id = 0;
  h.ray.flags = 0;
  h.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  h.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(l.embree, &context, &h);
  return h.hit.geomID != RTC_INVALID_GEOMETRY_ID ? h.ray.tfar : -1.0f;
}

using Cast = float (*)(const Level&, const Ray3&);

// ---- accuracy -----------------------------------------------------------------------------------

using Accuracy = std::vector<std::pair<std::string, double>>;

Accuracy accuracy(const std::string& name, Level& l, int set, Cast cast) {
  const std::vector<test::RayTruth>& ref = truth(l, set);
  const double inf = std::numeric_limits<double>::infinity();
  int misses = 0, false_hits = 0, wrong_fraction = 0, hits = 0;
  double max_err = 0.0;
  std::string cases;
  for (int i = 0; i < kRays; ++i) {
    const Ray3& r = l.rays[set][i];
    const test::RayTruth& t = ref[i];
    hits += t.nearest < inf;
    const float f = cast(l, r);
    const char* wrong = nullptr;
    if (f < 0.0f) {
      if (t.clear < inf) wrong = "missed", ++misses;
    } else if (t.possible == inf) {
      wrong = "false hit", ++false_hits;
    } else if (f < t.possible || f > t.clear) {
      wrong = "fraction", ++wrong_fraction;
    } else if (t.nearest < inf) {
      max_err = std::max(max_err, std::fabs(f - t.nearest) * glm::length(glm::dvec3(r.translation)));
    }
    if (wrong) {
      cases += " #" + std::to_string(i) + " (" + wrong + " " + std::to_string(f) + ", exact " +
               std::to_string(t.nearest) + ")";
    }
  }
  if (!cases.empty()) std::fprintf(stderr, "%s wrong:%s\n", name.c_str(), cases.c_str());
  return {{"misses", misses},
          {"false_hits", false_hits},
          {"wrong_fraction", wrong_fraction},
          {"max_err", max_err},
          {"hit_rate", double(hits) / kRays}};
}

// ---- timing -------------------------------------------------------------------------------------

void register_cast(Level* l, int set, const char* library, Cast cast) {
  const std::string name =
      std::string("BM_MeshRay/") + l->name + "/" + kSetNames[set] + "/" + library;
  auto acc = std::make_shared<std::optional<Accuracy>>();
  benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
    if (!*acc) *acc = accuracy(name, *l, set, cast);
    const std::vector<Ray3>& rays = l->rays[set];
    for (auto _ : state) {
      for (const Ray3& r : rays) benchmark::DoNotOptimize(cast(*l, r));
    }
    state.SetItemsProcessed(state.iterations() * kRays);
    state.counters["per_ray"] = benchmark::Counter(
        kRays, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
    for (const auto& [counter, value] : **acc) state.counters[counter] = value;
  })->Unit(benchmark::kMicrosecond);
}

template <class Build>
void register_build(const Level* l, const char* library, Build build) {
  const std::string name = std::string("BM_MeshBuild/") + l->name + "/" + library;
  benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) {
    for (auto _ : state) build(*l);
    state.counters["triangles"] = static_cast<double>(l->soup.triangles.size());
  })->Unit(benchmark::kMillisecond);
}

void register_all() {
  for (Level& l : levels()) {
    for (int set = 0; set < kSets; ++set) {
      register_cast(&l, set, "collide", cast_collide);
      register_cast(&l, set, "collide_bvh", cast_collide_bvh);
      register_cast(&l, set, "jolt", cast_jolt);
      register_cast(&l, set, "embree", cast_embree);
    }
  }
  for (const Level& l : levels()) {
    register_build(&l, "collide", [](const Level& level) {
      const TriangleMesh mesh = make_triangle_mesh(level.soup.positions, level.soup.triangles);
      benchmark::DoNotOptimize(mesh.bvh.node_count());
    });
    register_build(&l, "collide_bvh", [](const Level& level) {
      const TriangleBvh bvh(level.soup.positions, level.soup.triangles);
      benchmark::DoNotOptimize(bvh.node_count());
    });
    register_build(&l, "jolt", [](const Level& level) {
      const jolt_queries::MeshPtr mesh = jolt_queries::make_mesh(level.jolt_positions, level.jolt_triangles);
      benchmark::DoNotOptimize(mesh.get());
    });
    register_build(&l, "embree", [](const Level& level) {
      const RTCScene scene = make_embree_scene(level.soup, embree_device_one_thread());
      benchmark::DoNotOptimize(scene);
      rtcReleaseScene(scene);
    });
  }
}

std::string embree_context() {
  const RTCDevice d = embree_device();
  const auto prop = [d](RTCDeviceProperty p) { return rtcGetDeviceProperty(d, p) ? "yes" : "no"; };
  std::string cpu = "sse2";
  if (__builtin_cpu_supports("sse4.2")) cpu += " sse4.2";
  if (__builtin_cpu_supports("avx")) cpu += " avx";
  if (__builtin_cpu_supports("avx2")) cpu += " avx2";
  if (__builtin_cpu_supports("avx512f")) cpu += " avx512f";
  return "Embree " + std::to_string(rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_VERSION)) +
         " (Debian), kernels chosen at run time for this CPU (" + cpu + "); native ray4/8/16 " +
         prop(RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED) + "/" +
         prop(RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) + "/" +
         prop(RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::add_instruction_sets("jolt", jolt_queries::instruction_set());
  benchmark::AddCustomContext("embree", embree_context());
  for (const Level& l : levels()) {
    benchmark::AddCustomContext(
        "mesh " + l.name, std::to_string(l.mesh.triangle_count()) + " triangles, box diagonal " +
                              std::to_string(l.diagonal));
  }
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
