// Walk meshes from the real Recast demo levels (dungeon.obj: non-manifold edges, many islands;
// undulating.obj: coordinates near 5000) and make_walk_mesh's slope and headroom filters.
#include "walk_fixtures.hpp"

#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

namespace collide {
namespace {

using test::brute_distance;
using test::random_tangent;
using test::random_walk_point;
using test::uniform;

std::string mesh_path(const char* name) { return std::string(COLLIDE_DATA_DIR) + "/meshes/recast/" + name; }

const TriangleSoup& dungeon() {
  static const TriangleSoup soup = io::load_obj(mesh_path("dungeon.obj"));
  return soup;
}
const TriangleSoup& undulating() {
  static const TriangleSoup soup = io::load_obj(mesh_path("undulating.obj"));
  return soup;
}

double distance(Vec3 a, Vec3 b) { return glm::length(glm::dvec3(a) - glm::dvec3(b)); }

/// Segment-triangle intersection in double precision (Moeller-Trumbore), an independent check
/// of the headroom filter.
bool segment_hits_triangle(glm::dvec3 p, glm::dvec3 q, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c) {
  const glm::dvec3 d = q - p, e1 = b - a, e2 = c - a;
  const glm::dvec3 h = glm::cross(d, e2);
  const double det = glm::dot(e1, h);
  if (std::fabs(det) < 1e-12) return false;
  const glm::dvec3 s = p - a;
  const double u = glm::dot(s, h) / det;
  if (u < 0.0 || u > 1.0) return false;
  const glm::dvec3 qv = glm::cross(s, e1);
  const double v = glm::dot(d, qv) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = glm::dot(e2, qv) / det;
  return t >= 0.0 && t <= 1.0;
}

TEST(LevelWalkMesh, WholeDungeonBuildsWithItsKnownDefects) {
  const WalkMesh mesh = build_walk_mesh(dungeon());
  const WalkMeshStats& s = mesh.stats();
  // SOURCES.md: 5,101 vertices, 10,133 triangles, no degenerate ones, 138 non-manifold edges.
  // The level also has T-junctions; each split adds a triangle (and may add a shared edge).
  EXPECT_GT(s.t_junction_splits, 0u);
  EXPECT_EQ(s.triangles, 10133u + s.t_junction_splits);
  EXPECT_EQ(s.vertices, 5101u);
  EXPECT_EQ(s.degenerate_triangles, 0u);
  EXPECT_GE(s.non_manifold_edges, 138u);
  EXPECT_GE(s.boundary_edges, 432u);  // the open edges, plus unpaired sides of non-manifold edges
  EXPECT_GT(s.islands, 1u);
}

TEST(LevelWalkMesh, UndulatingIslandsMatchAnIndependentCount) {
  // Union-find over shared vertex indices: the terrain plus 50 six-vertex props.
  const TriangleSoup& soup = undulating();
  std::vector<std::uint32_t> parent(soup.positions.size());
  for (std::uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const glm::uvec3& t : soup.triangles) {
    parent[find(t.y)] = find(t.x);
    parent[find(t.z)] = find(t.x);
  }
  std::size_t roots = 0;
  for (std::uint32_t i = 0; i < parent.size(); ++i) roots += find(i) == i;
  const WalkMesh mesh = build_walk_mesh(soup);
  EXPECT_EQ(mesh.stats().islands, roots);
  // SOURCES.md counts 196 unshared edges; two knife-edge folds (< 2.5 degrees, kFoldBackLinkCos)
  // in the props are not linked either, which adds their four sides.
  EXPECT_GE(mesh.stats().boundary_edges, 196u);
  EXPECT_LE(mesh.stats().boundary_edges, 196u + 8u);
  EXPECT_EQ(mesh.stats().non_manifold_edges, 0u);
}

TEST(LevelWalkMesh, MakeWalkMeshKeepsWalkableSlopesWithHeadroom) {
  const TriangleSoup& level = dungeon();
  const WalkAgent agent{0.785398f, 2.0f, {0, 1, 0}};
  const WalkMesh mesh = make_walk_mesh(level, agent);
  const WalkMeshStats& s = mesh.stats();
  EXPECT_EQ(s.input_triangles, level.triangles.size());
  EXPECT_GT(s.too_steep_triangles, 1000u);
  EXPECT_GT(s.low_headroom_triangles, 100u);
  EXPECT_GT(s.triangles, 1000u);
  EXPECT_GT(s.headroom_refined_triangles, 100u);  // partly covered triangles keep their open parts
  EXPECT_LE(s.too_steep_triangles + s.low_headroom_triangles, level.triangles.size());
  std::mt19937 rng(51);
  int checked = 0, facing_down = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const WalkPoint p = mesh.walk_point(t, Vec3(1.0f));
    const float up = mesh.to_world_triangle_normal(p).y;
    EXPECT_GE(std::fabs(up), std::cos(agent.max_slope) - 1e-5f);  // walkable slope
    facing_down += up < 0.0f;
    if (t % 5 != 0) continue;
    // Headroom: vertical segments over points of a kept triangle meet no level triangle.
    for (int k = 0; k < 3; ++k) {
      float u = test::uniform01(rng), v = test::uniform01(rng);
      if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
      const WalkPoint sample = mesh.walk_point(t, {1.0f - u - v, u, v});
      // Level geometry that touches the space above within kHeadroomTolerance does not count:
      // stay that far inside the triangle.
      bool near_edge = false;
      const glm::uvec3 tri = mesh.triangle(t);
      for (int e = 0; e < 3; ++e) {
        const glm::dvec3 a(mesh.world_vertex(tri[e])), b(mesh.world_vertex(tri[(e + 1) % 3]));
        const glm::dvec3 q(mesh.to_world_point(sample));
        const double s = std::clamp(glm::dot(q - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
        near_edge |= glm::length(q - (a + s * (b - a))) < 4.0 * kHeadroomTolerance * 100.0;
      }
      if (near_edge) continue;
      const glm::dvec3 base(mesh.to_world_point(sample));
      const glm::dvec3 lo = base + glm::dvec3(0, 0.01, 0), hi = base + glm::dvec3(0, agent.height - 0.01, 0);
      for (const glm::uvec3& o : level.triangles) {
        ASSERT_FALSE(segment_hits_triangle(lo, hi, level.positions[o.x], level.positions[o.y], level.positions[o.z]))
            << "kept triangle " << t << " has level geometry above it: level triangle " << (&o - level.triangles.data())
            << " base " << base.x << " " << base.y << " " << base.z << " obstacle " << level.positions[o.x].x << ","
            << level.positions[o.x].y << "," << level.positions[o.x].z << " " << level.positions[o.y].x << ","
            << level.positions[o.y].y << "," << level.positions[o.y].z << " " << level.positions[o.z].x << ","
            << level.positions[o.z].y << "," << level.positions[o.z].z;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
  // Islands are wound to face up; only where the walkable surface folds over itself (two-sided
  // slopes meeting at a sharp crease) can a few triangles end up facing down.
  EXPECT_LT(facing_down, static_cast<int>(mesh.triangle_count() / 1000));
  // A taller agent fits in fewer places, a steeper-walking one in more.
  EXPECT_LT(make_walk_mesh(level, {0.785398f, 4.0f, {0, 1, 0}}).triangle_count(), mesh.triangle_count());
  EXPECT_GT(make_walk_mesh(level, {1.2f, 2.0f, {0, 1, 0}}).triangle_count(), mesh.triangle_count());
}

TEST(LevelWalkMesh, NearestWalkPointEqualsBruteForceOnRealLevels) {
  std::mt19937 rng(53);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    const Aabb3 box = fatten(mesh.bounds(), 2.0f);
    for (int i = 0; i < 300; ++i) {
      const Vec3 q(uniform(rng, box.min.x, box.max.x), uniform(rng, box.min.y, box.max.y),
                   uniform(rng, box.min.z, box.max.z));
      const WalkPoint p = mesh.nearest_walk_point(q);
      ASSERT_TRUE(mesh.is_valid(p));
      const double tol = 1e-6 * (100.0 + glm::length(glm::dvec3(q)));  // ~5e-3 near 5000
      EXPECT_NEAR(distance(mesh.to_world_point(p), q), brute_distance(mesh, q), tol) << level->name << " " << i;
    }
  }
}

TEST(LevelWalkMesh, NearestWalkPointNearTheSurfaceEqualsBruteForceOnRealLevels) {
  // The queries a game makes (and the bench times): within half a metre of the walkable floor,
  // where many triangles are at nearly the same distance (close calls for the pruning).
  std::mt19937 rng(54);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    int on_face = 0;
    for (int i = 0; i < 1000; ++i) {
      const Vec3 on = mesh.to_world_point(random_walk_point(mesh, rng));
      const float r = i % 5 == 0 ? 0.0f : 0.5f;
      const Vec3 q = on + Vec3(uniform(rng, -r, r), uniform(rng, -r, r), uniform(rng, -r, r));
      const WalkPoint p = mesh.nearest_walk_point(q);
      ASSERT_TRUE(mesh.is_valid(p));
      const double tol = 1e-6 * (100.0 + glm::length(glm::dvec3(q)));
      EXPECT_NEAR(distance(mesh.to_world_point(p), q), brute_distance(mesh, q), tol) << level->name << " " << i;
      on_face += std::min({p.weights.x, p.weights.y, p.weights.z}) > 0.0f;
    }
    EXPECT_GT(on_face, 300) << level->name;  // face regions and edge/vertex regions both occur
    EXPECT_LT(on_face, 990) << level->name;
  }
}

TEST(LevelWalkMesh, AgentsWalkingOnRealLevelsStayOnTheMesh) {
  std::mt19937 rng(57);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    const double tol = 1e-6 * (100.0 + glm::length(glm::dvec3(mesh.origin())));
    int walls = 0, crossings = 0;
    for (int agent = 0; agent < 10; ++agent) {
      WalkPoint p = random_walk_point(mesh, rng);
      for (int step = 0; step < 40; ++step) {
        const WalkResult r = mesh.walk(p, random_tangent(rng, mesh.to_world_triangle_normal(p), uniform(rng, 0.0f, 3.0f)));
        ASSERT_TRUE(mesh.is_valid(r.end));
        EXPECT_NE(r.status, WalkStatus::iteration_limit);
        EXPECT_EQ(mesh.island(r.end.triangle), mesh.island(p.triangle));
        ASSERT_LT(brute_distance(mesh, mesh.to_world_point(r.end)), tol) << level->name;
        // No jumps: the straight line from start to end is no longer than the path walked.
        EXPECT_LE(distance(mesh.to_world_point(r.end), mesh.to_world_point(p)), r.distance + tol) << level->name;
        walls += r.walls_hit > 0;
        crossings += r.edges_crossed;
        p = r.end;
      }
    }
    EXPECT_GT(walls, 3) << level->name;  // both outcomes (undulating.obj is open terrain: few walls)
    EXPECT_GT(crossings, 200) << level->name;
  }
}

TEST(LevelWalkMesh, WalkThereAndBackOnRealLevels) {
  // Away from walls a walk keeps its whole length, however many edges and folds it crosses, and
  // walking its carried step backwards returns to the start.
  std::mt19937 rng(59);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    const double tol = 2e-6 * (100.0 + glm::length(glm::dvec3(mesh.origin())));
    int returned = 0, over_edges = 0, over_folds = 0;
    for (int i = 0; i < 400; ++i) {
      const WalkPoint start = random_walk_point(mesh, rng);
      const Vec3 step = random_tangent(rng, mesh.to_world_triangle_normal(start), 1.5f);
      const WalkResult go = mesh.walk(start, step);
      if (go.walls_hit > 0) continue;
      EXPECT_EQ(go.status, WalkStatus::completed);
      EXPECT_NEAR(go.distance, 1.5f, 1e-5f) << level->name << " " << i;  // no length lost
      EXPECT_NEAR(glm::length(go.end_step), 1.5f, 1e-5f) << level->name << " " << i;
      const WalkResult back = mesh.walk(go.end, -go.end_step);
      EXPECT_EQ(back.walls_hit, 0);
      EXPECT_NEAR(back.distance, go.distance, 1e-5f) << level->name << " " << i;
      EXPECT_LT(distance(mesh.to_world_point(back.end), mesh.to_world_point(start)), tol) << level->name << " " << i;
      ++returned;
      over_edges += go.edges_crossed > 0;
      over_folds += glm::dot(mesh.to_world_triangle_normal(start), mesh.to_world_triangle_normal(go.end)) < 0.9999f;
    }
    // Both outcomes happen, and the returns really cross edges and changes of slope.
    EXPECT_GT(returned, 100) << level->name;
    EXPECT_LT(returned, 400) << level->name;
    EXPECT_GT(over_edges, returned / 2) << level->name;
    EXPECT_GT(over_folds, returned / 4) << level->name;
  }
}

TEST(LevelWalkMesh, WalkEqualsWalkInTriangleAndCrossEdgeStepByStepOnRealLevels) {
  // `walk` inlines the two primitives for speed; composed by hand through the public API (walk in
  // the triangle, cross the edge reached, turn what is left of the step by the crossing's
  // rotation) they must give the same walk wherever no wall is met.
  std::mt19937 rng(60);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    const double tol = 2e-6 * (100.0 + glm::length(glm::dvec3(mesh.origin())));
    int compared = 0, long_walks = 0;
    for (int i = 0; i < 400; ++i) {
      const WalkPoint start = random_walk_point(mesh, rng);
      const Vec3 step = random_tangent(rng, mesh.to_world_triangle_normal(start), uniform(rng, 0.1f, 3.0f));
      WalkPoint p = start;
      Vec3 left = step;
      int crossings = 0;
      bool wall = false;
      for (int k = 0; k < kMaxWalkIterations; ++k) {
        const TriangleWalk w = mesh.walk_in_triangle(p, left);
        p = w.end;
        if (!w.hit_edge) break;
        const std::optional<EdgeCrossing> c = mesh.cross_edge(w.end);
        if (!c) {
          wall = true;
          break;
        }
        left = c->rotation * ((1.0f - w.time) * left);
        p = c->end;
        ++crossings;
      }
      if (wall) continue;
      const WalkResult r = mesh.walk(start, step);
      ASSERT_EQ(r.walls_hit, 0) << level->name << " " << i;
      EXPECT_LT(distance(mesh.to_world_point(r.end), mesh.to_world_point(p)), tol) << level->name << " " << i;
      EXPECT_EQ(r.edges_crossed, crossings) << level->name << " " << i;
      ++compared;
      long_walks += crossings >= 3;
    }
    EXPECT_GT(compared, 100) << level->name;
    EXPECT_GT(long_walks, compared / 4) << level->name;
  }
}

TEST(LevelWalkMesh, CrossingEdgesOnRealLevelsKeepsTheWorldPosition) {
  std::mt19937 rng(61);
  for (const TriangleSoup* level : {&dungeon(), &undulating()}) {
    const WalkMesh mesh = make_walk_mesh(*level);
    const double tol = 1e-6 * (100.0 + glm::length(glm::dvec3(mesh.origin())));
    int crossed = 0;
    for (int i = 0; i < 1000; ++i) {
      const WalkPoint p = random_walk_point(mesh, rng);
      const TriangleWalk w = mesh.walk_in_triangle(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 5.0f));
      if (!w.hit_edge) continue;
      if (const auto c = mesh.cross_edge(w.end)) {
        ++crossed;
        EXPECT_LT(distance(mesh.to_world_point(w.end), mesh.to_world_point(c->end)), tol);
      }
    }
    EXPECT_GT(crossed, 300) << level->name;
  }
}

