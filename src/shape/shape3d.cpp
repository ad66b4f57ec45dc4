#include <collide/shape/shape3d.hpp>

namespace collide {

Aabb3 compute_aabb(const Shape3D& shape, const Transform3& xf) noexcept {
  return std::visit([&](const auto& s) { return compute_aabb(s, xf); }, shape);
}

const char* type_name(const Shape3D& shape) noexcept {
  constexpr const char* kNames[] = {"sphere", "capsule", "segment", "box", "hull"};
  return kNames[shape.index()];
}

}  // namespace collide
