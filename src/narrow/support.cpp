#include <collide/narrow/support.hpp>

#include <collide/core/error.hpp>

namespace collide {

ConvexProxyN<2>::ConvexProxyN(const Shape2D& shape) noexcept
    : ConvexProxyN(std::visit([](const auto& s) { return ConvexProxy(s); }, shape)) {}

ConvexProxyN<2>::ConvexProxyN(const Vec2* points, int count, float radius) noexcept
    : count_(count), radius_(radius) {
  COLLIDE_ASSERT(count >= 1 && count <= kMaxPolygonVertices, "proxy point count out of range");
  if (count <= 2) {
    buffer_[0] = points[0];
    buffer_[1] = points[count - 1];
  } else {
    points_ = points;
  }
}

}  // namespace collide
