#pragma once
// Debian's qhull (libqhull_r, double precision) as an independent oracle for convex hulls.
// Test-only: the library never links qhull.

#include <collide/core/math.hpp>

#include <span>
#include <string>
#include <vector>

namespace collide::test {

/// What qhull says about the convex hull of a point set.
struct QhullResult {
  bool ok = false;              ///< qhull succeeded
  std::string error;            ///< qhull's message when it did not
  double volume = 0.0;          ///< volume of the hull
  std::vector<int> vertices;    ///< input indices of the hull vertices, ascending
  struct Plane {
    glm::dvec3 normal;          ///< unit outward normal
    double offset;              ///< dot(normal, x) = offset on the facet
  };
  std::vector<Plane> facets;    ///< merged facets (qhull's default merging, C-0)
  int triangles = 0;            ///< facets of qhull's triangulated output (option Qt)
};

/// Runs qhull ("qhull" with default merging) on `points` (converted to double).
QhullResult qhull_hull(std::span<const Vec3> points);

}  // namespace collide::test
