// Approximate convex decomposition of 3D meshes: collide's decompose_approximate against
// V-HACD 2.x (Mamou 2016, volumetric splitting by planes: pybullet.vhacd's code, Bullet 3.24's
// Extras/VHACD, compiled here from Debian's Bullet source: vhacd/peer.cmake) and HACD (Mamou &
// Ghorbel, ICIP 2009: surface decimation, V-HACD's predecessor; Debian's libbullet-extras-dev),
// side by side in one run on the same meshes with the same hull budgets, and every result
// measured by the same yardstick: measure_decomposition (the one-sided Hausdorff distances from
// the hulls to the mesh's solid and from the mesh's surface to the hulls, sampled, and the
// hulls' volume over the mesh's). CoACD is a pip package only (coacd); this machine has no
// PyPI and Debian does not package it, so it is not in the run (README says so).
//
// BM_Decompose/<mesh>/<hulls>/<library>: one decomposition per iteration (Iterations(1): they
// take up to seconds), wall time, one thread each.
//   collide: decompose_approximate, concavity 0 (the whole budget spent), max_vertices 64,
//            default resolution (1e5 nodes);
//   vhacd:   pybullet.vhacd's defaults (1e5 voxels, 64 vertices per hull, alpha = beta = 0.05,
//            downsampling 4, voxel mode, hull approximation on) with the budget as V-HACD 2.x
//            takes one: depth log2(budget) (each stage splits every part still concave),
//            concavity 0, no merge (gamma 0). Its stages stop early on parts already convex,
//            so it may give fewer hulls than the budget:
//   collide_at_vhacd_count: collide asked for exactly V-HACD's hull count of the row before;
//   <mesh>/vhacd_defaults/vhacd: V-HACD with all of pybullet's defaults (depth 20, concavity
//            0.0025, merge below gamma 0.00125), the hull count it chooses, and collide at it;
//   hacd:    HACD::Compute with SetNClusters(budget), concavity 1e9 (merging stops at the
//            budget, not at a concavity), SetNVerticesPerCH(64), Bullet demo's other settings
//            (compacity weight 0.1, volume weight 0, extra distance points on), connect distance
//            1% of the diagonal (a soup welded, it is still several components where T-joints
//            or separate parts leave gaps).
//   Counters: hulls; hull_to_mesh and mesh_to_hull as % of the bounding-box diagonal; volume
//   ratio; the hulls' vertices.
// With COLLIDE_BENCH_HULLS_DIR=DIR set, each row's hulls are written to
// DIR/<mesh>_<hulls>_<library>.obj (pictures: `collide decompose MESH --hulls FILE --png`).
//
// Meshes: FCL's rob.obj and env.obj (../shared/data), and assimp-testmodels' spider.obj and
// WusonOBJ.obj (Debian package assimp-testmodels, /usr/share/assimp/models/OBJ/).
//
//   ./build/release/bench/bench_decompose_mesh

#include <collide/core/error.hpp>
#include <collide/decompose/approximate_decomposition.hpp>
#include <collide/io/obj.hpp>

#include <benchmark/benchmark.h>

#include <HACD/hacdHACD.h>
#if COLLIDE_HAVE_VHACD
#include <VHACD.h>
#endif

#include "instruction_set.hpp"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace collide;

struct MeshInput {
  const char* name;
  std::string path;
};

const std::vector<MeshInput>& meshes() {
  static const std::vector<MeshInput> list{
      {"rob", std::string(COLLIDE_DATA_DIR) + "/meshes/fcl/rob.obj"},
      {"env", std::string(COLLIDE_DATA_DIR) + "/meshes/fcl/env.obj"},
      {"spider", "/usr/share/assimp/models/OBJ/spider.obj"},
      {"wuson", "/usr/share/assimp/models/OBJ/WusonOBJ.obj"},
  };
  return list;
}

