#pragma once
/// @file
/// A static bounding volume hierarchy over the triangles of a mesh: the exact nearest triangle
/// to a point, every triangle whose box overlaps a query box, and the triangles a ray crosses,
/// without scanning all of them. The spatial index of `TriangleMesh` and of the walk mesh.

#include <collide/core/aabb.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/ray.hpp>
#include <collide/shape/triangle.hpp>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
#include <vector>

namespace collide {

/// Children per BVH node: the four child boxes of a node are tested together (one SIMD
/// register per coordinate).
inline constexpr int kBvhWidth = 4;
/// Most triangles in one BVH leaf: a leaf is one packet of four triangles tested together.
inline constexpr int kBvhLeafTriangles = 4;
/// Points one descent of `TriangleBvh::nearest` for many points serves: a 2x2x2 block of grid
/// nodes (a distance field's band).
inline constexpr int kBvhNearestBatch = 8;
/// Candidate split planes per axis for the binned surface area heuristic (32: among FCL's
/// env.obj's long triangles 16 found planes that cost 20% more instructions per ray; 64 gained
/// nothing over 32).
inline constexpr int kBvhBins = 32;
/// Depth of the binary build below which nodes are split by the surface area heuristic; deeper
/// nodes are split at the median (halving their count), so the tree is at most
/// kBvhMaxSahDepth + 32 levels deep for any input of fewer than 2^32 triangles, whatever the
/// coordinates (also non-finite ones: the split never depends on a comparison with a NaN).
inline constexpr int kBvhMaxSahDepth = 32;
/// Entries of the fixed traversal stack: a visit leaves at most kBvhWidth - 1 siblings pending
/// per level of the (at most kBvhMaxSahDepth + 32 deep) tree, plus room for one node's children.
/// Unused child slots are never entered (they are marked, not only given an empty box: an
/// infinite query box overlaps the empty box [+inf, -inf] too), so no query can exceed it.
inline constexpr int kBvhStackSize = (kBvhWidth - 1) * (kBvhMaxSahDepth + 32) + 2 * kBvhWidth;
/// A ray's fraction interval over a box is widened by this factor at its far end, so float
/// rounding in the slab test cannot drop a box the ray only grazes (a triangle hit exactly on
/// its box's boundary, a ray ending exactly on a triangle): 1 + 2 gamma_3 with gamma_n =
/// n u / (1 - n u), u = 2^-24 (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013).
inline constexpr float kBvhSlabSlack = 1.0f + 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

/// The triangle nearest to a point.
struct BvhNearest {
  std::uint32_t triangle = std::numeric_limits<std::uint32_t>::max();  ///< input index; max() when none
  TrianglePoint closest{};  ///< nearest point (BVH space) and its weights of the triangle's a, b, c
  float distance_squared = std::numeric_limits<float>::infinity();  ///< squared distance to it
};

/// Called by `TriangleBvh::box_cast` with each triangle whose box the moving box meets and the
/// fraction at which it first does. Returns the new maximum fraction (TriangleRayCallback's
/// convention): the best fraction found so far clips the cast, 0 stops it.
using TriangleCastCallback = FunctionRef<float(std::uint32_t triangle, float fraction)>;

/// Static AABB tree over triangles: built top-down by the binned surface area heuristic (Wald,
/// "On fast construction of SAH-based bounding volume hierarchies", 2007; Ericson, Real-Time
/// Collision Detection, 6.2) as a binary tree with leaves of at most four triangles, then
/// collapsed to four children per node by opening the largest inner child until a node has four
/// (Wald, Benthin, Boulos, "Getting rid of packets", 2008; Embree's BVH4). Boxes are stored per
/// node as four lanes per coordinate, triangles per leaf as a packet of four with their corners
/// inline, so a query tests four boxes or four triangles at once on contiguous memory.
/// Coordinates are those given to the constructor (callers shift large worlds to a local origin).
class TriangleBvh {
 public:
  TriangleBvh() = default;
  /// Builds over `triangles` (indices into `positions`). Indices must be in range and positions
  /// finite (callers validate; this is not an entry point for user data). Throws InvalidInput
  /// when the tree would need 2^27 leaf packets or more (over 134 million triangles).
  TriangleBvh(std::span<const Vec3> positions, std::span<const glm::uvec3> triangles);

