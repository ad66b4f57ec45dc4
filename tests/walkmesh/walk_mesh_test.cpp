// WalkMesh on generated meshes: conversions, movement, robustness of building, errors.
#include "walk_fixtures.hpp"

#include <collide/core/error.hpp>
#include <collide/walkmesh/walk_mesh.hpp>

#include <gtest/gtest.h>

namespace collide {
namespace {

using test::brute_distance;
using test::random_tangent;
using test::random_walk_point;
using test::uniform;

constexpr auto flat = [](float, float) { return 0.0f; };
constexpr auto hills = [](float x, float z) { return 1.5f * std::sin(0.4f * x) * std::cos(0.3f * z); };

double distance(Vec3 a, Vec3 b) { return glm::length(glm::dvec3(a) - glm::dvec3(b)); }

// ---- conversions ------------------------------------------------------------------------------

TEST(WalkMesh, WorldPointAndNormalsOfOneTriangle) {
  // Wound clockwise from above on purpose: the mesh turns it to face up.
  const TriangleSoup soup{"one", {{0, 0, 0}, {0, 0, 2}, {2, 0, 0}}, {{0, 2, 1}}};
  const WalkMesh mesh = build_walk_mesh(soup);
  EXPECT_EQ(mesh.stats().flipped_triangles, 1u);
  const WalkPoint p = mesh.walk_point(0, {0.25f, 0.25f, 0.5f});
  const glm::uvec3 t = mesh.triangle(0);
  const Vec3 expected = 0.25f * mesh.world_vertex(t.x) + 0.25f * mesh.world_vertex(t.y) + 0.5f * mesh.world_vertex(t.z);
  EXPECT_LT(distance(mesh.to_world_point(p), expected), 1e-6);
  EXPECT_LT(distance(mesh.to_world_triangle_normal(p), Vec3(0, 1, 0)), 1e-6);
  EXPECT_LT(distance(mesh.to_world_smooth_normal(p), Vec3(0, 1, 0)), 1e-6);
  EXPECT_EQ(mesh.stats().boundary_edges, 3u);
}

TEST(WalkMesh, SmoothNormalIsContinuousAndTriangleNormalIsNot) {
  std::mt19937 rng(11);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 12, 1.0f, 0.2f, hills));
  int jumps = 0, crossings = 0;
  for (int i = 0; i < 300; ++i) {
    const WalkPoint p = random_walk_point(mesh, rng);
    const TriangleWalk w = mesh.walk_in_triangle(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 5.0f));
    if (!w.hit_edge) continue;
    const auto c = mesh.cross_edge(w.end);
    if (!c) continue;
    ++crossings;
    EXPECT_LT(distance(mesh.to_world_smooth_normal(w.end), mesh.to_world_smooth_normal(c->end)), 1e-5);
    if (distance(mesh.to_world_triangle_normal(w.end), mesh.to_world_triangle_normal(c->end)) > 1e-3) ++jumps;
  }
  EXPECT_GT(crossings, 150);
  EXPECT_GT(jumps, crossings / 2);  // the faceted normal does jump: the test can tell them apart
  // At a vertex the smooth normal is the area-weighted mean of the normals of the triangles
  // around it, summed here by scanning every triangle (double precision).
  for (std::uint32_t t = 0; t < mesh.triangle_count(); t += 5) {
    const std::uint32_t v = mesh.triangle(t).x;
    glm::dvec3 sum(0.0);
    for (std::uint32_t u = 0; u < mesh.triangle_count(); ++u) {
      const glm::uvec3 tri = mesh.triangle(u);
      if (tri.x != v && tri.y != v && tri.z != v) continue;
      const glm::dvec3 a(mesh.world_vertex(tri.x)), b(mesh.world_vertex(tri.y)), c(mesh.world_vertex(tri.z));
      sum += glm::cross(b - a, c - a);  // length: twice the area
    }
    const Vec3 expected(glm::normalize(sum));
    EXPECT_LT(distance(mesh.to_world_smooth_normal(mesh.walk_point(t, {1.0f, 0.0f, 0.0f})), expected), 1e-5) << t;
  }
}

TEST(WalkMesh, NearestWalkPointEqualsBruteForce) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    const test::Rigid3 xf = test::random_rigid(rng, trial % 2 ? 1e4f : 10.0f, 0.6f);
    const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 16, 1.0f, 0.3f, hills, xf));
    const Aabb3 box = fatten(mesh.bounds(), 3.0f);
    int on_surface = 0;
    for (int i = 0; i < 300; ++i) {
      const Vec3 q(uniform(rng, box.min.x, box.max.x), uniform(rng, box.min.y, box.max.y),
                   uniform(rng, box.min.z, box.max.z));
      const WalkPoint p = mesh.nearest_walk_point(q);
      ASSERT_TRUE(mesh.is_valid(p));
      const double ours = distance(mesh.to_world_point(p), q);
      const double truth = brute_distance(mesh, q);
      // Float at 1e4 has a spacing of ~1e-3: tolerance relative to the coordinates' magnitude.
      const double tol = 1e-5 * (10.0 + glm::length(glm::dvec3(q)));
      EXPECT_NEAR(ours, truth, tol) << "trial " << trial << " query " << i;
      if (truth < 0.1) ++on_surface;
    }
    EXPECT_GT(on_surface, 0);  // some queries are close to the surface, most are off it
  }
}

TEST(WalkMesh, BoundedNearestWalkPointIsTheNearestWhenWithinReachAndNulloptOtherwise) {
  std::mt19937 rng(9);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 16, 1.0f, 0.3f, hills));
  const Aabb3 box = fatten(mesh.bounds(), 1.5f);
  int within = 0, beyond = 0;
  for (int i = 0; i < 500; ++i) {
    const Vec3 q(uniform(rng, box.min.x, box.max.x), uniform(rng, box.min.y, box.max.y),
                 uniform(rng, box.min.z, box.max.z));
    const float reach = uniform(rng, 0.0f, 2.5f);
    const double truth = brute_distance(mesh, q);
    if (std::abs(truth - reach) < 1e-4) continue;  // too close to call in float
    const std::optional<WalkPoint> p = mesh.nearest_walk_point(q, reach);
    ASSERT_EQ(p.has_value(), truth < reach) << i;
    if (!p) {
      ++beyond;
      continue;
    }
    ++within;
    const WalkPoint unbounded = mesh.nearest_walk_point(q);
    EXPECT_EQ(p->triangle, unbounded.triangle);
    EXPECT_EQ(p->weights, unbounded.weights);
  }
  EXPECT_GT(within, 100);
  EXPECT_GT(beyond, 100);
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(1.0f), -1.0f), InvalidInput);
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(1.0f), NAN), InvalidInput);
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(1.0f), INFINITY), InvalidInput);
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(NAN), 1.0f), InvalidInput);
  // Far enough that squared distances overflow float: an error, not an index out of range.
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(1e30f, 0.0f, 0.0f)), InvalidInput);
  EXPECT_FALSE(mesh.nearest_walk_point(Vec3(1e30f, 0.0f, 0.0f), 1.0f).has_value());
}

