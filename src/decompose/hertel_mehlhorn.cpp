// Hertel-Mehlhorn: coarsen a triangulation into convex pieces, and the whole decomposition.

#include <collide/decompose/convex_decomposition.hpp>

#include <collide/core/error.hpp>

#include "corner_turn.hpp"
#include "decomposition_steps.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

namespace collide {

namespace detail {

void merge_triangles(std::span<const Vec2> outline, std::span<const TriangleIndices> triangles,
                     DecompositionScratch& scratch, FlatPieces& out, bool twins_known) {
  // The triangulation as half-edges: half-edge h = 3 t + j runs from corner j of triangle t to
  // corner j + 1. Pieces are rings of half-edges linked by next/prev; removing a diagonal
  // splices two rings into one, so a merge costs O(1) and allocates nothing.
  const int m = static_cast<int>(triangles.size());
  const int count = 3 * m;
  auto origin = [&](int h) { return triangles[static_cast<size_t>(h / 3)][static_cast<size_t>(h % 3)]; };
  auto dest = [&](int h) { return triangles[static_cast<size_t>(h / 3)][static_cast<size_t>((h % 3 + 1) % 3)]; };
  std::vector<int>& next = scratch.next;
  std::vector<int>& prev = scratch.prev;
  std::vector<int>& twin = scratch.twin;
  next.resize(static_cast<size_t>(count));
  prev.resize(static_cast<size_t>(count));
  if (!twins_known) twin.assign(static_cast<size_t>(count), -1);
  for (int h = 0; h < count; ++h) {
    next[h] = 3 * (h / 3) + (h % 3 + 1) % 3;
    prev[h] = 3 * (h / 3) + (h % 3 + 2) % 3;
  }
  if (!twins_known) {  // A diagonal is the edge two triangles share, once in each direction. Bucket half-edges
     // by origin vertex (counting sort); the twin of a -> b is the b -> a in b's bucket.
    const int n = static_cast<int>(outline.size());
    std::vector<int>& start = scratch.bucket_start;
    std::vector<int>& fill = scratch.bucket_fill;
    std::vector<int>& by_origin = scratch.by_origin;
    start.assign(static_cast<size_t>(n) + 1, 0);
    for (int h = 0; h < count; ++h) ++start[static_cast<size_t>(origin(h)) + 1];
    for (int v = 0; v < n; ++v) start[v + 1] += start[v];
    fill.assign(start.begin(), start.end() - 1);
    by_origin.resize(static_cast<size_t>(count));
    for (int h = 0; h < count; ++h) by_origin[fill[origin(h)]++] = h;
    for (int h = 0; h < count; ++h) {
      const int b = dest(h);
      for (int k = start[b]; k < start[b + 1]; ++k) {
        if (dest(by_origin[k]) == origin(h)) twin[h] = by_origin[k];
      }
    }
  }
  // Union-find over triangles tracks which piece a half-edge is in and its vertex count.
  std::vector<int>& parent = scratch.parent;
  std::vector<int>& size = scratch.size;
  parent.resize(static_cast<size_t>(m));
  size.assign(static_cast<size_t>(m), 3);
  for (int t = 0; t < m; ++t) parent[t] = t;
  auto find = [&](int t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  std::vector<unsigned char>& removed = scratch.removed;
  removed.assign(static_cast<size_t>(count), 0);
  const float straight = outline.empty()
                             ? 0.0f
                             : detail::straight_turn_tolerance(detail::outline_size(outline));

  // Each diagonal once, in the order the triangulation made them.
  for (int h = 0; h < count; ++h) {
    const int g = twin[h];
    if (g < h) continue;  // an outline edge (-1) or already seen from the other side
    const int p = find(h / 3);
    const int q = find(g / 3);
    if (p == q || size[p] + size[q] - 2 > kMaxPolygonVertices) continue;
    // h runs a -> b in piece P, g runs b -> a in piece Q. Removing a-b changes only the corners
    // at a and b; a straight corner is fine (decompose_convex drops the vertex), a reflex one
    // is not.
    const Vec2 a = outline[origin(h)];
    const Vec2 b = outline[dest(h)];
    const bool convex_at_a =
        detail::corner_turn(outline[origin(prev[h])], a, outline[dest(next[g])]) >= -straight;
    const bool convex_at_b =
        detail::corner_turn(outline[origin(prev[g])], b, outline[dest(next[h])]) >= -straight;
    if (!convex_at_a || !convex_at_b) continue;
    next[prev[h]] = next[g];
    prev[next[g]] = prev[h];
    next[prev[g]] = next[h];
    prev[next[h]] = prev[g];
    removed[h] = removed[g] = 1;
    parent[q] = p;
    size[p] += size[q] - 2;
  }

  std::vector<unsigned char>& visited = scratch.visited;
  visited.assign(static_cast<size_t>(count), 0);
  out.start.clear();
  out.vertices.clear();
  out.start.push_back(0);
  for (int h = 0; h < count; ++h) {
    if (removed[h] || visited[h]) continue;
    for (int e = h; !visited[e]; e = next[e]) {
      visited[e] = 1;
      out.vertices.push_back(origin(e));
    }
    out.start.push_back(static_cast<int>(out.vertices.size()));
  }
}

}  // namespace detail

std::vector<std::vector<int>> merge_hertel_mehlhorn(std::span<const Vec2> outline,
                                                    std::span<const TriangleIndices> triangles) {
  detail::DecompositionScratch scratch;
  detail::FlatPieces flat;
  detail::merge_triangles(outline, triangles, scratch, flat, false);
  std::vector<std::vector<int>> pieces;
  for (size_t k = 0; k < flat.count(); ++k) {
    pieces.emplace_back(flat.vertices.begin() + flat.start[k], flat.vertices.begin() + flat.start[k + 1]);
  }
  return pieces;
}

std::vector<Polygon> decompose_convex(std::span<const Vec2> points, std::string_view name,
                                      int triangulations) {
  if (triangulations < 1) {
    throw InvalidInput(std::string(name) + ": decompose_convex needs triangulations >= 1");
  }
  const SimpleOutline outline = make_simple_outline(points, name);
  const int n = static_cast<int>(outline.vertices.size());
  const float straight = detail::straight_turn_tolerance(detail::outline_size(outline.vertices));
  // Every reflex vertex must be resolved by a cut and one cut resolves at most two, so no
  // decomposition has fewer than ceil(r / 2) + 1 pieces (Chazelle & Dobkin 1985): stop trying
  // triangulations once one reaches that.
  int reflex = 0;
  for (int i = 0; i < n; ++i) {
    reflex += detail::corner_turn(outline.vertices[(i + n - 1) % n], outline.vertices[i],
                                  outline.vertices[(i + 1) % n]) < -straight;
  }
  const size_t lower_bound = static_cast<size_t>((reflex + 1) / 2 + 1);
  detail::DecompositionScratch scratch;
  std::vector<TriangleIndices> triangles;
  detail::FlatPieces pieces;
  detail::FlatPieces candidate;
  const int starts = std::min(n, triangulations);
  for (int k = 0; k < starts && pieces.count() != lower_bound; ++k) {
    detail::ear_clip(outline.vertices, name, k * n / starts, scratch, triangles);
    detail::merge_triangles(outline.vertices, triangles, scratch, candidate, true);
    if (k == 0 || candidate.count() < pieces.count()) std::swap(pieces, candidate);
  }
  std::vector<Polygon> out;
  out.reserve(pieces.count());
  std::vector<Vec2> corners;
  for (size_t k = 0; k < pieces.count(); ++k) {
    corners.clear();
    for (int v = pieces.start[k]; v < pieces.start[k + 1]; ++v) {
      corners.push_back(outline.vertices[static_cast<size_t>(pieces.vertices[v])]);
    }
    // Merging may leave straight corners where a diagonal met the outline; drop them.
    for (size_t i = 0; corners.size() > 3 && i < corners.size();) {
      const size_t c = corners.size();
      if (detail::corner_turn(corners[(i + c - 1) % c], corners[i], corners[(i + 1) % c]) <=
          straight) {
        corners.erase(corners.begin() + static_cast<std::ptrdiff_t>(i));
        i = 0;
      } else {
        ++i;
      }
    }
    out.push_back(make_convex_polygon(corners));
  }
  return out;
}

}  // namespace collide