  /// The exact nearest point of all triangles to `p`: branch and bound, nearer child first,
  /// pruning boxes no nearer than the best so far (so among triangles at exactly the same
  /// distance, the first one found wins: deterministic for a given tree). No allocation.
  /// Only triangles within `max_distance_squared` of `p` (inclusive) count: a finite bound
  /// prunes from the first node on, for callers that know `p` is near the mesh (Detour's
  /// findNearestPoly takes a search box for the same reason). `distance_squared` of the result
  /// is recomputed from its closest point, so it may exceed the bound by rounding.
  /// Empty (triangle == max()) when no triangle is within the bound, when the tree is empty, or
  /// when squared distances from `p` overflow float (|p| beyond about 1e18).
  [[nodiscard]] BvhNearest nearest(Vec3 p, float max_distance_squared = std::numeric_limits<float>::infinity()) const noexcept;

  /// The nearest point of all triangles to each of `points`, each within its own bound: out[i]
  /// as nearest(points[i], max_distance_squared[i]) gives it (the same distance; among
  /// triangles at exactly the same distance another may win, as the search order differs). For
  /// points close together, as a block of grid nodes: the points are taken kBvhNearestBatch at
  /// a time, and each batch descends the tree once, entering a node when its box is nearer the
  /// batch's bounding box than the largest bound still open; a leaf's triangles are measured
  /// only for the points its box may bring nearer (the descent is most of a single query's
  /// cost: on recast's dungeon.obj, 2x2x2 nodes a voxel apart, one batch entered 11.7 nodes
  /// where eight single queries entered 58). Points far apart are answered right, only
  /// slower. The spans should be equally long: only as many points as the shortest holds are
  /// answered. No allocation.
  void nearest(std::span<const Vec3> points, std::span<const float> max_distance_squared,
               std::span<BvhNearest> out) const noexcept;

  /// Calls `visit(triangle index)` for every triangle whose bounding box overlaps `box`. A
  /// `visit` that returns bool stops the query by returning false.
  template <class Visit>
  void query(const Aabb3& box, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<std::uint32_t, kBvhStackSize> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      // The four slots' overlap tests without a branch each (& rather than &&: a missed
      // prediction per slot cost more than the comparisons), then the overlapping used slots.
      unsigned hits = 0;
      for (int k = 0; k < kBvhWidth; ++k) {
        const unsigned overlaps =
            unsigned{node.box[kMinX][k] <= box.max.x} & unsigned{box.min.x <= node.box[kMaxX][k]} &
            unsigned{node.box[kMinY][k] <= box.max.y} & unsigned{box.min.y <= node.box[kMaxY][k]} &
            unsigned{node.box[kMinZ][k] <= box.max.z} & unsigned{box.min.z <= node.box[kMaxZ][k]};
        hits |= overlaps << k;
      }
      for (hits &= used_slots(node); hits != 0; hits &= hits - 1) {
        const int k = std::countr_zero(hits);
        if (node.count[k] == 0) {
          stack[top++] = node.child[k];
          continue;
        }
        const Packet& packet = packets_[node.child[k] & kPacketMask];
        unsigned lanes = 0;
        for (std::uint32_t i = 0; i < kBvhLeafTriangles; ++i) {
          unsigned overlaps = 1;
          for (int axis = 0; axis < 3; ++axis) {
            const float p = packet.corners[0][axis][i], q = packet.corners[1][axis][i], r = packet.corners[2][axis][i];
            const float lo = std::min(std::min(p, q), r), hi = std::max(std::max(p, q), r);
            overlaps &= unsigned{lo <= box.max[axis]} & unsigned{box.min[axis] <= hi};
          }
          lanes |= overlaps << i;
        }
        lanes &= (1u << node.count[k]) - 1u;
        for (; lanes != 0; lanes &= lanes - 1) {
          const auto i = static_cast<std::uint32_t>(std::countr_zero(lanes));
          if constexpr (std::is_same_v<std::invoke_result_t<Visit&, std::uint32_t>, bool>) {
            if (!visit(packet.id[i])) return;
          } else {
            visit(packet.id[i]);
          }
        }
      }
    }
  }

