// Queries and movement on a built walk mesh. Building and cleaning is in walk_mesh_build.cpp.
#include <collide/walkmesh/walk_mesh.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Weights clamped to >= 0 and scaled to sum 1 (float drift after a step).
Vec3 clean_weights(Vec3 w) noexcept {
  w = glm::max(w, Vec3(0.0f));
  const float sum = w.x + w.y + w.z;
  return sum > 0.0f ? w * (1.0f / sum) : Vec3(1.0f, 0.0f, 0.0f);
}

/// The rotation that takes unit normal n0 to unit normal n1 about the unit edge axis they share.
/// Half-angle form: q = (1 + n0.n1, n0 x n1) normalised; for opposite normals (a fold of 180
/// degrees) the axis is the edge itself.
glm::quat rotation_between(Vec3 n0, Vec3 n1, Vec3 edge_axis) noexcept {
  const float w = 1.0f + glm::dot(n0, n1);
  const Vec3 v = glm::cross(n0, n1);
  if (w <= kFoldBackTolerance) return {0.0f, edge_axis.x, edge_axis.y, edge_axis.z};
  return glm::normalize(glm::quat(w, v.x, v.y, v.z));
}

}  // namespace

int WalkMesh::local_edge(std::uint32_t t, std::uint32_t u, std::uint32_t v) const noexcept {
  const glm::uvec3 tri = triangles_[t];
  for (int e = 0; e < 3; ++e) {
    if (tri[e] == u && tri[(e + 1) % 3] == v) return e;
  }
  return -1;
}

Vec3 WalkMesh::to_world_point(const WalkPoint& p) const noexcept {
  const Vec3 local = p.weights.x * positions_[p.indices.x] + p.weights.y * positions_[p.indices.y] +
                     p.weights.z * positions_[p.indices.z];
  return origin_ + local;
}

Vec3 WalkMesh::to_world_triangle_normal(const WalkPoint& p) const noexcept {
  return triangle_normals_[p.triangle];
}

Vec3 WalkMesh::to_world_smooth_normal(const WalkPoint& p) const noexcept {
  const Vec3 n = p.weights.x * vertex_normals_[p.indices.x] + p.weights.y * vertex_normals_[p.indices.y] +
                 p.weights.z * vertex_normals_[p.indices.z];
  const float len = glm::length(n);
  return len > 0.0f ? n / len : triangle_normals_[p.triangle];
}

float WalkMesh::triangle_area(std::uint32_t t) const noexcept {
  const glm::uvec3 tri = triangles_[t];
  const Vec3 a = positions_[tri.x];
  return 0.5f * glm::length(glm::cross(positions_[tri.y] - a, positions_[tri.z] - a));
}

WalkPoint WalkMesh::nearest_walk_point(Vec3 world) const {
  if (!is_finite(world)) throw InvalidInput("nearest_walk_point: world point is not finite");
  if (triangles_.empty()) throw InvalidInput("nearest_walk_point: the walk mesh is empty");
  const BvhNearest hit = bvh_.nearest(world - origin_);
  if (hit.triangle >= triangles_.size()) {
    throw InvalidInput("nearest_walk_point: world point too far from the mesh (squared distance overflows float)");
  }
  return {triangles_[hit.triangle], clean_weights(hit.closest.weights), hit.triangle};
}

std::optional<WalkPoint> WalkMesh::nearest_walk_point(Vec3 world, float max_distance) const {
  if (!is_finite(world)) throw InvalidInput("nearest_walk_point: world point is not finite");
  if (!(max_distance >= 0.0f) || !std::isfinite(max_distance)) {
    throw InvalidInput("nearest_walk_point: max_distance must be finite and non-negative");
  }
  if (triangles_.empty()) throw InvalidInput("nearest_walk_point: the walk mesh is empty");
  const BvhNearest hit = bvh_.nearest(world - origin_, max_distance * max_distance);
  if (hit.triangle >= triangles_.size()) return std::nullopt;
  return WalkPoint{triangles_[hit.triangle], clean_weights(hit.closest.weights), hit.triangle};
}

