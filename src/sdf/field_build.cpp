// Building distance fields: the exact band, the sign, and closest-point propagation
// (distance_field.hpp gives the method and its sources). One build for both dimensions and for
// both storages (dense grid, sparse bricks): the stages write through a store.

#include <collide/core/error.hpp>
#include <collide/core/large_pages.hpp>
#include <collide/core/lanes.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/shape/triangle.hpp>

#include <collide/sdf/winding_tree.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>
#include <string>
#include <variant>

namespace collide {
namespace {


template <int D>
using IVec = glm::vec<D, int>;

/// Node states during a build.
enum NodeState : std::uint8_t {
  kExact = 1,      ///< distance and closest point exact (within the band): never changed by propagation
  kSignKnown = 2,  ///< the inside bit is the node's own (containment or winding number)
  kInside = 4,     ///< inside the solid (own, or copied from a neighbour while propagating)
  kHasValue = 8,   ///< distance and closest point set
  kSignCopied = 16,  ///< the inside bit was copied from a neighbour whose sign was known or copied
};

/// Coordinate of the closest point of a node that has none yet: its squared distance to any
/// node overflows to +inf, so an offer from such a node never wins (propagate_mesh_dense).
constexpr float kNoClosestPoint = 1e30f;
/// A probe for the union's surface steps this fraction of a voxel off a candidate closest point.
constexpr float kSurfaceProbeVoxels = 0.01f;
/// A point whose winding number exceeds this is inside (Jacobson et al. 2013 threshold).
constexpr float kInsideWinding = 0.5f;
/// Most nodes of a grid, whatever the memory limit (sizes stay far from size_t's range).
constexpr double kMaxFieldNodes = 0x1p40;
/// Most nodes along one axis (indices stay far from int's range).
constexpr double kMaxNodesPerAxis = double(1 << 30);
/// Bytes per node a dense build holds at its peak: distance, closest point, state.
template <int D>
constexpr std::size_t kDenseBuildBytesPerNode = sizeof(float) + sizeof(VecN<D>) + 1;

/// Bytes per node of a sparse field's table (4 per brick-sized region); bricks are checked as
/// they are allocated.
template <int D>
constexpr double kSparseTableBytesPerNode = 4.0 / (D == 2 ? kFieldBrickSize * kFieldBrickSize
                                                           : kFieldBrickSize * kFieldBrickSize * kFieldBrickSize);

std::string format_bytes(double bytes) {
  std::ostringstream out;
  out.precision(3);
  if (bytes >= double(1u << 30)) out << bytes / double(1u << 30) << " GiB";
  else if (bytes >= double(1u << 20)) out << bytes / double(1u << 20) << " MiB";
  else out << bytes << " bytes";
  return out.str();
}

/// The grid over `bounds` plus the margin; refuses what would pass the memory limit.
template <int D>
FieldGridN<D> make_grid(AabbN<D> bounds, const FieldOptions& options, double bytes_per_node,
                        int round_to) {
  if (!std::isfinite(options.voxel) || !(options.voxel > 0.0f))
    throw InvalidInput("distance field: voxel size " + std::to_string(options.voxel) + " is not positive and finite");
  if (options.margin < 1) throw InvalidInput("distance field: margin " + std::to_string(options.margin) + " is below 1 voxel");
  if (!std::isfinite(options.band)) throw InvalidInput("distance field: band is not finite");
  for (int k = 0; k < D; ++k)
    if (!std::isfinite(bounds.min[k]) || !std::isfinite(bounds.max[k]))
      throw InvalidInput("distance field: the input's bounds are not finite");
  FieldGridN<D> grid;
  grid.voxel = options.voxel;
  grid.origin = bounds.min - VecN<D>(static_cast<float>(options.margin) * options.voxel);
  double nodes = 1.0;
  for (int k = 0; k < D; ++k) {
    double n = std::floor((double(bounds.max[k]) - double(bounds.min[k])) / double(options.voxel)) + 1.0 +
               2.0 * options.margin;
    n = std::ceil(n / round_to) * round_to;
    nodes *= n;
    grid.dims[k] = n < kMaxNodesPerAxis ? static_cast<int>(n) : static_cast<int>(kMaxNodesPerAxis);
  }
  const double bytes = nodes * bytes_per_node;
  bool too_many = !(bytes <= double(options.max_bytes)) || nodes > kMaxFieldNodes;
  for (int k = 0; k < D; ++k) too_many |= grid.dims[k] >= static_cast<int>(kMaxNodesPerAxis);
  if (too_many) {
    std::ostringstream out;
    out << "distance field: voxel size " << options.voxel << " needs " << format_bytes(bytes) << " (" << nodes
        << " nodes of " << bytes_per_node << " bytes), over the memory limit of "
        << format_bytes(double(options.max_bytes));
    throw InvalidInput(out.str());
  }
  return grid;
}

/// Node range [lo, hi] covering `box` (clamped to the grid); empty when lo > hi on an axis.
template <int D>
void node_range(const FieldGridN<D>& grid, const AabbN<D>& box, IVec<D>& lo, IVec<D>& hi) {
  for (int k = 0; k < D; ++k) {
    const float a = std::ceil((box.min[k] - grid.origin[k]) / grid.voxel);
    const float b = std::floor((box.max[k] - grid.origin[k]) / grid.voxel);
    lo[k] = static_cast<int>(std::clamp(a, 0.0f, float(grid.dims[k])));
    hi[k] = static_cast<int>(std::clamp(b, -1.0f, float(grid.dims[k] - 1)));
  }
}

/// Calls visit(node) for every node of [lo, hi], x fastest.
template <int D, class Visit>
void for_each_node(IVec<D> lo, IVec<D> hi, Visit&& visit) {
  for (int k = 0; k < D; ++k)
    if (lo[k] > hi[k]) return;
  IVec<D> i = lo;
  while (true) {
    visit(i);
    int k = 0;
    while (k < D && ++i[k] > hi[k]) {
      i[k] = lo[k];
      ++k;
    }
    if (k == D) return;
  }
}

/// Calls visit(node) for every node of [lo, hi] (inclusive), in the order `step` gives per
/// axis (+1: ascending, -1: descending), x fastest.
template <int D, class Visit>
void sweep_box(IVec<D> lo, IVec<D> hi, IVec<D> step, Visit&& visit) {
  IVec<D> first, end;
  for (int k = 0; k < D; ++k) {
    if (lo[k] > hi[k]) return;
    first[k] = step[k] > 0 ? lo[k] : hi[k];
    end[k] = step[k] > 0 ? hi[k] + 1 : lo[k] - 1;
  }
  IVec<D> i = first;
  while (true) {
    visit(i);
    int k = 0;
    while (k < D && (i[k] += step[k]) == end[k]) {
      i[k] = first[k];
      ++k;
    }
    if (k == D) return;
  }
}

// ---- stores ------------------------------------------------------------------------------

/// Build storage over the whole grid. Distances are squared until the build finishes (the
/// propagation compares them without a square root).
template <int D>
struct DenseStore {
  FieldGridN<D> grid;
  std::vector<float> distance;
  std::vector<VecN<D>> closest;
  std::vector<std::uint8_t> state;

  explicit DenseStore(const FieldGridN<D>& g)
      : grid(g),
        distance(large_page_vector(g.count(), std::numeric_limits<float>::infinity())),
        closest(large_page_vector(g.count(), VecN<D>(kNoClosestPoint))),
        state(g.count(), 0) {}
  COLLIDE_ALWAYS_INLINE std::size_t slot(IVec<D> i) { return grid.index(i); }
  /// The slot of a node that may have none (dense: always one).
  std::size_t find(IVec<D> i) const { return grid.index(i); }
  /// Calls visit(lo, hi) for each box of nodes the store holds (here the whole grid); `step`
  /// orders the boxes as sweep_box orders nodes.
  template <class Visit>
  void for_each_block(IVec<D> /*step*/, Visit&& visit) const { visit(IVec<D>(0), grid.dims - 1); }
  static constexpr bool kSparse = false;
  static constexpr bool keeps_closest() { return true; }
};

/// Build storage in bricks allocated on first touch, found through a table of regions. `slot`
/// is forced inline: called, its node coordinates went through the stack as three 4-byte stores
/// read back as one 8-byte load, which the CPU cannot forward (perf: a tenth of a mesh's sparse
/// build on that load; bench_sdf, dungeon at 64k nodes, 81 -> 65 ms).
template <int D>
struct SparseStore {
  static constexpr std::uint32_t kNone = SparseDistanceFieldN<D>::kNoBrick;
  static constexpr std::size_t kBrickNodes = D == 2 ? kFieldBrickSize * kFieldBrickSize
                                                    : kFieldBrickSize * kFieldBrickSize * kFieldBrickSize;
  FieldGridN<D> grid;
  IVec<D> regions{0};
  std::vector<std::uint32_t> table;
  std::vector<float> distance;
  std::vector<VecN<D>> closest;
  std::vector<std::uint8_t> state;
  std::size_t max_bytes = 0;
  bool keep_closest = true;  ///< false: the build needs no closest points (a mesh's sparse field)

  SparseStore(const FieldGridN<D>& g, std::size_t limit, bool closest_points = true)
      : grid(g), max_bytes(limit), keep_closest(closest_points) {
    regions = g.dims / kFieldBrickSize;
    std::size_t n = 1;
    for (int k = 0; k < D; ++k) n *= static_cast<std::size_t>(regions[k]);
    table.assign(n, kNone);
  }
  std::size_t region_index(IVec<D> r) const {
    std::size_t at = static_cast<std::size_t>(r[D - 1]);
    for (int k = D - 2; k >= 0; --k) at = at * static_cast<std::size_t>(regions[k]) + static_cast<std::size_t>(r[k]);
    return at;
  }
  static std::size_t local_index(IVec<D> l) {
    std::size_t at = static_cast<std::size_t>(l[D - 1]);
    for (int k = D - 2; k >= 0; --k) at = at * kFieldBrickSize + static_cast<std::size_t>(l[k]);
    return at;
  }
  COLLIDE_ALWAYS_INLINE std::size_t slot(IVec<D> i) {
    const IVec<D> r = i / kFieldBrickSize;
    std::uint32_t& brick = table[region_index(r)];
    if (brick == kNone) {
      const std::size_t bricks = distance.size() / kBrickNodes;
      if ((bricks + 1) * kBrickNodes * kDenseBuildBytesPerNode<D> > max_bytes) {
        throw InvalidInput("distance field: the band needs more than the memory limit of " +
                           format_bytes(double(max_bytes)) + " (" + std::to_string(bricks + 1) + " bricks)");
      }
      brick = static_cast<std::uint32_t>(bricks);
      distance.resize(distance.size() + kBrickNodes, std::numeric_limits<float>::infinity());
      if (keep_closest) closest.resize(closest.size() + kBrickNodes);
      state.resize(state.size() + kBrickNodes, 0);
    }
    return std::size_t{brick} * kBrickNodes + local_index(i - r * kFieldBrickSize);
  }
  /// The slot of node `i`, or SIZE_MAX when its region has no brick.
  std::size_t find(IVec<D> i) const {
    const IVec<D> r = i / kFieldBrickSize;
    const std::uint32_t brick = table[region_index(r)];
    if (brick == kNone) return std::numeric_limits<std::size_t>::max();
    return std::size_t{brick} * kBrickNodes + local_index(i - r * kFieldBrickSize);
  }
  /// Calls visit(lo, hi) for the node box of each brick, bricks in the order `step` gives.
  template <class Visit>
  void for_each_block(IVec<D> step, Visit&& visit) const {
    sweep_box<D>(IVec<D>(0), regions - 1, step, [&](IVec<D> r) {
      if (table[region_index(r)] == kNone) return;
      visit(r * kFieldBrickSize, r * kFieldBrickSize + (kFieldBrickSize - 1));
    });
  }
  static constexpr bool kSparse = true;
  bool keeps_closest() const { return keep_closest; }
};

// ---- stage 1: the exact band ---------------------------------------------------------------

/// Shapes binned on a coarse grid: which shapes may contain a point (the union's surface test).
template <int D>
class ShapeBins {
  /// At most about a million bins, whatever the extent and the voxel.
  static constexpr float kMaxBinsPerAxis = D == 2 ? 1024.0f : 128.0f;