TEST(LevelWalkMesh, AFarAwayPieceDoesNotCoarsenTheRestOfTheLevel) {
  // A 10 m floor far from the dungeon (a hidden room, a spawn area): the tolerances of welding,
  // T-junctions and headroom were fractions of the whole mesh's size, so 1 km away the dungeon
  // was welded at 1 cm and 10 km away at 10 cm, silently collapsing 1,600 and 11,700 of its
  // triangles. Now the dungeon's walk mesh is the same with or without the far floor, and a
  // floor so far that one float frame cannot hold both is refused, saying why.
  const TriangleSoup& level = dungeon();
  const WalkMesh alone = make_walk_mesh(level);
  for (const float far : {1e3f, 1e4f}) {
    TriangleSoup with = level;
    const auto b = static_cast<unsigned>(with.positions.size());
    with.positions.insert(with.positions.end(), {{far, 0.0f, far}, {far + 10.0f, 0.0f, far}, {far, 0.0f, far + 10.0f}});
    with.triangles.push_back({b, b + 2, b + 1});
    const WalkMesh mesh = make_walk_mesh(with);
    const WalkMeshStats& s = mesh.stats();
    EXPECT_EQ(s.triangles, alone.stats().triangles + 1) << far;
    EXPECT_EQ(s.degenerate_triangles, alone.stats().degenerate_triangles) << far;
    EXPECT_EQ(s.welded_vertices, alone.stats().welded_vertices) << far;
    EXPECT_EQ(s.islands, alone.stats().islands + 1) << far;
    EXPECT_EQ(s.boundary_edges, alone.stats().boundary_edges + 3) << far;
    EXPECT_EQ(s.low_headroom_triangles, alone.stats().low_headroom_triangles) << far;
  }
  TriangleSoup too_far = level;
  const auto b = static_cast<unsigned>(too_far.positions.size());
  too_far.positions.insert(too_far.positions.end(), {{1e6f, 0.0f, 1e6f}, {1e6f + 10.0f, 0.0f, 1e6f}, {1e6f, 0.0f, 1e6f + 10.0f}});
  too_far.triangles.push_back({b, b + 2, b + 1});
  try {
    (void)make_walk_mesh(too_far);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("dungeon.obj: spans"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("separate walk meshes"), std::string::npos) << e.what();
  }
}

