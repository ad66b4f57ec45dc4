// Signed distance fields of triangle meshes: collide's dense and sparse fields against OpenVDB
// 10 (Debian), side by side in one run on the same meshes, voxel sizes and query points, every
// field checked against the exact distance.
//
// Meshes: recast's dungeon.obj (10,133 triangles, an open level), undulating.obj (5,202, open
// terrain about 5000 units from the origin) and a closed torus made here (R 8, r 3, 96 x 48
// quads, 9,216 triangles; the shared data holds no closed mesh). collide gets the mesh through
// io::load_triangle_mesh (or make_triangle_mesh), OpenVDB the same triangles at the same
// mesh-space positions (TriangleMesh::origin + vertices). Voxel sizes: "4M" is the voxel giving
// the dense grid about 4e6 nodes; "32M", "512k" and "64k" are half, twice and four times it.
// OpenVDB's transform puts its voxel centres on collide's nodes (origin = bounds - margin).
//
// BM_SdfBuild/<mesh>/<nodes>/<library>: one build per iteration.
//   collide_dense:   make_distance_field (band 3, closest points kept: the default);
//   collide_sparse:  make_sparse_distance_field (band 3, bricks of 8^3);
//   collide_exact:   make_distance_field_exact, every node through the BVH (the yardstick the
//                    dense build must beat 10x; Iterations(1) at 4M, left out at 32M);
//   openvdb:         tools::meshToLevelSet, half width 3 voxels (the sparse build's rival), on
//                    one TBB thread (collide builds on one);
//   openvdb_2t:      the same on every core (2 here);
//   openvdb_wide:    tools::meshToSignedDistanceField with both bands wide enough to cover
//                    collide's dense grid (the dense build's rival; one thread; up to 4M).
//   Counters: bytes (collide: bytes(); OpenVDB: memUsage()), distance_bytes (dense: the
//   distances alone, 4 bytes a node, as OpenVDB keeps), nodes (dense: grid nodes; sparse: brick
//   nodes; OpenVDB: active voxels), voxel; for collide's dense and exact builds what the build
//   did (FieldBuildStats): band_nodes, nearest_queries (the band's BVH queries; 0 when the
//   triangles were scattered), sign_evaluations (winding numbers); errors against the exact
//   unsigned distance (TriangleBvh::nearest) in world units on 4096 seeded points uniform in
//   the band (|d| < 3 voxels: band_max_err, band_mean_err) and, for the fields defined everywhere
//   (dense, exact, openvdb_wide), on 4096 points uniform in collide's grid box (all_max_err,
//   all_mean_err); sign_agree: the share of the box points farther than a voxel from the
//   surface whose sign agrees with the generalised winding number (> 1/2 inside: collide's
//   definition, exact for the closed torus; OpenVDB signs an open mesh by flood fill, so it is
//   expected to differ on dungeon and undulating, and the errors compare magnitudes only).
// BM_SdfSample/<mesh>/4M/<points>/<method>: 4096 precomputed points per iteration, `box` (uniform
//   in the grid's box) or `band` (the band points above); per_point = time per query; the
//   collide rows (bare_read to dense_gradient) also at 64k nodes, a field that fits the caches.
//   bare_read:       distances[i] at each point's nearest node, the index precomputed (the
//                    floor: one memory access);
//   bare_lookup:     the same with the index computed from the point (bounds check, round);
//   dense_inside / dense_sample / dense_gradient: DistanceField3::is_inside, sample(p),
//                    sample(p, gradient);
//   dense_sample_batch: sample(field, points, out), the 4096 points as one batch (four at a
//                    time in SSE2 lanes) into a buffer, the same values as dense_sample;
//   sparse_inside / sparse_sample: the same on SparseDistanceField3;
//   openvdb_point / openvdb_box: tools::GridSampler with PointSampler (nearest voxel; its
//                    "< 0" is the rival of is_inside) and BoxSampler (trilinear) over a cached
//                    ConstAccessor of the narrow-band grid, world-space points (wsSample).
// BM_SdfClosest/<mesh>/4M/<points>/<method>: the closest surface point of the same points (the
//   lesson's comparison): stored = closest_point (the closest-point field), gradient_1 /
//   gradient_2 = closest_point_by_gradient with 1 or 2 steps, bvh_nearest = the exact answer
//   through the mesh's BVH; per_point; off_max / off_mean = how far the answer lies off the
//   surface, excess_max / excess_mean = | |p - answer| - exact distance |, world units (voxel:
//   the voxel size).
// BM_SdfParticles/<mesh>/4M/<field>: step_particles on 65536 particles (seeded, outside the
//   solid, random directions, speeds of 1 to 4 % of the box diagonal per second), 60 steps of
//   1/60 s per iteration from the same start (the reset is not timed); per_step = time per
//   particle step; bounced / near = shares of particle steps that bounced / needed a sample.
//   dense / sparse: the particles in random order (each step reads scattered nodes);
//   dense_sorted / sparse_sorted: the same particles sorted by node index once, at the start.
//
// Run (ratios: bench/sdf_ratios.py):
//   build/release/bench/bench_sdf --benchmark_enable_random_interleaving=true \
//     --benchmark_repetitions=5 --benchmark_out=sdf.json --benchmark_out_format=json
//   python3 bench/sdf_ratios.py sdf.json

