// OBJ files as collision meshes (io::load_triangle_mesh): the shared level meshes load with the
// counts SOURCES.md measured independently (triangles, vertices, boundary and non-manifold
// edges after welding equal positions), far-away ones around a local origin, and errors of
// make_triangle_mesh name the file.
#include <collide/core/error.hpp>
#include <collide/io/obj.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace collide {
namespace {

const std::string kMeshes = std::string(COLLIDE_DATA_DIR) + "/meshes/";

TEST(ObjMesh, SharedMeshesLoadWithTheirMeasuredCounts) {
  struct Expected {
    const char* file;
    std::size_t vertices, triangles;
    long boundary, non_manifold;  // -1: not measured in SOURCES.md
  };
  for (const Expected& e : {Expected{"recast/dungeon.obj", 5101, 10133, 432, 138}, Expected{"recast/undulating.obj", 2800, 5202, 196, 0},
                            Expected{"fcl/env.obj", 6540, 2180, -1, -1}, Expected{"fcl/rob.obj", 648, 216, 96, 27}}) {
    const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + e.file);
    EXPECT_EQ(mesh.vertices.size(), e.vertices) << e.file;
    EXPECT_EQ(mesh.triangle_count(), e.triangles) << e.file;  // SOURCES.md: no degenerate triangles
    EXPECT_EQ(mesh.stats.degenerate_triangles, 0u) << e.file;
    EXPECT_EQ(mesh.bvh.triangle_count(), e.triangles) << e.file;
    if (e.boundary >= 0) EXPECT_EQ(static_cast<long>(mesh.stats.boundary_edges), e.boundary) << e.file;
    if (e.non_manifold >= 0) EXPECT_EQ(static_cast<long>(mesh.stats.non_manifold_edges), e.non_manifold) << e.file;
    // Active edges include every boundary and non-manifold edge, and are a minority of a level's.
    EXPECT_GE(mesh.stats.active_edges, mesh.stats.boundary_edges + mesh.stats.non_manifold_edges) << e.file;
  }
}

TEST(ObjMesh, FarAwayTerrainIsStoredAroundALocalOrigin) {
  // undulating.obj: bbox (4999.1, -4.1, 4999.6)..(5098.0, 6.8, 5098.8) (SOURCES.md).
  const TriangleMesh mesh = io::load_triangle_mesh(kMeshes + "recast/undulating.obj");
  EXPECT_GT(mesh.origin.x, 4999.0f);
  EXPECT_LT(mesh.origin.x, 5099.0f);
  EXPECT_GT(mesh.origin.z, 4999.0f);
  EXPECT_LT(mesh.origin.z, 5099.0f);
  const Aabb3 local = mesh.bvh.bounds();
  EXPECT_LT(max_abs(local.min), 100.0f);
  EXPECT_LT(max_abs(local.max), 100.0f);
  const Aabb3 world = compute_aabb(mesh, Transform3{});
  EXPECT_NEAR(world.min.x, 4999.1f, 0.1f);
  EXPECT_NEAR(world.max.z, 5098.8f, 0.1f);
}

TEST(ObjMesh, ErrorsNameTheFile) {
  const std::string path = ::testing::TempDir() + "flat_line.obj";
  std::ofstream(path, std::ios::binary) << "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n";
  try {
    (void)io::load_triangle_mesh(path);
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "flat_line.obj: triangle mesh: all 1 triangles are degenerate (no area)");
  }
  std::remove(path.c_str());
  try {
    (void)io::load_triangle_mesh(kMeshes + "recast/dungeon.obj", {2.0f});
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "dungeon.obj: triangle mesh options: active_edge_cos_angle must be in [-1, 1]");
  }
}

}  // namespace
}  // namespace collide
