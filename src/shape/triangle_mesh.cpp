#include <collide/shape/triangle_mesh.hpp>

#include <collide/core/error.hpp>
#include <collide/core/radix_sort.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <string>

namespace collide {
namespace {

/// For each vertex, the smallest index of a vertex at exactly the same position (float equality:
/// -0 equals +0). One pass in index order over an open-addressed table (linear probing, at most
/// half full) of the first index seen at each position, keyed by the position's bits with -0 read
/// as +0 (the weld sorted the positions before: on FCL's env.obj, a soup of 6,540 vertices for
/// 2,180 triangles, the sort was a fifth of the mesh's build). Positions must be finite.
std::vector<std::uint32_t> weld_equal_positions(const std::vector<Vec3>& positions) {
  constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
  const std::size_t mask = std::bit_ceil(2 * positions.size() + 2) - 1;
  std::vector<std::uint32_t> table(mask + 1, kEmpty);
  std::vector<std::uint32_t> canonical(positions.size());
  for (std::uint32_t i = 0; i < positions.size(); ++i) {
    const Vec3 p = positions[i] + Vec3(0.0f);  // -0 + 0 = +0: equal positions, equal bits
    const std::uint64_t x = std::bit_cast<std::uint32_t>(p.x), y = std::bit_cast<std::uint32_t>(p.y),
                        z = std::bit_cast<std::uint32_t>(p.z);
    std::uint64_t h = x * 0x9E3779B97F4A7C15ull ^ y * 0xC2B2AE3D27D4EB4Full ^ z * 0x165667B19E3779F9ull;
    std::size_t at = static_cast<std::size_t>(h ^ (h >> 29)) & mask;
    while (table[at] != kEmpty && !(positions[table[at]] == positions[i])) at = (at + 1) & mask;
    if (table[at] == kEmpty) table[at] = i;
    canonical[i] = table[at];
  }
  return canonical;
}

/// One side of an edge: triangle t's edge k, between welded vertices lo < hi.
struct EdgeSide {
  std::uint32_t lo, hi;
  std::uint32_t triangle;
  std::uint8_t k;
  bool forward;  ///< the triangle runs lo -> hi along it
};

}  // namespace

Vec3 median_vertex(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles) {
  std::vector<float> axis(3 * triangles.size());
  Vec3 origin(0.0f);
  for (int k = 0; k < 3; ++k) {
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      for (int c = 0; c < 3; ++c) axis[3 * t + static_cast<std::size_t>(c)] = positions[triangles[t][c]][k];
    }
    const auto middle = axis.begin() + static_cast<std::ptrdiff_t>(axis.size() / 2);
    std::nth_element(axis.begin(), middle, axis.end());
    origin[k] = *middle;
  }
  return origin;
}

