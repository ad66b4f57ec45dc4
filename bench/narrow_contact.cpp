// Contact manifolds, collide vs Box2D v3 (the first rival) and Box2D 2.4, on the same
// pre-generated pairs in the same run. Each iteration computes the manifolds of all kPairs pairs
// (mixed overlapping and separated; the "overlap" counter is the touching fraction) with
// world-space points on every side: collide's `contact` returns them; Box2D 2.4 needs b2Collide*
// followed by b2WorldManifold; v3 takes the relative transform and answers in A's frame
// (box2d_v3/queries.cpp). Rows read side by side: BM_Contact_Poly4/collide, /box2d_v3, /box2d.
// Capsules: v3 only (2.4 has none).

#include <benchmark/benchmark.h>

#include "case_order.hpp"

#include "box2d_v3/queries.hpp"
#include "support/random.hpp"
#include <box2d/box2d.h>

#include <cmath>
#include <collide/narrow/contact.hpp>
#include <collide/shape/capsule.hpp>
#include <numbers>
#include <random>
#include <vector>

namespace {

using namespace collide;
namespace box2d_v3 = collide::bench::box2d_v3;
using namespace collide::test;  // uniform, random points, rotations and transforms

constexpr int kPairs = 1024;

/// A convex polygon with exactly n vertices on an ellipse of size about 0.5.
std::vector<Vec2> random_convex(std::mt19937& rng, int n) {
  std::vector<Vec2> pts;
  const float rx = uniform(rng, 0.3f, 0.6f), ry = uniform(rng, 0.3f, 0.6f);
  for (int i = 0; i < n; ++i) {
    const float angle =
        2.0f * kPi * (static_cast<float>(i) + uniform(rng, -0.25f, 0.25f)) / static_cast<float>(n);
    pts.push_back({rx * std::cos(angle), ry * std::sin(angle)});
  }
  return pts;
}

b2Transform to_b2(const Transform& xf) {
  b2Rot q;
  q.s = xf.q.s;
  q.c = xf.q.c;
  return b2Transform(b2Vec2(xf.p.x, xf.p.y), q);
}

b2PolygonShape to_b2(const std::vector<Vec2>& pts) {
  std::vector<b2Vec2> v;
  for (Vec2 p : pts) v.emplace_back(p.x, p.y);
  b2PolygonShape shape;
  shape.Set(v.data(), static_cast<int32>(v.size()));
  shape.m_radius = 0.0f;  // exact geometry, as collide's
  return shape;
}

struct PolygonPairs {
  std::vector<Polygon> a, b;
  std::vector<b2PolygonShape> a2, b2;
  std::vector<Transform> xa, xb;
  std::vector<b2Transform> xa2, xb2;
};

const PolygonPairs& polygon_pairs(int n) {
  static PolygonPairs cache[2];
  PolygonPairs& p = cache[n == 4 ? 0 : 1];
  if (!p.a.empty()) return p;
  std::mt19937 rng(n);
  for (int i = 0; i < kPairs; ++i) {
    const auto va = random_convex(rng, n), vb = random_convex(rng, n);
    p.a.push_back(make_convex_polygon(va));
    p.b.push_back(make_convex_polygon(vb));
    p.a2.push_back(to_b2(va));
    p.b2.push_back(to_b2(vb));
    p.xa.push_back(random_transform(rng, 0.75f));
    p.xb.push_back(random_transform(rng, 0.75f));
    p.xa2.push_back(to_b2(p.xa.back()));
    p.xb2.push_back(to_b2(p.xb.back()));
  }
  return p;
}

struct CirclePairs {
  std::vector<Polygon> a;
  std::vector<b2PolygonShape> a2;
  std::vector<Circle> b;
  std::vector<b2CircleShape> b2;
  std::vector<Transform> xa, xb;
  std::vector<b2Transform> xa2, xb2;
};

const CirclePairs& circle_pairs() {
  static CirclePairs p;
  if (!p.a.empty()) return p;
  std::mt19937 rng(17);
  for (int i = 0; i < kPairs; ++i) {
    const auto va = random_convex(rng, 6);
    p.a.push_back(make_convex_polygon(va));
    p.a2.push_back(to_b2(va));
    const float r = uniform(rng, 0.1f, 0.5f);
    p.b.push_back(make_circle({0.0f, 0.0f}, r));
    b2CircleShape c;
    c.m_radius = r;
    p.b2.push_back(c);
    p.xa.push_back(random_transform(rng, 0.65f));
    p.xb.push_back(random_transform(rng, 0.65f));
    p.xa2.push_back(to_b2(p.xa.back()));
    p.xb2.push_back(to_b2(p.xb.back()));
  }
  return p;
}

struct CapsulePairs {
  std::vector<Polygon> a;
  std::vector<Capsule> b;
  std::vector<Transform> xa, xb;
};

const CapsulePairs& capsule_pairs() {
  static CapsulePairs p;
  if (!p.a.empty()) return p;
  std::mt19937 rng(23);
  for (int i = 0; i < kPairs; ++i) {
    p.a.push_back(make_convex_polygon(random_convex(rng, 6)));
    const float half = uniform(rng, 0.1f, 0.4f);
    p.b.push_back(make_capsule({-half, 0.0f}, {half, 0.0f}, uniform(rng, 0.05f, 0.25f)));
    p.xa.push_back(random_transform(rng, 0.65f));
    p.xb.push_back(random_transform(rng, 0.65f));
  }
  return p;
}

// state.range(0): how many of the pairs to cycle through. 1024 distinct pairs spread collide's
// 192-byte polygons over 384 KiB (a world's worth of shapes, out of L1); 64 stay in L1 and show
// the arithmetic alone.
// `shuffled`: the pairs in CaseOrder instead (case_order.hpp), which no branch predictor learns;
// replayed in the same order every batch, they are learnt (the *_shuffled rows, stop 49).
template <class Pairs>
void ours(benchmark::State& state, const Pairs& p, bool shuffled) {
  const int pairs = static_cast<int>(state.range(0));
  int touching = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs - 1));
  for (auto _ : state) {
    touching = 0;
    for (int k = 0; k < pairs; ++k) {
      const int i = shuffled ? static_cast<int>(order.next()) : k;
      const Manifold m = contact(p.a[i], p.xa[i], p.b[i], p.xb[i]);
      benchmark::DoNotOptimize(m);
      touching += m.count > 0 ? 1 : 0;
    }
  }
  state.SetItemsProcessed(state.iterations() * pairs);
  state.counters["overlap"] = static_cast<double>(touching) / pairs;
}

