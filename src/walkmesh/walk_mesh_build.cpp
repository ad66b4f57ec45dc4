// Building a walk mesh from a triangle soup: validation, welding, cleaning, edge pairing,
// consistent winding, islands. Real level meshes have all of these problems at once
// (SOURCES.md: dungeon.obj has 138 edges shared by more than two triangles).
#include <collide/walkmesh/walk_mesh.hpp>

#include "local_frame.hpp"

#include <collide/core/error.hpp>
#include <collide/core/math.hpp>
#include <collide/core/radix_sort.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <optional>
#include <cmath>
#include <cstdint>
#include <string>

namespace collide {
namespace {

constexpr std::uint32_t kUnset = 0xffffffffu;

/// A vertex on another triangle's unshared edge is a T-junction only when its triangle lies on
/// the far side, its direction from the edge at a cosine below -this with the near side's.
constexpr float kTJunctionSideCos = 0.1f;
/// Grid cells the T-junction search of one edge may read whatever its slab holds; beyond this it
/// reads whichever is smaller, the cells or the vertices of the thinnest slab. Chosen, not tuned:
/// with cells of the median edge length most edges span a few cells, and a cell costs one binary
/// search per column.
constexpr std::uint64_t kTJunctionGridCells = 64;
/// Padding of the boxes of an edge's pieces, relative to the coordinates' size: a vertex whose
/// parameter falls in a piece is inside the piece's box despite rounding.
constexpr float kTJunctionPieceSlack = 1e-5f;

std::string where(const TriangleSoup& soup) { return soup.name.empty() ? "walk mesh" : soup.name; }

/// Integer cell of a hash grid.
struct Cell {
  std::int64_t x, y, z;
  friend bool operator==(const Cell&, const Cell&) = default;
};
[[nodiscard]] std::size_t hash_cell(const Cell& c) noexcept {
  return static_cast<std::size_t>(c.x * 73856093LL ^ c.y * 19349663LL ^ c.z * 83492791LL);
}

/// Welds positions closer than `radius` (the first one seen wins) with a hash grid of cell size
/// `radius`, searching the 27 cells around each point, each cell's points in the order they were
/// added. Returns the representative of each input. The grid is one open-addressed table (linear
/// probing) of cells, each the head and tail of a list through `next`: no allocation per cell
/// (a std::unordered_map of vectors was 7% of the walk mesh build on dungeon.obj).
std::vector<std::uint32_t> weld(const std::vector<Vec3>& local, const std::vector<bool>& used,
                                float radius, std::size_t& welded) {
  std::vector<std::uint32_t> rep(local.size(), kUnset);
  const float cell = radius > 0.0f ? radius : 1.0f;
  const float r2 = radius * radius;
  struct Slot {
    Cell cell;
    std::uint32_t head = kUnset, tail = kUnset;  // head kUnset: an empty slot
  };
  std::size_t count = 0;
  for (std::uint32_t i = 0; i < local.size(); ++i) count += used[i] ? 1 : 0;
  const std::size_t mask = std::bit_ceil(2 * count + 2) - 1;  // at most half full
  std::vector<Slot> table(mask + 1);
  std::vector<std::uint32_t> next(local.size(), kUnset);
  auto slot_of = [&](const Cell& c) -> Slot& {
    std::size_t at = hash_cell(c) & mask;
    while (table[at].head != kUnset && !(table[at].cell == c)) at = (at + 1) & mask;
    return table[at];
  };
  for (std::uint32_t i = 0; i < local.size(); ++i) {
    if (!used[i]) continue;
    const Vec3 p = local[i];
    const Cell c{static_cast<std::int64_t>(std::floor(p.x / cell)),
                 static_cast<std::int64_t>(std::floor(p.y / cell)),
                 static_cast<std::int64_t>(std::floor(p.z / cell))};
    std::uint32_t found = kUnset;
    for (std::int64_t dx = -1; dx <= 1 && found == kUnset; ++dx) {
      for (std::int64_t dy = -1; dy <= 1 && found == kUnset; ++dy) {
        for (std::int64_t dz = -1; dz <= 1 && found == kUnset; ++dz) {
          for (std::uint32_t j = slot_of({c.x + dx, c.y + dy, c.z + dz}).head; j != kUnset; j = next[j]) {
            const Vec3 d = local[j] - p;
            if (glm::dot(d, d) <= r2) {
              found = j;
              break;
            }
          }
        }
      }
    }
    if (found == kUnset) {
      rep[i] = i;
      Slot& slot = slot_of(c);
      if (slot.head == kUnset) {
        slot.cell = c;
        slot.head = i;
      } else {
        next[slot.tail] = i;
      }
      slot.tail = i;
    } else {
      rep[i] = found;
      ++welded;
    }
  }
  return rep;
}

/// One side of a link between two triangles over an edge.
struct EdgeSide {
  std::uint32_t lo, hi;  ///< the edge's vertices, lo < hi
  std::uint32_t triangle;
  std::uint32_t third;   ///< the triangle's vertex opposite the edge
};

/// Two triangles joined over edge (lo, hi).
struct Link {
  std::uint32_t t0, t1, lo, hi;
  bool cut = false;
};

/// Vertices in a uniform grid of cubic cells, stored as one array sorted by cell: the cells of a
/// box are read as runs of consecutive keys (one per x, y column), so a short edge looks at
/// the vertices around it only. Cell coordinates are clamped to 21 bits, monotonically, so a
/// box still holds every vertex inside it whatever the coordinates.
class VertexGrid {
 public:
  VertexGrid(const std::vector<Vec3>& local, const std::vector<std::uint32_t>& verts, Vec3 origin, float cell)
      : origin_(origin), inverse_(1.0f / cell) {
    entries_.reserve(verts.size());
    for (const std::uint32_t v : verts) entries_.push_back({key(cell_of(local[v])), v});
    std::sort(entries_.begin(), entries_.end());
  }

