#pragma once
// Pairs of real convex hulls (the clouds of Jolt's convex_hulls.bin) placed separated,
// overlapping or about to meet, with an exact reference for every answer, in double precision:
// the Minkowski difference K = A - B as an intersection of half-spaces. For convex polytopes
// each face normal of K is a face normal of A, a face normal of -B, or the cross product of an
// edge of A and an edge of B (Ericson, Real-Time Collision Detection, 5.5.2; Gregorius, "The
// Separating Axis Test between Convex Polyhedra", GDC 2013). Taking every such direction (both
// signs, whether or not it is a face of K) with its exact support value h(n) = max_a n.a -
// min_b n.b gives a superset of K's face planes, each of them supporting K, so their
// intersection is exactly K. From it:
//  - A and B overlap iff the origin is in K (every h >= 0);
//  - the penetration depth is min h (the distance from the origin to K's boundary), along the
//    minimising n, from A to B (moving B by depth n separates the pair);
//  - a translation of A by t va meets B first at the t where the ray -t va enters K.
// Distances of separated pairs come from brute_convex3.hpp (element pairs), not from K.
// Also a hull against a triangle. Used by bench/narrow3.cpp, tests/narrow/jolt_oracle_test.cpp
// and tests/narrow/triangle_query_test.cpp.

#include <collide/core/error.hpp>
#include <collide/core/transform3.hpp>
#include <collide/shape/convex_hull.hpp>

#include "support/brute_convex3.hpp"
#include "support/jolt_clouds.hpp"
#include "support/test_util.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <utility>
#include <vector>

namespace collide::test {

/// Every cloud of convex_hulls.bin that make_convex_hull accepts (not flat), moved so that its
/// hull's volume centroid is the origin and scaled so that its bounding box's longest side is
/// `size`, as a hull (rebuilt from the scaled points). At most `max_count` hulls, taken from
/// the whole file by a fixed-seed shuffle (all of them if max_count <= 0).
inline std::vector<ConvexHull> scaled_jolt_hulls(float size, int max_count = 0,
                                                 unsigned seed = 14) {
  std::vector<std::vector<Vec3>> clouds = load_jolt_clouds();
  std::mt19937 rng(seed);
  std::shuffle(clouds.begin(), clouds.end(), rng);
  std::vector<ConvexHull> hulls;
  for (const std::vector<Vec3>& cloud : clouds) {
    if (max_count > 0 && static_cast<int>(hulls.size()) >= max_count) break;
    ConvexHull original;
    try {
      original = make_convex_hull(cloud);
    } catch (const InvalidInput&) {
      continue;  // flat or degenerate cloud
    }
    const Vec3 extent = original.bounds.size();
    const float scale = size / std::max({extent.x, extent.y, extent.z});
    std::vector<Vec3> scaled;
    for (const Vec3& p : cloud) scaled.push_back((p - original.centroid) * scale);
    try {
      hulls.push_back(make_convex_hull(scaled));
    } catch (const InvalidInput&) {
      continue;
    }
  }
  return hulls;
}

/// K = A - B for two placed hulls, as half-spaces n.x <= h (see the file comment), with the
/// placed vertices of both (world space, double).
struct MinkowskiReference {
  std::vector<DVec3> a, b;        ///< world vertices of A and B
  std::vector<DVec3> normals;     ///< unit candidate directions
  std::vector<double> supports;   ///< h(n) for each direction

