// contact() against Box2D 2.4 as oracle, on random pairs of every pair type Box2D has:
// polygon-polygon, circle-circle, polygon-circle, segment-circle, segment-polygon.
// Compared: touching or not, normal, depth and points (as sets). Pairs whose answer is
// ambiguous are skipped and counted: near-touching (either library may round either way) and
// near-ties between reference faces (Box2D and collide prefer A with different tolerances).

#include "narrow/contact_oracle.hpp"

namespace collide {
namespace {

using contact_test::box2d_contact;
using contact_test::OracleManifold;

constexpr float kTol = 2e-4f;        // geometry of size ~1 in float
constexpr float kAmbiguous = 1e-3f;  // |depth| below this: touching is a coin toss

/// Oracle points deeper than kAmbiguous, and ours: the sets to compare.
OracleManifold deep_points(const OracleManifold& o) {
  OracleManifold out{o.normal, {}};
  for (const auto& p : o.points) {
    if (p.depth > kAmbiguous) out.points.push_back(p);
  }
  return out;
}
Manifold deep_points(Manifold m) {
  Manifold out = m;
  out.count = 0;
  for (int i = 0; i < m.count; ++i) {
    if (m.points[i].depth > kAmbiguous) out.points[out.count++] = m.points[i];
  }
  return out;
}

struct Tally {
  int compared = 0, touching = 0, skipped = 0;
  void expect_coverage(int trials) const {
    EXPECT_GT(touching, compared * 3 / 10) << "too few touching pairs";
    EXPECT_GT(compared - touching, compared * 3 / 10) << "too few separated pairs";
    EXPECT_LT(skipped, trials / 5) << "too many ambiguous pairs skipped";
  }
};

/// Compare ours with the oracle for one pair whose true depth is `depth` (brute force).
void compare(const Manifold& ours, const OracleManifold& oracle, float depth, Tally& tally) {
  if (std::fabs(depth) < kAmbiguous) {
    ++tally.skipped;
    return;
  }
  ++tally.compared;
  ASSERT_EQ(ours.touching(), !oracle.points.empty()) << "true depth " << depth;
  if (!ours.touching()) return;
  ++tally.touching;
  EXPECT_VEC2_NEAR(ours.normal, oracle.normal, kTol);
  EXPECT_TRUE(contact_test::same_points(deep_points(ours), deep_points(oracle), kTol));
}

/// Largest separation of B along A's edge normals, brute force.
float max_axis_separation(const contact_test::WorldCore& a, const contact_test::WorldCore& b) {
  float best = -1e30f;
  for (Vec2 n : contact_test::core_axes(a))
    best = std::max(best, contact_test::core_separation_along(n, a, b));
  return best;
}

TEST(ContactBox2D, PolygonPolygon) {
  std::mt19937 rng(101);
  Tally tally;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    const Polygon a = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 1.0f);
    const Polygon b = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 0.7f);
    const Transform xa = test::random_transform(rng, 1.2f);
    const Transform xb = test::random_transform(rng, 1.2f);
    const auto ca = contact_test::world_core(a, xa), cb = contact_test::world_core(b, xb);
    const float sep_a = max_axis_separation(ca, cb), sep_b = max_axis_separation(cb, ca);
    if (std::fabs(sep_a - sep_b) < 0.01f) {  // reference face is a near-tie
      ++tally.skipped;
      continue;
    }
    SCOPED_TRACE(t);
    compare(contact(a, xa, b, xb), box2d_contact(a, xa, b, xb), contact_test::true_depth(ca, cb),
            tally);
  }
  tally.expect_coverage(trials);
}

