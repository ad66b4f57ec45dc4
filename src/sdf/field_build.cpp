// Building distance fields: the exact band, the sign, and closest-point propagation
// (distance_field.hpp gives the method and its sources). One build for both dimensions and for
// both storages (dense grid, sparse bricks): the stages write through a store.

#include <collide/core/error.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/shape/triangle.hpp>

#include "winding_tree.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <variant>

namespace collide {
namespace {

using detail::WindingTree;

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
      : grid(g), distance(g.count(), std::numeric_limits<float>::infinity()), closest(g.count()), state(g.count(), 0) {}
  std::size_t slot(IVec<D> i) { return grid.index(i); }
  /// The slot of a node that may have none (dense: always one).
  std::size_t find(IVec<D> i) const { return grid.index(i); }
  /// Calls visit(lo, hi) for each box of nodes the store holds (here the whole grid); `step`
  /// orders the boxes as sweep_box orders nodes.
  template <class Visit>
  void for_each_block(IVec<D> /*step*/, Visit&& visit) const { visit(IVec<D>(0), grid.dims - 1); }
  static constexpr bool kSparse = false;
};

/// Build storage in bricks allocated on first touch, found through a table of regions.
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

  SparseStore(const FieldGridN<D>& g, std::size_t limit) : grid(g), max_bytes(limit) {
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
  std::size_t slot(IVec<D> i) {
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
      closest.resize(closest.size() + kBrickNodes);
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

/// A mesh's exact band: each triangle visits, row by row, the nodes within the band of its plane
/// and inside its box grown by the band. Coordinates relative to the mesh's origin.
template <class Store>
void mesh_band(const TriangleMesh& mesh, Vec3 local_origin, float band_distance, Store& store) {
  const FieldGrid3& grid = store.grid;
  const float band_squared = band_distance * band_distance;
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const Vec3 a = mesh.corner(t, 0), b = mesh.corner(t, 1), c = mesh.corner(t, 2);
    Aabb3 box{glm::min(glm::min(a, b), c) - Vec3(band_distance), glm::max(glm::max(a, b), c) + Vec3(band_distance)};
    box.min -= local_origin;  // node range in the grid's frame (grid.origin = mesh.origin + local_origin)
    box.max -= local_origin;
    FieldGrid3 local = grid;
    local.origin = Vec3(0.0f);
    glm::ivec3 lo, hi;
    node_range(local, box, lo, hi);
    if (lo.x > hi.x || lo.y > hi.y || lo.z > hi.z) continue;
    Vec3 n = glm::cross(b - a, c - a);
    const float length = glm::length(n);
    n = length > 0.0f ? n / length : Vec3(0.0f);
    for (int z = lo.z; z <= hi.z; ++z) {
      for (int y = lo.y; y <= hi.y; ++y) {
        // Nodes of this row within the band of the triangle's plane: |n . (p - a)| <= band.
        const float py = local_origin.y + float(y) * grid.voxel, pz = local_origin.z + float(z) * grid.voxel;
        const float offset = n.y * (py - a.y) + n.z * (pz - a.z) - n.x * a.x;
        int x0 = lo.x, x1 = hi.x;
        if (std::abs(n.x) > 1e-6f) {
          float u = (-band_distance - offset) / n.x, v = (band_distance - offset) / n.x;
          if (u > v) std::swap(u, v);
          x0 = std::max(x0, static_cast<int>(std::ceil((u - local_origin.x) / grid.voxel)) - 1);
          x1 = std::min(x1, static_cast<int>(std::floor((v - local_origin.x) / grid.voxel)) + 1);
        } else if (std::abs(offset) > band_distance) {
          continue;
        }
        for (int x = x0; x <= x1; ++x) {
          const Vec3 p{local_origin.x + float(x) * grid.voxel, py, pz};
          const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
          const Vec3 offset = p - q.point;
          const float d2 = glm::dot(offset, offset);
          if (d2 > band_squared) continue;
          const std::size_t at = store.slot({x, y, z});
          if (d2 >= store.distance[at]) continue;
          store.distance[at] = d2;
          store.closest[at] = q.point;
          store.state[at] |= kExact | kHasValue;
        }
      }
    }
  }
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

/// Signs the band's nodes within a voxel of the surface by their winding number.
template <class Store>
std::size_t sign_band(const TriangleMesh& mesh, Vec3 local_origin, Store& store) {
  const WindingTree winding(mesh.vertices, mesh.triangles);
  std::size_t evaluations = 0;
  const FieldGrid3& grid = store.grid;
  store.for_each_block(glm::ivec3(1), [&](glm::ivec3 lo, glm::ivec3 hi) {
    for_each_node<3>(lo, hi, [&](glm::ivec3 i) {
      const std::size_t at = store.find(i);
      // Nodes within a voxel of the surface: farther ones copy a neighbour's sign.
      if (!(store.state[at] & kExact) || store.distance[at] > grid.voxel * grid.voxel) return;
      ++evaluations;
      store.state[at] |= kSignKnown;
      if (winding(local_origin + Vec3(i) * grid.voxel) > kInsideWinding) store.state[at] |= kInside;
    });
  });
  return evaluations;
}

/// Closest points of a mesh build are kept in the mesh's local frame until the end.
void closest_to_mesh_space(std::vector<Vec3>& closest, Vec3 origin) {
  for (Vec3& c : closest) c += origin;
}

/// The sparse field from a store whose bricks hold the band: values beyond the band clamped,
/// signs of brick nodes propagated, each empty region's sign from a neighbour.
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
  field.bricks.resize(store.distance.size());
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
  DenseStore<3> store(make_grid<3>(mesh_bounds(mesh), options, kDenseBuildBytesPerNode<3>, 1));
  const Vec3 local = local_grid_origin(mesh, options);
  mesh_band(mesh, local, band_distance(options), store);
  const std::size_t signs = sign_band(mesh, local, store);
  propagate<3>(store, [&](glm::ivec3 i) { return local + Vec3(i) * store.grid.voxel; });
  if (options.keep_closest_points) closest_to_mesh_space(store.closest, mesh.origin);
  DistanceField3 field = finish_dense(store, options);
  field.stats.sign_evaluations = signs;
  field.stats.seconds = seconds_since(start);
  return field;
}

SparseDistanceField3 make_sparse_distance_field(const TriangleMesh& mesh, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  SparseStore<3> store(make_grid<3>(mesh_bounds(mesh), options, kSparseTableBytesPerNode<3>, kFieldBrickSize), options.max_bytes);
  const Vec3 local = local_grid_origin(mesh, options);
  mesh_band(mesh, local, band_distance(options), store);
  const std::size_t signs = sign_band(mesh, local, store);
  propagate<3>(store, [&](glm::ivec3 i) { return local + Vec3(i) * store.grid.voxel; });
  SparseDistanceField3 field = finish_sparse(store, options);
  field.stats.sign_evaluations = signs;
  field.stats.seconds = seconds_since(start);
  return field;
}

DistanceField3 make_distance_field_exact(const TriangleMesh& mesh, const FieldOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  DistanceField3 field;
  field.grid = make_grid<3>(mesh_bounds(mesh), options, sizeof(float) + sizeof(Vec3), 1);
  const Vec3 local = local_grid_origin(mesh, options);
  field.distances.resize(field.grid.count());
  if (options.keep_closest_points) field.closest_points.resize(field.grid.count());
  const WindingTree winding(mesh.vertices, mesh.triangles);
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
    omega += detail::solid_angle(mesh.corner(t, 0) - q, mesh.corner(t, 1) - q, mesh.corner(t, 2) - q);
  return omega / (4.0f * std::numbers::pi_v<float>);
}

}  // namespace collide
