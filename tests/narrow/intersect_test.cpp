// Polygon overlap checked against analytic boxes, and random pairs against an independent
// construction: the overlap of two convex polygons is the convex hull of A's vertices inside B,
// B's vertices inside A and the crossings of their edges (gift wrapping, shoelace area).

#include <collide/core/error.hpp>
#include <collide/narrow/intersect.hpp>

#include "support/brute_convex.hpp"
#include "support/test_util.hpp"

#include <optional>

namespace collide {
namespace {

using test::uniform;

bool inside_convex(const std::vector<Vec2>& poly, Vec2 p) {
  for (size_t i = 0; i < poly.size(); ++i) {
    if (cross(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]) < 0.0f) return false;
  }
  return true;
}

std::optional<Vec2> segment_crossing(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const float den = cross(b - a, d - c);
  if (den == 0.0f) return std::nullopt;
  const float s = cross(c - a, d - c) / den;
  const float t = cross(c - a, b - a) / den;
  if (s < 0.0f || s > 1.0f || t < 0.0f || t > 1.0f) return std::nullopt;
  return a + s * (b - a);
}

/// The overlap by brute force: hull of contained vertices and edge crossings; empty if fewer
/// than 3 points.
std::vector<Vec2> brute_overlap(const std::vector<Vec2>& a, const std::vector<Vec2>& b, float tol) {
  std::vector<Vec2> pts;
  for (Vec2 p : a) {
    if (inside_convex(b, p)) pts.push_back(p);
  }
  for (Vec2 p : b) {
    if (inside_convex(a, p)) pts.push_back(p);
  }
  for (size_t i = 0; i < a.size(); ++i) {
    for (size_t j = 0; j < b.size(); ++j) {
      if (auto x = segment_crossing(a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()])) {
        pts.push_back(*x);
      }
    }
  }
  if (pts.size() < 3) return {};
  return test::gift_wrap(pts, tol);
}

std::vector<Vec2> result_vertices(const OverlapPolygon& o) {
  return std::vector<Vec2>(o.vertices.begin(), o.vertices.begin() + o.count);
}

TEST(Intersect, OverlappingBoxesAnalytic) {
  std::mt19937 rng(31);
  const Polygon a = make_box({2.0f, 1.0f});
  const Polygon b = make_box({1.0f, 1.5f}, {2.5f, 0.5f}, 0.0f);
  // Overlap: x in [1.5, 2], y in [-1, 1]: area 1, centroid (1.75, 0).
  for (int trial = 0; trial < 100; ++trial) {
    const Transform xf =
        trial == 0 ? Transform{} : test::random_transform(rng, trial % 2 ? 1.0e4f : 10.0f);
    const float tol = trial % 2 ? 4e-3f : 1e-5f;
    const OverlapPolygon o = intersect(a, xf, b, xf);
    ASSERT_EQ(o.count, 4);
    EXPECT_NEAR(o.area, 1.0f, tol);
    EXPECT_VEC2_NEAR(o.centroid, transform_point(xf, {1.75f, 0.0f}), tol);
    EXPECT_GT(signed_area(result_vertices(o)), 0.0f);  // counter-clockwise
  }
}