 public:
  ShapeBins(std::span<const PlacedShapeN<D>> shapes, const std::vector<AabbN<D>>& boxes, AabbN<D> all, float cell)
      : shapes_(shapes), boxes_(boxes), origin_(all.min), cell_(cell) {
    std::size_t n = 1;
    for (int k = 0; k < D; ++k) {
      dims_[k] = std::max(1, static_cast<int>(std::min(kMaxBinsPerAxis, std::floor((all.max[k] - all.min[k]) / cell) + 1.0f)));
      n *= static_cast<std::size_t>(dims_[k]);
    }
    start_.assign(n + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
      for (std::uint32_t s = 0; s < shapes.size(); ++s) {
        const IVec<D> lo = cell_of(boxes[s].min), hi = cell_of(boxes[s].max);
        for_each_node<D>(lo, hi, [&](IVec<D> c) {
          const std::size_t at = flat(c);
          if (pass == 0) ++start_[at + 1];
          else ids_[fill_[at]++] = s;
        });
      }
      if (pass == 0) {
        for (std::size_t i = 0; i < n; ++i) start_[i + 1] += start_[i];
        ids_.resize(start_[n]);
        fill_.assign(start_.begin(), start_.end() - 1);
      }
    }
  }
  /// True when `p` lies strictly inside one of the shapes.
  bool inside_any(VecN<D> p) const {
    const std::size_t at = flat(cell_of(p));
    for (std::uint32_t i = start_[at]; i < start_[at + 1]; ++i) {
      const std::uint32_t s = ids_[i];
      if (!contains(boxes_[s], p)) continue;
      if (closest_point(shapes_[s].shape, shapes_[s].xf, p).distance < 0.0f) return true;
    }
    return false;
  }

 private:
  static bool contains(const AabbN<D>& box, VecN<D> p) {
    for (int k = 0; k < D; ++k)
      if (p[k] < box.min[k] || p[k] > box.max[k]) return false;
    return true;
  }
  IVec<D> cell_of(VecN<D> p) const {
    IVec<D> c;
    for (int k = 0; k < D; ++k)
      c[k] = static_cast<int>(std::clamp(std::floor((p[k] - origin_[k]) / cell_), 0.0f, float(dims_[k] - 1)));
    return c;
  }
  std::size_t flat(IVec<D> c) const {
    std::size_t at = static_cast<std::size_t>(c[D - 1]);
    for (int k = D - 2; k >= 0; --k) at = at * static_cast<std::size_t>(dims_[k]) + static_cast<std::size_t>(c[k]);
    return at;
  }
  std::span<const PlacedShapeN<D>> shapes_;
  const std::vector<AabbN<D>>& boxes_;
  VecN<D> origin_;
  float cell_;
  IVec<D> dims_{1};
  std::vector<std::uint32_t> start_, ids_, fill_;
};

/// True when surface point `c` of one shape is on the union's surface: a point a probe's step
/// away from it, outward, is inside no shape. `outward` is zero when the node lies on the
/// shape's surface (within a step); then the 2^D diagonal directions are probed (a probe along an axis could
/// run along a seam between abutting tiles, on both their surfaces and inside neither).
template <int D>
bool on_union_surface(const ShapeBins<D>& bins, VecN<D> c, VecN<D> outward, float step) {
  if (glm::dot(outward, outward) > 0.0f) return !bins.inside_any(c + step * outward);
  for (int corner = 0; corner < (1 << D); ++corner) {
    VecN<D> probe = c;
    for (int k = 0; k < D; ++k) probe[k] += ((corner >> k) & 1) ? step : -step;
    if (!bins.inside_any(probe)) return true;
  }
  return false;
}

/// The shapes' exact band: every node within a shape's box grown by the band gets the shape's
/// containment, and its surface point when that is the nearest on the union's surface so far.
template <int D, class Store>
void shapes_band(std::span<const PlacedShapeN<D>> shapes, const std::vector<AabbN<D>>& boxes, const ShapeBins<D>& bins,
                 float band_distance, Store& store) {
  const FieldGridN<D>& grid = store.grid;
  const float step = kSurfaceProbeVoxels * grid.voxel;
  for (std::size_t s = 0; s < shapes.size(); ++s) {
    AabbN<D> box = boxes[s];
    box.min -= VecN<D>(band_distance);
    box.max += VecN<D>(band_distance);
    IVec<D> lo, hi;
    node_range(grid, box, lo, hi);
    for_each_node<D>(lo, hi, [&](IVec<D> i) {
      const VecN<D> p = grid.node(i);
      const PointQueryN<D> q = closest_point(shapes[s].shape, shapes[s].xf, p);
      const bool inside = q.distance < 0.0f;
      const float d = std::abs(q.distance);
      if (!inside && d > band_distance) return;  // outside and beyond the band: nothing to say
      if constexpr (Store::kSparse) {
        if (d > band_distance) return;  // a sparse field keeps the band only
      }
      const std::size_t at = store.slot(i);
      std::uint8_t& state = store.state[at];
      state |= kSignKnown;
      // A node on this shape's surface is inside the union when every way off it is (a seam).
      if (inside || (d <= step && !(state & kInside) && !on_union_surface(bins, p, VecN<D>(0.0f), step))) state |= kInside;
      if (d > band_distance || d * d >= store.distance[at]) return;
      const VecN<D> away = inside ? q.closest - p : p - q.closest;
      const float length = glm::length(away);
      // Off the surface by less than a probe's step, the direction is rounding noise: probe all ways.
      const VecN<D> outward = length > step ? away / length : VecN<D>(0.0f);
      if (!on_union_surface(bins, q.closest, outward, step)) return;  // a seam inside the union
      store.distance[at] = d * d;
      store.closest[at] = q.closest;
      state |= kExact | kHasValue;
    });
  }
}

/// Nodes of a row a triangle's band kernel handles at once (its results sit in arrays this long).
constexpr int kBandChunk = 64;

/// The band kernel takes four nodes of a row at once, in lanes (collide/core/lanes.hpp: SSE2
/// on x86-64), every lane's operation as the float expression does it, in the same order.
using simd::Lanes;
using simd::LaneMask;
using simd::select;
using simd::splat;
constexpr int kBandLanes = 4;
static_assert(kBandChunk % kBandLanes == 0);

/// x clamped to [0, 1] by selects.
inline Lanes clamp01(Lanes x) {
  const Lanes zero = splat(0.0f), one = splat(1.0f);
  x = select(x > zero, x, zero);
  return select(x < one, x, one);
}

/// A triangle prepared for the distances of many nodes: its edges, their reciprocal squared
/// lengths, its normal and the in-plane inward normals of its edges.
struct BandTriangle {
  Vec3 a, b, c, ab, bc, ca, n, in_ab, in_bc, in_ca;
  float inv_ab = 0.0f, inv_bc = 0.0f, inv_ca = 0.0f, inv_nn = 0.0f;
  bool has_face = false;
  std::array<Vec3, 3> edge_inward{};  ///< unit inward normals of ab, bc, ca in the plane

  BandTriangle(Vec3 a_, Vec3 b_, Vec3 c_) : a(a_), b(b_), c(c_), ab(b_ - a_), bc(c_ - b_), ca(a_ - c_) {
    const auto inverse = [](float x) { return x > 0.0f ? 1.0f / x : 0.0f; };
    inv_ab = inverse(glm::dot(ab, ab));
    inv_bc = inverse(glm::dot(bc, bc));
    inv_ca = inverse(glm::dot(ca, ca));
    n = glm::cross(ab, -ca);
    const float nn = glm::dot(n, n);
    has_face = nn > 0.0f && std::isfinite(1.0f / nn);
    inv_nn = has_face ? 1.0f / nn : 0.0f;
    in_ab = glm::cross(n, ab);
    in_bc = glm::cross(n, bc);
    in_ca = glm::cross(n, ca);
    const Vec3 inward[3] = {in_ab, in_bc, in_ca};
    for (int e = 0; e < 3; ++e) {
      const float length = glm::length(inward[e]);
      edge_inward[e] = length > 0.0f ? inward[e] / length : Vec3(0.0f);
    }
  }
};

/// A BandTriangle's numbers in lanes (each in every lane), made once per triangle: the kernel
/// runs row after row, and broadcasting them at every row (as the compiler's own vectorisation
/// of the per-node loop did, 290 instructions a row) cost more than a short row's distances.
struct BandKernel {
  using F = Lanes;
  using Mask = LaneMask;
  F ax, ay, az, bx, by, bz, cx, cy, cz;
  F abx, aby, abz, bcx, bcy, bcz, cax, cay, caz;
  F nx, ny, nz, iabx, iaby, iabz, ibcx, ibcy, ibcz, icax, icay, icaz;
  F inv_ab, inv_bc, inv_ca, inv_nn, zero;
  F ux, uy, uz, mabx, maby, mabz, mbcx, mbcy, mbcz, mcax, mcay, mcaz;  ///< unit normal, unit inward edge normals
  Mask has_face;

  explicit BandKernel(const BandTriangle& t) {
    ax = splat(t.a.x), ay = splat(t.a.y), az = splat(t.a.z), bx = splat(t.b.x), by = splat(t.b.y), bz = splat(t.b.z);
    cx = splat(t.c.x), cy = splat(t.c.y), cz = splat(t.c.z);
    abx = splat(t.ab.x), aby = splat(t.ab.y), abz = splat(t.ab.z);
    bcx = splat(t.bc.x), bcy = splat(t.bc.y), bcz = splat(t.bc.z);
    cax = splat(t.ca.x), cay = splat(t.ca.y), caz = splat(t.ca.z);
    nx = splat(t.n.x), ny = splat(t.n.y), nz = splat(t.n.z);
    iabx = splat(t.in_ab.x), iaby = splat(t.in_ab.y), iabz = splat(t.in_ab.z);
    ibcx = splat(t.in_bc.x), ibcy = splat(t.in_bc.y), ibcz = splat(t.in_bc.z);
    icax = splat(t.in_ca.x), icay = splat(t.in_ca.y), icaz = splat(t.in_ca.z);
    inv_ab = splat(t.inv_ab), inv_bc = splat(t.inv_bc), inv_ca = splat(t.inv_ca), inv_nn = splat(t.inv_nn);
    zero = splat(0.0f);
    has_face = simd::mask(t.has_face);
    const Vec3 u = t.has_face ? t.n * std::sqrt(t.inv_nn) : Vec3(0.0f);  // no face: a bound of 0
    const std::array<Vec3, 3> m = t.has_face ? t.edge_inward : std::array<Vec3, 3>{};
    ux = splat(u.x), uy = splat(u.y), uz = splat(u.z);
    mabx = splat(m[0].x), maby = splat(m[0].y), mabz = splat(m[0].z);
    mbcx = splat(m[1].x), mbcy = splat(m[1].y), mbcz = splat(m[1].z);
    mcax = splat(m[2].x), mcay = splat(m[2].y), mcaz = splat(m[2].z);
  }

