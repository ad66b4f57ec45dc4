// GJK distance and overlap: collide vs Box2D v3 (b2ShapeDistance; /box2d_v3, the first rival,
// box2d_v3/queries.cpp) and Box2D 2.4 (b2Distance, b2TestOverlap; /box2d) on the same
// pre-generated inputs. Each benchmark iteration runs a batch of 1024 random pairs, mostly
// separated (4-16% overlap, depending on the shapes), except BM_Overlap_*Touching (B 0.2..0.9
// from A: mostly overlapping); names pair up as BM_X/collide, BM_X/box2d_v3 and BM_X/box2d.
// BM_Distance_*/collide is the public `distance` on the shapes (for polygons: last frame's
// pair checked, then the pair at the support points, then separating axes, GJK last);
// BM_Distance_*/gjk is GJK alone on prepared proxies. Both return world space; the v3 row
// converts b2ShapeDistance's frame-A points and normal to world space, as a game must.
// v3 has no boolean overlap test: its row is b2ShapeDistance < 10 FLT_EPSILON. v3 proxies hold
// at most 8 points, so the 64-gon rows have no v3 entry. Warm runs carry each pair's simplex
// cache from one frame to the next while B orbits A slowly. BM_Overlap_*/sat_alternative is the
// textbook scalar separating axis test (not in the library): collide's overlap runs the test
// four edges at a time in registers for polygons of up to 8 vertices, and GJK for larger ones
// or when the axes leave a gap undecided.
//
// Run: ./build/release/bench/bench_narrow_distance --benchmark_repetitions=5 \
//        --benchmark_report_aggregates_only=true

#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>

#include <benchmark/benchmark.h>

#include "case_order.hpp"

#include "box2d_v3/queries.hpp"
#include "support/random.hpp"
#include <box2d/b2_distance.h>
#include <box2d/box2d.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using namespace collide;
using namespace collide::test;  // uniform, random points, rotations and transforms

constexpr int kPairs = 1024;
/// Frames of slow motion for the warm-started runs: each iteration advances one frame.
constexpr int kFrames = 64;

Polygon random_polygon(std::mt19937& rng, int n, float size) {
  std::vector<Vec2> pts;
  const float start = uniform(rng, 0.0f, 6.2831853f);
  for (int i = 0; i < n; ++i) {
    const float angle = start + 6.2831853f * (float(i) + uniform(rng, -0.3f, 0.3f)) / float(n);
    const float r = size * uniform(rng, 0.7f, 1.0f);
    pts.push_back({r * std::cos(angle), r * std::sin(angle)});
  }
  return make_polygon(pts);
}

b2Transform to_b2(const Transform& xf) {
  b2Transform t;
  t.p.Set(xf.p.x, xf.p.y);
  t.q.c = xf.q.c;
  t.q.s = xf.q.s;
  return t;
}

/// A shape in both libraries: ours, and its Box2D vertex array (proxy and polygon shape).
struct Shape {
  Polygon polygon;
  Circle circle;
  bool is_circle = false;
  std::vector<b2Vec2> b2_vertices;
  float radius = 0.0f;
  b2PolygonShape b2_polygon;
};

struct Pair {
  Shape a;
  Shape b;
  Transform xa;
  std::vector<Transform> xb;  ///< one per frame (slow motion); frame 0 for cold runs
  b2Transform xa_b2;
  std::vector<b2Transform> xb_b2;  ///< xb converted once, so Box2D pays no conversion
};