TEST(WalkMesh, NearestWalkPointOfMeshPointsIsThePointItself) {
  std::mt19937 rng(8);
  const WalkMesh mesh = build_walk_mesh(test::torus_soup(24, 12, 4.0f, 1.0f));
  for (int i = 0; i < 500; ++i) {
    const WalkPoint p = random_walk_point(mesh, rng);
    const Vec3 w = mesh.to_world_point(p);
    EXPECT_LT(distance(mesh.to_world_point(mesh.nearest_walk_point(w)), w), 1e-5);
  }
}

// ---- walk_in_triangle and cross_edge ----------------------------------------------------------

TEST(WalkMesh, WalkInTriangleStopsAtTheFirstEdgeInEdgeForm) {
  // Right triangle (0,0,0) (4,0,0) (0,0,-4), counter-clockwise from +y.
  const TriangleSoup soup{"tri", {{0, 0, 0}, {4, 0, 0}, {0, 0, -4}}, {{0, 1, 2}}};
  const WalkMesh mesh = build_walk_mesh(soup);
  const WalkPoint start = mesh.nearest_walk_point({1, 0, -1});
  // Step +x by 4: the hypotenuse x - z = 4 is reached at x = 3, after a quarter... (3 - 1) / 4.
  const TriangleWalk w = mesh.walk_in_triangle(start, {4, 0, 0});
  ASSERT_TRUE(w.hit_edge);
  EXPECT_NEAR(w.time, 0.5f, 1e-6f);
  EXPECT_EQ(w.end.weights.z, 0.0f);
  EXPECT_LT(distance(mesh.to_world_point(w.end), {3, 0, -1}), 1e-5);
  // The edge form names the hypotenuse: vertices (4,0,0) and (0,0,-4).
  const Vec3 ex = mesh.world_vertex(w.end.indices.x), ey = mesh.world_vertex(w.end.indices.y);
  EXPECT_NEAR(ex.x - ex.z, 4.0f, 1e-6f);
  EXPECT_NEAR(ey.x - ey.z, 4.0f, 1e-6f);
  // A short step stays inside, time 1; the vertical part of a step is projected away.
  const TriangleWalk inside = mesh.walk_in_triangle(start, {0.5f, 7.0f, 0.0f});
  EXPECT_FALSE(inside.hit_edge);
  EXPECT_EQ(inside.time, 1.0f);
  EXPECT_LT(distance(mesh.to_world_point(inside.end), {1.5f, 0, -1}), 1e-5);
  // Boundary: no crossing.
  EXPECT_FALSE(mesh.cross_edge(w.end).has_value());
}

TEST(WalkMesh, CrossEdgeKeepsTheWorldPointAndRotatesNormalOntoNormal) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 3; ++trial) {
    const test::Rigid3 xf = test::random_rigid(rng, trial == 2 ? 1e4f : 5.0f, 0.5f);
    const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 10, 1.0f, 0.25f, hills, xf));
    int crossed = 0, walls = 0;
    for (int i = 0; i < 400; ++i) {
      const WalkPoint p = random_walk_point(mesh, rng);
      const TriangleWalk w = mesh.walk_in_triangle(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 3.0f));
      if (!w.hit_edge) continue;
      const auto c = mesh.cross_edge(w.end);
      if (!c) {
        ++walls;
        continue;
      }
      ++crossed;
      ASSERT_TRUE(mesh.is_valid(c->end));
      EXPECT_NE(c->end.triangle, w.end.triangle);
      const double tol = 1e-6 * (10.0 + glm::length(glm::dvec3(xf.p)));
      EXPECT_LT(distance(mesh.to_world_point(w.end), mesh.to_world_point(c->end)), tol);
      EXPECT_LT(distance(c->rotation * mesh.to_world_triangle_normal(w.end), mesh.to_world_triangle_normal(c->end)), 1e-5);
      // ... about the shared edge, which it leaves in place.
      const Vec3 edge = glm::normalize(mesh.world_vertex(w.end.indices.y) - mesh.world_vertex(w.end.indices.x));
      EXPECT_LT(distance(c->rotation * edge, edge), 1e-5);
      // Crossing back returns to the same triangle and point.
      const auto back = mesh.cross_edge(c->end);
      ASSERT_TRUE(back.has_value());
      EXPECT_EQ(back->end.triangle, w.end.triangle);
      EXPECT_EQ(back->end.weights, w.end.weights);
    }
    EXPECT_GT(crossed, 200);
    EXPECT_GT(walls, 5);  // grid borders are walls: both outcomes happen
  }
}

TEST(WalkMesh, CrossEdgeRejectsPointsNotInEdgeForm) {
  std::mt19937 rng(3);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 4, 1.0f, 0.0f, flat));
  const WalkPoint p = mesh.walk_point(0, {0.2f, 0.3f, 0.5f});
  EXPECT_FALSE(mesh.cross_edge(p).has_value());
}

// ---- walk -------------------------------------------------------------------------------------

TEST(WalkMesh, WalkOnAFlatMeshIsTheStraightLine) {
  // Analytic truth: on a plane away from the border the walk ends at start + step, whatever the
  // triangulation, winding, rigid placement or distance from the origin.
  std::mt19937 rng(5);
  int long_walks = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const bool far = trial >= 3;
    const test::Rigid3 xf = test::random_rigid(rng, far ? 1e4f : 10.0f, 0.7f);
    const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 20, 1.0f, 0.3f, flat, xf));
    const Vec3 n = xf.q * Vec3(0, 1, 0);
    const Vec3 center = xf(Vec3(10.0f, 0.0f, 10.0f));
    for (int i = 0; i < 200; ++i) {
      const Vec3 s = xf.q * Vec3(uniform(rng, -4, 4), 0.0f, uniform(rng, -4, 4));
      const Vec3 a = xf.q * Vec3(uniform(rng, -4, 4), 0.0f, uniform(rng, -4, 4));
      const WalkPoint start = mesh.nearest_walk_point(center + a);
      // The off-plane part of a step is dropped (only near the origin: at 1e4 the float
      // vertices are off the plane by ~1e-3, so the triangles are not exactly coplanar).
      const WalkResult r = mesh.walk(start, s + (far ? 0.0f : uniform(rng, -2, 2)) * n);
      ASSERT_TRUE(mesh.is_valid(r.end));
      EXPECT_EQ(r.status, WalkStatus::completed);
      EXPECT_EQ(r.walls_hit, 0);
      const double tol = far ? 3e-3 : 2e-5;
      EXPECT_LT(distance(mesh.to_world_point(r.end), mesh.to_world_point(start) + s), tol);
      EXPECT_NEAR(r.distance, glm::length(s), 1e-4 * 10.0);
      if (r.edges_crossed >= 3) ++long_walks;
    }
  }
  EXPECT_GT(long_walks, 600);
}