  /// A lower bound of the squared distance from the node(s) at (px, py, pz) to the triangle:
  /// the plane's distance squared plus the square of the farthest the node's projection lies
  /// outside an edge's line (the triangle lies inside all three). About a fifth of `node`'s
  /// arithmetic; 0 for a triangle without a face.
  F lower_bound(F px, F py, F pz) const {
    const F apx = px - ax, apy = py - ay, apz = pz - az;
    const F h = apx * ux + apy * uy + apz * uz;
    const F out_ab = -(apx * mabx + apy * maby + apz * mabz);
    const F out_bc = -((px - bx) * mbcx + (py - by) * mbcy + (pz - bz) * mbcz);
    const F out_ca = -((px - cx) * mcax + (py - cy) * mcay + (pz - cz) * mcaz);
    const F out = simd::max(simd::max(zero, out_ab), simd::max(out_bc, out_ca));
    return h * h + out * out;
  }

  /// Squared distance and closest point of the node(s) at (px, py, pz): the closest point of a
  /// triangle is its projection onto the plane when that lies inside all three edges, else the
  /// nearest of the three edges' closest points (Ericson, RTCD 5.1.5 and 5.1.2, every region
  /// evaluated and the answer picked by selects: no branch on the region, which Ericson's order
  /// mispredicts from node to node).
  void node(F px, F py, F pz, F& d2, F& qx, F& qy, F& qz) const {
    const F apx = px - ax, apy = py - ay, apz = pz - az, bpx = px - bx, bpy = py - by, bpz = pz - bz;
    const F cpx = px - cx, cpy = py - cy, cpz = pz - cz;
    // Edge ab: parameter clamped to the segment, then the offset from the closest point.
    const F t1 = clamp01((apx * abx + apy * aby + apz * abz) * inv_ab);
    const F e1x = apx - t1 * abx, e1y = apy - t1 * aby, e1z = apz - t1 * abz;
    const F t2 = clamp01((bpx * bcx + bpy * bcy + bpz * bcz) * inv_bc);
    const F e2x = bpx - t2 * bcx, e2y = bpy - t2 * bcy, e2z = bpz - t2 * bcz;
    const F t3 = clamp01((cpx * cax + cpy * cay + cpz * caz) * inv_ca);
    const F e3x = cpx - t3 * cax, e3y = cpy - t3 * cay, e3z = cpz - t3 * caz;
    const F s1 = e1x * e1x + e1y * e1y + e1z * e1z, s2 = e2x * e2x + e2y * e2y + e2z * e2z,
            s3 = e3x * e3x + e3y * e3y + e3z * e3z;
    F best = s1, ex = e1x, ey = e1y, ez = e1z;
    const Mask take2 = s2 < best;
    ex = select(take2, e2x, ex);
    ey = select(take2, e2y, ey);
    ez = select(take2, e2z, ez);
    best = select(take2, s2, best);
    const Mask take3 = s3 < best;
    ex = select(take3, e3x, ex);
    ey = select(take3, e3y, ey);
    ez = select(take3, e3z, ez);
    best = select(take3, s3, best);
    // The face: the projection lies inside every edge.
    const F h = (apx * nx + apy * ny + apz * nz) * inv_nn;
    const Mask inside = has_face & (apx * iabx + apy * iaby + apz * iabz >= zero) &
                        (bpx * ibcx + bpy * ibcy + bpz * ibcz >= zero) & (cpx * icax + cpy * icay + cpz * icaz >= zero);
    ex = select(inside, h * nx, ex);
    ey = select(inside, h * ny, ey);
    ez = select(inside, h * nz, ez);
    const F face = ex * ex + ey * ey + ez * ez;
    d2 = select(inside, face, best);
    qx = px - ex;
    qy = py - ey;
    qz = pz - ez;
  }
};

/// band_row skips a group of nodes when the triangle's lower bound, less this fraction of it
/// and kBandBoundSlackVoxels^2 voxels^2, is no nearer than any node's distance so far: the
/// bound and the kernel's distance round differently (a few ulps), and a skipped node must be
/// one the kernel would not have written.
constexpr float kBandBoundSlack = 1e-5f;
constexpr float kBandBoundSlackVoxels = 1e-3f;
/// A row limit (RowLimits) whose value changes by less than this fraction of a voxel from node to
/// node along the row is taken as parallel to the row: the whole row passes or fails it.
constexpr float kRowSlopeVoxels = 1e-6f;

/// Squared distances and closest points of the nodes (x0 + l) * voxel + ox, y, z of a row, l in
/// [0, count) (count <= kBandChunk), into arrays of kBandChunk: kBandLanes nodes at a time, the
/// last group padded with nodes past the row. Returns the nodes to write as bits (bit l: node
/// l within `band_squared` and, with `current` (each node's squared distance so far, and
/// readable up to the last group's end), nearer than that). With `current`, a group whose every
/// node the triangle's lower bound puts no nearer than its distance so far (or the band) is not
/// worked out.
inline std::uint64_t band_row(const BandKernel& k, float ox, float voxel, int x0, int count, float py, float pz,
                              float band_squared, const float* current, float* d2, float* qx, float* qy, float* qz) {
  const Lanes y = splat(py), z = splat(pz), origin = splat(ox), step = splat(voxel);
  const Lanes band = splat(band_squared);
  const Lanes keep_fraction = splat(1.0f - kBandBoundSlack);
  const Lanes slack = splat(kBandBoundSlackVoxels * kBandBoundSlackVoxels * voxel * voxel);
  std::uint64_t write = 0;
  for (int l = 0; l < count; l += kBandLanes) {
    // float(x0 + l + lane) * voxel + ox, per lane as the scalar form computes it.
    const Lanes x = simd::iota(x0 + l) * step + origin;
    Lanes so_far = splat(std::numeric_limits<float>::infinity());
    if (current != nullptr) {
      so_far = simd::load(current + l);
      const Lanes limit = simd::min(so_far, band);
      if (simd::lane_bits(k.lower_bound(x, y, z) * keep_fraction - slack < limit) == 0) continue;
    }
    Lanes d, px, py_, pz_;
    k.node(x, y, z, d, px, py_, pz_);
    simd::store(d2 + l, d);
    simd::store(qx + l, px);
    simd::store(qy + l, py_);
    simd::store(qz + l, pz_);
    write |= std::uint64_t{simd::lane_bits((d <= band) & (d < so_far))} << l;
  }
  return count >= 64 ? write : write & ((std::uint64_t{1} << count) - 1);
}

/// floor(x) and ceil(x) as ints for a row's node bounds, x first clamped to [lo - 2, hi + 2]
/// (a bound beyond the row's nodes cuts nothing more; NaN goes to lo - 2): no conversion
/// overflows, and no library floor or ceiling (SSE2 has no rounding instruction).
inline float node_clamp(float x, int lo, int hi) {
  const float a = static_cast<float>(lo - 2), b = static_cast<float>(hi + 2);
  x = x > a ? x : a;
  return x < b ? x : b;
}
inline int node_floor(float x, int lo, int hi) {
  x = node_clamp(x, lo, hi);
  const int i = static_cast<int>(x);  // towards zero
  return i - (static_cast<float>(i) > x ? 1 : 0);
}
inline int node_ceil(float x, int lo, int hi) {
  x = node_clamp(x, lo, hi);
  const int i = static_cast<int>(x);
  return i + (static_cast<float>(i) < x ? 1 : 0);
}

/// The nodes [lo, hi] of the box of triangle (a, b, c) grown by the band, clamped to the grid;
/// false when none. Corners relative to the mesh's origin (grid.origin = mesh.origin +
/// local_origin).
bool triangle_band_nodes(Vec3 a, Vec3 b, Vec3 c, const FieldGrid3& grid, Vec3 local_origin, float band_distance,
                         glm::ivec3& lo, glm::ivec3& hi) {
  const Aabb3 box{glm::min(glm::min(a, b), c) - Vec3(band_distance) - local_origin,
                  glm::max(glm::max(a, b), c) + Vec3(band_distance) - local_origin};
  FieldGrid3 local = grid;
  local.origin = Vec3(0.0f);
  node_range(local, box, lo, hi);
  return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
}

/// Which nodes of a grid row can lie within the band of a triangle: those within the band of its
/// plane (|n . (p - a)| <= band) and, for a triangle with a face, not farther than the band
/// outside any edge's line (m . (p - v) >= -band, m the edge's unit inward normal in the plane:
/// the triangle lies on the inner side of each). Along a row each of the five limits is linear
/// in the node index x, value = A + slope x, so it bounds x from one side; the four values (the
/// three edges and the plane) are worked out side by side in lanes, and the row's range is the
/// largest lower bound to the smallest upper bound, with a node of slack on each side for the
/// rounding of the bounds (their reciprocal slopes are made once per triangle). Worked out one by
/// one they were about a quarter of the scatter's instructions, rows being short (the torus of
/// bench_sdf at 512k nodes: 1.15M groups of four nodes in 550k rows); in lanes the torus's build
/// there takes 10% fewer instructions (964M -> 864M, callgrind) and 9% less time, undulating.obj
/// 8% fewer, dungeon.obj at 4.7M nodes 4% fewer, the fields bit for bit the same.
struct RowLimits {
  Lanes my, mz, vy, vz;      ///< lanes 0-2: the edges' inward normals and a corner on each; 3: the plane's
  Lanes x_term;              ///< m.x (origin.x - v.x): the part of A from the row's x origin
  Lanes inverse_slope;       ///< 1 / (m.x voxel) where sloped, else 0
  Lanes limit_low, limit_high;  ///< value >= limit_low and <= limit_high (+inf for the edges)
  LaneMask sloped, rising;

