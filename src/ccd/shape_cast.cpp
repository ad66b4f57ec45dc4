#include <collide/ccd/shape_cast.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace collide {
namespace {

/// A point of the Minkowski difference of the cores, w = pa - pb, remembering where it came
/// from. Everything is in A's local frame with both shapes at their t = 0 positions.
struct CastVertex {
  Vec2 w;       ///< pa - pb
  Vec2 pa;      ///< core point of A
  Vec2 pb;      ///< core point of B, in A's frame
  int ia;       ///< index of pa in A's proxy
  int ib;       ///< index of pb in B's proxy
  float bary;   ///< barycentric coordinate of the closest point (set by `closest`)
};

/// Up to three points of A - B whose convex hull holds the point of A - B closest to the
/// current ray point x found so far.
struct CastSimplex {
  std::array<CastVertex, 3> v{};
  int count = 0;

  /// Reduce the simplex to the smallest sub-simplex whose hull holds the point c closest to `x`
  /// and return x - c; barycentric coordinates of c go to `bary`. Voronoi regions of the
  /// vertices, edges and triangle decided by signed barycentric coordinates (Ericson, Real-Time
  /// Collision Detection, 5.1.2 and 5.1.5; Catto, "Computing Distance", GDC 2010). Works on
  /// y = w - x so the origin is the query point. On an edge, x - c is computed as the edge's
  /// perpendicular scaled by a cross product rather than as a difference of points: its
  /// direction then stays exact to float precision even when the points are far from x, which
  /// the support planes built on it need.
  Vec2 closest(Vec2 x) noexcept {
    if (count == 1) {
      v[0].bary = 1.0f;
      return x - v[0].w;
    }
    if (count == 2) return closest_on_edge(x, 0, 1);
    return closest_in_triangle(x);
  }

 private:
  /// Keep only vertex i; returns x - its point.
  Vec2 keep_vertex(Vec2 x, int i) noexcept {
    v[0] = v[i];
    v[0].bary = 1.0f;
    count = 1;
    return x - v[0].w;
  }

  /// x minus the closest point to x on the edge v[i]-v[j]; the simplex becomes that edge or one
  /// of its ends.
  Vec2 closest_on_edge(Vec2 x, int i, int j) noexcept {
    const Vec2 yi = v[i].w - x;
    const Vec2 yj = v[j].w - x;
    const Vec2 e = yj - yi;
    const float ui = dot(yj, e);   // > 0: x projects before vertex j
    const float uj = -dot(yi, e);  // > 0: x projects after vertex i
    if (uj <= 0.0f) return keep_vertex(x, i);
    if (ui <= 0.0f) return keep_vertex(x, j);
    const CastVertex a = v[i];
    const CastVertex b = v[j];
    v[0] = a;
    v[1] = b;
    count = 2;
    const float inv = 1.0f / (ui + uj);
    v[0].bary = ui * inv;
    v[1].bary = uj * inv;
    // -(bary_i yi + bary_j yj), the part of -yi perpendicular to e.
    return (cross(yi, yj) * inv) * left_perp(e);
  }

  Vec2 closest_in_triangle(Vec2 x) noexcept {
    const Vec2 y0 = v[0].w - x;
    const Vec2 y1 = v[1].w - x;
    const Vec2 y2 = v[2].w - x;
    // Edge coordinates: u01_0 > 0 means x lies before vertex 1 along edge 0->1, and so on.
    const Vec2 e01 = y1 - y0;
    const Vec2 e02 = y2 - y0;
    const Vec2 e12 = y2 - y1;
    const float u01_0 = dot(y1, e01);
    const float u01_1 = -dot(y0, e01);
    const float u02_0 = dot(y2, e02);
    const float u02_2 = -dot(y0, e02);
    const float u12_1 = dot(y2, e12);
    const float u12_2 = -dot(y1, e12);
    // Triangle coordinates: signed areas of the sub-triangles facing each vertex, signed by the
    // triangle's own orientation so that all three are positive inside.
    const float n = cross(e01, e02);
    const float t0 = n * cross(y1, y2);
    const float t1 = n * cross(y2, y0);
    const float t2 = n * cross(y0, y1);

    if (u01_1 <= 0.0f && u02_2 <= 0.0f) return keep_vertex(x, 0);
    if (u01_0 <= 0.0f && u12_2 <= 0.0f) return keep_vertex(x, 1);
    if (u02_0 <= 0.0f && u12_1 <= 0.0f) return keep_vertex(x, 2);
    if (u01_0 > 0.0f && u01_1 > 0.0f && t2 <= 0.0f) return closest_on_edge(x, 0, 1);
    if (u02_0 > 0.0f && u02_2 > 0.0f && t1 <= 0.0f) return closest_on_edge(x, 0, 2);
    if (u12_1 > 0.0f && u12_2 > 0.0f && t0 <= 0.0f) return closest_on_edge(x, 1, 2);
    const float sum = t0 + t1 + t2;
    if (!(sum > 0.0f)) {
      // Degenerate (collinear) triangle the region tests could not place: take the best edge.
      return best_edge(x);
    }
    const float inv = 1.0f / sum;
    v[0].bary = t0 * inv;
    v[1].bary = t1 * inv;
    v[2].bary = t2 * inv;
    return Vec2{0.0f, 0.0f};  // inside: the closest point is x itself
  }

