// Ray casts against the triangle shapes of levels: a single triangle, a mesh through its BVH, a
// height field through its cells. The ray is moved into the shape's local frame (and, for meshes
// and height fields, relative to their stored origin, which the shapes themselves take care of
// for height fields); hits come back in world space with the normal turned to face the ray.

#include <collide/ccd/raycast.hpp>

#include <limits>

namespace collide {
namespace {

/// True for the identity rotation, exactly: a level is most often placed unrotated, and its
/// rays then skip the three quaternion products (a fifth of a short ray's cost). The same
/// arithmetic otherwise (a rotation by the identity adds zeros).
bool unrotated(const Quat& q) noexcept {
  return q.w == 1.0f && q.x == 0.0f && q.y == 0.0f && q.z == 0.0f;
}

/// The ray in the frame of `xf`, relative to `origin` there.
Ray3 to_local(const Transform3& xf, const Ray3& ray, Vec3 origin) noexcept {
  if (unrotated(xf.q)) return {(ray.origin - xf.p) - origin, ray.translation};
  return {inv_transform_point(xf, ray.origin) - origin, inv_rotate(xf.q, ray.translation)};
}

/// A world hit from a local crossing: `normal` is the triangle's unit normal (local), turned
/// against the local translation, then rotated to the world.
RayHit3 to_world(const Transform3& xf, const Ray3& ray, const Ray3& local, float fraction, Vec3 normal,
                 std::uint32_t triangle) noexcept {
  const Vec3 facing = dot(normal, local.translation) > 0.0f ? -normal : normal;
  return {true, fraction, ray.at(fraction), unrotated(xf.q) ? facing : rotate(xf.q, facing), triangle};
}

}  // namespace

RayHit3 raycast(const Triangle& triangle, const Transform3& xf, const Ray3& ray) noexcept {
  const Ray3 local = to_local(xf, ray, Vec3(0.0f));
  const auto& v = triangle.vertices;
  const float fraction = ray_triangle_fraction(local, v[0], v[1], v[2]);
  if (fraction < 0.0f) return {};
  return to_world(xf, ray, local, fraction, triangle_normal(v[0], v[1], v[2]), 0);
}

RayHit3 raycast(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray) noexcept {
  const Ray3 local = to_local(xf, ray, mesh.origin);
  const TriangleRayHit hit = mesh.bvh.ray_cast(local);
  if (hit.triangle == std::numeric_limits<std::uint32_t>::max()) return {};
  return to_world(xf, ray, local, hit.fraction, hit.normal, hit.triangle);
}

RayHit3 raycast(const HeightField& field, const Transform3& xf, const Ray3& ray) noexcept {
  const Ray3 local = to_local(xf, ray, Vec3(0.0f));  // the field works relative to its origin itself
  const TriangleRayHit hit = field.ray_cast(local);
  if (hit.triangle == std::numeric_limits<std::uint32_t>::max()) return {};
  return to_world(xf, ray, local, hit.fraction, hit.normal, hit.triangle);
}

// The same crossings as the three casts above, the hit and fraction alone.
RayFraction raycast_fraction(const Triangle& triangle, const Transform3& xf, const Ray3& ray) noexcept {
  const auto& v = triangle.vertices;
  const float fraction = ray_triangle_fraction(to_local(xf, ray, Vec3(0.0f)), v[0], v[1], v[2]);
  if (fraction < 0.0f) return {};
  return {true, fraction};
}

RayFraction raycast_fraction(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray) noexcept {
  const TriangleRayHit hit = mesh.bvh.ray_cast(to_local(xf, ray, mesh.origin));
  if (hit.triangle == std::numeric_limits<std::uint32_t>::max()) return {};
  return {true, hit.fraction};
}

RayFraction raycast_fraction(const HeightField& field, const Transform3& xf, const Ray3& ray) noexcept {
  const TriangleRayHit hit = field.ray_cast(to_local(xf, ray, Vec3(0.0f)));
  if (hit.triangle == std::numeric_limits<std::uint32_t>::max()) return {};
  return {true, hit.fraction};
}

void raycast(const TriangleMesh& mesh, const Transform3& xf, const Ray3& ray, RayHitCallback visit) {
  const Ray3 local = to_local(xf, ray, mesh.origin);
  mesh.bvh.ray_cast(local, [&](std::uint32_t t, float fraction) {
    const Vec3 n = triangle_normal(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
    return visit(to_world(xf, ray, local, fraction, n, t));
  });
}

void raycast(const HeightField& field, const Transform3& xf, const Ray3& ray, RayHitCallback visit) {
  const Ray3 local = to_local(xf, ray, Vec3(0.0f));
  field.ray_cast(local, [&](std::uint32_t t, float fraction) {
    const std::array<Vec3, 3> p = field.grid_corners(t);
    return visit(to_world(xf, ray, local, fraction, triangle_normal(p[0], p[1], p[2]), t));
  });
}

}  // namespace collide