  RowLimits(const BandTriangle& tri, float voxel, float origin_x, float band) {
    const float length = glm::length(tri.n);
    const Vec3 n = length > 0.0f ? tri.n / length : Vec3(0.0f);
    // Without a face the edges limit nothing (value 0).
    const std::array<Vec3, 3> m = tri.has_face ? tri.edge_inward : std::array<Vec3, 3>{};
    const Lanes mx = simd::lanes(m[0].x, m[1].x, m[2].x, n.x);
    my = simd::lanes(m[0].y, m[1].y, m[2].y, n.y);
    mz = simd::lanes(m[0].z, m[1].z, m[2].z, n.z);
    const Lanes vx = simd::lanes(tri.a.x, tri.b.x, tri.c.x, tri.a.x);
    vy = simd::lanes(tri.a.y, tri.b.y, tri.c.y, tri.a.y);
    vz = simd::lanes(tri.a.z, tri.b.z, tri.c.z, tri.a.z);
    x_term = mx * (splat(origin_x) - vx);
    const Lanes slope = mx * splat(voxel);
    sloped = simd::max(slope, -slope) > splat(kRowSlopeVoxels * voxel);
    inverse_slope = select(sloped, splat(1.0f) / select(sloped, slope, splat(1.0f)), splat(0.0f));
    rising = inverse_slope > splat(0.0f);
    limit_low = splat(-band);
    constexpr float kNoLimit = std::numeric_limits<float>::infinity();
    limit_high = simd::lanes(kNoLimit, kNoLimit, kNoLimit, band);
  }
  /// The part of A from the slice's z (the same for every row of the slice).
  Lanes z_term(float pz) const { return mz * (splat(pz) - vz); }
  /// Narrows [x0, x1] to the row at (py, pz)'s nodes that can lie within the band; false when
  /// none can (a limit parallel to the row that the whole row fails).
  bool row(float py, Lanes z_at, int& x0, int& x1) const {
    const Lanes value = (x_term + my * (splat(py) - vy)) + z_at;  // A: the value at node x = 0
    if (simd::lane_bits(~sloped & ((value < limit_low) | (value > limit_high))) != 0) return false;
    const Lanes at_low = (limit_low - value) * inverse_slope, at_high = (limit_high - value) * inverse_slope;
    const Lanes infinity = splat(std::numeric_limits<float>::infinity());
    const Lanes lower = select(sloped, select(rising, at_low, at_high), -infinity);
    const Lanes upper = select(sloped, select(rising, at_high, at_low), infinity);
    const float largest_lower = -simd::horizontal_min(-lower)[0], smallest_upper = simd::horizontal_min(upper)[0];
    const int lo = x0, hi = x1;
    x0 = std::max(lo, node_ceil(largest_lower, lo, hi) - 1);
    x1 = std::min(hi, node_floor(smallest_upper, lo, hi) + 1);
    return true;
  }
};

/// A mesh's exact band, scattered per triangle (as OpenVDB's meshToVolume (Museth 2013) scatters
/// each triangle into the voxels near it): each triangle visits, row by row, the nodes within the
/// band of its plane and inside its box grown by the band, and keeps the nearer of its distance
/// and the node's. Coordinates relative to the mesh's origin.
template <class Store>
void mesh_band_scatter(const TriangleMesh& mesh, Vec3 local_origin, float band_distance, Store& store) {
  const FieldGrid3& grid = store.grid;
  const float band_squared = band_distance * band_distance;
  alignas(32) std::array<float, kBandChunk> d2, qx, qy, qz;
  alignas(32) std::array<float, kBandChunk> so_far{};  // dense, at the grid's end: the row's distances so far, padded
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
    glm::ivec3 lo, hi;
    if (!triangle_band_nodes(a, b, c, grid, local_origin, band_distance, lo, hi)) continue;
    const BandTriangle tri(a, b, c);
    const BandKernel kernel(tri);
    const RowLimits limits(tri, grid.voxel, local_origin.x, band_distance);
    for (int z = lo.z; z <= hi.z; ++z) {
      const float pz = local_origin.z + float(z) * grid.voxel;
      const Lanes z_term = limits.z_term(pz);
      for (int y = lo.y; y <= hi.y; ++y) {
        const float py = local_origin.y + float(y) * grid.voxel;
        int x0 = lo.x, x1 = hi.x;
        if (!limits.row(py, z_term, x0, x1)) continue;
        for (int first = x0; first <= x1; first += kBandChunk) {
          const int count = std::min(kBandChunk, x1 - first + 1);
          // A dense row's nodes are consecutive: their distances so far let band_row skip
          // groups and pick the nodes to write without a branch per node.
          const float* current = nullptr;
          std::size_t at0 = 0;
          if constexpr (!Store::kSparse) {
            at0 = store.slot({first, y, z});
            current = &store.distance[at0];
            // The last group reads up to kBandLanes - 1 nodes past the row (the next row's:
            // they only keep a group from being skipped, and are never written); at the end
            // of the grid a copy padded with 0 instead.
            const std::size_t padded = static_cast<std::size_t>((count + kBandLanes - 1) / kBandLanes * kBandLanes);
            if (at0 + padded > store.distance.size()) {
              for (std::size_t l = 0; l < padded; ++l) so_far[l] = l < static_cast<std::size_t>(count) ? current[l] : 0.0f;
              current = so_far.data();
            }
          }
          for (std::uint64_t write = band_row(kernel, local_origin.x, grid.voxel, first, count, py, pz, band_squared, current,
                                              d2.data(), qx.data(), qy.data(), qz.data());
               write != 0; write &= write - 1) {
            const int l = std::countr_zero(write);
            std::size_t at = at0 + static_cast<std::size_t>(l);
            if constexpr (Store::kSparse) {
              at = store.slot({first + l, y, z});
              if (d2[l] >= store.distance[at]) continue;
            }
            store.distance[at] = d2[l];
            if (store.keeps_closest()) store.closest[at] = Vec3(qx[l], qy[l], qz[l]);
            store.state[at] |= kExact | kHasValue;
          }
        }
      }
    }
  }
}

/// The nodes near a mesh, for mesh_band_nearest: the grid cut into regions of kFieldBrickSize^3
/// nodes (the sparse store's bricks), each region a 64-bit mask of its 2^3-node blocks that a
/// triangle's box grown by the band touches.
struct BandMarks {
  static constexpr int kBlock = 2;                          ///< nodes per side of a block
  static constexpr int kPerSide = kFieldBrickSize / kBlock;  ///< blocks per side of a region
  static_assert(kPerSide * kPerSide * kPerSide == 64);
  glm::ivec3 regions{0};
  std::vector<std::uint64_t> masks;  ///< per region, bit (z * 4 + y) * 4 + x per block
  std::size_t blocks = 0;            ///< blocks marked
  double rows = 0.0;                 ///< grid rows the scatter's triangles visit (their boxes' y-z extents)

  std::size_t region_index(glm::ivec3 r) const {
    return (std::size_t(r.z) * std::size_t(regions.y) + std::size_t(r.y)) * std::size_t(regions.x) + std::size_t(r.x);
  }
};

/// Memory of BandMarks, bytes per grid node (one 8-byte mask per kFieldBrickSize^3 nodes).
constexpr double kBandMarkBytesPerNode = 8.0 / (kFieldBrickSize * kFieldBrickSize * kFieldBrickSize);

/// One pass over the triangles: their boxes grown by the band, as blocks marked and rows counted.
BandMarks mark_band(const TriangleMesh& mesh, const FieldGrid3& grid, Vec3 local_origin, float band_distance) {
  BandMarks marks;
  marks.regions = (grid.dims + (kFieldBrickSize - 1)) / kFieldBrickSize;
  marks.masks.assign(std::size_t(marks.regions.x) * std::size_t(marks.regions.y) * std::size_t(marks.regions.z), 0);
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    glm::ivec3 lo, hi;
    if (!triangle_band_nodes(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2), grid, local_origin,
                             band_distance, lo, hi)) {
      continue;
    }
    marks.rows += double(hi.y - lo.y + 1) * double(hi.z - lo.z + 1);
    // The box's blocks, a region's at once: a row of blocks is a run of bits, a slice of rows
    // and the box copies of it (bit by bit, a coarse grid's large boxes took 12% of dungeon's
    // build at 64k nodes).
    const glm::ivec3 first = lo / BandMarks::kBlock, last = hi / BandMarks::kBlock;
    for_each_node<3>(first / BandMarks::kPerSide, last / BandMarks::kPerSide, [&](glm::ivec3 r) {
      const glm::ivec3 a = glm::max(first - r * BandMarks::kPerSide, 0);
      const glm::ivec3 b = glm::min(last - r * BandMarks::kPerSide, BandMarks::kPerSide - 1);
      const std::uint64_t row = ((std::uint64_t{1} << (b.x - a.x + 1)) - 1) << a.x;
      std::uint64_t slice = 0, box = 0;
      for (int y = a.y; y <= b.y; ++y) slice |= row << (y * BandMarks::kPerSide);
      for (int z = a.z; z <= b.z; ++z) box |= slice << (z * BandMarks::kPerSide * BandMarks::kPerSide);
      marks.masks[marks.region_index(r)] |= box;
    });
  }
  for (const std::uint64_t m : marks.masks) marks.blocks += static_cast<std::size_t>(std::popcount(m));
  return marks;
}

/// Slack of mesh_band_nearest's bound: this fraction of the bound, plus this fraction of the
/// grid's largest coordinate (the float rounding of either is a few ulps of those).
inline constexpr float kNearestBoundSlack = 1e-4f;

/// A mesh's exact band, node by node: each node of a marked block asks the mesh's BVH for its
/// nearest point within the band (TriangleBvh::nearest, branch and bound; a block's nodes in one
/// batch, one descent of the tree), bounded further by the node's distance to the last nearest
/// point found (a point of the surface: the node's own nearest point is no farther). Returns the
/// queries made. Coordinates relative to the mesh's origin, as the BVH's.
template <class Store>
std::size_t mesh_band_nearest(const TriangleMesh& mesh, const BandMarks& marks, Vec3 local_origin,
                              float band_distance, Store& store) {
  constexpr int kBlockNodes = BandMarks::kBlock * BandMarks::kBlock * BandMarks::kBlock;
  static_assert(kBlockNodes <= kBvhNearestBatch);
  const FieldGrid3& grid = store.grid;
  const float band_squared = band_distance * band_distance;
  const Vec3 far_corner = local_origin + Vec3(grid.dims - 1) * grid.voxel;
  const Vec3 magnitude = glm::max(glm::abs(local_origin), glm::abs(far_corner));
  const float slack = kNearestBoundSlack * std::max({magnitude.x, magnitude.y, magnitude.z});
  std::size_t queries = 0;
  bool seeded = false;  // a node has found its nearest point: `seed`
  Vec3 seed{0.0f};
  std::array<glm::ivec3, kBlockNodes> nodes;
  std::array<Vec3, kBlockNodes> points;
  std::array<float, kBlockNodes> bounds;
  std::array<BvhNearest, kBlockNodes> nearest;
  for_each_node<3>(glm::ivec3(0), marks.regions - 1, [&](glm::ivec3 r) {
    for (std::uint64_t m = marks.masks[marks.region_index(r)]; m != 0; m &= m - 1) {
      const int bit = std::countr_zero(m);
      const glm::ivec3 in{bit % BandMarks::kPerSide, (bit / BandMarks::kPerSide) % BandMarks::kPerSide,
                          bit / (BandMarks::kPerSide * BandMarks::kPerSide)};
      const glm::ivec3 first = r * kFieldBrickSize + in * BandMarks::kBlock;
      std::size_t n = 0;
      for_each_node<3>(first, glm::min(first + (BandMarks::kBlock - 1), grid.dims - 1), [&](glm::ivec3 i) {
        const Vec3 p = local_origin + Vec3(i) * grid.voxel;
        float bound = band_squared;
        if (seeded) {
          const float reach = glm::length(p - seed) * (1.0f + kNearestBoundSlack) + slack;
          bound = std::min(bound, reach * reach);
        }
        nodes[n] = i;
        points[n] = p;
        bounds[n++] = bound;
      });
      queries += n;
      mesh.bvh.nearest(std::span(points.data(), n), std::span(bounds.data(), n), std::span(nearest.data(), n));
      for (std::size_t k = 0; k < n; ++k) {
        const float d2 = nearest[k].distance_squared;
        if (nearest[k].triangle == std::numeric_limits<std::uint32_t>::max() || !(d2 <= band_squared)) continue;
        seeded = true;
        seed = nearest[k].closest.point;
        const std::size_t at = store.slot(nodes[k]);
        store.distance[at] = d2;
        if (store.keeps_closest()) store.closest[at] = nearest[k].closest.point;
        store.state[at] |= kExact | kHasValue;
      }
    }
  });
  return queries;
}

/// How many of the scatter's rows one nearest-point query is taken to cost. Where the two ways
/// take the same time (each forced, alternating in one process, 9 repetitions, AMD EPYC, stop
/// 74): queries 0-15% slower at 2.2-2.6 rows a query on dungeon.obj, the torus of bench_sdf and
/// undulating.obj, even at 2.8 (dungeon), 4-12% faster at 3.2-4.7. It was 2.0 before a row's
/// limits went into lanes (stop 74), 3.5 before a block's queries shared one descent of the BVH
/// (stop 73), 2.2 before the scatter's groups were skipped by a lower bound (stop 72).
inline constexpr double kNearestQueryRows = 2.75;

/// A mesh's exact band, the cheaper of two ways: scattered per triangle (its work grows with the
/// rows each triangle's box visits) or node by node through the BVH (its work grows with the
/// nodes near the mesh). On a grid coarse beside the triangles each band node lies within the
/// band of tens of triangles and the scatter visits it for each (dungeon.obj at 64k nodes:
/// 448k rows for 17.9k band nodes); on a fine one the scatter's rows are short and few per node.
/// Returns the nearest-point queries made (0: scattered).
template <class Store>
std::size_t mesh_band(const TriangleMesh& mesh, Vec3 local_origin, float band_distance, Store& store) {
  const BandMarks marks = mark_band(mesh, store.grid, local_origin, band_distance);
  const double candidates = double(marks.blocks) * BandMarks::kBlock * BandMarks::kBlock * BandMarks::kBlock;
  if (candidates * kNearestQueryRows < marks.rows) return mesh_band_nearest(mesh, marks, local_origin, band_distance, store);
  mesh_band_scatter(mesh, local_origin, band_distance, store);
  return 0;
}