/// The batched polygon-circle `contact` on the same pairs in the same order: each iteration
/// gathers them into the batch's pair list (pointers and transforms, in the order the other
/// rows visit them: timed, as a game's narrow phase would build it from its broad phase's
/// pairs), then makes one call for all.
void ours_batch(benchmark::State& state, const CirclePairs& p, bool shuffled) {
  const int pairs = static_cast<int>(state.range(0));
  std::vector<PolygonCirclePair> batch(static_cast<std::size_t>(pairs));
  std::vector<Manifold> manifolds(static_cast<std::size_t>(pairs));
  int touching = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs - 1));
  for (auto _ : state) {
    for (int k = 0; k < pairs; ++k) {
      const auto i = static_cast<std::size_t>(shuffled ? static_cast<int>(order.next()) : k);
      batch[static_cast<std::size_t>(k)] = {&p.a[i], p.xa[i], &p.b[i], p.xb[i]};
    }
    contact(batch, manifolds);
    benchmark::DoNotOptimize(manifolds.data());
    touching = 0;
    for (const Manifold& m : manifolds) touching += m.count > 0 ? 1 : 0;
  }
  state.SetItemsProcessed(state.iterations() * pairs);
  state.counters["overlap"] = static_cast<double>(touching) / pairs;
}

template <class Pairs, class Collide>
void box2d(benchmark::State& state, const Pairs& p, Collide collide, bool shuffled = false) {
  const int pairs = static_cast<int>(state.range(0));
  int touching = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs - 1));
  for (auto _ : state) {
    touching = 0;
    for (int k = 0; k < pairs; ++k) {
      const int i = shuffled ? static_cast<int>(order.next()) : k;
      b2Manifold m;
      collide(&m, &p.a2[i], p.xa2[i], &p.b2[i], p.xb2[i]);
      b2WorldManifold wm;
      wm.Initialize(&m, p.xa2[i], p.a2[i].m_radius, p.xb2[i], p.b2[i].m_radius);
      benchmark::DoNotOptimize(wm);
      touching += m.pointCount > 0 ? 1 : 0;
    }
  }
  state.SetItemsProcessed(state.iterations() * pairs);
  state.counters["overlap"] = static_cast<double>(touching) / pairs;
}

