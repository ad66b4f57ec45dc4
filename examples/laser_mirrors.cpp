// The lesson's laser and mirrors: cast a ray, reflect it about the hit normal, repeat.

#include <collide/ccd/raycast.hpp>

#include <array>
#include <cstdio>

int main() {
  using namespace collide;
  struct Mirror {
    Shape2D shape;
    Transform at;
  };
  const std::array<Mirror, 3> mirrors = {{
      {make_segment({0.0f, -2.0f}, {0.0f, 2.0f}), Transform::from({6.0f, 0.0f}, 0.3f)},
      {make_box({2.0f, 0.2f}), Transform::from({0.5f, -4.2f}, 0.3f)},
      {make_circle({0.0f, 0.0f}, 1.0f), Transform::from({-5.0f, -3.5f}, 0.0f)},
  }};

  Ray laser{{0.0f, 0.0f}, {40.0f, 0.0f}};  // from the origin, 40 units to the right
  for (int bounce = 0; bounce < 8; ++bounce) {
    RayHit best;
    best.fraction = 2.0f;
    int best_mirror = -1;
    for (int i = 0; i < static_cast<int>(mirrors.size()); ++i) {
      const RayHit hit = raycast(mirrors[i].shape, mirrors[i].at, laser);
      if (hit.hit && hit.fraction < best.fraction && hit.fraction > 0.0f) {
        best = hit;
        best_mirror = i;
      }
    }
    if (best_mirror < 0) {
      const Vec2 end = laser.at(1.0f);
      std::printf("laser leaves the scene at (%.2f, %.2f)\n", end.x, end.y);
      break;
    }
    std::printf("bounce %d off mirror %d at (%.2f, %.2f), normal (%.2f, %.2f)\n", bounce,
                best_mirror, best.point.x, best.point.y, best.normal.x, best.normal.y);
    laser = reflect(laser, best);
    laser.origin += 1e-4f * best.normal;  // step off the surface so the next cast starts outside
  }
  return 0;
}
