#pragma once
// Box2D v3's side of the 2D query benchmarks (bench_narrow_contact, ...). Box2D 2.4 and v3 both
// spell their header <box2d/box2d.h> with clashing types, so v3 lives in its own translation
// unit (queries.cpp) and takes collide's shapes: each function converts them to v3's types
// before the timed loop, then times v3 answering in world space, as collide does (v3 answers in
// shape A's frame; the relative transform in and the world-space points out are part of the
// timed work). Symbols do not clash: 2.4 is C++ (mangled), v3 is C.

#include <benchmark/benchmark.h>

#include <collide/ccd/sweep.hpp>
#include <collide/core/aabb.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/transform.hpp>
#include <collide/narrow/support.hpp>
#include <collide/shape/capsule.hpp>
#include <collide/shape/circle.hpp>
#include <collide/shape/polygon.hpp>

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace collide::bench::box2d_v3 {

/// Adds to the benchmark context collide's and Box2D v3's instruction sets, v3's version and
/// Box2D 2.4's instruction set (Debian's x86-64 package). Call after benchmark::Initialize.
void add_context();

/// Manifolds of pairs [0, state.range(0)) per iteration (in that order, or `shuffled`: as many
/// pairs in CaseOrder, case_order.hpp): `b2CollidePolygons` with the relative transform, then
/// points and normal to world space. Counter "overlap": touching fraction.
void contact_polygons(benchmark::State& state, std::span<const Polygon> a,
                      std::span<const Transform> xa, std::span<const Polygon> b,
                      std::span<const Transform> xb, bool shuffled = false);
/// As contact_polygons, `b2CollidePolygonAndCircle`.
void contact_polygon_circle(benchmark::State& state, std::span<const Polygon> a,
                            std::span<const Transform> xa, std::span<const Circle> b,
                            std::span<const Transform> xb, bool shuffled = false);
/// As contact_polygons, `b2CollidePolygonAndCapsule`.
void contact_polygon_capsule(benchmark::State& state, std::span<const Polygon> a,
                             std::span<const Transform> xa, std::span<const Capsule> b,
                             std::span<const Transform> xb, bool shuffled = false);

/// A moving pair as the continuous collision benches hold it (world space; velocities are the
/// displacement over the step).
struct MovingPair {
  ConvexProxy a;
  ConvexProxy b;
  Transform xa;
  Transform xb;
  Vec2 va;
  Vec2 vb;
  Sweep sa;
  Sweep sb;
};

/// `b2ShapeCast` over every pair per iteration: B's pose and the relative motion put in A's
/// frame (timed, as collide takes world space). `fractions[i]`: the hit fraction, -1 for a
/// miss. Counter "iters": mean GJK iterations. `shuffled`: as many casts per iteration, pairs
/// drawn in CaseOrder (a power-of-two count of pairs) instead of in order.
void shape_cast(benchmark::State& state, std::span<const MovingPair> pairs,
                std::vector<float>& fractions, bool shuffled = false);

/// `b2TimeOfImpact` over every pair per iteration (v3 turns a sweep by normalised linear
/// interpolation of its rotations, collide by its angle: for turning pairs the motions differ
/// slightly between the start and end poses). `fractions[i]`: the time of a hit, -1 otherwise.
/// `shuffled` as for shape_cast.
void time_of_impact(benchmark::State& state, std::span<const MovingPair> pairs,
                    std::vector<float>& fractions, bool shuffled = false);

/// A pair for distance and overlap: B at one pose per frame (frame 0 for cold runs).
struct DistancePair {
  ConvexProxy a;
  ConvexProxy b;
  Transform xa;
  std::span<const Transform> xb;
};

/// Most points a v3 proxy holds (B2_MAX_POLYGON_VERTICES): larger shapes are left out.
inline constexpr int kMaxProxyPoints = 8;

/// `b2ShapeDistance` (radii included) over every pair per iteration, B's pose put in A's frame
/// and the frame-A points and normal put back in world space (both timed). Warm: each pair
/// keeps its simplex cache and B advances one frame per iteration. `shuffled`: as many pairs
/// per iteration drawn in CaseOrder (case_order.hpp) instead of in order.
void distance(benchmark::State& state, std::span<const DistancePair> pairs, bool warm,
              bool shuffled = false);

/// Overlap as v3 answers it (it has no boolean test): `b2ShapeDistance` below 10 FLT_EPSILON,
/// cold, frame 0. Counter "overlap": the overlapping fraction. `shuffled` as for distance.
void overlap(benchmark::State& state, std::span<const DistancePair> pairs, bool shuffled = false);

/// One ray cast: the shape's placement and the ray, world space.
struct RayCase {
  Transform xf;
  Ray ray;
};

/// One ray cast per iteration, as bench_ray_cast's rows: case i (in CaseOrder over `cases`, a
/// power of two) against shape i & state.range(1). v3 casts in the shape's frame: the ray in
/// and the hit point and normal out are converted (timed). Counter "hit_rate".
void ray_cast(benchmark::State& state, std::span<const Polygon> shapes,
              std::span<const RayCase> cases);
/// As above, `b2RayCastCircle`.
void ray_cast(benchmark::State& state, std::span<const Circle> shapes,
              std::span<const RayCase> cases);
/// As above, `b2RayCastCapsule`.
void ray_cast(benchmark::State& state, std::span<const Capsule> shapes,
              std::span<const RayCase> cases);

/// Box2D v3's b2DynamicTree driven as v3's broad phase drives it for moving bodies: each proxy
/// holds a fat box (the exact box grown by min(5 cm, 1/8 of its largest half extent): v3's
/// B2_MAX_AABB_MARGIN and B2_AABB_MARGIN_FRACTION); a box that leaves its fat box gets a new one
/// (b2DynamicTree_EnlargeProxy, v3's move buffer), the tree is rebuilt where it was enlarged
/// (b2DynamicTree_Rebuild(tree, false), as b2Collide does each step), then every box queries the
/// tree and the exact boxes decide: the full set of overlapping pairs, as collide's broad
/// phases produce (v3 itself queries only the moved proxies and keeps older pairs in its
/// contact list).
class DynamicTreeRace {
 public:
  explicit DynamicTreeRace(std::span<const Aabb> boxes);
  ~DynamicTreeRace();
  DynamicTreeRace(const DynamicTreeRace&) = delete;
  DynamicTreeRace& operator=(const DynamicTreeRace&) = delete;

  /// One frame with the boxes moved: returns the number of overlapping pairs.
  std::size_t frame(std::span<const Aabb> boxes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace collide::bench::box2d_v3
