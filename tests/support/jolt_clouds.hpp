#pragma once
// The point clouds of Jolt's convex_hulls.bin (../shared/data/meshes/jolt, see SOURCES.md),
// for tests and benchmarks (both define COLLIDE_DATA_DIR).

#include <collide/core/math.hpp>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace collide::test {

/// The clouds in file order: repeated [uint32 n][n x float32 (x, y, z)], little-endian. Empty if
/// the file is missing.
inline std::vector<std::vector<Vec3>> load_jolt_clouds() {
  const std::string path = std::string(COLLIDE_DATA_DIR) + "/meshes/jolt/convex_hulls.bin";
  std::ifstream in(path, std::ios::binary);
  std::vector<std::vector<Vec3>> clouds;
  std::uint32_t n = 0;
  while (in.read(reinterpret_cast<char*>(&n), sizeof n)) {
    std::vector<Vec3> cloud(n);
    static_assert(sizeof(Vec3) == 12);
    in.read(reinterpret_cast<char*>(cloud.data()), static_cast<std::streamsize>(n * sizeof(Vec3)));
    if (!in) break;
    clouds.push_back(std::move(cloud));
  }
  return clouds;
}

}  // namespace collide::test
