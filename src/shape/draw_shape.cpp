#include <collide/shape/draw_shape.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <type_traits>

namespace collide {

void draw_shape(DebugDraw& draw, const Shape2D& shape, const Transform& xf, DrawRole role) {
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Circle>) {
          draw.draw_circle(transform_point(xf, s.center), s.radius, role);
        } else if constexpr (std::is_same_v<S, Capsule>) {
          draw.draw_capsule(transform_point(xf, s.a), transform_point(xf, s.b), s.radius, role);
        } else if constexpr (std::is_same_v<S, Segment>) {
          draw.draw_segment(transform_point(xf, s.a), transform_point(xf, s.b), role);
        } else {
          std::array<Vec2, kMaxPolygonVertices> world;
          for (int i = 0; i < s.count; ++i) world[i] = transform_point(xf, s.vertices[i]);
          draw.draw_polygon({world.data(), static_cast<size_t>(s.count)}, s.radius, role);
        }
      },
      shape);
}

}  // namespace collide

namespace collide {

namespace {

/// Every point within `r` of the segment a-b (a sphere when a == b), as bands of triangles from
/// b's pole to a's: kDrawSphereRings / 2 bands per cap, the cylinder between the two equators,
/// 2 kDrawSphereRings segments around.
void draw_rounded_segment(DebugDraw3& draw, Vec3 a, Vec3 b, float r, DrawRole role) {
  constexpr int kSegments = 2 * kDrawSphereRings;
  constexpr int kCapRings = kDrawSphereRings / 2;
  const Vec3 axis = b - a;
  const float len = length(axis);
  const Vec3 w = len > 0.0f ? axis / len : Vec3(0.0f, 1.0f, 0.0f);
  // Any unit vector across w, then the third.
  const Vec3 seed = std::fabs(w.x) < 0.6f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  const Vec3 u = normalize(cross(w, seed));
  const Vec3 v = cross(w, u);
  const float pi = std::numbers::pi_v<float>;
  // Ring k of 2 kCapRings + 2: b's cap from its pole to its equator, then a's from its equator
  // to its pole; the angle is measured from the nearer pole so that both poles are exact points.
  const auto ring_point = [&](int k, int j) {
    const bool b_cap = k <= kCapRings;
    const int from_pole = b_cap ? k : 2 * kCapRings + 1 - k;
    const float alpha = 0.5f * pi * static_cast<float>(from_pole) / static_cast<float>(kCapRings);
    const float phi = 2.0f * pi * static_cast<float>(j % kSegments) / static_cast<float>(kSegments);  // the seam closes exactly
    const Vec3 across = std::cos(phi) * u + std::sin(phi) * v;
    return (b_cap ? b : a) + r * (std::sin(alpha) * across + (b_cap ? std::cos(alpha) : -std::cos(alpha)) * w);
  };
  for (int k = 0; k <= 2 * kCapRings; ++k) {
    for (int j = 0; j < kSegments; ++j) {
      const Vec3 p00 = ring_point(k, j), p01 = ring_point(k, j + 1);
      const Vec3 p10 = ring_point(k + 1, j), p11 = ring_point(k + 1, j + 1);
      if (k != 0) draw.draw_triangle(p00, p10, p01, role);                // not at b's pole
      if (k != 2 * kCapRings) draw.draw_triangle(p01, p10, p11, role);    // not at a's pole
    }
  }
}

}  // namespace

void draw_shape(DebugDraw3& draw, const Shape3D& shape, const Transform3& xf, DrawRole role) {
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere>) {
          const Vec3 c = transform_point(xf, s.center);
          draw_rounded_segment(draw, c, c, s.radius, role);
        } else if constexpr (std::is_same_v<S, Capsule3>) {
          draw_rounded_segment(draw, transform_point(xf, s.a), transform_point(xf, s.b), s.radius, role);
        } else if constexpr (std::is_same_v<S, Segment3>) {
          draw.draw_segment(transform_point(xf, s.a), transform_point(xf, s.b), role);
        } else if constexpr (std::is_same_v<S, Box>) {
          // The rounding as the box grown by it (corners square).
          const Box grown{s.half + Vec3(s.radius), 0.0f};
          std::array<Vec3, 8> c;
          for (int i = 0; i < 8; ++i) c[i] = transform_point(xf, grown.vertex(i));
          // Face 2 k + side: the corners with bit k equal to side, counter-clockwise seen from
          // outside (along axis k + 1, then k + 2 on the + side; the other way on the - side).
          for (int k = 0; k < 3; ++k) {
            for (int side = 0; side < 2; ++side) {
              const int next = 1 << ((k + 1) % 3), after = 1 << ((k + 2) % 3);
              const int b1 = side == 1 ? next : after, b2 = side == 1 ? after : next;
              const int base = side << k;
              draw.draw_triangle(c[base], c[base + b1], c[base + b1 + b2], role);
              draw.draw_triangle(c[base], c[base + b1 + b2], c[base + b2], role);
            }
          }
        } else {  // ConvexHull: each polygonal face as a fan (the rounding radius is not drawn)
          for (const HullFace& f : s.faces) {
            const Vec3 p0 = transform_point(xf, s.vertices[s.face_vertices[f.first]]);
            for (int k = 1; k + 1 < f.count; ++k) {
              draw.draw_triangle(p0, transform_point(xf, s.vertices[s.face_vertices[f.first + k]]),
                                 transform_point(xf, s.vertices[s.face_vertices[f.first + k + 1]]), role);
            }
          }
        }
      },
      shape);
}

void draw_shape(DebugDraw3& draw, const TriangleMesh& mesh, const Transform3& xf, DrawRole role) {
  for (std::uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    draw.draw_triangle(transform_point(xf, mesh.origin + mesh.corner(t, 0)),
                       transform_point(xf, mesh.origin + mesh.corner(t, 1)),
                       transform_point(xf, mesh.origin + mesh.corner(t, 2)), role);
  }
}

void draw_shape(DebugDraw3& draw, const HeightField& field, const Transform3& xf, DrawRole role) {
  for_each_triangle(field, xf, compute_aabb(field, xf),  // every cell (the box is closed)
                    [&](std::uint32_t, const std::array<Vec3, 3>& c) {
                      draw.draw_triangle(c[0], c[1], c[2], role);
                      return true;
                    });
}

}  // namespace collide