TEST(WalkMesh, WalkSlidesAlongAWallAndStopsInACorner) {
  // Square [0, 10] x [0, 10] in xz; walls on all four sides.
  std::mt19937 rng(9);
  for (int trial = 0; trial < 4; ++trial) {
    const test::Rigid3 xf = trial == 0 ? test::Rigid3{} : test::random_rigid(rng, trial == 3 ? 1e4f : 10.0f, 0.5f);
    const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 10, 1.0f, 0.3f, flat, xf));
    const double tol = trial == 3 ? 3e-3 : 2e-5;
    const WalkPoint start = mesh.nearest_walk_point(xf(Vec3(5, 0, 5)));
    // Into the x = 10 wall at half the step, then the along-wall part (+1.5 in z) remains.
    const WalkResult slide = mesh.walk(start, xf.q * Vec3(10, 0, 3));
    EXPECT_EQ(slide.status, WalkStatus::completed);
    EXPECT_GE(slide.walls_hit, 1);
    EXPECT_LT(distance(mesh.to_world_point(slide.end), xf(Vec3(10, 0, 8))), tol);
    EXPECT_NEAR(slide.distance, 0.5f * glm::length(Vec3(10, 0, 3)) + 1.5f, 1e-4f);
    // Straight into the corner: stops there, blocked.
    const WalkResult corner = mesh.walk(start, xf.q * Vec3(10, 0, 10));
    EXPECT_EQ(corner.status, WalkStatus::blocked);
    EXPECT_LT(distance(mesh.to_world_point(corner.end), xf(Vec3(10, 0, 10))), tol);
    // Head-on into a wall: stops at it.
    const WalkResult wall = mesh.walk(start, xf.q * Vec3(0, 0, -8));
    EXPECT_EQ(wall.status, WalkStatus::blocked);
    EXPECT_LT(distance(mesh.to_world_point(wall.end), xf(Vec3(5, 0, 0))), tol);
    // Sliding past a corner turns along the next wall? No: a convex corner of the mesh ends the
    // slide (the step's along-wall part points out of the mesh).
    const WalkResult past = mesh.walk(mesh.nearest_walk_point(xf(Vec3(9, 0, 9))), xf.q * Vec3(4, 0, 2));
    EXPECT_LT(distance(mesh.to_world_point(past.end), xf(Vec3(10, 0, 10))), tol);
  }
}

TEST(WalkMesh, WalkStartingExactlyOnVerticesAndEdges) {
  // The cases that trip point-location code (recastnavigation #263/#377/#556): a start exactly
  // on a vertex shared by many triangles, exactly on an edge, and steps exactly along edges.
  std::mt19937 rng(13);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 12, 1.0f, 0.0f, flat));
  int moves = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); t += 7) {
    for (const Vec3 w : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.5f, 0.5f, 0), Vec3(0, 0.5f, 0.5f)}) {
      const WalkPoint start = mesh.walk_point(t, w);
      const Vec3 p0 = mesh.to_world_point(start);
      for (int k = 0; k < 16; ++k) {  // 16 directions, including the axes and the diagonals
        const float angle = 2.0f * 3.14159265f * static_cast<float>(k) / 16.0f;
        const Vec3 s(1.3f * std::cos(angle), 0.0f, 1.3f * std::sin(angle));
        const WalkResult r = mesh.walk(start, s);
        ASSERT_TRUE(mesh.is_valid(r.end));
        const Vec3 target = p0 + s;
        const bool inside = target.x > 0 && target.x < 12 && target.z > 0 && target.z < 12;
        if (inside) {
          ++moves;
          EXPECT_EQ(r.status, WalkStatus::completed);
          EXPECT_LT(distance(mesh.to_world_point(r.end), target), 1e-5) << "triangle " << t << " dir " << k;
        } else {
          const Vec3 e = mesh.to_world_point(r.end);  // stays on the square
          EXPECT_TRUE(e.x >= -1e-5f && e.x <= 12 + 1e-5f && e.z >= -1e-5f && e.z <= 12 + 1e-5f);
        }
      }
    }
  }
  EXPECT_GT(moves, 1000);
}

TEST(WalkMesh, WalkThereAndBackReturnsToTheStart) {
  std::mt19937 rng(17);
  for (int trial = 0; trial < 3; ++trial) {
    const test::Rigid3 xf = test::random_rigid(rng, trial == 2 ? 1e4f : 10.0f, 0.5f);
    const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 16, 1.0f, 0.3f, hills, xf));
    int returned = 0, walled = 0;
    for (int i = 0; i < 300; ++i) {
      const WalkPoint start = random_walk_point(mesh, rng);
      const WalkResult go = mesh.walk(start, random_tangent(rng, mesh.to_world_triangle_normal(start), 4.0f));
      ASSERT_TRUE(mesh.is_valid(go.end));
      if (go.walls_hit > 0) {
        ++walled;
        continue;
      }
      const WalkResult back = mesh.walk(go.end, -go.end_step);
      EXPECT_EQ(back.walls_hit, 0);
      EXPECT_NEAR(back.distance, go.distance, 1e-4f * go.distance + 1e-5f);
      const double tol = trial == 2 ? 5e-3 : 1e-4;
      EXPECT_LT(distance(mesh.to_world_point(back.end), mesh.to_world_point(start)), tol) << i;
      ++returned;
    }
    EXPECT_GT(returned, 150);
    EXPECT_GT(walled, 10);
  }
}