  /// h(n) = max over A of n.a - min over B of n.b, for any direction n.
  [[nodiscard]] double support(DVec3 n) const {
    double hi = -std::numeric_limits<double>::infinity();
    double lo = std::numeric_limits<double>::infinity();
    for (const DVec3& p : a) hi = std::max(hi, glm::dot(n, p));
    for (const DVec3& p : b) lo = std::min(lo, glm::dot(n, p));
    return hi - lo;
  }
  /// True when the shapes overlap (touching counts).
  [[nodiscard]] bool overlapping() const {
    return std::all_of(supports.begin(), supports.end(), [](double h) { return h >= 0.0; });
  }
  /// Penetration depth of overlapping shapes (negative: a lower bound of minus the distance of
  /// separated ones), and its direction from A to B in `normal`.
  double depth(DVec3* normal = nullptr) const {
    const auto it = std::min_element(supports.begin(), supports.end());
    if (normal) *normal = normals[static_cast<size_t>(it - supports.begin())];
    return *it;
  }
  /// How far B must move along the unit direction `n` to separate (negative if apart): the
  /// depth that a contact normal n implies, exact; >= depth() for every n, equal for the best.
  [[nodiscard]] double depth_along(DVec3 n) const { return support(n); }
  /// First fraction t in [0, 1] at which A moved by t * va touches B (static), or a negative
  /// value if it does not within the step. The shapes must start apart.
  [[nodiscard]] double first_touch(DVec3 va) const {
    // The ray -t va must lie in every half-space: -t (n.va) <= h.
    double enter = 0.0;
    double leave = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < normals.size(); ++i) {
      const double c = -glm::dot(normals[i], va);
      const double h = supports[i];
      if (c > 0.0) {
        leave = std::min(leave, h / c);
      } else if (c < 0.0) {
        enter = std::max(enter, h / c);
      } else if (h < 0.0) {
        return -1.0;
      }
    }
    return enter <= leave && enter <= 1.0 ? enter : -1.0;
  }
};

/// Newell's normal of hull face `f`, placed by `xf`, in double.
inline DVec3 face_normal(const ConvexHull& hull, const HullFace& f, const Transform3& xf) {
  DVec3 n(0.0);
  for (int k = 0; k < f.count; ++k) {
    const DVec3 p = to_world(xf, hull.vertices[hull.face_vertices[f.first + k]]);
    const DVec3 q = to_world(xf, hull.vertices[hull.face_vertices[f.first + (k + 1) % f.count]]);
    n += glm::cross(p, q);
  }
  return glm::normalize(n);
}

/// K from both shapes' world vertices, their face normals (both signs taken) and edge
/// directions (every cross product of an edge of A with an edge of B, both signs, unless
/// parallel): the file comment's superset of K's face planes.
inline MinkowskiReference minkowski_from(std::vector<DVec3> a, std::vector<DVec3> b, const std::vector<DVec3>& faces,
                                         const std::vector<DVec3>& edges_a, const std::vector<DVec3>& edges_b) {
  MinkowskiReference k;
  k.a = std::move(a);
  k.b = std::move(b);
  const auto add = [&](DVec3 n) {
    k.normals.push_back(n);
    k.normals.push_back(-n);
  };
  for (const DVec3& n : faces) add(n);
  for (const DVec3& da : edges_a) {
    for (const DVec3& db : edges_b) {
      const DVec3 n = glm::cross(da, db);
      const double len2 = glm::dot(n, n);
      if (len2 > 1e-24 * glm::dot(da, da) * glm::dot(db, db)) add(n / std::sqrt(len2));
    }
  }
  k.supports.reserve(k.normals.size());
  for (const DVec3& n : k.normals) k.supports.push_back(k.support(n));
  return k;
}

/// A placed hull's world vertices, face normals and edge directions, appended.
inline void gather_hull(const ConvexHull& hull, const Transform3& xf, std::vector<DVec3>& vertices,
                        std::vector<DVec3>& faces, std::vector<DVec3>& edges) {
  const std::size_t first = vertices.size();
  for (const Vec3& v : hull.vertices) vertices.push_back(to_world(xf, v));
  for (const HullFace& f : hull.faces) faces.push_back(face_normal(hull, f, xf));
  for (const HullEdge& e : hull.edges) edges.push_back(vertices[first + e.v1] - vertices[first + e.v0]);
}

inline MinkowskiReference minkowski_reference(const ConvexHull& a, const Transform3& xa,
                                              const ConvexHull& b, const Transform3& xb) {
  std::vector<DVec3> va, vb, faces, ea, eb;
  gather_hull(a, xa, va, faces, ea);
  gather_hull(b, xb, vb, faces, eb);
  return minkowski_from(std::move(va), std::move(vb), faces, ea, eb);
}

