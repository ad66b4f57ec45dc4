// Box2D v3's side of the 2D query benchmarks: see queries.hpp.
#include "queries.hpp"

#include "../case_order.hpp"
#include "../instruction_set.hpp"

#include <box2d/box2d.h>
#include <box2d/collision.h>

#include <algorithm>
#include <cfloat>
#include <vector>

namespace collide::bench::box2d_v3 {
namespace {

b2Vec2 to_v3(Vec2 v) { return {v.x, v.y}; }

b2Transform to_v3(const Transform& xf) { return {to_v3(xf.p), {xf.q.c, xf.q.s}}; }

b2Polygon to_v3(const Polygon& p) {
  std::vector<b2Vec2> points;
  for (int i = 0; i < p.count; ++i) points.push_back(to_v3(p.vertices[i]));
  const b2Hull hull = b2ComputeHull(points.data(), static_cast<int>(points.size()));
  return b2MakePolygon(&hull, p.radius);
}

b2Circle to_v3(const Circle& c) { return {to_v3(c.center), c.radius}; }

b2Capsule to_v3(const Capsule& c) { return {to_v3(c.a), to_v3(c.b), c.radius}; }

template <class A, class B>
struct Pairs {
  std::vector<A> a;
  std::vector<B> b;
  std::vector<b2Transform> xa, xb;
};

template <class ShapeA, class ShapeB>
auto convert(std::span<const ShapeA> a, std::span<const Transform> xa, std::span<const ShapeB> b,
             std::span<const Transform> xb) {
  Pairs<decltype(to_v3(a[0])), decltype(to_v3(b[0]))> out;
  for (const ShapeA& s : a) out.a.push_back(to_v3(s));
  for (const ShapeB& s : b) out.b.push_back(to_v3(s));
  for (const Transform& x : xa) out.xa.push_back(to_v3(x));
  for (const Transform& x : xb) out.xb.push_back(to_v3(x));
  return out;
}

/// The world-space manifold a game reads: normal and points rotated out of frame A.
struct WorldManifold {
  b2Vec2 normal;
  b2Vec2 points[2];
  float separations[2];
  int count;
};

template <class P, class Collide>
void run(benchmark::State& state, const P& p, Collide collide, bool shuffled) {
  const int pairs = static_cast<int>(state.range(0));
  int touching = 0;
  CaseOrder order(static_cast<std::uint32_t>(pairs - 1));
  for (auto _ : state) {
    touching = 0;
    for (int k = 0; k < pairs; ++k) {
      const int i = shuffled ? static_cast<int>(order.next()) : k;
      const b2Transform xa = p.xa[static_cast<size_t>(i)];
      const b2Transform rel = b2InvMulTransforms(xa, p.xb[static_cast<size_t>(i)]);
      const b2LocalManifold m =
          collide(&p.a[static_cast<size_t>(i)], &p.b[static_cast<size_t>(i)], rel);
      WorldManifold w;
      w.count = m.pointCount;
      w.normal = b2RotateVector(xa.q, m.normal);
      for (int k = 0; k < m.pointCount; ++k) {
        w.points[k] = b2TransformPoint(xa, m.points[k].point);
        w.separations[k] = m.points[k].separation;
      }
      benchmark::DoNotOptimize(w);
      touching += m.pointCount > 0 ? 1 : 0;
    }
  }
  state.SetItemsProcessed(state.iterations() * pairs);
  state.counters["overlap"] = static_cast<double>(touching) / pairs;
}

}  // namespace

void add_context() {
  add_instruction_sets("box2d v3", COLLIDE_BOX2D_V3_ISA);
  const b2Version v = b2GetVersion();
  benchmark::AddCustomContext("box2d v3 version", std::to_string(v.major) + "." +
                                                      std::to_string(v.minor) + "." +
                                                      std::to_string(v.revision));
  benchmark::AddCustomContext("box2d 2.4 instruction set", kDebianPackageIsa);
}

void contact_polygons(benchmark::State& state, std::span<const Polygon> a,
                      std::span<const Transform> xa, std::span<const Polygon> b,
                      std::span<const Transform> xb, bool shuffled) {
  run(state, convert(a, xa, b, xb), b2CollidePolygons, shuffled);
}

void contact_polygon_circle(benchmark::State& state, std::span<const Polygon> a,
                            std::span<const Transform> xa, std::span<const Circle> b,
                            std::span<const Transform> xb, bool shuffled) {
  run(state, convert(a, xa, b, xb), b2CollidePolygonAndCircle, shuffled);
}

void contact_polygon_capsule(benchmark::State& state, std::span<const Polygon> a,
                             std::span<const Transform> xa, std::span<const Capsule> b,
                             std::span<const Transform> xb, bool shuffled) {
  run(state, convert(a, xa, b, xb), b2CollidePolygonAndCapsule, shuffled);
}

namespace {

b2ShapeProxy proxy(const ConvexProxy& p) {
  std::vector<b2Vec2> points;
  for (int i = 0; i < p.count(); ++i) points.push_back(to_v3(p.point(i)));
  return b2MakeProxy(points.data(), p.count(), p.radius());
}

b2Sweep to_v3(const Sweep& s) {
  return {to_v3(s.local_center), to_v3(s.c0), to_v3(s.c1), b2MakeRot(s.a0), b2MakeRot(s.a1)};
}

}  // namespace

void shape_cast(benchmark::State& state, std::span<const MovingPair> pairs,
                std::vector<float>& fractions, bool shuffled) {
  struct Input {
    b2ShapeProxy a, b;
    b2Transform xa, xb;
    b2Vec2 va, vb;
  };
  std::vector<Input> inputs;
  for (const MovingPair& p : pairs) {
    inputs.push_back({proxy(p.a), proxy(p.b), to_v3(p.xa), to_v3(p.xb), to_v3(p.va), to_v3(p.vb)});
  }
  fractions.assign(pairs.size(), -1.0f);
  double iterations = 0.0;
  CaseOrder order(static_cast<std::uint32_t>(inputs.size() - 1));
  for (auto _ : state) {
    int iters = 0;
    for (size_t k = 0; k < inputs.size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      const Input& in = inputs[i];
      b2ShapeCastPairInput cast{};
      cast.proxyA = in.a;
      cast.proxyB = in.b;
      cast.transform = b2InvMulTransforms(in.xa, in.xb);
      cast.translationB = b2InvRotateVector(in.xa.q, b2Sub(in.vb, in.va));
      cast.maxFraction = 1.0f;
      cast.canEncroach = false;
      const b2CastOutput out = b2ShapeCast(&cast);
      fractions[i] = out.hit ? out.fraction : -1.0f;
      iters += out.iterations;
    }
    iterations = iters;
    benchmark::DoNotOptimize(fractions.data());
  }
  state.counters["iters"] = iterations / double(inputs.size());
}

void time_of_impact(benchmark::State& state, std::span<const MovingPair> pairs,
                    std::vector<float>& fractions, bool shuffled) {
  std::vector<b2TOIInput> inputs;
  for (const MovingPair& p : pairs) {
    b2TOIInput in{};
    in.proxyA = proxy(p.a);
    in.proxyB = proxy(p.b);
    in.sweepA = to_v3(p.sa);
    in.sweepB = to_v3(p.sb);
    in.maxFraction = 1.0f;
    inputs.push_back(in);
  }
  fractions.assign(pairs.size(), -1.0f);
  CaseOrder order(static_cast<std::uint32_t>(inputs.size() - 1));
  for (auto _ : state) {
    for (size_t k = 0; k < inputs.size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      const b2TOIOutput out = b2TimeOfImpact(&inputs[i]);
      fractions[i] = out.state == b2_toiStateHit && out.fraction > 0.0f ? out.fraction : -1.0f;
    }
    benchmark::DoNotOptimize(fractions.data());
  }
}

namespace {

struct DistanceInputs {
  std::vector<b2DistanceInput> inputs;   // proxies, radii on; transform set per call
  std::vector<b2Transform> xa;
  std::vector<std::vector<b2Transform>> xb;
};

DistanceInputs distance_inputs(std::span<const DistancePair> pairs) {
  DistanceInputs d;
  for (const DistancePair& p : pairs) {
    b2DistanceInput in{};
    in.proxyA = proxy(p.a);
    in.proxyB = proxy(p.b);
    in.useRadii = true;
    d.inputs.push_back(in);
    d.xa.push_back(to_v3(p.xa));
    std::vector<b2Transform> frames;
    for (const Transform& x : p.xb) frames.push_back(to_v3(x));
    d.xb.push_back(std::move(frames));
  }
  return d;
}

}  // namespace

void distance(benchmark::State& state, std::span<const DistancePair> pairs, bool warm,
              bool shuffled) {
  DistanceInputs d = distance_inputs(pairs);
  std::vector<b2SimplexCache> caches(pairs.size(), b2SimplexCache{});
  const size_t frames = pairs.empty() ? 1 : pairs[0].xb.size();
  size_t frame = 0;
  int iterations = 0;
  CaseOrder order(static_cast<std::uint32_t>(d.inputs.size() - 1));
  for (auto _ : state) {
    float sum = 0.0f;
    iterations = 0;
    for (size_t k = 0; k < d.inputs.size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      b2DistanceInput& in = d.inputs[i];
      in.transform = b2InvMulTransforms(d.xa[i], d.xb[i][warm ? frame : 0]);
      b2SimplexCache cold{};
      const b2DistanceOutput out = b2ShapeDistance(&in, warm ? &caches[i] : &cold, nullptr, 0);
      // Frame A to world, as collide answers.
      const b2Vec2 world[3] = {b2TransformPoint(d.xa[i], out.pointA),
                               b2TransformPoint(d.xa[i], out.pointB),
                               b2RotateVector(d.xa[i].q, out.normal)};
      benchmark::DoNotOptimize(world);
      sum += out.distance;
      iterations += out.iterations;
    }
    benchmark::DoNotOptimize(sum);
    frame = (frame + 1) % frames;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs.size()));
  state.counters["iters"] = static_cast<double>(iterations) / static_cast<double>(pairs.size());
}