TEST(WalkMesh, WalksOnAClosedSurfaceNeverHitWallsAndKeepTheirLength) {
  std::mt19937 rng(23);
  const test::Rigid3 xf = test::random_rigid(rng, 100.0f, 3.0f);
  const WalkMesh mesh = build_walk_mesh(test::torus_soup(40, 16, 6.0f, 2.0f, xf));
  EXPECT_EQ(mesh.stats().boundary_edges, 0u);
  EXPECT_EQ(mesh.stats().islands, 1u);
  for (int i = 0; i < 300; ++i) {
    const WalkPoint start = random_walk_point(mesh, rng);
    const float len = uniform(rng, 0.1f, 30.0f);  // up to more than a full turn around the tube
    const WalkResult r = mesh.walk(start, random_tangent(rng, mesh.to_world_triangle_normal(start), len));
    ASSERT_TRUE(mesh.is_valid(r.end));
    EXPECT_EQ(r.status, WalkStatus::completed);
    EXPECT_EQ(r.walls_hit, 0);
    EXPECT_NEAR(r.distance, len, 1e-4f * len);
    EXPECT_NEAR(glm::length(r.end_step), len, 1e-4f * len);
    EXPECT_LT(brute_distance(mesh, mesh.to_world_point(r.end)), 1e-4);
  }
}

TEST(WalkMesh, RandomWalksStayOnTheMesh) {
  std::mt19937 rng(29);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 20, 0.7f, 0.35f, hills));
  int walls = 0;
  for (int agent = 0; agent < 20; ++agent) {
    WalkPoint p = random_walk_point(mesh, rng);
    for (int step = 0; step < 200; ++step) {
      const WalkResult r = mesh.walk(p, random_tangent(rng, mesh.to_world_triangle_normal(p), uniform(rng, 0.0f, 2.0f)));
      ASSERT_TRUE(mesh.is_valid(r.end));
      ASSERT_LT(brute_distance(mesh, mesh.to_world_point(r.end)), 1e-5);
      walls += r.walls_hit > 0;
      p = r.end;
    }
  }
  EXPECT_GT(walls, 20);
}

TEST(WalkMesh, Regression377WalkEndingOnAnEdgeSharedWithAnotherIslandStaysOnItsIsland) {
  // recastnavigation #377: a move ending exactly on an edge shared with an unconnected polygon,
  // re-located by position, jumped to the other component. A walk point keeps its triangle, so
  // it cannot. Floor: two flat triangles over edge (0,1); a fin stands on the same edge.
  const TriangleSoup s{"fin", {{0, 0, 0}, {0, 0, 2}, {2, 0, 1}, {-2, 0, 1}, {0, 2, 1}}, {{0, 1, 2}, {0, 4, 1}, {1, 0, 3}}};
  const WalkMesh mesh = build_walk_mesh(s);
  ASSERT_EQ(mesh.stats().islands, 2u);
  const WalkPoint start = mesh.nearest_walk_point({1.0f, 0.0f, 1.0f});
  const WalkResult to_edge = mesh.walk(start, {-1.0f, 0.0f, 0.0f});  // ends exactly on the shared edge
  EXPECT_LT(distance(mesh.to_world_point(to_edge.end), {0.0f, 0.0f, 1.0f}), 1e-6);
  EXPECT_EQ(mesh.island(to_edge.end.triangle), mesh.island(start.triangle));
  const WalkResult on = mesh.walk(to_edge.end, {-1.0f, 0.0f, 0.0f});  // and walking on continues on the floor
  EXPECT_EQ(mesh.island(on.end.triangle), mesh.island(start.triangle));
  EXPECT_LT(distance(mesh.to_world_point(on.end), {-1.0f, 0.0f, 1.0f}), 1e-6);
  EXPECT_EQ(on.walls_hit, 0);
}

TEST(WalkMesh, Regression263And556PointsExactlyOnEdgesAreValidEverywhere) {
  // recastnavigation #263 and #556: a point exactly on a polygon edge (from a clamp or a random
  // point) failed point-in-polygon, so later queries rejected it. Here every query accepts
  // walk points with zero weights.
  std::mt19937 rng(19);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 8, 1.0f, 0.3f, hills));
  int on_edge = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const float u = test::uniform01(rng);
    for (const Vec3 w : {Vec3(u, 1.0f - u, 0.0f), Vec3(0.0f, u, 1.0f - u), Vec3(0.0f, 0.0f, 1.0f)}) {
      const WalkPoint p = mesh.walk_point(t, w);
      ASSERT_TRUE(mesh.is_valid(p, 0.0f + 1e-6f));
      const Vec3 world = mesh.to_world_point(p);
      EXPECT_LT(distance(mesh.to_world_point(mesh.nearest_walk_point(world)), world), 1e-5);
      const WalkResult still = mesh.walk(p, Vec3(0.0f));
      EXPECT_EQ(still.end.triangle, p.triangle);
      EXPECT_LT(distance(mesh.to_world_point(still.end), world), 1e-6);
      const WalkResult moved = mesh.walk(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 0.5f));
      ASSERT_TRUE(mesh.is_valid(moved.end));
      ++on_edge;
    }
  }
  EXPECT_GT(on_edge, 300);
}

TEST(WalkMesh, Regression377AnEdgeWithoutALinkIsAWallEvenWhereAnotherIslandTouchesIt) {
  // recastnavigation #377, the other direction: two polygons touch along an edge with no link
  // between them; moveAlongSurface ended on that edge and a position lookup put the agent in the
  // other, unconnected polygon. Here the fin of the fixture above meets the floor along edge
  // (0,1) without a link: walking down the fin must stop on the fin, at the edge, and go on
  // sliding along it, never onto the floor.
  const TriangleSoup s{"fin", {{0, 0, 0}, {0, 0, 2}, {2, 0, 1}, {-2, 0, 1}, {0, 2, 1}}, {{0, 1, 2}, {0, 4, 1}, {1, 0, 3}}};
  const WalkMesh mesh = build_walk_mesh(s);
  const WalkPoint on_fin = mesh.nearest_walk_point({0.0f, 1.0f, 1.0f});
  ASSERT_GT(mesh.to_world_triangle_normal(on_fin).x * mesh.to_world_triangle_normal(on_fin).x, 0.99f);  // the fin
  const std::uint32_t fin = mesh.island(on_fin.triangle);
  const WalkResult down = mesh.walk(on_fin, {0.0f, -3.0f, 0.0f});
  EXPECT_EQ(down.status, WalkStatus::blocked);
  EXPECT_EQ(down.edges_crossed, 0);
  EXPECT_EQ(mesh.island(down.end.triangle), fin);
  EXPECT_LT(distance(mesh.to_world_point(down.end), {0.0f, 0.0f, 1.0f}), 1e-6);
  // From the edge, a step down and along: slides along the fin's foot, stays on the fin.
  const WalkResult slide = mesh.walk(down.end, {0.0f, -1.0f, 0.5f});
  EXPECT_EQ(mesh.island(slide.end.triangle), fin);
  EXPECT_LT(distance(mesh.to_world_point(slide.end), {0.0f, 0.0f, 1.5f}), 1e-6);
  // And the floor, walked over the same edge, never climbs the fin.
  const WalkResult across = mesh.walk(mesh.nearest_walk_point({0.5f, 0.0f, 1.0f}), {-1.0f, 0.0f, 0.0f});
  EXPECT_NE(mesh.island(across.end.triangle), fin);
  EXPECT_LT(distance(mesh.to_world_point(across.end), {-0.5f, 0.0f, 1.0f}), 1e-6);
}