TEST(ContactBox2D, CircleCircle) {
  std::mt19937 rng(102);
  Tally tally;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    const Circle a = make_circle(test::random_point(rng, 0.3f), test::uniform(rng, 0.0f, 1.0f));
    const Circle b = make_circle(test::random_point(rng, 0.3f), test::uniform(rng, 0.1f, 1.0f));
    const Transform xa = test::random_transform(rng, 1.2f);
    const Transform xb = test::random_transform(rng, 1.2f);
    SCOPED_TRACE(t);
    compare(
        contact(a, xa, b, xb), box2d_contact(a, xa, b, xb),
        contact_test::true_depth(contact_test::world_core(a, xa), contact_test::world_core(b, xb)),
        tally);
  }
  tally.expect_coverage(trials);
}

TEST(ContactBox2D, PolygonCircleBothOrders) {
  std::mt19937 rng(103);
  Tally tally;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    const Polygon a = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 1.0f);
    const Circle b = make_circle(test::random_point(rng, 0.3f), test::uniform(rng, 0.05f, 0.8f));
    const Transform xa = test::random_transform(rng, 1.2f);
    const Transform xb = test::random_transform(rng, 1.2f);
    SCOPED_TRACE(t);
    const Manifold ab = contact(a, xa, b, xb);
    compare(
        ab, box2d_contact(a, xa, b, xb),
        contact_test::true_depth(contact_test::world_core(a, xa), contact_test::world_core(b, xb)),
        tally);
    // Circle first: the table serves it as reversed(polygon, circle).
    const Manifold ba = contact(b, xb, a, xa);
    ASSERT_EQ(ba.count, ab.count);
    if (ab.count > 0) {
      EXPECT_VEC2_NEAR(ba.normal, -ab.normal, 0.0f);
      EXPECT_EQ(ba.points[0].id, (ContactId{ab.points[0].id.index_b, ab.points[0].id.index_a,
                                            ab.points[0].id.type_b, ab.points[0].id.type_a}));
    }
  }
  tally.expect_coverage(trials);
}

TEST(ContactBox2D, SegmentCircle) {
  std::mt19937 rng(104);
  Tally tally;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    const Segment a = make_segment(test::random_point(rng, 1.0f), test::random_point(rng, 1.0f));
    const Circle b = make_circle(test::random_point(rng, 0.3f), test::uniform(rng, 0.1f, 0.8f));
    const Transform xa = test::random_transform(rng, 0.5f);
    const Transform xb = test::random_transform(rng, 0.5f);
    SCOPED_TRACE(t);
    compare(
        contact(a, xa, b, xb), box2d_contact(a, xa, b, xb),
        contact_test::true_depth(contact_test::world_core(a, xa), contact_test::world_core(b, xb)),
        tally);
  }
  tally.expect_coverage(trials);
}

TEST(ContactBox2D, SegmentPolygon) {
  std::mt19937 rng(105);
  Tally tally;
  const int trials = 3000;
  for (int t = 0; t < trials; ++t) {
    const Segment a = make_segment(test::random_point(rng, 1.0f), test::random_point(rng, 1.0f));
    const Polygon b = test::random_polygon(rng, 3 + static_cast<int>(rng() % 6), 0.7f);
    const Transform xa = test::random_transform(rng, 0.6f);
    const Transform xb = test::random_transform(rng, 0.6f);
    const auto ca = contact_test::world_core(a, xa), cb = contact_test::world_core(b, xb);
    // Box2D keeps the edge's axis unless the polygon's is better by 2% + 0.001 (hysteresis);
    // skip pairs where that choice and ours could differ.
    const float sep_edge = max_axis_separation(ca, cb), sep_poly = max_axis_separation(cb, ca);
    if (std::fabs(sep_edge - sep_poly) < 0.03f * std::fabs(sep_edge) + 0.01f) {
      ++tally.skipped;
      continue;
    }
    SCOPED_TRACE(t);
    compare(contact(a, xa, b, xb), box2d_contact(a, xa, b, xb), contact_test::true_depth(ca, cb),
            tally);
  }
  tally.expect_coverage(trials);
}

}  // namespace
}  // namespace collide