WalkPoint WalkMesh::walk_point(std::uint32_t triangle, Vec3 weights) const {
  if (triangle >= triangles_.size()) {
    throw InvalidInput("walk_point: triangle " + std::to_string(triangle) + " out of range (" +
                       std::to_string(triangles_.size()) + " triangles)");
  }
  if (!is_finite(weights) || weights.x < 0.0f || weights.y < 0.0f || weights.z < 0.0f ||
      !(weights.x + weights.y + weights.z > 0.0f)) {
    throw InvalidInput("walk_point: weights must be finite, non-negative and of positive sum");
  }
  return {triangles_[triangle], weights / (weights.x + weights.y + weights.z), triangle};
}

bool WalkMesh::is_valid(const WalkPoint& p, float tolerance) const noexcept {
  if (p.triangle >= triangles_.size()) return false;
  const glm::uvec3 t = triangles_[p.triangle];
  const bool rotation = (p.indices == t) || (p.indices == glm::uvec3(t.y, t.z, t.x)) ||
                        (p.indices == glm::uvec3(t.z, t.x, t.y));
  if (!rotation || !is_finite(p.weights)) return false;
  const Vec3 w = p.weights;
  return w.x >= -tolerance && w.y >= -tolerance && w.z >= -tolerance &&
         std::fabs(w.x + w.y + w.z - 1.0f) <= tolerance;
}

// The step, a world vector, moves the weights at constant rates: the rate of corner a is the
// signed area swept against the opposite edge, dw_a = n.((c - b) x step) / |n|^2 = g_a.step with
// g_a = n x (c - b) / |n|^2 (the gradient of the barycentric weight, Ericson 3.4), precomputed per
// triangle. This projects the step onto the triangle's plane by itself. The point leaves through
// the edge opposite the first corner whose weight reaches zero.
namespace {
constexpr int kNext[5] = {0, 1, 2, 0, 1};  // (i + k) % 3 without dividing
}  // namespace

inline Vec3 WalkMesh::weight_rates(const WalkPoint& p, Vec3 step) const noexcept {
  const glm::uvec3 tri = triangles_[p.triangle];
  const int r = tri.x == p.indices.x ? 0 : (tri.y == p.indices.x ? 1 : 2);
  const std::array<Vec3, 3>& g = weight_gradients_[p.triangle];
  return {glm::dot(g[r], step), glm::dot(g[kNext[r + 1]], step), glm::dot(g[kNext[r + 2]], step)};
}

namespace {

/// The corner whose weight reaches zero first while the weights move by `rate` over time
/// [0, 1], and when; corner -1 when none does. Rates below kBarycentricRateTolerance of the
/// largest are zeroed first (in `rate`), so a step along an edge keeps the point on it. Ties (a
/// point on a vertex) go to the corner whose weight falls fastest: the edge crossed most directly.
struct FirstZero {
  int corner = -1;
  float time = 1.0f;
};
FirstZero first_zero(Vec3 w, Vec3& rate) noexcept {
  FirstZero out;
  const float largest = std::max({std::fabs(rate.x), std::fabs(rate.y), std::fabs(rate.z)});
  if (!(largest > 0.0f)) {  // no motion in the plane (or a NaN step)
    rate = Vec3(0.0f);
    return out;
  }
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(rate[k]) <= kBarycentricRateTolerance * largest) rate[k] = 0.0f;
  }
  for (int k = 0; k < 3; ++k) {
    if (rate[k] >= 0.0f || w[k] + rate[k] >= 0.0f) continue;  // stays >= 0 for the whole step
    const float t = std::max(w[k], 0.0f) / -rate[k];
    if (t < out.time || (t == out.time && out.corner >= 0 && rate[k] < rate[out.corner])) {
      out.time = t;
      out.corner = k;
    }
  }
  return out;
}