#include <collide/io/obj.hpp>
#include <collide/sdf/distance_field.hpp>

#include "instruction_set.hpp"
#include "support/random.hpp"

#include <benchmark/benchmark.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace collide;

constexpr int kPoints = 4096;
constexpr int kParticles = 65536;
constexpr int kParticleSteps = 60;
constexpr float kParticleDt = 1.0f / 60.0f;
constexpr float kRestitution = 0.5f;
constexpr double kTargetNodes = 4e6;  // the "4M" voxel
constexpr float kBand = kFieldDefaultBand;

struct Scale {
  const char* name;
  float factor;  ///< voxel = factor * the 4M voxel
};
constexpr std::array<Scale, 4> kScales = {{{"64k", 4.0f}, {"512k", 2.0f}, {"4M", 1.0f}, {"32M", 0.5f}}};
constexpr int kMainScale = 2;  // 4M: the samples and the particles

using VdbGrid = openvdb::FloatGrid;

/// Query points with their exact answers.
struct Points {
  std::vector<Vec3> p;
  std::vector<float> distance;  ///< exact unsigned distance to the mesh
  std::vector<int> inside;      ///< winding number > 1/2; -1: not evaluated (within a voxel)
};

using Counters = std::vector<std::pair<std::string, double>>;

struct Level;

/// One voxel size of one mesh, with its fields (built when first needed) and query points.
struct Res {
  Level* level = nullptr;
  const Scale* scale = nullptr;
  float voxel = 0.0f;
  FieldOptions options;
  Aabb3 box;  ///< collide's grid box: the mesh's bounds plus the margin
  openvdb::math::Transform::Ptr xf;
  std::optional<Points> band, all;
  std::optional<DistanceField3> dense;
  std::optional<SparseDistanceField3> sparse;
  VdbGrid::Ptr vdb;
  float wide_band = 0.0f;  ///< OpenVDB's bands (voxels) covering the dense grid; 0 until known
  std::array<std::optional<Counters>, 6> accuracy;
};

struct Level {
  std::string name;
  TriangleMesh mesh;
  std::vector<openvdb::Vec3s> vdb_points;
  std::vector<openvdb::Vec3I> vdb_triangles;
  Aabb3 bounds;
  std::array<Res, kScales.size()> res;
};

