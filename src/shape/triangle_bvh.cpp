#include <collide/shape/triangle_bvh.hpp>

#include "watertight_ray.hpp"

#include <collide/core/config.hpp>
#include <collide/core/error.hpp>
#include <collide/core/lanes.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

namespace collide {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

Aabb3 triangle_box(const std::array<Vec3, 3>& t) noexcept {
  return {glm::min(glm::min(t[0], t[1]), t[2]), glm::max(glm::max(t[0], t[1]), t[2])};
}

/// A node of the binary tree the build makes first.
struct BinaryNode {
  Aabb3 bounds;
  std::uint32_t first = 0;  ///< leaf: first slot of `order`; inner: index of the left child (right is next)
  std::uint32_t count = 0;  ///< leaf: number of triangles (1..kBvhLeafTriangles); inner: 0
};

/// A box as two lanes (x, y, z and a copy of x), for the build's merges: simd::min(b, a) and
/// simd::max(b, a) are glm::min(a, b) and glm::max(a, b) lane by lane (the same comparisons,
/// the same operand on ties and NaN), so merge() here gives merge()'s floats.
struct BoxLanes {
  simd::Lanes lo, hi;
};
inline BoxLanes box_lanes(const Aabb3& b) noexcept {
  return {simd::lanes(b.min.x, b.min.y, b.min.z, b.min.x), simd::lanes(b.max.x, b.max.y, b.max.z, b.max.x)};
}
inline BoxLanes merge(const BoxLanes& a, const BoxLanes& b) noexcept {
  return {simd::min(b.lo, a.lo), simd::max(b.hi, a.hi)};
}
inline Aabb3 to_aabb(const BoxLanes& b) noexcept {
  std::array<float, 4> lo, hi;
  simd::store(lo.data(), b.lo);
  simd::store(hi.data(), b.hi);
  return {Vec3(lo[0], lo[1], lo[2]), Vec3(hi[0], hi[1], hi[2])};
}

/// surface_metric() of the box's Aabb3 (to_aabb), the same floats: 2 (x y + y z + z x) of its
/// extents, in that order.
inline float box_metric(const BoxLanes& b) noexcept {
  std::array<float, 4> d;
  simd::store(d.data(), b.hi - b.lo);
  return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/// Nodes of at most this many triangles fill and sweep only the bins their triangles fall in
/// (build_binary; the same planes): on FCL's env.obj the mesh build 14% faster, dungeon.obj 5%,
/// undulating.obj 7% (8 and 32 measured too: 16 the best on all three).
constexpr std::uint32_t kFewTriangles = 16;
static_assert(kBvhBins <= 32, "a node's full bins are the bits of one 32-bit word");
static_assert(kBvhBins % 4 == 0, "the sweeps' costs are worked out four bins at a time");

/// Lanes of bin positions b (a centroid's offset from the node's least centroid times the bins
/// per unit) as bin indices: b >= 1 ? (b < kBvhBins ? int(b) : kBvhBins - 1) : 0, a NaN to 0.
inline std::array<int, 4> bin_indices(simd::Lanes b) noexcept {
  const simd::Lanes last = simd::splat(static_cast<float>(kBvhBins - 1));
  const simd::Lanes clamped = simd::select(b >= simd::splat(1.0f),
                                           simd::select(b < simd::splat(static_cast<float>(kBvhBins)), b, last),
                                           simd::splat(0.0f));
  std::array<int, 4> out;
#if defined(__GNUC__) || defined(__clang__)
  using Ints = std::int32_t __attribute__((vector_size(16)));
  const Ints whole = __builtin_convertvector(clamped, Ints);  // truncation, as static_cast<int>
  std::memcpy(out.data(), &whole, sizeof out);
#else
  for (int k = 0; k < 4; ++k) out[k] = static_cast<int>(clamped[k]);
#endif
  return out;
}

/// Top-down binary build. Every node of more than kBvhLeafTriangles triangles is split: at the
/// best of kBvhBins - 1 planes per axis by the binned surface area heuristic (Wald 2007), cost
///   area(left) * count(left) + area(right) * count(right),
/// or at the median of the longest centroid axis when SAH has no valid plane (all centroids in
/// one bin, equal centroids) or the node is kBvhMaxSahDepth deep (which bounds the depth).
/// `order` comes out permuted so that each leaf's triangles are a contiguous range.
/// Centroids are box centres (halves added: finite for any finite corners, where the mean of
/// three corners near 3.4e38 overflows), a NaN coordinate (from non-finite input) counts as
/// +inf, and bins are chosen without converting a NaN or infinity to int: so the sort order is a
/// strict weak one and the median split always halves, whatever the input.
std::vector<BinaryNode> build_binary(const std::vector<std::array<Vec3, 3>>& corners, std::vector<std::uint32_t>& order) {
  const std::size_t n = corners.size();
  // Each triangle's box once, in lanes: every level's bounds and bins merge them (made again
  // from the corners there, four times a level, they were a fifth of the build; merged as
  // Vec3s, the bins' and sweeps' merges were a third of the rest).
  // The centroids in lanes too (x, y, z and x again): a node's centroid bounds and all three
  // axes' bins are worked out a triangle at a time in lanes.
  std::vector<BoxLanes> boxes(n);
  std::vector<simd::Lanes> centroids(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Aabb3 box = triangle_box(corners[i]);
    boxes[i] = box_lanes(box);
    Vec3 centroid = 0.5f * box.min + 0.5f * box.max;
    for (int axis = 0; axis < 3; ++axis) {
      if (std::isnan(centroid[axis])) centroid[axis] = kInfinity;
    }
    centroids[i] = simd::lanes(centroid.x, centroid.y, centroid.z, centroid.x);
  }
  order.resize(n);
  std::iota(order.begin(), order.end(), 0u);

  struct Work {
    std::uint32_t node, begin, end;
    int depth;
  };
  struct Bin {
    BoxLanes box{simd::splat(std::numeric_limits<float>::max()), simd::splat(-std::numeric_limits<float>::max())};
    std::uint32_t count = 0;
  };
  // An axis's swept boxes by bin (bins b..last on the right, 0..b on the left): their extents
  // (x, y, z and x again, as BoxLanes) and their costs' factor, packets(count) (0 for no
  // triangle), a slot per bin; the slot a side has no box for (the right's first, the left's
  // last) is empty (`clear`), and so is the right's slot past the last bin, which the left's
  // last group of four reads.
  struct Sweep {
    std::array<simd::Lanes, kBvhBins> extent;
    std::array<float, kBvhBins + 1> packets;
    void clear(int b) noexcept {
      extent[static_cast<std::size_t>(b)] = simd::splat(0.0f);
      packets[static_cast<std::size_t>(b)] = 0.0f;
    }
  };
  // box_metric() of the swept boxes at bins b..b+3, the same floats.
  auto sweep_metrics = [](const Sweep& sweep, int b) noexcept {
    simd::Lanes x = sweep.extent[b], y = sweep.extent[b + 1], z = sweep.extent[b + 2], x_again = sweep.extent[b + 3];
    simd::transpose(x, y, z, x_again);
    return simd::splat(2.0f) * (x * y + y * z + z * x);
  };
  std::vector<BinaryNode> nodes;
  std::vector<Work> work;
  nodes.reserve(2 * n);
  nodes.push_back({});
  work.push_back({0, 0, static_cast<std::uint32_t>(n), 0});
  while (!work.empty()) {
    const Work w = work.back();
    work.pop_back();
    BoxLanes box = boxes[order[w.begin]];
    BoxLanes centroid_lanes{centroids[order[w.begin]], centroids[order[w.begin]]};
    for (std::uint32_t i = w.begin + 1; i < w.end; ++i) {
      box = merge(box, boxes[order[i]]);
      centroid_lanes = merge(centroid_lanes, BoxLanes{centroids[order[i]], centroids[order[i]]});
    }
    nodes[w.node].bounds = to_aabb(box);
    const Aabb3 centroid_box = to_aabb(centroid_lanes);
    const std::uint32_t count = w.end - w.begin;
    if (count <= kBvhLeafTriangles) {
      nodes[w.node].first = w.begin;
      nodes[w.node].count = count;
      continue;
    }
    const Vec3 spread = centroid_box.size();
    // A leaf's triangles are tested four at a time, so a side costs its count in packets.
    auto packets = [](std::uint32_t c) { return static_cast<float>((c + kBvhLeafTriangles - 1) / kBvhLeafTriangles); };
    float best_cost = std::numeric_limits<float>::max();
    int best_axis = -1;
    float best_plane = 0.0f;
    std::array<bool, 3> binned{};
    std::array<float, 3> scale{};
    for (int axis = 0; axis < 3; ++axis) {
      binned[axis] = w.depth < kBvhMaxSahDepth && spread[axis] > 0.0f;
      scale[axis] = binned[axis] ? static_cast<float>(kBvhBins) / spread[axis] : 0.0f;
    }
    // A triangle's bin on each axis: b = (centroid - min) * scale, then b >= 1 ? (b < kBvhBins ?
    // int(b) : kBvhBins - 1) : 0 (NaN goes to bin 0), the three axes in lanes.
    const simd::Lanes bin_origin = centroid_lanes.lo;
    const simd::Lanes bin_scale = simd::lanes(scale[0], scale[1], scale[2], 0.0f);
    // The plane after bin b of `axis`, of cost `cost`, offered in the sweeps' order (axes, then
    // bins ascending): the first of the least costs is kept.
    const auto offer = [&](float cost, int axis, int b) {
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_plane = centroid_box.min[axis] + static_cast<float>(b + 1) / scale[axis];
      }
    };
    if (count <= kFewTriangles) {
      // Few triangles: most bins would be empty, and filling and sweeping all of them would
      // cost more than the triangles do. Only the bins they fall in are filled (a bit each) and
      // swept: a plane after an empty bin has the sides (so the cost) of the plane after the last
      // full bin before it, and the first of equal costs is kept, so only the planes after full
      // bins count.
      std::array<std::array<int, 4>, kFewTriangles> bin_of;
      for (std::uint32_t i = 0; i < count; ++i) {
        bin_of[i] = bin_indices((centroids[order[w.begin + i]] - bin_origin) * bin_scale);
      }
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[axis]) continue;
        std::array<Bin, kBvhBins> axis_bins;  // only the bins of `full` are merged into and read
        std::uint32_t full = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
          const BoxLanes& tri_box = boxes[order[w.begin + i]];
          const int b = bin_of[i][axis];
          const std::uint32_t bit = std::uint32_t{1} << b;
          if (full & bit) {
            axis_bins[b].box = merge(axis_bins[b].box, tri_box);
            ++axis_bins[b].count;
          } else {
            axis_bins[b] = {tri_box, 1};
            full |= bit;
          }
        }
        std::array<Bin, kBvhBins> right;  // right[b], b full: bins b..last
        Bin sum;
        for (std::uint32_t m = full; m != 0;) {
          const int b = std::bit_width(m) - 1;
          m &= ~(std::uint32_t{1} << b);
          sum.box = merge(sum.box, axis_bins[b].box);
          sum.count += axis_bins[b].count;
          right[b] = sum;
        }
        Bin left;
        for (std::uint32_t m = full; m != 0;) {
          const int b = std::countr_zero(m);
          m &= m - 1;
          if (m == 0) break;  // the last full bin: nothing on the right
          left.box = merge(left.box, axis_bins[b].box);
          left.count += axis_bins[b].count;
          const Bin& r = right[std::countr_zero(m)];
          offer(box_metric(left.box) * packets(left.count) + box_metric(r.box) * packets(r.count), axis, b);
        }
      }
    } else if (binned[0] || binned[1] || binned[2]) {
      // The three axes' bins filled in one pass over the node's triangles.
      std::array<std::array<Bin, kBvhBins>, 3> bins{};
      for (std::uint32_t i = w.begin; i < w.end; ++i) {
        const std::uint32_t tri = order[i];
        const std::array<int, 4> bin_of = bin_indices((centroids[tri] - bin_origin) * bin_scale);
        for (int axis = 0; axis < 3; ++axis) {
          if (!binned[axis]) continue;
          Bin& bin = bins[axis][bin_of[axis]];
          bin.box = merge(bin.box, boxes[tri]);
          ++bin.count;
        }
      }
      for (int axis = 0; axis < 3; ++axis) {
        if (!binned[axis]) continue;
        const std::array<Bin, kBvhBins>& axis_bins = bins[axis];
        // The swept boxes are merged one bin at a time; their costs are worked out after, four
        // bins at a time in lanes (one after each merge, the metric's scalar steps and the
        // count's conversion were half the sweeps' time): box_metric(box) * packets(count), the
        // same floats. A left side of every triangle leaves the right side empty.
        Sweep right_sweep, left_sweep;
        Bin right;
        for (int b = kBvhBins - 1; b > 0; --b) {
          right.box = merge(right.box, axis_bins[b].box);
          right.count += axis_bins[b].count;
          right_sweep.extent[b] = right.box.hi - right.box.lo;
          right_sweep.packets[b] = packets(right.count);
        }
        Bin left;
        for (int b = 0; b < kBvhBins - 1; ++b) {
          left.box = merge(left.box, axis_bins[b].box);
          left.count += axis_bins[b].count;
          left_sweep.extent[b] = left.box.hi - left.box.lo;
          left_sweep.packets[b] = packets(left.count);
        }
        right_sweep.clear(0);
        right_sweep.packets[kBvhBins] = 0.0f;
        left_sweep.clear(kBvhBins - 1);
        std::array<float, kBvhBins + 1> right_cost;  // the last: no bin past the last one
        std::array<float, kBvhBins> cost;
        const simd::Lanes zero = simd::splat(0.0f);
        for (int b = 0; b < kBvhBins; b += 4) {
          const simd::Lanes p = simd::load(&right_sweep.packets[b]);
          simd::store(&right_cost[b], simd::select(p > zero, sweep_metrics(right_sweep, b) * p, zero));
        }
        right_cost[kBvhBins] = 0.0f;
        for (int b = 0; b < kBvhBins; b += 4) {  // a side with no triangle is no split: never below best_cost
          const simd::Lanes p = simd::load(&left_sweep.packets[b]);
          const simd::LaneMask split = (p > zero) & (simd::load(&right_sweep.packets[b + 1]) > zero);
          simd::store(&cost[b], simd::select(split, sweep_metrics(left_sweep, b) * p + simd::load(&right_cost[b + 1]),
                                             simd::splat(kInfinity)));
        }
        for (int b = 0; b < kBvhBins - 1; ++b) offer(cost[b], axis, b);
      }
    }
    std::uint32_t mid = w.begin;
    if (best_axis >= 0) {
      const auto split = std::partition(order.begin() + w.begin, order.begin() + w.end,
                                        [&](std::uint32_t tri) { return centroids[tri][best_axis] < best_plane; });
      mid = static_cast<std::uint32_t>(split - order.begin());
    }
    if (mid == w.begin || mid == w.end) {  // no SAH plane (or a float edge case): median split
      const int axis = spread.x >= spread.y ? (spread.x >= spread.z ? 0 : 2) : (spread.y >= spread.z ? 1 : 2);
      mid = w.begin + count / 2;
      std::nth_element(order.begin() + w.begin, order.begin() + mid, order.begin() + w.end,
                       [&](std::uint32_t a, std::uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
    }
    const auto left = static_cast<std::uint32_t>(nodes.size());
    nodes.push_back({});
    nodes.push_back({});
    nodes[w.node].first = left;
    nodes[w.node].count = 0;
    work.push_back({left + 1, mid, w.end, w.depth + 1});
    work.push_back({left, w.begin, mid, w.depth + 1});
  }
  return nodes;
}