/// Rotation r of a walk point's indices against its stored triangle: indices[m] == tri[(m + r) % 3].
int rotation_of(const WalkPoint& p, glm::uvec3 tri) noexcept {
  return p.indices.x == tri.x ? 0 : (p.indices.x == tri.y ? 1 : 2);
}

}  // namespace

TriangleWalk WalkMesh::walk_in_triangle(const WalkPoint& start, Vec3 step) const noexcept {
  TriangleWalk out;
  out.end = start;
  if (!is_finite(step)) {
    out.time = 0.0f;
    return out;
  }
  Vec3 rate = weight_rates(start, step);
  const Vec3 moved = start.weights + rate;
  if (moved.x >= 0.0f && moved.y >= 0.0f && moved.z >= 0.0f) {  // the whole step stays inside
    out.end.weights = moved * (1.0f / (moved.x + moved.y + moved.z));
    return out;
  }
  const FirstZero hit = first_zero(start.weights, rate);
  if (hit.corner < 0) {
    out.end.weights = clean_weights(start.weights + rate);
    return out;
  }
  Vec3 w = start.weights + hit.time * rate;
  w[hit.corner] = 0.0f;
  w = clean_weights(w);
  // Rotate so the edge reached is (x, y) and the corner opposite it is z.
  const int i = kNext[hit.corner + 1];
  const int j = kNext[hit.corner + 2];
  out.end.indices = {start.indices[i], start.indices[j], start.indices[hit.corner]};
  out.end.weights = {w[i], w[j], 0.0f};
  out.time = hit.time;
  out.hit_edge = true;
  return out;
}

std::optional<EdgeCrossing> WalkMesh::cross_edge(const WalkPoint& start) const noexcept {
  if (start.weights.z != 0.0f || start.triangle >= triangles_.size()) return std::nullopt;
  const std::uint32_t x = start.indices.x;
  const std::uint32_t y = start.indices.y;
  // indices is a rotation of the stored triangle, so edge (x, y) is stored edge "where x is".
  const glm::uvec3 tri = triangles_[start.triangle];
  const int e = x == tri.x ? 0 : (x == tri.y ? 1 : (x == tri.z ? 2 : -1));
  if (e < 0 || tri[kNext[e + 1]] != y) return std::nullopt;
  const std::uint32_t next = neighbors_[start.triangle][e];
  if (next == kNoNeighbor) return std::nullopt;
  const int back = neighbor_edges_[start.triangle][e];  // (y, x) in the neighbour
  EdgeCrossing out;
  out.end.triangle = next;
  out.end.indices = {y, x, triangles_[next][kNext[back + 2]]};
  out.end.weights = {start.weights.y, start.weights.x, 0.0f};
  const Vec3 n0 = triangle_normals_[start.triangle];
  const Vec3 n1 = triangle_normals_[next];
  if (n0 != n1) out.rotation = rotation_between(n0, n1, glm::normalize(positions_[y] - positions_[x]));
  return out;
}