/// A closed torus about the y axis, wound outward.
TriangleMesh make_torus(float major, float minor, int around, int tube) {
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  const float two_pi = 2.0f * test::kPi;
  for (int i = 0; i < around; ++i) {
    const float u = two_pi * static_cast<float>(i) / static_cast<float>(around);
    for (int j = 0; j < tube; ++j) {
      const float v = two_pi * static_cast<float>(j) / static_cast<float>(tube);
      const float r = major + minor * std::cos(v);
      vertices.push_back({r * std::cos(u), minor * std::sin(v), r * std::sin(u)});
    }
  }
  const auto at = [&](int i, int j) { return static_cast<unsigned>((i % around) * tube + j % tube); };
  for (int i = 0; i < around; ++i) {
    for (int j = 0; j < tube; ++j) {
      triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  }
  TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
  if (winding_number(mesh, Vec3(major, 0.0f, 0.0f)) < 0.0f) {  // wound inward: flip
    for (glm::uvec3& t : triangles) std::swap(t.y, t.z);
    mesh = make_triangle_mesh(vertices, triangles);
  }
  return mesh;
}

float exact_distance(const TriangleMesh& mesh, Vec3 p, float bound_squared = std::numeric_limits<float>::infinity()) {
  const BvhNearest n = mesh.bvh.nearest(p - mesh.origin, bound_squared);
  return n.triangle == std::numeric_limits<std::uint32_t>::max() ? std::numeric_limits<float>::infinity()
                                                                  : std::sqrt(n.distance_squared);
}

Points make_points(const Res& r, bool in_band, unsigned seed) {
  const TriangleMesh& mesh = r.level->mesh;
  std::mt19937 rng(seed);
  const float band = kBand * r.voxel;
  Points out;
  for (int attempts = 0; static_cast<int>(out.p.size()) < kPoints && attempts < 1000 * kPoints; ++attempts) {
    const Vec3 p(test::uniform(rng, r.box.min.x, r.box.max.x), test::uniform(rng, r.box.min.y, r.box.max.y),
                 test::uniform(rng, r.box.min.z, r.box.max.z));
    const float d = in_band ? exact_distance(mesh, p, band * band) : exact_distance(mesh, p);
    if (in_band && !(d < band)) continue;
    out.p.push_back(p);
    out.distance.push_back(d);
    out.inside.push_back(d > r.voxel ? (winding_number(mesh, p) > 0.5f ? 1 : 0) : -1);
  }
  if (static_cast<int>(out.p.size()) < kPoints) {
    std::fprintf(stderr, "%s: only %zu band points\n", r.level->name.c_str(), out.p.size());
  }
  return out;
}

const Points& band_points(Res& r) {
  if (!r.band) r.band = make_points(r, true, 17);
  return *r.band;
}
const Points& box_points(Res& r) {
  if (!r.all) r.all = make_points(r, false, 29);
  return *r.all;
}

// ---- the builds ---------------------------------------------------------------------------------

enum Lib { kDense, kSparse, kExact, kVdb, kVdb2, kVdbWide };
const char* const kLibNames[] = {"collide_dense", "collide_sparse", "collide_exact", "openvdb", "openvdb_2t", "openvdb_wide"};

VdbGrid::Ptr build_vdb(const Res& r, float band_voxels) {
  return openvdb::tools::meshToLevelSet<VdbGrid>(*r.xf, r.level->vdb_points, r.level->vdb_triangles, band_voxels);
}

VdbGrid::Ptr build_vdb_wide(const Res& r) {
  return openvdb::tools::meshToSignedDistanceField<VdbGrid>(*r.xf, r.level->vdb_points, r.level->vdb_triangles,
                                                            std::vector<openvdb::Vec4I>(), r.wide_band, r.wide_band);
}

const DistanceField3& dense(Res& r) {
  if (!r.dense) r.dense = make_distance_field(r.level->mesh, r.options);
  return *r.dense;
}
const SparseDistanceField3& sparse(Res& r) {
  if (!r.sparse) r.sparse = make_sparse_distance_field(r.level->mesh, r.options);
  return *r.sparse;
}
const VdbGrid& vdb(Res& r) {
  if (!r.vdb) {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r.vdb = build_vdb(r, kBand);
  }
  return *r.vdb;
}

/// Errors of `value(p)` (a signed distance) against the exact distance: magnitudes, and signs.
template <class Value>
Counters accuracy(Res& r, bool everywhere, Value&& value) {
  Counters out;
  const auto errors = [&](const Points& pts, const char* prefix) {
    double max_err = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < pts.p.size(); ++i) {
      const double e = std::fabs(std::fabs(double(value(pts.p[i]))) - double(pts.distance[i]));
      max_err = std::max(max_err, e);
      sum += e;
    }
    out.push_back({std::string(prefix) + "_max_err", max_err});
    out.push_back({std::string(prefix) + "_mean_err", sum / double(std::max<std::size_t>(pts.p.size(), 1))});
  };
  errors(band_points(r), "band");
  const Points& all = box_points(r);
  if (everywhere) errors(all, "all");
  int agree = 0, counted = 0;
  for (std::size_t i = 0; i < all.p.size(); ++i) {
    if (all.inside[i] < 0) continue;
    ++counted;
    agree += (value(all.p[i]) < 0.0f) == (all.inside[i] == 1);
  }
  out.push_back({"sign_agree", counted ? double(agree) / counted : 0.0});
  return out;
}

