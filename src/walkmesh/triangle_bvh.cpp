#include <collide/walkmesh/triangle_bvh.hpp>

#include <algorithm>
#include <numeric>

namespace collide {
namespace {

Aabb3 triangle_box(const std::array<Vec3, 3>& t) noexcept {
  return {glm::min(glm::min(t[0], t[1]), t[2]), glm::max(glm::max(t[0], t[1]), t[2])};
}

/// Squared distance from `p` to the closed box (0 inside). Ericson 5.1.3.1. Written out per axis:
/// it runs for every node a query visits.
inline float distance_squared(const Aabb3& box, Vec3 p) noexcept {
  const float dx = std::max(std::max(box.min.x - p.x, p.x - box.max.x), 0.0f);
  const float dy = std::max(std::max(box.min.y - p.y, p.y - box.max.y), 0.0f);
  const float dz = std::max(std::max(box.min.z - p.z, p.z - box.max.z), 0.0f);
  return dx * dx + dy * dy + dz * dz;
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
    // Binned surface area heuristic (Wald 2007): try kBvhBins - 1 planes on each axis, keep the
    // one minimising  area(left) * count(left) + area(right) * count(right).
    struct Bin {
      Aabb3 box{Vec3(std::numeric_limits<float>::max()), Vec3(-std::numeric_limits<float>::max())};
      std::uint32_t count = 0;
    };
    float best_cost = std::numeric_limits<float>::max();
    int best_axis = -1;
    float best_plane = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(spread[axis] > 0.0f)) continue;
      std::array<Bin, kBvhBins> bins{};
      const float scale = static_cast<float>(kBvhBins) / spread[axis];
      auto bin_of = [&](std::uint32_t tri) {
        const int b = static_cast<int>((centroids[tri][axis] - centroid_box.min[axis]) * scale);
        return std::clamp(b, 0, kBvhBins - 1);
      };
      for (std::uint32_t i = w.begin; i < w.end; ++i) {
        Bin& bin = bins[bin_of(order[i])];
        bin.box = merge(bin.box, triangle_box(corners[order[i]]));
        ++bin.count;
      }
      std::array<float, kBvhBins> right_cost{};
      Bin right;
      for (int b = kBvhBins - 1; b > 0; --b) {
        right.box = merge(right.box, bins[b].box);
        right.count += bins[b].count;
        right_cost[b] = right.count ? surface_metric(right.box) * static_cast<float>(right.count) : 0.0f;
      }
      Bin left;
      for (int b = 0; b < kBvhBins - 1; ++b) {
        left.box = merge(left.box, bins[b].box);
        left.count += bins[b].count;
        if (left.count == 0 || left.count == count) continue;
        const float cost = surface_metric(left.box) * static_cast<float>(left.count) + right_cost[b + 1];
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_plane = centroid_box.min[axis] + static_cast<float>(b + 1) / scale;
        }
      }
    }
    std::uint32_t mid = w.begin + count / 2;
    if (best_axis >= 0) {
      const auto split = std::partition(order.begin() + w.begin, order.begin() + w.end,
                                        [&](std::uint32_t tri) { return centroids[tri][best_axis] < best_plane; });
      mid = static_cast<std::uint32_t>(split - order.begin());
    }
    if (mid == w.begin || mid == w.end) {  // float edge case: fall back to a median split
      const int axis = spread.x >= spread.y ? (spread.x >= spread.z ? 0 : 2) : (spread.y >= spread.z ? 1 : 2);
      mid = w.begin + count / 2;
      std::nth_element(order.begin() + w.begin, order.begin() + mid, order.begin() + w.end,
                       [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    }
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
  struct Entry {
    std::uint32_t node;
    float distance_squared;  // from p to the node's box, computed once when pushed
  };
  std::array<Entry, kBvhStackSize> stack;
  int top = 0;
  stack[top++] = {0, distance_squared(nodes_[0].bounds, p)};
  while (top > 0) {
    const Entry entry = stack[--top];
    if (entry.distance_squared >= best.distance_squared) continue;  // cannot be strictly nearer
    const Node& node = nodes_[entry.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        if (distance_squared(leaf_bounds_[i], p) >= best.distance_squared) continue;
        const auto& t = corners_[i];
        const TrianglePoint q = closest_point_on_triangle(p, t[0], t[1], t[2]);
        const Vec3 d = q.point - p;
        const float d2 = glm::dot(d, d);
        if (d2 < best.distance_squared) {
          best = {ids_[i], q, d2};
        }
      }
      continue;
    }
    if (top + 2 > kBvhStackSize) continue;  // cannot happen for trees of sane depth (see kBvhStackSize)
    // Push the farther child first so the nearer one is searched first and tightens the bound.
    const Entry l{node.first, distance_squared(nodes_[node.first].bounds, p)};
    const Entry r{node.first + 1, distance_squared(nodes_[node.first + 1].bounds, p)};
    if (l.distance_squared <= r.distance_squared) {
      if (r.distance_squared < best.distance_squared) stack[top++] = r;
      stack[top++] = l;
    } else {
      if (l.distance_squared < best.distance_squared) stack[top++] = l;
      stack[top++] = r;
    }
  }
  return best;
}

}  // namespace collide