template <class Pairs>
void v3(benchmark::State& s, const Pairs& p, bool shuffled) {
  using B = typename decltype(p.b)::value_type;
  if constexpr (std::is_same_v<B, Polygon>) {
    box2d_v3::contact_polygons(s, p.a, p.xa, p.b, p.xb, shuffled);
  } else if constexpr (std::is_same_v<B, Circle>) {
    box2d_v3::contact_polygon_circle(s, p.a, p.xa, p.b, p.xb, shuffled);
  } else {
    box2d_v3::contact_polygon_capsule(s, p.a, p.xa, p.b, p.xb, shuffled);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::box2d_v3::add_context();
  const auto add = [](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark(name.c_str(), fn)->Arg(kPairs)->Arg(64);
  };
  for (const bool shuffled : {false, true}) {
    const std::string order = shuffled ? "_shuffled" : "";
    add("BM_Contact_Poly4" + order + "/collide",
        [=](benchmark::State& s) { ours(s, polygon_pairs(4), shuffled); });
    add("BM_Contact_Poly4" + order + "/box2d_v3",
        [=](benchmark::State& s) { v3(s, polygon_pairs(4), shuffled); });
    add("BM_Contact_Poly4" + order + "/box2d",
        [=](benchmark::State& s) { box2d(s, polygon_pairs(4), b2CollidePolygons, shuffled); });
    add("BM_Contact_Poly8" + order + "/collide",
        [=](benchmark::State& s) { ours(s, polygon_pairs(8), shuffled); });
    add("BM_Contact_Poly8" + order + "/box2d_v3",
        [=](benchmark::State& s) { v3(s, polygon_pairs(8), shuffled); });
    add("BM_Contact_Poly8" + order + "/box2d",
        [=](benchmark::State& s) { box2d(s, polygon_pairs(8), b2CollidePolygons, shuffled); });
    add("BM_Contact_CirclePoly" + order + "/collide",
        [=](benchmark::State& s) { ours(s, circle_pairs(), shuffled); });
    add("BM_Contact_CirclePoly" + order + "/box2d_v3",
        [=](benchmark::State& s) { v3(s, circle_pairs(), shuffled); });
    add("BM_Contact_CirclePoly" + order + "/box2d", [=](benchmark::State& s) {
      box2d(s, circle_pairs(), b2CollidePolygonAndCircle, shuffled);
    });
    add("BM_Contact_CirclePoly_batch" + order + "/collide",
        [=](benchmark::State& s) { ours_batch(s, circle_pairs(), shuffled); });
    add("BM_Contact_CapsulePoly" + order + "/collide",
        [=](benchmark::State& s) { ours(s, capsule_pairs(), shuffled); });
    add("BM_Contact_CapsulePoly" + order + "/box2d_v3",
        [=](benchmark::State& s) { v3(s, capsule_pairs(), shuffled); });
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