// ---- stage 3: propagation ------------------------------------------------------------------

/// 2^D sweeps: each node without an exact value takes an upstream neighbour's closest point
/// when it is nearer, and every node whose sign is unknown takes the inside bit of an upstream
/// neighbour whose sign is known (or was copied). Copying is exact for a node more than a voxel
/// from the surface: no surface lies between it and a neighbour. After the 2^D orders every
/// node is downstream of a node with a known sign in one of them. `position` maps a node to the
/// coordinates the closest points are in.
/// One sweep of `propagate` over a dense store, with neighbours found by strides (the generic
/// sweep below computes every node's index afresh; this is the build's hot loop).
template <int D, class Position>
void propagate_dense(DenseStore<D>& store, IVec<D> step, Position& position) {
  const FieldGridN<D>& grid = store.grid;
  constexpr std::uint8_t kSignValid = kSignKnown | kSignCopied;
  std::uint8_t* state = store.state.data();
  float* distance = store.distance.data();
  VecN<D>* closest = store.closest.data();
  const int nx = grid.dims[0];
  // One neighbour's offer to the node at `at` (position p, computed on first need).
  auto offer = [&](std::ptrdiff_t at, std::ptrdiff_t from, const VecN<D>& p) {
    std::uint8_t& here = state[at];
    const std::uint8_t source = state[from];
    if (!(here & kSignValid) && (source & kSignValid))
      here = static_cast<std::uint8_t>((here & ~kInside) | (source & kInside) | kSignCopied);
    if ((here & kExact) || !(source & kHasValue)) return;
    const VecN<D> offset = p - closest[from];
    const float d2 = glm::dot(offset, offset);
    if ((here & kHasValue) && d2 >= distance[at]) return;
    distance[at] = d2;
    closest[at] = closest[from];
    here |= kHasValue;
  };
  IVec<D> rows_hi = grid.dims - 1;
  rows_hi[0] = 0;
  // Rows in sweep order; along each row a tight loop with the row's neighbours by stride.
  sweep_box<D>(IVec<D>(0), rows_hi, step, [&](IVec<D> row) {
    std::array<std::ptrdiff_t, D> upstream{};  // offset of the upstream row neighbour per axis (0: none)
    std::ptrdiff_t stride = nx;
    for (int k = 1; k < D; ++k) {
      const bool edge = step[k] > 0 ? row[k] == 0 : row[k] == grid.dims[k] - 1;
      upstream[k] = edge ? 0 : step[k] * stride;
      stride *= grid.dims[k];
    }
    const auto base = static_cast<std::ptrdiff_t>(grid.index(row));
    const int x0 = step[0] > 0 ? 0 : nx - 1, x_end = step[0] > 0 ? nx : -1;
    IVec<D> i = row;
    for (int x = x0; x != x_end; x += step[0]) {
      const std::ptrdiff_t at = base + x;
      if ((state[at] & kExact) && (state[at] & kSignValid)) continue;
      i[0] = x;
      const VecN<D> p = position(i);
      if (x != x0) offer(at, at - step[0], p);
      for (int k = 1; k < D; ++k)
        if (upstream[k] != 0) offer(at, at - upstream[k], p);
    }
  });
}

/// Bytes per node propagate_mesh_dense holds while it runs: the closest points again, one array
/// per coordinate.
constexpr std::size_t kPropagateBytesPerNode = 3 * sizeof(float);

/// `propagate` for a mesh's dense build, whose every node is signed already (sign_blocks):
/// closest-point propagation (Danielsson 1980) with distances only and no state: an offer from a
/// node without a closest point has an infinite distance (kNoClosestPoint), and one to a band
/// node cannot beat its exact distance (beyond rounding, which then swaps equally near points).
/// Two passes over the planes (z up, then down), each plane as Danielsson's two-dimensional
/// 4SED: its rows in y order, each taking the offers of the row upstream in y (and, in the y
/// pass up, of the same row in the plane upstream in z), then scanned along x both ways; then
/// the rows again in the opposite y order. Four band nodes side by side take no offers at all
/// (their states read as one word): on undulating.obj at 822k nodes 4.7% fewer instructions in
/// the whole build, the torus 3.3%, dungeon.obj 0.8-1.3%; the error against the exact build the
/// same (band nodes no longer swap to an equally near point by rounding). An upstream row
/// offers three nodes to each node: the one in line and its two neighbours along x (with the
/// one in line alone the mean error was 2-5% above the octant sweeps' of the generic
/// `propagate`). Against the exact build on dungeon.obj, undulating.obj and bench_sdf's torus,
/// 64k to 4M nodes: mean error 25-40% below the octant sweeps', the largest never above theirs.
/// A pass reads the grid from memory once (the plane and the one before it stay in the cache)
/// where the 8 octant sweeps read it eight times. The upstream offers are independent along a row: four nodes a step in lanes, on one
/// array per coordinate (on the Vec3s, 12 bytes apart, GCC made each node a branch), each node
/// loaded and stored once for all its offers; the scans carry the upstream node's closest point
/// in registers. The closest points (the mesh's local frame) are copied into those arrays and,
/// when `keep_closest` (the field keeps them), back in mesh space (plus `mesh_origin`).
void propagate_mesh_dense(DenseStore<3>& store, Vec3 local_origin, Vec3 mesh_origin, bool keep_closest) {
  const FieldGrid3& grid = store.grid;
  const std::size_t count = store.closest.size();
  std::vector<float> xs = large_page_vector(count, 0.0f);
  std::vector<float> ys = large_page_vector(count, 0.0f);
  std::vector<float> zs = large_page_vector(count, 0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    xs[i] = store.closest[i].x;
    ys[i] = store.closest[i].y;
    zs[i] = store.closest[i].z;
  }
  float* const distance = store.distance.data();
  float* const closest_x = xs.data();
  float* const closest_y = ys.data();
  float* const closest_z = zs.data();
  const int nx = grid.dims.x, ny = grid.dims.y, nz = grid.dims.z;
  const float voxel = grid.voxel;
  const std::ptrdiff_t sy = nx, sz = std::ptrdiff_t{nx} * ny;
  // The nodes' x coordinates along a row (the same in every row), made once: a load where each
  // offer converted, multiplied and added (callgrind: 2% of the build at 4.7M nodes). Padded to
  // whole groups of four.
  std::vector<float> node_x(static_cast<std::size_t>(nx) + 4);
  for (std::size_t x = 0; x < node_x.size(); ++x) node_x[x] = local_origin.x + float(x) * voxel;
  // Node x of the row whose arrays start at d, cx, cy, cz (its y and z at py, pz) offered the
  // point (fx, fy, fz): taken when nearer. The scalar form of the lanes below.
  const auto offer = [&](float* __restrict d, float* __restrict cx, float* __restrict cy, float* __restrict cz, int x,
                         float py, float pz, float fx, float fy, float fz) {
    const float px = node_x[static_cast<std::size_t>(x)];
    const float dx = px - fx, dy = py - fy, dz = pz - fz;
    const float d2 = dx * dx + dy * dy + dz * dz;
    if (!(d2 < d[x])) return false;
    d[x] = d2;
    cx[x] = fx;
    cy[x] = fy;
    cz[x] = fz;
    return true;
  };
  // The nodes of the row being worked on that changed (took an offer) since it was last scanned
  // both ways, as bits (node x: bit x % 64 of word x / 64; one word of padding for a group of
  // four that straddles a word).
  const std::size_t words = static_cast<std::size_t>(nx) / 64 + 2;
  std::vector<std::uint64_t> changed(words, 0);
  const auto mark = [&](int x) { changed[static_cast<std::size_t>(x) / 64] |= std::uint64_t{1} << (x % 64); };
  const auto marked = [&](int x) { return (changed[static_cast<std::size_t>(x) / 64] >> (x % 64)) & 1u; };
  // The first changed node at or after x going `dir` (nx or -1 when none).
  const auto next_marked = [&](int x, int dir) {
    if (dir > 0) {
      if (x >= nx) return nx;
      std::size_t w = static_cast<std::size_t>(x) / 64;
      std::uint64_t bits = changed[w] & (~std::uint64_t{0} << (x % 64));
      while (bits == 0) {
        if (++w * 64 >= static_cast<std::size_t>(nx)) return nx;
        bits = changed[w];
      }
      return std::min(nx, static_cast<int>(w * 64) + std::countr_zero(bits));
    }
    if (x < 0) return -1;
    std::size_t w = static_cast<std::size_t>(x) / 64;
    std::uint64_t bits = changed[w] & (~std::uint64_t{0} >> (63 - x % 64));
    while (bits == 0) {
      if (w == 0) return -1;
      bits = changed[--w];
    }
    return static_cast<int>(w * 64) + 63 - std::countl_zero(bits);
  };
  // The row at `base` takes the offers of three nodes of each upstream row (`ups`: offsets of
  // the rows, nodes before `base`): the node in line and its two neighbours along x. Lanes of
  // four nodes, each loaded and stored once for all offers; the row's two end nodes alone.
  // Marks the nodes that took an offer; returns whether any did.
  const auto from_rows = [&](std::ptrdiff_t base, std::span<const std::ptrdiff_t> ups, float py, float pz) {
    bool taken = false;
    float* __restrict d = distance + base;
    float* __restrict cx = closest_x + base;
    float* __restrict cy = closest_y + base;
    float* __restrict cz = closest_z + base;
    const auto one = [&](int x) {
      for (const std::ptrdiff_t up : ups)
        for (int from = std::max(x - 1, 0); from <= std::min(x + 1, nx - 1); ++from)
          if (offer(d, cx, cy, cz, x, py, pz, cx[from - up], cy[from - up], cz[from - up])) {
            mark(x);
            taken = true;
          }
    };
    one(0);
    int x = 1;
    const std::uint8_t* const exact_at = store.state.data() + base;
    for (; x + 4 <= nx - 1; x += 4) {
      std::uint32_t states;
      std::memcpy(&states, exact_at + x, sizeof states);
      if ((states & (0x01010101u * kExact)) == 0x01010101u * kExact) continue;  // four band nodes: exact already
      const simd::Lanes px = simd::load(node_x.data() + x);
      const simd::Lanes qy = simd::splat(py), qz = simd::splat(pz);
      simd::Lanes best = simd::load(d + x), bx = simd::load(cx + x), by = simd::load(cy + x), bz = simd::load(cz + x);
      simd::LaneMask any = simd::mask(false);
      for (const std::ptrdiff_t up : ups)
        for (int shift = -1; shift <= 1; ++shift) {
          const std::ptrdiff_t from = x + shift - up;
          const simd::Lanes fx = simd::load(cx + from), fy = simd::load(cy + from), fz = simd::load(cz + from);
          const simd::Lanes dx = px - fx, dy = qy - fy, dz = qz - fz;
          const simd::Lanes d2 = dx * dx + dy * dy + dz * dz;
          const simd::LaneMask nearer = d2 < best;
          any = any | nearer;
          best = simd::select(nearer, d2, best);
          bx = simd::select(nearer, fx, bx);
          by = simd::select(nearer, fy, by);
          bz = simd::select(nearer, fz, bz);
        }
      simd::store(d + x, best);
      simd::store(cx + x, bx);
      simd::store(cy + x, by);
      simd::store(cz + x, bz);
      if (const std::uint64_t bits = simd::lane_bits(any); bits != 0) {
        const std::size_t w = static_cast<std::size_t>(x) / 64;
        const int at = x % 64;
        changed[w] |= bits << at;
        if (at > 60) changed[w + 1] |= bits >> (64 - at);
        taken = true;
      }
    }
    for (; x < nx; ++x) one(x);
    return taken;
  };
  // The row at `base` scanned along x in direction `dir`, each node offered its upstream
  // neighbour's closest point where that neighbour is marked (changed since the row was last
  // scanned both ways; all its nodes on its first scan), on from each marked node until a node
  // declines: after a scan both ways each node already beats its neighbours' offers (beyond
  // rounding, see above), so an unmarked node's offer would change nothing, and the scan jumps
  // to the next marked node. Marks the nodes this scan changed (for the scan the other way).
  // (With the changed nodes as one span instead, the scans went over whole rows on every pass:
  // a row's few changes lie spread along it.)
  const auto scan = [&](std::ptrdiff_t base, int dir, float py, float pz) {
    float* __restrict d = distance + base;
    float* __restrict cx = closest_x + base;
    float* __restrict cy = closest_y + base;
    float* __restrict cz = closest_z + base;
    const int x_end = dir > 0 ? nx : -1;
    for (int from = next_marked(dir > 0 ? 0 : nx - 1, dir); from != x_end;) {
      float ax = cx[from], ay = cy[from], az = cz[from];
      int x = from + dir;
      for (; x != x_end; x += dir) {
        if (offer(d, cx, cy, cz, x, py, pz, ax, ay, az)) {
          mark(x);
        } else if (marked(x)) {
          ax = cx[x];
          ay = cy[x];
          az = cz[x];
        } else {
          break;
        }
      }
      if (x == x_end) break;
      from = next_marked(x + dir, dir);
    }
  };
  for (const int z_dir : {1, -1}) {
    for (int k = 0; k < nz; ++k) {
      const int z = z_dir > 0 ? k : nz - 1 - k;
      const float pz = local_origin.z + float(z) * voxel;
      for (const int y_dir : {1, -1}) {
        for (int j = 0; j < ny; ++j) {
          const int y = y_dir > 0 ? j : ny - 1 - j;
          const float py = local_origin.y + float(y) * voxel;
          const std::ptrdiff_t base = sy * y + sz * z;
          const std::array<std::ptrdiff_t, 2> ups{y_dir * sy, z_dir * sz};
          const bool plane = y_dir > 0 && k > 0;
          std::fill(changed.begin(), changed.end(), std::uint64_t{0});
          bool any = false;
          if (j > 0) any = from_rows(base, std::span(ups).first(plane ? 2 : 1), py, pz);
          else if (plane) any = from_rows(base, std::span(ups).last(1), py, pz);
          if (z_dir > 0 && y_dir > 0) {  // its first visit: never scanned, every node marked
            std::fill_n(changed.begin(), nx / 64, ~std::uint64_t{0});
            if (nx % 64 != 0) changed[static_cast<std::size_t>(nx / 64)] = (std::uint64_t{1} << (nx % 64)) - 1;
            any = true;
          }
          if (!any) continue;
          scan(base, 1, py, pz);
          scan(base, -1, py, pz);
        }
      }
    }
  }
  if (!keep_closest) return;
  for (std::size_t i = 0; i < count; ++i) store.closest[i] = Vec3(xs[i], ys[i], zs[i]) + mesh_origin;
}

