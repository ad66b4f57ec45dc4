// Walking agents on dungeon.obj: collide's WalkMesh against Recast/Detour, same level, same
// start points, same steering, in one run.
//  - Walk step: WalkMesh::walk + to_world_point, against dtNavMeshQuery::moveAlongSurface +
//    getPolyHeight (the per-frame pattern of DetourCrowd and RecastDemo), small steps (0.1 m).
//  - Nearest point: WalkMesh::nearest_walk_point against dtNavMeshQuery::findNearestPoly
//    (search box of half extents 2, 4, 2, as RecastDemo uses), for query points within half a
//    metre (per axis) of the walkable floor. Two collide variants: unbounded (the exact nearest
//    point however far: more than Detour answers) and bounded by a ball of radius
//    sqrt(2^2 + 4^2 + 2^2) = 4.9 m, the ball around Detour's search box (every point Detour could
//    return, and more). Both return the exact nearest point of the walk mesh; Detour returns its
//    nearest polygon and the closest point on it (on its detail mesh when over the polygon).
//  - Build: make_walk_mesh against the Recast + Detour pipeline below, from the same triangles.
// The navmesh is built with RecastDemo's default parameters (cell 0.3, agent height 2, radius
// 0.6, climb 0.9, slope 45 degrees); the walk mesh with make_walk_mesh (height 2, slope 45).

#include <collide/io/obj.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <DetourNavMesh.h>
#include <DetourNavMeshBuilder.h>
#include <DetourNavMeshQuery.h>
#include <Recast.h>

#include <benchmark/benchmark.h>

#include "instruction_set.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