void overlap(benchmark::State& state, std::span<const DistancePair> pairs, bool shuffled) {
  DistanceInputs d = distance_inputs(pairs);
  int hits = 0;
  CaseOrder order(static_cast<std::uint32_t>(d.inputs.size() - 1));
  for (auto _ : state) {
    hits = 0;
    for (size_t k = 0; k < d.inputs.size(); ++k) {
      const size_t i = shuffled ? order.next() : k;
      b2DistanceInput& in = d.inputs[i];
      in.transform = b2InvMulTransforms(d.xa[i], d.xb[i][0]);
      b2SimplexCache cache{};
      const b2DistanceOutput out = b2ShapeDistance(&in, &cache, nullptr, 0);
      hits += out.distance < 10.0f * FLT_EPSILON ? 1 : 0;
    }
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pairs.size()));
  state.counters["overlap"] = static_cast<double>(hits) / static_cast<double>(pairs.size());
}

namespace {

struct WorldHit {
  b2Vec2 point;
  b2Vec2 normal;
  float fraction;
  bool hit;
};

template <class Shape, class Cast>
void run_rays(benchmark::State& state, std::span<const Shape> shapes,
              std::span<const RayCase> cases, Cast cast) {
  std::vector<decltype(to_v3(shapes[0]))> v3_shapes;
  for (const Shape& s : shapes) v3_shapes.push_back(to_v3(s));
  struct Input {
    b2Transform xf;
    b2Vec2 origin, translation;
  };
  std::vector<Input> inputs;
  for (const RayCase& c : cases) {
    inputs.push_back({to_v3(c.xf), to_v3(c.ray.origin), to_v3(c.ray.translation)});
  }
  CaseOrder order(static_cast<std::uint32_t>(inputs.size() - 1));
  const size_t shape_mask = static_cast<size_t>(state.range(1));
  int64_t hits = 0, casts = 0;
  for (auto _ : state) {
    const size_t i = order.next();
    const Input& in = inputs[i];
    b2RayCastInput local;
    local.origin = b2InvTransformPoint(in.xf, in.origin);
    local.translation = b2InvRotateVector(in.xf.q, in.translation);
    local.maxFraction = 1.0f;
    const b2CastOutput out = cast(&v3_shapes[i & shape_mask], &local);
    WorldHit h{};
    h.hit = out.hit;
    if (out.hit) {
      h.fraction = out.fraction;
      h.point = b2TransformPoint(in.xf, out.point);
      h.normal = b2RotateVector(in.xf.q, out.normal);
    }
    benchmark::DoNotOptimize(h);
    hits += out.hit ? 1 : 0;
    ++casts;
  }
  state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(casts);
}

}  // namespace

