// Validation and cleaning of a user's polygon outline before decomposition.

#include <collide/decompose/convex_decomposition.hpp>

#include <collide/core/error.hpp>

#include "corner_turn.hpp"

#include <algorithm>
#include <string>

namespace collide {
namespace {

std::string label(std::string_view name) { return std::string(name) + ": "; }

/// Sign of the turn a -> b -> c without tolerance: exact touching counts as touching.
int orientation(Vec2 a, Vec2 b, Vec2 c) noexcept {
  const float t = cross(b - a, c - a);
  return (t > 0.0f) - (t < 0.0f);
}

/// p on the closed segment a-b, given that a, b, p are collinear.
bool within_box(Vec2 a, Vec2 b, Vec2 p) noexcept {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

/// Closed segments p1-p2 and q1-q2 share a point (crossing, touching or overlapping).
/// Orientation tests, Cormen et al., "Introduction to Algorithms", 33.1.
bool segments_touch(Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2) noexcept {
  const int d1 = orientation(q1, q2, p1);
  const int d2 = orientation(q1, q2, p2);
  const int d3 = orientation(p1, p2, q1);
  const int d4 = orientation(p1, p2, q2);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && within_box(q1, q2, p1)) || (d2 == 0 && within_box(q1, q2, p2)) ||
         (d3 == 0 && within_box(p1, p2, q1)) || (d4 == 0 && within_box(p1, p2, q2));
}

}  // namespace

SimpleOutline make_simple_outline(std::span<const Vec2> points, std::string_view name,
                                  StraightCorners straight_corners) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!is_finite(points[i])) {
      throw InvalidInput(label(name) + "polygon vertex " + std::to_string(i) + ": not finite");
    }
  }
  if (points.size() < 3) {
    throw InvalidInput(label(name) + "polygon needs at least 3 vertices, got " +
                       std::to_string(points.size()));
  }
  const float size = detail::outline_size(points);
  const float weld = kWeldTolerance * size;
  const float straight = detail::straight_turn_tolerance(size);

  SimpleOutline out;
  // Drop consecutive duplicates (cyclically: a closing copy of the first vertex goes too).
  for (size_t i = 0; i < points.size(); ++i) {
    if (!out.vertices.empty() && distance_squared(out.vertices.back(), points[i]) <= weld * weld) {
      continue;
    }
    out.vertices.push_back(points[i]);
    out.source.push_back(static_cast<int>(i));
  }
  while (out.vertices.size() > 1 &&
         distance_squared(out.vertices.back(), out.vertices.front()) <= weld * weld) {
    out.vertices.pop_back();
    out.source.pop_back();
  }
  if (out.vertices.size() < 3) {
    throw InvalidInput(label(name) + "polygon has fewer than 3 distinct vertices (" +
                       std::to_string(out.vertices.size()) + ")");
  }
  // All on one line (within tolerance of the line through vertex 0 and the vertex farthest
  // from it): zero area, whatever else is wrong with the outline.
  {
    const Vec2 origin = out.vertices[0];
    Vec2 far = origin;
    for (Vec2 v : out.vertices) {
      if (distance_squared(origin, v) > distance_squared(origin, far)) far = v;
    }
    const bool collinear = std::all_of(out.vertices.begin(), out.vertices.end(), [&](Vec2 v) {
      return std::fabs(cross(far - origin, v - origin)) <= straight;
    });
    if (collinear) {
      throw InvalidInput(label(name) + "polygon has zero area (all vertices collinear)");
    }
  }
  // Drop straight corners until none is left (or keep them); a corner that turns back on itself
  // is a spike of zero width, which makes the outline touch itself.
  for (bool changed = true; changed && out.vertices.size() >= 3;) {
    changed = false;
    const size_t n = out.vertices.size();
    for (size_t i = 0; i < n; ++i) {
      const Vec2 prev = out.vertices[(i + n - 1) % n];
      const Vec2 cur = out.vertices[i];
      const Vec2 next = out.vertices[(i + 1) % n];
      if (std::fabs(detail::corner_turn(prev, cur, next)) > straight) continue;
      if (dot(cur - prev, next - cur) < 0.0f) {
        throw InvalidInput(label(name) + "polygon is self-intersecting: the outline doubles back "
                           "at vertex " + std::to_string(out.source[i]));
      }
      if (straight_corners == StraightCorners::keep) continue;
      out.vertices.erase(out.vertices.begin() + static_cast<std::ptrdiff_t>(i));
      out.source.erase(out.source.begin() + static_cast<std::ptrdiff_t>(i));
      changed = true;
      break;
    }
  }
  if (out.vertices.size() < 3) {
    throw InvalidInput(label(name) + "polygon has zero area (all vertices collinear)");
  }
  const size_t n = out.vertices.size();
  // Edge boxes first: most pairs are far apart, and a box test is cheaper than orientations.
  std::vector<Aabb> boxes(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = out.vertices[i];
    const Vec2 b = out.vertices[(i + 1) % n];
    boxes[i] = {glm::min(a, b), glm::max(a, b)};
  }
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the wrap-around
      if (!overlap(boxes[i], boxes[j])) continue;
      if (segments_touch(out.vertices[i], out.vertices[i + 1], out.vertices[j],
                         out.vertices[(j + 1) % n])) {
        throw InvalidInput(label(name) + "polygon is self-intersecting: edge " +
                           std::to_string(out.source[i]) + "-" +
                           std::to_string(out.source[i + 1]) + " meets edge " +
                           std::to_string(out.source[j]) + "-" +
                           std::to_string(out.source[(j + 1) % n]));
      }
    }
  }
  const float area = signed_area(out.vertices);
  if (std::fabs(area) <= straight) {
    throw InvalidInput(label(name) + "polygon has zero area");
  }
  if (area < 0.0f) {
    std::reverse(out.vertices.begin(), out.vertices.end());
    std::reverse(out.source.begin(), out.source.end());
    out.reversed = true;
  }
  return out;
}

}  // namespace collide