template <int D, class Store, class Position>
void propagate(Store& store, Position&& position) {
  const FieldGridN<D>& grid = store.grid;
  constexpr std::uint8_t kSignValid = kSignKnown | kSignCopied;
  for (int order = 0; order < (1 << D); ++order) {
    IVec<D> step;
    for (int k = 0; k < D; ++k) step[k] = ((order >> k) & 1) == 0 ? 1 : -1;
    if constexpr (!Store::kSparse) {
      propagate_dense<D>(store, step, position);
      continue;
    }
    store.for_each_block(step, [&](IVec<D> lo, IVec<D> hi) {
      sweep_box<D>(lo, hi, step, [&](IVec<D> i) {
        const std::size_t at = store.find(i);
        std::uint8_t& state = store.state[at];
        const bool exact = state & kExact;
        if (exact && (state & kSignValid)) return;
        const VecN<D> p = position(i);
        for (int k = 0; k < D; ++k) {
          IVec<D> m = i;
          m[k] -= step[k];
          if (m[k] < 0 || m[k] >= grid.dims[k]) continue;
          const std::size_t from = store.find(m);
          if (from == std::numeric_limits<std::size_t>::max()) continue;
          const std::uint8_t source = store.state[from];
          if (!(state & kSignValid) && (source & kSignValid))
            state = static_cast<std::uint8_t>((state & ~kInside) | (source & kInside) | kSignCopied);
          if (exact || !(source & kHasValue)) continue;
          const VecN<D> offset = p - store.closest[from];
          const float d2 = glm::dot(offset, offset);
          if ((state & kHasValue) && d2 >= store.distance[at]) continue;
          store.distance[at] = d2;
          store.closest[at] = store.closest[from];
          state |= kHasValue;
        }
      });
    });
  }
}

// ---- the builds ----------------------------------------------------------------------------

template <int D>
AabbN<D> shapes_bounds(std::span<const PlacedShapeN<D>> shapes, std::vector<AabbN<D>>& boxes) {
  if (shapes.empty()) throw InvalidInput("distance field: no shapes to build from");
  boxes.clear();
  AabbN<D> all{VecN<D>(std::numeric_limits<float>::infinity()), VecN<D>(-std::numeric_limits<float>::infinity())};
  for (const PlacedShapeN<D>& s : shapes) {
    boxes.push_back(compute_aabb(s.shape, s.xf));
    all.min = glm::min(all.min, boxes.back().min);
    all.max = glm::max(all.max, boxes.back().max);
  }
  return all;
}

float band_distance(const FieldOptions& options) { return std::max(1.0f, options.band) * options.voxel; }

template <int D>
DistanceFieldN<D> finish_dense(DenseStore<D>& store, const FieldOptions& options) {
  DistanceFieldN<D> field;
  field.grid = store.grid;
  for (std::size_t i = 0; i < store.distance.size(); ++i) {
    if (store.state[i] & kExact) ++field.stats.band_nodes;
    const float d = std::sqrt(store.distance[i]);
    store.distance[i] = (store.state[i] & kInside) ? -d : d;
  }
  field.distances = std::move(store.distance);
  if (options.keep_closest_points) field.closest_points = std::move(store.closest);
  field.stats.nodes = field.grid.count();
  field.stats.bytes = field.bytes();
  return field;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <int D>
DistanceFieldN<D> dense_from_shapes(std::span<const PlacedShapeN<D>> shapes, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<AabbN<D>> boxes;
  const AabbN<D> all = shapes_bounds(shapes, boxes);
  DenseStore<D> store(make_grid<D>(all, options, kDenseBuildBytesPerNode<D>, 1));
  const ShapeBins<D> bins(shapes, boxes, all, kFieldBrickSize * options.voxel);
  shapes_band<D>(shapes, boxes, bins, band_distance(options), store);
  propagate<D>(store, [&](IVec<D> i) { return store.grid.node(i); });
  DistanceFieldN<D> field = finish_dense(store, options);
  field.stats.sign_evaluations = field.stats.nodes;
  field.stats.seconds = seconds_since(start);
  return field;
}

Aabb3 mesh_bounds(const TriangleMesh& mesh) {
  if (mesh.triangle_count() == 0) throw InvalidInput("distance field: the mesh has no triangles");
  Aabb3 box = mesh.bvh.bounds();
  return {box.min + mesh.origin, box.max + mesh.origin};
}

/// The grid's origin relative to the mesh's stored coordinates (grid.origin - mesh.origin, in
/// the local frame where precision is kept).
Vec3 local_grid_origin(const TriangleMesh& mesh, const FieldOptions& options) {
  return mesh.bvh.bounds().min - Vec3(static_cast<float>(options.margin) * options.voxel);
}

/// Two neighbouring nodes may have the surface between them only when their exact distances sum
/// to at most the voxel (plus this fraction of it, for rounding): see sign_blocks.
constexpr float kCrossingSlackVoxels = 0.01f;
/// Length of a neighbour offset of squared length 0 to 3 (voxels).
constexpr std::array<float, 4> kNeighbourLength = {0.0f, 1.0f, std::numbers::sqrt2_v<float>, std::numbers::sqrt3_v<float>};
/// Bytes per node sign_blocks holds while it runs (each node's region).
constexpr std::size_t kSignBytesPerNode = sizeof(std::uint32_t);
/// Nodes per block of sign_blocks (the sparse field's brick).
constexpr int kSignBlockNodes = kFieldBrickSize * kFieldBrickSize * kFieldBrickSize;
/// sign_blocks keeps a block's distances inside a wall of one node on every side (its side
/// kWalledBlock), so a neighbour's distance needs no bounds check: the wall, and a partial
/// block's missing nodes, read -inf, which joins nothing.
constexpr int kWalledBlock = kFieldBrickSize + 2;
/// Cells of the walled block (its nodes and the wall).
constexpr int kWalledBlockNodes = kWalledBlock * kWalledBlock * kWalledBlock;
/// Place of block node (x, y, z) in the walled block.
constexpr int walled_cell(int x, int y, int z) { return (x + 1) + kWalledBlock * ((y + 1) + kWalledBlock * (z + 1)); }
/// A block's nodes as bits: slice z one 64-bit word, node (x, y) its bit y * 8 + x.
static_assert(kFieldBrickSize == 8, "a block's slice of 8 x 8 nodes is one 64-bit word");
using BlockBits = std::array<std::uint64_t, kFieldBrickSize>;
/// The 13 neighbour steps forward in scan order (z, then y, then x); with their reverses, the
/// 26 neighbours. Each with its squared length in voxels (an index of kNeighbourLength). All
/// 26, each with its own length: a node within a small fraction of a voxel of an oblique
/// surface has no axis neighbour passing the join test, but one along a diagonal that points
/// away from the surface.
struct ForwardSteps {
  std::array<glm::ivec3, 13> step{};
  std::array<int, 13> squared_length{};
};
constexpr ForwardSteps kForwardSteps = [] {
  ForwardSteps f;
  int e = 0;
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dz > 0 || dy > 0 || (dy == 0 && dx > 0)) {
          f.step[e] = {dx, dy, dz};
          f.squared_length[e++] = dx * dx + dy * dy + dz * dz;
        }
  return f;
}();
/// Slice word `w` moved by `shift` bits (a step's dy * 8 + dx): towards higher bits when positive.
constexpr std::uint64_t move_bits(std::uint64_t w, int shift) { return shift >= 0 ? w << shift : w >> -shift; }

/// Calls visit(lo, hi) for the node box of every block of kFieldBrickSize^3 nodes the store
/// holds: the sparse store's bricks; the dense grid cut into blocks (partial at its far faces).
template <class Visit>
void for_each_sign_block(const DenseStore<3>& store, Visit&& visit) {
  const glm::ivec3 dims = store.grid.dims;
  const glm::ivec3 blocks = (dims + (kFieldBrickSize - 1)) / kFieldBrickSize;
  for_each_node<3>(glm::ivec3(0), blocks - 1, [&](glm::ivec3 b) {
    const glm::ivec3 lo = b * kFieldBrickSize;
    visit(lo, glm::min(lo + (kFieldBrickSize - 1), dims - 1));
  });
}
template <class Visit>
void for_each_sign_block(const SparseStore<3>& store, Visit&& visit) {
  store.for_each_block(glm::ivec3(1), visit);
}