/// Hull budgets compared.
constexpr int kBudgets[] = {8, 16, 32};
/// Vertices per hull, both libraries.
constexpr int kBenchMaxVertices = 64;
/// HACD joins components closer than this fraction of the diagonal.
constexpr double kHacdConnectFraction = 0.01;
/// Samples of the measurement (each surface).
constexpr int kBenchSamples = 20000;

const TriangleMesh& load(const MeshInput& input) {
  static std::map<std::string, std::unique_ptr<TriangleMesh>> cache;
  auto& slot = cache[input.path];
  if (!slot) slot = std::make_unique<TriangleMesh>(io::load_triangle_mesh(input.path));
  return *slot;
}

/// Counters of a row; with COLLIDE_BENCH_HULLS_DIR set, the hulls also go to
/// DIR/<mesh>_<hulls>_<library>.obj (for pictures: `collide decompose MESH --hulls FILE --png`).
void report(benchmark::State& state, const TriangleMesh& mesh, const std::vector<ConvexHull>& hulls,
            const MeshInput& input, const char* library) {
  if (const char* folder = std::getenv("COLLIDE_BENCH_HULLS_DIR")) {
    io::write_hulls_obj(std::string(folder) + "/" + input.name + "_" + std::to_string(hulls.size()) + "_" + library +
                            ".obj",
                        hulls);
  }
  const DecompositionError e = measure_decomposition(mesh, hulls, kBenchSamples, 1);
  const Aabb3 box = compute_aabb(mesh, Transform3{});
  const float diagonal = glm::length(box.max - box.min);
  int vertices = 0;
  for (const ConvexHull& h : hulls) vertices += h.vertex_count();
  state.counters["hulls"] = static_cast<double>(hulls.size());
  state.counters["hull_to_mesh_pct"] = 100.0 * e.hull_to_mesh / diagonal;
  state.counters["mesh_to_hull_pct"] = 100.0 * e.mesh_to_hull / diagonal;
  state.counters["volume_ratio"] = e.volume_ratio;
  state.counters["vertices"] = vertices;
}

void BM_Collide(benchmark::State& state, const MeshInput* input, int budget) {
  const TriangleMesh& mesh = load(*input);
  ApproximateDecompositionOptions options;
  options.max_hulls = budget;
  options.concavity = 0.0f;
  options.max_vertices = kBenchMaxVertices;
  options.measure_samples = 0;
  std::vector<ConvexHull> hulls;
  for (auto _ : state) {
    ApproximateDecomposition d = decompose_approximate(mesh, options);
    hulls = std::move(d.hulls);
  }
  report(state, mesh, hulls, *input, "collide");
}

