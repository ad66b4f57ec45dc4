// Ear clipping triangulation of a simple counter-clockwise outline.

#include <collide/decompose/convex_decomposition.hpp>

#include <collide/core/error.hpp>

#include "corner_turn.hpp"
#include "decomposition_steps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace collide {
namespace {

/// A turn computed in float from coordinates of magnitude up to x, over edges up to L long, is
/// off by up to about this many float epsilons of x L (the two differences are off by an
/// epsilon of x each; the cross product adds one of L^2 <= x L). TurnScale::triangle never
/// calls a corner convex below it.
constexpr float kTurnRoundingUlps = 4.0f;

/// p inside the counter-clockwise triangle a, b, c, on its boundary, or outside by no more than
/// `tol` (a turn, twice an area): a vertex on or near the cut a-c blocks the cut, whichever way
/// float rounding puts it.
bool in_closed_triangle(Vec2 p, Vec2 a, Vec2 b, Vec2 c, float tol) noexcept {
  return cross(b - a, p - a) >= -tol && cross(c - b, p - b) >= -tol && cross(a - c, p - c) >= -tol;
}

}  // namespace

namespace detail {

void ear_clip(std::span<const Vec2> outline, std::string_view name, int first_corner,
              DecompositionScratch& scratch, std::vector<TriangleIndices>& triangles, TurnScale scale) {
  const int n = static_cast<int>(outline.size());
  triangles.clear();
  if (n < 3) return;
  triangles.reserve(static_cast<size_t>(n - 2));
  const float size = detail::outline_size(outline);
  const float outline_straight = detail::straight_turn_tolerance(size);
  // TurnScale::triangle: float rounding of a turn from coordinates of magnitude up to `extent`,
  // per unit of edge length.
  float extent = 0.0f;
  for (Vec2 p : outline) extent = std::max({extent, std::fabs(p.x), std::fabs(p.y)});
  const float rounding = kTurnRoundingUlps * std::numeric_limits<float>::epsilon() * extent;
  // The turn at most which the corner b of the triangle a, b, c is straight.
  auto straight_at = [&](Vec2 a, Vec2 b, Vec2 c) {
    if (scale == TurnScale::outline) return outline_straight;
    const float longest = std::max({distance_squared(a, b), distance_squared(b, c), distance_squared(c, a)});
    return std::max(kDegenerateAreaTolerance * longest, rounding * std::sqrt(longest));
  };

  // The remaining polygon as a doubly linked ring of outline indices.
  // Half-edge partners, filled as triangles are cut: ring_twin[v] is the half-edge of an
  // already cut triangle that runs opposite to the ring edge v -> next(v) (-1: outline edge).
  std::vector<int>& ring_twin = scratch.ring_twin;
  std::vector<int>& twin = scratch.twin;
  ring_twin.assign(static_cast<size_t>(n), -1);
  twin.assign(static_cast<size_t>(3 * (n - 2)), -1);
  auto emit = [&](int p, int c, int x) {  // triangle p, c, x: half-edges p->c, c->x, x->p
    const int h = 3 * static_cast<int>(triangles.size());
    triangles.push_back({p, c, x});
    for (const auto& [edge, from] : {std::pair{h, p}, std::pair{h + 1, c}}) {
      if (ring_twin[from] >= 0) {
        twin[edge] = ring_twin[from];
        twin[ring_twin[from]] = edge;
      }
    }
    ring_twin[p] = h + 2;  // the cut x -> p faces the new ring edge p -> x
  };
  std::vector<int>& prev = scratch.ring_prev;
  std::vector<int>& next = scratch.ring_next;
  prev.resize(static_cast<size_t>(n));
  next.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  // Only a corner that is not strictly convex can lie in an ear's triangle (a convex corner
  // inside would put a reflex one inside too), so the ear test scans those alone.
  std::vector<unsigned char>& convex = scratch.convex;
  convex.resize(static_cast<size_t>(n));
  auto update = [&](int i) {
    const Vec2 a = outline[prev[i]], b = outline[i], c = outline[next[i]];
    convex[i] = detail::corner_turn(a, b, c) > straight_at(a, b, c);
  };
  for (int i = 0; i < n; ++i) update(i);
  // An ear: all three corners of its triangle strictly convex (so the triangle is a valid
  // Polygon) and no other remaining vertex in the closed triangle (so the cut is a diagonal).
  auto is_ear = [&](int i) {
    if (!convex[i]) return false;
    const Vec2 a = outline[prev[i]];
    const Vec2 b = outline[i];
    const Vec2 c = outline[next[i]];
    const float straight = straight_at(a, b, c);
    if (detail::corner_turn(b, c, a) <= straight || detail::corner_turn(c, a, b) <= straight) {
      return false;
    }
    for (int j = next[next[i]]; j != prev[i]; j = next[j]) {
      if (!convex[j] && in_closed_triangle(outline[j], a, b, c, straight)) return false;
    }
    return true;
  };

  int remaining = n;
  int cursor = ((first_corner % n) + n) % n;
  int since_last_ear = 0;  // corners inspected since the last clip: a full lap means no ear
  while (remaining > 3) {
    if (is_ear(cursor)) {
      emit(prev[cursor], cursor, next[cursor]);
      const int before = prev[cursor];
      const int after = next[cursor];
      next[before] = after;
      prev[after] = before;
      update(before);
      update(after);
      cursor = before;  // the corners beside the cut changed; look there first
      --remaining;
      since_last_ear = 0;
      continue;
    }
    cursor = next[cursor];
    if (++since_last_ear > remaining) {
      // Either what is left is flat (a zero-area sliver of straight corners: nothing to add),
      // or float rounding hid every ear of a nearly self-touching outline.
      std::vector<Vec2> rest;
      for (int k = 0, j = cursor; k < remaining; ++k, j = next[j]) rest.push_back(outline[j]);
      const float rest_size = detail::outline_size(rest);
      const float flat = scale == TurnScale::outline
                             ? outline_straight
                             : std::max(kDegenerateAreaTolerance * rest_size * rest_size, rounding * rest_size);
      if (std::fabs(signed_area(rest)) <= flat) return;
      throw InvalidInput(std::string(name) +
                         ": polygon could not be triangulated (outline nearly touches itself)");
    }
  }
  const TriangleIndices last{prev[cursor], cursor, next[cursor]};
  const Vec2 a = outline[last[0]], b = outline[last[1]], c = outline[last[2]];
  if (detail::corner_turn(a, b, c) > straight_at(a, b, c)) emit(last[0], last[1], last[2]);
}

}  // namespace detail

std::vector<TriangleIndices> triangulate_ear_clipping(std::span<const Vec2> outline,
                                                      std::string_view name, int first_corner,
                                                      TurnScale scale) {
  detail::DecompositionScratch scratch;
  std::vector<TriangleIndices> triangles;
  detail::ear_clip(outline, name, first_corner, scratch, triangles, scale);
  return triangles;
}

}  // namespace collide