TEST(WalkMesh, Regression377TwoIslandsMeetingFlatAlongOneEdgeStaySeparate) {
  // Four triangles on one edge (x = 0): a floor on each side and a gentle ramp on each side,
  // the ramps continuing each other. The builder links floor to floor and ramp to ramp, so two
  // islands touch along the edge with no link between them; a point exactly on that edge is as
  // close to both (Detour's findNearestPoly tie). Walks keep their island.
  const float h = 0.2f;
  const TriangleSoup s{"two floors",
                       {{0, 0, 0}, {0, 0, 2}, {2, 0, 1}, {-2, 0, 1}, {2, h, 1}, {-2, -h, 1}},
                       {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}}};
  const WalkMesh mesh = build_walk_mesh(s);
  ASSERT_EQ(mesh.stats().non_manifold_edges, 1u);
  ASSERT_EQ(mesh.stats().islands, 2u);
  std::mt19937 rng(71);
  int crossed = 0;
  for (int i = 0; i < 200; ++i) {
    const WalkPoint p = random_walk_point(mesh, rng);
    const Vec3 n = mesh.to_world_triangle_normal(p);
    const WalkResult r = mesh.walk(p, random_tangent(rng, n, uniform(rng, 0.1f, 4.0f)));
    ASSERT_TRUE(mesh.is_valid(r.end));
    EXPECT_EQ(mesh.island(r.end.triangle), mesh.island(p.triangle)) << i;
    // The ramp rises with x on both sides, the floor is flat: the height tells the island.
    const Vec3 e = mesh.to_world_point(r.end);
    const bool on_ramp = std::fabs(n.x) > 1e-3f;
    EXPECT_NEAR(e.y, on_ramp ? h * e.x / 2.0f : 0.0f, 1e-5f) << i;
    crossed += r.edges_crossed > 0;
  }
  EXPECT_GT(crossed, 50);
}

TEST(WalkMesh, Regression263AWallClampedPositionIsAValidStartFarFromTheOrigin) {
  // recastnavigation #263: a character corrected to where a move hit the navmesh border (a point
  // exactly on a border edge, coordinates around (-1416, 2892)) was rejected as the start of the
  // next query. Here: walk into the walls again and again, each time from where the last walk
  // stopped, then walk away; every start is accepted and the moves are exact.
  std::mt19937 rng(73);
  const test::Rigid3 xf{glm::angleAxis(0.3f, Vec3(0, 1, 0)), {-1416.0f, 12.0f, 2892.0f}};
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 10, 1.0f, 0.3f, flat, xf));
  const float tol = 4e-3f;  // float spacing at 3000 is 2.4e-4; a few roundings per crossing
  WalkPoint p = mesh.nearest_walk_point(xf(Vec3(5, 0, 5)));
  int on_wall = 0;
  for (int i = 0; i < 200; ++i) {
    const float angle = uniform(rng, -3.14159f, 3.14159f);
    const WalkResult hit = mesh.walk(p, xf.q * Vec3(30.0f * std::cos(angle), 0.0f, 30.0f * std::sin(angle)));
    ASSERT_TRUE(mesh.is_valid(hit.end));
    ASSERT_GE(hit.walls_hit, 1);
    const Vec3 local = glm::inverse(xf.q) * (mesh.to_world_point(hit.end) - xf.p);
    const float border = std::min({local.x, local.z, 10.0f - local.x, 10.0f - local.z});
    EXPECT_NEAR(border, 0.0f, tol) << i;  // on the border
    on_wall += std::min({hit.end.weights.x, hit.end.weights.y, hit.end.weights.z}) == 0.0f;
    // Straight back towards the centre by one unit: a full, unobstructed move from the wall.
    const Vec3 centre = xf(Vec3(5, 0, 5));
    const Vec3 inward = glm::normalize(centre - mesh.to_world_point(hit.end));
    const WalkResult away = mesh.walk(hit.end, inward);
    EXPECT_EQ(away.status, WalkStatus::completed) << i;
    EXPECT_EQ(away.walls_hit, 0) << i;
    EXPECT_NEAR(away.distance, 1.0f, 1e-4f) << i;
    EXPECT_LT(distance(mesh.to_world_point(away.end), mesh.to_world_point(hit.end) + inward), tol) << i;
    p = hit.end;  // the next walk starts on the wall
  }
  // Most clamped points are exactly on an edge (a zero weight). The others slid past a border
  // vertex: at 3000 the rounded border is straight only to ~1e-4, and a slide keeps the first
  // edge's direction, so it may leave the wall by that much (checked above).
  EXPECT_GT(on_wall, 100);  // the clamped points really are on an edge (a zero weight)
}

TEST(WalkMesh, Regression556RandomPointsWithZeroWeightsWorkFarFromTheOrigin) {
  // recastnavigation #556: findRandomPoint produced a point exactly on a polygon edge and its
  // own height query (getPolyHeight) then failed. Random walk points with weights exactly 0 or 1,
  // near 5000 like undulating.obj: the world point is on the triangle, the nearest walk point
  // finds it again, and walking from it works.
  std::mt19937 rng(75);
  const test::Rigid3 xf{glm::angleAxis(0.2f, Vec3(0, 1, 0)), {5000.0f, 0.0f, 5000.0f}};
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 12, 2.0f, 0.3f, hills, xf));
  const double tol = 2e-3;
  int checked = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const float u = test::uniform01(rng);
    for (const Vec3 w : {Vec3(u, 1.0f - u, 0.0f), Vec3(1.0f - u, 0.0f, u), Vec3(0.0f, 1.0f, 0.0f)}) {
      const WalkPoint p = mesh.walk_point(t, w);
      const Vec3 world = mesh.to_world_point(p);
      const glm::uvec3 tri = mesh.triangle(t);
      const glm::dvec3 on = test::brute_closest_on_triangle(glm::dvec3(world), glm::dvec3(mesh.world_vertex(tri.x)),
                                                            glm::dvec3(mesh.world_vertex(tri.y)),
                                                            glm::dvec3(mesh.world_vertex(tri.z)));
      EXPECT_LT(glm::length(on - glm::dvec3(world)), tol);  // "its height" is the triangle's
      EXPECT_LT(distance(mesh.to_world_point(mesh.nearest_walk_point(world)), world), tol);
      const WalkResult r = mesh.walk(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 1.0f));
      ASSERT_TRUE(mesh.is_valid(r.end));
      EXPECT_NE(r.status, WalkStatus::iteration_limit);
      ++checked;
    }
  }
  EXPECT_GT(checked, 800);
}