TEST(LevelWalkMesh, ErrorsNameTheFileAndTheTriangle) {
  const std::string path = ::testing::TempDir() + "broken_level.obj";
  {
    std::ofstream f(path);
    f << "v 0 0 0\nv 1 0 0\nv 0 0 1\nf 1 2 3\nf 1 2 3\nf 3 2 1\n";
  }
  const TriangleSoup soup = io::load_obj(path);
  EXPECT_EQ(soup.name, "broken_level.obj");
  TriangleSoup bad = soup;
  bad.triangles[2].y = 40;
  try {
    (void)make_walk_mesh(bad);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "broken_level.obj: triangle 2: vertex index 40 out of range (3 vertices)");
  }
  EXPECT_THROW((void)io::load_obj(::testing::TempDir() + "no_such_level.obj"), InvalidInput);
  EXPECT_THROW((void)make_walk_mesh(soup, {2.0f, 2.0f, {0, 1, 0}}), InvalidInput);   // max_slope
  EXPECT_THROW((void)make_walk_mesh(soup, {0.5f, -1.0f, {0, 1, 0}}), InvalidInput);  // height
  // A wall only: nothing walkable, said so.
  const TriangleSoup wall{"wall.obj", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
  try {
    (void)make_walk_mesh(wall);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("wall.obj: no walkable triangles"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace collide
