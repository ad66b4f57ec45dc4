#pragma once
/// @file
/// Any 2D shape, for code that stores shapes of mixed types (worlds, file loaders, the query
/// tool). Queries on `Shape2D` dispatch once on the pair of types.

#include <collide/shape/capsule.hpp>
#include <collide/shape/circle.hpp>
#include <collide/shape/polygon.hpp>
#include <collide/shape/segment.hpp>

#include <variant>

namespace collide {

/// One of the 2D shapes. The alternative order is the `ShapeType2D` order.
using Shape2D = std::variant<Circle, Capsule, Polygon, Segment>;

/// The 2D shape types, in `Shape2D` alternative order.
enum class ShapeType2D : unsigned char { circle, capsule, polygon, segment };

/// Any of the four 2D shape structs.
template <class T>
concept Shape2DType = std::is_same_v<T, Circle> || std::is_same_v<T, Capsule> ||
                      std::is_same_v<T, Polygon> || std::is_same_v<T, Segment>;

/// Bounding box of any 2D shape placed by `xf`, world space.
[[nodiscard]] Aabb compute_aabb(const Shape2D& shape, const Transform& xf) noexcept;

/// Lower-case name of the shape's type ("circle", "capsule", "polygon", "segment").
[[nodiscard]] const char* type_name(const Shape2D& shape) noexcept;

}  // namespace collide
