// 3D point queries checked against the double-precision brute force (tests/support/
// brute_query3.hpp: minima over points, segments and triangles) on random shapes under random
// rigid transforms, near the origin, 1e4 away and at size ratios of 1e4; Voronoi features
// checked on points built inside each region of a box (numbering of box.hpp, rebuilt here from
// its description), a capsule and a segment; the face of least penetration inside.

#include <collide/narrow/closest_point.hpp>

#include "support/brute_query3.hpp"
#include "support/random_shapes3.hpp"
#include "support/test_util.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <vector>

namespace collide {
namespace {

using test::DVec3;
using test::uniform;

DVec3 dvec(Vec3 v) { return DVec3(v); }

std::vector<Shape3D> random_shapes(std::mt19937& rng, float size) {
  std::vector<Shape3D> v;
  for (int i = 0; i < 10; ++i) {
    v.push_back(make_sphere(test::random_point3(rng, 0.5f * size), size * uniform(rng, 0.3f, 2.0f)));
    v.push_back(make_capsule(test::random_point3(rng, 1.5f * size), test::random_point3(rng, 1.5f * size),
                             size * uniform(rng, 0.1f, 1.2f)));
    v.push_back(make_segment(test::random_point3(rng, 2.0f * size), test::random_point3(rng, 2.0f * size)));
    const Vec3 half = size * Vec3{uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f)};
    v.push_back(make_box(half));
    v.push_back(make_box(half, size * uniform(rng, 0.05f, 1.0f)));
    v.push_back(test::random_hull(rng, 4 + 4 * i, 2.0f * size));
    v.push_back(test::random_hull(rng, 4 + 2 * i, 2.0f * size, size * uniform(rng, 0.05f, 1.0f)));
  }
  return v;
}

/// Float rounding of a local point query: 8 float epsilons of the point's local coordinates
/// plus the shape's size (the world offset cancels when the point is moved to local space).
constexpr double kRounding = 1e-6;
/// World points round to float at the coordinates' size.
constexpr double kWorldRounding = 2e-7;

struct Counts {
  int inside = 0, outside = 0, total = 0;
};

/// Random points around random placements of random shapes: the signed distance matches the
/// brute force, the closest point is that far from the point and on the surface, `inside`
/// matches the sign, the Shape3D overload agrees exactly.
Counts compare_with_brute_force(std::mt19937& rng, Vec3 far, float size) {
  Counts n;
  double worst = 0.0;
  for (const Shape3D& shape : random_shapes(rng, size)) {
    for (int k = 0; k < 40; ++k) {
      const Transform3 xf{far + test::random_point3(rng, 3.0f * size), test::random_rotation(rng)};
      const Vec3 p = xf.p + test::random_point3(rng, 2.0f * size);
      const PointQuery3 q = closest_point(shape, xf, p);
      // The brute force in double, shifted by -xf.p (exact), is the truth for these inputs.
      const DVec3 shift = dvec(xf.p);
      const test::BruteCore core = test::brute_core_of(shape, Transform3{Vec3(0.0f), xf.q});
      const double truth = test::brute_signed_distance(core, dvec(p) - shift);
      const double local = glm::length(dvec(p) - shift) + 4.0 * size;
      // A hull's faces are planar only within its build tolerance: the planes the query uses
      // and the corners the brute force triangulates differ by up to that much.
      const ConvexHull* hull = std::get_if<ConvexHull>(&shape);
      const double tol = kRounding * local + (hull ? hull->tolerance : 0.0);
      const double world = tol + kWorldRounding * max_abs(far);
      SCOPED_TRACE(testing::Message() << type_name(shape) << " point " << k);
      ++n.total;
      worst = std::max(worst, std::fabs(q.distance - truth) / local);
      EXPECT_NEAR(q.distance, truth, tol);
      EXPECT_EQ(q.inside, q.distance < 0.0f);
      (q.inside ? n.inside : n.outside)++;
      EXPECT_NEAR(glm::length(dvec(q.closest) - dvec(p)), std::fabs(truth), world);
      EXPECT_NEAR(test::brute_signed_distance(core, dvec(q.closest) - shift), 0.0, world);
      const PointQuery3 any = closest_point(Shape3D{shape}, xf, p);
      EXPECT_EQ(any.distance, q.distance);
      EXPECT_EQ(any.closest, q.closest);
      EXPECT_EQ(any.feature, q.feature);
    }
  }
  std::printf("[ rates    ] %d inside, %d outside of %d; worst distance error %.2g of the extent\n",
              n.inside, n.outside, n.total, worst);
  return n;
}

TEST(ClosestPoint3, MatchesBruteForce) {
  std::mt19937 rng(21);
  for (const auto& [far, size] : {std::pair{Vec3(0.0f), 1.0f}, std::pair{Vec3{1e4f, -1e4f, 1e4f}, 1.0f},
                                  std::pair{Vec3(0.0f), 1e-2f}, std::pair{Vec3(0.0f), 1e2f},
                                  std::pair{Vec3{-1e4f, 1e4f, 1e4f}, 1e-2f}}) {
    SCOPED_TRACE(testing::Message() << "far " << far.x << " size " << size);
    const Counts n = compare_with_brute_force(rng, far, size);
    EXPECT_GT(n.inside, n.total * 10 / 100);
    EXPECT_GT(n.outside, n.total * 40 / 100);
  }
}

// Size ratio 1e4 within one query: a box 1e4 times longer than it is thick, and points near it.
TEST(ClosestPoint3, ThinLongBox) {
  std::mt19937 rng(22);
  const Box box = make_box({1e2f, 1e-2f, 1.0f});
  int inside = 0;
  for (int k = 0; k < 2000; ++k) {
    const Transform3 xf = test::random_transform3(rng, 10.0f);
    const Vec3 local{uniform(rng, -120.0f, 120.0f), uniform(rng, -0.03f, 0.03f), uniform(rng, -1.5f, 1.5f)};
    const PointQuery3 q = closest_point(box, xf, transform_point(xf, local));
    const test::BruteCore core = test::brute_core(box, Transform3{Vec3(0.0f), xf.q});
    const double truth = test::brute_signed_distance(core, dvec(transform_point(xf, local)) - dvec(xf.p));
    EXPECT_NEAR(q.distance, truth, 2e-4);  // 8 float epsilons of the coordinates (~1e2)
    inside += q.inside;
  }
  EXPECT_GT(inside, 100);
}

/// Corner i of a box from the numbering of box.hpp: bit k of i set = + side on axis k.
Vec3 corner(const Box& b, int i) {
  return {(i & 1) ? b.half.x : -b.half.x, (i & 2) ? b.half.y : -b.half.y, (i & 4) ? b.half.z : -b.half.z};
}

Vec3 axis_vector(int k, float sign) {
  Vec3 e(0.0f);
  e[k] = sign;
  return e;
}

// Points built in every Voronoi region of a box's core (8 corner cones, 12 edge wedges, 6 face
// slabs) get that feature, numbered as box.hpp says, and the closest point on it.
TEST(ClosestPoint3, BoxFeatureOfEachVoronoiRegion) {
  std::mt19937 rng(23);
  for (int trial = 0; trial < 100; ++trial) {
    const bool far = trial % 2 == 0;
    const float r = trial % 3 == 0 ? uniform(rng, 0.05f, 0.5f) : 0.0f;
    const Box box = make_box({uniform(rng, 0.3f, 2.0f), uniform(rng, 0.3f, 2.0f), uniform(rng, 0.3f, 2.0f)}, r);
    const Transform3 xf = test::random_transform3(rng, far ? 1.0e4f : 10.0f);
    const float tol = far ? 4e-3f : 2e-5f;
    auto query = [&](Vec3 local) { return closest_point(box, xf, transform_point(xf, local)); };
    for (int i = 0; i < 8; ++i) {
      // Corner cone: out along every axis.
      Vec3 out;
      for (int k = 0; k < 3; ++k) out[k] = ((i >> k) & 1 ? 1.0f : -1.0f) * uniform(rng, 0.05f, 1.0f);
      const PointQuery3 q = query(corner(box, i) + out);
      EXPECT_EQ(q.feature, (Feature{FeatureType::vertex, std::uint32_t(i)}));
      EXPECT_NEAR(q.distance, length(out) - r, tol);
      EXPECT_VEC3_NEAR(q.closest, transform_point(xf, corner(box, i) + r * normalize_or_zero(out)), tol);
    }
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 4; ++j) {
        // Edge 4k + j runs along axis k; bit 0 of j is its side on axis (k + 1) % 3, bit 1 on
        // (k + 2) % 3. Its ends are the corners with those bits and either side on axis k.
        const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        const int base = ((j & 1) << k1) | (((j >> 1) & 1) << k2);
        const Vec3 a = corner(box, base), b = corner(box, base | (1 << k));
        const Vec3 on = a + uniform(rng, 0.05f, 0.95f) * (b - a);
        const Vec3 out = axis_vector(k1, (j & 1) ? 1.0f : -1.0f) * uniform(rng, 0.05f, 1.0f) +
                         axis_vector(k2, (j & 2) ? 1.0f : -1.0f) * uniform(rng, 0.05f, 1.0f);
        const PointQuery3 q = query(on + out);
        EXPECT_EQ(q.feature, (Feature{FeatureType::edge, std::uint32_t(4 * k + j)})) << k << " " << j;
        EXPECT_NEAR(q.distance, length(out) - r, tol);
        EXPECT_VEC3_NEAR(q.closest, transform_point(xf, on + r * normalize_or_zero(out)), tol);
      }
      for (int s = 0; s < 2; ++s) {
        // Face 2k + s: outward normal -axis k (s = 0) or +axis k (s = 1).
        const Vec3 n = axis_vector(k, s ? 1.0f : -1.0f);
        Vec3 on = n * box.half[k];
        on[(k + 1) % 3] = uniform(rng, -0.95f, 0.95f) * box.half[(k + 1) % 3];
        on[(k + 2) % 3] = uniform(rng, -0.95f, 0.95f) * box.half[(k + 2) % 3];
        const float h = uniform(rng, 0.01f, 2.0f);
        const PointQuery3 q = query(on + h * n);
        EXPECT_EQ(q.feature, (Feature{FeatureType::face, std::uint32_t(2 * k + s)}));
        EXPECT_NEAR(q.distance, h - r, tol);
        EXPECT_VEC3_NEAR(q.closest, transform_point(xf, on + r * n), tol);
        // Inside, nearer this face than any other: the face of least penetration.
        float room = std::numeric_limits<float>::infinity();
        for (int m = 0; m < 3; ++m) {
          room = std::min(room, box.half[m] - std::fabs(on[m] * (m == k ? 0.0f : 1.0f)));
        }
        const float depth = 0.4f * std::min(room, box.half[k]);
        const PointQuery3 qi = query(on - depth * n);
        EXPECT_TRUE(qi.inside);
        EXPECT_EQ(qi.feature, (Feature{FeatureType::face, std::uint32_t(2 * k + s)}));
        EXPECT_NEAR(qi.distance, -depth - r, tol);
        EXPECT_VEC3_NEAR(qi.closest, transform_point(xf, on + r * n), tol);
      }
    }
  }
}

