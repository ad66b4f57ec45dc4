// Sphere, Capsule3, Segment3 and Box: validation and bounding boxes.

#include <collide/core/error.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/sphere.hpp>

#include "axis_length.hpp"

#include <cmath>
#include <string>

namespace collide {
namespace {

void check_radius(float radius, const char* what) {
  if (!std::isfinite(radius)) throw InvalidInput(std::string(what) + " radius: not finite");
  if (radius < 0.0f) {
    throw InvalidInput(std::string(what) + " radius: negative (" + std::to_string(radius) + ")");
  }
}

void check_point(Vec3 p, const char* what) {
  if (!is_finite(p)) throw InvalidInput(std::string(what) + ": not finite");
}

}  // namespace

Sphere make_sphere(Vec3 center, float radius) {
  check_point(center, "sphere center");
  check_radius(radius, "sphere");
  return {center, radius};
}

Aabb3 compute_aabb(const Sphere& sphere, const Transform3& xf) noexcept {
  const Vec3 c = transform_point(xf, sphere.center);
  const Vec3 r(sphere.radius);
  return {c - r, c + r};
}

Capsule3 make_capsule(Vec3 a, Vec3 b, float radius) {
  check_point(a, "capsule a");
  check_point(b, "capsule b");
  check_radius(radius, "capsule");
  detail::check_axis(a, b, "capsule", " (use a sphere)");
  return {a, b, radius};
}

Aabb3 compute_aabb(const Capsule3& capsule, const Transform3& xf) noexcept {
  const Vec3 a = transform_point(xf, capsule.a);
  const Vec3 b = transform_point(xf, capsule.b);
  const Vec3 r(capsule.radius);
  return {glm::min(a, b) - r, glm::max(a, b) + r};
}

Segment3 make_segment(Vec3 a, Vec3 b) {
  check_point(a, "segment a");
  check_point(b, "segment b");
  detail::check_axis(a, b, "segment");
  return {a, b};
}

Aabb3 compute_aabb(const Segment3& segment, const Transform3& xf) noexcept {
  const Vec3 a = transform_point(xf, segment.a);
  const Vec3 b = transform_point(xf, segment.b);
  return {glm::min(a, b), glm::max(a, b)};
}

Box make_box(Vec3 half, float radius) {
  static const char* const kAxis[] = {"box half.x", "box half.y", "box half.z"};
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(half[k])) throw InvalidInput(std::string(kAxis[k]) + ": not finite");
    if (!(half[k] > 0.0f)) {
      throw InvalidInput(std::string(kAxis[k]) + ": not positive (" + std::to_string(half[k]) + ")");
    }
  }
  check_radius(radius, "box");
  return {half, radius};
}

Aabb3 compute_aabb(const Box& box, const Transform3& xf) noexcept {
  const Mat3 r = glm::mat3_cast(xf.q);
  // World extent on axis i: sum over local axes k of |R[k][i]| half[k] (column k is local axis k).
  Vec3 e(box.radius);
  for (int k = 0; k < 3; ++k) e += collide::abs(r[k]) * box.half[k];
  return {xf.p - e, xf.p + e};
}

}  // namespace collide