  /// Side of a cell.
  [[nodiscard]] float cell() const noexcept { return 1.0f / inverse_; }

  /// Cells a box spans (in 64 bits: the product may exceed 32).
  [[nodiscard]] std::uint64_t cell_count(Vec3 lo, Vec3 hi) const noexcept {
    const glm::uvec3 a = cell_of(lo), b = cell_of(hi);
    return std::uint64_t{b.x - a.x + 1} * (b.y - a.y + 1) * (b.z - a.z + 1);
  }

  /// Calls visit(vertex) for every vertex in a cell the box spans.
  template <class Visit>
  void for_each(Vec3 lo, Vec3 hi, Visit&& visit) const {
    const glm::uvec3 a = cell_of(lo), b = cell_of(hi);
    for (std::uint32_t x = a.x; x <= b.x; ++x) {
      for (std::uint32_t y = a.y; y <= b.y; ++y) {
        auto it = std::lower_bound(entries_.begin(), entries_.end(), Entry{key({x, y, a.z}), 0});
        const std::uint64_t last = key({x, y, b.z});
        for (; it != entries_.end() && it->first <= last; ++it) visit(it->second);
      }
    }
  }

 private:
  using Entry = std::pair<std::uint64_t, std::uint32_t>;
  static constexpr float kMaxCell = 2097151.0f;  // 2^21 - 1
  [[nodiscard]] glm::uvec3 cell_of(Vec3 p) const noexcept {
    glm::uvec3 c;
    for (int k = 0; k < 3; ++k) {
      const float f = (p[k] - origin_[k]) * inverse_;
      c[k] = static_cast<std::uint32_t>(f > 0.0f ? std::min(f, kMaxCell) : 0.0f);
    }
    return c;
  }
  [[nodiscard]] static std::uint64_t key(glm::uvec3 c) noexcept {
    return (std::uint64_t{c.x} << 42) | (std::uint64_t{c.y} << 21) | c.z;
  }
  Vec3 origin_;
  float inverse_;
  std::vector<Entry> entries_;
};

/// Splits triangles at T-junctions: a vertex lying inside an unshared edge of another triangle
/// (within `tolerance`), as where a refined part of a mesh meets an unrefined one. The triangle
/// (u, v, x) with w on edge (u, v) becomes (u, w, x) and (w, v, x), same winding, when a triangle at
/// w runs along (u, v) on the far side from x (overlapping geometry is left alone). Every such
/// vertex of an edge is taken in one pass, in order from u (ties: the lowest index), each cutting
/// the rest of the edge, until a cut would leave a degenerate piece; passes repeat (at most
/// kMaxTJunctionPasses) for a triangle with T-junctions on two edges, whose second edge waits for
/// the next pass, and until no unshared edge holds a vertex. Candidate vertices for an
/// edge come from a grid of cells as large as the mesh's median edge: the cells of the edge's box
/// when it spans at most kTJunctionGridCells; else the cells along it, read piece by piece (pieces
/// about a cell long), or the axis-sorted vertex list whose slab around the edge holds the fewest,
/// whichever reads less.
std::size_t split_t_junctions(std::vector<glm::uvec3>& tris, const std::vector<Vec3>& local,
                              float tolerance) {
  std::vector<std::uint32_t> verts;
  {
    std::vector<bool> seen(local.size(), false);
    for (const glm::uvec3& t : tris) {
      for (int k = 0; k < 3; ++k) {
        if (!seen[t[k]]) {
          seen[t[k]] = true;
          verts.push_back(t[k]);
        }
      }
    }
  }
  // Per axis the vertices in coordinate order (ties by index), with their coordinates beside them
  // so that sorting and searching read one contiguous array.
  std::array<std::vector<std::uint32_t>, 3> sorted;
  std::array<std::vector<float>, 3> keys;
  {
    std::vector<std::pair<float, std::uint32_t>> keyed(verts.size());
    for (int axis = 0; axis < 3; ++axis) {
      for (std::size_t i = 0; i < verts.size(); ++i) keyed[i] = {local[verts[i]][axis], verts[i]};
      std::sort(keyed.begin(), keyed.end());
      sorted[axis].resize(keyed.size());
      keys[axis].resize(keyed.size());
      for (std::size_t i = 0; i < keyed.size(); ++i) {
        keys[axis][i] = keyed[i].first;
        sorted[axis][i] = keyed[i].second;
      }
    }
  }
  // The grid's cell: the median edge length (of edges with a length), so that a typical edge
  // spans a few cells. Not the mean: a few long edges would make cells that hold thousands of
  // vertices where the rest are dense; long edges are read piece by piece instead.
  std::optional<VertexGrid> grid;
  if (!verts.empty()) {
    std::vector<float> lengths;
    lengths.reserve(3 * tris.size());
    Vec3 lo = local[verts[0]];
    for (const std::uint32_t v : verts) lo = glm::min(lo, local[v]);
    for (const glm::uvec3& t : tris) {
      for (int k = 0; k < 3; ++k) {
        const float length = glm::length(local[t[(k + 1) % 3]] - local[t[k]]);
        if (length > 0.0f) lengths.push_back(length);
      }
    }
    if (!lengths.empty()) {
      const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
      std::nth_element(lengths.begin(), middle, lengths.end());
      const float cell = *middle;
      if (std::isfinite(1.0f / cell)) grid.emplace(local, verts, lo, cell);
    }
  }
  std::size_t splits = 0;
  for (int pass = 0; pass < kMaxTJunctionPasses; ++pass) {
    // Edge uses by their vertex pair (sort_edge_uses): a run of one is an unshared edge.
    const std::vector<EdgeUse> uses =
        sort_edge_uses(tris, local.size(), [](std::uint32_t v) { return v; });
    // Triangles around each vertex, to check that a vertex found on an edge really belongs to the
    // other side of it (and not to geometry overlapping this triangle).
    std::vector<std::uint32_t> around_start(local.size() + 1, 0), around;
    for (const glm::uvec3& t : tris) {
      for (int k = 0; k < 3; ++k) ++around_start[t[k] + 1];
    }
    for (std::size_t v = 0; v < local.size(); ++v) around_start[v + 1] += around_start[v];
    around.resize(around_start.back());
    {
      std::vector<std::uint32_t> fill(around_start.begin(), around_start.end() - 1);
      for (std::uint32_t t = 0; t < tris.size(); ++t) {
        for (int k = 0; k < 3; ++k) around[fill[tris[t][k]]++] = t;
      }
    }
    std::vector<bool> split_this_pass(tris.size(), false);
    std::vector<std::pair<float, std::uint32_t>> on_edge;  // (parameter along the edge, vertex)
    std::size_t before = tris.size();
    for (std::size_t i = 0; i < uses.size();) {
      std::size_t j = i + 1;
      while (j < uses.size() && uses[j].key == uses[i].key) ++j;
      if (j - i == 1 && !split_this_pass[uses[i].use / 3]) {
        const auto t = static_cast<std::uint32_t>(uses[i].use / 3);
        const int e = static_cast<int>(uses[i].use % 3);
        const std::uint32_t u = tris[t][e], v = tris[t][(e + 1) % 3], x = tris[t][(e + 2) % 3];
        const Vec3 a = local[u], d = local[v] - a;
        const float dd = glm::dot(d, d);
        on_edge.clear();
        // Parameters of the piece of the edge being searched: a vertex counts in the piece that
        // holds its parameter, so one found by two pieces' boxes counts once.
        float piece_lo = 0.0f, piece_hi = 2.0f;
        const auto consider = [&](std::uint32_t q) {
          if (q == u || q == v) return;
          const float s = glm::dot(local[q] - a, d) / dd;
          if (!(s > 0.0f && s < 1.0f && s >= piece_lo && s < piece_hi)) return;
          const Vec3 off = local[q] - (a + s * d);
          if (!(glm::dot(off, off) <= tolerance * tolerance)) return;
          // A true T-junction: some triangle at q has an edge along (u, v) and lies on the other
          // side of it than x.
          const Vec3 x_side = glm::cross(d, local[x] - a);
          bool other_side = false;
          for (std::uint32_t k2 = around_start[q]; k2 < around_start[q + 1] && !other_side; ++k2) {
            const glm::uvec3 o = tris[around[k2]];
            // `around` is from the start of the pass: a triangle split since may no longer have q
            // (its other half is found next pass).
            if (o.x != q && o.y != q && o.z != q) continue;
            for (int c = 0; c < 3 && !other_side; ++c) {
              const std::uint32_t y = o[c];
              if (y == q) continue;
              const float sy = glm::dot(local[y] - a, d) / dd;
              const Vec3 off_y = local[y] - (a + sy * d);
              if (sy < -1e-6f || sy > 1.0f + 1e-6f || glm::dot(off_y, off_y) > tolerance * tolerance) continue;
              const std::uint32_t third = o[0] + o[1] + o[2] - q - y;  // the corner off the line
              // Clearly the other side: the two triangles continue each other (a fold of less
              // than about 84 degrees), not a wall standing on the edge, where the sign is noise.
              const Vec3 o_side = glm::cross(d, local[third] - a);
              other_side = glm::dot(o_side, x_side) < -kTJunctionSideCos * glm::length(o_side) * glm::length(x_side);
            }
          }
          if (other_side) on_edge.emplace_back(s, q);
        };
        const Vec3 box_lo = glm::min(a, local[v]) - Vec3(tolerance);
        const Vec3 box_hi = glm::max(a, local[v]) + Vec3(tolerance);
        if (!(dd > 0.0f)) {
          // No direction: nothing lies inside it.
        } else if (grid && grid->cell_count(box_lo, box_hi) <= kTJunctionGridCells) {
          grid->for_each(box_lo, box_hi, consider);
        } else {
          // The axis whose slab around the edge holds the fewest vertices.
          int best_axis = 0;
          std::size_t best_count = std::numeric_limits<std::size_t>::max();
          std::array<std::pair<std::size_t, std::size_t>, 3> range{};
          for (int axis = 0; axis < 3; ++axis) {
            const auto& list = keys[axis];
            const auto first = std::lower_bound(list.begin(), list.end(), box_lo[axis]);
            const auto last = std::upper_bound(first, list.end(), box_hi[axis]);
            range[axis] = {static_cast<std::size_t>(first - list.begin()), static_cast<std::size_t>(last - list.begin())};
            if (range[axis].second - range[axis].first < best_count) {
              best_count = range[axis].second - range[axis].first;
              best_axis = axis;
            }
          }
          // Against it, the grid read in pieces about a cell long: the cells along the edge.
          std::uint64_t pieces = 0, piece_cells = 0;
          Vec3 pad{0.0f};
          if (grid) {
            const float n = std::ceil(max_abs(d) / grid->cell());
            if (n >= 1.0f && n <= static_cast<float>(best_count)) {
              pieces = static_cast<std::uint64_t>(n);
              pad = Vec3(tolerance + kTJunctionPieceSlack * (grid->cell() + max_abs(a) + max_abs(d)));
              const Vec3 end = a + d / n;
              piece_cells = grid->cell_count(glm::min(a, end) - pad, glm::max(a, end) + pad);
            }
          }
          // (Divided, not multiplied: a piece's box may span up to 2^63 cells.)
          if (pieces > 0 && piece_cells <= best_count / pieces) {
            const auto count = static_cast<float>(pieces);
            for (std::uint64_t k = 0; k < pieces; ++k) {
              // The same expression for a boundary from both sides, so the pieces tile [0, 1).
              piece_lo = static_cast<float>(k) / count;
              piece_hi = k + 1 == pieces ? 2.0f : static_cast<float>(k + 1) / count;
              const Vec3 p0 = a + piece_lo * d, p1 = a + std::min(piece_hi, 1.0f) * d;
              grid->for_each(glm::min(p0, p1) - pad, glm::max(p0, p1) + pad, consider);
            }
          } else {
            for (std::size_t k = range[best_axis].first; k < range[best_axis].second; ++k) consider(sorted[best_axis][k]);
          }
        }
        auto solid = [&](std::uint32_t p0, std::uint32_t p1, std::uint32_t p2) {  // the degenerate test of step 3
          const Vec3 e0 = local[p1] - local[p0], e1 = local[p2] - local[p1], e2 = local[p0] - local[p2];
          const float longest2 = std::max({glm::dot(e0, e0), glm::dot(e1, e1), glm::dot(e2, e2)});
          return glm::length(glm::cross(e0, -e2)) > kWalkDegenerateTolerance * longest2;
        };
        // Cut the edge at each vertex in order from u; the triangle holding the rest of the edge
        // (first t, then the last one added) is cut again.
        std::sort(on_edge.begin(), on_edge.end());
        std::uint32_t rest = t, from = u;
        float from_param = 0.0f;
        for (const auto& [s, w] : on_edge) {
          if (!(s > from_param)) continue;  // coincident with the last cut
          if (!solid(from, w, x) || !solid(w, v, x)) break;
          tris[rest] = {from, w, x};
          rest = static_cast<std::uint32_t>(tris.size());
          tris.push_back({w, v, x});
          from = w;
          from_param = s;
          split_this_pass[t] = true;
          ++splits;
        }
      }
      i = j;
    }
    if (tris.size() == before) break;
  }
  return splits;
}

bool has_directed_edge(glm::uvec3 t, std::uint32_t u, std::uint32_t v) {
  return (t.x == u && t.y == v) || (t.y == u && t.z == v) || (t.z == u && t.x == v);
}

}  // namespace

Vec3 detail::local_origin(const TriangleSoup& soup) { return median_vertex(soup.positions, soup.triangles); }

void detail::check_float_span(float size, const std::string& name) {
  if (!std::isfinite(size)) {
    throw InvalidInput(name + ": spans more than float range (coordinates near +-3.4e38 on both sides); "
                              "no float frame holds it");
  }
}

float detail::tolerance_scale(const TriangleSoup& soup, float size, const std::string& name) {
  std::vector<float> edges;
  edges.reserve(3 * soup.triangles.size());
  for (const glm::uvec3& t : soup.triangles) {
    for (int k = 0; k < 3; ++k) {
      const float length = glm::length(soup.positions[t[(k + 1) % 3]] - soup.positions[t[k]]);
      if (length > 0.0f) edges.push_back(length);
    }
  }
  if (edges.empty()) return size;
  const auto middle = edges.begin() + static_cast<std::ptrdiff_t>(edges.size() / 2);
  std::nth_element(edges.begin(), middle, edges.end());
  const float median = *middle;
  const float rounding = size * 0x1p-24f;
  if (rounding > kWalkPrecisionFraction * median) {
    throw InvalidInput(name + ": spans " + std::to_string(size) + " but its median edge is " + std::to_string(median) +
                       ": float rounding over that span (" + std::to_string(rounding) +
                       ") is too coarse for its triangles; build pieces this far apart as separate walk meshes");
  }
  // Rounded down to a power of two: adding or removing a few triangles moves the median a little,
  // and decisions right at a tolerance (contacts in headroom tests) must not flip with it.
  const float scale = std::min(size, kWalkScaleMedianEdges * median);
  return scale > 0.0f ? std::exp2(std::floor(std::log2(scale))) : scale;
}

void validate_triangle_soup(const TriangleSoup& soup) {
  const std::string name = where(soup);
  if (soup.triangles.empty()) throw InvalidInput(name + ": no triangles");
  const std::size_t nv = soup.positions.size();
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = soup.triangles[t][k];
      if (v >= nv) {
        throw InvalidInput(name + ": triangle " + std::to_string(t) + ": vertex index " +
                           std::to_string(v) + " out of range (" + std::to_string(nv) + " vertices)");
      }
      if (!is_finite(soup.positions[v])) {
        throw InvalidInput(name + ": triangle " + std::to_string(t) + ": vertex " + std::to_string(v) +
                           " is not finite");
      }
    }
  }
}

