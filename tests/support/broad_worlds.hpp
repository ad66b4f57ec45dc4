#pragma once
// Test worlds for the broad phases: seeded random box sets in 2D and 3D, each aimed at a
// weakness of some structure (crowded cells, huge boxes, boxes touching exactly on cell
// boundaries, negative and far-from-origin coordinates), moving versions of them, and the
// brute-force pairs every structure is checked against.

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/brute_force.hpp>
#include <collide/core/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace collide::test {

template <int D>
using Boxes = std::vector<AabbN<D>>;

inline float uniform_f(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

template <int D>
VecN<D> random_vec(std::mt19937& rng, float lo, float hi) {
  VecN<D> v;
  for (int k = 0; k < D; ++k) v[k] = uniform_f(rng, lo, hi);
  return v;
}

/// The reference answer: every overlapping pair, i < j, sorted (BruteForceN).
template <int D>
PairList brute_pairs(std::span<const AabbN<D>> boxes) {
  BruteForceN<D> brute;
  brute.build(boxes);
  PairList pairs;
  brute.find_pairs(pairs);
  return pairs;
}

template <int D>
AabbN<D> box_at(const VecN<D>& center, const VecN<D>& half) {
  return {center - half, center + half};
}

/// n boxes with centres uniform in [offset - extent, offset + extent]^D, half sizes in [lo, hi].
template <int D>
Boxes<D> uniform_world(std::mt19937& rng, int n, float extent, float lo, float hi,
                       float offset = 0.0f) {
  Boxes<D> boxes;
  for (int i = 0; i < n; ++i) {
    boxes.push_back(box_at<D>(VecN<D>(offset) + random_vec<D>(rng, -extent, extent),
                              random_vec<D>(rng, lo, hi)));
  }
  return boxes;
}

/// n boxes in a few tight Gaussian clusters: many boxes per cell.
template <int D>
Boxes<D> clustered_world(std::mt19937& rng, int n, float extent) {
  std::vector<VecN<D>> centres;
  for (int c = 0; c < 5; ++c) centres.push_back(random_vec<D>(rng, -extent, extent));
  std::normal_distribution<float> spread(0.0f, extent * 0.03f);
  Boxes<D> boxes;
  for (int i = 0; i < n; ++i) {
    VecN<D> p = centres[rng() % centres.size()];
    for (int k = 0; k < D; ++k) p[k] += spread(rng);
    boxes.push_back(box_at<D>(p, random_vec<D>(rng, 0.05f, 0.5f)));
  }
  return boxes;
}

/// Mostly 0.1-unit boxes with some 100-unit boxes among them.
template <int D>
Boxes<D> mixed_size_world(std::mt19937& rng, int n, float extent) {
  Boxes<D> boxes;
  for (int i = 0; i < n; ++i) {
    const bool big = rng() % 20 == 0;
    const VecN<D> half = big ? random_vec<D>(rng, 20.0f, 50.0f) : random_vec<D>(rng, 0.05f, 0.1f);
    boxes.push_back(box_at<D>(random_vec<D>(rng, -extent, extent), half));
  }
  return boxes;
}

/// A uniform world plus a few boxes that cover most of it (ground planes, trigger volumes).
template <int D>
Boxes<D> huge_object_world(std::mt19937& rng, int n, float extent) {
  Boxes<D> boxes = uniform_world<D>(rng, n, extent, 0.2f, 1.0f);
  for (int i = 0; i < 4; ++i) {
    const int at = static_cast<int>(rng() % boxes.size());
    boxes[at] = box_at<D>(random_vec<D>(rng, -extent * 0.2f, extent * 0.2f),
                          random_vec<D>(rng, extent * 0.5f, extent));
  }
  return boxes;
}

/// Boxes with integer corners on a lattice of unit cells: neighbours share faces, edges and
/// corners exactly on cell boundaries (cell size 1), including points and repeated boxes.
template <int D>
Boxes<D> touching_world(std::mt19937& rng, int n, int extent) {
  Boxes<D> boxes;
  std::uniform_int_distribution<int> pos(-extent, extent);
  std::uniform_int_distribution<int> len(0, 2);
  for (int i = 0; i < n; ++i) {
    AabbN<D> b;
    for (int k = 0; k < D; ++k) {
      b.min[k] = static_cast<float>(pos(rng));
      b.max[k] = b.min[k] + static_cast<float>(len(rng));
    }
    boxes.push_back(b);
    if (rng() % 10 == 0) boxes.push_back(b);  // an exact duplicate
  }
  return boxes;
}

/// Moves every box by a random velocity in [-speed, speed]^D per frame (a random walk that
/// keeps its velocity; bounced back at the world edge, on every bounce_every-th step only).
template <int D>
struct MovingWorld {
  Boxes<D> boxes;
  std::vector<VecN<D>> velocity;
  float extent = 0.0f;
  float offset = 0.0f;
  int bounce_every = 1;
  int steps = 0;  // steps taken so far

  void step() {
    const bool may_bounce = steps++ % bounce_every == 0;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
      const VecN<D> c = boxes[i].center() + velocity[i];
      for (int k = 0; k < D && may_bounce; ++k) {
        if (c[k] > offset + extent || c[k] < offset - extent) velocity[i][k] = -velocity[i][k];
      }
      boxes[i].min += velocity[i];
      boxes[i].max += velocity[i];
    }
  }
};

