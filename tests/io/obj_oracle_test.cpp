// collide_io's OBJ reader against an independent one, tinyobjloader (libtinyobjloader-dev), on
// the shared level meshes and the n-gon level: the same vertices (to the float), and the same
// faces (for triangles the same indices; for n-gons the same vertices, n - 2 triangles).
#include <collide/io/obj.hpp>

#include <gtest/gtest.h>

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace collide {
namespace {

TEST(ObjOracle, VerticesAndFacesAreTinyobjloadersToo) {
  for (const std::string path :
       {std::string(COLLIDE_DATA_DIR) + "/meshes/recast/dungeon.obj", std::string(COLLIDE_DATA_DIR) + "/meshes/recast/undulating.obj",
        std::string(COLLIDE_DATA_DIR) + "/meshes/fcl/env.obj", std::string(COLLIDE_DATA_DIR) + "/meshes/fcl/rob.obj",
        std::string(COLLIDE_TEST_DATA_DIR) + "/ngon_level.obj"}) {
    SCOPED_TRACE(path);
    tinyobj::ObjReaderConfig config;
    config.triangulate = false;
    tinyobj::ObjReader oracle;
    ASSERT_TRUE(oracle.ParseFromFile(path, config)) << oracle.Error();
    const TriangleSoup soup = io::load_obj(path);
    const std::vector<float>& v = oracle.GetAttrib().vertices;
    ASSERT_EQ(soup.positions.size() * 3, v.size());
    int different = 0;
    for (std::size_t i = 0; i < soup.positions.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        // tinyobjloader's own decimal conversion may round the last bit the other way.
        const float ours = soup.positions[i][k], theirs = v[3 * i + static_cast<std::size_t>(k)];
        if (ours != theirs) ++different;
        EXPECT_NEAR(ours, theirs, 1e-6f * std::max(1.0f, std::fabs(theirs)));
      }
    }
    EXPECT_LE(different, static_cast<int>(v.size() / 100));
    std::size_t next = 0;
    for (const tinyobj::shape_t& shape : oracle.GetShapes()) {
      std::size_t corner = 0;
      for (const unsigned int n : shape.mesh.num_face_vertices) {
        std::set<std::uint32_t> face;
        for (unsigned int k = 0; k < n; ++k) face.insert(static_cast<std::uint32_t>(shape.mesh.indices[corner + k].vertex_index));
        std::set<std::uint32_t> used;
        for (unsigned int k = 0; k + 2 < n; ++k) {
          ASSERT_LT(next, soup.triangles.size());
          const glm::uvec3 t = soup.triangles[next++];
          if (n == 3) {
            EXPECT_EQ(t, glm::uvec3(static_cast<std::uint32_t>(shape.mesh.indices[corner].vertex_index),
                                    static_cast<std::uint32_t>(shape.mesh.indices[corner + 1].vertex_index),
                                    static_cast<std::uint32_t>(shape.mesh.indices[corner + 2].vertex_index)));
          }
          used.insert({t.x, t.y, t.z});
        }
        EXPECT_EQ(used, face);  // every vertex of the face a corner, no other
        corner += n;
      }
    }
    EXPECT_EQ(next, soup.triangles.size());
  }
}

}  // namespace
}  // namespace collide
