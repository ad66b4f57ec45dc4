#pragma once
/// @file
/// Any convex 3D shape, for code that stores shapes of mixed types (worlds, file loaders, the
/// query tool). Queries on `Shape3D` dispatch once on the pair of types. The non-convex level
/// shapes (`TriangleMesh`, `HeightField`) are not alternatives: their queries visit one result
/// per triangle and have overloads of their own.

#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/shape/triangle.hpp>

#include <type_traits>
#include <variant>

namespace collide {

/// One of the convex 3D shapes. The alternative order is the `ShapeType3D` order.
using Shape3D = std::variant<Sphere, Capsule3, Segment3, Box, ConvexHull>;

/// The convex 3D shape types, in `Shape3D` alternative order.
enum class ShapeType3D : unsigned char { sphere, capsule, segment, box, hull };

/// Any of the convex 3D shape structs: the `Shape3D` alternatives and `Triangle`. A single
/// triangle takes every convex query (as the piece of a level a body touches), but it is not a
/// `Shape3D` alternative: a level's triangles live in a `TriangleMesh` or a `HeightField`.
template <class T>
concept Shape3DType = std::is_same_v<T, Sphere> || std::is_same_v<T, Capsule3> ||
                      std::is_same_v<T, Segment3> || std::is_same_v<T, Box> ||
                      std::is_same_v<T, ConvexHull> || std::is_same_v<T, Triangle>;

/// A convex 3D shape whose type is known at compile time (`Shape3DType`) or only at run time
/// (`Shape3D`): shape A of the queries against the level shapes `TriangleMesh` and
/// `HeightField`.
template <class T>
concept ConvexShape3DType = Shape3DType<T> || std::is_same_v<T, Shape3D>;

/// Bounding box of any convex 3D shape placed by `xf`, world space.
[[nodiscard]] Aabb3 compute_aabb(const Shape3D& shape, const Transform3& xf) noexcept;

/// Lower-case name of the shape's type ("sphere", "capsule", "segment", "box", "hull").
[[nodiscard]] const char* type_name(const Shape3D& shape) noexcept;

}  // namespace collide