/// A batch of pairs: A a polygon with `na` vertices (or a circle if na == 1), B likewise.
std::vector<Pair> make_pairs(int na, int nb, unsigned seed, float min_dist = 1.0f,
                             float max_dist = 3.0f) {
  std::mt19937 rng(seed);
  auto make_shape = [&](int n) {
    Shape s;
    if (n == 1) {
      s.is_circle = true;
      s.circle = make_circle({0.0f, 0.0f}, uniform(rng, 0.3f, 0.6f));
      s.radius = s.circle.radius;
      s.b2_vertices = {b2Vec2(0.0f, 0.0f)};
    } else {
      s.polygon = random_polygon(rng, n, uniform(rng, 0.5f, 1.0f));
      for (int i = 0; i < s.polygon.count; ++i) {
        s.b2_vertices.emplace_back(s.polygon.vertices[i].x, s.polygon.vertices[i].y);
      }
      if (s.polygon.count <= b2_maxPolygonVertices) {
        s.b2_polygon.Set(s.b2_vertices.data(), s.polygon.count);
        s.b2_polygon.m_radius = 0.0f;  // same geometry as ours (no skin)
      }
    }
    return s;
  };
  std::vector<Pair> pairs(kPairs);
  for (Pair& p : pairs) {
    p.a = make_shape(na);
    p.b = make_shape(nb);
    p.xa = Transform::from({uniform(rng, -50.0f, 50.0f), uniform(rng, -50.0f, 50.0f)},
                           uniform(rng, -3.1f, 3.1f));
    // B min_dist .. max_dist from A (1..3 by default: mostly separated, some overlapping).
    const float dist = uniform(rng, min_dist, max_dist);
    const float dir = uniform(rng, -3.1f, 3.1f);
    const float rot = uniform(rng, -3.1f, 3.1f);
    for (int f = 0; f < kFrames; ++f) {
      const float t = 0.005f * float(f);  // a slowly orbiting, slowly turning B
      p.xb.push_back(Transform::from(
          p.xa.p + dist * Vec2{std::cos(dir + t), std::sin(dir + t)}, rot + 2.0f * t));
      p.xb_b2.push_back(to_b2(p.xb.back()));
    }
    p.xa_b2 = to_b2(p.xa);
  }
  return pairs;
}

ConvexProxy proxy(const Shape& s) {
  return s.is_circle ? ConvexProxy(s.circle) : ConvexProxy(s.polygon);
}

b2DistanceProxy b2_proxy(const Shape& s) {
  b2DistanceProxy p;
  p.Set(s.b2_vertices.data(), static_cast<int32>(s.b2_vertices.size()), s.radius);
  return p;
}

/// The public call a game makes on the shapes (`distance`: for polygons, warm pairs and
/// separating axes before GJK), or GJK alone on prepared proxies (`gjk_only`: the /gjk rows).
DistanceResult query(const Pair& p, const Transform& xb, SimplexCache* cache, bool gjk_only) {
  if (gjk_only) return gjk_distance(proxy(p.a), p.xa, proxy(p.b), xb, cache);
  if (p.a.is_circle) return distance(p.a.circle, p.xa, p.b.polygon, xb, cache);
  return distance(p.a.polygon, p.xa, p.b.polygon, xb, cache);
}

/// `shuffled` (cold rows only): the batch's pairs drawn in CaseOrder (case_order.hpp), which no
/// branch predictor learns, instead of replayed in the same order every batch.
void distance_collide(benchmark::State& state, const std::vector<Pair>* pairs, bool warm,
                      bool gjk_only, bool shuffled) {
  std::vector<SimplexCache> caches(pairs->size());
  int frame = 0;
  int iterations = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    float sum = 0.0f;
    iterations = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      const Pair& p = (*pairs)[i];
      const DistanceResult r =
          query(p, p.xb[warm ? frame : 0], warm ? &caches[i] : nullptr, gjk_only);
      sum += r.distance;
      iterations += r.iterations;
    }
    benchmark::DoNotOptimize(sum);
    frame = (frame + 1) % kFrames;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
  state.counters["iters"] = static_cast<double>(iterations) / static_cast<double>(pairs->size());
}

