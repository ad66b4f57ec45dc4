#pragma once
// Concave test meshes made of axis-aligned boxes, for the mesh decomposition's tests and the
// world's compound bodies: one home for the box triangles and the dumbbell.

#include <collide/core/math.hpp>

#include <glm/vec3.hpp>

#include <vector>

namespace collide::test {

/// Triangles of the axis-aligned box [lo, hi], outward wound (counter-clockwise seen from
/// outside), appended to (vertices, triangles): 8 vertices, 12 triangles.
inline void add_box(std::vector<Vec3>& vertices, std::vector<glm::uvec3>& triangles, Vec3 lo, Vec3 hi) {
  const auto base = static_cast<unsigned>(vertices.size());
  for (int c = 0; c < 8; ++c) vertices.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  // Corner c has bit 0 = x, bit 1 = y, bit 2 = z; each face as two triangles.
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& f : faces) {
    triangles.push_back({base + f[0], base + f[1], base + f[2]});
    triangles.push_back({base + f[0], base + f[2], base + f[3]});
  }
}

/// The dumbbell, moved by `offset`: two 1 m cubes [0, 1]^3 and [4, 5] x [0, 1]^2, 3 m apart,
/// joined by a 0.2 m square bar along x through y, z in [0.4, 0.6] (three overlapping closed
/// boxes: three convex parts), appended to (vertices, triangles).
inline void add_dumbbell(std::vector<Vec3>& vertices, std::vector<glm::uvec3>& triangles, Vec3 offset = Vec3(0.0f)) {
  add_box(vertices, triangles, offset + Vec3(0, 0, 0), offset + Vec3(1, 1, 1));
  add_box(vertices, triangles, offset + Vec3(4, 0, 0), offset + Vec3(5, 1, 1));
  add_box(vertices, triangles, offset + Vec3(1, 0.4f, 0.4f), offset + Vec3(4, 0.6f, 0.6f));
}

}  // namespace collide::test
