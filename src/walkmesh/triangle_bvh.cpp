#include <collide/walkmesh/triangle_bvh.hpp>

#include <algorithm>
#include <numeric>

namespace collide {
namespace {

Aabb3 triangle_box(const std::array<Vec3, 3>& t) noexcept {
  return {glm::min(glm::min(t[0], t[1]), t[2]), glm::max(glm::max(t[0], t[1]), t[2])};
}

/// Squared distance from `p` to the closed box (0 inside). Ericson 5.1.3.1.
float distance_squared(const Aabb3& box, Vec3 p) noexcept {
  const Vec3 d = glm::max(glm::max(box.min - p, p - box.max), Vec3(0.0f));
  return glm::dot(d, d);
}

}  // namespace

TriangleBvh::TriangleBvh(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles) {
  const std::size_t n = triangles.size();
  if (n == 0) return;
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::array<Vec3, 3>> corners(n);
  std::vector<Vec3> centroids(n);
  for (std::size_t i = 0; i < n; ++i) {
    corners[i] = {positions[triangles[i].x], positions[triangles[i].y], positions[triangles[i].z]};
    centroids[i] = (corners[i][0] + corners[i][1] + corners[i][2]) * (1.0f / 3.0f);
  }

  // Top-down build with an explicit work list: node index and its range of `order`.
  struct Work {
    std::uint32_t node, begin, end;
  };
  std::vector<Work> work;
  nodes_.reserve(2 * n / kBvhLeafTriangles + 1);
  nodes_.push_back({});
  work.push_back({0, 0, static_cast<std::uint32_t>(n)});
  while (!work.empty()) {
    const Work w = work.back();
    work.pop_back();
    Aabb3 box = triangle_box(corners[order[w.begin]]);
    Aabb3 centroid_box{centroids[order[w.begin]], centroids[order[w.begin]]};
    for (std::uint32_t i = w.begin + 1; i < w.end; ++i) {
      box = merge(box, triangle_box(corners[order[i]]));
      centroid_box = merge(centroid_box, Aabb3{centroids[order[i]], centroids[order[i]]});
    }
    nodes_[w.node].bounds = box;
    const std::uint32_t count = w.end - w.begin;
    const Vec3 spread = centroid_box.size();
    if (count <= kBvhLeafTriangles || (spread.x <= 0.0f && spread.y <= 0.0f && spread.z <= 0.0f)) {
      nodes_[w.node].first = w.begin;  // slots are assigned in `order` order below
      nodes_[w.node].count = count;
      continue;
    }
    const int axis = spread.x >= spread.y ? (spread.x >= spread.z ? 0 : 2) : (spread.y >= spread.z ? 1 : 2);
    const std::uint32_t mid = w.begin + count / 2;
    std::nth_element(order.begin() + w.begin, order.begin() + mid, order.begin() + w.end,
                     [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back({});
    nodes_.push_back({});
    nodes_[w.node].first = left;
    nodes_[w.node].count = 0;
    work.push_back({left + 1, mid, w.end});
    work.push_back({left, w.begin, mid});
  }

  ids_ = order;
  corners_.resize(n);
  leaf_bounds_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    corners_[i] = corners[order[i]];
    leaf_bounds_[i] = triangle_box(corners_[i]);
  }
}

BvhNearest TriangleBvh::nearest(Vec3 p) const noexcept {
  BvhNearest best;
  if (nodes_.empty()) return best;
  std::array<std::uint32_t, kBvhStackSize> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (distance_squared(node.bounds, p) > best.distance_squared) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (distance_squared(leaf_bounds_[i], p) > best.distance_squared) continue;
        const auto& t = corners_[i];
        const TrianglePoint q = closest_point_on_triangle(p, t[0], t[1], t[2]);
        const Vec3 d = q.point - p;
        const float d2 = glm::dot(d, d);
        if (d2 < best.distance_squared || (d2 == best.distance_squared && ids_[i] < best.triangle)) {
          best = {ids_[i], q, d2};
        }
      }
      continue;
    }
    if (top + 2 > kBvhStackSize) continue;  // cannot happen for median-split trees (see kBvhStackSize)
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    const std::uint32_t l = node.first;
    const std::uint32_t r = node.first + 1;
    const float dl = distance_squared(nodes_[l].bounds, p);
    const float dr = distance_squared(nodes_[r].bounds, p);
    if (dl <= dr) {
      stack[top++] = r;
      stack[top++] = l;
    } else {
      stack[top++] = l;
      stack[top++] = r;
    }
  }
  return best;
}

}  // namespace collide