  Vec2 best_edge(Vec2 x) noexcept {
    const CastSimplex original = *this;
    int best_i = 0;
    int best_j = 1;
    float best = 0.0f;
    constexpr int kEdges[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int k = 0; k < 3; ++k) {
      CastSimplex s = original;
      const float d2 = length_squared(s.closest_on_edge(x, kEdges[k][0], kEdges[k][1]));
      if (k == 0 || d2 < best) {
        best = d2;
        best_i = kEdges[k][0];
        best_j = kEdges[k][1];
      }
    }
    return closest_on_edge(x, best_i, best_j);
  }

 public:
  [[nodiscard]] bool contains(int ia, int ib) const noexcept {
    for (int i = 0; i < count; ++i) {
      if (v[i].ia == ia && v[i].ib == ib) return true;
    }
    return false;
  }
};

/// Distance from point 0 of the core to its farthest point, plus the radius: the shape's size,
/// which the tolerances scale with.
float proxy_size(const ConvexProxy& p) noexcept {
  const Vec2 p0 = p.point(0);
  float r2 = 0.0f;
  for (int i = 1; i < p.count(); ++i) r2 = std::max(r2, distance_squared(p0, p.point(i)));
  return std::sqrt(r2) + p.radius();
}

}  // namespace

namespace detail {
void check_cast_input(const Transform& xa, Vec2 va, const Transform& xb, Vec2 vb) {
  if (!is_valid(xa)) throw InvalidInput("xa: not finite or rotation not unit length");
  if (!is_valid(xb)) throw InvalidInput("xb: not finite or rotation not unit length");
  if (!is_finite(va)) throw InvalidInput("va: not finite");
  if (!is_finite(vb)) throw InvalidInput("vb: not finite");
}
}  // namespace detail