void ray_cast(benchmark::State& state, std::span<const Polygon> shapes,
              std::span<const RayCase> cases) {
  run_rays(state, shapes, cases, b2RayCastPolygon);
}

void ray_cast(benchmark::State& state, std::span<const Circle> shapes,
              std::span<const RayCase> cases) {
  run_rays(state, shapes, cases, b2RayCastCircle);
}

void ray_cast(benchmark::State& state, std::span<const Capsule> shapes,
              std::span<const RayCase> cases) {
  run_rays(state, shapes, cases, b2RayCastCapsule);
}

namespace {

b2AABB to_v3(const Aabb& b) { return {to_v3(b.min), to_v3(b.max)}; }

/// v3's fat box for a moving shape: min(B2_MAX_AABB_MARGIN, B2_AABB_MARGIN_FRACTION x extent).
Aabb fat_box(const Aabb& b) {
  const Vec2 half = 0.5f * (b.max - b.min);
  return fatten(b, std::min(0.05f, 0.125f * std::max(half.x, half.y)));
}

}  // namespace

struct DynamicTreeRace::Impl {
  b2DynamicTree tree;
  std::vector<int> proxy;
  std::vector<Aabb> fat;
  std::span<const Aabb> boxes;
  int current = 0;
  std::size_t count = 0;