// Four lanes of float (collide/core/lanes.hpp): the packets below are four triangles or boxes.
using namespace simd;

/// A 3D vector of lanes: four points or directions at once.
struct Vec3Lanes {
  Lanes x, y, z;
};
inline Vec3Lanes operator-(const Vec3Lanes& a, const Vec3Lanes& b) noexcept { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3Lanes operator*(Lanes s, const Vec3Lanes& a) noexcept { return {s * a.x, s * a.y, s * a.z}; }
inline Lanes dot(const Vec3Lanes& a, const Vec3Lanes& b) noexcept { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3Lanes cross(const Vec3Lanes& a, const Vec3Lanes& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Edge lengths squared at or below this count as zero in the segment distance (the parameter
/// along a zero-length edge is then 0: the distance to its one point). The smallest normal float.
constexpr float kMinEdgeLengthSquared = std::numeric_limits<float>::min();

/// Corners of four triangles as lanes: [corner][axis][lane].
using CornerLanes = std::array<std::array<std::array<float, 4>, 3>, 3>;
/// Four triangles' normals as lanes: [axis][lane] (TriangleBvh's normals_).
using NormalLanes = std::array<std::array<float, 4>, 3>;

/// Four triangles prepared for the squared distances of points (a leaf packet): what depends on
/// the triangles alone, worked out once for all the points of a batch that reach the leaf (up to
/// kBvhNearestBatch): per triangle (a, b, c) its edges, their reciprocal squared lengths, its
/// unit normal n, and the in-plane inward normals of the edges (n x (v - u) for the edge
/// u -> v). A point's distance then needs no division and no cross product; before, each point
/// made them again (four divisions and four cross products a point and packet). The unit
/// normals come made (TriangleBvh's normals_, in double, then rounded): made here in float, a
/// sliver's turned by FLT_EPSILON times its length over width and the search took it for
/// nearer or farther than it is, and a triangle of area below about 1e-19 (|n|^2 below the
/// smallest float) had no face. closest_point_on_triangle, which gives the winner's point,
/// works in double too, so the two agree within rounding on any triangle.
struct TriangleLanes {
  Vec3Lanes a, b, c, ab, bc, ca, n, in_ab, in_bc, in_ca;
  Lanes inv_ab, inv_bc, inv_ca;
  LaneMask has_face;

  TriangleLanes(const CornerLanes& t, const NormalLanes& normal) noexcept
      : a{load(t[0][0]), load(t[0][1]), load(t[0][2])},
        b{load(t[1][0]), load(t[1][1]), load(t[1][2])},
        c{load(t[2][0]), load(t[2][1]), load(t[2][2])},
        n{load(normal[0]), load(normal[1]), load(normal[2])} {
    ab = b - a, bc = c - b, ca = a - c;
    const Lanes one = splat(1.0f);
    // A face where the normal is a unit vector (zero: corners collinear or equal, no face).
    has_face = dot(n, n) > splat(0.5f);
    // Edge lengths squared at or below kMinEdgeLengthSquared count as zero: the parameter along
    // a zero-length edge is then 0, the distance to its one point.
    const Lanes min_edge = splat(kMinEdgeLengthSquared);
    inv_ab = one / max(dot(ab, ab), min_edge);
    inv_bc = one / max(dot(bc, bc), min_edge);
    inv_ca = one / max(dot(ca, ca), min_edge);
    in_ab = cross(n, ab), in_bc = cross(n, bc), in_ca = cross(n, ca);
  }

  /// Exact squared distance from p to each of the four closed triangles, without branches. Per
  /// lane: if the triangle has a face (a unit normal n) and p projects into it, (p - u) .
  /// (n x (v - u)) >= 0 for every edge u -> v, the distance is to the plane, d^2 = ((p - a) .
  /// n)^2; otherwise the nearest point lies on the boundary, d^2 = the least over the
  /// three edges of the squared distance to the segment (the parameter clamped to [0, 1]). (The
  /// Voronoi regions of Ericson 5.1.5 in another grouping: the face region is where all three
  /// edge tests pass; every other region's nearest point is on an edge or at a vertex, and the
  /// nearest of the three clamped segment points is it.)
  [[nodiscard]] Lanes distance_squared(const Vec3Lanes& p) const noexcept {
    const Vec3Lanes ap = p - a, bp = p - b, cp = p - c;
    const Lanes zero = splat(0.0f), one = splat(1.0f);
    const LaneMask inside = has_face & (dot(ap, in_ab) >= zero) & (dot(bp, in_bc) >= zero) & (dot(cp, in_ca) >= zero);
    const Lanes height = dot(ap, n);
    const Lanes plane = height * height;
    const auto segment = [&](const Vec3Lanes& w, const Vec3Lanes& e, Lanes inv_ee) {
      const Lanes t = min(max(dot(w, e) * inv_ee, zero), one);
      const Vec3Lanes d = w - t * e;
      return dot(d, d);
    };
    const Lanes edges = min(min(segment(ap, ab, inv_ab), segment(bp, bc, inv_bc)), segment(cp, ca, inv_ca));
    return select(inside, plane, edges);
  }
};

}  // namespace

TriangleBvh::TriangleBvh(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles) {
  const std::size_t n = triangles.size();
  triangle_count_ = n;
  if (n == 0) return;
  std::vector<std::array<Vec3, 3>> corners(n);
  for (std::size_t i = 0; i < n; ++i) {
    corners[i] = {positions[triangles[i].x], positions[triangles[i].y], positions[triangles[i].z]};
  }
  std::vector<std::uint32_t> order;
  const std::vector<BinaryNode> binary = build_binary(corners, order);
  bounds_ = binary[0].bounds;

  // Collapse to four-wide nodes: a node takes its binary node's two children, then repeatedly
  // replaces its inner child of largest surface area by that child's two children, up to four.
  // Nodes and packets are numbered depth first, so a subtree is contiguous in memory.
  nodes_.reserve(binary.size() / 2 + 1);
  packets_.reserve(binary.size() / 2 + 1);
  normals_.reserve(binary.size() / 2 + 1);
  struct Work {
    std::uint32_t binary, node;  // binary node to collapse into wide node `node`
  };
  std::vector<Work> work{{0, 0}};
  nodes_.push_back({});
  while (!work.empty()) {
    const Work w = work.back();
    work.pop_back();
    std::array<std::uint32_t, kBvhWidth> children{};
    int count = 0;
    if (binary[w.binary].count > 0) {
      children[count++] = w.binary;  // a root that is one leaf
    } else {
      children[count++] = binary[w.binary].first;
      children[count++] = binary[w.binary].first + 1;
    }
    while (count < kBvhWidth) {
      int open = -1;
      float open_area = -1.0f;
      for (int k = 0; k < count; ++k) {
        const BinaryNode& c = binary[children[k]];
        if (c.count == 0 && surface_metric(c.bounds) > open_area) {
          open = k;
          open_area = surface_metric(c.bounds);
        }
      }
      if (open < 0) break;
      const std::uint32_t left = binary[children[open]].first;
      children[open] = left;
      children[count++] = left + 1;
    }
    Node node;
    for (int row = 0; row < 6; ++row) node.box[row].fill(row < 3 ? kInfinity : -kInfinity);
    node.child.fill(kEmpty);
    node.count.fill(0);
    std::array<std::uint32_t, kBvhWidth> pending{};
    int pending_count = 0;
    for (int k = 0; k < count; ++k) {
      const BinaryNode& c = binary[children[k]];
      for (int axis = 0; axis < 3; ++axis) {
        node.box[kMinX + axis][k] = c.bounds.min[axis];
        node.box[kMaxX + axis][k] = c.bounds.max[axis];
      }
      if (c.count > 0) {
        Packet packet;
        std::uint32_t slivers = 0;
        for (std::uint32_t lane = 0; lane < kBvhLeafTriangles; ++lane) {
          const std::uint32_t slot = c.first + std::min(lane, c.count - 1);  // repeat the last one
          for (int v = 0; v < 3; ++v) {
            for (int axis = 0; axis < 3; ++axis) packet.corners[v][axis][lane] = corners[order[slot]][v][axis];
          }
          packet.id[lane] = order[slot];
          const auto& tri = corners[order[slot]];
          if (lane < c.count && detail::is_sliver(tri[0], tri[1], tri[2])) slivers |= 1u << lane;
        }
        if (packets_.size() >= kPacketMask) {
          throw InvalidInput("triangle mesh: " + std::to_string(n) + " triangles: more than the BVH holds");
        }
        node.child[k] = kLeaf | slivers << kSliverShift | static_cast<std::uint32_t>(packets_.size());
        node.count[k] = c.count;
        packets_.push_back(packet);
        PacketNormals& normal = normals_.emplace_back();
        for (std::uint32_t lane = 0; lane < kBvhLeafTriangles; ++lane) {
          if (lane >= c.count) {  // (an unused lane repeats the last triangle)
            for (int axis = 0; axis < 3; ++axis) normal[axis][lane] = normal[axis][lane - 1];
            continue;
          }
          const Vec3 unit = triangle_normal(packet.corner(0, lane), packet.corner(1, lane), packet.corner(2, lane));
          for (int axis = 0; axis < 3; ++axis) normal[axis][lane] = unit[axis];
        }
      } else {
        node.child[k] = static_cast<std::uint32_t>(nodes_.size() + pending_count);
        pending[pending_count++] = children[k];
      }
    }
    nodes_[w.node] = node;
    // Reserve the inner children's nodes now (contiguous siblings); build them depth first.
    const auto first_child = static_cast<std::uint32_t>(nodes_.size());
    nodes_.resize(nodes_.size() + pending_count);
    for (int k = pending_count - 1; k >= 0; --k) work.push_back({pending[k], first_child + k});
  }
}

namespace {

/// A search's nearest triangle so far: its squared distance (strictly below which a candidate
/// must be) and where it is.
struct NearestSoFar {
  float distance_squared;
  std::uint32_t packet = 0;
  int lane = -1;  ///< -1: none yet
};

/// The first NearestSoFar of a search bounded by `max_distance_squared` (inclusive): the next
/// float above the bound admits exactly the distances at or below it (std::nextafter(bound,
/// inf) for bounds >= 0, without the library call; +inf and NaN stay as they are, -0 counts as 0).
inline NearestSoFar nearest_start(float max_distance_squared) noexcept {
  const float bound = max_distance_squared + 0.0f;
  return {bound < kInfinity ? std::bit_cast<float>(std::bit_cast<std::uint32_t>(bound) + 1u) : bound};
}

/// A leaf packet's four squared distances `d2` offered to `best`: the lowest lane at the minimum
/// wins (as a scan in lane order) when strictly nearer.
inline void offer_packet(Lanes d2, std::uint32_t packet, NearestSoFar& best) noexcept {
  const Lanes nearest = horizontal_min(d2);
  const unsigned at_minimum = lane_bits(d2 == nearest);
  if (at_minimum != 0 && nearest[0] < best.distance_squared) {
    best = {nearest[0], packet, std::countr_zero(at_minimum)};
  } else if (at_minimum == 0) {
    // A NaN distance (corners beyond kFiniteQueryRange overflow) makes the minimum disagree
    // with every lane, and countr_zero(0) = 32 read past the packet (found by fuzz_shapes):
    // scan the lanes instead, NaN never winning.
    std::array<float, kBvhWidth> d;
    std::memcpy(d.data(), &d2, sizeof d);
    for (int k = 0; k < kBvhWidth; ++k) {
      if (d[k] < best.distance_squared) best = {d[k], packet, k};  // (unused lanes repeat the last triangle)
    }
  }
}

/// Squared distances from the box [lo, hi] (lanes of one point each, or of a box) to four boxes
/// (Ericson 5.1.3.1 per axis: d = max(min - hi, lo - max, 0); distance^2 = dx^2 + dy^2 + dz^2;
/// for a point lo = hi = p).
inline Lanes box_distance_squared(const TriangleBvh::Node& node, const Vec3Lanes& lo, const Vec3Lanes& hi) noexcept {
  using B = TriangleBvh;
  const Lanes zero = splat(0.0f);
  const Lanes dx = max(max(load(node.box[B::kMinX]) - hi.x, lo.x - load(node.box[B::kMaxX])), zero);
  const Lanes dy = max(max(load(node.box[B::kMinY]) - hi.y, lo.y - load(node.box[B::kMaxY])), zero);
  const Lanes dz = max(max(load(node.box[B::kMinZ]) - hi.z, lo.z - load(node.box[B::kMaxZ])), zero);
  return dx * dx + dy * dy + dz * dz;
}

/// The nearest child among `open` by `d2` (lowest slot among equals) is returned, to be searched
/// next; the other open children are pushed with their distances without branches: each slot is
/// written, and kept if its bit is set. (A NaN distance, from non-finite corners, can leave no
/// open lane at the minimum: then the lowest open slot, never an out-of-range one.)
template <class Entry, std::size_t N>
inline std::uint32_t descend(const TriangleBvh::Node& node, Lanes d2, unsigned open, std::array<Entry, N>& stack,
                             int& top) noexcept {
  const unsigned at_minimum = lane_bits(d2 == horizontal_min(d2)) & open;
  const int nearest = std::countr_zero(at_minimum != 0 ? at_minimum : open);
  const unsigned rest = open & ~(1u << nearest);
  std::array<float, kBvhWidth> d;
  std::memcpy(d.data(), &d2, sizeof d);
  for (int k = 0; k < kBvhWidth; ++k) {
    stack[top] = {node.child[k], d[k]};
    top += static_cast<int>((rest >> k) & 1u);
  }
  return node.child[nearest];
}

/// A search's result from its nearest triangle so far: the nearest point and weights by the
/// region test, the distance recomputed from that point.
COLLIDE_ALWAYS_INLINE BvhNearest nearest_result(const TriangleBvh::Packet& packet, int lane, Vec3 p) noexcept {
  BvhNearest out;
  const auto l = static_cast<std::uint32_t>(lane);
  out.triangle = packet.id[l];
  out.closest = closest_point_on_triangle(p, packet.corner(0, l), packet.corner(1, l), packet.corner(2, l));
  const Vec3 d = out.closest.point - p;
  out.distance_squared = glm::dot(d, d);
  return out;
}

/// An entry of a nearest-point search's stack: a subtree and its squared distance from the query
/// (computed when pushed).
struct NearestEntry {
  std::uint32_t ref;  ///< node index, or packet index | kLeaf
  float distance_squared;
};

}  // namespace

// Branch and bound over the four-wide tree, depth first. A node's four child boxes get their
// squared distances to p at once (box_distance_squared; unused slots are never opened). The
// search goes on into the nearest child (which most tightens the bound); the other children
// nearer than the best so far wait on the stack, and are dropped when popped if the bound has
// passed them meanwhile. A leaf's four triangles get their exact squared distances at once
// (TriangleLanes::distance_squared above); the nearest point and weights of the winner come from
// the same region test on its one lane at the end.
BvhNearest TriangleBvh::nearest(Vec3 p, float max_distance_squared) const noexcept {
  if (nodes_.empty()) return {};
  const Vec3Lanes pl{splat(p.x), splat(p.y), splat(p.z)};
  NearestSoFar best = nearest_start(max_distance_squared);
  std::array<NearestEntry, kBvhStackSize> stack;
  int top = 0;
  std::uint32_t ref = 0;  // the node or packet being searched: the root first
  for (;;) {
    if (ref & kLeaf) {
      const std::uint32_t packet = ref & kPacketMask;
      offer_packet(TriangleLanes(packets_[packet].corners, normals_[packet]).distance_squared(pl), packet, best);
    } else {
      const Node& node = nodes_[ref];
      const Lanes d2 = box_distance_squared(node, pl, pl);
      // Children that may hold a nearer point (never an unused slot, whatever p is).
      const unsigned open = lane_bits(d2 < splat(best.distance_squared)) & used_slots(node);
      if (open != 0) {
        ref = descend(node, d2, open, stack, top);
        continue;
      }
    }
    // Next: the most recently pushed subtree that may still hold a nearer point.
    while (top > 0 && !(stack[top - 1].distance_squared < best.distance_squared)) --top;
    if (top == 0) break;
    ref = stack[--top].ref;
  }
  if (best.lane < 0) return {};
  return nearest_result(packets_[best.packet], best.lane, p);
}

// The same branch and bound for a batch of points: the boxes' distances are taken from the
// batch's bounding box (a lower bound of every point's), against the largest of the points'
// bests. A node's leaf children are searched when the node is entered, each for the points whose
// own distance to its box is below their best (the points' distances to the four child boxes in
// lanes, one point at a time); its inner children are searched as a single query's, nearest
// first.
void TriangleBvh::nearest(std::span<const Vec3> points, std::span<const float> max_distance_squared,
                          std::span<BvhNearest> out) const noexcept {
  const std::size_t count = std::min({points.size(), max_distance_squared.size(), out.size()});
  for (std::size_t first = 0; first < count; first += kBvhNearestBatch) {
    const int n = static_cast<int>(std::min<std::size_t>(kBvhNearestBatch, count - first));
    const Vec3* p = points.data() + first;
    std::array<NearestSoFar, kBvhNearestBatch> best;
    std::array<Vec3Lanes, kBvhNearestBatch> pl;
    Vec3 lo = p[0], hi = p[0];
    float widest = -kInfinity;  // the largest best: a subtree farther than it helps no point
    for (int i = 0; i < n; ++i) {
      best[i] = nearest_start(max_distance_squared[first + i]);
      pl[i] = {splat(p[i].x), splat(p[i].y), splat(p[i].z)};
      lo = glm::min(lo, p[i]);
      hi = glm::max(hi, p[i]);
      widest = std::max(widest, best[i].distance_squared);
    }
    const Vec3Lanes lo_lanes{splat(lo.x), splat(lo.y), splat(lo.z)}, hi_lanes{splat(hi.x), splat(hi.y), splat(hi.z)};
    std::array<NearestEntry, kBvhStackSize> stack;
    int top = 0;
    std::uint32_t ref = 0;
    while (!nodes_.empty()) {
      const Node& node = nodes_[ref];
      const Lanes d2 = box_distance_squared(node, lo_lanes, hi_lanes);
      unsigned open = lane_bits(d2 < splat(widest)) & used_slots(node);
      unsigned leaves = 0;
      for (int k = 0; k < kBvhWidth; ++k) leaves |= static_cast<unsigned>(is_leaf(node.child[k])) << k;
      if ((open & leaves) != 0) {
        std::array<std::array<float, kBvhWidth>, kBvhNearestBatch> reach;  // per point: its distances to the four boxes
        for (int i = 0; i < n; ++i) store(reach[i].data(), box_distance_squared(node, pl[i], pl[i]));
        for (unsigned m = open & leaves; m != 0; m &= m - 1) {
          const int k = std::countr_zero(m);
          const std::uint32_t packet = node.child[k] & kPacketMask;
          const TriangleLanes triangles(packets_[packet].corners, normals_[packet]);  // once for every point reaching the leaf
          for (int i = 0; i < n; ++i) {
            if (reach[i][k] < best[i].distance_squared) offer_packet(triangles.distance_squared(pl[i]), packet, best[i]);
          }
        }
        widest = best[0].distance_squared;
        for (int i = 1; i < n; ++i) widest = std::max(widest, best[i].distance_squared);
        open &= ~leaves & lane_bits(d2 < splat(widest));
      }
      if (open != 0) {
        // (the leaves' lanes out of the nearest child's choice)
        const LaneMask leaf_lanes = masks((leaves & 1u) != 0, (leaves & 2u) != 0, (leaves & 4u) != 0, (leaves & 8u) != 0);
        ref = descend(node, select(leaf_lanes, splat(kInfinity), d2), open, stack, top);
        continue;
      }
      while (top > 0 && !(stack[top - 1].distance_squared < widest)) --top;
      if (top == 0) break;
      ref = stack[--top].ref;
    }
    for (int i = 0; i < n; ++i) {
      out[first + i] = best[i].lane < 0 ? BvhNearest{} : nearest_result(packets_[best[i].packet], best[i].lane, p[i]);
    }
  }
}

// ---- ray casts ---------------------------------------------------------------------------

namespace {

/// The edge functions of four triangles for one watertight ray (the scalar steps of
/// detail::WatertightRay::fraction, lane by lane): the crossings as lane bits and their
/// fractions. Lanes whose float edge function is exactly zero are redone in double, as there.
struct PacketCrossings {
  unsigned bits = 0;                 ///< lanes the ray crosses within the maximum fraction
  std::array<float, 4> fraction{};   ///< where (valid in the lanes of `bits`)
};

/// A watertight ray's constants as lanes, made once per ray (not at every leaf).
struct PacketRay {
  const detail::WatertightRay& ray;
  int kx, ky, kz;
  Lanes ox, oy, oz, sx, sy, sz;
  explicit PacketRay(const detail::WatertightRay& r) noexcept
      : ray(r), kx(r.kx), ky(r.ky), kz(r.kz), ox(splat(r.origin[r.kx])), oy(splat(r.origin[r.ky])),
        oz(splat(r.origin[r.kz])), sx(splat(r.sx)), sy(splat(r.sy)), sz(splat(r.sz)) {}
};

/// The sliver lanes `lanes` whose edge functions the ray's line passes, measured from their
/// planes by the scalar test's own function (so both give the same floats): a crossing within
/// (0, max_fraction] joins out.bits. Rare, and out of line: inside cross_packet it cost every
/// ray a few percent.
COLLIDE_COLD void measure_slivers(const CornerLanes& t, unsigned lanes, const detail::WatertightRay& ray,
                                  float max_fraction, PacketCrossings& out) noexcept {
  for (; lanes != 0; lanes &= lanes - 1) {
    const int k = std::countr_zero(lanes);
    const auto corner = [&](int c) { return Vec3(t[c][0][k], t[c][1][k], t[c][2][k]); };
    const float fraction = ray.sliver_fraction(corner(0), corner(1), corner(2), max_fraction);
    if (fraction > 0.0f) out.bits |= 1u << k;
    out.fraction[k] = fraction;
  }
}

/// `slivers`: the lanes whose triangles are slivers (from the leaf reference), whose fractions
/// are taken from their planes as WatertightRay::fraction does.
inline PacketCrossings cross_packet(const CornerLanes& t, unsigned slivers, const PacketRay& r, float max_fraction) noexcept {
  const Lanes ox = r.ox, oy = r.oy, oz = r.oz, sx = r.sx, sy = r.sy, sz = r.sz;
  // Corners relative to the origin, in the ray's axes, sheared so the ray runs along z.
  const Lanes az = load(t[0][r.kz]) - oz, bz = load(t[1][r.kz]) - oz, cz = load(t[2][r.kz]) - oz;
  const Lanes ax = (load(t[0][r.kx]) - ox) - sx * az, ay = (load(t[0][r.ky]) - oy) - sy * az;
  const Lanes bx = (load(t[1][r.kx]) - ox) - sx * bz, by = (load(t[1][r.ky]) - oy) - sy * bz;
  const Lanes cx = (load(t[2][r.kx]) - ox) - sx * cz, cy = (load(t[2][r.ky]) - oy) - sy * cz;
  Lanes u = cx * by - cy * bx;
  Lanes v = ax * cy - ay * cx;
  Lanes w = bx * ay - by * ax;
  const Lanes zero = splat(0.0f);
  if (const unsigned on_edge = lane_bits((u == zero) | (v == zero) | (w == zero))) {
    std::array<float, 4> uu, vv, ww, axs, ays, bxs, bys, cxs, cys;
    std::memcpy(uu.data(), &u, sizeof uu);
    std::memcpy(vv.data(), &v, sizeof vv);
    std::memcpy(ww.data(), &w, sizeof ww);
    std::memcpy(axs.data(), &ax, sizeof axs);
    std::memcpy(ays.data(), &ay, sizeof ays);
    std::memcpy(bxs.data(), &bx, sizeof bxs);
    std::memcpy(bys.data(), &by, sizeof bys);
    std::memcpy(cxs.data(), &cx, sizeof cxs);
    std::memcpy(cys.data(), &cy, sizeof cys);
    for (int k = 0; k < 4; ++k) {
      if (!((on_edge >> k) & 1u)) continue;
      uu[k] = static_cast<float>(double(cxs[k]) * double(bys[k]) - double(cys[k]) * double(bxs[k]));
      vv[k] = static_cast<float>(double(axs[k]) * double(cys[k]) - double(ays[k]) * double(cxs[k]));
      ww[k] = static_cast<float>(double(bxs[k]) * double(ays[k]) - double(bys[k]) * double(axs[k]));
    }
    u = load(uu);
    v = load(vv);
    w = load(ww);
  }
  const auto inside = ((u >= zero) & (v >= zero) & (w >= zero)) | ((u <= zero) & (v <= zero) & (w <= zero));
  PacketCrossings out;
  // Most leaves a ray opens hold no triangle it passes through: done before the fractions.
  if (lane_bits(inside) == 0) return out;
  const Lanes det = u + v + w;
  const Lanes time = u * (sz * az) + v * (sz * bz) + w * (sz * cz);
  // Two-sided: the back side has a negative determinant; flip both.
  const auto back = det < zero;
  const Lanes abs_det = select(back, zero - det, det);
  const Lanes abs_time = select(back, zero - time, time);
  const auto crossed = inside & (abs_det > zero);
  out.bits = lane_bits(crossed & (abs_time > zero) & (abs_time <= splat(max_fraction) * abs_det)) & ~slivers;
  const unsigned crossed_slivers = lane_bits(crossed) & slivers;
  if ((out.bits | crossed_slivers) != 0) {
    const Lanes f = min(abs_time / abs_det, splat(max_fraction));
    std::memcpy(out.fraction.data(), &f, sizeof f);
    if (crossed_slivers != 0) measure_slivers(t, crossed_slivers, r.ray, max_fraction, out);
  }
  return out;
}

/// Lanes of a packet that hold distinct triangles: unused lanes repeat the last one.
inline unsigned distinct_lanes(const std::array<std::uint32_t, kBvhLeafTriangles>& id) noexcept {
  return 1u | static_cast<unsigned>(id[1] != id[0]) << 1 | static_cast<unsigned>(id[2] != id[1]) << 2 |
         static_cast<unsigned>(id[3] != id[2]) << 3;
}

}  // namespace

// Depth first, nearer child first. A node's four child boxes get their entry and exit
// fractions at once by the slab test (Williams et al. 2005): per axis the near side is chosen
// by the sign of the direction (row axis or axis + 3 of the node's boxes), so
//   t_near = (near - o) / d,  t_far = (far - o) / d  need no min/max between them;
// an axis the ray does not move along (d = +-0, 1 / d = +-inf) gives +-inf, or NaN when the
// origin lies exactly in that face plane, which the max / min below ignore (the origin is
// then inside that slab: boxes are closed). A child is entered when
//   max(t_near_x, t_near_y, t_near_z, 0) <= min(t_far_x, t_far_y, t_far_z, max_fraction) * slack.
// The entered children are visited nearest first; the others wait on the stack with their entry
// fraction and are dropped when popped if the ray has been clipped before them meanwhile.
// With Grow (box_cast) every box is first grown by `half` on each side: a box of half extents
// `half` moving from centre `origin` meets a box exactly when the ray from its centre enters
// that box grown by `half` (their Minkowski sum). Always inlined: called out of line, the ray
// walk read its watertight ray through a pointer at every leaf and lost 10% against the walk
// written inside traverse_ray (bench_mesh_raycast).
template <bool Grow, class OnLeaf>
COLLIDE_ALWAYS_INLINE void TriangleBvh::traverse_slabs(Vec3 origin_point, Vec3 translation, Vec3 half, float max_fraction,
                                 OnLeaf&& on_leaf) const {
  if (nodes_.empty() || !(max_fraction > 0.0f)) return;
  std::array<int, 3> near_row, far_row;
  std::array<Lanes, 3> origin, inverse, near_grow, far_grow;
  // The three reciprocals by one vector division (a division per ray is a fixed cost that short
  // rays, which open two or three nodes, feel).
  const Lanes reciprocal = splat(1.0f) / lanes(translation.x, translation.y, translation.z, 1.0f);
  for (int axis = 0; axis < 3; ++axis) {
    const bool down = std::signbit(translation[axis]);
    near_row[axis] = down ? kMaxX + axis : kMinX + axis;
    far_row[axis] = down ? kMinX + axis : kMaxX + axis;
    origin[axis] = splat(origin_point[axis]);
    inverse[axis] = splat(reciprocal[axis]);
    near_grow[axis] = splat(down ? half[axis] : -half[axis]);
    far_grow[axis] = splat(down ? -half[axis] : half[axis]);
  }
  struct Entry {
    std::uint32_t ref;  // node index, or packet index | kLeaf
    float fraction;     // where the ray enters its box
  };
  std::array<Entry, kBvhStackSize> stack;
  int top = 0;
  std::uint32_t ref = 0;  // the root first
  float max_t = max_fraction;
  for (;;) {
    if (ref & kLeaf) {
      max_t = on_leaf(packets_[ref & kPacketMask], (ref >> kSliverShift) & 0xfu, max_t);
      if (!(max_t > 0.0f)) return;
    } else {
      const Node& node = nodes_[ref];
      // The fraction at which the ray reaches row `row[axis]` of the node's boxes (grown).
      const auto slab = [&](const std::array<int, 3>& row, const std::array<Lanes, 3>& grow, int axis) {
        Lanes side = load(node.box[row[axis]]);
        if constexpr (Grow) side = side + grow[axis];
        return (side - origin[axis]) * inverse[axis];
      };
      const Lanes t_near_x = slab(near_row, near_grow, 0);
      const Lanes t_near_y = slab(near_row, near_grow, 1);
      const Lanes t_near_z = slab(near_row, near_grow, 2);
      const Lanes t_far_x = slab(far_row, far_grow, 0);
      const Lanes t_far_y = slab(far_row, far_grow, 1);
      const Lanes t_far_z = slab(far_row, far_grow, 2);
      const Lanes enter = max(t_near_x, max(t_near_y, max(t_near_z, splat(0.0f))));
      const Lanes exit = min(t_far_x, min(t_far_y, min(t_far_z, splat(max_t)))) * splat(kBvhSlabSlack);
      // An unused slot's box [+inf, -inf] is never entered by a finite ray (its near side is
      // +inf or NaN, its far side -inf or NaN, on every axis), so no used_slots mask here.
      unsigned open = lane_bits(enter <= exit);
      COLLIDE_ASSERT((open & ~used_slots(node)) == 0, "BVH ray walk entered an unused slot");
      if (open != 0) {
        std::array<float, kBvhWidth> t;
        std::memcpy(t.data(), &enter, sizeof t);
        // One or two open children (most nodes a ray opens) without the sort, on one path: a
        // long ray's nodes open one or two in no order a branch predictor learns (undulating.obj's
        // long rays in bench_mesh_raycast: 8% of the walk went to that branch). With one,
        // `second` is `first`, the comparison holds and the entry written is not kept. The nearer
        // goes next; of two at the same fraction the higher slot, as the sort below orders them.
        // Their order stays a branch: chosen by masks it joined every visit's chain of loads, and
        // short rays (whose one or two a predictor does learn) lost 20-30%.
        const int first = std::countr_zero(open);
        const unsigned rest = open & (open - 1);
        if ((rest & (rest - 1)) == 0) {
          const int second = std::bit_width(open) - 1;  // the highest open slot: `first` when alone
          const bool second_nearer = t[second] <= t[first];
          const int next = second_nearer ? second : first;
          const int later = second_nearer ? first : second;
          stack[top] = {node.child[later], t[later]};
          top += rest != 0;
          ref = node.child[next];
          continue;
        }
        // Three or four: pushed in order of entry fraction, farthest first (an insertion sort
        // on the stack itself), and the nearest taken back off.
        COLLIDE_ASSERT(top + kBvhWidth <= kBvhStackSize, "BVH traversal stack overflow");
        const int base = top;
        while (open != 0) {
          const int k = std::countr_zero(open);
          open &= open - 1;
          const Entry e{node.child[k], t[k]};
          int i = top++;
          for (; i > base && stack[i - 1].fraction < e.fraction; --i) stack[i] = stack[i - 1];
          stack[i] = e;
        }
        ref = stack[--top].ref;
        continue;
      }
    }
    // Next: the most recently pushed subtree the ray (as clipped now) still enters.
    while (top > 0 && !(stack[top - 1].fraction <= max_t * kBvhSlabSlack)) --top;
    if (top == 0) return;
    ref = stack[--top].ref;
  }
}

// The slab walk with the watertight crossing test of each packet at the leaves.
template <class OnLeaf>
void TriangleBvh::traverse_ray(const Ray3& ray, float max_fraction, OnLeaf&& on_leaf) const {
  if (nodes_.empty()) return;
  const detail::WatertightRay watertight(ray);
  if (!watertight.valid) return;
  const PacketRay packet_ray(watertight);
  traverse_slabs<false>(ray.origin, ray.translation, Vec3(0.0f), max_fraction,
                        [&](const Packet& packet, unsigned slivers, float max_t) {
                          PacketCrossings hits = cross_packet(packet.corners, slivers, packet_ray, max_t);
                          hits.bits &= distinct_lanes(packet.id);
                          return hits.bits != 0 ? on_leaf(packet, hits.bits, hits.fraction, max_t) : max_t;
                        });
}

void TriangleBvh::ray_cast(const Ray3& ray, TriangleRayCallback visit, float max_fraction) const {
  traverse_ray(ray, max_fraction,
               [&](const Packet& packet, unsigned bits, const std::array<float, 4>& fraction, float max_t) {
                 for (; bits != 0; bits &= bits - 1) {
                   const int k = std::countr_zero(bits);
                   if (!(fraction[k] <= max_t)) continue;  // clipped by an earlier lane of this packet
                   const float next = visit(packet.id[k], fraction[k]);
                   if (!(next > 0.0f)) return 0.0f;
                   if (next < max_t) max_t = next;
                 }
                 return max_t;
               });
}

TriangleRayHit TriangleBvh::ray_cast(const Ray3& ray, float max_fraction) const noexcept {
  const Packet* best_packet = nullptr;
  int best_lane = 0;
  float best = max_fraction;
  traverse_ray(ray, max_fraction,
               [&](const Packet& packet, unsigned bits, const std::array<float, 4>& fraction, float max_t) {
                 for (; bits != 0; bits &= bits - 1) {
                   const int k = std::countr_zero(bits);
                   // Strictly nearer, or the first crossing at all (which may sit at max_fraction).
                   if (fraction[k] < max_t || (best_packet == nullptr && fraction[k] <= max_t)) {
                     max_t = fraction[k];
                     best_packet = &packet;
                     best_lane = k;
                   }
                 }
                 best = max_t;
                 return max_t;
               });
  TriangleRayHit hit;
  if (best_packet == nullptr) return hit;
  const auto lane = static_cast<std::uint32_t>(best_lane);
  hit.triangle = best_packet->id[lane];
  hit.fraction = best;
  // The unit normal the build made (triangle_normal, in double): read, not made again per cast.
  const PacketNormals& normal = normals_[static_cast<std::size_t>(best_packet - packets_.data())];
  hit.normal = Vec3(normal[0][lane], normal[1][lane], normal[2][lane]);
  return hit;
}

// The slab walk grown by the cast box's half extents; leaves test each triangle's own box the
// same way (grown by h, entered from the box's centre c), scalar.
void TriangleBvh::box_cast(const Aabb3& box, Vec3 translation, TriangleCastCallback visit,
                           float max_fraction) const {
  const Vec3 c = 0.5f * (box.min + box.max);
  const Vec3 h = 0.5f * (box.max - box.min);
  for (int axis = 0; axis < 3; ++axis) {
    if (!std::isfinite(c[axis]) || !(h[axis] >= 0.0f) || !std::isfinite(h[axis]) ||
        !std::isfinite(translation[axis])) {
      return;
    }
  }
  const Vec3 inverse = 1.0f / translation;
  traverse_slabs<true>(c, translation, h, max_fraction, [&](const Packet& packet, unsigned, float max_t) {
    for (unsigned bits = distinct_lanes(packet.id); bits != 0; bits &= bits - 1) {
      const auto lane = static_cast<std::uint32_t>(std::countr_zero(bits));
      const Vec3 a = packet.corner(0, lane), b = packet.corner(1, lane), d = packet.corner(2, lane);
      const Vec3 lo = glm::min(glm::min(a, b), d) - h;
      const Vec3 hi = glm::max(glm::max(a, b), d) + h;
      float enter = 0.0f;
      float exit = max_t;
      for (int axis = 0; axis < 3 && enter <= exit; ++axis) {
        if (translation[axis] == 0.0f) {
          if (!(lo[axis] <= c[axis] && c[axis] <= hi[axis])) exit = -1.0f;
          continue;
        }
        float t0 = (lo[axis] - c[axis]) * inverse[axis];
        float t1 = (hi[axis] - c[axis]) * inverse[axis];
        if (t0 > t1) std::swap(t0, t1);
        enter = std::max(enter, t0);
        exit = std::min(exit, t1 * kBvhSlabSlack);
      }
      if (!(enter <= exit)) continue;
      const float next = visit(packet.id[lane], enter);
      if (!(next > 0.0f)) return 0.0f;
      if (next < max_t) max_t = next;
    }
    return max_t;
  });
}

}  // namespace collide