/// K = A - T for a placed hull A and a triangle T (world space, double): T's two face
/// directions and its three edges stand in for B's face normals and edges (a triangle is a flat
/// polytope: its faces are its plane's two sides).
inline MinkowskiReference minkowski_reference(const ConvexHull& a, const Transform3& xa,
                                              const std::array<DVec3, 3>& triangle) {
  std::vector<DVec3> va, faces, ea;
  gather_hull(a, xa, va, faces, ea);
  faces.push_back(glm::normalize(glm::cross(triangle[1] - triangle[0], triangle[2] - triangle[0])));
  const std::vector<DVec3> et{triangle[1] - triangle[0], triangle[2] - triangle[1], triangle[0] - triangle[2]};
  return minkowski_from(std::move(va), {triangle.begin(), triangle.end()}, faces, ea, et);
}

/// How a pair is placed.
enum class Placement {
  separated,    ///< B moved away from touching by a gap along a random direction
  overlapping,  ///< B moved into A by a penetration along a random direction
  approaching,  ///< B apart, and A moving by `va` towards it (meeting B in about half the pairs)
};

/// Two hulls of a list, placed.
struct HullPair {
  int a = 0, b = 0;  ///< indices into the hull list
  Transform3 xa, xb;
  Vec3 va{0.0f};     ///< A's translation over the step (approaching pairs; B is static)
};

/// Parameters of make_hull_pairs, in units of the hulls' size.
struct PairSpread {
  float position = 10.0f;                     ///< A anywhere in [-position, position]^3
  float gap_min = 0.01f, gap_max = 0.5f;      ///< separated: offset beyond touching along d
  float depth_min = 0.01f, depth_max = 0.25f; ///< overlapping: offset within touching along d
  float cast_min = 0.01f, cast_max = 0.6f;    ///< approaching: length of A's translation
};

/// `count` pairs of random hulls from `hulls` (whose local origins are inside them), randomly
/// turned, B's position found exactly from the touching offset along a random direction d (the
/// exit of the ray from the origin along d out of K with both origins together).
inline std::vector<HullPair> make_hull_pairs(std::span<const ConvexHull> hulls, int count,
                                             Placement placement, unsigned seed,
                                             const PairSpread& spread = {}) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(hulls.size()) - 1);
  std::vector<HullPair> pairs;
  while (static_cast<int>(pairs.size()) < count) {
    HullPair p;
    p.a = pick(rng);
    p.b = pick(rng);
    p.xa = random_transform3(rng, spread.position);
    p.xb = Transform3::from(p.xa.p, random_rotation(rng));
    Vec3 d = random_point3(rng, 1.0f);
    if (dot(d, d) < 1e-4f) continue;
    d = normalize(d);
    const MinkowskiReference k = minkowski_reference(hulls[p.a], p.xa, hulls[p.b], p.xb);
    // B at xa.p + s d touches A where the ray s d leaves K.
    double touch = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < k.normals.size(); ++i) {
      const double c = glm::dot(k.normals[i], DVec3(d));
      if (c > 0.0) touch = std::min(touch, k.supports[i] / c);
    }
    float offset = static_cast<float>(touch);
    switch (placement) {
      case Placement::separated: offset += uniform(rng, spread.gap_min, spread.gap_max); break;
      case Placement::overlapping:
        // Not past the middle: the far side of A's origin need not be inside K.
        offset = std::max(offset - uniform(rng, spread.depth_min, spread.depth_max), 0.5f * offset);
        break;
      case Placement::approaching: {
        offset += uniform(rng, spread.gap_min, spread.gap_max);
        // Towards B, off the line of centres by up to about 30 degrees.
        const Vec3 aim = normalize(d + 0.25f * random_point3(rng, 1.0f));
        p.va = uniform(rng, spread.cast_min, spread.cast_max) * aim;
        break;
      }
    }
    p.xb.p = p.xa.p + offset * d;
    pairs.push_back(p);
  }
  return pairs;
}

}  // namespace collide::test
