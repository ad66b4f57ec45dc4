// A game's frame with World3D: a height-field floor, a ramp mesh up to a platform, a crate and
// a fast ball; a player capsule walks up the ramp with move_character, and a mouse pick finds
// what is under the cursor.

#include <collide/world/character.hpp>
#include <collide/world/world3d.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

int main() {
  using namespace collide;
  World3D world(WorldOptions3{.gravity = {0.0f, -9.81f, 0.0f}});

  // The floor: 21 x 21 samples 1 unit apart, gently rolling (user id 1).
  std::vector<float> heights;
  for (int j = 0; j < 21; ++j) {
    for (int i = 0; i < 21; ++i) heights.push_back(0.1f * std::sin(0.5f * static_cast<float>(i)) * std::cos(0.4f * static_cast<float>(j)));
  }
  world.add_static({.shapes = {std::make_shared<const HeightField>(make_height_field(21, 21, heights, Vec2(1.0f), Vec3(-10.0f, 0.0f, -10.0f)))},
                    .user_id = 1});
  // A 25 degree ramp along +x up to a platform (one mesh and a box, user id 2).
  const float top = 4.0f * std::tan(25.0f * 3.14159265f / 180.0f);
  const std::vector<Vec3> ramp{{0, 0.2f, -1}, {0, 0.2f, 1}, {4, top, 1}, {4, top, -1}};
  const std::vector<glm::uvec3> faces{{0, 1, 2}, {0, 2, 3}};
  world.add_static({.shapes = {std::make_shared<const TriangleMesh>(make_triangle_mesh(ramp, faces))}, .user_id = 2});
  world.add_static({.shapes = {make_box({1.5f, 0.5f * top, 1.0f})}, .transform = Transform3{{5.5f, 0.5f * top, 0.0f}}, .user_id = 2});

  const BodyId crate = world.add_body({.shapes = {make_box({0.3f, 0.3f, 0.3f})}, .transform = Transform3{{-3.0f, 2.0f, 2.0f}},
                                       .user_id = 10});
  world.add_body({.shapes = {make_sphere({0.0f, 0.0f, 0.0f}, 0.1f)}, .transform = Transform3{{-8.0f, 1.0f, -3.0f}},
                  .velocity = {300.0f, 0.0f, 40.0f}, .user_id = 11, .bullet = true});  // 50 sizes a frame: CCD

  // The player: a capsule 1.8 tall, walking along +x at 2 units per second.
  const Shape3D player = make_capsule({0.0f, -0.5f, 0.0f}, {0.0f, 0.5f, 0.0f}, 0.4f);
  Transform3 player_at{{-2.0f, 1.0f, 0.0f}};
  Vec3 velocity{2.0f, 0.0f, 0.0f};
  const CharacterSettings3 settings{.step_height = 0.3f, .filter = QueryFilter{.bodies = false}};
  const float dt = 1.0f / 60.0f;
  CharacterMove3 m;  // the last move, handed to the next one (which then casts less; a fresh one is not used)
  for (int frame = 1; frame <= 240; ++frame) {
    world.step(dt);
    velocity.y -= 9.81f * dt;
    m = move_character(world, player, player_at, velocity * dt, settings, &m);
    player_at = m.transform;
    if (m.grounded) velocity.y = 0.0f;
    if (frame % 60 == 0) {
      std::printf("frame %3d: player at (%.2f, %.2f, %.2f) %s\n", frame, static_cast<double>(player_at.p.x),
                  static_cast<double>(player_at.p.y), static_cast<double>(player_at.p.z),
                  m.grounded ? (m.ground_user_id == 2 ? "on the ramp" : "on the floor") : "in the air");
    }
  }
  // The world's response is kinematic: bodies bounce, so the crate is still hopping.
  const WorldCastHit3 ground = world.ground_check(crate, {0.0f, -0.05f, 0.0f});
  std::printf("crate at height %.2f, %s\n", static_cast<double>(world.transform(crate).p.y),
              ground.hit ? "on the floor" : "in the air");
  // A mouse pick: the ray from the camera through a pixel.
  const auto pick = world.raycast(Ray3{{-2.0f, 6.0f, 8.0f}, {4.0f, -8.0f, -10.0f}});
  if (pick) std::printf("picked %s %u at (%.2f, %.2f, %.2f)\n", pick->collider.is_static ? "static" : "body", pick->collider.index,
                        static_cast<double>(pick->hit.point.x), static_cast<double>(pick->hit.point.y),
                        static_cast<double>(pick->hit.point.z));
  std::printf("tunnelled: %lld\n", static_cast<long long>(world.total_stats().tunnelled));
  return world.total_stats().tunnelled == 0 ? 0 : 1;
}