TriangleMesh make_triangle_mesh(std::span<const Vec3> vertices, std::span<const glm::uvec3> triangles,
                                const TriangleMeshOptions& options) {
  if (!(options.active_edge_cos_angle >= -1.0f && options.active_edge_cos_angle <= 1.0f)) {
    throw InvalidInput("triangle mesh options: active_edge_cos_angle must be in [-1, 1]");
  }
  if (triangles.size() > kMaxMeshTriangles) {
    throw InvalidInput("triangle mesh: " + std::to_string(triangles.size()) + " triangles, more than the " +
                       std::to_string(kMaxMeshTriangles) + " a mesh can name (kMaxMeshTriangles)");
  }
  if (triangles.empty()) throw InvalidInput("triangle mesh: no triangles");
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    if (!is_finite(vertices[i])) throw InvalidInput("triangle mesh vertex " + std::to_string(i) + ": not finite");
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      if (triangles[t][k] >= vertices.size()) {
        throw InvalidInput("triangle mesh triangle " + std::to_string(t) + ": vertex index " + std::to_string(triangles[t][k]) +
                           " out of range (" + std::to_string(vertices.size()) + " vertices)");
      }
    }
  }

  TriangleMesh mesh;
  mesh.stats.input_triangles = triangles.size();
  mesh.origin = median_vertex(vertices, triangles);
  // The span of the used vertices must fit float: beyond it local coordinates overflow.
  Aabb3 box{vertices[triangles[0].x], vertices[triangles[0].x]};
  for (const glm::uvec3& t : triangles) {
    for (int k = 0; k < 3; ++k) box = merge(box, Aabb3{vertices[t[k]], vertices[t[k]]});
  }
  if (!is_finite(box.size())) {
    throw InvalidInput("triangle mesh: spans more than float range (coordinates near +-3.4e38 on both sides); "
                       "no float frame holds it");
  }
  // The used vertices are within that span of the origin; an unused one may not be (refused, as
  // an unused vertex that is not finite is: `vertices` keeps every given vertex, finite).
  mesh.vertices.resize(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    mesh.vertices[i] = vertices[i] - mesh.origin;
    if (!is_finite(mesh.vertices[i])) {
      throw InvalidInput("triangle mesh vertex " + std::to_string(i) +
                         ": beyond float range of the triangles' vertices (no float frame holds them all)");
    }
  }

  // Drop triangles without a normal in float in the stored coordinates (their cross product
  // zero or beyond float range), as before stop 104 made triangle_normal in double: a needle
  // whose sides' cross product rounds to zero in float (a short side of 1e-14 at 1e-10 from the
  // origin) has a double normal, but the contact's clip and separating axes, in float, lose it
  // (the fuzzer's sphere check found one without a contact).
  std::vector<Vec3> normals;
  mesh.triangles.reserve(triangles.size());
  normals.reserve(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const glm::uvec3 v = triangles[t];
    const Vec3 a = mesh.vertices[v.x], b = mesh.vertices[v.y], c = mesh.vertices[v.z];
    const float float_area = max_abs(cross(b - a, c - a));
    const Vec3 n = float_area > 0.0f && std::isfinite(float_area) ? triangle_normal(a, b, c) : Vec3(0.0f);
    if (n == Vec3(0.0f)) {
      mesh.dropped_triangles.push_back(static_cast<std::uint32_t>(t));
      continue;
    }
    mesh.triangles.push_back(v);
    normals.push_back(n);
  }
  mesh.stats.degenerate_triangles = mesh.dropped_triangles.size();
  if (mesh.triangles.empty()) {
    throw InvalidInput("triangle mesh: all " + std::to_string(triangles.size()) + " triangles are degenerate (no area)");
  }

  // Active edges: group the triangles' edges by their welded end points.
  const std::vector<std::uint32_t> canonical = weld_equal_positions(mesh.vertices);
  // Ordered by (lo, hi), then triangle and corner (sort_edge_uses keeps use order).
  std::vector<EdgeSide> sides;
  sides.reserve(3 * mesh.triangles.size());
  for (const EdgeUse& e :
       sort_edge_uses(mesh.triangles, mesh.vertices.size(), [&](std::uint32_t v) { return canonical[v]; })) {
    const auto t = static_cast<std::uint32_t>(e.use / 3);
    const int k = static_cast<int>(e.use % 3);
    const std::uint32_t u = canonical[mesh.triangles[t][k]], v = canonical[mesh.triangles[t][(k + 1) % 3]];
    sides.push_back({std::min(u, v), std::max(u, v), t, static_cast<std::uint8_t>(k), u < v});
  }
  mesh.active_edges.assign(mesh.triangles.size(), 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].lo == sides[i].lo && sides[j].hi == sides[i].hi) ++j;
    if (j - i == 2) {
      const EdgeSide& a = sides[i];
      const EdgeSide& b = sides[i + 1];
      const Vec3 e = mesh.vertices[a.forward ? a.hi : a.lo] - mesh.vertices[a.forward ? a.lo : a.hi];
      // Consistent windings run a shared edge in opposite directions; otherwise turn b's normal.
      const bool consistent = a.forward != b.forward;
      const Vec3 nb = consistent ? normals[b.triangle] : -normals[b.triangle];
      // Sides as a sees them; b, its winding consistent, sees the same (n2 x n1 . -e is n1 x n2
      // . e); inconsistent, both sides or neither.
      const std::uint8_t on = active_edge_sides(normals[a.triangle], nb, e, consistent, options.active_edge_cos_angle);
      if (on & 1u) ++mesh.stats.active_edges;
      if (on & 2u) ++mesh.stats.active_edges_from_behind;
      for (std::size_t s = i; s < j; ++s) mesh.active_edges[sides[s].triangle] |= active_edge_bits(sides[s].k, on);
    } else {
      // One triangle (a boundary) or three and more (non-manifold): active from both sides.
      ++(j - i == 1 ? mesh.stats.boundary_edges : mesh.stats.non_manifold_edges);
      ++mesh.stats.active_edges;
      ++mesh.stats.active_edges_from_behind;
      for (std::size_t s = i; s < j; ++s) mesh.active_edges[sides[s].triangle] |= active_edge_bits(sides[s].k, 3u);
    }
    i = j;
  }

  mesh.bvh = TriangleBvh(mesh.vertices, mesh.triangles);
  return mesh;
}

void for_each_triangle(const TriangleMesh& mesh, const Transform3& xm, const Aabb3& box,
                       TriangleCornersCallback visit) {
  // The box in the stored frame (mesh space minus the origin), the corners back to the world.
  const Aabb3 local = transform_aabb(box, inv_mul(xm, Transform3{}));
  const Aabb3 stored{local.min - mesh.origin, local.max - mesh.origin};
  Transform3 stored_to_world = xm;
  stored_to_world.p += rotate(xm.q, mesh.origin);
  const Frame3 f = Frame3::from(stored_to_world);
  mesh.bvh.query(stored, [&](std::uint32_t t) -> bool {
    return visit(t, {transform_point(f, mesh.corner(t, 0)), transform_point(f, mesh.corner(t, 1)),
                     transform_point(f, mesh.corner(t, 2))});
  });
}

Aabb3 compute_aabb(const TriangleMesh& mesh, const Transform3& xf) noexcept {
  const Aabb3 local = mesh.bvh.bounds();
  return transform_aabb({mesh.origin + local.min, mesh.origin + local.max}, xf);
}

}  // namespace collide
