#pragma once
// The per-ray setup of the watertight ray-triangle test (Woop, Benthin & Wald, JCGT 2013) and
// its scalar test, shared by single triangles, the BVH (which runs the same steps four
// triangles at a time) and height fields. One ray, one setup: the shear constants must be the
// same for every triangle the ray meets, or two triangles sharing an edge could both miss.
// Also the plane of a triangle for a ray, its normal in double (triangle_area_normal, in
// <collide/shape/triangle.hpp>), which keeps slivers exact.

#include <collide/core/ray.hpp>
#include <collide/shape/triangle.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace collide::detail {

/// A triangle whose longest edge is more than this many times its width (the height onto that
/// edge) is a sliver: the watertight test's fraction, interpolated by the edge functions, is
/// then off by about this factor times the float spacing of the coordinates (0.04 units along a
/// ray of FCL's env.obj, at a wall strip 9 by 6000 units, 3000 units from the origin), and so
/// is a plane built in float (its normal, from two nearly parallel edges, turns as much).
inline constexpr float kSliverAspect = 8.0f;

/// Whether triangle (a, b, c) is a sliver (longer than kSliverAspect times its width). Float,
/// so that TriangleBvh's packets, flagged once, agree with the scalar test.
[[nodiscard]] inline bool is_sliver(Vec3 a, Vec3 b, Vec3 c) noexcept {
  const Vec3 ab = b - a, ac = c - a, bc = c - b;
  const float longest = std::max(std::max(dot(ab, ab), dot(ac, ac)), dot(bc, bc));
  const Vec3 n = cross(ab, ac);
  // width = |n| / length, so length / width > K  <=>  length^2 > K |n|.
  return longest > kSliverAspect * std::sqrt(dot(n, n));
}

/// Where the ray (origin + fraction * translation) meets the plane of triangle (a, b, c), its
/// normal in double (triangle_area_normal). NaN or infinite for a ray parallel to the plane.
[[nodiscard]] inline float plane_fraction(Vec3 a, Vec3 b, Vec3 c, Vec3 origin, Vec3 translation) noexcept {
  const glm::dvec3 n = triangle_area_normal(a, b, c);
  return static_cast<float>(glm::dot(n, glm::dvec3(a) - glm::dvec3(origin)) / glm::dot(n, glm::dvec3(translation)));
}

/// A ray prepared for the watertight test: the axis it moves most along becomes z (kz), the
/// other two x and y (kx, ky, swapped when the ray runs down kz so the winding is kept), and
/// the shear that takes the ray to the z axis.
struct WatertightRay {
  Vec3 origin{0.0f};
  Vec3 translation{0.0f};
  int kx = 0, ky = 1, kz = 2;
  float sx = 0.0f, sy = 0.0f, sz = 0.0f;  ///< shear: x' = x - sx z, y' = y - sy z, z' = sz z
  bool valid = false;  ///< finite, non-zero translation

  explicit WatertightRay(const Ray3& ray) noexcept : origin(ray.origin), translation(ray.translation) {
    const Vec3 d = ray.translation;
    if (!is_finite(ray.origin) || !is_finite(d)) return;
    const Vec3 a = collide::abs(d);
    kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
    if (!(a[kz] > 0.0f)) return;  // zero translation
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0f) std::swap(kx, ky);
    // One division per ray: the shear needs only to be the same for every triangle the ray
    // meets (that is what makes the test watertight), not correctly rounded.
    sz = 1.0f / d[kz];
    sx = d[kx] * sz;
    sy = d[ky] * sz;
    valid = true;
  }

  /// Fraction in (0, max_fraction] at which the ray crosses triangle (a, b, c), either side;
  /// -1 on a miss. `valid` must be true. The paper's fraction interpolates the corners'
  /// distances along the ray by the edge functions, whose rounding grows with the triangle's
  /// length over its width: a sliver (`is_sliver`) is measured from its plane instead.
  [[nodiscard]] float fraction(Vec3 a, Vec3 b, Vec3 c, float max_fraction) const noexcept {
    const Vec3 pa = a - origin, pb = b - origin, pc = c - origin;
    const float ax = pa[kx] - sx * pa[kz], ay = pa[ky] - sy * pa[kz];
    const float bx = pb[kx] - sx * pb[kz], by = pb[ky] - sy * pb[kz];
    const float cx = pc[kx] - sx * pc[kz], cy = pc[ky] - sy * pc[kz];
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
      // On an edge in float: decide in double, where products of floats are exact and the one
      // rounding of their difference keeps its sign.
      u = static_cast<float>(double(cx) * double(by) - double(cy) * double(bx));
      v = static_cast<float>(double(ax) * double(cy) - double(ay) * double(cx));
      w = static_cast<float>(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return -1.0f;
    float det = u + v + w;
    float t = u * (sz * pa[kz]) + v * (sz * pb[kz]) + w * (sz * pc[kz]);
    if (det < 0.0f) det = -det, t = -t;  // two-sided: the back side has a negative determinant
    if (!(det > 0.0f)) return -1.0f;
    if (is_sliver(a, b, c)) return sliver_fraction(a, b, c, max_fraction);
    if (!(t > 0.0f) || !(t <= max_fraction * det)) return -1.0f;
    const float f = t / det;
    return f < max_fraction ? f : max_fraction;
  }

  /// The crossing of a sliver (a, b, c) whose edge functions the ray's line passes (the test
  /// above): where the ray meets its plane, -1 (a miss) outside (0, max_fraction]. The plane
  /// alone decides the range, so every path that tests a sliver agrees on it.
  [[nodiscard]] float sliver_fraction(Vec3 a, Vec3 b, Vec3 c, float max_fraction) const noexcept {
    const float t = plane_fraction(a, b, c, origin, translation);
    return t > 0.0f && t <= max_fraction ? t : -1.0f;
  }
};

}  // namespace collide::detail