TEST(WalkMesh, WalksOverNeedleTrianglesStayOnTheMeshAndReturn) {
  // Needles: triangles whose third corner is within 5e-6 of the opposite edge (area 5e-6 of the
  // longest edge squared, just above kWalkDegenerateTolerance, no two corners close enough to
  // weld). Their weight gradients are huge: the case where float barycentric stepping drifts.
  // A strip [0, n] x [0, 1] in xz: along its bottom edge a needle under every cell, the rest
  // filled with ordinary triangles.
  std::mt19937 rng(77);
  const int n = 12;
  const float eps = 5e-6f;
  TriangleSoup s;
  s.name = "needles";
  for (int i = 0; i <= n; ++i) {
    const float x = static_cast<float>(i);
    s.positions.push_back({x, 0.0f, 0.0f});         // bottom A_i = 3i
    s.positions.push_back({x + 0.5f, 0.0f, eps});   // needle tip M_i = 3i + 1 (unused at i = n)
    s.positions.push_back({x, 0.0f, 1.0f});         // top T_i = 3i + 2
  }
  for (unsigned i = 0; i < static_cast<unsigned>(n); ++i) {
    const unsigned a = 3 * i, m = 3 * i + 1, t = 3 * i + 2, a1 = 3 * i + 3, t1 = 3 * i + 5;
    s.triangles.push_back({a, a1, m});   // the needle
    s.triangles.push_back({a, m, t});
    s.triangles.push_back({m, t1, t});
    s.triangles.push_back({m, a1, t1});
  }
  const WalkMesh mesh = build_walk_mesh(s);
  ASSERT_EQ(mesh.triangle_count(), s.triangles.size());  // none dropped as degenerate
  ASSERT_EQ(mesh.stats().islands, 1u);
  ASSERT_EQ(mesh.stats().boundary_edges, 2u * n + 2u);
  int returned = 0, through_needles = 0;
  for (int i = 0; i < 2000; ++i) {
    // Half the starts inside a needle, stepping along it (through the next needles, edge to edge
    // and vertex to vertex); the others anywhere near the bottom, stepping mostly along it.
    WalkPoint start;
    Vec3 step;
    if (i % 2 == 0) {
      const auto needle = static_cast<std::uint32_t>(rng() % n);
      // Inside the needle's middle half, off its bottom (a wall) by at least eps / 10.
      start = mesh.nearest_walk_point({static_cast<float>(needle) + uniform(rng, 0.25f, 0.75f), 0.0f,
                                       eps * uniform(rng, 0.2f, 0.5f)});
      step = Vec3((rng() % 2 ? 1.0f : -1.0f) * uniform(rng, 0.5f, 6.0f), 0.0f, uniform(rng, -2e-7f, 2e-7f));
    } else {
      start = mesh.nearest_walk_point({uniform(rng, 0.0f, n), 0.0f, uniform(rng, 1e-4f, 0.01f)});
      step = random_tangent(rng, Vec3(0, 1, 0), uniform(rng, 0.1f, 6.0f)) * Vec3(1.0f, 1.0f, 0.01f);
    }
    const WalkResult go = mesh.walk(start, step);
    ASSERT_TRUE(mesh.is_valid(go.end));
    ASSERT_NE(go.status, WalkStatus::iteration_limit);
    const Vec3 e = mesh.to_world_point(go.end);
    ASSERT_TRUE(e.x >= -1e-5f && e.x <= n + 1e-5f && e.z >= -1e-6f && e.z <= 1.0f + 1e-6f) << i;
    EXPECT_EQ(e.y, 0.0f);
    if (go.walls_hit > 0) continue;
    // Unobstructed: the straight line, and back again.
    EXPECT_LT(distance(e, mesh.to_world_point(start) + step), 1e-5) << i;
    const WalkResult back = mesh.walk(go.end, -go.end_step);
    EXPECT_EQ(back.walls_hit, 0) << i;
    EXPECT_LT(distance(mesh.to_world_point(back.end), mesh.to_world_point(start)), 1e-5) << i;
    ++returned;
    through_needles += i % 2 == 0 && go.edges_crossed >= 3;
  }
  EXPECT_GT(returned, 600);
  EXPECT_GT(through_needles, 300);
}

// ---- building from messy soups ----------------------------------------------------------------

TEST(WalkMeshBuild, WeldingAnUnsharedSoupRecoversTheMesh) {
  std::mt19937 rng(31);
  const TriangleSoup indexed = test::grid_soup(rng, 8, 1.0f, 0.3f, hills, test::random_rigid(rng, 5000.0f, 0.3f));
  const WalkMesh a = build_walk_mesh(indexed);
  const WalkMesh b = build_walk_mesh(test::unshared(indexed));
  EXPECT_EQ(b.stats().vertices, a.stats().vertices);
  EXPECT_EQ(b.stats().welded_vertices, 3 * indexed.triangles.size() - a.stats().vertices);
  EXPECT_EQ(b.stats().boundary_edges, 4u * 8u * 1u);  // the border: 8 edges per side
  EXPECT_EQ(b.stats().islands, 1u);
}

TEST(WalkMeshBuild, InconsistentWindingIsMadeConsistentAndUp) {
  std::mt19937 rng(37);
  const WalkMesh mesh = build_walk_mesh(test::grid_soup(rng, 10, 1.0f, 0.3f, hills));
  EXPECT_GT(mesh.stats().flipped_triangles, 50u);  // the grid winds half its triangles wrongly
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_GT(mesh.to_world_triangle_normal(mesh.walk_point(t, Vec3(1.0f))).y, 0.0f);
    for (int e = 0; e < 3; ++e) {  // neighbours use the shared edge in opposite directions
      const std::uint32_t n = mesh.neighbor(t, e);
      if (n == kNoNeighbor) continue;
      const glm::uvec3 a = mesh.triangle(t), b = mesh.triangle(n);
      const std::uint32_t u = a[e], v = a[(e + 1) % 3];
      bool opposite = false;
      for (int k = 0; k < 3; ++k) opposite |= b[k] == v && b[(k + 1) % 3] == u;
      EXPECT_TRUE(opposite);
    }
  }
}