Counters vdb_accuracy(Res& r, const VdbGrid& grid, bool everywhere) {
  const VdbGrid::ConstAccessor acc = grid.getConstAccessor();
  const openvdb::tools::GridSampler<VdbGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(acc, grid.transform());
  return accuracy(r, everywhere, [&](Vec3 p) { return sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z)); });
}

void register_build(Res* r, Lib lib) {
  const std::string name = std::string("BM_SdfBuild/") + r->level->name + "/" + r->scale->name + "/" + kLibNames[lib];
  auto* b = benchmark::RegisterBenchmark(name.c_str(), [r, lib](benchmark::State& state) {
    Counters measured;
    std::optional<Counters>& acc = r->accuracy[lib];
    if (lib == kDense || lib == kExact) {
      DistanceField3 field;
      for (auto _ : state) {
        field = lib == kDense ? make_distance_field(r->level->mesh, r->options)
                              : make_distance_field_exact(r->level->mesh, r->options);
        benchmark::DoNotOptimize(field.distances.data());
      }
      measured = {{"bytes", double(field.bytes())},
                  {"distance_bytes", double(field.distances.size() * sizeof(float))},
                  {"nodes", double(field.grid.count())},
                  {"band_nodes", double(field.stats.band_nodes)},
                  {"nearest_queries", double(field.stats.nearest_queries)},
                  {"sign_evaluations", double(field.stats.sign_evaluations)}};
      if (!acc) acc = accuracy(*r, true, [&](Vec3 p) { return field.sample(p); });
    } else if (lib == kSparse) {
      SparseDistanceField3 field;
      for (auto _ : state) {
        field = make_sparse_distance_field(r->level->mesh, r->options);
        benchmark::DoNotOptimize(field.bricks.data());
      }
      measured = {{"bytes", double(field.bytes())}, {"nodes", double(field.stats.nodes)}};
      if (!acc) acc = accuracy(*r, false, [&](Vec3 p) { return field.sample(p); });
    } else {
      if (lib == kVdbWide && r->wide_band == 0.0f) {
        // Both bands as wide as the farthest node of collide's dense grid from the surface, plus
        // two voxels: OpenVDB's field then covers every node collide's does.
        float farthest = 0.0f;
        for (float v : dense(*r).distances) farthest = std::max(farthest, std::fabs(v));
        r->wide_band = std::ceil(farthest / r->voxel) + 2.0f;
      }
      VdbGrid::Ptr grid;
      {
        std::optional<tbb::global_control> one;
        if (lib != kVdb2) one.emplace(tbb::global_control::max_allowed_parallelism, 1);
        for (auto _ : state) {
          grid.reset();  // as collide's loop, which frees the previous field when assigning
          grid = lib == kVdbWide ? build_vdb_wide(*r) : build_vdb(*r, kBand);
          benchmark::DoNotOptimize(grid.get());
        }
      }
      measured = {{"bytes", double(grid->memUsage())}, {"nodes", double(grid->activeVoxelCount())}};
      if (lib == kVdbWide) measured.push_back({"wide_band", r->wide_band});
      if (!acc) acc = vdb_accuracy(*r, *grid, lib == kVdbWide);
    }
    measured.push_back({"voxel", r->voxel});
    for (const auto& [counter, v] : measured) state.counters[counter] = v;
    for (const auto& [counter, v] : *acc) state.counters[counter] = v;
  });
  b->Unit(benchmark::kMillisecond)->UseRealTime();
  if (lib == kExact && r->scale->factor <= 1.0f) b->Iterations(1);
}