WalkMesh build_walk_mesh(const TriangleSoup& soup, const WalkMeshOptions& options) {
  const std::string name = where(soup);
  if (!is_finite(options.up) || !(glm::length(options.up) > 0.0f)) {
    throw InvalidInput(name + ": WalkMeshOptions.up must be a finite non-zero vector");
  }
  if (!std::isfinite(options.weld_tolerance) || options.weld_tolerance < 0.0f) {
    throw InvalidInput(name + ": WalkMeshOptions.weld_tolerance must be finite and >= 0");
  }
  if (!std::isfinite(options.tolerance_scale) || options.tolerance_scale < 0.0f) {
    throw InvalidInput(name + ": WalkMeshOptions.tolerance_scale must be finite and >= 0");
  }
  validate_triangle_soup(soup);
  const Vec3 up = glm::normalize(options.up);

  // 1. Bounds of the vertices that triangles use (only those must be finite).
  const std::size_t nv = soup.positions.size();
  std::vector<bool> used(nv, false);
  Aabb3 box{soup.positions[soup.triangles[0].x], soup.positions[soup.triangles[0].x]};
  for (const glm::uvec3& t : soup.triangles) {
    for (int k = 0; k < 3; ++k) {
      used[t[k]] = true;
      box = merge(box, Aabb3{soup.positions[t[k]], soup.positions[t[k]]});
    }
  }

  // 2. Shift to a local origin (float precision far from the world origin: the vertices' median,
  //    which a piece far from the rest does not drag away), then weld.
  WalkMesh mesh;
  mesh.origin_ = detail::local_origin(soup);
  const Vec3 extent = box.size();
  mesh.size_ = std::max({extent.x, extent.y, extent.z});
  detail::check_float_span(mesh.size_, name);
  std::vector<Vec3> local(nv);
  for (std::size_t i = 0; i < nv; ++i) {
    if (used[i]) local[i] = soup.positions[i] - mesh.origin_;
  }
  WalkMeshStats stats;
  stats.input_triangles = soup.triangles.size();
  const float scale = options.tolerance_scale > 0.0f ? options.tolerance_scale
                                                     : detail::tolerance_scale(soup, mesh.size_, name);
  const std::vector<std::uint32_t> rep = weld(local, used, options.weld_tolerance * scale, stats.welded_vertices);

  // 3. Drop degenerate and duplicate triangles.
  std::vector<glm::uvec3> tris;
  tris.reserve(soup.triangles.size());
  for (const glm::uvec3& in : soup.triangles) {
    const glm::uvec3 t{rep[in.x], rep[in.y], rep[in.z]};
    if (t.x == t.y || t.y == t.z || t.z == t.x) {
      ++stats.degenerate_triangles;
      continue;
    }
    const Vec3 a = local[t.x], b = local[t.y], c = local[t.z];
    const float longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    if (!(glm::length(glm::cross(b - a, c - a)) > kWalkDegenerateTolerance * longest2)) {
      ++stats.degenerate_triangles;
      continue;
    }
    tris.push_back(t);
  }
  {
    std::vector<std::pair<glm::uvec3, std::uint32_t>> keys(tris.size());
    for (std::uint32_t i = 0; i < tris.size(); ++i) {
      glm::uvec3 k = tris[i];
      if (k.x > k.y) std::swap(k.x, k.y);
      if (k.y > k.z) std::swap(k.y, k.z);
      if (k.x > k.y) std::swap(k.x, k.y);
      keys[i] = {k, i};
    }
    std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) {
      if (a.first.x != b.first.x) return a.first.x < b.first.x;
      if (a.first.y != b.first.y) return a.first.y < b.first.y;
      if (a.first.z != b.first.z) return a.first.z < b.first.z;
      return a.second < b.second;
    });
    std::vector<bool> keep(tris.size(), true);
    for (std::size_t i = 1; i < keys.size(); ++i) {
      if (keys[i].first == keys[i - 1].first) keep[keys[i].second] = false;
    }
    std::vector<glm::uvec3> unique;
    unique.reserve(tris.size());
    for (std::size_t i = 0; i < tris.size(); ++i) {
      if (keep[i]) unique.push_back(tris[i]);
    }
    stats.duplicate_triangles = tris.size() - unique.size();
    tris = std::move(unique);
  }
  if (tris.empty()) {
    throw InvalidInput(name + ": no usable triangles (all " + std::to_string(soup.triangles.size()) +
                       " are degenerate or duplicates)");
  }
  stats.t_junction_splits =
      split_t_junctions(tris, local, std::max(options.weld_tolerance, kWalkWeldTolerance) * scale);
  const auto nt = static_cast<std::uint32_t>(tris.size());

  // 4. Pair triangles over edges. An edge with more than two triangles links, greedily, the
  //    pairs that continue each other most flatly (their thirds on opposite sides of the edge).
  //    Uses by (lo, hi), then triangle (sort_edge_uses keeps use order).
  std::vector<EdgeSide> uses;
  uses.reserve(3 * tris.size());
  for (const EdgeUse& e : sort_edge_uses(tris, local.size(), [](std::uint32_t v) { return v; })) {
    const auto t = static_cast<std::uint32_t>(e.use / 3);
    const int k = static_cast<int>(e.use % 3);
    const std::uint32_t u = tris[t][k], v = tris[t][(k + 1) % 3];
    uses.push_back({std::min(u, v), std::max(u, v), t, tris[t][(k + 2) % 3]});
  }
  std::vector<Link> links;
  links.reserve(3 * tris.size() / 2);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    const std::size_t count = j - i;
    const Vec3 p = local[uses[i].lo];
    const Vec3 axis = glm::normalize(local[uses[i].hi] - p);
    auto side = [&](std::size_t k) {  // unit direction from the edge to the third vertex
      Vec3 d = local[uses[k].third] - p;
      d -= glm::dot(d, axis) * axis;
      return glm::normalize(d);
    };
    if (count == 2) {
      // Two triangles folded back onto each other (overlapping geometry) are not a walkable
      // continuation: no link, a wall.
      if (!(glm::dot(side(i), side(i + 1)) > kFoldBackLinkCos)) {
        links.push_back({uses[i].triangle, uses[i + 1].triangle, uses[i].lo, uses[i].hi});
      }
    } else if (count > 2) {
      ++stats.non_manifold_edges;
      struct Candidate {
        float flatness;
        std::size_t a, b;
      };
      std::vector<Candidate> candidates;
      for (std::size_t a = i; a < j; ++a) {
        for (std::size_t b = a + 1; b < j; ++b) candidates.push_back({-glm::dot(side(a), side(b)), a, b});
      }
      std::stable_sort(candidates.begin(), candidates.end(),
                       [](const Candidate& x, const Candidate& y) { return x.flatness > y.flatness; });
      std::vector<bool> paired(count, false);
      for (const Candidate& c : candidates) {
        if (paired[c.a - i] || paired[c.b - i] || -c.flatness > kFoldBackLinkCos) continue;
        paired[c.a - i] = paired[c.b - i] = true;
        links.push_back({uses[c.a].triangle, uses[c.b].triangle, uses[c.a].lo, uses[c.a].hi});
      }
    }
    i = j;
  }
  std::vector<std::array<std::uint32_t, 3>> links_of(nt, {kUnset, kUnset, kUnset});
  for (std::uint32_t l = 0; l < links.size(); ++l) {
    for (std::uint32_t t : {links[l].t0, links[l].t1}) {
      for (auto& slot : links_of[t]) {
        if (slot == kUnset) {
          slot = l;
          break;
        }
      }
    }
  }

  // 5. Consistent winding by breadth-first search over links: linked triangles must use their
  //    shared edge in opposite directions. A link that cannot agree is cut. Islands fall out.
  std::vector<std::int8_t> flip(nt, -1);
  std::vector<std::uint32_t> island(nt, kUnset);
  std::vector<std::uint32_t> queue;
  queue.reserve(nt);
  std::uint32_t islands = 0;
  for (std::uint32_t seed = 0; seed < nt; ++seed) {
    if (flip[seed] >= 0) continue;
    const std::uint32_t id = islands++;
    flip[seed] = 0;
    island[seed] = id;
    queue.clear();
    queue.push_back(seed);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t t = queue[q];
      for (std::uint32_t l : links_of[t]) {
        if (l == kUnset || links[l].cut) continue;
        Link& link = links[l];
        const std::uint32_t other = link.t0 == t ? link.t1 : link.t0;
        const bool same_direction = has_directed_edge(tris[t], link.lo, link.hi) ==
                                    has_directed_edge(tris[other], link.lo, link.hi);
        const std::int8_t want = static_cast<std::int8_t>(flip[t] ^ (same_direction ? 1 : 0));
        if (flip[other] < 0) {
          flip[other] = want;
          island[other] = id;
          queue.push_back(other);
        } else if (flip[other] != want) {
          link.cut = true;
          ++stats.orientation_conflicts;
        }
      }
    }
  }

  // 6. Turn each island so its area-weighted normal points up; an island with no clear up side
  //    (a closed surface, a vertical wall) keeps the winding most of its input area had.
  std::vector<double> up_sum(islands, 0.0), area_sum(islands, 0.0), flipped_area(islands, 0.0);
  for (std::uint32_t t = 0; t < nt; ++t) {
    const Vec3 n = glm::cross(local[tris[t].y] - local[tris[t].x], local[tris[t].z] - local[tris[t].x]);
    const double area = glm::length(n);
    const double facing = glm::dot(n, up) * (flip[t] ? -1.0 : 1.0);
    up_sum[island[t]] += facing;
    area_sum[island[t]] += area;
    if (flip[t]) flipped_area[island[t]] += area;
  }
  std::vector<bool> turn(islands);
  for (std::uint32_t i = 0; i < islands; ++i) {
    if (std::fabs(up_sum[i]) > kIslandUpTolerance * area_sum[i]) {
      turn[i] = up_sum[i] < 0.0;
    } else {
      turn[i] = flipped_area[i] > 0.5 * area_sum[i];
    }
  }
  for (std::uint32_t t = 0; t < nt; ++t) {
    if ((flip[t] != 0) != turn[island[t]]) {
      std::swap(tris[t].y, tris[t].z);
      ++stats.flipped_triangles;
    }
  }

  // 7. Compact the vertices, store them relative to the origin.
  std::vector<std::uint32_t> index(nv, kUnset);
  for (glm::uvec3& t : tris) {
    for (int k = 0; k < 3; ++k) {
      if (index[t[k]] == kUnset) {
        index[t[k]] = static_cast<std::uint32_t>(mesh.positions_.size());
        mesh.positions_.push_back(local[t[k]]);
      }
      t[k] = index[t[k]];
    }
  }
  for (Link& link : links) {
    link.lo = index[link.lo];
    link.hi = index[link.hi];
  }
  mesh.triangles_ = std::move(tris);
  mesh.islands_ = std::move(island);

  // 8. Neighbours from the links that survived.
  mesh.neighbors_.assign(nt, {kNoNeighbor, kNoNeighbor, kNoNeighbor});
  mesh.neighbor_edges_.assign(nt, {0, 0, 0});
  for (const Link& link : links) {
    if (link.cut) continue;
    int e0 = mesh.local_edge(link.t0, link.lo, link.hi);
    if (e0 < 0) e0 = mesh.local_edge(link.t0, link.hi, link.lo);
    int e1 = mesh.local_edge(link.t1, link.lo, link.hi);
    if (e1 < 0) e1 = mesh.local_edge(link.t1, link.hi, link.lo);
    mesh.neighbors_[link.t0][e0] = link.t1;
    mesh.neighbors_[link.t1][e1] = link.t0;
    mesh.neighbor_edges_[link.t0][e0] = static_cast<std::uint8_t>(e1);
    mesh.neighbor_edges_[link.t1][e1] = static_cast<std::uint8_t>(e0);
  }

  // 9. Normals, bounds, BVH, statistics.
  mesh.triangle_normals_.resize(nt);
  mesh.weight_gradients_.resize(nt);
  mesh.vertex_normals_.assign(mesh.positions_.size(), Vec3(0.0f));
  for (std::uint32_t t = 0; t < nt; ++t) {
    const glm::uvec3 tri = mesh.triangles_[t];
    const Vec3 n = glm::cross(mesh.positions_[tri.y] - mesh.positions_[tri.x],
                              mesh.positions_[tri.z] - mesh.positions_[tri.x]);
    mesh.triangle_normals_[t] = glm::normalize(n);
    const float inv_nn = 1.0f / glm::dot(n, n);
    const Vec3 a = mesh.positions_[tri.x], b = mesh.positions_[tri.y], c = mesh.positions_[tri.z];
    mesh.weight_gradients_[t] = {glm::cross(n, c - b) * inv_nn, glm::cross(n, a - c) * inv_nn,
                                 glm::cross(n, b - a) * inv_nn};
    for (int k = 0; k < 3; ++k) mesh.vertex_normals_[tri[k]] += n;  // area-weighted
  }
  for (std::size_t v = 0; v < mesh.vertex_normals_.size(); ++v) {
    const float len = glm::length(mesh.vertex_normals_[v]);
    mesh.vertex_normals_[v] = len > 0.0f ? mesh.vertex_normals_[v] / len : up;
  }
  mesh.local_bounds_ = {mesh.positions_[0], mesh.positions_[0]};
  for (const Vec3& p : mesh.positions_) mesh.local_bounds_ = merge(mesh.local_bounds_, Aabb3{p, p});
  mesh.bvh_ = TriangleBvh(mesh.positions_, mesh.triangles_);
  for (const auto& n : mesh.neighbors_) {
    for (std::uint32_t x : n) stats.boundary_edges += x == kNoNeighbor ? 1 : 0;
  }
  stats.triangles = nt;
  stats.vertices = mesh.positions_.size();
  stats.islands = islands;
  mesh.stats_ = stats;
  return mesh;
}

}  // namespace collide