void distance_box2d(benchmark::State& state, const std::vector<Pair>* pairs, bool warm,
                    bool shuffled) {
  std::vector<b2DistanceInput> inputs(pairs->size());
  for (size_t i = 0; i < pairs->size(); ++i) {
    inputs[i].proxyA = b2_proxy((*pairs)[i].a);
    inputs[i].proxyB = b2_proxy((*pairs)[i].b);
    inputs[i].transformA = (*pairs)[i].xa_b2;
    inputs[i].useRadii = true;
  }
  std::vector<b2SimplexCache> caches(pairs->size());
  for (b2SimplexCache& c : caches) c.count = 0;
  int frame = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    float sum = 0.0f;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      b2DistanceInput& in = inputs[i];
      in.transformB = (*pairs)[i].xb_b2[warm ? frame : 0];
      b2SimplexCache cold;
      cold.count = 0;
      b2DistanceOutput out;
      b2Distance(&out, warm ? &caches[i] : &cold, &in);
      sum += out.distance;
    }
    benchmark::DoNotOptimize(sum);
    frame = (frame + 1) % kFrames;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
}

void overlap_collide(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  int hits = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    hits = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const Pair& p = (*pairs)[shuffled ? order.next() : k];
      hits += overlap(p.a.polygon, p.xa, p.b.polygon, p.xb[0]) ? 1 : 0;
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
  state.counters["overlap"] = static_cast<double>(hits) / static_cast<double>(pairs->size());
}