TEST(WalkMeshBuild, DegenerateAndDuplicateTrianglesAreDropped) {
  std::mt19937 rng(41);
  TriangleSoup s = test::grid_soup(rng, 6, 1.0f, 0.2f, flat);
  const std::size_t clean = s.triangles.size();
  s.triangles.push_back({0, 0, 1});                                  // repeated corner
  s.positions.push_back({0.5f, 0.0f, 0.0f});                         // collinear with 0 and (1, 0, 0)
  s.triangles.push_back({0, 7, static_cast<unsigned>(s.positions.size() - 1)});
  s.triangles.push_back({s.triangles[3].z, s.triangles[3].y, s.triangles[3].x});  // same, other winding
  const WalkMesh mesh = build_walk_mesh(s);
  EXPECT_EQ(mesh.stats().degenerate_triangles, 2u);
  EXPECT_EQ(mesh.stats().duplicate_triangles, 1u);
  EXPECT_EQ(mesh.triangle_count(), clean);
}

TEST(WalkMeshBuild, TJunctionsAreSplitSoBothSidesLink) {
  // Two unit squares side by side in xz; the left one is split at the midpoint (1, 0.5) of the
  // shared edge x = 1, the right one is not: a T-junction, which would be a wall.
  const TriangleSoup s{"t-junction",
                       {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {2, 0, 0}, {2, 0, 1}, {1, 0, 0.5f}},
                       {{0, 6, 1}, {0, 3, 6}, {3, 2, 6}, {1, 5, 4}, {1, 2, 5}}};
  const WalkMesh mesh = build_walk_mesh(s);
  EXPECT_EQ(mesh.stats().t_junction_splits, 1u);
  EXPECT_EQ(mesh.stats().boundary_edges, 6u);  // the outline: one edge per side, two on top and bottom
  for (const float z : {0.25f, 0.5f, 0.75f}) {
    const WalkResult r = mesh.walk(mesh.nearest_walk_point({0.5f, 0.0f, z}), {1.0f, 0.0f, 0.0f});
    EXPECT_EQ(r.walls_hit, 0) << z;
    EXPECT_LT(distance(mesh.to_world_point(r.end), {1.5f, 0.0f, z}), 1e-6);
  }
}

TEST(WalkMeshBuild, AnEdgeHoldingManyVerticesIsSplitAtEveryOne) {
  // A strip of 40 unit squares along x meets, at z = 0, one long triangle whose edge runs the
  // strip's whole length: 39 strip vertices lie inside that edge (T-junctions, all cut; passes
  // once cut one per edge per pass, up to kMaxTJunctionPasses). The strip and the long triangle
  // then form one island, and a walk from the strip crosses into the long triangle anywhere.
  constexpr int kSquares = 40;
  TriangleSoup s{"strip", {}, {}};
  for (int i = 0; i <= kSquares; ++i) {
    s.positions.push_back({static_cast<float>(i), 0.0f, 0.0f});
    s.positions.push_back({static_cast<float>(i), 0.0f, 1.0f});
  }
  for (std::uint32_t i = 0; i < kSquares; ++i) {
    s.triangles.push_back({2 * i, 2 * i + 1, 2 * i + 3});
    s.triangles.push_back({2 * i, 2 * i + 3, 2 * i + 2});
  }
  const auto far = static_cast<std::uint32_t>(s.positions.size());
  s.positions.push_back({0.5f * kSquares, 0.0f, -5.0f});
  s.triangles.push_back({0, 2 * kSquares, far});  // edge (0, 2 kSquares) along z = 0
  const WalkMesh mesh = build_walk_mesh(s);
  EXPECT_EQ(mesh.stats().t_junction_splits, static_cast<std::size_t>(kSquares - 1));
  EXPECT_EQ(mesh.stats().islands, 1u);
  for (const float x : {10.0f, 17.3f, 30.5f}) {  // where the long triangle is deeper than the step
    const WalkPoint start = mesh.nearest_walk_point({x, 0.0f, 0.5f});
    const WalkResult r = mesh.walk(start, {0.0f, 0.0f, -1.5f});
    EXPECT_EQ(r.status, WalkStatus::completed) << x;
    EXPECT_LT(distance(mesh.to_world_point(r.end), {x, 0.0f, -1.0f}), 1e-4) << x;
  }
}

TEST(WalkMeshBuild, AWallStandingOnAnEdgeIsNotATJunction) {
  // A floor square whose edge x = 2 carries a wall split at its midpoint: the wall's vertex lies
  // on the floor's unshared edge, but the wall does not continue the floor (it stands at 90
  // degrees), so the floor is not split there and does not link up the wall. (The side test was
  // a dot product of perpendicular vectors, decided by rounding.)
  std::mt19937 rng(79);
  for (int trial = 0; trial < 100; ++trial) {  // rigid placements: rounding noise of either sign
    const test::Rigid3 xf = test::random_rigid(rng, 2000.0f, 0.5f);
    TriangleSoup s{"wall on edge",
                   {{0, 0, 0}, {2, 0, 0}, {2, 0, 2}, {0, 0, 2}, {2, 0, 1}, {2, 2, 0}, {2, 2, 2}, {2, 2, 1}},
                   {{0, 1, 2}, {0, 2, 3}, {1, 4, 7}, {1, 7, 5}, {4, 2, 6}, {4, 6, 7}}};
    for (Vec3& p : s.positions) p = xf(p);
    const WalkMesh mesh = build_walk_mesh(s, {xf.q * Vec3(0, 1, 0)});
    EXPECT_EQ(mesh.stats().t_junction_splits, 0u) << trial;
    EXPECT_EQ(mesh.stats().islands, 2u) << trial;
    const WalkPoint start = mesh.nearest_walk_point(xf(Vec3(1.0f, 0.0f, 1.0f)));
    const WalkResult r = mesh.walk(start, xf.q * Vec3(3.0f, 0.0f, 0.0f));
    EXPECT_EQ(r.status, WalkStatus::blocked) << trial;
    EXPECT_EQ(mesh.island(r.end.triangle), mesh.island(start.triangle)) << trial;
    EXPECT_LT(distance(mesh.to_world_point(r.end), xf(Vec3(2.0f, 0.0f, 1.0f))), 2e-3) << trial;
  }
}

