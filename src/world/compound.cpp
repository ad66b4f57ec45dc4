// make_compound_body / make_compound_static (compound.hpp): convex hulls, such as a convex
// decomposition's, as one body re-centred on their volume centroid, or as one static.

#include <collide/world/compound.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace collide {

namespace {

/// Throws InvalidInput unless there is a hull and each has a positive finite volume and a
/// finite centroid (what make_convex_hull gives; a default-constructed hull has neither).
void check_hulls(std::span<const ConvexHull> hulls) {
  if (hulls.empty()) throw InvalidInput("compound hulls: none given");
  for (std::size_t k = 0; k < hulls.size(); ++k) {
    const ConvexHull& h = hulls[k];
    if (!(h.volume > 0.0f) || !std::isfinite(h.volume) || !is_finite(h.centroid) || h.vertex_count() < 4) {
      throw InvalidInput("compound hulls[" + std::to_string(k) +
                         "]: no volume (a hull must come from make_convex_hull)");
    }
  }
}

void check_placement(const Transform3& placement) {
  if (!is_valid(placement)) {
    throw InvalidInput("compound placement: not finite, or its quaternion is not unit length");
  }
}

}  // namespace

Vec3 compound_centroid(std::span<const ConvexHull> hulls) {
  check_hulls(hulls);
  double volume = 0.0;
  glm::dvec3 moment(0.0);
  for (const ConvexHull& h : hulls) {
    volume += double(h.volume);
    moment += double(h.volume) * glm::dvec3(h.centroid);
  }
  return Vec3(moment / volume);
}

BodyDef3 make_compound_body(std::span<const ConvexHull> hulls, const Transform3& placement) {
  const Vec3 c = compound_centroid(hulls);
  check_placement(placement);
  BodyDef3 def;
  def.shapes.reserve(hulls.size());
  std::vector<Vec3> points;
  for (std::size_t k = 0; k < hulls.size(); ++k) {
    const ConvexHull& h = hulls[k];
    points.resize(h.vertices.size());
    std::transform(h.vertices.begin(), h.vertices.end(), points.begin(), [c](Vec3 v) { return v - c; });
    // The same points, moved: every one is a corner, so the rebuild keeps them all, in order
    // (unless its tolerance, which grows with the coordinates, grew enough to merge faces: then
    // the shape moves by less than that tolerance). The cap only has to let them all in.
    const HullOptions options{.radius = h.radius,
                              .max_vertices = std::clamp(h.vertex_count(), 4, kMaxHullVertices)};
    try {
      def.shapes.emplace_back(make_convex_hull(points, options));
    } catch (const InvalidInput& e) {
      throw InvalidInput("compound hulls[" + std::to_string(k) + "]: " + e.what());
    }
  }
  def.transform = Transform3{transform_point(placement, c), placement.q};
  return def;
}

StaticDef3 make_compound_static(std::span<const ConvexHull> hulls, const Transform3& placement) {
  check_hulls(hulls);
  check_placement(placement);
  StaticDef3 def;
  def.shapes.assign(hulls.begin(), hulls.end());
  def.transform = placement;
  return def;
}

}  // namespace collide
