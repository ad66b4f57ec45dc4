// From a level mesh to a walk mesh: slope filter, headroom filter, then build_walk_mesh.
#include <collide/walkmesh/make_walk_mesh.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace collide {
namespace {

/// Interval of the points' projections onto `axis`.
template <std::size_t N>
void project(const std::array<Vec3, N>& points, Vec3 axis, float& lo, float& hi) noexcept {
  lo = hi = glm::dot(points[0], axis);
  for (std::size_t i = 1; i < N; ++i) {
    const float d = glm::dot(points[i], axis);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
}

/// True when the convex prism (triangle `base` swept by `lift`) and triangle `other` overlap by
/// more than `tolerance` on every separating axis candidate: the face normals of both, and the
/// cross products of every prism edge direction (three base edges, the lift) with every edge of
/// the other triangle (separating axis theorem for convex polyhedra; Ericson 5.2.1).
bool penetrates(const std::array<Vec3, 3>& base, Vec3 lift, const std::array<Vec3, 3>& other,
                float tolerance) noexcept {
  const std::array<Vec3, 6> prism{base[0], base[1], base[2], base[0] + lift, base[1] + lift, base[2] + lift};
  const std::array<Vec3, 3> e{base[1] - base[0], base[2] - base[1], base[0] - base[2]};
  const std::array<Vec3, 3> f{other[1] - other[0], other[2] - other[1], other[0] - other[2]};
  std::array<Vec3, 17> axes;
  int n = 0;
  axes[n++] = glm::cross(e[0], e[1]);
  axes[n++] = glm::cross(f[0], f[1]);
  for (const Vec3& ei : e) axes[n++] = glm::cross(ei, lift);
  for (const Vec3& fj : f) {
    for (const Vec3& ei : e) axes[n++] = glm::cross(ei, fj);
    axes[n++] = glm::cross(lift, fj);
  }
  for (const Vec3& raw : axes) {
    const float len = glm::length(raw);
    if (!(len > 0.0f)) continue;  // parallel edges: no axis
    const Vec3 axis = raw / len;
    float a_lo, a_hi, b_lo, b_hi;
    project(prism, axis, a_lo, a_hi);
    project(other, axis, b_lo, b_hi);
    if (a_hi - b_lo <= tolerance || b_hi - a_lo <= tolerance) return false;
  }
  return true;
}

}  // namespace

WalkMesh make_walk_mesh(const TriangleSoup& level, const WalkAgent& agent) {
  const std::string name = level.name.empty() ? "level" : level.name;
  if (!std::isfinite(agent.max_slope) || agent.max_slope < 0.0f ||
      agent.max_slope >= 0.5f * std::numbers::pi_v<float>) {
    throw InvalidInput(name + ": WalkAgent.max_slope must be in [0, pi/2) radians");
  }
  if (!std::isfinite(agent.height) || agent.height < 0.0f) {
    throw InvalidInput(name + ": WalkAgent.height must be finite and >= 0");
  }
  if (!is_finite(agent.up) || !(glm::length(agent.up) > 0.0f)) {
    throw InvalidInput(name + ": WalkAgent.up must be a finite non-zero vector");
  }
  validate_triangle_soup(level);
  const Vec3 up = glm::normalize(agent.up);

  // Work near the origin: level coordinates may be large (undulating.obj sits at 5000).
  Aabb3 box{level.positions[level.triangles[0].x], level.positions[level.triangles[0].x]};
  for (const glm::uvec3& t : level.triangles) {
    for (int k = 0; k < 3; ++k) box = merge(box, Aabb3{level.positions[t[k]], level.positions[t[k]]});
  }
  const Vec3 origin = box.center();
  const Vec3 extent = box.size();
  const float size = std::max({extent.x, extent.y, extent.z});
  std::vector<Vec3> local(level.positions.size(), Vec3(0.0f));
  for (const glm::uvec3& t : level.triangles) {
    for (int k = 0; k < 3; ++k) local[t[k]] = level.positions[t[k]] - origin;
  }
  const TriangleBvh bvh(local, level.triangles);
  const float cos_max_slope = std::cos(agent.max_slope);
  const Vec3 lift = agent.height * up;
  const float tolerance = kHeadroomTolerance * size;

  TriangleSoup walkable;
  walkable.name = level.name;
  walkable.positions = level.positions;
  std::size_t too_steep = 0, degenerate = 0, low_headroom = 0, refined = 0;
  auto blocked = [&](std::uint32_t self, const std::array<Vec3, 3>& base) {
    bool hit = false;
    Aabb3 prism_box{glm::min(glm::min(base[0], base[1]), base[2]), glm::max(glm::max(base[0], base[1]), base[2])};
    prism_box = merge(prism_box, Aabb3{prism_box.min + lift, prism_box.max + lift});
    bvh.query(prism_box, [&](std::uint32_t other) {
      if (hit || other == self) return;
      const glm::uvec3 o = level.triangles[other];
      hit = penetrates(base, lift, {local[o.x], local[o.y], local[o.z]}, tolerance);
    });
    return hit;
  };
  // A triangle partly under an obstacle is split into four at its edge midpoints, again and
  // again, keeping the pieces with headroom, until pieces are smaller than
  // kHeadroomRefineFraction of the agent's height. Neighbours that were not split meet the
  // pieces at T-junctions, which build_walk_mesh splits so they link.
  const float min_edge = kHeadroomRefineFraction * agent.height;
  struct Piece {
    std::array<Vec3, 3> corners;  // local coordinates
    int depth;
  };
  std::vector<Piece> pieces;
  for (std::uint32_t t = 0; t < level.triangles.size(); ++t) {
    const glm::uvec3 tri = level.triangles[t];
    const std::array<Vec3, 3> base{local[tri.x], local[tri.y], local[tri.z]};
    const Vec3 n = glm::cross(base[1] - base[0], base[2] - base[0]);
    const float len = glm::length(n);
    const float longest2 = std::max({glm::dot(base[1] - base[0], base[1] - base[0]),
                                     glm::dot(base[2] - base[1], base[2] - base[1]),
                                     glm::dot(base[0] - base[2], base[0] - base[2])});
    if (!(len > kWalkDegenerateTolerance * longest2)) {  // no plane, so no slope: build_walk_mesh's test
      ++degenerate;
      continue;
    }
    if (std::fabs(glm::dot(n, up)) < cos_max_slope * len) {
      ++too_steep;
      continue;
    }
    if (agent.height <= 0.0f || !blocked(t, base)) {
      walkable.triangles.push_back(tri);
      continue;
    }
    bool dropped = false, split = false;
    pieces.assign(1, {base, 0});
    while (!pieces.empty()) {
      const Piece piece = pieces.back();
      pieces.pop_back();
      const auto& c = piece.corners;
      if (piece.depth > 0 && !blocked(t, c)) {
        const auto first = static_cast<unsigned>(walkable.positions.size());
        for (const Vec3& corner : c) walkable.positions.push_back(origin + corner);
        walkable.triangles.push_back({first, first + 1, first + 2});
        continue;
      }
      const float longest = std::sqrt(std::max({glm::dot(c[1] - c[0], c[1] - c[0]), glm::dot(c[2] - c[1], c[2] - c[1]),
                                                glm::dot(c[0] - c[2], c[0] - c[2])}));
      if (piece.depth >= kMaxHeadroomRefineDepth || !(longest > min_edge)) {
        dropped = true;
        continue;
      }
      split = true;
      // Midpoints as (a + b) * 0.5 are the same float for both triangles sharing an edge.
      const Vec3 m01 = (c[0] + c[1]) * 0.5f, m12 = (c[1] + c[2]) * 0.5f, m20 = (c[2] + c[0]) * 0.5f;
      const int d = piece.depth + 1;
      pieces.push_back({{c[0], m01, m20}, d});
      pieces.push_back({{m01, c[1], m12}, d});
      pieces.push_back({{m20, m12, c[2]}, d});
      pieces.push_back({{m01, m12, m20}, d});
    }
    refined += split ? 1 : 0;
    low_headroom += dropped ? 1 : 0;
  }
  if (walkable.triangles.empty()) {
    throw InvalidInput(name + ": no walkable triangles (" + std::to_string(too_steep) + " too steep, " +
                       std::to_string(degenerate) + " degenerate, " + std::to_string(low_headroom) +
                       " without headroom for the agent)");
  }
  WalkMesh mesh = build_walk_mesh(walkable, {up, kWalkWeldTolerance});
  mesh.stats_.input_triangles = level.triangles.size();
  mesh.stats_.too_steep_triangles = too_steep;
  mesh.stats_.degenerate_triangles += degenerate;
  mesh.stats_.low_headroom_triangles = low_headroom;
  mesh.stats_.headroom_refined_triangles = refined;
  return mesh;
}

}  // namespace collide
