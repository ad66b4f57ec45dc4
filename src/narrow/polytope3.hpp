#pragma once
/// @file
/// The core of a convex 3D shape as a polytope: what the separating axis test and face
/// clipping need (vertices, faces with planes and corner loops, edges with their two faces).
/// Internal to the narrow phase.
///
/// Every convex 3D shape's core is a polytope: a sphere's a point, a capsule's and a segment's
/// a segment (one edge, no faces), a box's and a hull's a solid polyhedron, a triangle's a flat
/// one with two faces (front and back). The layout is ConvexHull's (HullFace, HullEdge, corner
/// loops counter-clockwise seen from outside), so a hull is viewed without copying and the
/// small shapes fill inline buffers (the view is built in place, never copied).

#include <collide/core/config.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/shape/triangle.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace collide::detail {

/// A face slot that names no face (a segment's edge has none).
inline constexpr std::uint16_t kNoFace = 0xffff;

/// The view. Indices are local to it; `face_feature` maps a face to the shape's public feature
/// index (a triangle's two sides are both face 0).
struct Polytope3 {
  enum class Kind : unsigned char { point, segment, box, triangle, hull };

  Kind kind = Kind::point;
  const Vec3* vertices = nullptr;
  int vertex_count = 0;
  const HullFace* faces = nullptr;
  int face_count = 0;
  const HullVertexIndex* face_vertices = nullptr;
  const std::uint16_t* face_edges = nullptr;
  const HullEdge* edges = nullptr;
  int edge_count = 0;
  Vec3 centroid{0.0f};  ///< an interior point (a flat polytope's: on it)
  float radius = 0.0f;  ///< rounding radius of the shape
  /// The core's scale for tolerances: twice the largest distance of a vertex from the
  /// centroid, plus the radius (set when the view is made: a level's triangles are all met by
  /// the same A).
  float size = 0.0f;
  /// Has volume: each edge's two faces bound a Gauss-map arc shorter than a half circle, so
  /// edge pairs can be pruned by the Gauss map (Gregorius 2013). Triangles, segments and points
  /// are not solid.
  bool solid = false;
  const ConvexHull* hull = nullptr;  ///< for its support queries
  /// A hull's face planes four at a time (ConvexHull::face_blocks), else null.
  const float* face_blocks = nullptr;

  /// The small shapes' own vertices and faces, filled by make_polytope (left uninitialised
  /// until then: a level contact makes a view per candidate triangle).
  std::array<Vec3, 8> vertex_buffer;
  std::array<HullFace, 6> face_buffer;

  Polytope3() = default;
  Polytope3(const Polytope3&) = delete;
  Polytope3& operator=(const Polytope3&) = delete;

  [[nodiscard]] int face_feature(int face) const noexcept {
    return kind == Kind::triangle ? 0 : face;
  }
  [[nodiscard]] Vec3 vertex(int i) const noexcept { return vertices[i]; }
  [[nodiscard]] const HullVertexIndex* corners(int face) const noexcept {
    return face_vertices + faces[face].first;
  }

  /// Index of a vertex farthest along `d` (local space); ties: the lowest index (a box: the
  /// - side on an axis where d is 0).
  [[nodiscard]] int support(Vec3 d) const noexcept {
    switch (kind) {
      case Kind::box: return int(d.x > 0.0f) | (int(d.y > 0.0f) << 1) | (int(d.z > 0.0f) << 2);
      case Kind::hull: return hull->support_index(d);
      default: break;
    }
    return support_point_index<3>({vertices, static_cast<std::size_t>(vertex_count)}, d);
  }
};

// Box topology (corner i has bit k set on the + side of axis k; box.hpp): faces 2k + s, edges
// 4k + j, as box.hpp numbers them.
inline constexpr std::array<HullVertexIndex, 24> kBoxFaceVertices = {
    4, 6, 2, 0, 1, 3, 7, 5, 1, 5, 4, 0, 2, 6, 7, 3, 2, 3, 1, 0, 4, 5, 7, 6};
inline constexpr std::array<std::uint16_t, 24> kBoxFaceEdges = {
    5, 10, 4, 8, 6, 11, 7, 9, 9, 2, 8, 0, 10, 3, 11, 1, 1, 6, 0, 4, 2, 7, 3, 5};
inline constexpr std::array<HullEdge, 12> kBoxEdges = {{
    {0, 1, 2, 4}, {2, 3, 4, 3}, {4, 5, 5, 2}, {6, 7, 3, 5},
    {0, 2, 4, 0}, {4, 6, 0, 5}, {1, 3, 1, 4}, {5, 7, 5, 1},
    {0, 4, 0, 2}, {1, 5, 2, 1}, {2, 6, 3, 0}, {3, 7, 1, 3},
}};

// Triangle topology: face 0 the front (corners 0 1 2), face 1 the back (0 2 1); edge k runs
// from corner k to corner k + 1 as the triangle's features do.
inline constexpr std::array<HullVertexIndex, 6> kTriangleFaceVertices = {0, 1, 2, 0, 2, 1};
inline constexpr std::array<std::uint16_t, 6> kTriangleFaceEdges = {0, 1, 2, 2, 1, 0};
inline constexpr std::array<HullEdge, 3> kTriangleEdges = {{{0, 1, 0, 1}, {1, 2, 0, 1}, {0, 2, 1, 0}}};

