// Triangulation of a planar polygon in 3D (a level mesh's n-gon face): into its plane, then the
// 2D outline cleaning and ear clipping that decompose_convex uses.

#include <collide/decompose/convex_decomposition.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

namespace collide {
namespace {

using DVec3 = glm::dvec3;

/// A length for a message: enough digits to tell values apart, not more.
std::string shown(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

}  // namespace

std::vector<TriangleIndices> triangulate_planar_polygon(std::span<const Vec3> points, std::string_view name) {
  const std::string label = std::string(name) + ": ";
  const size_t n = points.size();
  for (size_t i = 0; i < n; ++i) {
    if (!is_finite(points[i])) throw InvalidInput(label + "polygon vertex " + std::to_string(i) + ": not finite");
  }
  if (n < 3) throw InvalidInput(label + "polygon needs at least 3 vertices, got " + std::to_string(n));

  // In double, around the average corner and divided by the size: float coordinates anywhere in
  // range give corners within about 1 of the origin, so nothing below overflows or underflows.
  DVec3 lo(points[0]), hi(points[0]), sum(0.0);
  for (const Vec3& p : points) {
    lo = glm::min(lo, DVec3(p));
    hi = glm::max(hi, DVec3(p));
    sum += DVec3(p);
  }
  const DVec3 centre = sum / static_cast<double>(n);
  const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  if (!(size > 0.0)) throw InvalidInput(label + "polygon has zero area (all vertices at one point)");
  std::vector<DVec3> local(n);
  for (size_t i = 0; i < n; ++i) local[i] = (DVec3(points[i]) - centre) / size;

  // Newell's method: the vector area, which points to the side the polygon winds
  // counter-clockwise around.
  DVec3 normal(0.0);
  for (size_t i = 0; i < n; ++i) normal += glm::cross(local[i], local[(i + 1) % n]);
  const double degenerate = static_cast<double>(kDegenerateAreaTolerance);  // of the squared size, 1 here
  if (glm::length(normal) <= degenerate) {
    // No vector area: all corners on a line, or lobes wound against each other cancel (a
    // bow-tie). The plane through the corner farthest from the centre and the corner farthest
    // from that line holds a planar self-intersecting outline, which the 2D test then names.
    size_t far = 0;
    for (size_t i = 1; i < n; ++i) {
      if (glm::dot(local[i], local[i]) > glm::dot(local[far], local[far])) far = i;
    }
    normal = DVec3(0.0);
    for (size_t i = 0; i < n; ++i) {
      const DVec3 c = glm::cross(local[far], local[i]);
      if (glm::dot(c, c) > glm::dot(normal, normal)) normal = c;
    }
    if (glm::length(normal) <= degenerate) {
      throw InvalidInput(label + "polygon has zero area (all vertices collinear)");
    }
  }
  normal = glm::normalize(normal);

  // Planar enough: every corner near the plane through the average corner.
  size_t worst = 0;
  for (size_t i = 1; i < n; ++i) {
    if (std::fabs(glm::dot(local[i], normal)) > std::fabs(glm::dot(local[worst], normal))) worst = i;
  }
  const double off = std::fabs(glm::dot(local[worst], normal));
  if (off > static_cast<double>(kPlanarityTolerance)) {
    throw InvalidInput(label + "polygon is not planar: vertex " + std::to_string(worst) + " lies " +
                       shown(off * size) + " from its best-fit plane, more than " +
                       shown(100.0 * static_cast<double>(kPlanarityTolerance)) + "% of its size " + shown(size) +
                       " (kPlanarityTolerance)");
  }

  // (u, v, normal) right-handed: counter-clockwise in (u, v) is counter-clockwise seen from the
  // normal's side.
  const DVec3 axis = std::fabs(normal.x) < 0.6 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
  const DVec3 u = glm::normalize(glm::cross(axis, normal));
  const DVec3 v = glm::cross(normal, u);
  std::vector<Vec2> flat(n);
  for (size_t i = 0; i < n; ++i) {
    flat[i] = Vec2(static_cast<float>(glm::dot(local[i], u)), static_cast<float>(glm::dot(local[i], v)));
  }
  const SimpleOutline outline = make_simple_outline(flat, name, StraightCorners::keep);
  std::vector<TriangleIndices> triangles = triangulate_ear_clipping(outline.vertices, name, 0, TurnScale::triangle);
  for (TriangleIndices& t : triangles) {
    for (int& corner : t) corner = outline.source[static_cast<size_t>(corner)];
    // A clockwise outline was reversed to clip it: wind its triangles back as the polygon.
    if (outline.reversed) std::swap(t[1], t[2]);
  }
  return triangles;
}

}  // namespace collide