void BM_Hacd(benchmark::State& state, const MeshInput* input, int budget) {
  const TriangleMesh& mesh = load(*input);
  // HACD's graph is the mesh's triangle adjacency through shared vertex indices: a soup (three
  // vertices per triangle, as FCL's files are) is welded where positions are exactly equal, as
  // make_triangle_mesh does for its own adjacency. HACD normalises the points it is given in
  // place: a fresh copy per run, mesh space.
  std::vector<HACD::Vec3<HACD::Real>> source_points;
  std::map<std::array<float, 3>, long> welded;
  std::vector<long> index_of(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3 p = mesh.vertices[i] + mesh.origin;
    const auto [it, added] = welded.try_emplace({p.x, p.y, p.z}, static_cast<long>(source_points.size()));
    if (added) source_points.emplace_back(p.x, p.y, p.z);
    index_of[i] = it->second;
  }
  std::vector<HACD::Vec3<long>> triangles;
  for (const glm::uvec3& t : mesh.triangles) triangles.emplace_back(index_of[t[0]], index_of[t[1]], index_of[t[2]]);
  const Aabb3 box = compute_aabb(mesh, Transform3{});
  std::vector<ConvexHull> hulls;
  for (auto _ : state) {
    std::vector<HACD::Vec3<HACD::Real>> points = source_points;
    HACD::HACD hacd;
    hacd.SetPoints(points.data());
    hacd.SetNPoints(points.size());
    hacd.SetTriangles(triangles.data());
    hacd.SetNTriangles(triangles.size());
    hacd.SetCompacityWeight(0.1);
    hacd.SetVolumeWeight(0.0);
    hacd.SetNClusters(static_cast<std::size_t>(budget));
    hacd.SetNVerticesPerCH(kBenchMaxVertices);
    hacd.SetConcavity(1e9);
    hacd.SetConnectDist(kHacdConnectFraction * glm::length(box.max - box.min));
    hacd.SetAddExtraDistPoints(true);
    hacd.SetAddNeighboursDistPoints(false);
    hacd.SetAddFacesPoints(true);
    if (!hacd.Compute()) {
      state.SkipWithError("HACD::Compute failed");
      return;
    }
    hulls.clear();
    for (std::size_t c = 0; c < hacd.GetNClusters(); ++c) {
      std::vector<HACD::Vec3<HACD::Real>> ch_points(hacd.GetNPointsCH(c));
      std::vector<HACD::Vec3<long>> ch_triangles(hacd.GetNTrianglesCH(c));
      hacd.GetCH(c, ch_points.data(), ch_triangles.data());
      std::vector<Vec3> cloud;
      for (const auto& p : ch_points) cloud.emplace_back(float(p.X()), float(p.Y()), float(p.Z()));
      try {
        hulls.push_back(make_convex_hull(cloud));  // its own hull's points: convex already
      } catch (const InvalidInput&) {
        // a flat cluster (a single sheet): no volume, nothing a convex query could use
      }
    }
  }
  if (hulls.empty()) {
    state.SkipWithError("HACD gave no hull with volume");
    return;
  }
  report(state, mesh, hulls, *input, "hacd");
}

#if COLLIDE_HAVE_VHACD
/// Hulls V-HACD gave per (mesh, budget; 0 = its defaults), for the rows that match its count.
std::map<std::pair<std::string, int>, int>& vhacd_hull_counts() {
  static std::map<std::pair<std::string, int>, int> counts;
  return counts;
}

/// V-HACD's clipping stages for a budget: each stage splits every part still concave, so
/// depth d gives at most 2^d hulls.
int vhacd_depth(int budget) {
  int depth = 0;
  while ((2 << depth) <= budget) ++depth;
  return depth;
}

