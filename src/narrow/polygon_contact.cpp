// Contact between two convex polygons, rounded or not (capsules and segments arrive as
// 2-vertex polygons).
//
// 1. Move B into A's local frame once, shifted so that A's vertex 0 is the origin: coordinates
//    stay small however far from the world origin the pair is.
// 2. Separating axis test over A's edge normals, then B's (sat.cpp); stop at the first axis that
//    separates the rounded shapes.
// 3. The reference face is the axis of greatest separation, preferring A within a tolerance
//    relative to the shapes' size so that the choice does not flicker between frames. The
//    incident edge is the edge of the other polygon most anti-parallel to the reference normal.
// 4. If the cores overlap (or nearly touch), clip the incident edge to the reference edge's side
//    planes and keep the points within the radii sum of the reference face: 1 or 2 points.
//    If the cores are apart (rounded shapes only reach here then), the closest points of the two
//    edges tell vertex-vertex contact (one point, normal along the closest points) from face
//    contact (clip as above).
// Catto, "Contact Manifolds", GDC 2007; Ericson, Real-Time Collision Detection, 5.2.1, 5.1.9.

#include "contact_routines.hpp"
#include "polygon_clip.hpp"

#include <collide/core/tolerance.hpp>
#include <collide/narrow/sat.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>

namespace collide::detail {
namespace {

/// A polygon's core in the shared local frame.
struct LocalPolygon {
  const Vec2* vertices = nullptr;
  const Vec2* normals = nullptr;
  int count = 0;
  float radius = 0.0f;

