#pragma once
// Jolt Physics (../shared/peers/jolt) as a benchmark rival and test oracle, behind plain types:
// the target `collide_jolt_queries` (cmake/peers.cmake) is the only code compiled with Jolt's
// headers and instruction set (Jolt's own -mavx2 -mfma ... options), so the benchmarks and
// tests that link it (bench_narrow3, bench_ray_cast3, bench_convex_hull, bench_mesh_raycast,
// test_oracles) keep collide's. Each function is one query as a Jolt user makes it, called once per pair or ray (a
// plain function call costs a few ns against queries of 0.1 to 10 us); where a query is a few
// ns itself (support points) the loop runs here.

#include <array>
#include <cstdint>
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

// ---- hulls: building and support points (bench_convex_hull) -----------------------------------

/// A point cloud in Jolt's form (JPH::Array<JPH::Vec3>), converted once outside a timed loop.
class Cloud;
struct CloudDeleter {
  void operator()(Cloud* c) const;
};
using CloudPtr = std::unique_ptr<Cloud, CloudDeleter>;
CloudPtr make_cloud(std::span<const Vec> points);

struct HullBuild {
  bool ok = false;   ///< ConvexHullBuilder::Initialize returned Success
  int faces = 0;     ///< faces of the builder's hull (triangles merged into polygons)
  int vertices = 0;  ///< GetNumVerticesUsed
};
/// JPH::ConvexHullBuilder on the cloud: Initialize(max_vertices, tolerance); with `verify`, then
/// DetermineMaxError (every point against every face, as ConvexHullShape checks its hull before
/// it keeps it).
HullBuild build_hull(const Cloud& cloud, int max_vertices, float tolerance, bool verify = false);

/// Sum of the x coordinates of the hull's support points (ConvexShape::GetSupportFunction,
/// convex radius excluded, fetched once as GJK does) over `directions`: the timed loop of a
/// support benchmark, run here so that each support point costs no call.
float support_sum(const Hull& hull, std::span<const Vec> directions);

// ---- meshes: ray casts (bench_mesh_raycast) ---------------------------------------------------

/// A JPH::MeshShape (default MeshShapeSettings: 8 triangles per leaf; degenerate and duplicate
/// triangles removed by its Sanitize).
class Mesh;
struct MeshDeleter {
  void operator()(Mesh* m) const;
};
using MeshPtr = std::unique_ptr<Mesh, MeshDeleter>;
/// nullptr if Jolt rejects the mesh.
MeshPtr make_mesh(std::span<const Vec> positions,
                  std::span<const std::array<std::uint32_t, 3>> triangles);

/// Shape::CastRay (closest hit, the mesh at the origin): the fraction of `translation` at the
/// first hit, or -1 for none. Back faces are hit too (CastRay's default).
float cast_ray(const Mesh& mesh, Vec origin, Vec translation);

// ---- convex shapes against a mesh (bench_narrow_mesh) --------------------------------------

/// A convex JPH::Shape with convex radius 0 (exact geometry, as collide's shapes).
class Convex;
struct ConvexDeleter {
  void operator()(Convex* c) const;
};
using ConvexPtr = std::unique_ptr<Convex, ConvexDeleter>;
/// JPH::BoxShape of half extents `half`; with `radius` > 0 its edges and corners rounded by
/// that convex radius (`half` the outer extents, radius <= the smallest of them).
ConvexPtr make_box(Vec half, float radius = 0.0f);
/// JPH::SphereShape of `radius` (a sphere's radius is its convex radius: exact).
ConvexPtr make_sphere(float radius);
/// JPH::CapsuleShape along y: segment from (0, -half_height, 0) to (0, half_height, 0).
ConvexPtr make_capsule(float half_height, float radius);
/// JPH::ConvexHullShape of `points` (hull tolerance 0); nullptr if Jolt rejects them.
ConvexPtr make_convex(std::span<const Vec> points);

struct MeshContactOut {
  int hits = 0;        ///< collision results (one per triangle within the margin)
  int points = 0;      ///< contact points over all results' manifolds
  float depth = 0.0f;  ///< largest penetration depth among the results
};
/// CollisionDispatch::sCollideShapeVsShape of the convex shape whose local frame is `pose`
/// against the mesh at the origin (faces collected, mMaxSeparationDistance = `margin`, back
/// faces collided with, as collide's triangles are two-sided; active edges on, Jolt's default),
/// each result made a manifold as PhysicsSystem does
/// (ManifoldBetweenTwoFaces, PruneContactPoints).
MeshContactOut mesh_contact(const Convex& convex, const Pose& pose, const Mesh& mesh, float margin);

/// CollisionDispatch::sCastShapeVsShapeWorldSpace: the convex shape whose local frame is
/// `pose`, moving by `translation`, against the mesh at the origin; ShapeCastSettings with back
/// faces collided with (two-sided, as collide's triangles), closest hit.
CastOut mesh_cast(const Convex& convex, const Pose& pose, Vec translation, const Mesh& mesh);

/// Shape::CastRay of the convex shape whose local frame is `pose`, as TransformedShape::CastRay
/// makes it: the world-space ray (origin, translation) taken into the shape's centre-of-mass
/// frame, closest hit. The fraction of `translation` at the hit, or -1 for none; a ray that
/// starts inside the shape hits at 0 (Jolt's convention). No normal (Jolt asks the shape for it
/// separately, GetSurfaceNormal).
float cast_ray(const Convex& convex, const Pose& pose, Vec origin, Vec translation);

/// A ray cast's answer with its world-space point and unit normal.
struct RayOut {
  float fraction = -1.0f;  ///< -1: no hit
  Vec point, normal;
};
/// cast_ray, then the hit's point and normal as a Jolt user asks for them (TransformedShape's
/// documented way): RRayCast::GetPointOnRay(fraction), then
/// TransformedShape::GetWorldSpaceSurfaceNormal(sub shape id, point), which takes the point into
/// the centre-of-mass frame, asks Shape::GetSurfaceNormal and turns the normal back, normalised.
RayOut cast_ray_normal(const Convex& convex, const Pose& pose, Vec origin, Vec translation);

/// Jolt's build as JPH::GetConfigurationString() gives it: precision, CPU and instruction set,
/// e.g. "Single precision x86 64-bit with instructions: SSE2 SSE4.1 SSE4.2 AVX AVX2 F16C LZCNT
/// TZCNT FMADD ...".
const char* instruction_set();

}  // namespace jolt_queries
