// TriangleMesh: validation named by field, degenerate triangles dropped and counted, the local
// origin, bounds, and active edges on analytic meshes (flat grids, a cube, steps and bends of
// known angle, a fin), whose right answers follow from the geometry.
#include "support/test_util.hpp"

#include <collide/core/error.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace collide {
namespace {

using test::uniform;

struct Indexed {
  std::vector<Vec3> vertices;
  std::vector<glm::uvec3> triangles;
  [[nodiscard]] TriangleMesh make(const TriangleMeshOptions& options = {}) const {
    return make_triangle_mesh(vertices, triangles, options);
  }
};

std::string error_of(const Indexed& m, const TriangleMeshOptions& options = {}) {
  try {
    (void)m.make(options);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "no error";
}

/// Edge k of triangle t as its two mesh-space end points.
std::pair<Vec3, Vec3> edge(const TriangleMesh& m, std::uint32_t t, int k) {
  return {m.origin + m.corner(t, k), m.origin + m.corner(t, (k + 1) % 3)};
}

/// A flat n x n grid of unit cells in y = height, corner (x0, z0), split along random diagonals,
/// wound up (+y) or, with `random_winding`, either way. With `soup` every triangle gets its own
/// three vertices.
Indexed flat_grid(std::mt19937& rng, int n, float x0, float z0, float height, bool random_winding, bool soup) {
  Indexed m;
  auto at = [&](int i, int j) { return Vec3(x0 + static_cast<float>(i), height, z0 + static_cast<float>(j)); };
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) m.vertices.push_back(at(i, j));
  }
  auto id = [n](int i, int j) { return static_cast<unsigned>(i * (n + 1) + j); };
  std::vector<glm::uvec3> tris;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      // Wound up: (d - a) x (c - a) = +y, and so for the other three.
      if (rng() % 2) {
        tris.push_back({a, d, c});
        tris.push_back({a, c, b});
      } else {
        tris.push_back({a, d, b});
        tris.push_back({b, d, c});
      }
    }
  }
  for (glm::uvec3& t : tris) {
    if (random_winding && rng() % 2) std::swap(t.y, t.z);
  }
  if (!soup) {
    m.triangles = tris;
    return m;
  }
  Indexed s;
  for (const glm::uvec3& t : tris) {
    const auto base = static_cast<unsigned>(s.vertices.size());
    for (int k = 0; k < 3; ++k) s.vertices.push_back(m.vertices[t[k]]);
    s.triangles.push_back({base, base + 1, base + 2});
  }
  return s;
}

TEST(TriangleMesh, InvalidInputIsNamedByField) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Indexed m{{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}}, {{0, 2, 1}, {1, 2, 3}}};
  EXPECT_EQ(error_of(m), "no error");
  Indexed bad = m;
  bad.vertices[3].y = nan;
  EXPECT_EQ(error_of(bad), "triangle mesh vertex 3: not finite");
  bad = m;
  bad.vertices.push_back(Vec3(std::numeric_limits<float>::infinity()));  // unused, still refused
  EXPECT_EQ(error_of(bad), "triangle mesh vertex 4: not finite");
  bad = m;
  bad.triangles[1].z = 7;
  EXPECT_EQ(error_of(bad), "triangle mesh triangle 1: vertex index 7 out of range (4 vertices)");
  bad = m;
  bad.triangles.clear();
  EXPECT_EQ(error_of(bad), "triangle mesh: no triangles");
  bad = m;
  bad.triangles = {{0, 0, 1}, {0, 1, 1}};
  EXPECT_EQ(error_of(bad), "triangle mesh: all 2 triangles are degenerate (no area)");
  bad = m;
  bad.vertices = {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 0, 1}, {1, 0, 1}};
  EXPECT_EQ(error_of(bad), "triangle mesh: spans more than float range (coordinates near +-3.4e38 on both sides); no float frame holds it");
  // An unused vertex on the far side of the float range from the used ones (found by
  // fuzz_obj_mesh: its local coordinate overflowed to -inf in an accepted mesh). Unused, still
  // refused, naming it; near enough, it is kept.
  bad = m;
  bad.vertices = {{3e38f, 0, 0}, {3e38f, 0, 1}, {2e38f, 0, 0}, {-2e38f, 0, 0}};
  bad.triangles = {{0, 1, 2}};
  EXPECT_EQ(error_of(bad), "triangle mesh vertex 3: beyond float range of the triangles' vertices (no float frame holds them all)");
  bad.vertices[3].x = 0.0f;
  EXPECT_EQ(error_of(bad), "no error");
  for (float cos_angle : {nan, -1.5f, 1.01f}) {
    EXPECT_EQ(error_of(m, {cos_angle}), "triangle mesh options: active_edge_cos_angle must be in [-1, 1]");
  }
  // Too many triangles: refused from the count alone, before any is read.
  const std::span<const glm::uvec3> too_many(m.triangles.data(), kMaxMeshTriangles + 1);
  try {
    (void)make_triangle_mesh(m.vertices, too_many);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "triangle mesh: 357913942 triangles, more than the 357913941 a mesh can name (kMaxMeshTriangles)");
  }
  static_assert(3 * (kMaxMeshTriangles - 1) + 2 < (std::size_t{1} << 30), "edge feature ids below 2^30");
}