// Touching: points exactly on a box's face, edge and corner have distance 0 and are not inside;
// on the boundary the feature is a face that holds the point. The centre of a box: the face of
// least penetration (the thinnest axis), lowest axis on ties.
TEST(ClosestPoint3, BoxBoundaryAndCentre) {
  const Box box = make_box({1.0f, 2.0f, 3.0f});
  const Transform3 id{};
  const PointQuery3 face = closest_point(box, id, {1.0f, 0.5f, -0.5f});
  EXPECT_EQ(face.distance, 0.0f);
  EXPECT_FALSE(face.inside);
  EXPECT_EQ(face.feature, (Feature{FeatureType::face, 1}));
  const PointQuery3 edge = closest_point(box, id, {-1.0f, 2.0f, 0.5f});
  EXPECT_EQ(edge.distance, 0.0f);
  EXPECT_EQ(edge.feature, (Feature{FeatureType::face, 0}));
  const PointQuery3 vertex = closest_point(box, id, {1.0f, -2.0f, 3.0f});
  EXPECT_EQ(vertex.distance, 0.0f);
  EXPECT_EQ(vertex.closest, Vec3(1.0f, -2.0f, 3.0f));
  const PointQuery3 centre = closest_point(box, id, {0.0f, 0.0f, 0.0f});
  EXPECT_EQ(centre.distance, -1.0f);
  EXPECT_EQ(centre.feature, (Feature{FeatureType::face, 1}));
  EXPECT_EQ(centre.closest, Vec3(1.0f, 0.0f, 0.0f));
  const PointQuery3 tie = closest_point(make_box({1.0f, 1.0f, 1.0f}), id, {0.0f, 0.0f, 0.0f});
  EXPECT_EQ(tie.feature, (Feature{FeatureType::face, 1}));
  // A rounded box: on the rounded edge, distance 0 (0.375^2 + 0.5^2 = 0.625^2 exactly).
  const PointQuery3 rounded = closest_point(make_box({1.0f, 1.0f, 1.0f}, 0.625f), id, {1.375f, 1.5f, 0.25f});
  EXPECT_EQ(rounded.distance, 0.0f);
  EXPECT_EQ(rounded.feature, (Feature{FeatureType::edge, 4 * 2 + 3}));
}