// ---- queries ------------------------------------------------------------------------------------

enum Method { kBareRead, kBareLookup, kDenseInside, kDenseSample, kDenseSampleBatch, kDenseGradient, kSparseInside,
              kSparseSample, kVdbPoint, kVdbBox };
const char* const kMethodNames[] = {"bare_read", "bare_lookup", "dense_inside", "dense_sample", "dense_sample_batch",
                                    "dense_gradient", "sparse_inside", "sparse_sample", "openvdb_point", "openvdb_box"};

void register_sample(Res* r, bool in_band, Method method) {
  const std::string name = std::string("BM_SdfSample/") + r->level->name + "/" + r->scale->name + "/" +
                           (in_band ? "band" : "box") + "/" + kMethodNames[method];
  benchmark::RegisterBenchmark(name.c_str(), [r, in_band, method](benchmark::State& state) {
    const std::vector<Vec3>& pts = (in_band ? band_points(*r) : box_points(*r)).p;
    const std::size_t n = pts.size();
    const DistanceField3& d = dense(*r);
    const SparseDistanceField3& s = sparse(*r);
    const VdbGrid& g = vdb(*r);
    const FieldGrid3& grid = d.grid;
    if (glm::length(grid.origin - r->box.min) > 1e-2f * grid.voxel) {
      std::fprintf(stderr, "%s: OpenVDB's voxels are %g voxels off collide's nodes\n", r->level->name.c_str(),
                   double(glm::length(grid.origin - r->box.min) / grid.voxel));
    }
    const float* values = d.distances.data();
    const float inv_voxel = 1.0f / grid.voxel;
    std::vector<std::uint32_t> nearest(n);
    for (std::size_t i = 0; i < n; ++i) {
      const glm::ivec3 at = glm::clamp(glm::ivec3(glm::floor((pts[i] - grid.origin) * inv_voxel + 0.5f)),
                                       glm::ivec3(0), grid.dims - 1);
      nearest[i] = static_cast<std::uint32_t>(grid.index(at));
    }
    const VdbGrid::ConstAccessor acc = g.getConstAccessor();
    const openvdb::tools::GridSampler<VdbGrid::ConstAccessor, openvdb::tools::BoxSampler> box(acc, g.transform());
    const openvdb::tools::GridSampler<VdbGrid::ConstAccessor, openvdb::tools::PointSampler> point(acc, g.transform());
    const auto vdb_p = [](Vec3 p) { return openvdb::Vec3d(p.x, p.y, p.z); };
    std::vector<float> out(n);
    for (auto _ : state) {
      float sum = 0.0f;
      int inside = 0;
      switch (method) {
        case kBareRead:
          for (std::size_t i = 0; i < n; ++i) sum += values[nearest[i]];
          break;
        case kBareLookup:
          for (std::size_t i = 0; i < n; ++i) {
            const Vec3 t = (pts[i] - grid.origin) * inv_voxel + 0.5f;
            const glm::ivec3 at(t);
            if (t.x >= 0.0f && t.y >= 0.0f && t.z >= 0.0f && at.x < grid.dims.x && at.y < grid.dims.y &&
                at.z < grid.dims.z) {
              inside += values[(static_cast<std::size_t>(at.z) * grid.dims.y + at.y) * grid.dims.x + at.x] < 0.0f;
            }
          }
          break;
        case kDenseInside:
          for (const Vec3& p : pts) inside += d.is_inside(p);
          break;
        case kDenseSample:
          for (const Vec3& p : pts) sum += d.sample(p);
          break;
        case kDenseSampleBatch:
          sample(d, std::span<const Vec3>(pts), std::span<float>(out));
          benchmark::DoNotOptimize(out.data());
          benchmark::ClobberMemory();
          break;
        case kDenseGradient:
          for (const Vec3& p : pts) {
            Vec3 gradient;
            sum += d.sample(p, gradient);
            sum += gradient.x;
          }
          break;
        case kSparseInside:
          for (const Vec3& p : pts) inside += s.is_inside(p);
          break;
        case kSparseSample:
          for (const Vec3& p : pts) sum += s.sample(p);
          break;
        case kVdbPoint:
          for (const Vec3& p : pts) inside += point.wsSample(vdb_p(p)) < 0.0f;
          break;
        case kVdbBox:
          for (const Vec3& p : pts) sum += box.wsSample(vdb_p(p));
          break;
      }
      benchmark::DoNotOptimize(sum);
      benchmark::DoNotOptimize(inside);
    }
    state.counters["per_point"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  })->Unit(benchmark::kMicrosecond);
}

// ---- closest points -----------------------------------------------------------------------------

enum ClosestMethod { kStored, kGradient1, kGradient2, kBvhNearest };
const char* const kClosestNames[] = {"stored", "gradient_1", "gradient_2", "bvh_nearest"};

/// The lesson's comparison: the closest surface point from the stored closest-point field
/// (closest_point), by stepping down the distance field's gradient once or twice
/// (closest_point_by_gradient), and exactly through the mesh's BVH (TriangleBvh::nearest, the
/// truth and the cost of not storing anything).
void register_closest(Res* r, bool in_band, ClosestMethod method) {
  const std::string name = std::string("BM_SdfClosest/") + r->level->name + "/" + r->scale->name + "/" +
                           (in_band ? "band" : "box") + "/" + kClosestNames[method];
  benchmark::RegisterBenchmark(name.c_str(), [r, in_band, method](benchmark::State& state) {
    const std::vector<Vec3>& pts = (in_band ? band_points(*r) : box_points(*r)).p;
    const DistanceField3& d = dense(*r);
    const TriangleMesh& mesh = r->level->mesh;
    const auto answer = [&](Vec3 p) {
      switch (method) {
        case kStored: return closest_point(d, p).closest;
        case kGradient1: return closest_point_by_gradient(d, p, 1).closest;
        case kGradient2: return closest_point_by_gradient(d, p, 2).closest;
        case kBvhNearest: break;
      }
      return mesh.bvh.nearest(p - mesh.origin).closest.point + mesh.origin;
    };
    for (auto _ : state) {
      Vec3 sum(0.0f);
      for (const Vec3& p : pts) sum += answer(p);
      benchmark::DoNotOptimize(sum);
    }
    // Errors, world units: how far the answer lies off the surface, and how much farther from
    // the query point it is than the exact closest point (not the distance between the two
    // points: near the medial axis two far-apart surface points are about equally close).
    double off_max = 0.0, off_total = 0.0, excess_max = 0.0, excess_total = 0.0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Vec3 a = answer(pts[i]);
      const double off = exact_distance(mesh, a);
      const double excess = std::fabs(double(glm::length(a - pts[i])) - double(exact_distance(mesh, pts[i])));
      off_max = std::max(off_max, off);
      off_total += off;
      excess_max = std::max(excess_max, excess);
      excess_total += excess;
    }
    const double n = double(pts.size());
    state.counters["off_max"] = off_max;
    state.counters["off_mean"] = off_total / n;
    state.counters["excess_max"] = excess_max;
    state.counters["excess_mean"] = excess_total / n;
    state.counters["voxel"] = r->voxel;
    state.counters["per_point"] =
        benchmark::Counter(double(pts.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  })->Unit(benchmark::kMicrosecond);
}

// ---- particles ----------------------------------------------------------------------------------

Particles3 make_particles(Res& r) {
  const DistanceField3& d = dense(r);
  std::mt19937 rng(41);
  const float diagonal = glm::length(r.box.max - r.box.min);
  Particles3 out;
  while (static_cast<int>(out.positions.size()) < kParticles) {
    const Vec3 p(test::uniform(rng, r.box.min.x, r.box.max.x), test::uniform(rng, r.box.min.y, r.box.max.y),
                 test::uniform(rng, r.box.min.z, r.box.max.z));
    if (d.sample(p) < r.voxel) continue;
    out.positions.push_back(p);
    out.velocities.push_back(test::random_unit3(rng) * (diagonal * test::uniform(rng, 0.01f, 0.04f)));
  }
  return out;
}

/// The same particles in the order of their nodes in memory (as a game that sorts its particles
/// by cell now and then): neighbours in the array read neighbouring nodes.
Particles3 sort_particles(const Particles3& in, const FieldGrid3& grid) {
  std::vector<std::pair<std::size_t, std::size_t>> order;
  for (std::size_t i = 0; i < in.positions.size(); ++i) {
    const glm::ivec3 at = glm::clamp(glm::ivec3((in.positions[i] - grid.origin) / grid.voxel + 0.5f),
                                     glm::ivec3(0), grid.dims - 1);
    order.push_back({grid.index(at), i});
  }
  std::sort(order.begin(), order.end());
  Particles3 out;
  for (const auto& [node, i] : order) {
    out.positions.push_back(in.positions[i]);
    out.velocities.push_back(in.velocities[i]);
  }
  return out;
}

template <class Field>
void run_particles(benchmark::State& state, Res& r, const Field& field, bool sorted) {
  const Particles3 start = sorted ? sort_particles(make_particles(r), field.grid) : make_particles(r);
  Particles3 particles = start;
  double bounced = 0.0, near = 0.0;
  for (auto _ : state) {
    state.PauseTiming();
    std::copy(start.positions.begin(), start.positions.end(), particles.positions.begin());
    std::copy(start.velocities.begin(), start.velocities.end(), particles.velocities.begin());
    state.ResumeTiming();
    for (int step = 0; step < kParticleSteps; ++step) {
      const ParticleStepStats stats = step_particles(field, particles, kParticleDt, kRestitution);
      bounced += double(stats.bounced);
      near += double(stats.near);
    }
    benchmark::DoNotOptimize(particles.positions.data());
  }
  const double steps = double(state.iterations()) * kParticles * kParticleSteps;
  state.counters["per_step"] = benchmark::Counter(double(kParticles) * kParticleSteps,
                                                  benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["bounced"] = bounced / steps;
  state.counters["near"] = near / steps;
}

void register_particles(Res* r, bool use_sparse, bool sorted) {
  const std::string name = std::string("BM_SdfParticles/") + r->level->name + "/" + r->scale->name + "/" +
                           (use_sparse ? "sparse" : "dense") + (sorted ? "_sorted" : "");
  benchmark::RegisterBenchmark(name.c_str(), [r, use_sparse, sorted](benchmark::State& state) {
    if (use_sparse) {
      run_particles(state, *r, sparse(*r), sorted);
    } else {
      run_particles(state, *r, dense(*r), sorted);
    }
  })->Unit(benchmark::kMillisecond);
}

// ---- setup --------------------------------------------------------------------------------------

std::vector<std::unique_ptr<Level>> make_levels() {
  std::vector<std::unique_ptr<Level>> out;
  const auto add = [&out](std::string name, TriangleMesh mesh) {
    auto l = std::make_unique<Level>();
    l->name = std::move(name);
    l->mesh = std::move(mesh);
    for (const Vec3& v : l->mesh.vertices) {
      const Vec3 p = l->mesh.origin + v;  // mesh space, as collide's fields
      l->vdb_points.emplace_back(p.x, p.y, p.z);
    }
    for (const glm::uvec3& t : l->mesh.triangles) l->vdb_triangles.emplace_back(t.x, t.y, t.z);
    l->bounds = compute_aabb(l->mesh, Transform3{});
    const Vec3 size = l->bounds.max - l->bounds.min;
    const float voxel = std::cbrt(static_cast<float>(double(size.x) * size.y * size.z / kTargetNodes));
    for (std::size_t k = 0; k < kScales.size(); ++k) {
      Res& r = l->res[k];
      r.level = l.get();
      r.scale = &kScales[k];
      r.voxel = voxel * kScales[k].factor;
      r.options.voxel = r.voxel;
      r.options.band = kBand;
      // collide's grid box, its origin rounded as the build rounds it (local, then shifted).
      const Vec3 margin(static_cast<float>(r.options.margin) * r.voxel);
      r.box = {l->mesh.origin + (l->mesh.bvh.bounds().min - margin), l->bounds.max + margin};
      r.xf = openvdb::math::Transform::createLinearTransform(r.voxel);
      r.xf->postTranslate(openvdb::Vec3d(r.box.min.x, r.box.min.y, r.box.min.z));
    }
    out.push_back(std::move(l));
  };
  const std::string dir = std::string(COLLIDE_DATA_DIR) + "/meshes/";
  add("dungeon", io::load_triangle_mesh(dir + "recast/dungeon.obj"));
  add("undulating", io::load_triangle_mesh(dir + "recast/undulating.obj"));
  add("torus", make_torus(8.0f, 3.0f, 96, 48));
  return out;
}

std::vector<std::unique_ptr<Level>>& levels() {
  static std::vector<std::unique_ptr<Level>> all = make_levels();
  return all;
}

void register_all() {
  for (auto& l : levels()) {
    for (std::size_t k = 0; k < kScales.size(); ++k) {
      Res* r = &l->res[k];
      const bool finest = kScales[k].factor < 1.0f;
      for (Lib lib : {kDense, kSparse, kExact, kVdb, kVdb2, kVdbWide}) {
        if (finest && (lib == kExact || lib == kVdbWide)) continue;
        register_build(r, lib);
      }
    }
    Res* r = &l->res[kMainScale];
    for (bool in_band : {false, true}) {
      for (int m = kBareRead; m <= kVdbBox; ++m) register_sample(r, in_band, static_cast<Method>(m));
    }
    // The same reads in a field that fits the caches (64k nodes, 256 KiB): what a query costs
    // when its cache lines are not what it waits for.
    for (bool in_band : {false, true}) {
      for (int m = kBareRead; m <= kDenseGradient; ++m) register_sample(&l->res[0], in_band, static_cast<Method>(m));
    }
    for (bool in_band : {false, true}) {
      for (int m = kStored; m <= kBvhNearest; ++m) register_closest(r, in_band, static_cast<ClosestMethod>(m));
    }
    for (bool sorted : {false, true}) {
      register_particles(r, false, sorted);
      register_particles(r, true, sorted);
    }
  }
}

std::string openvdb_context() {
  std::string s = std::string("OpenVDB ") + openvdb::getLibraryAbiVersionString() +
                  " (Debian libopenvdb-dev): meshToLevelSet / meshToSignedDistanceField run in "
                  "libopenvdb.so (explicitly instantiated there; Debian's amd64 build, x86-64 "
                  "baseline), the samplers are header templates compiled here as collide's side (";
  s += collide::bench::compiled_instruction_set();
#if defined(OPENVDB_USE_SSE42) || defined(OPENVDB_USE_AVX)
  s += ", OPENVDB_USE_SSE42/AVX on";
#endif
  return s + ")";
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  openvdb::initialize();
  collide::bench::add_instruction_sets("openvdb", openvdb_context());
  benchmark::AddCustomContext("threads", "collide: one; openvdb: one TBB thread (tbb::global_control), "
                                         "openvdb_2t: every core");
  for (const auto& l : levels()) {
    const Res& r = l->res[kMainScale];
    const Vec3 size = l->bounds.max - l->bounds.min;
    benchmark::AddCustomContext(
        "mesh " + l->name, std::to_string(l->mesh.triangle_count()) + " triangles, " +
                               std::to_string(l->mesh.stats.boundary_edges) + " boundary edges, size " +
                               std::to_string(size.x) + " x " + std::to_string(size.y) + " x " +
                               std::to_string(size.z) + ", 4M voxel " + std::to_string(r.voxel));
  }
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
