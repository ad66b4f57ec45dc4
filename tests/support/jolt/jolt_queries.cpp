// Jolt's queries (see jolt_queries.hpp): compiled with Jolt's own flags.

#include "jolt_queries.hpp"
#include "jolt_internal.hpp"

#include <Jolt/Jolt.h>

#include <Jolt/ConfigurationString.h>
#include <Jolt/Core/Factory.h>
#include <Jolt/Core/Memory.h>
#include <Jolt/Geometry/ConvexHullBuilder.h>
#include <Jolt/Geometry/ConvexSupport.h>
#include <Jolt/Geometry/EPAPenetrationDepth.h>
#include <Jolt/Geometry/GJKClosestPoint.h>
#include <Jolt/Physics/Collision/CollideShape.h>
#include <Jolt/Physics/Collision/CollisionCollectorImpl.h>
#include <Jolt/Physics/Collision/CollisionDispatch.h>
#include <Jolt/Physics/Collision/ManifoldBetweenTwoFaces.h>
#include <Jolt/Physics/Collision/RayCast.h>
#include <Jolt/Physics/Collision/CastResult.h>
#include <Jolt/Physics/Collision/ShapeCast.h>
#include <Jolt/Physics/Collision/Shape/BoxShape.h>
#include <Jolt/Physics/Collision/Shape/CapsuleShape.h>
#include <Jolt/Physics/Collision/Shape/ConvexHullShape.h>
#include <Jolt/Physics/Collision/Shape/MeshShape.h>
#include <Jolt/Physics/Collision/Shape/SphereShape.h>
#include <Jolt/Physics/PhysicsSettings.h>
#include <Jolt/RegisterTypes.h>

#include <algorithm>
#include <cfloat>
#include <mutex>

namespace jolt_queries {

using JPH::Mat44;
using JPH::Vec3;

class Hull {
 public:
  JPH::RefConst<JPH::ConvexHullShape> shape;
};

void HullDeleter::operator()(Hull* h) const { delete h; }

class Cloud {
 public:
  JPH::Array<Vec3> points;
};

void CloudDeleter::operator()(Cloud* c) const { delete c; }

void MeshDeleter::operator()(Mesh* m) const { delete m; }

void ConvexDeleter::operator()(Convex* c) const { delete c; }

namespace {

/// The centre-of-mass transform, as JPH::Body::GetCenterOfMassTransform computes it.
Mat44 com_transform(const Body& b) {
  return Mat44::sRotationTranslation(to_jolt(b.com.q), to_jolt(b.com.p));
}

const JPH::ConvexShape::Support* support(const Body& b, JPH::ConvexShape::SupportBuffer& buffer,
                                         JPH::ConvexShape::ESupportMode mode) {
  return b.hull->shape->GetSupportFunction(mode, buffer, Vec3::sOne());
}

/// B's transform in A's centre-of-mass frame, as ConvexShape::sCollideConvexVsConvex makes it.
Mat44 b_in_a(const Body& a, const Body& b) {
  return com_transform(a).InversedRotationTranslation() * com_transform(b);
}

/// First search direction: from A's centre of mass to B's (Jolt's choice in
/// sCollideConvexVsConvex).
Vec3 first_axis(const Mat44& b_to_a) {
  Vec3 v = b_to_a.GetTranslation();
  return v.IsNearZero() ? Vec3::sAxisX() : v;
}

/// Collects the collision result and builds the manifold as PhysicsSystem's
/// NonReductionCollideShapeCollector does.
class ManifoldCollector : public JPH::CollideShapeCollector {
 public:
  explicit ManifoldCollector(float max_contact_distance)
      : max_contact_distance_(max_contact_distance) {}
  void AddHit(const JPH::CollideShapeResult& r) override {
    JPH::ContactPoints on1, on2;
    JPH::ManifoldBetweenTwoFaces(r.mContactPointOn1, r.mContactPointOn2, r.mPenetrationAxis,
                                 max_contact_distance_, r.mShape1Face, r.mShape2Face, on1, on2);
    const Vec3 normal = r.mPenetrationAxis.Normalized();
    if (on1.size() > 4) JPH::PruneContactPoints(normal, on1, on2);
    out.count = static_cast<int>(on1.size());
    out.depth = r.mPenetrationDepth;
    out.normal = from_jolt(normal);
    for (int i = 0; i < out.count && i < 4; ++i) {
      out.points_a[i] = from_jolt(on1[i]);
      out.points_b[i] = from_jolt(on2[i]);
    }
  }
  ContactOut out;