TEST(TriangleMesh, DegenerateTrianglesAreDroppedCountedAndListed) {
  Indexed m{{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {2, 0, 0}, {1, 0, 1}}, {}};
  m.triangles = {{0, 2, 1}, {0, 1, 3} /* collinear */, {1, 2, 4}, {2, 2, 4} /* repeated */, {4, 1, 1}};
  const TriangleMesh mesh = m.make();
  EXPECT_EQ(mesh.triangle_count(), 2u);
  EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 2, 1));
  EXPECT_EQ(mesh.triangles[1], glm::uvec3(1, 2, 4));
  EXPECT_EQ(mesh.dropped_triangles, (std::vector<std::uint32_t>{1, 3, 4}));
  EXPECT_EQ(mesh.stats.input_triangles, 5u);
  EXPECT_EQ(mesh.stats.degenerate_triangles, 3u);
  EXPECT_EQ(mesh.bvh.triangle_count(), 2u);
  EXPECT_EQ(mesh.vertices.size(), 5u);  // vertices and their indices are kept as given
}

TEST(TriangleMesh, FarAwayMeshesAreStoredAroundALocalOrigin) {
  std::mt19937 rng(80);
  const Indexed grid = flat_grid(rng, 10, 1e5f, -2e5f, 3e4f, false, false);
  const TriangleMesh mesh = grid.make();
  // The median vertex: the middle of the grid, exactly a vertex coordinate on every axis.
  EXPECT_EQ(mesh.origin, Vec3(1e5f + 5.0f, 3e4f, -2e5f + 5.0f));
  for (std::size_t i = 0; i < grid.vertices.size(); ++i) {
    EXPECT_EQ(mesh.origin + mesh.vertices[i], grid.vertices[i]);  // exact: small integers apart
    EXPECT_LE(max_abs(mesh.vertices[i]), 5.0f);
  }
  EXPECT_VEC3_NEAR(mesh.bvh.bounds().min, Vec3(-5, 0, -5), 0.0f);
  // The median ignores a far piece: one more triangle 1e6 away does not move the origin.
  Indexed with_far = grid;
  const auto base = static_cast<unsigned>(with_far.vertices.size());
  with_far.vertices.insert(with_far.vertices.end(), {Vec3(1e6f, 0, 0), Vec3(1e6f, 0, 1), Vec3(1e6f + 1, 0, 0)});
  with_far.triangles.push_back({base, base + 1, base + 2});
  EXPECT_EQ(with_far.make().origin, mesh.origin);
}