// Points built in every Voronoi region of a hull's core: in front of a face's interior (face),
// out from an edge between its two face normals (edge), out from a vertex along a positive mix
// of its faces' normals (vertex); the closest point is on that feature, the distance the
// offset's length. Inside, just below a face's centre: that face of least penetration.
TEST(ClosestPoint3, HullFeatureOfEachVoronoiRegion) {
  std::mt19937 rng(26);
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const bool far = trial % 2 == 0;
    const float r = trial % 3 == 0 ? uniform(rng, 0.05f, 0.3f) : 0.0f;
    const ConvexHull hull = test::random_hull(rng, 6 + trial % 30, 2.0f, r);
    const Transform3 xf = test::random_transform3(rng, far ? 1.0e4f : 10.0f);
    const float tol = far ? 4e-3f : 2e-5f;
    auto query = [&](Vec3 local) { return closest_point(hull, xf, transform_point(xf, local)); };
    for (std::size_t f = 0; f < hull.faces.size(); ++f) {
      const HullFace& face = hull.faces[f];
      Vec3 centre(0.0f);
      for (int k = 0; k < face.count; ++k) centre += hull.vertices[hull.face_vertices[face.first + k]];
      centre /= static_cast<float>(face.count);
      const float h = uniform(rng, 0.01f, 1.0f);
      const PointQuery3 q = query(centre + h * face.normal);
      EXPECT_EQ(q.feature, (Feature{FeatureType::face, std::uint32_t(f)}));
      EXPECT_NEAR(q.distance, h - r, tol);
      // Just below the centre, less deep than any other face's plane: the same face.
      float room = INFINITY;
      for (const HullFace& g : hull.faces) {
        if (&g != &face) room = std::min(room, g.offset - dot(g.normal, centre));
      }
      const float depth = 0.3f * std::min(room, 0.5f);
      if (depth > 20.0f * tol) {
        const PointQuery3 qi = query(centre - depth * face.normal);
        EXPECT_TRUE(qi.inside);
        EXPECT_EQ(qi.feature, (Feature{FeatureType::face, std::uint32_t(f)}));
        EXPECT_NEAR(qi.distance, -depth - r, tol);
      }
      ++checked;
    }
    for (std::size_t e = 0; e < hull.edges.size(); ++e) {
      const HullEdge& edge = hull.edges[e];
      const Vec3 a = hull.vertices[edge.v0], b = hull.vertices[edge.v1];
      const Vec3 out = uniform(rng, 0.1f, 1.0f) * hull.faces[edge.face0].normal +
                       uniform(rng, 0.1f, 1.0f) * hull.faces[edge.face1].normal;
      const Vec3 on = a + uniform(rng, 0.2f, 0.8f) * (b - a);
      // Only well inside the wedge (the normals may be nearly parallel on a flat-ish edge).
      if (length(cross(hull.faces[edge.face0].normal, hull.faces[edge.face1].normal)) < 0.05f) continue;
      const Vec3 offset = 0.5f * out;
      const PointQuery3 q = query(on + offset);
      EXPECT_EQ(q.feature, (Feature{FeatureType::edge, std::uint32_t(e)}));
      EXPECT_NEAR(q.distance, length(offset) - r, tol);
      ++checked;
    }
    for (int v = 0; v < hull.vertex_count(); ++v) {
      Vec3 out(0.0f);
      int faces = 0;
      for (const HullFace& g : hull.faces) {
        for (int k = 0; k < g.count; ++k) {
          if (hull.face_vertices[g.first + k] == v) {
            out += uniform(rng, 0.2f, 1.0f) * g.normal;
            ++faces;
          }
        }
      }
      ASSERT_GE(faces, 3);
      const Vec3 offset = 0.5f * normalize_or_zero(out);
      // The vertex's region is bounded by the planes across its edges at it; skip an offset
      // within rounding of one (a face normal lies on two of them, so a mix may come close).
      bool clear = true;
      for (const HullEdge& e : hull.edges) {
        if (e.v0 != v && e.v1 != v) continue;
        const Vec3 along = normalize_or_zero(hull.vertices[e.v0 == v ? e.v1 : e.v0] - hull.vertices[v]);
        clear = clear && dot(offset, along) < -20.0f * tol;
      }
      if (!clear) continue;
      const PointQuery3 q = query(hull.vertices[v] + offset);
      EXPECT_EQ(q.feature, (Feature{FeatureType::vertex, std::uint32_t(v)}));
      EXPECT_NEAR(q.distance, 0.5f - r, tol);
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

// A box and the hull of its corners are the same solid: the same distances and closest points.
TEST(ClosestPoint3, CubeHullMatchesBox) {
  std::mt19937 rng(27);
  for (int trial = 0; trial < 50; ++trial) {
    const Box box = make_box({uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f), uniform(rng, 0.2f, 2.0f)},
                             trial % 2 ? uniform(rng, 0.05f, 0.8f) : 0.0f);
    std::vector<Vec3> corners;
    for (int i = 0; i < 8; ++i) corners.push_back(box.vertex(i));
    const ConvexHull hull = make_convex_hull(corners, HullOptions{box.radius});
    for (int k = 0; k < 100; ++k) {
      const Transform3 xf = test::random_transform3(rng, 10.0f);
      const Vec3 p = xf.p + test::random_point3(rng, 3.0f);
      const PointQuery3 a = closest_point(box, xf, p);
      const PointQuery3 b = closest_point(hull, xf, p);
      EXPECT_NEAR(a.distance, b.distance, 1e-5f);
      EXPECT_VEC3_NEAR(a.closest, b.closest, 2e-5f);
      EXPECT_EQ(a.feature.type, b.feature.type);
    }
  }
}

TEST(ClosestPoint3, SphereAnalytic) {
  std::mt19937 rng(24);
  int inside = 0, outside = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const bool far = trial % 2 == 0;
    const Sphere s = make_sphere(test::random_point3(rng, 1.0f), uniform(rng, 0.1f, 3.0f));
    const Transform3 xf = test::random_transform3(rng, far ? 1.0e4f : 10.0f);
    const float tol = far ? 4e-3f : 1e-5f;
    const Vec3 center = transform_point(xf, s.center);
    const Vec3 p = center + test::random_point3(rng, 1.2f * s.radius);
    const PointQuery3 q = closest_point(s, xf, p);
    const float d = distance(p, center);
    EXPECT_NEAR(q.distance, d - s.radius, tol);
    EXPECT_VEC3_NEAR(q.closest, center + s.radius * normalize_or_zero(p - center), tol);
    EXPECT_EQ(q.feature, (Feature{FeatureType::face, 0}));
    EXPECT_EQ(q.inside, q.distance < 0.0f);
    (q.inside ? inside : outside)++;
  }
  EXPECT_GT(inside, 450);
  EXPECT_GT(outside, 450);
  // The centre itself: distance -radius, the surface point along local +x.
  const Transform3 xf = Transform3::from_axis_angle({1.0f, 2.0f, 3.0f}, {0.0f, 0.0f, 1.0f}, 0.5f * test::kPi);
  const PointQuery3 at_center = closest_point(make_sphere({0.0f, 0.0f, 0.0f}, 0.5f), xf, {1.0f, 2.0f, 3.0f});
  EXPECT_FLOAT_EQ(at_center.distance, -0.5f);
  EXPECT_VEC3_NEAR(at_center.closest, Vec3(1.0f, 2.5f, 3.0f), 1e-6f);
}