  [[nodiscard]] int next(int i) const noexcept { return i + 1 == count ? 0 : i + 1; }
};

/// Index of the edge of `p` whose normal is most anti-parallel to `normal`.
int incident_edge(const LocalPolygon& p, Vec2 normal) noexcept {
  int best = 0;
  float lowest = dot(normal, p.normals[0]);
  for (int i = 1; i < p.count; ++i) {
    const float d = dot(normal, p.normals[i]);
    if (d < lowest) {
      lowest = d;
      best = i;
    }
  }
  return best;
}

/// The manifold with polygon 1 as "A": reference edge `reference.edge` of p1, normal its
/// outward normal (or, for vertex-vertex contact of rounded shapes, the direction between the
/// closest core points). `frame` maps the shared local frame to world space. `apart` is the
/// separation below which the cores count as touching.
Manifold reference_face_manifold(const LocalPolygon& p1, EdgeSeparation reference,
                                 const LocalPolygon& p2, const Transform& frame,
                                 float apart) noexcept {
  const int i11 = reference.edge;
  const int i12 = p1.next(i11);
  const Vec2 n1 = p1.normals[i11];
  const int i21 = incident_edge(p2, n1);
  const int i22 = p2.next(i21);
  const EdgeRef ref{p1.vertices[i11], p1.vertices[i12], i11, i12};
  const EdgeRef inc{p2.vertices[i21], p2.vertices[i22], i21, i22};
  const float r1 = p1.radius;
  const float r2 = p2.radius;
  const float radius = r1 + r2;

  Manifold m;
  if (reference.separation > apart) {
    // Cores apart, rounded surfaces within reach: is it corner against corner?
    const EdgeClosestPoints closest =
        closest_points_between_edges(ref.start, ref.end, inc.start, inc.end);
    const bool end1 = closest.fraction1 == 0.0f || closest.fraction1 == 1.0f;
    const bool end2 = closest.fraction2 == 0.0f || closest.fraction2 == 1.0f;
    if (end1 && end2) {
      const Vec2 d = closest.point2 - closest.point1;
      const float dist2 = length_squared(d);
      if (!(dist2 <= radius * radius)) return m;
      const float dist = std::sqrt(dist2);
      const Vec2 n = d * (1.0f / dist);  // dist >= separation > apart > 0
      // Midway between A's surface point1 + r1 n and B's point2 - r2 n.
      const Vec2 mid = closest.point1 + (0.5f * (r1 + dist - r2)) * n;
      const int v1 = closest.fraction1 == 0.0f ? i11 : i12;
      const int v2 = closest.fraction2 == 0.0f ? i21 : i22;
      m.normal = rotate(frame.q, n);
      m.points[0] = {transform_point(frame, mid), radius - dist,
                     ContactId{static_cast<std::uint8_t>(v1), static_cast<std::uint8_t>(v2),
                               FeatureType::vertex, FeatureType::vertex}};
      m.count = 1;
      return m;
    }
  }

  // Face contact: the tangent left_perp(n1) is the unit direction of the reference edge.
  const ClippedEdge clipped = clip_incident_edge(ref, left_perp(n1), inc);
  for (int k = 0; k < clipped.count; ++k) {
    const ClipVertex& cv = clipped.vertices[k];
    const float separation = dot(n1, cv.point - ref.start);  // of the cores
    if (separation <= radius) {
      // B's core point is cv.point; A's surface lies at (r1 - separation) along n1 from it and
      // B's at -r2: the midpoint is half their sum.
      const Vec2 mid = cv.point + (0.5f * (r1 - separation - r2)) * n1;
      m.points[m.count++] = {transform_point(frame, mid), radius - separation, cv.id};
    }
  }
  if (m.count > 0) m.normal = rotate(frame.q, n1);
  return m;
}

}  // namespace

Manifold contact_polygons(const Polygon& a, const Transform& xa, const Polygon& b,
                          const Transform& xb) noexcept {
  const int na = a.count;
  const int nb = b.count;
  const Transform b_in_a = inv_mul(xa, xb);
  const Vec2 origin = a.vertices[0];
  const Vec2 shift = b_in_a.p - origin;

  // Both cores in A's frame, origin at A's vertex 0; sizes for the relative tolerances.
  std::array<Vec2, kMaxPolygonVertices> va;
  std::array<Vec2, kMaxPolygonVertices> vb;
  std::array<Vec2, kMaxPolygonVertices> normals_b;
  Vec2 extent_a{0.0f, 0.0f};
  for (int i = 0; i < na; ++i) {
    va[i] = a.vertices[i] - origin;
    extent_a = glm::max(extent_a, glm::abs(va[i]));
  }
  Vec2 extent_b{0.0f, 0.0f};
  const Vec2 b0 = b.vertices[0];
  for (int j = 0; j < nb; ++j) {
    vb[j] = rotate(b_in_a.q, b.vertices[j]) + shift;
    normals_b[j] = rotate(b_in_a.q, b.normals[j]);
    extent_b = glm::max(extent_b, glm::abs(b.vertices[j] - b0));
  }
  const float radius = a.radius + b.radius;

  const std::span<const Vec2> verts_a(va.data(), na);
  const std::span<const Vec2> verts_b(vb.data(), nb);
  const EdgeSeparation sep_a =
      find_max_separation(verts_a, std::span(a.normals.data(), na), verts_b, radius);
  if (sep_a.separation > radius) return {};
  const EdgeSeparation sep_b =
      find_max_separation(verts_b, std::span(normals_b.data(), nb), verts_a, radius);
  if (sep_b.separation > radius) return {};

  const float size = std::max({extent_a.x, extent_a.y, extent_b.x, extent_b.y});
  const float apart = kRelativeTolerance * size;
  const Transform frame{transform_point(xa, origin), xa.q};
  const LocalPolygon pa{va.data(), a.normals.data(), na, a.radius};
  const LocalPolygon pb{vb.data(), normals_b.data(), nb, b.radius};
  if (sep_b.separation > sep_a.separation + kReferenceFaceTolerance * size) {
    return reversed(reference_face_manifold(pb, sep_b, pa, frame, apart));
  }
  return reference_face_manifold(pa, sep_a, pb, frame, apart);
}

}  // namespace collide::detail