  /// Every triangle `ray` crosses (either side; BVH space) within `max_fraction`, reported to
  /// `visit` with the fraction of the crossing, which may clip the ray (see TriangleRayCallback).
  /// Nearer boxes are opened first, so a closest-hit callback clips early; hits come in no
  /// particular order otherwise, and a triangle is reported once. The crossing test is
  /// `ray_triangle_fraction`'s (watertight; fraction 0 and rays in a triangle's plane do not
  /// count), four triangles at a time. Boxes: the slab test four at a time (Williams, Barrus,
  /// Morley & Shirley, "An Efficient and Robust Ray-Box Intersection Algorithm", JGT 2005:
  /// the inverse direction picks each slab's near side, and a NaN from an axis the ray does not
  /// move along is ignored by the min/max, so a ray in a box's face plane still enters it),
  /// widened by kBvhSlabSlack. No allocation; nothing is reported for a ray of zero length or
  /// with a non-finite coordinate. What `visit` throws propagates.
  void ray_cast(const Ray3& ray, TriangleRayCallback visit, float max_fraction = 1.0f) const;

  /// Every triangle whose bounding box the axis-aligned box `box` (BVH space) meets while it
  /// moves by `translation` within `max_fraction` of it, reported to `visit` with the fraction
  /// at which the moving box first touches the triangle's box (0 when they overlap at the
  /// start); the callback returns the new maximum fraction (TriangleCastCallback). Nearer
  /// boxes are opened first, so a caller that clips at its best hit so far prunes the rest.
  /// Exactly the ray traversal of `ray_cast` from the box's centre through boxes grown by its
  /// half extents (their Minkowski sum), with the same slack. No allocation; nothing for a
  /// non-finite input.
  void box_cast(const Aabb3& box, Vec3 translation, TriangleCastCallback visit, float max_fraction = 1.0f) const;

  /// The nearest triangle `ray` crosses within `max_fraction` (the callback version with a
  /// callback that clips at each hit, without the indirect call). Among crossings at exactly the
  /// same fraction (a ray through a shared edge) the first found wins: deterministic for a given
  /// tree. A miss has triangle == max().
  [[nodiscard]] TriangleRayHit ray_cast(const Ray3& ray, float max_fraction = 1.0f) const noexcept;

  [[nodiscard]] std::size_t triangle_count() const noexcept { return triangle_count_; }
  /// Nodes of the four-wide tree.
  [[nodiscard]] std::size_t node_count() const noexcept { return nodes_.size(); }
  /// Box of everything; a zero box when empty.
  [[nodiscard]] Aabb3 bounds() const noexcept { return bounds_; }

  // ---- The layout, for algorithms that walk the tree with data of their own per child box
  // (the fast winding number of sdf/winding_tree.hpp keeps a cluster's dipole per child). ----

  /// Set in a child reference that names a leaf packet rather than a node. A leaf reference
  /// is kLeaf | slivers << kSliverShift | packet index, `slivers` bit k set when lane k's
  /// triangle is a sliver (longer than detail::kSliverAspect times its width), whose ray
  /// crossings are measured from its plane (src/shape/watertight_ray.hpp): kept here rather
  /// than in the packet, whose 160 bytes a ray reads at every leaf (176 cost short rays 3-5%).
  static constexpr std::uint32_t kLeaf = 0x80000000u;
  /// Position of the sliver bits in a leaf reference.
  static constexpr int kSliverShift = 27;
  /// The packet index bits of a leaf reference (packet_index).
  static constexpr std::uint32_t kPacketMask = (1u << kSliverShift) - 1;
  /// The child reference of an unused slot (packets number fewer than kPacketMask).
  static constexpr std::uint32_t kEmpty = 0xffffffffu;
  /// Rows of Node::box: the near side of a slab for a ray moving up the axis is row axis, for a
  /// ray moving down it row axis + 3.
  static constexpr int kMinX = 0, kMinY = 1, kMinZ = 2, kMaxX = 3, kMaxY = 4, kMaxZ = 5;