TEST(TriangleMesh, BoundsHoldEveryCornerPlaced) {
  std::mt19937 rng(81);
  Indexed m;
  for (int i = 0; i < 60; ++i) m.vertices.push_back(Vec3(5000, 0, 5000) + test::random_point3(rng, 20));
  for (unsigned i = 0; i + 2 < 60; i += 3) m.triangles.push_back({i, i + 1, i + 2});
  const TriangleMesh mesh = m.make();
  for (int trial = 0; trial < 50; ++trial) {
    const Transform3 xf{test::random_point3(rng, 100), test::random_rotation(rng)};
    const Aabb3 box = compute_aabb(mesh, xf);
    for (const Vec3& v : m.vertices) {
      const Vec3 w = transform_point(xf, v);
      EXPECT_TRUE(contains(fatten(box, 1e-2f), w));
    }
  }
  // Unrotated, the box is tight.
  const Aabb3 box = compute_aabb(mesh, Transform3{});
  Vec3 lo(1e30f), hi(-1e30f);
  for (const Vec3& v : m.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
  EXPECT_VEC3_NEAR(box.min, lo, 1e-3f);
  EXPECT_VEC3_NEAR(box.max, hi, 1e-3f);
}

TEST(TriangleMesh, FlatGridHasOnlyItsBorderActive) {
  std::mt19937 rng(82);
  for (int variant = 0; variant < 4; ++variant) {
    const int n = 6;
    const Indexed grid = flat_grid(rng, n, -3.0f, 2.0f, 0.5f, variant & 1, variant & 2);
    const TriangleMesh mesh = grid.make();
    int border = 0, inner = 0;
    for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
      for (int k = 0; k < 3; ++k) {
        const auto [a, b] = edge(mesh, t, k);
        // On the border when both ends lie on the same side of the square.
        const bool on_border = (a.x == b.x && (a.x == -3.0f || a.x == -3.0f + n)) || (a.z == b.z && (a.z == 2.0f || a.z == 2.0f + n));
        EXPECT_EQ(mesh.is_edge_active(t, k), on_border) << "variant " << variant << " triangle " << t << " edge " << k;
        (on_border ? border : inner)++;
      }
    }
    EXPECT_EQ(border, 4 * n);
    EXPECT_EQ(mesh.stats.boundary_edges, static_cast<std::size_t>(4 * n));
    EXPECT_EQ(mesh.stats.active_edges, static_cast<std::size_t>(4 * n));
    EXPECT_EQ(mesh.stats.non_manifold_edges, 0u);
    EXPECT_GT(inner, 100);
  }
}

TEST(TriangleMesh, CubeHasItsTwelveEdgesActiveAndItsFaceDiagonalsInactive) {
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  // Outward counter-clockwise quads, each split into two triangles.
  const std::vector<std::array<unsigned, 4>> quads{{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};
  Indexed cube{v, {}};
  for (const auto& q : quads) {
    cube.triangles.push_back({q[0], q[1], q[2]});
    cube.triangles.push_back({q[0], q[2], q[3]});
  }
  // Also with two triangles wound the other way: their edges over the cube's edges have no
  // outside but turn 90 degrees (active), their diagonals are flat (inactive).
  for (bool flip_some : {false, true}) {
    Indexed m = cube;
    if (flip_some) std::swap(m.triangles[3].y, m.triangles[3].z), std::swap(m.triangles[4].y, m.triangles[4].z);  // no shared edge
    const TriangleMesh mesh = m.make();
    EXPECT_EQ(mesh.stats.active_edges, 12u);
    EXPECT_EQ(mesh.stats.boundary_edges, 0u);
    for (std::uint32_t t = 0; t < 12; ++t) {
      for (int k = 0; k < 3; ++k) {
        const auto [a, b] = edge(mesh, t, k);
        const Vec3 d = glm::abs(b - a);
        const bool cube_edge = (d.x > 0) + (d.y > 0) + (d.z > 0) == 1;  // a diagonal moves on two axes
        EXPECT_EQ(mesh.is_edge_active(t, k), cube_edge) << t << " " << k;
      }
    }
  }
  // The same cube wound inwards (seen from inside, a room): every edge concave, none active.
  Indexed room = cube;
  for (glm::uvec3& t : room.triangles) std::swap(t.y, t.z);
  EXPECT_EQ(room.make().stats.active_edges, 0u);
}

/// Two unit squares meeting along the z axis: the first in y = 0 over x in [-1, 0] (normal +y),
/// the second rotated about z by `degrees` (positive: its far edge goes down, a convex ridge).
Indexed bend(float degrees) {
  const float r = degrees * test::kPi / 180.0f;
  const Vec3 far(std::cos(r), -std::sin(r), 0.0f);
  Indexed m{{{-1, 0, 0}, {-1, 0, 1}, {0, 0, 0}, {0, 0, 1}, far, far + Vec3(0, 0, 1)}, {}};
  m.triangles = {{0, 1, 3}, {0, 3, 2}, {2, 3, 5}, {2, 5, 4}};  // wound up (+y for the flat part)
  return m;
}

/// The bend's edge along z (x = 0): is it active, seen from `side` (0 above, where the
/// triangles face; 1 below), in both triangles that share it?
bool ridge_active(const TriangleMesh& mesh, int side = 0) {
  int active = 0, sides = 0;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = edge(mesh, t, k);
      if (a.x == 0.0f && b.x == 0.0f && a.y == 0.0f && b.y == 0.0f) ++sides, active += mesh.is_edge_active(t, k, side);
    }
  }
  EXPECT_EQ(sides, 2);
  EXPECT_TRUE(active == 0 || active == 2);
  return active == 2;
}