/// A region whose winding number is within this of 1/2 is not sure of its side: it takes the side
/// of the surest sure region it reaches without crossing the surface (sign_blocks). Under an open
/// terrain the winding number stays within about 0.1 to 0.3 of 1/2 for voxels below the surface
/// (undulating.obj), so 0.1 left pockets of flipped sign under its valleys; 0.3 removes them and
/// keeps dungeon.obj's rooms (about 0 and 1) on the winding number's side.
constexpr float kUnsureWinding = 0.3f;
/// A region of a block whose nodes all lie within this of the surface (voxels) would take its
/// winding number on the surface, where it is dearest (every nearby leaf opened) and least
/// telling: when it is joined to a neighbouring block's region it takes its side from the
/// flood as an unsure region does (sign_blocks).
constexpr float kNearSurfaceRegionVoxels = 0.5f;
/// A region's winding number not evaluated (yet).
constexpr float kDeferredWinding = std::numeric_limits<float>::quiet_NaN();

/// Signs every node of a mesh build with few winding numbers, in three steps.
///  1. Regions: within a block of kFieldBrickSize^3 nodes, two neighbouring nodes i, j (26
///     neighbours) can have the surface between them only when d_i + d_j <= |i - j| (a
///     crossing point s on the segment gives d_i <= |i - s| and d_j <= |j - s|; a node beyond
///     the band counts as the band's distance, a lower bound of its own). The pairs that fail this test join the block's
///     nodes into regions no surface crosses (a flood fill, as OpenVDB's meshToVolume (Museth
///     2013) floods its sign between the voxels the surface cuts; here on bit sets, a slice of
///     the block one 64-bit word, the join tests of a row of 8 nodes two lane compares, and a
///     region grown a link a step with shifts and masks: 6-13% off the dense build against a
///     node by node flood fill with the same regions), and one winding number (Barill et al.
///     2018), at the region's node farthest from the surface, gives its side; a region within
///     kNearSurfaceRegionVoxels of the surface that step 2 joins to another takes none and
///     counts as unsure (15-29% fewer winding numbers on dungeon, undulating and the torus at
///     64k-4M nodes, every node's side the same).
///  2. The regions of neighbouring blocks are joined the same way across the blocks' faces.
///  3. Sure regions (winding number at least kUnsureWinding from 1/2) keep their side and flood
///     it through joined unsure regions, the surest first (a priority flood: an unsure region
///     takes the side of the surest sure region that reaches it without crossing the surface);
///     joined unsure regions that no sure region reaches take the side of most of their nodes.
/// A closed mesh's sides are exact (every region's winding number is about 0 or 1). An open
/// terrain's underside, whose winding number hovers about 1/2 just below it and falls off
/// farther down, takes the side of the sure regions around it instead of flipping under every
/// valley (the sign then changes only across the surface, or between sure regions that disagree
/// across a hole: the dungeon's rooms keep the winding number's sides). The regions are the
/// flood fill's; the rule on unsure regions is ours. Returns the winding numbers evaluated.
template <class Store>
std::size_t sign_blocks(const TriangleMesh& mesh, Vec3 local_origin, float band_distance, Store& store) {
  const WindingTree winding(mesh.bvh);
  const float voxel = store.grid.voxel;
  const float join = voxel * (1.0f + kCrossingSlackVoxels);
  // A node beyond the band is farther than the band from the surface: its distance's lower bound.
  const auto distance_at = [&](std::size_t at) {
    return (store.state[at] & kExact) ? std::sqrt(store.distance[at]) : band_distance;
  };
  constexpr float kNoJoin = -std::numeric_limits<float>::infinity();
  std::array<float, kWalledBlockNodes> dist;
  dist.fill(kNoJoin);
  std::array<std::size_t, kSignBlockNodes> slot;  // node (x, y, z) at z * 64 + y * 8 + x
  std::array<BlockBits, kForwardSteps.step.size()> link;
  std::vector<std::uint32_t> region(store.state.size());  // node slot -> region
  std::vector<float> region_winding;  // kDeferredWinding: not evaluated (yet)
  std::vector<Vec3> region_probe;     // where a region's winding number is taken
  std::vector<std::uint32_t> region_size;
  // Room for a few regions and joins per block up front (the block loops then rarely allocate).
  const std::size_t blocks_estimate = store.state.size() / kSignBlockNodes + 1;
  region_winding.reserve(4 * blocks_estimate);
  region_probe.reserve(4 * blocks_estimate);
  region_size.reserve(4 * blocks_estimate);
  // The join test's bound for each forward step.
  std::array<simd::Lanes, kForwardSteps.step.size()> reach;
  for (std::size_t e = 0; e < reach.size(); ++e) reach[e] = simd::splat(join * kNeighbourLength[kForwardSteps.squared_length[e]]);
  const float reach_longest = join * kNeighbourLength.back();
  // 1. Regions within each block.
  for_each_sign_block(store, [&](glm::ivec3 lo, glm::ivec3 hi) {
    const glm::ivec3 n = hi - lo + 1;
    const auto first = static_cast<std::uint32_t>(region_winding.size());
    if (n != glm::ivec3(kFieldBrickSize))  // a partial block: the missing nodes join nothing
      for (int z = 0; z < kFieldBrickSize; ++z)
        for (int y = 0; y < kFieldBrickSize; ++y) std::fill_n(&dist[walled_cell(0, y, z)], kFieldBrickSize, kNoJoin);
    BlockBits valid{};
    bool any_band = false;
    float nearest = std::numeric_limits<float>::infinity();  // the block's least distance
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y) {
        // A row's nodes are consecutive in either store (a dense row; a brick's row).
        const std::size_t row = store.find(lo + glm::ivec3(0, y, z));
        float* const out = &dist[walled_cell(0, y, z)];
        unsigned exact = 0;  // (the states' kExact bits, or-ed: no branch a node)
        for (int x = 0; x < n.x; ++x) {
          const std::size_t at = row + static_cast<std::size_t>(x);
          slot[(z * kFieldBrickSize + y) * kFieldBrickSize + x] = at;
          out[x] = distance_at(at);
          nearest = std::min(nearest, out[x]);
          exact |= store.state[at] & kExact;
        }
        any_band |= exact != 0;
        valid[z] |= ((std::uint64_t{1} << n.x) - 1) << (y * kFieldBrickSize);
      }
    // A region of the block: its nodes (bits of slices z_lo..z_hi) numbered, its winding number
    // at its node farthest from the surface (the last in scan order of equally far ones, as all
    // nodes beyond the band are: against the flood fill's first one in its order, on
    // undulating.obj at 4M nodes 69 nodes took the other side, the exact winding number siding
    // with this choice at 44).
    const auto add_region = [&](const BlockBits& nodes, int z_lo, int z_hi) {
      const auto r = static_cast<std::uint32_t>(region_winding.size());
      std::uint32_t size = 0;
      float best = -1.0f;
      glm::ivec3 best_node{0};
      for (int z = z_lo; z <= z_hi; ++z)
        for (std::uint64_t w = nodes[z]; w != 0; w &= w - 1) {
          const int bit = std::countr_zero(w);
          const int x = bit % kFieldBrickSize, y = bit / kFieldBrickSize;
          region[slot[z * kFieldBrickSize * kFieldBrickSize + bit]] = r;
          ++size;
          const float d = dist[walled_cell(x, y, z)];
          if (d >= best) {
            best = d;
            best_node = {x, y, z};
          }
        }
      const Vec3 probe = local_origin + Vec3(lo + best_node) * voxel;
      region_probe.push_back(probe);
      region_winding.push_back(best < kNearSurfaceRegionVoxels * voxel ? kDeferredWinding : winding(probe));
      region_size.push_back(size);
    };
    if (!any_band) {  // no surface in the block: one region, its winding number at the centre
      region_probe.push_back(local_origin + Vec3((lo + hi) / 2) * voxel);
      region_winding.push_back(winding(region_probe.back()));
      region_size.push_back(static_cast<std::uint32_t>(n.x * n.y * n.z));
      for (int z = 0; z < n.z; ++z)
        for (int y = 0; y < n.y; ++y)
          for (int x = 0; x < n.x; ++x) region[slot[(z * kFieldBrickSize + y) * kFieldBrickSize + x]] = first;
      return;
    }
    // Every node farther from the surface than half the longest link's reach (so farther than
    // kNearSurfaceRegionVoxels): every link passes the join test, so the block is one region
    // (the growth below would find it link by link).
    static_assert((1.0f + kCrossingSlackVoxels) * kNeighbourLength.back() / 2.0f > kNearSurfaceRegionVoxels);
    if (nearest + nearest > reach_longest) {
      add_region(valid, 0, n.z - 1);
      return;
    }
    // The links: bit (x, y) of link[e][z] when node (x, y, z) and its neighbour a step e on
    // pass the join test, eight nodes of a row at once.
    for (std::size_t e = 0; e < link.size(); ++e) {
      const glm::ivec3 step = kForwardSteps.step[e];
      const int to = walled_cell(step.x, step.y, step.z) - walled_cell(0, 0, 0);
      for (int z = 0; z < kFieldBrickSize; ++z) {
        std::uint64_t word = 0;
        for (int y = 0; y < kFieldBrickSize; ++y) {
          const float* row = &dist[walled_cell(0, y, z)];
          const unsigned low = simd::lane_bits(simd::load(row) + simd::load(row + to) > reach[e]);
          const unsigned high = simd::lane_bits(simd::load(row + 4) + simd::load(row + 4 + to) > reach[e]);
          word |= std::uint64_t(low | high << 4) << (y * kFieldBrickSize);
        }
        link[e][z] = word;
      }
    }
    // Each region grown from its first node in scan order (the regions numbered as a flood fill
    // seeded in that order numbers them) through the links, as bit sets: every step moves the
    // whole set one link on, forward and back, until it stops growing.
    BlockBits todo = valid;
    for (int seed_z = 0; seed_z < kFieldBrickSize; ++seed_z) {
      while (todo[seed_z] != 0) {
        BlockBits grown{};
        grown[seed_z] = todo[seed_z] & (~todo[seed_z] + 1);
        int z_lo = seed_z, z_hi = seed_z;  // the slices the set has reached
        while (true) {
          const BlockBits before = grown;
          for (std::size_t e = 0; e < link.size(); ++e) {
            const glm::ivec3 step = kForwardSteps.step[e];
            const int shift = step.y * kFieldBrickSize + step.x;
            const int z_end = std::min(z_hi, kFieldBrickSize - 1 - step.z);
            for (int z = std::max(z_lo - step.z, 0); z <= z_end; ++z) {
              grown[z + step.z] |= move_bits(grown[z] & link[e][z], shift);
              grown[z] |= link[e][z] & move_bits(grown[z + step.z], -shift);
            }
            if (step.z > 0) {
              if (z_lo > 0 && grown[z_lo - 1] != 0) --z_lo;
              if (z_hi < kFieldBrickSize - 1 && grown[z_hi + 1] != 0) ++z_hi;
            }
          }
          if (grown == before) break;
        }
        for (int z = z_lo; z <= z_hi; ++z) todo[z] &= ~grown[z];
        add_region(grown, z_lo, z_hi);
      }
    }
  });
  const std::size_t regions = region_winding.size();
  // 2. Joins across block faces (pairs of regions; repeats of the last pair skipped).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> joins;
  joins.reserve(12 * blocks_estimate);
  const glm::ivec3 dims = store.grid.dims;
  for_each_sign_block(store, [&](glm::ivec3 lo, glm::ivec3 hi) {
    for (int axis = 0; axis < 3; ++axis) {
      if (hi[axis] + 1 >= dims[axis]) continue;
      glm::ivec3 face_lo = lo, face_hi = hi;
      face_lo[axis] = face_hi[axis] = hi[axis];
      std::pair<std::uint32_t, std::uint32_t> last{0xffffffffu, 0xffffffffu};
      for_each_node<3>(face_lo, face_hi, [&](glm::ivec3 i) {
        glm::ivec3 j = i;
        ++j[axis];
        const std::size_t from = store.find(i), to = store.find(j);
        if (to == std::numeric_limits<std::size_t>::max()) return;
        const std::uint32_t a = region[from], b = region[to];
        if (a == b || !(distance_at(from) + distance_at(to) > join)) return;
        const std::pair<std::uint32_t, std::uint32_t> pair{a, b};
        if (pair == last) return;
        last = pair;
        joins.push_back(pair);
        joins.push_back({b, a});
      });
    }
  });
  // Joins as adjacency lists (counting sort by the first region).
  std::vector<std::uint32_t> start(regions + 1, 0), next(joins.size());
  for (const auto& [a, b] : joins) ++start[a + 1];
  for (std::size_t r = 0; r < regions; ++r) start[r + 1] += start[r];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const auto& [a, b] : joins) next[fill[a]++] = b;
  }
  // A near-surface region joined to another follows the flood below (it counts as unsure); one
  // joined to none has only its own winding number, taken now.
  std::size_t evaluated = 0;
  const auto evaluate = [&](std::uint32_t r) {
    region_winding[r] = winding(region_probe[r]);
    ++evaluated;
  };
  for (std::uint32_t r = 0; r < regions; ++r) {
    if (!std::isnan(region_winding[r])) ++evaluated;
    else if (start[r] == start[r + 1]) evaluate(r);
  }
  // 3. Sure regions keep their side and flood it into the unsure ones, the surest first (a
  // region is claimed by the surest sure region that reaches it through unsure ones).
  std::vector<std::uint8_t> inside(regions), done(regions, 0);
  std::vector<std::pair<float, std::uint32_t>> heap;  // (sureness of the side, region)
  heap.reserve(regions);
  for (std::uint32_t r = 0; r < regions; ++r) {
    inside[r] = region_winding[r] > kInsideWinding ? kInside : 0;
    const float sureness = std::abs(region_winding[r] - kInsideWinding);
    if (sureness >= kUnsureWinding) heap.push_back({sureness, r});
  }
  std::make_heap(heap.begin(), heap.end());
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end());
    const auto [sureness, r] = heap.back();
    heap.pop_back();
    if (done[r]) continue;
    done[r] = 1;
    for (std::uint32_t e = start[r]; e < start[r + 1]; ++e) {
      const std::uint32_t to = next[e];
      if (done[to] || std::abs(region_winding[to] - kInsideWinding) >= kUnsureWinding) continue;
      inside[to] = inside[r];
      heap.push_back({sureness, to});
      std::push_heap(heap.begin(), heap.end());
    }
  }
  // Joined unsure regions no sure region reaches take the side most of their nodes are on.
  std::vector<std::uint32_t> queue;
  for (std::uint32_t r = 0; r < regions; ++r) {
    if (done[r]) continue;
    queue.assign(1, r);
    done[r] = 1;
    std::int64_t vote = 0;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t at = queue[head];
      if (std::isnan(region_winding[at])) {  // near the surface, and no sure region claimed it
        evaluate(at);
        inside[at] = region_winding[at] > kInsideWinding ? kInside : 0;
      }
      vote += inside[at] ? std::int64_t{region_size[at]} : -std::int64_t{region_size[at]};
      for (std::uint32_t e = start[at]; e < start[at + 1]; ++e) {
        if (done[next[e]]) continue;
        done[next[e]] = 1;
        queue.push_back(next[e]);
      }
    }
    for (const std::uint32_t at : queue) inside[at] = vote > 0 ? kInside : 0;
  }
  for (std::size_t at = 0; at < store.state.size(); ++at)
    store.state[at] |= static_cast<std::uint8_t>(kSignKnown | inside[region[at]]);
  return evaluated;
}

