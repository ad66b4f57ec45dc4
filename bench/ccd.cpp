// Continuous collision: collide vs Box2D v3 (/box2d_v3, the first rival) and Box2D 2.4 (/box2d)
// on the same pre-generated inputs, each benchmark iteration a batch of 1024 moving pairs (about
// half of them meet during the step).
//  - BM_ShapeCast/<pair>/collide (shape_cast on the shapes: sharp polygon pairs take the
//    separating-axis cast into A - B, the rest GJK's ray cast) vs b2ShapeCast; /gjk (GJK's ray
//    cast alone, gjk_shape_cast on prepared proxies), and /explicit (build A - B, cast into
//    it) for polygon pairs. v3 casts in A's frame: the conversion of B's pose and the motion
//    is timed on its side (box2d_v3/queries.cpp).
//  - BM_ToiTranslation/<pair>: time_of_impact without rotation vs b2TimeOfImpact: /collide on
//    the shapes (translating sharp polygons take the separating-axis cast moved by the target),
//    /gjk on prepared proxies (the GJK ray cast for every pair).
//  - BM_ToiRotation/<pair>: time_of_impact with turns up to pi/2 per step (Box2D's per-step
//    limit) vs b2TimeOfImpact; collide at Box2D's target (b2_linearSlop, 2.4's and v3's
//    linear slop alike: 0.005) and at its own default (1e-3 of the smaller size: tighter, more
//    accurate).
//  - BM_ShapeCast_shuffled, BM_ToiTranslation_shuffled, BM_ToiRotation_shuffled (stop 50): the
//    same calls with the pairs drawn in CaseOrder's pseudo-random order (case_order.hpp) on
//    every side, as many per iteration: replayed in order, a batch's branch outcomes are learnt
//    by the branch predictor (the manifold rows showed it).
// Counters (computed once, outside the timing): hits, and sep_at_t, the mean distance between
// the shapes at the reported time of hits (by Box2D's b2Distance): the accuracy.
//
// Run: ./build/release/bench/bench_ccd --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/time_of_impact.hpp>

#include <benchmark/benchmark.h>

#include "case_order.hpp"

#include "box2d_v3/queries.hpp"
#include "support/random.hpp"
#include <box2d/b2_distance.h>
#include <box2d/b2_time_of_impact.h>
#include <box2d/box2d.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using namespace collide::test;  // uniform, random points, rotations and transforms

constexpr int kPairs = 1024;

/// A shape in both libraries: ours, and Box2D's proxy on the same exact core points.
struct Shape {
  Shape2D shape;
  std::vector<b2Vec2> b2_points;
  float radius = 0.0f;
};

Shape make_shape(std::mt19937& rng, int kind) {
  Shape s;
  if (kind == 0) {
    s.shape = make_circle({0.0f, 0.0f}, uniform(rng, 0.3f, 0.6f));
  } else if (kind == 1) {
    const float h = uniform(rng, 0.3f, 0.7f);
    s.shape = make_capsule({-h, 0.0f}, {h, 0.0f}, uniform(rng, 0.1f, 0.3f));
  } else {
    std::vector<Vec2> pts;
    const int n = kind;
    const float size = uniform(rng, 0.5f, 1.0f);
    const float start = uniform(rng, 0.0f, 2.0f * kPi);
    for (int i = 0; i < n; ++i) {
      const float angle = start + 2.0f * kPi * (float(i) + uniform(rng, -0.3f, 0.3f)) / float(n);
      const float r = size * uniform(rng, 0.7f, 1.0f);
      pts.push_back({r * std::cos(angle), r * std::sin(angle)});
    }
    s.shape = make_polygon(pts);
  }
  const ConvexProxy p(s.shape);
  for (int i = 0; i < p.count(); ++i) s.b2_points.emplace_back(p.point(i).x, p.point(i).y);
  s.radius = p.radius();
  return s;
}

b2DistanceProxy b2_proxy(const Shape& s) {
  b2DistanceProxy p;
  p.Set(s.b2_points.data(), static_cast<int32>(s.b2_points.size()), s.radius);
  return p;
}

b2Transform to_b2(const Transform& xf) {
  b2Transform t;
  t.p.Set(xf.p.x, xf.p.y);
  t.q.c = xf.q.c;
  t.q.s = xf.q.s;
  return t;
}