inline constexpr std::array<HullEdge, 1> kSegmentEdges = {{{0, 1, kNoFace, kNoFace}}};

/// Sets `size` from the vertices, centroid and radius made so far.
inline void set_size(Polytope3& p) noexcept {
  float r = 0.0f;
  for (int i = 0; i < p.vertex_count; ++i) r = std::max(r, distance_squared(p.vertex(i), p.centroid));
  p.size = 2.0f * std::sqrt(r) + p.radius;
}
inline void make_polytope(Polytope3& p, const Sphere& s) noexcept {
  p.kind = Polytope3::Kind::point;
  p.vertex_buffer[0] = s.center;
  p.vertices = p.vertex_buffer.data();
  p.vertex_count = 1;
  p.centroid = s.center;
  p.radius = s.radius;
  set_size(p);
}

inline void make_segment_polytope(Polytope3& p, Vec3 a, Vec3 b, float radius) noexcept {
  p.kind = Polytope3::Kind::segment;
  p.vertex_buffer[0] = a;
  p.vertex_buffer[1] = b;
  p.vertices = p.vertex_buffer.data();
  p.vertex_count = 2;
  p.edges = kSegmentEdges.data();
  p.edge_count = 1;
  p.centroid = 0.5f * (a + b);
  p.radius = radius;
  set_size(p);
}
inline void make_polytope(Polytope3& p, const Capsule3& c) noexcept {
  make_segment_polytope(p, c.a, c.b, c.radius);
}
inline void make_polytope(Polytope3& p, const Segment3& s) noexcept {
  make_segment_polytope(p, s.a, s.b, 0.0f);
}

inline void make_polytope(Polytope3& p, const Box& box) noexcept {
  p.kind = Polytope3::Kind::box;
  for (int i = 0; i < 8; ++i) p.vertex_buffer[i] = box.vertex(i);
  for (int k = 0; k < 3; ++k) {
    for (int s = 0; s < 2; ++s) {
      Vec3 n(0.0f);
      n[k] = s ? 1.0f : -1.0f;
      p.face_buffer[2 * k + s] = HullFace{n, box.half[k], std::uint16_t(4 * (2 * k + s)), 4};
    }
  }
  p.vertices = p.vertex_buffer.data();
  p.vertex_count = 8;
  p.faces = p.face_buffer.data();
  p.face_count = 6;
  p.face_vertices = kBoxFaceVertices.data();
  p.face_edges = kBoxFaceEdges.data();
  p.edges = kBoxEdges.data();
  p.edge_count = 12;
  p.centroid = Vec3(0.0f);
  p.radius = box.radius;
  p.solid = true;
  set_size(p);
}

/// A triangle (corners a, b, c, counter-clockwise seen from its front) as a flat polytope, `n`
/// its unit normal as triangle_normal makes it. The triangle must not be degenerate. Always inlined: GCC kept it out of line for a mesh's
/// contacts, and its corners then came in as register pairs put back together through the
/// stack by loads that cannot be store-forwarded (scripts/store-forward-scan).
COLLIDE_ALWAYS_INLINE void make_triangle_polytope(Polytope3& p, Vec3 a, Vec3 b, Vec3 c, float radius,
                                                  Vec3 n) noexcept {
  p.kind = Polytope3::Kind::triangle;
  p.vertex_buffer[0] = a;
  p.vertex_buffer[1] = b;
  p.vertex_buffer[2] = c;
  const float offset = dot(n, a);
  p.face_buffer[0] = HullFace{n, offset, 0, 3};
  p.face_buffer[1] = HullFace{-n, -offset, 3, 3};
  p.vertices = p.vertex_buffer.data();
  p.vertex_count = 3;
  p.faces = p.face_buffer.data();
  p.face_count = 2;
  p.face_vertices = kTriangleFaceVertices.data();
  p.face_edges = kTriangleFaceEdges.data();
  p.edges = kTriangleEdges.data();
  p.edge_count = 3;
  p.centroid = (a + b + c) * (1.0f / 3.0f);
  p.radius = radius;
  set_size(p);
}

/// make_triangle_polytope with the normal made here (triangle_normal).
COLLIDE_ALWAYS_INLINE void make_triangle_polytope(Polytope3& p, Vec3 a, Vec3 b, Vec3 c, float radius) noexcept {
  make_triangle_polytope(p, a, b, c, radius, triangle_normal(a, b, c));
}

inline void make_polytope(Polytope3& p, const Triangle& t) noexcept {
  make_triangle_polytope(p, t.vertices[0], t.vertices[1], t.vertices[2], 0.0f);
}

inline void make_polytope(Polytope3& p, const ConvexHull& hull) noexcept {
  p.kind = Polytope3::Kind::hull;
  p.hull = &hull;
  p.vertices = hull.vertices.data();
  p.vertex_count = hull.vertex_count();
  p.faces = hull.faces.data();
  p.face_count = static_cast<int>(hull.faces.size());
  p.face_vertices = hull.face_vertices.data();
  p.face_edges = hull.face_edges.data();
  p.edges = hull.edges.data();
  p.edge_count = static_cast<int>(hull.edges.size());
  p.face_blocks = hull.face_blocks.data();
  p.centroid = hull.centroid;
  p.radius = hull.radius;
  p.solid = true;
  set_size(p);
}

}  // namespace collide::detail
