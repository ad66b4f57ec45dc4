#include <collide/shape/shape2d.hpp>

namespace collide {

Aabb compute_aabb(const Shape2D& shape, const Transform& xf) noexcept {
  return std::visit([&](const auto& s) { return compute_aabb(s, xf); }, shape);
}

const char* type_name(const Shape2D& shape) noexcept {
  constexpr const char* kNames[] = {"circle", "capsule", "polygon", "segment"};
  return kNames[shape.index()];
}

}  // namespace collide