b2Sweep to_b2(const Sweep& s) {
  b2Sweep w;
  w.localCenter.Set(s.local_center.x, s.local_center.y);
  w.c0.Set(s.c0.x, s.c0.y);
  w.c.Set(s.c1.x, s.c1.y);
  w.a0 = s.a0;
  w.a = s.a1;
  w.alpha0 = 0.0f;
  return w;
}

struct Pair {
  Shape a;
  Shape b;
  Sweep sa;
  Sweep sb;
  [[nodiscard]] Transform xa() const { return sa.at(0.0f); }
  [[nodiscard]] Transform xb() const { return sb.at(0.0f); }
  [[nodiscard]] Vec2 va() const { return sa.c1 - sa.c0; }
  [[nodiscard]] Vec2 vb() const { return sb.c1 - sb.c0; }
};

/// A batch: A of kind `ka`, B of kind `kb` (0 circle, 1 capsule, n >= 3 an n-gon), B 2..5
/// units away, A fired at it at 2..10 units per step (half aimed, half random), B drifting;
/// each turning by up to `max_turn` radians over the step.
std::vector<Pair> make_pairs(int ka, int kb, float max_turn, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Pair> pairs(kPairs);
  for (Pair& p : pairs) {
    p.a = make_shape(rng, ka);
    p.b = make_shape(rng, kb);
    const Vec2 ca{uniform(rng, -50.0f, 50.0f), uniform(rng, -50.0f, 50.0f)};
    const float dir = uniform(rng, -kPi, kPi);
    const Vec2 cb = ca + uniform(rng, 2.0f, 5.0f) * Vec2{std::cos(dir), std::sin(dir)};
    const float aim = dir + uniform(rng, -0.6f, 0.6f);
    const Vec2 va = uniform(rng, 2.0f, 10.0f) * Vec2{std::cos(aim), std::sin(aim)};
    const Vec2 vb{uniform(rng, -1.0f, 1.0f), uniform(rng, -1.0f, 1.0f)};
    const float a0 = uniform(rng, -kPi, kPi);
    const float b0 = uniform(rng, -kPi, kPi);
    p.sa = {{0.0f, 0.0f}, ca, ca + va, a0, a0 + uniform(rng, -max_turn, max_turn)};
    p.sb = {{0.0f, 0.0f}, cb, cb + vb, b0, b0 + uniform(rng, -max_turn, max_turn)};
  }
  return pairs;
}

/// Distance between the pair at time t, by Box2D (the same judge for both libraries).
float separation_at(const Pair& p, float t) {
  b2DistanceInput in;
  in.proxyA = b2_proxy(p.a);
  in.proxyB = b2_proxy(p.b);
  in.transformA = to_b2(p.sa.at(t));
  in.transformB = to_b2(p.sb.at(t));
  in.useRadii = true;
  b2SimplexCache cache;
  cache.count = 0;
  b2DistanceOutput out;
  b2Distance(&out, &cache, &in);
  return out.distance;
}

void report(benchmark::State& state, const std::vector<Pair>& pairs,
            const std::vector<float>& hit_times) {
  double sep = 0.0;
  int hits = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    if (hit_times[i] < 0.0f) continue;
    ++hits;
    sep += separation_at(pairs[i], hit_times[i]);
  }
  state.counters["hits"] = hits;
  state.counters["sep_at_t"] = hits > 0 ? sep / hits : 0.0;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs.size()));
}

// ---- shape cast -------------------------------------------------------------------------------

std::vector<collide::bench::box2d_v3::MovingPair> moving_pairs(const std::vector<Pair>& pairs) {
  std::vector<collide::bench::box2d_v3::MovingPair> out;
  for (const Pair& p : pairs) {
    out.push_back({ConvexProxy(p.a.shape), ConvexProxy(p.b.shape), p.xa(), p.xb(), p.va(), p.vb(),
                   p.sa, p.sb});
  }
  return out;
}

/// The public call on the shapes as a game holds them (validation, the variant's dispatch, and
/// for sharp polygons of up to 8 vertices the separating-axis cast into A - B).
void cast_collide(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  const auto inputs = moving_pairs(*pairs);  // the poses and motions, prepared once
  std::vector<float> times(pairs->size(), -1.0f);
  double iterations = 0.0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    int iters = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      const Pair& p = (*pairs)[i];
      const collide::bench::box2d_v3::MovingPair& in = inputs[i];
      const ShapeCastResult r = shape_cast(p.a.shape, in.xa, in.va, p.b.shape, in.xb, in.vb);
      times[i] = r.status == QueryStatus::hit ? r.fraction : -1.0f;
      iters += r.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(times.data());
  }
  state.counters["iters"] = iterations / double(pairs->size());
  report(state, *pairs, times);
}