TEST(TriangleMesh, ConvexEdgesSharperThanTheThresholdAreActiveConcaveOnesNever) {
  EXPECT_FALSE(ridge_active(bend(0.0f).make()));     // flat
  EXPECT_FALSE(ridge_active(bend(3.0f).make()));     // convex, gentler than 5 degrees
  EXPECT_TRUE(ridge_active(bend(10.0f).make()));     // convex, sharper
  EXPECT_TRUE(ridge_active(bend(90.0f).make()));     // a ledge
  EXPECT_TRUE(ridge_active(bend(170.0f).make()));    // nearly folded back
  EXPECT_FALSE(ridge_active(bend(-10.0f).make()));   // concave
  EXPECT_FALSE(ridge_active(bend(-90.0f).make()));   // a wall rising from a floor
  EXPECT_FALSE(ridge_active(bend(-170.0f).make()));  // a narrow crease
  // The threshold is an option: at 2 degrees, the 3-degree ridge is active.
  EXPECT_TRUE(ridge_active(bend(3.0f).make({std::cos(2.0f * test::kPi / 180.0f)})));
  EXPECT_FALSE(ridge_active(bend(3.0f).make({std::cos(4.0f * test::kPi / 180.0f)})));
}

// Triangles are two-sided: from below, a concave edge is a ridge and a convex one a valley
// (finding 22: a sphere under a height field touching a spike's tip, whose edges are all concave
// from above, lost its contact to the one-sided correction).
TEST(TriangleMesh, FromBehindConcaveEdgesSharperThanTheThresholdAreActiveConvexOnesNever) {
  EXPECT_FALSE(ridge_active(bend(0.0f).make(), 1));
  EXPECT_FALSE(ridge_active(bend(-3.0f).make(), 1));  // concave, gentler than 5 degrees
  EXPECT_TRUE(ridge_active(bend(-10.0f).make(), 1));
  EXPECT_TRUE(ridge_active(bend(-90.0f).make(), 1));
  EXPECT_TRUE(ridge_active(bend(-170.0f).make(), 1));
  EXPECT_FALSE(ridge_active(bend(10.0f).make(), 1));  // convex from above
  EXPECT_FALSE(ridge_active(bend(90.0f).make(), 1));
  EXPECT_TRUE(ridge_active(bend(179.5f).make(), 1));  // folded back: both sides
  EXPECT_TRUE(ridge_active(bend(179.5f).make(), 0));
  EXPECT_TRUE(ridge_active(bend(-3.0f).make({std::cos(2.0f * test::kPi / 180.0f)}), 1));
  const TriangleMesh wall = bend(-90.0f).make();
  EXPECT_EQ(wall.stats.active_edges, wall.stats.boundary_edges);  // the crease is not active from the front
  EXPECT_EQ(wall.stats.active_edges_from_behind, wall.stats.boundary_edges + 1);
  // The same edge's two sides by the rule itself: n1 = +y, n2 turned about e = +z.
  const Vec3 up(0, 1, 0), e(0, 0, 1);
  EXPECT_EQ(active_edge_sides(up, Vec3(0.5f, 0.866025f, 0), e, true, kActiveEdgeCosAngle), 2u);   // concave from the front
  EXPECT_EQ(active_edge_sides(up, Vec3(-0.5f, 0.866025f, 0), e, true, kActiveEdgeCosAngle), 1u);  // convex
  EXPECT_EQ(active_edge_sides(up, Vec3(0.5f, 0.866025f, 0), e, false, kActiveEdgeCosAngle), 3u);  // windings disagree
  EXPECT_EQ(active_edge_sides(up, up, e, false, kActiveEdgeCosAngle), 0u);                         // flat
}

