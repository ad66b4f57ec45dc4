#pragma once
/// @file
/// Axis-aligned bounding boxes in 2D and 3D, one template for both: the broad phase and the
/// early-out pretests are written once for any dimension.

#include <collide/core/math.hpp>

#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace collide {

/// Vector of D floats: Vec2 for D = 2, Vec3 for D = 3.
template <int D>
using VecN = glm::vec<D, float, glm::defaultp>;

/// An axis-aligned box [min, max] in D dimensions, world space. A box is valid when
/// min <= max on every axis; a point is a valid box of zero size. Boxes are closed: two boxes
/// that share only a face, edge or corner overlap.
template <int D>
struct AabbN {
  VecN<D> min{0.0f};  ///< lower corner
  VecN<D> max{0.0f};  ///< upper corner

  [[nodiscard]] constexpr VecN<D> center() const noexcept { return 0.5f * (min + max); }
  [[nodiscard]] constexpr VecN<D> extents() const noexcept { return 0.5f * (max - min); }
  [[nodiscard]] constexpr VecN<D> size() const noexcept { return max - min; }
};

using Aabb = AabbN<2>;   ///< 2D box
using Aabb3 = AabbN<3>;  ///< 3D box

/// Closed-box overlap test: touching counts. NaN on any side yields false.
template <int D>
[[nodiscard]] constexpr bool overlap(const AabbN<D>& a, const AabbN<D>& b) noexcept {
  for (int i = 0; i < D; ++i) {
    if (!(a.min[i] <= b.max[i] && b.min[i] <= a.max[i])) return false;
  }
  return true;
}

/// True when `p` lies in the closed box.
template <int D>
[[nodiscard]] constexpr bool contains(const AabbN<D>& a, const VecN<D>& p) noexcept {
  for (int i = 0; i < D; ++i) {
    if (!(a.min[i] <= p[i] && p[i] <= a.max[i])) return false;
  }
  return true;
}

/// True when `inner` lies entirely inside the closed box `outer`.
template <int D>
[[nodiscard]] constexpr bool contains(const AabbN<D>& outer, const AabbN<D>& inner) noexcept {
  return contains(outer, inner.min) && contains(outer, inner.max);
}

/// The smallest box holding both.
template <int D>
[[nodiscard]] constexpr AabbN<D> merge(const AabbN<D>& a, const AabbN<D>& b) noexcept {
  return {glm::min(a.min, b.min), glm::max(a.max, b.max)};
}

/// `a` grown by `margin` on every side.
template <int D>
[[nodiscard]] constexpr AabbN<D> fatten(const AabbN<D>& a, float margin) noexcept {
  return {a.min - VecN<D>(margin), a.max + VecN<D>(margin)};
}

/// Sum of edge lengths (2D: half the perimeter) or surface area (3D): the cost metric of
/// bounding volume trees (Goldsmith & Salmon 1987; MacDonald & Booth 1990).
template <int D>
[[nodiscard]] constexpr float surface_metric(const AabbN<D>& a) noexcept {
  const VecN<D> d = a.max - a.min;
  if constexpr (D == 2) {
    return d.x + d.y;
  } else {
    return 2.0f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
}

/// Every coordinate finite and min <= max on every axis.
template <int D>
[[nodiscard]] inline bool is_valid(const AabbN<D>& a) noexcept {
  for (int i = 0; i < D; ++i) {
    if (!std::isfinite(a.min[i]) || !std::isfinite(a.max[i]) || !(a.min[i] <= a.max[i])) {
      return false;
    }
  }
  return true;
}

}  // namespace collide
