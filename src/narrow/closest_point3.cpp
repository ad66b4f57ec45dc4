// 3D point queries by Voronoi regions (Ericson, Real-Time Collision Detection, 5.1), the same
// pattern as closest_point.cpp: find the feature of the shape's core whose region holds the
// point, take the closest point on it, then apply the radius along the direction from the
// core's closest point to the point. The point is moved into the shape's local frame first
// (large coordinates cancel before any other arithmetic); the answer is moved back once.

#include <collide/narrow/closest_point.hpp>

#include "segment_closest.hpp"

#include <cmath>
#include <cstdint>

namespace collide {
namespace {

/// A point query on the core in local space, before the radius is applied.
struct CoreQuery3 {
  float distance = 0.0f;  ///< signed distance to the core: negative inside a box core
  Vec3 closest{0.0f};
  /// Unit direction from the core's closest point towards the outside of the surface.
  Vec3 outward{0.0f};
  Feature feature{};
};

/// Grow the core answer by `radius` and place it in the world.
PointQuery3 finish(const CoreQuery3& q, float radius, const Transform3& xf) noexcept {
  PointQuery3 out;
  out.distance = q.distance - radius;
  out.inside = out.distance < 0.0f;
  out.closest = transform_point(xf, q.closest + radius * q.outward);
  out.feature = q.feature;
  return out;
}

/// A unit vector across `axis` (nonzero): its cross product with the coordinate axis it is
/// least aligned with, so the choice is stable under small changes of `axis`.
Vec3 unit_across(Vec3 axis) noexcept {
  const Vec3 a = collide::abs(axis);
  Vec3 e(0.0f);
  e[a.x <= a.y && a.x <= a.z ? 0 : (a.y <= a.z ? 1 : 2)] = 1.0f;
  return normalize_or_zero(cross(axis, e));
}

/// Segment core a-b (capsules, segments): the clamped projection (Ericson 5.1.2). Vertex 0 or
/// 1 when clamped to an end, edge 0 otherwise.
CoreQuery3 segment_core(Vec3 a, Vec3 b, Vec3 p) noexcept {
  const detail::PointSegmentClosest<3> c = detail::closest_on_segment<3>(p, a, b);
  CoreQuery3 q;
  const Vec3 axis = b - a;
  if (c.t <= 0.0f || c.t >= 1.0f) {
    const bool at_a = c.t <= 0.0f;
    q.feature = {FeatureType::vertex, at_a ? 0u : 1u};
    q.closest = at_a ? a : b;  // exactly the end (a + 1 * (b - a) may round off b)
    q.distance = length(p - q.closest);
    // On the end itself: out along the axis, away from the other end.
    q.outward = q.distance > 0.0f ? (p - q.closest) * (1.0f / q.distance)
                                  : normalize_or_zero(at_a ? -axis : axis);
    return q;
  }
  q.closest = c.point;
  q.distance = std::sqrt(c.distance_squared);
  q.feature = {FeatureType::edge, 0u};
  // Straight across the axis, even when rounding leaves a trace of the axis in p - closest
  // (a point on the core): the radius is then applied perpendicular to the core, onto the
  // surface.
  Vec3 away = p - q.closest;
  away -= (dot(away, axis) / length_squared(axis)) * axis;
  const float across = length(away);
  q.outward = across > 0.0f ? away * (1.0f / across) : unit_across(axis);
  return q;
}

/// Box core [-h, h]. Outside: clamp each coordinate (Ericson 5.1.3); the clamped axes name the
/// feature. Inside or on the surface: the face of least penetration h_k - |p_k| (lowest axis on
/// ties), the point pushed out to it.
CoreQuery3 box_core(Vec3 h, Vec3 p) noexcept {
  CoreQuery3 q;
  int outside = 0;        // number of clamped axes
  std::uint32_t bits = 0; // bit k: + side on axis k (for the clamped axes)
  int last_out = 0, last_in = 0;
  for (int k = 0; k < 3; ++k) {
    const bool above = p[k] > h[k];
    const bool below = p[k] < -h[k];
    q.closest[k] = above ? h[k] : (below ? -h[k] : p[k]);
    if (above || below) {
      ++outside;
      last_out = k;
    } else {
      last_in = k;
    }
    if (p[k] > 0.0f) bits |= 1u << k;
  }
  if (outside == 0) {
    int face_axis = 0;
    float depth = h[0] - std::fabs(p[0]);
    for (int k = 1; k < 3; ++k) {
      const float dk = h[k] - std::fabs(p[k]);
      if (dk < depth) {
        depth = dk;
        face_axis = k;
      }
    }
    const bool plus = p[face_axis] >= 0.0f;
    q.distance = -depth;
    q.closest = p;
    q.closest[face_axis] = plus ? h[face_axis] : -h[face_axis];
    q.outward = Vec3(0.0f);
    q.outward[face_axis] = plus ? 1.0f : -1.0f;
    q.feature = {FeatureType::face, std::uint32_t(2 * face_axis + (plus ? 1 : 0))};
    return q;
  }
  const Vec3 away = p - q.closest;
  q.distance = length(away);
  q.outward = away * (1.0f / q.distance);  // > 0: some coordinate is beyond the box
  if (outside == 1) {
    q.feature = {FeatureType::face, std::uint32_t(2 * last_out + ((bits >> last_out) & 1u))};
  } else if (outside == 2) {
    // Edge along the one axis k inside: bit 0 of j the side on (k + 1) % 3, bit 1 on (k + 2) % 3.
    const int k = last_in;
    const std::uint32_t j = ((bits >> ((k + 1) % 3)) & 1u) | (((bits >> ((k + 2) % 3)) & 1u) << 1);
    q.feature = {FeatureType::edge, std::uint32_t(4 * k) + j};
  } else {
    q.feature = {FeatureType::vertex, bits};
  }
  return q;
}

/// The closest point of one face polygon of a hull to p, which lies `sep` > 0 in front of the
/// face's plane: its projection if that lies within the polygon, else the nearest point of the
/// polygon's sides (Ericson 5.1.2 per side), named as a hull edge or vertex.
struct FacePoint {
  float distance_squared;
  Vec3 point;
  Feature feature;
};

FacePoint face_closest(const ConvexHull& hull, int face, Vec3 p, float sep) noexcept {
  const HullFace& f = hull.faces[face];
  const HullVertexIndex* corners = hull.face_vertices.data() + f.first;
  const Vec3 x = p - sep * f.normal;  // the projection onto the plane
  FacePoint best{sep * sep, x, {FeatureType::face, std::uint32_t(face)}};
  float best_side = INFINITY;
  for (int k = 0; k < f.count; ++k) {
    const int kn = k + 1 < f.count ? k + 1 : 0;
    const Vec3 v = hull.vertices[corners[k]];
    const Vec3 w = hull.vertices[corners[kn]];
    // Outside this side (its outward direction in the plane is (w - v) x n): the nearest point
    // of the polygon is on a side that the projection is outside of.
    if (!(dot(cross(w - v, f.normal), x - v) > 0.0f)) continue;
    const detail::PointSegmentClosest<3> c = detail::closest_on_segment<3>(p, v, w);
    if (c.distance_squared < best_side) {
      best_side = c.distance_squared;
      if (c.t <= 0.0f || c.t >= 1.0f) {
        const HullVertexIndex corner = corners[c.t <= 0.0f ? k : kn];
        best = {c.distance_squared, hull.vertices[corner], {FeatureType::vertex, corner}};
      } else {
        best = {c.distance_squared, c.point, {FeatureType::edge, hull.face_edges[f.first + k]}};
      }
    }
  }
  return best;  // the projection, unless p is outside some side
}

/// Hull core. The face of greatest separation n . p - offset decides:
/// - inside (every separation <= 0): the face of least penetration, the point pushed out to it
///   (its nearest plane; the projection lies on the face, as a nearer boundary point would lie
///   on a nearer plane).
/// - outside: the closest point of a convex polyhedron lies on a face whose plane separates it
///   from p (p - closest is in the normal cone of the closest point, so some face at the
///   closest point has n . (p - closest) > 0). If p projects within the face of greatest
///   separation, that is the answer (the face's half-space holds the hull); otherwise every
///   face with positive separation is searched for its closest point (face_closest) and the
///   nearest taken. O(vertices of the separating faces); no allocation.
CoreQuery3 hull_core(const ConvexHull& hull, Vec3 p) noexcept {
  const int n = static_cast<int>(hull.faces.size());
  int best = 0;
  float best_sep = -INFINITY;
  for (int i = 0; i < n; ++i) {
    const float sep = dot(hull.faces[i].normal, p) - hull.faces[i].offset;
    if (sep > best_sep) {
      best_sep = sep;
      best = i;
    }
  }
  CoreQuery3 q;
  if (!(best_sep > 0.0f)) {
    q.distance = best_sep;
    q.closest = p - best_sep * hull.faces[best].normal;
    q.outward = hull.faces[best].normal;
    q.feature = {FeatureType::face, std::uint32_t(best)};
    return q;
  }
  FacePoint closest = face_closest(hull, best, p, best_sep);
  if (closest.feature.type != FeatureType::face) {
    for (int i = 0; i < n; ++i) {
      const float sep = dot(hull.faces[i].normal, p) - hull.faces[i].offset;
      if (i == best || !(sep > 0.0f)) continue;
      const FacePoint c = face_closest(hull, i, p, sep);
      if (c.distance_squared < closest.distance_squared) closest = c;
      if (c.feature.type == FeatureType::face) break;  // p projects within it: the answer
    }
  }
  q.closest = closest.point;
  if (closest.feature.type == FeatureType::face) {
    q.distance = std::sqrt(closest.distance_squared);
    q.outward = hull.faces[closest.feature.index].normal;
  } else {
    const Vec3 away = p - closest.point;
    q.distance = length(away);
    q.outward = away * (1.0f / q.distance);  // > 0: p is in front of a face
  }
  q.feature = closest.feature;
  return q;
}

CoreQuery3 core_query(const Sphere& sphere, Vec3 p) noexcept {
  const Vec3 away = p - sphere.center;
  CoreQuery3 q;
  q.distance = length(away);
  q.closest = sphere.center;
  // At the centre every direction is closest: report +x.
  q.outward = q.distance > 0.0f ? away * (1.0f / q.distance) : Vec3{1.0f, 0.0f, 0.0f};
  q.feature = {FeatureType::face, 0u};
  return q;
}

CoreQuery3 core_query(const Capsule3& capsule, Vec3 p) noexcept {
  return segment_core(capsule.a, capsule.b, p);
}
CoreQuery3 core_query(const Segment3& segment, Vec3 p) noexcept {
  return segment_core(segment.a, segment.b, p);
}
CoreQuery3 core_query(const Box& box, Vec3 p) noexcept { return box_core(box.half, p); }
CoreQuery3 core_query(const ConvexHull& hull, Vec3 p) noexcept { return hull_core(hull, p); }

/// Triangle: the closest point by its Voronoi regions (Ericson 5.1.5, closest_point_on_triangle);
/// the corners with nonzero barycentric weight name the feature: one a vertex, two an edge
/// (edge k joins corners k and k + 1), three the face. No inside.
CoreQuery3 core_query(const Triangle& triangle, Vec3 p) noexcept {
  const auto& v = triangle.vertices;
  const TrianglePoint c = closest_point_on_triangle(p, v[0], v[1], v[2]);
  CoreQuery3 q;
  q.closest = c.point;
  const Vec3 away = p - c.point;
  q.distance = length(away);
  const unsigned used = unsigned(c.weights[0] > 0.0f) | (unsigned(c.weights[1] > 0.0f) << 1) |
                        (unsigned(c.weights[2] > 0.0f) << 2);
  switch (used) {
    case 1u: q.feature = {FeatureType::vertex, 0u}; break;
    case 2u: q.feature = {FeatureType::vertex, 1u}; break;
    case 4u: q.feature = {FeatureType::vertex, 2u}; break;
    case 3u: q.feature = {FeatureType::edge, 0u}; break;
    case 6u: q.feature = {FeatureType::edge, 1u}; break;
    case 5u: q.feature = {FeatureType::edge, 2u}; break;
    default: q.feature = {FeatureType::face, 0u}; break;
  }
  const Vec3 n = triangle_normal(v[0], v[1], v[2]);
  if (q.distance > 0.0f) {
    q.outward = away * (1.0f / q.distance);
  } else {
    q.outward = n;  // on the triangle: its front side
  }
  return q;
}

float radius_of(const Sphere& s) noexcept { return s.radius; }
float radius_of(const Capsule3& s) noexcept { return s.radius; }
float radius_of(const Segment3&) noexcept { return 0.0f; }
float radius_of(const Box& s) noexcept { return s.radius; }
float radius_of(const ConvexHull& s) noexcept { return s.radius; }
float radius_of(const Triangle&) noexcept { return 0.0f; }

}  // namespace

template <Shape3DType S>
PointQuery3 closest_point(const S& shape, const Transform3& xf, Vec3 point) noexcept {
  const Vec3 local = inv_transform_point(xf, point);
  return finish(core_query(shape, local), radius_of(shape), xf);
}

template PointQuery3 closest_point(const Sphere&, const Transform3&, Vec3) noexcept;
template PointQuery3 closest_point(const Capsule3&, const Transform3&, Vec3) noexcept;
template PointQuery3 closest_point(const Segment3&, const Transform3&, Vec3) noexcept;
template PointQuery3 closest_point(const Box&, const Transform3&, Vec3) noexcept;
template PointQuery3 closest_point(const ConvexHull&, const Transform3&, Vec3) noexcept;
template PointQuery3 closest_point(const Triangle&, const Transform3&, Vec3) noexcept;

PointQuery3 closest_point(const Shape3D& shape, const Transform3& xf, Vec3 point) noexcept {
  return std::visit([&](const auto& s) { return closest_point(s, xf, point); }, shape);
}

}  // namespace collide