// The walk loop: walk in the current triangle; at an edge, cross it and rotate what is left of
// the step into the new triangle (so the step keeps its length over folds); at a boundary edge,
// keep only the step's component along the edge and slide. Two wall hits without progress in
// between mean a corner that absorbs the step.
WalkResult WalkMesh::walk(const WalkPoint& start, Vec3 step) const noexcept {
  WalkResult out;
  out.end = start;
  if (!is_finite(step)) {
    out.status = WalkStatus::invalid_step;
    return out;
  }
  const Vec3 n0 = triangle_normals_[start.triangle];
  Vec3 heading = step - glm::dot(step, n0) * n0;  // the whole step, tangent, carried along
  // The same steps as walk_in_triangle + cross_edge, written inline on (triangle, rotation,
  // weights): the edge reached and the neighbour's rotation follow from the stored edge
  // indices, with no searching and no edge-form copies.
  std::uint32_t t = start.triangle;
  int r = rotation_of(start, triangles_[t]);  // indices[m] == triangles_[t][(m + r) % 3]
  Vec3 w = start.weights;
  float heading_length = glm::length(heading);
  float left = 1.0f;                 // fraction of `heading` still to walk
  const float done_length = kWalkLengthTolerance * size_;
  bool wall_since_progress = false;  // a wall was reached and nothing was walked since
  int idle = 0;                      // iterations in a row that walked nothing
  int iteration = 0;
  for (; iteration < kMaxWalkIterations; ++iteration) {
    if (!(left * heading_length > done_length)) break;
    const Vec3 s = left * heading;
    const std::array<Vec3, 3>& g = weight_gradients_[t];
    Vec3 rate{glm::dot(g[r], s), glm::dot(g[kNext[r + 1]], s), glm::dot(g[kNext[r + 2]], s)};
    const Vec3 moved = w + rate;
    if (moved.x >= 0.0f && moved.y >= 0.0f && moved.z >= 0.0f) {  // the rest fits in this triangle
      w = moved * (1.0f / (moved.x + moved.y + moved.z));
      out.distance += left * heading_length;
      left = 0.0f;
      break;
    }
    const FirstZero hit = first_zero(w, rate);
    if (hit.corner < 0) {
      w = clean_weights(w + rate);
      out.distance += left * heading_length;
      left = 0.0f;
      break;
    }
    out.distance += hit.time * left * heading_length;
    Vec3 on_edge = w + hit.time * rate;
    on_edge[hit.corner] = 0.0f;
    w = clean_weights(on_edge);
    if (hit.time > 0.0f) {
      wall_since_progress = false;
      idle = 0;
    } else if (++idle > kMaxIdleIterations) {
      out.status = WalkStatus::blocked;  // circling a vertex without moving
      break;
    }
    left *= 1.0f - hit.time;
    // The edge reached runs from corner i to corner j: stored edge e of triangle t.
    const int i = kNext[hit.corner + 1];
    const int j = kNext[hit.corner + 2];
    const int e = kNext[i + r];
    const glm::uvec3 tri = triangles_[t];
    const std::uint32_t next = neighbors_[t][e];
    if (next != kNoNeighbor) {
      // Cross: the neighbour stores the edge as (y, x) at index `back`, so rotating its corners
      // by `back` gives indices (y, x, z') and weights (w_y, w_x, 0).
      const int back = neighbor_edges_[t][e];
      const Vec3 n_old = triangle_normals_[t];
      const Vec3 n_new = triangle_normals_[next];
      if (n_old != n_new) {  // a fold: turn the step over it, then remove drift off the new plane
        const Vec3 axis = glm::normalize(positions_[tri[kNext[e + 1]]] - positions_[tri[e]]);
        heading = rotation_between(n_old, n_new, axis) * heading;
        const Vec3 tangent = heading - glm::dot(heading, n_new) * n_new;
        const float tangent_length = glm::length(tangent);
        heading = tangent_length > 0.0f ? tangent * (heading_length / tangent_length) : tangent;
      }
      w = {w[j], w[i], 0.0f};
      t = next;
      r = back;
      ++out.edges_crossed;
      continue;
    }
    // A wall: slide along it. A second wall before any progress means the slide along the first
    // one points out of the mesh too: a corner, which absorbs the step.
    ++out.walls_hit;
    if (wall_since_progress) {
      out.status = WalkStatus::blocked;
      break;
    }
    wall_since_progress = true;
    const Vec3 along = glm::normalize(positions_[tri[kNext[e + 1]]] - positions_[tri[e]]);
    const float along_length = glm::dot(heading, along);
    if (!(std::fabs(along_length) > kWallSlideTolerance * heading_length)) {
      heading = Vec3(0.0f);
      out.status = WalkStatus::blocked;  // walked (almost) straight into the wall
      break;
    }
    heading = along_length * along;
    heading_length = std::fabs(along_length);
  }
  if (iteration == kMaxWalkIterations) out.status = WalkStatus::iteration_limit;
  const glm::uvec3 tri = triangles_[t];
  out.end = {{tri[r], tri[kNext[r + 1]], tri[kNext[r + 2]]}, w, t};
  out.end_step = heading;
  return out;
}

}  // namespace collide
