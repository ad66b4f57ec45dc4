// The narrow-phase questions a game asks of two shapes, one call each.
//   does it touch?         overlap
//   where and how deep?    contact (manifold: normal from A to B, 1-2 points, depth, feature ids)
//   how far?               distance (GJK; closest points)
//   which feature is near? closest_point (signed distance + Voronoi feature)

#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include <cstdio>

int main() {
  using namespace collide;
  const Polygon ground = make_box({5.0f, 0.5f});                  // 10 x 1, centred on its origin
  const Polygon crate = make_box({0.5f, 0.5f}, /*radius=*/0.05f);  // slightly rounded
  const Capsule player = make_capsule({0.0f, -0.5f}, {0.0f, 0.5f}, 0.3f);

  const Transform ground_at = Transform::from({0.0f, 0.0f}, 0.0f);
  const Transform crate_at = Transform::from({1.0f, 1.0f}, 0.2f);  // resting, tilted 0.2 rad
  const Transform player_at = Transform::from({-3.0f, 1.7f}, 0.0f);

  std::printf("crate overlaps ground: %s\n", overlap(ground, ground_at, crate, crate_at) ? "yes" : "no");

  const Manifold m = contact(ground, ground_at, crate, crate_at);
  std::printf("contact: %d point(s), normal (%.3f, %.3f)\n", m.count, m.normal.x, m.normal.y);
  for (int i = 0; i < m.count; ++i) {
    std::printf("  point (%.3f, %.3f) depth %.4f feature key %08x\n", m.points[i].point.x,
                m.points[i].point.y, m.points[i].depth, m.points[i].id.key());
  }

  SimplexCache cache;  // keep one per pair across frames to warm-start GJK
  const DistanceResult d = distance(player, player_at, ground, ground_at, &cache);
  std::printf("player is %.3f above the ground (closest points (%.2f, %.2f) and (%.2f, %.2f))\n",
              d.distance, d.point_a.x, d.point_a.y, d.point_b.x, d.point_b.y);

  const PointQuery q = closest_point(crate, crate_at, Vec2{3.0f, 3.0f});
  std::printf("mouse at (3, 3): %.3f from the crate, nearest feature %s %d\n", q.distance,
              q.feature.type == FeatureType::vertex ? "vertex" : "edge", q.feature.index);
  return 0;
}
