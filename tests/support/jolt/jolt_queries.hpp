#pragma once
// Jolt Physics (../shared/peers/jolt) as a benchmark rival and test oracle, behind plain types:
// the target `collide_jolt_queries` (cmake/peers.cmake) is the only code compiled with Jolt's
// headers and instruction set (Jolt's own -mavx2 -mfma ... options), so the benchmarks and
// tests that link it (bench_narrow3, test_narrow) keep collide's. Each function is one query as
// a Jolt user makes it, called once per pair (a plain function call costs a few ns against
// queries of a microsecond).

#include <array>
#include <memory>
#include <span>

namespace jolt_queries {

struct Vec {
  float x = 0.0f, y = 0.0f, z = 0.0f;
};

/// A rigid placement: position and unit quaternion (x, y, z, w).
struct Pose {
  Vec p;
  std::array<float, 4> q{0.0f, 0.0f, 0.0f, 1.0f};
};

/// Registers Jolt's allocator, factory and shape types (once per process).
void init();

/// A JPH::ConvexHullShape built from `points` (local space) with convex radius 0 (exact
/// geometry) and hull tolerance `hull_tolerance`; the shape's centre of mass is its origin in
/// Jolt, so a body pose is turned into a centre-of-mass pose by `place`.
class Hull;
struct HullDeleter {
  void operator()(Hull* h) const;
};
using HullPtr = std::unique_ptr<Hull, HullDeleter>;
/// nullptr if Jolt rejects the points.
HullPtr make_hull(std::span<const Vec> points, float hull_tolerance);
/// Number of vertices Jolt's hull kept.
int vertex_count(const Hull& hull);

/// A hull placed in the world, as a Jolt body holds it: centre-of-mass position and rotation.
struct Body {
  const Hull* hull = nullptr;
  Pose com;
};
/// The body of `hull` whose local frame (the frame of the points given to make_hull) is `pose`.
Body place(const Hull& hull, const Pose& pose);

/// GJKClosestPoint::Intersects on the two support functions (B moved into A's frame), tolerance
/// cDefaultCollisionTolerance.
bool overlap(const Body& a, const Body& b);

struct DistanceOut {
  float distance = 0.0f;  ///< 0 when overlapping
  Vec point_a, point_b;   ///< world space
};
/// GJKClosestPoint::GetClosestPoints (tolerance cDefaultCollisionTolerance).
DistanceOut distance(const Body& a, const Body& b);

struct DepthOut {
  bool hit = false;
  float depth = 0.0f;
  Vec normal;  ///< unit, world space, direction to move B out of A
};
/// EPAPenetrationDepth as ConvexShape::sCollideConvexVsConvex runs it: the GJK step, then the
/// EPA step when the cores overlap (default tolerances, no separation distance, no faces).
DepthOut penetration(const Body& a, const Body& b);

struct ContactOut {
  int count = 0;     ///< contact points after pruning (0: no contact)
  float depth = 0.0f;  ///< penetration depth of the collision result
  Vec normal;        ///< unit, world space, from A to B
  std::array<Vec, 4> points_a{}, points_b{};  ///< first four points on A and B, world space
};
/// CollisionDispatch::sCollideShapeVsShape with faces collected and mMaxSeparationDistance =
/// `margin`, then the manifold as PhysicsSystem / ContactConstraintManager build it:
/// ManifoldBetweenTwoFaces (max contact distance margin + PhysicsSettings::mManifoldTolerance)
/// and PruneContactPoints when more than 4 points remain.
ContactOut contact(const Body& a, const Body& b, float margin);

struct CastOut {
  bool hit = false;
  float fraction = 1.0f;
};
/// CollisionDispatch::sCastShapeVsShapeWorldSpace: A moving by `translation_a` against static
/// B, default ShapeCastSettings, closest hit.
CastOut cast(const Body& a, Vec translation_a, const Body& b);

/// Jolt's compile-time instruction set, e.g. "AVX2 FMA F16C LZCNT TZCNT SSE4.2".
const char* instruction_set();

}  // namespace jolt_queries