TEST(TriangleMesh, ConcaveStepHasItsInsideCornerInactiveAndItsLipActive) {
  // Profile in x-y, extruded over z in [0, 1]: floor y = 0 for x in [0, 1], wall x = 1 up to
  // y = 1 (facing the floor, -x), top y = 1 for x in [1, 2]. Inside corner at (1, 0), lip at (1, 1).
  const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {2, 1, 1}};
  Indexed step{v, {}};
  for (unsigned i = 0; i < 3; ++i) {  // the strip from profile point i to i + 1, wound so its normal faces up / -x
    step.triangles.push_back({i, i + 4, i + 5});
    step.triangles.push_back({i, i + 5, i + 1});
  }
  const TriangleMesh mesh = step.make();
  EXPECT_EQ(triangle_normal(v[0], v[4], v[5]), Vec3(0, 1, 0));
  EXPECT_EQ(triangle_normal(v[1], v[5], v[6]), Vec3(-1, 0, 0));
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const auto [a, b] = edge(mesh, t, k);
      if (a.z == b.z || a.x != b.x || a.y != b.y) continue;  // only the edges along z
      if (a.x == 1.0f && a.y == 0.0f) EXPECT_FALSE(mesh.is_edge_active(t, k)) << "inside corner";
      if (a.x == 1.0f && a.y == 1.0f) EXPECT_TRUE(mesh.is_edge_active(t, k)) << "lip";
      if (a.x == 0.0f || a.x == 2.0f) EXPECT_TRUE(mesh.is_edge_active(t, k)) << "boundary";
      // From behind (below the floor, behind the wall) the inside corner is the ridge.
      if (a.x == 1.0f && a.y == 0.0f) EXPECT_TRUE(mesh.is_edge_active(t, k, 1)) << "inside corner from behind";
      if (a.x == 1.0f && a.y == 1.0f) EXPECT_FALSE(mesh.is_edge_active(t, k, 1)) << "lip from behind";
      if (a.x == 0.0f || a.x == 2.0f) EXPECT_TRUE(mesh.is_edge_active(t, k, 1)) << "boundary from behind";
    }
  }
}

TEST(TriangleMesh, FinsAndNonManifoldEdgesAreActive) {
  // A triangle folded back over its edge (0, 1): normals opposite.
  const Indexed fin{{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0.5f, 0, 1}}, {{0, 1, 2}, {1, 0, 3}}};
  const TriangleMesh folded = fin.make();
  EXPECT_TRUE(folded.is_edge_active(0, 0));
  EXPECT_TRUE(folded.is_edge_active(1, 0));
  // Three flat triangles on one edge (a T of walls): non-manifold, active though coplanar pairs.
  const Indexed tee{{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}}, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
  const TriangleMesh mesh = tee.make();
  EXPECT_EQ(mesh.stats.non_manifold_edges, 1u);
  for (std::uint32_t t = 0; t < 3; ++t) EXPECT_TRUE(mesh.is_edge_active(t, 0));
}

}  // namespace
}  // namespace collide