TEST(Intersect, RandomPairsMatchBruteForceOverlap) {
  std::mt19937 rng(32);
  int overlapping = 0, empty = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    // Far out, the brute force gets the same float inputs shifted exactly to the origin.
    const bool far_out = trial % 4 == 0;
    const Vec2 far = far_out ? Vec2{-1.0e4f, 1.0e4f} : Vec2{0.0f, 0.0f};
    const Polygon a = test::random_polygon(rng, 3 + trial % 10, uniform(rng, 0.5f, 2.0f));
    const Polygon b = test::random_polygon(rng, 3 + trial % 9, uniform(rng, 0.5f, 2.0f));
    const Transform xa{far + test::random_point(rng, 1.5f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const Transform xb{far + test::random_point(rng, 1.5f),
                       Rot2::from_angle(uniform(rng, -3.2f, 3.2f))};
    const OverlapPolygon o = intersect(a, xa, b, xb);
    const std::vector<Vec2> wa = test::world_vertices(a, {xa.p - far, xa.q});
    const std::vector<Vec2> wb = test::world_vertices(b, {xb.p - far, xb.q});
    const float tol = far_out ? 4e-3f : 1e-4f;
    const std::vector<Vec2> truth = brute_overlap(wa, wb, tol);
    Vec2 truth_centroid{0.0f, 0.0f};
    const float truth_area = truth.empty() ? 0.0f : test::shoelace_area(truth, &truth_centroid);
    EXPECT_NEAR(o.area, truth_area, 10.0f * tol);
    if (truth_area > 100.0f * tol) {
      ASSERT_GE(o.count, 3);
      EXPECT_VEC2_NEAR(o.centroid - far, truth_centroid, 10.0f * tol);
      // Every result vertex lies on the truth's boundary, and vice versa.
      std::vector<Vec2> ours = result_vertices(o);
      for (Vec2& v : ours) v -= far;
      for (Vec2 v : ours) EXPECT_LE(test::brute_distance(truth, v).boundary, tol);
      for (Vec2 v : truth) EXPECT_LE(test::brute_distance(ours, v).boundary, tol);
      EXPECT_NEAR(test::shoelace_area(ours), o.area, 10.0f * tol);
    }
    if (o.count == 0) {
      EXPECT_EQ(o.area, 0.0f);
      EXPECT_EQ(o.centroid, Vec2(0.0f, 0.0f));
    }
    // Disjoint per the separating axis test: empty.
    if (test::sat_separation(wa, wb) > tol) EXPECT_EQ(o.count, 0);
    (o.count > 0 ? overlapping : empty)++;
  }
  EXPECT_GT(overlapping, 300);
  EXPECT_GT(empty, 300);
}

TEST(Intersect, OverlapAreaAgreesWithMonteCarlo) {
  // An independent sanity check of the area: the fraction of uniform samples in both.
  std::mt19937 rng(33);
  for (int trial = 0; trial < 10; ++trial) {
    const Polygon a = test::random_polygon(rng, 6, 1.5f);
    const Polygon b = test::random_polygon(rng, 5, 1.5f);
    const Transform xa = Transform::from({0.0f, 0.0f}, uniform(rng, -3.0f, 3.0f));
    const Transform xb = Transform::from(test::random_point(rng, 0.5f), uniform(rng, -3.0f, 3.0f));
    const OverlapPolygon o = intersect(a, xa, b, xb);
    const std::vector<Vec2> wa = test::world_vertices(a, xa), wb = test::world_vertices(b, xb);
    constexpr int kSamples = 200000;
    int in_both = 0;
    for (int k = 0; k < kSamples; ++k) {
      const Vec2 p = test::random_point(rng, 2.0f);
      if (inside_convex(wa, p) && inside_convex(wb, p)) ++in_both;
    }
    const float mc_area = 16.0f * static_cast<float>(in_both) / kSamples;
    // Standard error of the estimate is about 16 * sqrt(p (1 - p) / N) < 0.02.
    EXPECT_NEAR(o.area, mc_area, 0.08f);
  }
}

// Touching along an edge or at a corner, and apart: empty, under random rigid motions. Far out
// the placement itself rounds by ~1e-3, so "touching" boxes may truly overlap by a sliver that
// thin: there the overlap must be empty or a sliver within that rounding.
TEST(Intersect, TouchingAndDisjointAreEmpty) {
  std::mt19937 rng(34);
  const Polygon a = make_box({1.0f, 1.0f});
  for (int trial = 0; trial < 100; ++trial) {
    const bool far = trial % 2 == 1;
    const Transform xf =
        trial == 0 ? Transform{} : test::random_transform(rng, far ? 1.0e4f : 10.0f);
    auto placed = [&](Vec2 offset) { return Transform{transform_point(xf, offset), xf.q}; };
    // Sliver allowed: placement rounding (2e-3 far, 2e-6 near) times the edge length 2.
    const float sliver = far ? 4e-3f : 0.0f;
    SCOPED_TRACE(trial);
    EXPECT_LE(intersect(a, xf, a, placed({2.0f, 0.5f})).area, sliver) << "edge contact";
    EXPECT_LE(intersect(a, xf, a, placed({2.0f, 2.0f})).area, sliver) << "corner contact";
    EXPECT_LE(intersect(a, xf, a, placed({0.0f, 2.0f})).area, sliver) << "edge contact, full";
    EXPECT_EQ(intersect(a, xf, a, placed({2.01f, 0.0f})).count, 0) << "apart";
    if (!far) {
      EXPECT_EQ(intersect(a, xf, a, placed({2.0f, 0.5f})).count, 0) << "edge contact";
      EXPECT_EQ(intersect(a, xf, a, placed({2.0f, 2.0f})).count, 0) << "corner contact";
    }
  }
}

// One inside the other: the overlap is the inner polygon itself.
TEST(Intersect, ContainedPolygonIsTheOverlap) {
  std::mt19937 rng(35);
  for (int trial = 0; trial < 100; ++trial) {
    const bool far = trial % 2 == 0;
    // Clipping the outer box by the inner polygon's edges rebuilds the inner vertices as
    // crossings of lines, which loses a few ulps of the box's size (6) on shallow crossings.
    const float tol = far ? 4e-3f : 1e-4f;
    const Polygon outer = make_box({3.0f, 3.0f});
    const Polygon inner = test::random_polygon(rng, 3 + trial % 12, 1.0f);
    const Transform xo = test::random_transform(rng, far ? 1.0e4f : 10.0f);
    const Transform xi{transform_point(xo, test::random_point(rng, 1.5f)),
                       Rot2::from_angle(uniform(rng, -3.0f, 3.0f))};
    for (int order = 0; order < 2; ++order) {
      const OverlapPolygon o =
          order == 0 ? intersect(outer, xo, inner, xi) : intersect(inner, xi, outer, xo);
      ASSERT_EQ(o.count, inner.count);
      EXPECT_NEAR(o.area, signed_area(std::span<const Vec2>(inner.vertices.data(), inner.count)),
                  tol);
      EXPECT_VEC2_NEAR(o.centroid, transform_point(xi, inner.centroid), tol);
      for (int i = 0; i < inner.count; ++i) {
        float best = INFINITY;
        for (int k = 0; k < o.count; ++k)
          best = std::min(best, distance(o.vertices[k], transform_point(xi, inner.vertices[i])));
        EXPECT_LE(best, tol);
      }
    }
  }
}

TEST(Intersect, RejectsRoundedPolygons) {
  const Polygon sharp = make_box({1.0f, 1.0f});
  const Polygon rounded = make_box({1.0f, 1.0f}, 0.1f);
  EXPECT_THROW((void)intersect(rounded, Transform{}, sharp, Transform{}), InvalidInput);
  try {
    (void)intersect(sharp, Transform{}, rounded, Transform{});
    FAIL() << "rounded polygon b accepted";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("polygon b radius"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace collide
