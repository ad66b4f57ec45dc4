// Many small round things against a level's tiles, one batched call a step: particles (circles)
// fall onto a row of box tiles and bounce. A game's broad phase says which particle may touch
// which tile (here: the tiles under the particle's box); the batched `contact` answers all those
// pairs at once, four at a time in SIMD lanes, each manifold the same as `contact` on the pair.

#include <collide/narrow/contact.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

int main() {
  using namespace collide;
  // The level: a row of 1 x 1 tiles, their tops at y = 0, from x = 0 to 32, and a wall at each
  // end (a particle that hits a tile's corner is knocked sideways, and nothing here stops it
  // sliding). Solid j covers x in [j - 1, j].
  constexpr int kTiles = 32;
  const Polygon tile = make_box({0.5f, 0.5f});
  const Polygon wall = make_box({0.5f, 2.0f});
  struct Solid {
    const Polygon* shape;
    Transform at;
  };
  std::vector<Solid> solids{{&wall, Transform::from({-0.5f, 1.0f}, 0.0f)}};
  for (int t = 0; t < kTiles; ++t) solids.push_back({&tile, Transform::from({float(t) + 0.5f, -0.5f}, 0.0f)});
  solids.push_back({&wall, Transform::from({float(kTiles) + 0.5f, 1.0f}, 0.0f)});

  struct Particle {
    Circle shape;
    Vec2 position;
    Vec2 velocity;
  };
  std::vector<Particle> particles;
  for (int i = 0; i < 1000; ++i) {
    const float x = 0.5f + float(i % 250) * 0.124f, y = 1.0f + float(i / 250) * 0.5f;
    particles.push_back({make_circle({0.0f, 0.0f}, 0.05f), {x, y}, {0.0f, 0.0f}});
  }

  std::vector<PolygonCirclePair> pairs;  // reused every step: no allocation once grown
  std::vector<int> owner;                // which particle each pair belongs to
  std::vector<Manifold> manifolds;
  // Four steps a frame (4 s of play): a particle moves less than its radius in one step, so its
  // centre never passes below a tile's top, where the tiles' sides would push it sideways.
  const float dt = 1.0f / 240.0f;
  int touching = 0;
  for (int step = 0; step < 4 * 240; ++step) {
    pairs.clear();
    owner.clear();
    for (int i = 0; i < int(particles.size()); ++i) {
      Particle& p = particles[std::size_t(i)];
      p.velocity.y -= 9.81f * dt;
      p.position += dt * p.velocity;
      // Broad phase: the solids under the particle's box.
      const int first = std::clamp(int(std::floor(p.position.x - p.shape.radius)) + 1, 0, kTiles + 1);
      const int last = std::clamp(int(std::floor(p.position.x + p.shape.radius)) + 1, 0, kTiles + 1);
      for (int j = first; j <= last; ++j) {
        const Solid& s = solids[std::size_t(j)];
        pairs.push_back({s.shape, s.at, &p.shape, Transform::from(p.position, 0.0f)});
        owner.push_back(i);
      }
    }
    manifolds.resize(pairs.size());
    contact(pairs, manifolds);  // narrow phase: every pair at once
    touching = 0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const Manifold& m = manifolds[k];
      if (m.count == 0) continue;
      ++touching;
      Particle& p = particles[std::size_t(owner[k])];
      p.position += m.points[0].depth * m.normal;  // normal from the solid to the particle
      const float approach = dot(p.velocity, m.normal);
      if (approach < 0.0f) p.velocity -= 1.5f * approach * m.normal;  // bounce, restitution 0.5
    }
  }
  float lowest = particles.front().position.y;
  for (const Particle& p : particles) lowest = std::min(lowest, p.position.y);
  std::printf("%zu particles on %d tiles: %d touching in the last step, lowest centre at y = %.3f\n",
              particles.size(), kTiles, touching, lowest);
  return 0;
}