template <int D>
MovingWorld<D> moving_world(std::mt19937& rng, Boxes<D> boxes, float extent, float speed,
                            float offset = 0.0f) {
  MovingWorld<D> w;
  w.boxes = std::move(boxes);
  w.extent = extent;
  w.offset = offset;
  for (std::size_t i = 0; i < w.boxes.size(); ++i) {
    w.velocity.push_back(random_vec<D>(rng, -speed, speed));
  }
  return w;
}

/// The named static worlds every structure must get exactly right (fixed seed per dimension).
template <int D>
std::vector<std::pair<std::string, Boxes<D>>> static_worlds() {
  std::mt19937 rng(1234 + D);
  std::vector<std::pair<std::string, Boxes<D>>> worlds;
  // 3D worlds are smaller so that pairs are about as frequent as in 2D.
  const float scale = D == 2 ? 1.0f : 0.4f;
  worlds.emplace_back("uniform", uniform_world<D>(rng, 600, 30.0f * scale, 0.1f, 1.5f));
  worlds.emplace_back("clustered", clustered_world<D>(rng, 500, 50.0f));
  worlds.emplace_back("mixed_size", mixed_size_world<D>(rng, 600, 200.0f));
  worlds.emplace_back("huge_object", huge_object_world<D>(rng, 500, 40.0f * scale));
  worlds.emplace_back("touching", touching_world<D>(rng, 500, D == 2 ? 20 : 8));
  worlds.emplace_back("negative", uniform_world<D>(rng, 500, 20.0f * scale, 0.1f, 1.0f, -1000.0f));
  worlds.emplace_back("far_1e4", uniform_world<D>(rng, 500, 30.0f * scale, 0.1f, 1.5f, 1.0e4f));
  worlds.emplace_back("far_1e6", uniform_world<D>(rng, 500, 300.0f * scale, 1.0f, 15.0f, 1.0e6f));
  // Points (zero-size boxes) on a small lattice: many exact duplicates.
  Boxes<D> points;
  std::uniform_int_distribution<int> lattice(-3, 3);
  for (int i = 0; i < 300; ++i) {
    VecN<D> p;
    for (int k = 0; k < D; ++k) p[k] = static_cast<float>(lattice(rng));
    points.push_back({p, p});
  }
  worlds.emplace_back("points", points);
  worlds.emplace_back("one_box", Boxes<D>{box_at<D>(VecN<D>(1.0f), VecN<D>(1.0f))});
  worlds.emplace_back("empty", Boxes<D>{});
  return worlds;
}