namespace {

using collide::Vec3;

constexpr int kAgents = 64;
constexpr int kHeadings = 4096;   // steering table length per agent
constexpr float kStep = 0.1f;     // metres per tick
constexpr int kQueries = 1024;
const float kHalfExtents[3] = {2.0f, 4.0f, 2.0f};

struct Detour {
  dtNavMesh* mesh = nullptr;
  dtNavMeshQuery* query = nullptr;
  dtQueryFilter filter;
  ~Detour() {
    dtFreeNavMeshQuery(query);
    dtFreeNavMesh(mesh);
  }
};

/// The RecastDemo "solo mesh" pipeline with its default settings.
std::unique_ptr<Detour> build_detour(const collide::TriangleSoup& level) {
  std::vector<float> verts;
  for (const Vec3& p : level.positions) verts.insert(verts.end(), {p.x, p.y, p.z});
  std::vector<int> tris;
  for (const glm::uvec3& t : level.triangles) {
    tris.insert(tris.end(), {static_cast<int>(t.x), static_cast<int>(t.y), static_cast<int>(t.z)});
  }
  const int nv = static_cast<int>(level.positions.size());
  const int nt = static_cast<int>(level.triangles.size());
  rcContext ctx(false);
  rcConfig cfg{};
  cfg.cs = 0.3f;
  cfg.ch = 0.2f;
  cfg.walkableSlopeAngle = 45.0f;
  cfg.walkableHeight = static_cast<int>(std::ceil(2.0f / cfg.ch));
  cfg.walkableClimb = static_cast<int>(std::floor(0.9f / cfg.ch));
  cfg.walkableRadius = static_cast<int>(std::ceil(0.6f / cfg.cs));
  cfg.maxEdgeLen = static_cast<int>(12.0f / cfg.cs);
  cfg.maxSimplificationError = 1.3f;
  cfg.minRegionArea = 8 * 8;
  cfg.mergeRegionArea = 20 * 20;
  cfg.maxVertsPerPoly = 6;
  cfg.detailSampleDist = cfg.cs * 6.0f;
  cfg.detailSampleMaxError = cfg.ch * 1.0f;
  rcCalcBounds(verts.data(), nv, cfg.bmin, cfg.bmax);
  rcCalcGridSize(cfg.bmin, cfg.bmax, cfg.cs, &cfg.width, &cfg.height);

  rcHeightfield* solid = rcAllocHeightfield();
  rcCompactHeightfield* chf = rcAllocCompactHeightfield();
  rcContourSet* cset = rcAllocContourSet();
  rcPolyMesh* pmesh = rcAllocPolyMesh();
  rcPolyMeshDetail* dmesh = rcAllocPolyMeshDetail();
  std::vector<unsigned char> areas(static_cast<std::size_t>(nt), 0);
  bool ok = rcCreateHeightfield(&ctx, *solid, cfg.width, cfg.height, cfg.bmin, cfg.bmax, cfg.cs, cfg.ch);
  rcMarkWalkableTriangles(&ctx, cfg.walkableSlopeAngle, verts.data(), nv, tris.data(), nt, areas.data());
  ok = ok && rcRasterizeTriangles(&ctx, verts.data(), nv, tris.data(), areas.data(), nt, *solid, cfg.walkableClimb);
  rcFilterLowHangingWalkableObstacles(&ctx, cfg.walkableClimb, *solid);
  rcFilterLedgeSpans(&ctx, cfg.walkableHeight, cfg.walkableClimb, *solid);
  rcFilterWalkableLowHeightSpans(&ctx, cfg.walkableHeight, *solid);
  ok = ok && rcBuildCompactHeightfield(&ctx, cfg.walkableHeight, cfg.walkableClimb, *solid, *chf);
  ok = ok && rcErodeWalkableArea(&ctx, cfg.walkableRadius, *chf);
  ok = ok && rcBuildDistanceField(&ctx, *chf);
  ok = ok && rcBuildRegions(&ctx, *chf, 0, cfg.minRegionArea, cfg.mergeRegionArea);
  ok = ok && rcBuildContours(&ctx, *chf, cfg.maxSimplificationError, cfg.maxEdgeLen, *cset);
  ok = ok && rcBuildPolyMesh(&ctx, *cset, cfg.maxVertsPerPoly, *pmesh);
  ok = ok && rcBuildPolyMeshDetail(&ctx, *pmesh, *chf, cfg.detailSampleDist, cfg.detailSampleMaxError, *dmesh);
  if (!ok) throw std::runtime_error("Recast build failed");
  for (int i = 0; i < pmesh->npolys; ++i) pmesh->flags[i] = 1;

  dtNavMeshCreateParams params{};
  params.verts = pmesh->verts;
  params.vertCount = pmesh->nverts;
  params.polys = pmesh->polys;
  params.polyAreas = pmesh->areas;
  params.polyFlags = pmesh->flags;
  params.polyCount = pmesh->npolys;
  params.nvp = pmesh->nvp;
  params.detailMeshes = dmesh->meshes;
  params.detailVerts = dmesh->verts;
  params.detailVertsCount = dmesh->nverts;
  params.detailTris = dmesh->tris;
  params.detailTriCount = dmesh->ntris;
  params.walkableHeight = 2.0f;
  params.walkableRadius = 0.6f;
  params.walkableClimb = 0.9f;
  rcVcopy(params.bmin, pmesh->bmin);
  rcVcopy(params.bmax, pmesh->bmax);
  params.cs = cfg.cs;
  params.ch = cfg.ch;
  params.buildBvTree = true;
  unsigned char* data = nullptr;
  int size = 0;
  if (!dtCreateNavMeshData(&params, &data, &size)) throw std::runtime_error("dtCreateNavMeshData failed");
  auto out = std::make_unique<Detour>();
  out->mesh = dtAllocNavMesh();
  if (dtStatusFailed(out->mesh->init(data, size, DT_TILE_FREE_DATA))) throw std::runtime_error("dtNavMesh::init failed");
  out->query = dtAllocNavMeshQuery();
  if (dtStatusFailed(out->query->init(out->mesh, 2048))) throw std::runtime_error("dtNavMeshQuery::init failed");
  rcFreeHeightField(solid);
  rcFreeCompactHeightfield(chf);
  rcFreeContourSet(cset);
  rcFreePolyMesh(pmesh);
  rcFreePolyMeshDetail(dmesh);
  return out;
}

/// Everything both sides share: the level, both meshes, start points, steering, query points.
struct Scene {
  collide::TriangleSoup level;
  collide::WalkMesh walk_mesh;
  std::unique_ptr<Detour> detour;
  std::vector<Vec3> starts;           // world points on both meshes
  std::vector<Vec3> steps;            // kAgents x kHeadings horizontal steps
  std::vector<Vec3> queries;          // points near the walkable floor
  Scene() {
    level = collide::io::load_obj(std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj");
    walk_mesh = collide::make_walk_mesh(level, {0.785398f, 2.0f, {0, 1, 0}});
    detour = build_detour(level);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    // Points uniform over the walkable area (not per triangle: the walk mesh has many small
    // pieces along obstacles).
    std::vector<float> cumulative(walk_mesh.triangle_count());
    float area = 0.0f;
    for (std::uint32_t t = 0; t < walk_mesh.triangle_count(); ++t) cumulative[t] = (area += walk_mesh.triangle_area(t));
    auto random_triangle = [&]() {
      const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), unit(rng) * area);
      return static_cast<std::uint32_t>(std::min<std::ptrdiff_t>(it - cumulative.begin(), walk_mesh.triangle_count() - 1));
    };
    // Start points: walk-mesh points where Detour also has ground within 0.3 m.
    while (starts.size() < kAgents) {
      const std::uint32_t t = random_triangle();
      const Vec3 p = walk_mesh.to_world_point(walk_mesh.walk_point(t, {unit(rng), unit(rng), unit(rng)}));
      dtPolyRef ref = 0;
      float nearest[3];
      detour->query->findNearestPoly(&p.x, kHalfExtents, &detour->filter, &ref, nearest);
      if (ref != 0 && glm::length(Vec3(nearest[0], nearest[1], nearest[2]) - p) < 0.3f) starts.push_back(p);
    }
    for (int a = 0; a < kAgents; ++a) {
      float heading = unit(rng) * 6.2831853f;
      for (int k = 0; k < kHeadings; ++k) {
        heading += (unit(rng) - 0.5f) * 0.6f;
        steps.push_back(kStep * Vec3(std::cos(heading), 0.0f, std::sin(heading)));
      }
    }
    for (int i = 0; i < kQueries; ++i) {
      const std::uint32_t t = random_triangle();
      const Vec3 p = walk_mesh.to_world_point(walk_mesh.walk_point(t, {unit(rng), unit(rng), unit(rng)}));
      queries.push_back(p + Vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f));
    }
  }
};