/// GJK's ray cast alone on proxies prepared once (as Box2D's inputs are).
void cast_gjk(benchmark::State& state, const std::vector<Pair>* pairs) {
  const auto inputs = moving_pairs(*pairs);
  std::vector<float> times(pairs->size(), -1.0f);
  double iterations = 0.0;
  for (auto _ : state) {
    int iters = 0;
    for (size_t i = 0; i < inputs.size(); ++i) {
      const collide::bench::box2d_v3::MovingPair& in = inputs[i];
      const ShapeCastResult r = gjk_shape_cast(in.a, in.xa, in.va, in.b, in.xb, in.vb);
      times[i] = r.status == QueryStatus::hit ? r.fraction : -1.0f;
      iters += r.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(times.data());
  }
  state.counters["iters"] = iterations / double(inputs.size());
  report(state, *pairs, times);
}

void cast_explicit(benchmark::State& state, const std::vector<Pair>* pairs) {
  std::vector<float> times(pairs->size(), -1.0f);
  for (auto _ : state) {
    for (size_t i = 0; i < pairs->size(); ++i) {
      const Pair& p = (*pairs)[i];
      const ShapeCastResult r =
          shape_cast_minkowski(std::get<Polygon>(p.a.shape), p.xa(), p.va(),
                               std::get<Polygon>(p.b.shape), p.xb(), p.vb());
      times[i] = r.status == QueryStatus::hit ? r.fraction : -1.0f;
    }
    benchmark::DoNotOptimize(times.data());
  }
  report(state, *pairs, times);
}

void cast_box2d(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  std::vector<b2ShapeCastInput> inputs(pairs->size());
  for (size_t i = 0; i < pairs->size(); ++i) {
    const Pair& p = (*pairs)[i];
    inputs[i].proxyA = b2_proxy(p.a);
    inputs[i].proxyB = b2_proxy(p.b);
    inputs[i].transformA = to_b2(p.xa());
    inputs[i].transformB = to_b2(p.xb());
    const Vec2 r = p.vb() - p.va();  // Box2D moves B only: the relative motion
    inputs[i].translationB.Set(r.x, r.y);
  }
  std::vector<float> times(pairs->size(), -1.0f);
  double iterations = 0.0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    int iters = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      b2ShapeCastOutput out;
      times[i] = b2ShapeCast(&out, &inputs[i]) ? out.lambda : -1.0f;
      iters += out.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(times.data());
  }
  state.counters["iters"] = iterations / double(pairs->size());
  report(state, *pairs, times);
}

void cast_box2d_v3(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  std::vector<float> times;
  collide::bench::box2d_v3::shape_cast(state, moving_pairs(*pairs), times, shuffled);
  report(state, *pairs, times);
}

void toi_box2d_v3(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  std::vector<float> times;
  collide::bench::box2d_v3::time_of_impact(state, moving_pairs(*pairs), times, shuffled);
  report(state, *pairs, times);
}

// ---- time of impact ---------------------------------------------------------------------------

/// time_of_impact as a game calls it, on the shapes (validation, the variant's dispatch, and for
/// translating sharp polygons of up to 8 vertices the separating-axis cast into A - B), or
/// (`on_proxies`) on proxies prepared once, the GJK path for every pair.
void toi_collide(benchmark::State& state, const std::vector<Pair>* pairs, bool box2d_target,
                 bool on_proxies, bool shuffled) {
  std::vector<ConvexProxy> pa;
  std::vector<ConvexProxy> pb;
  for (const Pair& p : *pairs) {
    pa.emplace_back(p.a.shape);
    pb.emplace_back(p.b.shape);
  }
  const float target = box2d_target ? b2_linearSlop : -1.0f;
  std::vector<float> times(pairs->size(), -1.0f);
  double iterations = 0.0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    int iters = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      const Pair& p = (*pairs)[i];
      const ToiResult r = on_proxies ? time_of_impact(pa[i], p.sa, pb[i], p.sb, target)
                                     : time_of_impact(p.a.shape, p.sa, p.b.shape, p.sb, target);
      times[i] = r.status == QueryStatus::hit ? r.fraction : -1.0f;
      iters += r.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(times.data());
  }
  state.counters["iters"] = iterations / double(pairs->size());
  report(state, *pairs, times);
}