/// Capsule (radius r) and segment (r = 0): features by construction (before a, past b,
/// beside the core) and points on the core itself.
template <class S>
void check_segment_like(const S& shape, float r, std::mt19937& rng) {
  const bool far = rng() % 2 == 0;
  const Transform3 xf = test::random_transform3(rng, far ? 1.0e4f : 10.0f);
  const float tol = far ? 4e-3f : 1e-5f;
  const Vec3 a = shape.a, b = shape.b;
  const Vec3 u = normalize_or_zero(b - a);
  const Vec3 across = normalize_or_zero(cross(u, test::random_point3(rng, 1.0f)));
  const float h = uniform(rng, 0.01f, 2.0f);
  const float s = uniform(rng, 0.05f, 0.95f);
  const Vec3 beside = a + s * (b - a);
  const Vec3 cases[3] = {a - h * u + uniform(rng, -1.0f, 1.0f) * h * across,
                         b + h * u + uniform(rng, -1.0f, 1.0f) * h * across, beside + h * across};
  const Feature expected[3] = {{FeatureType::vertex, 0}, {FeatureType::vertex, 1}, {FeatureType::edge, 0}};
  for (int c = 0; c < 3; ++c) {
    const PointQuery3 q = closest_point(shape, xf, transform_point(xf, cases[c]));
    EXPECT_EQ(q.feature, expected[c]) << "case " << c;
  }
  const PointQuery3 side = closest_point(shape, xf, transform_point(xf, beside + h * across));
  EXPECT_NEAR(side.distance, h - r, tol);
  // The placed point rounds by ~tol, which turns the direction across by tol / h.
  EXPECT_VEC3_NEAR(side.closest, transform_point(xf, beside + r * across), tol * (1.0f + r / h));
  // On the core: distance -r, the closest point r across the axis (some direction).
  const PointQuery3 on = closest_point(shape, xf, transform_point(xf, beside));
  EXPECT_NEAR(on.distance, -r, tol);
  EXPECT_EQ(on.feature, (Feature{FeatureType::edge, 0}));
  const Vec3 off = inv_transform_point(xf, on.closest) - beside;
  EXPECT_NEAR(length(off), r, tol);
  EXPECT_NEAR(dot(off, u), 0.0f, tol);
  // Just beyond an end (by more than the rounding of the placed point): that end's vertex.
  const PointQuery3 end = closest_point(shape, xf, transform_point(xf, a - 0.05f * u));
  EXPECT_EQ(end.feature, (Feature{FeatureType::vertex, 0}));
  EXPECT_NEAR(end.distance, 0.05f - r, tol);
  // Exactly on an end (identity placement, no rounding): out along the axis.
  const PointQuery3 on_end = closest_point(shape, Transform3{}, b);
  EXPECT_EQ(on_end.feature, (Feature{FeatureType::vertex, 1}));
  EXPECT_EQ(on_end.distance, -r);
  EXPECT_VEC3_NEAR(on_end.closest, b + r * u, 1e-6f);
}

TEST(ClosestPoint3, CapsuleAndSegmentFeatures) {
  std::mt19937 rng(25);
  for (int trial = 0; trial < 200; ++trial) {
    const Capsule3 c = make_capsule(test::random_point3(rng, 2.0f), test::random_point3(rng, 2.0f),
                                    uniform(rng, 0.2f, 1.5f));
    check_segment_like(c, c.radius, rng);
    const Segment3 s = make_segment(test::random_point3(rng, 2.0f), test::random_point3(rng, 2.0f));
    check_segment_like(s, 0.0f, rng);
  }
  // A segment has no inside: a point on it has distance 0, edge 0, and is the closest point.
  const PointQuery3 on = closest_point(make_segment({-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}), Transform3{},
                                       {0.25f, 0.0f, 0.0f});
  EXPECT_EQ(on.distance, 0.0f);
  EXPECT_FALSE(on.inside);
  EXPECT_EQ(on.closest, Vec3(0.25f, 0.0f, 0.0f));
  EXPECT_EQ(on.feature, (Feature{FeatureType::edge, 0}));
}

}  // namespace
}  // namespace collide