 private:
  float max_contact_distance_;
};

}  // namespace

void init() {
  const ClearUpperOnReturn clear_upper;
  static std::once_flag once;
  std::call_once(once, [] {
    JPH::RegisterDefaultAllocator();
    JPH::Factory::sInstance = new JPH::Factory();
    JPH::RegisterTypes();
  });
}

HullPtr make_hull(std::span<const Vec> points, float hull_tolerance) {
  const ClearUpperOnReturn clear_upper;
  JPH::Array<Vec3> pts;
  pts.reserve(points.size());
  for (Vec p : points) pts.push_back(to_jolt(p));
  JPH::ConvexHullShapeSettings settings(pts, 0.0f);
  settings.mHullTolerance = hull_tolerance;
  const JPH::ShapeSettings::ShapeResult result = settings.Create();
  if (result.HasError()) return nullptr;
  HullPtr hull(new Hull);
  hull->shape = static_cast<const JPH::ConvexHullShape*>(result.Get().GetPtr());
  return hull;
}

int vertex_count(const Hull& hull) { return static_cast<int>(hull.shape->GetNumPoints()); }

Body place(const Hull& hull, const Pose& pose) {
  const ClearUpperOnReturn clear_upper;
  const JPH::Quat q = to_jolt(pose.q);
  const Vec3 com = to_jolt(pose.p) + q * hull.shape->GetCenterOfMass();
  return {&hull, {from_jolt(com), pose.q}};
}

bool overlap(const Body& a, const Body& b) {
  const ClearUpperOnReturn clear_upper;
  const Mat44 rel = b_in_a(a, b);
  JPH::ConvexShape::SupportBuffer buffer_a, buffer_b;
  const auto* sa = support(a, buffer_a, JPH::ConvexShape::ESupportMode::ExcludeConvexRadius);
  const auto* sb = support(b, buffer_b, JPH::ConvexShape::ESupportMode::ExcludeConvexRadius);
  const JPH::TransformedConvexObject tb(rel, *sb);
  Vec3 v = first_axis(rel);
  JPH::GJKClosestPoint gjk;
  return gjk.Intersects(*sa, tb, JPH::cDefaultCollisionTolerance, v);
}

DistanceOut distance(const Body& a, const Body& b) {
  const ClearUpperOnReturn clear_upper;
  const Mat44 xa = com_transform(a);
  const Mat44 rel = xa.InversedRotationTranslation() * com_transform(b);
  JPH::ConvexShape::SupportBuffer buffer_a, buffer_b;
  const auto* sa = support(a, buffer_a, JPH::ConvexShape::ESupportMode::ExcludeConvexRadius);
  const auto* sb = support(b, buffer_b, JPH::ConvexShape::ESupportMode::ExcludeConvexRadius);
  const JPH::TransformedConvexObject tb(rel, *sb);
  Vec3 v = first_axis(rel);
  Vec3 pa, pb;
  JPH::GJKClosestPoint gjk;
  const float d2 =
      gjk.GetClosestPoints(*sa, tb, JPH::cDefaultCollisionTolerance, FLT_MAX, v, pa, pb);
  DistanceOut out;
  if (d2 > 0.0f) {
    out.distance = std::sqrt(d2);
    out.point_a = from_jolt(xa * pa);
    out.point_b = from_jolt(xa * pb);
  }
  return out;
}

DepthOut penetration(const Body& a, const Body& b) {
  const ClearUpperOnReturn clear_upper;
  using Mode = JPH::ConvexShape::ESupportMode;
  const Mat44 xa = com_transform(a);
  const Mat44 rel = xa.InversedRotationTranslation() * com_transform(b);
  Vec3 axis = first_axis(rel);
  Vec3 p1, p2;
  JPH::EPAPenetrationDepth epa;
  JPH::EPAPenetrationDepth::EStatus status;
  {
    JPH::ConvexShape::SupportBuffer buffer_a, buffer_b;
    const auto* sa = support(a, buffer_a, Mode::ExcludeConvexRadius);
    const auto* sb = support(b, buffer_b, Mode::ExcludeConvexRadius);
    const JPH::TransformedConvexObject tb(rel, *sb);
    status = epa.GetPenetrationDepthStepGJK(*sa, sa->GetConvexRadius(), tb, sb->GetConvexRadius(),
                                            JPH::cDefaultCollisionTolerance, axis, p1, p2);
  }
  if (status == JPH::EPAPenetrationDepth::EStatus::NotColliding) return {};
  if (status == JPH::EPAPenetrationDepth::EStatus::Indeterminate) {
    JPH::ConvexShape::SupportBuffer buffer_a, buffer_b;
    const auto* sa = support(a, buffer_a, Mode::IncludeConvexRadius);
    const auto* sb = support(b, buffer_b, Mode::IncludeConvexRadius);
    const JPH::TransformedConvexObject tb(rel, *sb);
    if (!epa.GetPenetrationDepthStepEPA(*sa, tb, JPH::cDefaultPenetrationTolerance, axis, p1, p2)) {
      return {};
    }
  }
  DepthOut out;
  out.hit = true;
  out.depth = (p2 - p1).Length();
  out.normal = from_jolt(xa.Multiply3x3(axis.NormalizedOr(Vec3::sAxisX())));
  return out;
}

ContactOut contact(const Body& a, const Body& b, float margin) {
  const ClearUpperOnReturn clear_upper;
  JPH::CollideShapeSettings settings;
  settings.mCollectFacesMode = JPH::ECollectFacesMode::CollectFaces;
  settings.mMaxSeparationDistance = margin;
  ManifoldCollector collector(margin + JPH::PhysicsSettings().mManifoldTolerance);
  JPH::CollisionDispatch::sCollideShapeVsShape(a.hull->shape, b.hull->shape, Vec3::sOne(),
                                               Vec3::sOne(), com_transform(a), com_transform(b),
                                               JPH::SubShapeIDCreator(), JPH::SubShapeIDCreator(),
                                               settings, collector);
  return collector.out;
}

CastOut cast(const Body& a, Vec translation_a, const Body& b) {
  const ClearUpperOnReturn clear_upper;
  const JPH::ShapeCast shape_cast(a.hull->shape, Vec3::sOne(), com_transform(a),
                                  to_jolt(translation_a));
  JPH::ShapeCastSettings settings;
  JPH::ClosestHitCollisionCollector<JPH::CastShapeCollector> collector;
  JPH::CollisionDispatch::sCastShapeVsShapeWorldSpace(shape_cast, settings, b.hull->shape,
                                                      Vec3::sOne(), JPH::ShapeFilter(),
                                                      com_transform(b), JPH::SubShapeIDCreator(),
                                                      JPH::SubShapeIDCreator(), collector);
  if (!collector.HadHit()) return {};
  return {true, collector.mHit.mFraction};
}

CloudPtr make_cloud(std::span<const Vec> points) {
  const ClearUpperOnReturn clear_upper;
  CloudPtr cloud(new Cloud);
  cloud->points.reserve(points.size());
  for (Vec p : points) cloud->points.push_back(to_jolt(p));
  return cloud;
}

HullBuild build_hull(const Cloud& cloud, int max_vertices, float tolerance, bool verify) {
  const ClearUpperOnReturn clear_upper;
  JPH::ConvexHullBuilder builder(cloud.points);
  const char* error = nullptr;
  HullBuild out;
  out.ok = builder.Initialize(max_vertices, tolerance, error) ==
           JPH::ConvexHullBuilder::EResult::Success;
  out.faces = static_cast<int>(builder.GetFaces().size());
  out.vertices = builder.GetNumVerticesUsed();
  if (verify && out.ok) {
    JPH::ConvexHullBuilder::Face* face = nullptr;
    float error = 0.0f;
    int index = -1;
    float coplanar = 0.0f;
    builder.DetermineMaxError(face, error, index, coplanar);
  }
  return out;
}

float support_sum(const Hull& hull, std::span<const Vec> directions) {
  const ClearUpperOnReturn clear_upper;
  JPH::ConvexShape::SupportBuffer buffer;
  const JPH::ConvexShape::Support* s = hull.shape->GetSupportFunction(
      JPH::ConvexShape::ESupportMode::ExcludeConvexRadius, buffer, Vec3::sOne());
  float sum = 0.0f;
  for (Vec d : directions) sum += s->GetSupport(to_jolt(d)).GetX();
  return sum;
}

MeshPtr make_mesh(std::span<const Vec> positions,
                  std::span<const std::array<std::uint32_t, 3>> triangles) {
  const ClearUpperOnReturn clear_upper;
  JPH::VertexList vertices;
  vertices.reserve(positions.size());
  for (Vec p : positions) vertices.push_back(JPH::Float3(p.x, p.y, p.z));
  JPH::IndexedTriangleList indexed;
  indexed.reserve(triangles.size());
  for (const auto& t : triangles) indexed.push_back(JPH::IndexedTriangle(t[0], t[1], t[2]));
  JPH::MeshShapeSettings settings(std::move(vertices), std::move(indexed));
  const JPH::ShapeSettings::ShapeResult result = settings.Create();
  if (result.HasError()) return nullptr;
  MeshPtr mesh(new Mesh);
  mesh->shape = result.Get();
  return mesh;
}

float cast_ray(const Mesh& mesh, Vec origin, Vec translation) {
  const ClearUpperOnReturn clear_upper;
  const JPH::RayCast ray{to_jolt(origin), to_jolt(translation)};
  JPH::RayCastResult hit;
  return mesh.shape->CastRay(ray, JPH::SubShapeIDCreator(), hit) ? hit.mFraction : -1.0f;
}

ConvexPtr make_box(Vec half, float radius) {
  const ClearUpperOnReturn clear_upper;
  ConvexPtr c(new Convex);
  c->shape = new JPH::BoxShape(to_jolt(half), radius);
  return c;
}

ConvexPtr make_sphere(float radius) {
  const ClearUpperOnReturn clear_upper;
  ConvexPtr c(new Convex);
  c->shape = new JPH::SphereShape(radius);
  return c;
}

ConvexPtr make_capsule(float half_height, float radius) {
  const ClearUpperOnReturn clear_upper;
  ConvexPtr c(new Convex);
  c->shape = new JPH::CapsuleShape(half_height, radius);
  return c;
}

ConvexPtr make_convex(std::span<const Vec> points) {
  const ClearUpperOnReturn clear_upper;
  JPH::Array<Vec3> pts;
  for (Vec p : points) pts.push_back(to_jolt(p));
  JPH::ConvexHullShapeSettings settings(pts, 0.0f);
  settings.mHullTolerance = 0.0f;
  const JPH::ShapeSettings::ShapeResult result = settings.Create();
  if (result.HasError()) return nullptr;
  ConvexPtr c(new Convex);
  c->shape = static_cast<const JPH::ConvexShape*>(result.Get().GetPtr());
  return c;
}

namespace {

/// The centre-of-mass transform of `shape` whose local frame is `pose`.
Mat44 com_transform(const JPH::Shape& shape, const Pose& pose) {
  const JPH::Quat q = to_jolt(pose.q);
  return Mat44::sRotationTranslation(q, to_jolt(pose.p) + q * shape.GetCenterOfMass());
}

/// Every result made a manifold, as PhysicsSystem's collector does for a body pair.
class MeshManifoldCollector : public JPH::CollideShapeCollector {
 public:
  explicit MeshManifoldCollector(float max_contact_distance)
      : max_contact_distance_(max_contact_distance) {}
  void AddHit(const JPH::CollideShapeResult& r) override {
    JPH::ContactPoints on1, on2;
    JPH::ManifoldBetweenTwoFaces(r.mContactPointOn1, r.mContactPointOn2, r.mPenetrationAxis,
                                 max_contact_distance_, r.mShape1Face, r.mShape2Face, on1, on2);
    if (on1.size() > 4) JPH::PruneContactPoints(r.mPenetrationAxis.Normalized(), on1, on2);
    ++out.hits;
    out.points += static_cast<int>(on1.size());
    out.depth = out.hits == 1 ? r.mPenetrationDepth : std::max(out.depth, r.mPenetrationDepth);
  }
  MeshContactOut out;

