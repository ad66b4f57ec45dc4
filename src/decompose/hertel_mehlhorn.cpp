// Hertel-Mehlhorn: coarsen a triangulation into convex pieces, and the whole decomposition.

#include <collide/decompose/convex_decomposition.hpp>

#include "corner_turn.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>

namespace collide {
namespace {

std::uint64_t edge_key(int from, int to) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) |
         static_cast<std::uint32_t>(to);
}

/// `piece` rotated so that it starts at vertex `first`.
std::vector<int> starting_at(const std::vector<int>& piece, int first) {
  std::vector<int> out(piece.size());
  const auto it = std::find(piece.begin(), piece.end(), first);
  std::rotate_copy(piece.begin(), it, piece.end(), out.begin());
  return out;
}

}  // namespace

std::vector<std::vector<int>> merge_hertel_mehlhorn(std::span<const Vec2> outline,
                                                    std::span<const TriangleIndices> triangles) {
  std::vector<std::vector<int>> pieces;
  pieces.reserve(triangles.size());
  // owner[a -> b] = the piece whose counter-clockwise boundary holds the directed edge a -> b.
  std::unordered_map<std::uint64_t, int> owner;
  for (const TriangleIndices& t : triangles) {
    const int id = static_cast<int>(pieces.size());
    pieces.push_back({t[0], t[1], t[2]});
    for (int k = 0; k < 3; ++k) owner[edge_key(t[k], t[(k + 1) % 3])] = id;
  }
  if (outline.empty()) return pieces;
  const float straight = detail::straight_turn_tolerance(detail::outline_size(outline));
  std::vector<bool> alive(pieces.size(), true);

  // Each diagonal once (a < b), in the order the triangulation made them.
  for (const TriangleIndices& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[k];
      const int b = t[(k + 1) % 3];
      if (a > b) continue;
      const auto pa = owner.find(edge_key(a, b));
      const auto qa = owner.find(edge_key(b, a));
      if (pa == owner.end() || qa == owner.end()) continue;  // an outline edge
      const int p = pa->second;
      const int q = qa->second;
      if (p == q) continue;
      const size_t merged_count = pieces[p].size() + pieces[q].size() - 2;
      if (merged_count > static_cast<size_t>(kMaxPolygonVertices)) continue;
      // P holds a -> b, Q holds b -> a. Merged boundary: P from b round to a, then Q's
      // vertices strictly between a and b.
      const std::vector<int> pr = starting_at(pieces[p], b);  // b ... a
      const std::vector<int> qr = starting_at(pieces[q], a);  // a ... b
      // Removing a-b changes only the corners at a and b; a straight corner is fine (the
      // vertex is dropped when the piece becomes a Polygon), a reflex one is not.
      const bool convex_at_a =
          detail::corner_turn(outline[pr[pr.size() - 2]], outline[a], outline[qr[1]]) >= -straight;
      const bool convex_at_b =
          detail::corner_turn(outline[qr[qr.size() - 2]], outline[b], outline[pr[1]]) >= -straight;
      if (!convex_at_a || !convex_at_b) continue;
      std::vector<int> merged = pr;
      merged.insert(merged.end(), qr.begin() + 1, qr.end() - 1);
      owner.erase(edge_key(a, b));
      owner.erase(edge_key(b, a));
      for (size_t i = 0; i < merged.size(); ++i) {
        owner[edge_key(merged[i], merged[(i + 1) % merged.size()])] = p;
      }
      pieces[p] = std::move(merged);
      pieces[q].clear();
      alive[q] = false;
    }
  }
  std::vector<std::vector<int>> out;
  for (size_t i = 0; i < pieces.size(); ++i) {
    if (alive[i]) out.push_back(std::move(pieces[i]));
  }
  return out;
}

std::vector<Polygon> decompose_convex(std::span<const Vec2> points, std::string_view name) {
  const SimpleOutline outline = make_simple_outline(points, name);
  const int n = static_cast<int>(outline.vertices.size());
  std::vector<std::vector<int>> pieces;
  const int starts = n <= kDecompositionRetryLimit ? n : 1;
  for (int start = 0; start < starts; ++start) {
    std::vector<std::vector<int>> candidate = merge_hertel_mehlhorn(
        outline.vertices, triangulate_ear_clipping(outline.vertices, name, start));
    if (pieces.empty() || candidate.size() < pieces.size()) pieces = std::move(candidate);
  }
  std::vector<Polygon> out;
  out.reserve(pieces.size());
  const float straight = detail::straight_turn_tolerance(detail::outline_size(outline.vertices));
  std::vector<Vec2> corners;
  for (const std::vector<int>& piece : pieces) {
    corners.clear();
    for (int i : piece) corners.push_back(outline.vertices[static_cast<size_t>(i)]);
    // Merging may leave straight corners where a diagonal met the outline; drop them.
    for (size_t i = 0; corners.size() > 3 && i < corners.size();) {
      const size_t n = corners.size();
      if (detail::corner_turn(corners[(i + n - 1) % n], corners[i], corners[(i + 1) % n]) <=
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
