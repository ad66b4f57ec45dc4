#pragma once
/// @file
/// `overlap`: do two 2D shapes share at least one point? The cheapest question; each pair takes
/// its cheapest exact path (no manifold, no closest points are built).

#include <collide/shape/shape2d.hpp>

namespace collide {

/// True when shape A placed by `xa` and shape B placed by `xb` share at least one point
/// (touching counts, within float rounding). Circle pairs and circle-segment/capsule pairs are
/// analytic; pairs with a polygon use GJK with early exit on a separating direction (Gilbert,
/// Johnson & Keerthi 1988; the lower bound of van den Bergen 2003, 4.3.4), which stops as soon
/// as either bound decides. Shapes must be valid; transforms finite.
template <Shape2DType A, Shape2DType B>
[[nodiscard]] bool overlap(const A& a, const Transform& xa, const B& b,
                           const Transform& xb) noexcept;

/// `overlap` for shapes of types known only at run time.
[[nodiscard]] bool overlap(const Shape2D& a, const Transform& xa, const Shape2D& b,
                           const Transform& xb) noexcept;

}  // namespace collide