// GJK ray cast (van den Bergen 2004), on the Minkowski difference D = A - B of the cores in A's
// frame, with the ray x(t) = t r, r = vb - va, and the radius sum R handled as a margin:
// the shapes touch at t when x(t) is within R of D.
//
// Loop invariant: no contact before t. Each step takes v = x - c, c the point of the current
// simplex closest to x, and the support point p of D along v. The plane through p with normal
// v bounds D, so the separation at x is at least gap = (x - p) . v/|v| - R. If gap > 0 the ray
// may safely move forward to where it meets that plane (shifted by R); if it moves away from
// the plane instead, it never touches D. Then p joins the simplex and c is recomputed. The
// loop ends when |x - c| - R, an upper bound of the separation at x, is within tolerance.
ShapeCastResult gjk_shape_cast(const ConvexProxy& a, const Transform& xa, Vec2 va,
                               const ConvexProxy& b, const Transform& xb, Vec2 vb) noexcept {
  COLLIDE_ASSERT(is_finite(va) && is_finite(vb), "shape cast velocities must be finite");
  COLLIDE_ASSERT(a.count() >= 1 && b.count() >= 1, "shape cast proxies must hold points");

  const Transform xr = inv_mul(xa, xb);  // B's placement in A's frame
  const Vec2 r = inv_rotate(xa.q, vb - va);
  const float radius = a.radius() + b.radius();

  const float size_a = proxy_size(a);
  const float size_b = proxy_size(b);
  const float smaller = std::min(size_a, size_b) > 0.0f ? std::min(size_a, size_b)
                                                        : std::max(size_a, size_b);
  const float magnitude = length(r) + length(xr.p) + size_a + size_b;
  const float tolerance = kShapeCastTolerance * smaller + kShapeCastRounding * magnitude;

  auto support = [&](Vec2 d) noexcept {
    const int ia = a.support_index(d);
    const int ib = b.support_index(inv_rotate(xr.q, -d));
    const Vec2 pa = a.point(ia);
    const Vec2 pb = transform_point(xr, b.point(ib));
    return CastVertex{pa - pb, pa, pb, ia, ib, 0.0f};
  };

  CastSimplex simplex;
  {
    const Vec2 pb = transform_point(xr, b.point(0));
    simplex.v[0] = CastVertex{a.point(0) - pb, a.point(0), pb, 0, 0, 1.0f};
    simplex.count = 1;
  }

  ShapeCastResult result;
  float t = 0.0f;
  Vec2 x{0.0f, 0.0f};
  Vec2 plane_normal{0.0f, 0.0f};
  bool advanced = false;
  Vec2 v = x - simplex.v[0].w;
  int iteration = 0;
  bool converged = false;
  for (; iteration < kShapeCastMaxIterations; ++iteration) {
    const float dist = length(v);  // upper bound of the cores' distance at x
    if (simplex.count == 3 || dist == 0.0f) {
      converged = true;  // the cores touch or overlap at x
      break;
    }
    const Vec2 n = v * (1.0f / dist);
    const CastVertex p = support(n);
    const float lower = dot(x - p.w, n);  // lower bound of the cores' distance at x
    if (dist - radius <= tolerance && dist - lower <= tolerance) {
      // Within tolerance of touching, and the simplex is the closest feature (not a chord
      // through A - B), so its barycentric coordinates give the contact point.
      converged = true;
      break;
    }
    const float gap = lower - radius;  // lower bound of the separation at x
    bool moved = false;
    if (gap > 0.0f) {
      const float rn = dot(r, n);
      if (!(rn < 0.0f)) {
        // Moving along or away from a plane that A - B lies behind: never closer than gap.
        if (gap > tolerance) break;
      } else {
        float t_new = t + gap / -rn;
        if (!(t_new <= 1.0f)) {
          // Reaches the plane only after the step; a hit only if within tolerance at t = 1.
          if (gap + (1.0f - t) * rn > tolerance) break;
          t_new = 1.0f;
        }
        moved = t_new > t;
        t = t_new;
        x = t * r;
        plane_normal = n;
        advanced = true;
      }
    }
    if (simplex.contains(p.ia, p.ib)) {
      if (!moved) {
        // No new support point and x did not move: the distance has converged to within
        // rounding, and the support plane says it is at most the radius sum.
        converged = true;
        break;
      }
    } else {
      simplex.v[simplex.count++] = p;
    }
    v = simplex.closest(x);
  }
  result.iterations = iteration;
  result.t = t;

  if (!converged) {
    result.status = iteration >= kShapeCastMaxIterations ? ImpactStatus::failed
                                                         : ImpactStatus::separated;
    if (result.status == ImpactStatus::separated) result.t = 1.0f;
    return result;
  }

  // Contact: the closest features' points from the simplex's barycentric coordinates.
  Vec2 pa{0.0f, 0.0f};
  Vec2 pb{0.0f, 0.0f};
  if (simplex.count == 3) {
    // x inside the core triangle: `closest` already left the coordinates of x in `bary`.
    for (int i = 0; i < 3; ++i) {
      pa += simplex.v[i].bary * simplex.v[i].pa;
      pb += simplex.v[i].bary * simplex.v[i].pb;
    }
  } else {
    for (int i = 0; i < simplex.count; ++i) {
      pa += simplex.v[i].bary * simplex.v[i].pa;
      pb += simplex.v[i].bary * simplex.v[i].pb;
    }
  }
  // The normal. When the cores are apart by more than the tolerance (rounded shapes), the
  // direction between their closest points: the simplex is their closest feature pair, so it
  // is exact, and on a curved surface it is the only right one. Otherwise the normal of the
  // last support plane the ray advanced to: x lies on it, so the shapes' separation along it is
  // exactly zero at t, which makes it a contact normal (at a vertex, one of the valid ones).
  // Without an advance (overlapped at t = 0) and with touching cores there is none.
  const float dist = length(v);
  Vec2 n_local{0.0f, 0.0f};
  if (simplex.count < 3 && dist > tolerance) {
    n_local = v * (1.0f / dist);
  } else if (advanced) {
    n_local = plane_normal;
  }
  const Vec2 surface_a = pa + t * inv_rotate(xa.q, va) + a.radius() * n_local;
  const Vec2 surface_b = pb + t * inv_rotate(xa.q, vb) - b.radius() * n_local;
  result.hit = true;
  result.status = advanced ? ImpactStatus::hit : ImpactStatus::overlapped;
  result.point = transform_point(xa, 0.5f * (surface_a + surface_b));
  result.normal = rotate(xa.q, n_local);
  return result;
}

ShapeCastResult shape_cast(const Shape2D& a, const Transform& xa, Vec2 va, const Shape2D& b,
                           const Transform& xb, Vec2 vb) {
  detail::check_cast_input(xa, va, xb, vb);
  return gjk_shape_cast(ConvexProxy(a), xa, va, ConvexProxy(b), xb, vb);
}

}  // namespace collide