void toi_box2d(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  std::vector<b2TOIInput> inputs(pairs->size());
  for (size_t i = 0; i < pairs->size(); ++i) {
    const Pair& p = (*pairs)[i];
    inputs[i].proxyA = b2_proxy(p.a);
    inputs[i].proxyB = b2_proxy(p.b);
    inputs[i].sweepA = to_b2(p.sa);
    inputs[i].sweepB = to_b2(p.sb);
    inputs[i].tMax = 1.0f;
  }
  std::vector<float> times(pairs->size(), -1.0f);
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      b2TOIOutput out;
      b2TimeOfImpact(&out, &inputs[i]);
      times[i] = out.state == b2TOIOutput::e_touching && out.t > 0.0f ? out.t : -1.0f;
    }
    benchmark::DoNotOptimize(times.data());
  }
  report(state, *pairs, times);
}

}  // namespace

int main(int argc, char** argv) {
  struct Case {
    const char* name;
    int ka;
    int kb;
  };
  const Case cases[] = {{"box_box", 4, 4},
                        {"poly8_poly8", 8, 8},
                        {"circle_poly8", 0, 8},
                        {"capsule_poly8", 1, 8}};
  static std::vector<std::vector<Pair>> translating;
  static std::vector<std::vector<Pair>> rotating;
  translating.reserve(4);
  rotating.reserve(4);
  unsigned seed = 1;
  for (const Case& c : cases) {
    translating.push_back(make_pairs(c.ka, c.kb, 0.0f, seed++));
    rotating.push_back(make_pairs(c.ka, c.kb, 0.5f * kPi, seed++));
  }
  for (size_t i = 0; i < 4; ++i) {
    const std::string n = cases[i].name;
    const std::vector<Pair>* tr = &translating[i];
    const std::vector<Pair>* rot = &rotating[i];
    const auto add = [](const std::string& name, auto fn, auto... args) {
      benchmark::RegisterBenchmark(name.c_str(), fn, args...);
    };
    for (const bool shuffled : {false, true}) {
      // shuffled: the pairs drawn in CaseOrder (case_order.hpp) on every side, as the manifold,
      // distance and ray cast rows; the /gjk and /explicit rows only replay.
      const std::string order = shuffled ? "_shuffled" : "";
      add("BM_ShapeCast" + order + "/" + n + "/collide", cast_collide, tr, shuffled);
      if (!shuffled) add("BM_ShapeCast/" + n + "/gjk", cast_gjk, tr);
      add("BM_ShapeCast" + order + "/" + n + "/box2d_v3", cast_box2d_v3, tr, shuffled);
      add("BM_ShapeCast" + order + "/" + n + "/box2d", cast_box2d, tr, shuffled);
      if (!shuffled && cases[i].ka >= 3 && cases[i].kb >= 3) {
        add("BM_ShapeCast/" + n + "/explicit", cast_explicit, tr);
      }
      add("BM_ToiTranslation" + order + "/" + n + "/collide", toi_collide, tr, true, false, shuffled);
      if (!shuffled) add("BM_ToiTranslation/" + n + "/gjk", toi_collide, tr, true, true, false);
      add("BM_ToiTranslation" + order + "/" + n + "/box2d_v3", toi_box2d_v3, tr, shuffled);
      add("BM_ToiTranslation" + order + "/" + n + "/box2d", toi_box2d, tr, shuffled);
      add("BM_ToiRotation" + order + "/" + n + "/collide_box2d_target", toi_collide, rot, true, false,
          shuffled);
      if (!shuffled) add("BM_ToiRotation/" + n + "/collide", toi_collide, rot, false, false, false);
      add("BM_ToiRotation" + order + "/" + n + "/box2d_v3", toi_box2d_v3, rot, shuffled);
      add("BM_ToiRotation" + order + "/" + n + "/box2d", toi_box2d, rot, shuffled);
    }
  }
  benchmark::Initialize(&argc, argv);
  collide::bench::box2d_v3::add_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