/// Moving versions of the named worlds, n boxes each (fixed seed per dimension): clusters that
/// drift together and slowly loosen, 0.1- and 100-unit boxes, huge boxes among small ones,
/// boxes touching exactly on cell boundaries, negative coordinates, coordinates near 1e6. The
/// touching world moves by half units (exact in float) and bounces on even steps only, so
/// after every second step all its corners are on the integer lattice again.
template <int D>
std::vector<std::pair<std::string, MovingWorld<D>>> moving_worlds(int n) {
  std::mt19937 rng(4321 + D);
  const float scale = D == 2 ? 1.0f : 0.4f;  // 3D worlds smaller: pairs about as frequent
  std::vector<std::pair<std::string, MovingWorld<D>>> worlds;
  {
    Boxes<D> boxes = clustered_world<D>(rng, n, 50.0f);
    MovingWorld<D> w = moving_world<D>(rng, std::move(boxes), 50.0f, 0.02f);
    const VecN<D> drift = random_vec<D>(rng, -0.4f, 0.4f);
    for (VecN<D>& v : w.velocity) v += drift;
    worlds.emplace_back("clustered", std::move(w));
  }
  {
    const float extent = D == 2 ? 200.0f : 80.0f;
    Boxes<D> boxes = mixed_size_world<D>(rng, n, extent);
    worlds.emplace_back("mixed_size", moving_world<D>(rng, std::move(boxes), extent, 1.0f));
  }
  {
    Boxes<D> boxes = huge_object_world<D>(rng, n, 40.0f * scale);
    worlds.emplace_back("huge_object", moving_world<D>(rng, std::move(boxes), 40.0f * scale, 0.3f));
  }
  {
    const int extent = D == 2 ? 15 : 6;
    MovingWorld<D> w = moving_world<D>(rng, touching_world<D>(rng, n, extent),
                                       static_cast<float>(extent), 0.0f);
    std::uniform_int_distribution<int> step(-1, 1);
    for (VecN<D>& v : w.velocity) {
      for (int k = 0; k < D; ++k) v[k] = 0.5f * static_cast<float>(step(rng));
    }
    w.bounce_every = 2;
    worlds.emplace_back("touching", std::move(w));
  }
  {
    Boxes<D> boxes = uniform_world<D>(rng, n, 20.0f * scale, 0.1f, 1.0f, -1000.0f);
    worlds.emplace_back("negative",
                        moving_world<D>(rng, std::move(boxes), 20.0f * scale, 0.2f, -1000.0f));
  }
  {
    Boxes<D> boxes = uniform_world<D>(rng, n, 300.0f * scale, 1.0f, 15.0f, 1.0e6f);
    worlds.emplace_back("far_1e6",
                        moving_world<D>(rng, std::move(boxes), 300.0f * scale, 2.0f, 1.0e6f));
  }
  return worlds;
}

/// A box spoiled in a way every broad phase must reject, naming the box: a NaN, an infinity
/// or min > max, at the first, a middle or the last box of n, min or max corner.
template <int D>
struct BadBox {
  int index;
  const char* what;
  void (*spoil)(AabbN<D>& box);
};

template <int D>
std::vector<BadBox<D>> bad_boxes(int n) {
  constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
  constexpr float kInf = std::numeric_limits<float>::infinity();
  return {
      {0, "NaN min.x", [](AabbN<D>& b) { b.min[0] = kNaN; }},
      {3, "NaN max, last axis", [](AabbN<D>& b) { b.max[D - 1] = kNaN; }},
      {n / 8, "+inf max.y", [](AabbN<D>& b) { b.max[1] = kInf; }},
      {n * 3 / 5, "-inf min.x", [](AabbN<D>& b) { b.min[0] = -kInf; }},
      {n - 1, "+inf min, last axis", [](AabbN<D>& b) { b.min[D - 1] = kInf; }},
      {n * 2 / 5, "min.y > max.y", [](AabbN<D>& b) { b.min[1] = b.max[1] + 0.5f; }},
      {n - 1, "max.x < min.x", [](AabbN<D>& b) { b.max[0] = b.min[0] - 0.5f; }},
  };
}

/// Runs `call` (a build or update given the spoiled boxes) and expects an InvalidInput whose
/// message names box `bad.index` ("box 17: ...").
template <int D, class Call>
void expect_rejects_naming_the_box(const BadBox<D>& bad, Call&& call) {
  try {
    call();
    ADD_FAILURE() << bad.what << " accepted";
  } catch (const InvalidInput& e) {
    const std::string want = "box " + std::to_string(bad.index) + ":";
    EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << bad.what << ": " << e.what();
  }
}

}  // namespace collide::test