TEST(WalkMeshBuild, NonManifoldEdgeLinksTheFlatContinuation) {
  // Two floor triangles share edge (0,1); a third triangle (a fin) stands up on the same edge.
  const TriangleSoup s{"fin",
                       {{0, 0, 0}, {0, 0, 2}, {2, 0, 1}, {-2, 0, 1}, {0, 2, 1}},
                       {{0, 1, 2}, {0, 4, 1}, {1, 0, 3}}};
  const WalkMesh mesh = build_walk_mesh(s);
  EXPECT_EQ(mesh.stats().non_manifold_edges, 1u);
  EXPECT_EQ(mesh.stats().islands, 2u);  // the fin is its own island
  // Walking from the +x floor towards -x crosses into the -x floor, not up the fin.
  const WalkPoint start = mesh.nearest_walk_point({1.0f, 0.0f, 1.0f});
  const WalkResult r = mesh.walk(start, {-2.0f, 0.0f, 0.0f});
  EXPECT_EQ(r.edges_crossed, 1);
  EXPECT_LT(distance(mesh.to_world_point(r.end), {-1.0f, 0.0f, 1.0f}), 1e-5);
}

TEST(WalkMeshBuild, MoebiusStripGetsOneCutLinkAndStaysWalkable) {
  TriangleSoup s;
  s.name = "moebius";
  const int n = 24;
  for (int i = 0; i < n; ++i) {
    const float u = 2.0f * 3.14159265f * static_cast<float>(i) / n;
    for (float v : {-0.5f, 0.5f}) {
      s.positions.push_back({(2.0f + v * std::cos(u / 2)) * std::cos(u), v * std::sin(u / 2),
                             (2.0f + v * std::cos(u / 2)) * std::sin(u)});
    }
  }
  for (int i = 0; i < n; ++i) {
    const unsigned a = 2 * i, b = 2 * i + 1;
    const unsigned c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;  // the twist
    s.triangles.push_back({a, b, d});
    s.triangles.push_back({a, d, c});
  }
  const WalkMesh mesh = build_walk_mesh(s);
  EXPECT_EQ(mesh.stats().orientation_conflicts, 1u);
  EXPECT_EQ(mesh.stats().islands, 1u);
  std::mt19937 rng(43);
  for (int i = 0; i < 200; ++i) {
    const WalkPoint p = random_walk_point(mesh, rng);
    const WalkResult r = mesh.walk(p, random_tangent(rng, mesh.to_world_triangle_normal(p), 3.0f));
    ASSERT_TRUE(mesh.is_valid(r.end));
    EXPECT_LT(brute_distance(mesh, mesh.to_world_point(r.end)), 1e-5);
  }
}

TEST(WalkMeshBuild, IslandsAreCountedAndWalksStayOnTheirIsland) {
  std::mt19937 rng(47);
  TriangleSoup a = test::grid_soup(rng, 5, 1.0f, 0.2f, flat);
  const TriangleSoup b = test::grid_soup(rng, 5, 1.0f, 0.2f, flat, test::Rigid3{{1, 0, 0, 0}, {20, 3, 0}});
  const auto offset = static_cast<unsigned>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (glm::uvec3 t : b.triangles) a.triangles.push_back(t + offset);
  const WalkMesh mesh = build_walk_mesh(a);
  EXPECT_EQ(mesh.stats().islands, 2u);
  for (int i = 0; i < 200; ++i) {
    const WalkPoint p = random_walk_point(mesh, rng);
    const WalkResult r = mesh.walk(p, random_tangent(rng, Vec3(0, 1, 0), 30.0f));
    EXPECT_EQ(mesh.island(r.end.triangle), mesh.island(p.triangle));
    EXPECT_GE(r.walls_hit, 1);  // 30 units do not fit on a 5-unit island
    EXPECT_LT(r.distance, 7.1f + 5.0f);  // a diagonal of the island, then at most one side of slide
  }
}

TEST(WalkMeshBuild, BadInputNamesTheProblemAndWhere) {
  auto message = [](const TriangleSoup& s) {
    try {
      (void)build_walk_mesh(s);
    } catch (const InvalidInput& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({"level.obj", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}, {0, 1, 9}}}),
            "level.obj: triangle 1: vertex index 9 out of range (3 vertices)");
  EXPECT_EQ(message({"level.obj", {{0, 0, 0}, {1, 0, 0}, {0, NAN, 1}}, {{0, 1, 2}}}),
            "level.obj: triangle 0: vertex 2 is not finite");
  EXPECT_EQ(message({"level.obj", {}, {}}), "level.obj: no triangles");
  EXPECT_EQ(message({"flat.obj", {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}}),
            "flat.obj: no usable triangles (all 1 are degenerate or duplicates)");
  EXPECT_THROW((void)build_walk_mesh({"x", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}}}, {Vec3(0.0f)}),
               InvalidInput);
  const WalkMesh mesh = build_walk_mesh({"x", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}}});
  EXPECT_THROW((void)mesh.walk_point(1, Vec3(1.0f)), InvalidInput);
  EXPECT_THROW((void)mesh.walk_point(0, Vec3(-1.0f, 1.0f, 1.0f)), InvalidInput);
  EXPECT_THROW((void)mesh.nearest_walk_point(Vec3(NAN)), InvalidInput);
  // A step that is not finite is refused by the noexcept movement queries: nothing moves.
  const WalkPoint p = mesh.walk_point(0, {0.2f, 0.3f, 0.5f});
  for (const Vec3 bad : {Vec3(NAN, 0.0f, 0.0f), Vec3(0.0f, 0.0f, INFINITY), Vec3(-INFINITY, NAN, 1.0f)}) {
    const WalkResult r = mesh.walk(p, bad);
    EXPECT_EQ(r.status, WalkStatus::invalid_step);
    EXPECT_EQ(r.end.triangle, p.triangle);
    EXPECT_EQ(r.end.indices, p.indices);
    EXPECT_EQ(r.end.weights, p.weights);
    EXPECT_EQ(r.distance, 0.0f);
    EXPECT_EQ(r.end_step, Vec3(0.0f));
    const TriangleWalk w = mesh.walk_in_triangle(p, bad);
    EXPECT_FALSE(w.hit_edge);
    EXPECT_EQ(w.time, 0.0f);
    EXPECT_EQ(w.end.weights, p.weights);
  }
}

}  // namespace
}  // namespace collide