void BM_Vhacd(benchmark::State& state, const MeshInput* input, int budget) {
  const TriangleMesh& mesh = load(*input);
  std::vector<float> points;
  for (const Vec3& v : mesh.vertices) {
    const Vec3 p = v + mesh.origin;
    points.insert(points.end(), {p.x, p.y, p.z});
  }
  std::vector<int> triangles;
  for (const glm::uvec3& t : mesh.triangles)
    triangles.insert(triangles.end(), {int(t[0]), int(t[1]), int(t[2])});
  // pybullet.vhacd's defaults (resolution 1e5 voxels, as collide's grid; 64 vertices per hull;
  // alpha = beta = 0.05, plane and hull downsampling 4, voxel mode, hull approximation on;
  // depth 20, concavity 0.0025, merge below gamma 0.00125). With a budget, the budget as V-HACD
  // takes one: depth log2(budget), concavity 0 (every stage splits every part not convex
  // already) and gamma 0 (no merge stage after).
  VHACD::IVHACD::Parameters params;
  params.m_resolution = 100000;
  params.m_depth = budget > 0 ? vhacd_depth(budget) : 20;
  params.m_concavity = budget > 0 ? 0.0 : 0.0025;
  params.m_gamma = budget > 0 ? 0.0 : 0.00125;
  params.m_alpha = 0.05;
  params.m_beta = 0.05;
  params.m_minVolumePerCH = 0.0001;
  params.m_maxNumVerticesPerCH = kBenchMaxVertices;
  params.m_planeDownsampling = 4;
  params.m_convexhullDownsampling = 4;
  params.m_pca = 0;
  params.m_mode = 0;
  params.m_convexhullApproximation = 1;
  params.m_oclAcceleration = 0;
  std::vector<ConvexHull> hulls;
  for (auto _ : state) {
    VHACD::IVHACD* vhacd = VHACD::CreateVHACD();
    if (!vhacd->Compute(points.data(), 3, static_cast<unsigned>(mesh.vertices.size()), triangles.data(), 3,
                        static_cast<unsigned>(mesh.triangles.size()), params)) {
      vhacd->Release();
      state.SkipWithError("V-HACD Compute failed");
      return;
    }
    hulls.clear();
    for (unsigned c = 0; c < vhacd->GetNConvexHulls(); ++c) {
      VHACD::IVHACD::ConvexHull ch;
      vhacd->GetConvexHull(c, ch);
      std::vector<Vec3> cloud;
      for (unsigned i = 0; i < ch.m_nPoints; ++i)
        cloud.emplace_back(float(ch.m_points[3 * i]), float(ch.m_points[3 * i + 1]), float(ch.m_points[3 * i + 2]));
      try {
        hulls.push_back(make_convex_hull(cloud));
      } catch (const InvalidInput&) {
        // a flat hull: no volume
      }
    }
    vhacd->Clean();
    vhacd->Release();
  }
  if (hulls.empty()) {
    state.SkipWithError("V-HACD gave no hull with volume");
    return;
  }
  vhacd_hull_counts()[{input->name, budget}] = static_cast<int>(hulls.size());
  report(state, mesh, hulls, *input, "vhacd");
}

/// collide with the hull count V-HACD gave in the row before (its stages stop early on parts
/// already convex, and its defaults choose their own count): the same hull count both sides.
void BM_CollideAtVhacdCount(benchmark::State& state, const MeshInput* input, int budget) {
  const auto found = vhacd_hull_counts().find({input->name, budget});
  if (found == vhacd_hull_counts().end()) {
    state.SkipWithError("run with the V-HACD row before it");
    return;
  }
  BM_Collide(state, input, found->second);
}
#endif

void register_all() {
  for (const MeshInput& input : meshes()) {
    if (!std::filesystem::exists(input.path)) {
      std::fprintf(stderr, "bench_decompose_mesh: %s not found (install assimp-testmodels); left out\n",
                   input.path.c_str());
      continue;
    }
    for (const int budget : kBudgets) {
      const std::string base = std::string("BM_Decompose/") + input.name + "/" + std::to_string(budget);
      benchmark::RegisterBenchmark((base + "/collide").c_str(), BM_Collide, &input, budget)
          ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
      benchmark::RegisterBenchmark((base + "/hacd").c_str(), BM_Hacd, &input, budget)
          ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
#if COLLIDE_HAVE_VHACD
      benchmark::RegisterBenchmark((base + "/vhacd").c_str(), BM_Vhacd, &input, budget)
          ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
      benchmark::RegisterBenchmark((base + "/collide_at_vhacd_count").c_str(), BM_CollideAtVhacdCount, &input, budget)
          ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
    }
#if COLLIDE_HAVE_VHACD
    const std::string base = std::string("BM_Decompose/") + input.name + "/vhacd_defaults";
    benchmark::RegisterBenchmark((base + "/vhacd").c_str(), BM_Vhacd, &input, 0)
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
    benchmark::RegisterBenchmark((base + "/collide_at_vhacd_count").c_str(), BM_CollideAtVhacdCount, &input, 0)
        ->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();
#endif
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  collide::bench::add_instruction_sets("hacd", "Debian's libHACD (Bullet 3.24 Extras), built for x86-64 baseline (SSE2)");
#if COLLIDE_HAVE_VHACD
  collide::bench::add_instruction_sets("vhacd", "V-HACD 2.x from Debian's Bullet 3.24 source, this build's flags (x86-64 baseline, SSE2), one thread");
#endif
  register_all();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