/// The sparse field from a store whose bricks hold the band: values beyond the band clamped,
/// brick nodes signed (propagation or sign_blocks), each empty region's sign from a neighbour.
template <int D>
SparseDistanceFieldN<D> finish_sparse(SparseStore<D>& store, const FieldOptions& options) {
  const float band = band_distance(options);
  SparseDistanceFieldN<D> field;
  field.grid = store.grid;
  field.bricks_per_axis = store.regions;
  field.band_distance = band;
  for (std::size_t i = 0; i < store.state.size(); ++i)
    if (store.state[i] & kExact) ++field.stats.band_nodes;
  // Empty regions: breadth-first from the regions with bricks, each taking the sign of the node
  // of its neighbour that faces it (no surface lies between them: both are beyond the band).
  std::vector<std::uint32_t>& table = store.table;
  std::vector<std::uint8_t> region_inside(table.size(), 0), known(table.size(), 0);
  std::vector<std::size_t> queue;
  for_each_node<D>(IVec<D>(0), store.regions - 1, [&](IVec<D> r) {
    const std::size_t at = store.region_index(r);
    if (table[at] != SparseStore<D>::kNone) {
      known[at] = 1;
      queue.push_back(at);
    }
  });
  auto region_of = [&](std::size_t at) {
    IVec<D> r;
    for (int k = 0; k < D; ++k) {
      r[k] = static_cast<int>(at % static_cast<std::size_t>(store.regions[k]));
      at /= static_cast<std::size_t>(store.regions[k]);
    }
    return r;
  };
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const IVec<D> r = region_of(queue[head]);
    const bool has_brick = table[queue[head]] != SparseStore<D>::kNone;
    for (int k = 0; k < D; ++k) {
      for (int s : {-1, 1}) {
        IVec<D> q = r;
        q[k] += s;
        if (q[k] < 0 || q[k] >= store.regions[k]) continue;
        const std::size_t to = store.region_index(q);
        if (known[to]) continue;
        known[to] = 1;
        if (has_brick) {
          IVec<D> face = r * kFieldBrickSize + IVec<D>(kFieldBrickSize / 2);
          face[k] = s > 0 ? r[k] * kFieldBrickSize + kFieldBrickSize - 1 : r[k] * kFieldBrickSize;
          region_inside[to] = (store.state[store.find(face)] & kInside) ? 1 : 0;
        } else {
          region_inside[to] = region_inside[queue[head]];
        }
        queue.push_back(to);
      }
    }
  }
  for (std::size_t at = 0; at < table.size(); ++at)
    if (table[at] == SparseStore<D>::kNone && region_inside[at]) table[at] = SparseDistanceFieldN<D>::kNoBrickInside;
  field.table = std::move(table);
  field.bricks = large_page_vector(store.distance.size(), 0.0f);
  for (std::size_t i = 0; i < store.distance.size(); ++i) {
    const float d = std::min(std::sqrt(store.distance[i]), band);
    field.bricks[i] = (store.state[i] & kInside) ? -d : d;
  }
  field.stats.nodes = field.bricks.size();
  field.stats.bytes = field.bytes();
  return field;
}

template <int D>
SparseDistanceFieldN<D> sparse_from_shapes(std::span<const PlacedShapeN<D>> shapes, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<AabbN<D>> boxes;
  const AabbN<D> all = shapes_bounds(shapes, boxes);
  // The table costs 4 bytes per region; bricks are checked as they are allocated.
  SparseStore<D> store(make_grid<D>(all, options, kSparseTableBytesPerNode<D>, kFieldBrickSize), options.max_bytes);
  const ShapeBins<D> bins(shapes, boxes, all, kFieldBrickSize * options.voxel);
  shapes_band<D>(shapes, boxes, bins, band_distance(options), store);
  propagate<D>(store, [&](IVec<D> i) { return store.grid.node(i); });
  SparseDistanceFieldN<D> field = finish_sparse(store, options);
  field.stats.sign_evaluations = field.stats.nodes;
  field.stats.seconds = seconds_since(start);
  return field;
}

}  // namespace

DistanceField make_distance_field(std::span<const PlacedShape> shapes, const FieldOptions& options) {
  return dense_from_shapes<2>(shapes, options);
}

DistanceField3 make_distance_field(std::span<const PlacedShape3> shapes, const FieldOptions& options) {
  return dense_from_shapes<3>(shapes, options);
}

SparseDistanceField make_sparse_distance_field(std::span<const PlacedShape> shapes, const FieldOptions& options) {
  return sparse_from_shapes<2>(shapes, options);
}

SparseDistanceField3 make_sparse_distance_field(std::span<const PlacedShape3> shapes, const FieldOptions& options) {
  return sparse_from_shapes<3>(shapes, options);
}

DistanceField3 make_distance_field(const TriangleMesh& mesh, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  DenseStore<3> store(make_grid<3>(mesh_bounds(mesh), options,
                                   double(kDenseBuildBytesPerNode<3> + std::max(kSignBytesPerNode, kPropagateBytesPerNode)) +
                                       kBandMarkBytesPerNode,
                                   1));
  const Vec3 local = local_grid_origin(mesh, options);
  const std::size_t queries = mesh_band(mesh, local, band_distance(options), store);
  const std::size_t signs = sign_blocks(mesh, local, band_distance(options), store);
  propagate_mesh_dense(store, local, mesh.origin, options.keep_closest_points);
  DistanceField3 field = finish_dense(store, options);
  field.stats.sign_evaluations = signs;
  field.stats.nearest_queries = queries;
  field.stats.seconds = seconds_since(start);
  return field;
}

SparseDistanceField3 make_sparse_distance_field(const TriangleMesh& mesh, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SparseStore<3> store(
      make_grid<3>(mesh_bounds(mesh), options, kSparseTableBytesPerNode<3> + kBandMarkBytesPerNode, kFieldBrickSize),
      options.max_bytes, false);
  const Vec3 local = local_grid_origin(mesh, options);
  const std::size_t queries = mesh_band(mesh, local, band_distance(options), store);
  // Every brick node is signed; nodes beyond the band keep +inf, which finish_sparse clamps to
  // the band (propagated distances would be clamped as well: no propagation).
  const std::size_t signs = sign_blocks(mesh, local, band_distance(options), store);
  SparseDistanceField3 field = finish_sparse(store, options);
  field.stats.sign_evaluations = signs;
  field.stats.nearest_queries = queries;
  field.stats.seconds = seconds_since(start);
  return field;
}

DistanceField3 make_distance_field_exact(const TriangleMesh& mesh, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  DistanceField3 field;
  field.grid = make_grid<3>(mesh_bounds(mesh), options, sizeof(float) + sizeof(Vec3), 1);
  const Vec3 local = local_grid_origin(mesh, options);
  field.distances = large_page_vector(field.grid.count(), 0.0f);
  if (options.keep_closest_points) field.closest_points = large_page_vector(field.grid.count(), Vec3(0.0f));
  const WindingTree winding(mesh.bvh);
  for_each_node<3>(glm::ivec3(0), field.grid.dims - 1, [&](glm::ivec3 i) {
    const Vec3 p = local + Vec3(i) * field.grid.voxel;
    const BvhNearest nearest = mesh.bvh.nearest(p);
    const float d = std::sqrt(nearest.distance_squared);
    const std::size_t at = field.grid.index(i);
    field.distances[at] = winding(p) > kInsideWinding ? -d : d;
    if (options.keep_closest_points) field.closest_points[at] = nearest.closest.point + mesh.origin;
  });
  field.stats.nodes = field.stats.band_nodes = field.stats.sign_evaluations = field.grid.count();
  field.stats.bytes = field.bytes();
  field.stats.seconds = seconds_since(start);
  return field;
}

float winding_number(const TriangleMesh& mesh, Vec3 p) noexcept {
  const Vec3 q = p - mesh.origin;
  float omega = 0.0f;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t)
    omega += solid_angle(mesh.corner(t, 0) - q, mesh.corner(t, 1) - q, mesh.corner(t, 2) - q);
  return omega / (4.0f * std::numbers::pi_v<float>);
}

}  // namespace collide