 private:
  float max_contact_distance_;
};

}  // namespace

MeshContactOut mesh_contact(const Convex& convex, const Pose& pose, const Mesh& mesh, float margin) {
  const ClearUpperOnReturn clear_upper;
  JPH::CollideShapeSettings settings;
  settings.mCollectFacesMode = JPH::ECollectFacesMode::CollectFaces;
  settings.mMaxSeparationDistance = margin;
  settings.mBackFaceMode = JPH::EBackFaceMode::CollideWithBackFaces;  // two-sided, as collide's
  MeshManifoldCollector collector(margin + JPH::PhysicsSettings().mManifoldTolerance);
  JPH::CollisionDispatch::sCollideShapeVsShape(
      convex.shape, mesh.shape, Vec3::sOne(), Vec3::sOne(), com_transform(*convex.shape, pose),
      Mat44::sIdentity(), JPH::SubShapeIDCreator(), JPH::SubShapeIDCreator(), settings, collector);
  return collector.out;
}

CastOut mesh_cast(const Convex& convex, const Pose& pose, Vec translation, const Mesh& mesh) {
  const ClearUpperOnReturn clear_upper;
  const JPH::ShapeCast shape_cast(convex.shape, Vec3::sOne(), com_transform(*convex.shape, pose),
                                  to_jolt(translation));
  JPH::ShapeCastSettings settings;
  settings.SetBackFaceMode(JPH::EBackFaceMode::CollideWithBackFaces);  // two-sided, as collide's
  JPH::ClosestHitCollisionCollector<JPH::CastShapeCollector> collector;
  JPH::CollisionDispatch::sCastShapeVsShapeWorldSpace(
      shape_cast, settings, mesh.shape, Vec3::sOne(), JPH::ShapeFilter(), Mat44::sIdentity(),
      JPH::SubShapeIDCreator(), JPH::SubShapeIDCreator(), collector);
  if (!collector.HadHit()) return {};
  return {true, collector.mHit.mFraction};
}

float cast_ray(const Convex& convex, const Pose& pose, Vec origin, Vec translation) {
  const ClearUpperOnReturn clear_upper;
  // TransformedShape::CastRay: the ray into the centre-of-mass frame (its inverse transform made
  // from the rotation and the centre of mass's position, as TransformedShape holds them).
  const JPH::Quat q = to_jolt(pose.q);
  const Vec3 com = to_jolt(pose.p) + q * convex.shape->GetCenterOfMass();
  const JPH::RayCast ray =
      JPH::RayCast{to_jolt(origin), to_jolt(translation)}.Transformed(Mat44::sInverseRotationTranslation(q, com));
  JPH::RayCastResult hit;
  return convex.shape->CastRay(ray, JPH::SubShapeIDCreator(), hit) ? hit.mFraction : -1.0f;
}

RayOut cast_ray_normal(const Convex& convex, const Pose& pose, Vec origin, Vec translation) {
  const ClearUpperOnReturn clear_upper;
  const JPH::Quat q = to_jolt(pose.q);
  const Vec3 com = to_jolt(pose.p) + q * convex.shape->GetCenterOfMass();
  const JPH::RayCast world{to_jolt(origin), to_jolt(translation)};
  const JPH::RayCast ray = world.Transformed(Mat44::sInverseRotationTranslation(q, com));
  JPH::RayCastResult hit;
  if (!convex.shape->CastRay(ray, JPH::SubShapeIDCreator(), hit)) return {};
  // GetWorldSpaceSurfaceNormal with unit scale: its own inverse transform, the point into it.
  const Vec3 point = world.GetPointOnRay(hit.mFraction);
  const Mat44 inverse = Mat44::sInverseRotationTranslation(q, com);
  const Vec3 normal =
      inverse.Multiply3x3Transposed(convex.shape->GetSurfaceNormal(hit.mSubShapeID2, inverse * point)).Normalized();
  return {hit.mFraction, from_jolt(point), from_jolt(normal)};
}

const char* instruction_set() { return JPH::GetConfigurationString(); }

}  // namespace jolt_queries