  static bool query(int proxy_id, uint64_t user_data, void* context) {
    (void)proxy_id;
    Impl& self = *static_cast<Impl*>(context);
    const int j = static_cast<int>(user_data);
    if (j > self.current && overlap(self.boxes[static_cast<size_t>(self.current)],
                                    self.boxes[static_cast<size_t>(j)])) {
      ++self.count;
    }
    return true;
  }
};

DynamicTreeRace::DynamicTreeRace(std::span<const Aabb> boxes) : impl_(std::make_unique<Impl>()) {
  impl_->tree = b2DynamicTree_Create(static_cast<int>(boxes.size()));
  for (size_t i = 0; i < boxes.size(); ++i) {
    impl_->fat.push_back(fat_box(boxes[i]));
    impl_->proxy.push_back(b2DynamicTree_CreateProxy(&impl_->tree, to_v3(impl_->fat.back()),
                                                     B2_DEFAULT_CATEGORY_BITS, i));
  }
  b2DynamicTree_Rebuild(&impl_->tree, true);
}

DynamicTreeRace::~DynamicTreeRace() { b2DynamicTree_Destroy(&impl_->tree); }

std::size_t DynamicTreeRace::frame(std::span<const Aabb> boxes) {
  Impl& m = *impl_;
  for (size_t i = 0; i < boxes.size(); ++i) {
    if (!contains(m.fat[i], boxes[i])) {
      m.fat[i] = fat_box(boxes[i]);
      b2DynamicTree_EnlargeProxy(&m.tree, m.proxy[i], to_v3(m.fat[i]));
    }
  }
  b2DynamicTree_Rebuild(&m.tree, false);
  m.boxes = boxes;
  m.count = 0;
  for (m.current = 0; m.current < static_cast<int>(boxes.size()); ++m.current) {
    b2DynamicTree_Query(&m.tree, to_v3(boxes[static_cast<size_t>(m.current)]),
                        B2_DEFAULT_MASK_BITS, Impl::query, &m);
  }
  return m.count;
}

}  // namespace collide::bench::box2d_v3