void overlap_box2d(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  int hits = 0;
  collide::bench::CaseOrder order(static_cast<std::uint32_t>(pairs->size() - 1));
  for (auto _ : state) {
    hits = 0;
    for (size_t k = 0; k < pairs->size(); ++k) {
      const Pair& p = (*pairs)[shuffled ? order.next() : k];
      hits += b2TestOverlap(&p.a.b2_polygon, 0, &p.b.b2_polygon, 0, p.xa_b2, p.xb_b2[0]) ? 1 : 0;
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
  state.counters["overlap"] = static_cast<double>(hits) / static_cast<double>(pairs->size());
}

/// The textbook scalar separating axis test over both polygons' edge normals (Ericson 5.2.1),
/// with B moved into A's frame once and an early exit on the first separating axis: what the
/// library's register version (src/narrow/sat_lanes.hpp) is measured against.
bool overlap_sat(const Polygon& a, const Transform& xa, const Polygon& b, const Transform& xb) {
  const Transform b_in_a = inv_mul(xa, xb);
  std::array<Vec2, kMaxPolygonVertices> vb;
  for (int j = 0; j < b.count; ++j) vb[j] = transform_point(b_in_a, b.vertices[j]);
  for (int i = 0; i < a.count; ++i) {
    float lowest = dot(a.normals[i], vb[0] - a.vertices[i]);
    for (int j = 1; j < b.count; ++j) {
      lowest = std::min(lowest, dot(a.normals[i], vb[j] - a.vertices[i]));
    }
    if (lowest > 0.0f) return false;
  }
  for (int j = 0; j < b.count; ++j) {
    const Vec2 n = rotate(b_in_a.q, b.normals[j]);
    float lowest = dot(n, a.vertices[0] - vb[j]);
    for (int i = 1; i < a.count; ++i) lowest = std::min(lowest, dot(n, a.vertices[i] - vb[j]));
    if (lowest > 0.0f) return false;
  }
  return true;
}

void overlap_sat_alternative(benchmark::State& state, const std::vector<Pair>* pairs) {
  for (auto _ : state) {
    int hits = 0;
    for (const Pair& p : *pairs) hits += overlap_sat(p.a.polygon, p.xa, p.b.polygon, p.xb[0]) ? 1 : 0;
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs->size()));
}

std::vector<collide::bench::box2d_v3::DistancePair> v3_pairs(const std::vector<Pair>& pairs) {
  std::vector<collide::bench::box2d_v3::DistancePair> out;
  for (const Pair& p : pairs) out.push_back({proxy(p.a), proxy(p.b), p.xa, p.xb});
  return out;
}

void distance_box2d_v3(benchmark::State& state, const std::vector<Pair>* pairs, bool warm,
                       bool shuffled) {
  collide::bench::box2d_v3::distance(state, v3_pairs(*pairs), warm, shuffled);
}

void overlap_box2d_v3(benchmark::State& state, const std::vector<Pair>* pairs, bool shuffled) {
  collide::bench::box2d_v3::overlap(state, v3_pairs(*pairs), shuffled);
}

bool fits_v3(const std::vector<Pair>& pairs) {
  for (const Pair& p : pairs) {
    if (proxy(p.a).count() > collide::bench::box2d_v3::kMaxProxyPoints ||
        proxy(p.b).count() > collide::bench::box2d_v3::kMaxProxyPoints) {
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  static const std::vector<Pair> poly4 = make_pairs(4, 4, 1);
  static const std::vector<Pair> poly8 = make_pairs(8, 8, 2);
  static const std::vector<Pair> circle_poly = make_pairs(1, 8, 3);
  static const std::vector<Pair> poly64 = make_pairs(64, 8, 4);
  static const std::vector<Pair> poly4_touching = make_pairs(4, 4, 5, 0.2f, 0.9f);
  static const std::vector<Pair> poly8_touching = make_pairs(8, 8, 6, 0.2f, 0.9f);
  struct Case {
    const char* name;
    const std::vector<Pair>* pairs;
    bool warm;
  };
  const Case cases[] = {
      {"BM_Distance_Poly4", &poly4, false},       {"BM_Distance_Poly8", &poly8, false},
      {"BM_Distance_CirclePoly8", &circle_poly, false}, {"BM_Distance_Poly64Poly8", &poly64, false},
      {"BM_DistanceWarm_Poly8", &poly8, true},    {"BM_DistanceWarm_Poly64Poly8", &poly64, true},
  };
  for (const Case& c : cases) {
    // Cold rows also with the pairs shuffled (the name's _shuffled), side by side.
    for (const bool shuffled : {false, true}) {
      if (shuffled && c.warm) continue;
      const std::string name = std::string(c.name) + (shuffled ? "_shuffled" : "");
      benchmark::RegisterBenchmark((name + "/collide").c_str(), distance_collide, c.pairs, c.warm,
                                   false, shuffled);
      benchmark::RegisterBenchmark((name + "/gjk").c_str(), distance_collide, c.pairs, c.warm,
                                   true, shuffled);
      if (fits_v3(*c.pairs)) {
        benchmark::RegisterBenchmark((name + "/box2d_v3").c_str(), distance_box2d_v3, c.pairs,
                                     c.warm, shuffled);
      }
      benchmark::RegisterBenchmark((name + "/box2d").c_str(), distance_box2d, c.pairs, c.warm,
                                   shuffled);
    }
  }
  const std::pair<const char*, const std::vector<Pair>*> overlaps[] = {
      {"BM_Overlap_Poly4", &poly4},
      {"BM_Overlap_Poly8", &poly8},
      {"BM_Overlap_Poly4Touching", &poly4_touching},
      {"BM_Overlap_Poly8Touching", &poly8_touching}};
  for (const auto& [base, pairs] : overlaps) {
    for (const bool shuffled : {false, true}) {
      const std::string name = std::string(base) + (shuffled ? "_shuffled" : "");
      benchmark::RegisterBenchmark((name + "/collide").c_str(), overlap_collide, pairs, shuffled);
      benchmark::RegisterBenchmark((name + "/box2d_v3").c_str(), overlap_box2d_v3, pairs,
                                   shuffled);
      benchmark::RegisterBenchmark((name + "/box2d").c_str(), overlap_box2d, pairs, shuffled);
    }
  }
  benchmark::RegisterBenchmark("BM_Overlap_Poly4/sat_alternative", overlap_sat_alternative, &poly4);
  benchmark::RegisterBenchmark("BM_Overlap_Poly8/sat_alternative", overlap_sat_alternative, &poly8);
  benchmark::RegisterBenchmark("BM_Overlap_Poly4Touching/sat_alternative", overlap_sat_alternative, &poly4_touching);
  benchmark::RegisterBenchmark("BM_Overlap_Poly8Touching/sat_alternative", overlap_sat_alternative, &poly8_touching);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  collide::bench::box2d_v3::add_context();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
