#include <collide/draw/debug_draw.hpp>

#include <array>
#include <type_traits>

namespace collide {

const char* to_string(DrawRole role) noexcept {
  switch (role) {
    case DrawRole::static_geometry: return "static geometry";
    case DrawRole::sensor: return "sensor";
    case DrawRole::body: return "body";
    case DrawRole::fast_body: return "fast body";
    case DrawRole::contact_point: return "contact point";
    case DrawRole::contact_normal: return "contact normal";
    case DrawRole::laser: return "laser";
    case DrawRole::laser_hit: return "laser hit";
    case DrawRole::path: return "path";
    case DrawRole::shape_a: return "shape A";
    case DrawRole::shape_b: return "shape B";
    case DrawRole::minkowski: return "Minkowski difference";
    case DrawRole::origin: return "origin";
    case DrawRole::highlight: return "highlight";
  }
  return "unknown";
}

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