  /// Four child boxes as lanes per coordinate (two cache lines). Used slots come first; an
  /// unused slot has child kEmpty (and the box min = +inf, max = -inf).
  struct alignas(64) Node {
    std::array<std::array<float, kBvhWidth>, 6> box;  ///< [kMinX..kMaxZ][slot]
    std::array<std::uint32_t, kBvhWidth> child;  ///< inner: node index; leaf: packet index | kLeaf; kEmpty
    std::array<std::uint32_t, kBvhWidth> count;  ///< leaf: triangles in its packet (1..4); else 0
  };
  /// Up to four triangles of one leaf, corners as lanes per coordinate. Unused lanes repeat the
  /// last triangle (same id), so they tie with it and never win a strict comparison.
  struct alignas(16) Packet {
    std::array<std::array<std::array<float, kBvhLeafTriangles>, 3>, 3> corners;  ///< [corner][axis][lane]
    std::array<std::uint32_t, kBvhLeafTriangles> id;  ///< input triangle index per lane
    [[nodiscard]] Vec3 corner(int c, std::uint32_t lane) const noexcept {
      return {corners[c][0][lane], corners[c][1][lane], corners[c][2][lane]};
    }
  };

  /// The four-wide nodes, root first. Numbered depth first: a node's inner children come after
  /// it, and the packets of a subtree are one contiguous range.
  [[nodiscard]] std::span<const Node> nodes() const noexcept { return nodes_; }
  /// The leaf packets, in the order the depth-first numbering meets them.
  [[nodiscard]] std::span<const Packet> packets() const noexcept { return packets_; }
  /// Whether a child reference names a leaf packet (else a node, or kEmpty: test that first).
  [[nodiscard]] static constexpr bool is_leaf(std::uint32_t ref) noexcept { return (ref & kLeaf) != 0; }
  /// The packet index of a leaf reference.
  [[nodiscard]] static constexpr std::uint32_t packet_index(std::uint32_t ref) noexcept { return ref & kPacketMask; }
  /// Bit k set where slot k of the node is used.
  [[nodiscard]] static unsigned used_slots(const Node& node) noexcept {
    unsigned bits = 0;
    for (int k = 0; k < kBvhWidth; ++k) bits |= static_cast<unsigned>(node.child[k] != kEmpty) << k;
    return bits;
  }

 private:
  /// The fixed-stack slab walk behind ray_cast and box_cast: from `origin` along `translation`
  /// within `max_fraction`, nearer children first, through the node boxes (grown by `half` on
  /// each side when Grow). `on_leaf(packet, slivers, max)` handles one packet (`slivers`: its
  /// sliver lanes, from the leaf reference) and returns the new max (<= 0 stops).
  template <bool Grow, class OnLeaf>
  void traverse_slabs(Vec3 origin, Vec3 translation, Vec3 half, float max_fraction, OnLeaf&& on_leaf) const;

  /// The ray traversal behind both ray_cast overloads: `on_leaf(packet, lane bits, fractions,
  /// max)` handles the crossings of one packet and returns the new max (<= 0 stops).
  template <class OnLeaf>
  void traverse_ray(const Ray3& ray, float max_fraction, OnLeaf&& on_leaf) const;

  std::vector<Node> nodes_;      ///< root first
  /// A packet's four triangles' unit normals (triangle_normal: zero for collinear or equal
  /// corners) as lanes per coordinate ([axis][lane]), for `nearest` and a ray's hit: made in
  /// double, then rounded, as a sliver's normal made in float turns by FLT_EPSILON times its
  /// length over width (39% of dungeon.obj's packets hold a triangle longer than 8 times its
  /// width). Apart from the packets, which rays read at every leaf without them; a ray cast
  /// reads its hit's normal here once instead of making it.
  using PacketNormals = std::array<std::array<float, kBvhLeafTriangles>, 3>;

  std::vector<Packet> packets_;  ///< in traversal order of the build
  std::vector<PacketNormals> normals_;  ///< per packet, as packets_
  std::size_t triangle_count_ = 0;
  Aabb3 bounds_{};
};

}  // namespace collide