const Scene& scene() {
  static const Scene s;
  return s;
}

void BM_WalkStep_Collide(benchmark::State& state) {
  const Scene& s = scene();
  const collide::WalkMesh& mesh = s.walk_mesh;
  std::vector<collide::WalkPoint> at;
  for (const Vec3& p : s.starts) at.push_back(mesh.nearest_walk_point(p));
  std::size_t tick = 0;
  for (auto _ : state) {
    const std::size_t k = tick++ % kHeadings;
    for (int a = 0; a < kAgents; ++a) {
      const collide::WalkResult r = mesh.walk(at[a], s.steps[a * kHeadings + k]);
      at[a] = r.end;
      const Vec3 world = mesh.to_world_point(r.end);
      benchmark::DoNotOptimize(world);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kAgents);
}

void BM_WalkStep_Detour(benchmark::State& state) {
  const Scene& s = scene();
  const dtNavMeshQuery& q = *s.detour->query;
  std::vector<dtPolyRef> ref(kAgents);
  std::vector<Vec3> pos(kAgents);
  for (int a = 0; a < kAgents; ++a) q.findNearestPoly(&s.starts[a].x, kHalfExtents, &s.detour->filter, &ref[a], &pos[a].x);
  std::size_t tick = 0;
  dtPolyRef visited[16];
  for (auto _ : state) {
    const std::size_t k = tick++ % kHeadings;
    for (int a = 0; a < kAgents; ++a) {
      const Vec3 target = pos[a] + s.steps[a * kHeadings + k];
      Vec3 result;
      int nvisited = 0;
      q.moveAlongSurface(ref[a], &pos[a].x, &target.x, &s.detour->filter, &result.x, visited, &nvisited, 16);
      if (nvisited > 0) ref[a] = visited[nvisited - 1];
      float h = result.y;
      q.getPolyHeight(ref[a], &result.x, &h);
      result.y = h;
      pos[a] = result;
      benchmark::DoNotOptimize(pos[a]);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kAgents);
}

void BM_NearestPoint_Collide(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) {
    for (const Vec3& p : s.queries) benchmark::DoNotOptimize(s.walk_mesh.nearest_walk_point(p));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kQueries);
}

void BM_NearestPointWithin_Collide(benchmark::State& state) {
  const Scene& s = scene();
  const float reach = std::sqrt(kHalfExtents[0] * kHalfExtents[0] + kHalfExtents[1] * kHalfExtents[1] +
                                kHalfExtents[2] * kHalfExtents[2]);
  for (auto _ : state) {
    for (const Vec3& p : s.queries) benchmark::DoNotOptimize(s.walk_mesh.nearest_walk_point(p, reach));
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kQueries);
}

void BM_NearestPoint_Detour(benchmark::State& state) {
  const Scene& s = scene();
  const dtNavMeshQuery& q = *s.detour->query;
  for (auto _ : state) {
    for (const Vec3& p : s.queries) {
      dtPolyRef ref = 0;
      float nearest[3];
      q.findNearestPoly(&p.x, kHalfExtents, &s.detour->filter, &ref, nearest);
      benchmark::DoNotOptimize(ref);
      benchmark::DoNotOptimize(nearest);
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * kQueries);
}

// Building what the walks run on, from the level's triangles: collide's walk mesh (slope and
// headroom filters on the exact triangles, refinement under obstacles, adjacency, BVH) against
// Recast's solo-mesh pipeline and Detour's navmesh (voxels, regions, contours, polygons, detail
// mesh, BV tree). Not the same product: Recast also erodes by the agent's radius and simplifies.
void BM_Build_Collide(benchmark::State& state) {
  const Scene& s = scene();
  std::size_t triangles = 0;
  for (auto _ : state) {
    const collide::WalkMesh mesh = collide::make_walk_mesh(s.level, {0.785398f, 2.0f, {0, 1, 0}});
    triangles = mesh.triangle_count();
    benchmark::DoNotOptimize(triangles);
  }
  state.counters["triangles"] = static_cast<double>(triangles);
}

void BM_Build_Detour(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) {
    const std::unique_ptr<Detour> detour = build_detour(s.level);
    benchmark::DoNotOptimize(detour.get());
  }
}

BENCHMARK(BM_Build_Collide)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Build_Detour)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WalkStep_Collide);
BENCHMARK(BM_WalkStep_Detour);
BENCHMARK(BM_NearestPoint_Collide);
BENCHMARK(BM_NearestPointWithin_Collide);
BENCHMARK(BM_NearestPoint_Detour);

}  // namespace

int main(int argc, char** argv) {
  return collide::bench::run_benchmarks(argc, argv, [] {
    collide::bench::add_instruction_sets("recast/detour", collide::bench::kDebianPackageIsa);
  });
}
