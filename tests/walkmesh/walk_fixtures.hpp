#pragma once
// Generated walk meshes and independent answers (brute force in double precision) for the
// walk mesh tests.

#include <collide/walkmesh/walk_mesh.hpp>

#include "support/brute_triangle.hpp"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace collide::test {

inline float uniform01(std::mt19937& rng) { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng); }
inline float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

/// A random rigid 3D transform: rotation (tilted at most `max_tilt` radians away from +y up) and
/// a translation of size `extent`.
struct Rigid3 {
  glm::quat q{1.0f, 0.0f, 0.0f, 0.0f};
  Vec3 p{0.0f};
  Vec3 operator()(Vec3 v) const { return p + q * v; }
};
inline Rigid3 random_rigid(std::mt19937& rng, float extent, float max_tilt) {
  const float yaw = uniform(rng, -3.14159f, 3.14159f);
  const float tilt = uniform(rng, 0.0f, max_tilt);
  const float tilt_dir = uniform(rng, -3.14159f, 3.14159f);
  const glm::quat q = glm::angleAxis(tilt, Vec3(std::cos(tilt_dir), 0.0f, std::sin(tilt_dir))) *
                      glm::angleAxis(yaw, Vec3(0.0f, 1.0f, 0.0f));
  return {q, Vec3(uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent))};
}

/// An n x n grid of cells of size `cell` in the xz plane (height from `height(x, z)`), corners
/// jittered by `jitter` (fraction of a cell), each cell split along a random diagonal, each
/// triangle wound at random. Vertices are shared (indexed mesh).
template <class Height>
TriangleSoup grid_soup(std::mt19937& rng, int n, float cell, float jitter, Height height,
                       const Rigid3& xf = {}) {
  TriangleSoup s;
  s.name = "grid";
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      float x = static_cast<float>(i) * cell, z = static_cast<float>(j) * cell;
      if (!border) {
        x += uniform(rng, -jitter, jitter) * cell;
        z += uniform(rng, -jitter, jitter) * cell;
      }
      s.positions.push_back(xf(Vec3(x, height(x, z), z)));
    }
  }
  auto id = [n](int i, int j) { return static_cast<unsigned>(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      glm::uvec3 t0, t1;
      if (rng() % 2) {
        t0 = {a, b, c};
        t1 = {a, c, d};
      } else {
        t0 = {a, b, d};
        t1 = {b, c, d};
      }
      if (rng() % 2) std::swap(t0.y, t0.z);
      if (rng() % 2) std::swap(t1.y, t1.z);
      s.triangles.push_back(t0);
      s.triangles.push_back(t1);
    }
  }
  return s;
}

/// A torus (closed, no boundary): major radius R, minor r, nu x nv quads split in two.
inline TriangleSoup torus_soup(int nu, int nv, float R, float r, const Rigid3& xf = {}) {
  TriangleSoup s;
  s.name = "torus";
  const float two_pi = 2.0f * std::numbers::pi_v<float>;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const float u = two_pi * static_cast<float>(i) / static_cast<float>(nu);
      const float v = two_pi * static_cast<float>(j) / static_cast<float>(nv);
      s.positions.push_back(xf(Vec3((R + r * std::cos(v)) * std::cos(u), r * std::sin(v),
                                    (R + r * std::cos(v)) * std::sin(u))));
    }
  }
  auto id = [&](int i, int j) { return static_cast<unsigned>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      s.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      s.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  }
  return s;
}

/// Every triangle with its own three copies of its vertices (what STL files and FCL's env.obj
/// look like): welding must recover the shared mesh.
inline TriangleSoup unshared(const TriangleSoup& in) {
  TriangleSoup s;
  s.name = in.name + " (unshared)";
  for (const glm::uvec3& t : in.triangles) {
    const auto base = static_cast<unsigned>(s.positions.size());
    for (int k = 0; k < 3; ++k) s.positions.push_back(in.positions[t[k]]);
    s.triangles.push_back({base, base + 1, base + 2});
  }
  return s;
}

/// Distance from a world point to the walk mesh by scanning every triangle, in double precision.
inline double brute_distance(const WalkMesh& mesh, Vec3 world) {
  double best = std::numeric_limits<double>::infinity();
  const glm::dvec3 p(world);
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::uvec3 tri = mesh.triangle(t);
    const glm::dvec3 q = brute_closest_on_triangle(p, glm::dvec3(mesh.world_vertex(tri.x)),
                                                   glm::dvec3(mesh.world_vertex(tri.y)),
                                                   glm::dvec3(mesh.world_vertex(tri.z)));
    best = std::min(best, glm::length(q - p));
  }
  return best;
}

/// A random walk point, uniform over the mesh's area.
inline WalkPoint random_walk_point(const WalkMesh& mesh, std::mt19937& rng) {
  std::vector<float> cumulative(mesh.triangle_count());
  float sum = 0.0f;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) cumulative[t] = (sum += mesh.triangle_area(t));
  const float x = uniform01(rng) * sum;
  const auto t = static_cast<std::uint32_t>(
      std::min<std::size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), x) - cumulative.begin(),
                            mesh.triangle_count() - 1));
  float u = uniform01(rng), v = uniform01(rng);
  if (u + v > 1.0f) {
    u = 1.0f - u;
    v = 1.0f - v;
  }
  return mesh.walk_point(t, Vec3(1.0f - u - v, u, v));
}

/// A random direction in the plane perpendicular to `n`, of length `len`.
inline Vec3 random_tangent(std::mt19937& rng, Vec3 n, float len) {
  Vec3 d(uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f));
  d -= glm::dot(d, n) * n;
  const float l = glm::length(d);
  return l > 0.0f ? d * (len / l) : Vec3(0.0f);
}

}  // namespace collide::test
