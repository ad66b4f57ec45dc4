#pragma once
/// @file
/// Rays as origin + translation, the one fraction convention of collide (STYLE.md):
/// point = origin + fraction * translation, fraction in [0, 1].

#include <collide/core/aabb.hpp>

namespace collide {

/// A ray segment in D dimensions, world space unless a function says otherwise.
template <int D>
struct RayN {
  VecN<D> origin{0.0f};       ///< start point
  VecN<D> translation{0.0f};  ///< end point minus start point; the ray covers fractions [0, 1]

  /// The point at `fraction` along the translation.
  [[nodiscard]] constexpr VecN<D> at(float fraction) const noexcept {
    return origin + fraction * translation;
  }
};

using Ray = RayN<2>;   ///< 2D ray
using Ray3 = RayN<3>;  ///< 3D ray

}  // namespace collide
