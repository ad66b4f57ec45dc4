#include <collide/shape/draw_shape.hpp>

#include <array>
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
