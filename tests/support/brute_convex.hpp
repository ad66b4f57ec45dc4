#pragma once
// Slow, obviously correct reference geometry for tests of closest points, Minkowski sums and
// polygon overlap: written independently of the library's algorithms (no Voronoi walks, no
// edge merging, no clipping), so that agreement means something.

#include <collide/core/transform.hpp>
#include <collide/shape/polygon.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace collide::test {

/// The polygon's core vertices placed in the world.
inline std::vector<Vec2> world_vertices(const Polygon& p, const Transform& xf) {
  std::vector<Vec2> out;
  for (int i = 0; i < p.count; ++i) out.push_back(transform_point(xf, p.vertices[i]));
  return out;
}

/// Closest point on segment a-b to p (clamped projection).
inline Vec2 closest_on_segment(Vec2 a, Vec2 b, Vec2 p) {
  const Vec2 e = b - a;
  const float ee = length_squared(e);
  const float s = ee > 0.0f ? std::clamp(dot(p - a, e) / ee, 0.0f, 1.0f) : 0.0f;
  return a + s * e;
}

/// Convex hull by gift wrapping (Jarvis march), counter-clockwise, collinear points dropped
/// (the farthest point in a direction wins). Points within `tol` of each other count as one.
inline std::vector<Vec2> gift_wrap(const std::vector<Vec2>& pts, float tol) {
  if (pts.empty()) return {};
  size_t start = 0;
  for (size_t i = 1; i < pts.size(); ++i) {
    if (pts[i].y < pts[start].y || (pts[i].y == pts[start].y && pts[i].x < pts[start].x)) {
      start = i;
    }
  }
  std::vector<Vec2> hull;
  size_t cur = start;
  for (size_t guard = 0; guard <= pts.size(); ++guard) {
    hull.push_back(pts[cur]);
    size_t best = cur;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (distance(pts[i], pts[cur]) <= tol) continue;
      if (best == cur) {
        best = i;
        continue;
      }
      const float c = cross(pts[best] - pts[cur], pts[i] - pts[cur]);
      // Every other point must be to the left of cur -> best; on the line, keep the farthest.
      const float scale = length(pts[best] - pts[cur]) * length(pts[i] - pts[cur]);
      if (c < -1e-6f * scale ||
          (std::fabs(c) <= 1e-6f * scale &&
           distance_squared(pts[cur], pts[i]) > distance_squared(pts[cur], pts[best]))) {
        best = i;
      }
    }
    if (best == cur || distance(pts[best], pts[start]) <= tol) break;
    cur = best;
  }
  return hull;
}

/// Shoelace area (counter-clockwise positive) and centroid of a simple polygon.
inline float shoelace_area(const std::vector<Vec2>& v, Vec2* centroid = nullptr) {
  double a = 0.0, cx = 0.0, cy = 0.0;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2 p = v[i];
    const Vec2 q = v[(i + 1) % v.size()];
    const double c = double(p.x) * q.y - double(q.x) * p.y;
    a += c;
    cx += (double(p.x) + q.x) * c;
    cy += (double(p.y) + q.y) * c;
  }
  if (centroid != nullptr && a != 0.0) {
    *centroid = Vec2{float(cx / (3.0 * a)), float(cy / (3.0 * a))};
  }
  return float(0.5 * a);
}

/// Distance from p to the boundary of the convex polygon `v` (min over edges), and whether p
/// is strictly inside (left of every edge).
struct BruteDistance {
  float boundary = 0.0f;
  bool inside = false;
  Vec2 closest{0.0f, 0.0f};
  int edge = 0;    ///< edge whose segment holds the closest point
  float s = 0.0f;  ///< where on that edge, 0..1
};
inline BruteDistance brute_distance(const std::vector<Vec2>& v, Vec2 p) {
  BruteDistance out;
  out.boundary = std::numeric_limits<float>::infinity();
  out.inside = true;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec2 a = v[i];
    const Vec2 b = v[(i + 1) % v.size()];
    if (cross(b - a, p - a) <= 0.0f) out.inside = false;
    const Vec2 c = closest_on_segment(a, b, p);
    const float d = distance(c, p);
    if (d < out.boundary) {
      out.boundary = d;
      out.closest = c;
      out.edge = static_cast<int>(i);
      out.s = distance(a, c) / distance(a, b);
    }
  }
  return out;
}

/// Separating axis test, brute force over every edge normal of both (world vertices): the
/// largest separation (positive: apart by that much along the axis; negative: minus the
/// smallest overlap). For convex polygons this is also the signed distance of the origin to
/// A - B when it is <= 0.
inline float sat_separation(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  float best = -std::numeric_limits<float>::infinity();
  auto axes_of = [&](const std::vector<Vec2>& p) {
    for (size_t i = 0; i < p.size(); ++i) {
      const Vec2 e = p[(i + 1) % p.size()] - p[i];
      const Vec2 n = normalize_or_zero(Vec2{e.y, -e.x});
      float a_max = -std::numeric_limits<float>::infinity();
      float a_min = std::numeric_limits<float>::infinity();
      float b_max = a_max, b_min = a_min;
      for (Vec2 q : a) {
        a_max = std::max(a_max, dot(n, q));
        a_min = std::min(a_min, dot(n, q));
      }
      for (Vec2 q : b) {
        b_max = std::max(b_max, dot(n, q));
        b_min = std::min(b_min, dot(n, q));
      }
      best = std::max(best, std::max(b_min - a_max, a_min - b_max));
    }
  };
  axes_of(a);
  axes_of(b);
  return best;
}

/// Distance between two disjoint convex polygons: the min over vertex-edge pairs both ways.
inline float brute_polygon_distance(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  float best = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < a.size(); ++i) {
    for (size_t j = 0; j < b.size(); ++j) {
      const Vec2 b0 = b[j], b1 = b[(j + 1) % b.size()];
      const Vec2 a0 = a[i], a1 = a[(i + 1) % a.size()];
      best = std::min(best, distance(a[i], closest_on_segment(b0, b1, a[i])));
      best = std::min(best, distance(b[j], closest_on_segment(a0, a1, b[j])));
    }
  }
  return best;
}

}  // namespace collide::test
