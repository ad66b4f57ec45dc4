// The lesson's signed distance field: bake a level's solid once into a grid, then ask "is this
// point inside?" with one memory access, how far and which way out, and bounce a batch of
// particles off it. A 2D level of three pieces: a floor, a wall and a round rock.

#include <collide/sdf/distance_field.hpp>

#include <array>
#include <cstdio>
#include <span>
#include <vector>

int main() {
  using namespace collide;
  const std::array<PlacedShape, 3> level = {{
      {make_box({10.0f, 0.5f}), Transform::from({0.0f, -0.5f}, 0.0f)},  // floor, top at y = 0
      {make_box({0.5f, 3.0f}), Transform::from({6.0f, 3.0f}, 0.0f)},    // wall
      {make_circle({0.0f, 0.0f}, 1.5f), Transform::from({-3.0f, 1.0f}, 0.0f)},
  }};
  FieldOptions options;
  options.voxel = 0.1f;  // world units between nodes
  const DistanceField field = make_distance_field(level, options);
  std::printf("field: %d x %d nodes, %zu bytes, built in %.2f ms\n", field.grid.dims.x, field.grid.dims.y,
              field.bytes(), 1e3 * field.stats.seconds);

  // The one-memory-access test, and the interpolated distance with its gradient (the way out).
  const Vec2 probe{-3.0f, 2.0f};
  Vec2 way_out;
  const float d = field.sample(probe, way_out);
  std::printf("(%.1f, %.1f): inside %s, distance %.3f, gradient (%.2f, %.2f)\n", probe.x, probe.y,
              field.is_inside(probe) ? "yes" : "no", d, way_out.x, way_out.y);

  // The closest surface point, from the stored closest points and by stepping down the gradient.
  const PointQuery stored = closest_point(field, {2.0f, 2.0f});
  const PointQuery stepped = closest_point_by_gradient(field, {2.0f, 2.0f});
  std::printf("closest to (2, 2): stored (%.3f, %.3f), by gradient (%.3f, %.3f)\n", stored.closest.x,
              stored.closest.y, stepped.closest.x, stepped.closest.y);

  // A laser by sphere tracing.
  const RayHit hit = raymarch(field, Ray{{-9.0f, 4.0f}, {20.0f, -4.0f}});
  if (hit.hit) std::printf("laser hits at (%.2f, %.2f), normal (%.2f, %.2f)\n", hit.point.x, hit.point.y, hit.normal.x, hit.normal.y);

  // Particles falling onto the level, bounced off the field once per step.
  Particles particles;
  for (int i = 0; i < 100; ++i) {
    particles.positions.push_back({-8.0f + 0.16f * static_cast<float>(i), 6.0f});
    particles.velocities.push_back({0.0f, 0.0f});
  }
  std::size_t bounced = 0;
  for (int step = 0; step < 120; ++step) {
    for (Vec2& v : particles.velocities) v.y -= 9.8f / 60.0f;  // gravity
    bounced += step_particles(field, particles, 1.0f / 60.0f, 0.3f).bounced;
  }
  // Many points at once: sample(field, points, out), the same values as one at a time (a dense
  // 3D field takes four points at a time in SIMD lanes).
  std::vector<float> depth(particles.positions.size());
  sample(field, std::span<const Vec2>(particles.positions), std::span<float>(depth));
  int resting_inside = 0;
  for (const float d : depth) resting_inside += d < -options.voxel ? 1 : 0;
  std::printf("particles: %zu bounces in 120 steps, %d of 100 deeper than a voxel inside at the end\n", bounced,
              resting_inside);
  return resting_inside == 0 ? 0 : 1;
}
