// A game's frame with World2D: a room with a concave obstacle, a ball, a crate and a bullet;
// step, read the contact events, cast a laser, check whether the crate stands on the floor.

#include <collide/world/world2d.hpp>

#include <cstdio>
#include <vector>

int main() {
  using namespace collide;
  World2D world(WorldOptions{.bounds = Aabb{{-10.0f, 0.0f}, {10.0f, 10.0f}}});

  // The room: a floor and two walls (user ids 1..3), and an L-shaped ledge (concave: several
  // convex pieces).
  world.add_static({.shapes = {make_box({11.0f, 0.5f})}, .transform = Transform::from({0.0f, -0.5f}, 0.0f), .user_id = 1});
  world.add_static({.shapes = {make_box({0.5f, 6.0f})}, .transform = Transform::from({-10.5f, 5.0f}, 0.0f), .user_id = 2});
  world.add_static({.shapes = {make_segment({0.0f, 0.0f}, {0.0f, 10.0f})}, .transform = Transform::from({10.0f, 0.0f}, 0.0f), .user_id = 3});
  const std::vector<Vec2> ledge = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3}, {0, 3}};
  world.add_static({.shapes = convex_pieces(ledge, "ledge"), .transform = Transform::from({2.0f, 3.0f}, 0.0f), .user_id = 4});

  const BodyId crate = world.add_body({.shapes = {make_box({0.5f, 0.5f})}, .transform = Transform::from({-5.0f, 0.5f}, 0.0f),
                                       .velocity = {1.0f, 0.0f}, .user_id = 10});
  world.add_body({.shapes = {make_circle({0.0f, 0.0f}, 0.3f)}, .transform = Transform::from({-2.0f, 6.0f}, 0.0f),
                  .velocity = {3.0f, -4.0f}, .user_id = 11});
  // A bullet: 0.1 across, 600 units per second (100 times its size per frame). Continuous
  // collision stops it at the thin right wall.
  world.add_body({.shapes = {make_circle({0.0f, 0.0f}, 0.05f)}, .transform = Transform::from({-9.0f, 8.0f}, 0.0f),
                  .velocity = {600.0f, 0.0f}, .user_id = 12, .bullet = true});

  for (int frame = 1; frame <= 120; ++frame) {
    world.step(1.0f / 60.0f);
    for (const ContactEvent& e : world.events()) {
      if (e.type == ContactEventType::persist) continue;
      std::printf("frame %3d: %-5s body %llu - %s %llu\n", frame, to_string(e.type),
                  static_cast<unsigned long long>(e.user_a), e.b.is_static ? "static" : "body",
                  static_cast<unsigned long long>(e.user_b));
    }
  }
  const WorldCastHit ground = world.ground_check(crate, {0.0f, -0.05f});
  std::printf("crate at (%.2f, %.2f) %s\n", static_cast<double>(world.transform(crate).p.x),
              static_cast<double>(world.transform(crate).p.y),
              ground.hit ? "stands on something" : "is in the air");
  const LaserPath laser = world.cast_laser(Ray{{-9.0f, 2.0f}, {60.0f, 25.0f}}, 6);
  std::printf("laser: %d segments, %d hits\n", laser.segments, laser.hit_count);
  std::printf("tunnelled: %lld\n", static_cast<long long>(world.total_stats().tunnelled));
  return world.total_stats().tunnelled == 0 ? 0 : 1;
}
