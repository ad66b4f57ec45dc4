// Jolt's PhysicsSystem stepping a world of kinematic bodies (see jolt_scale_world.hpp):
// compiled with Jolt's own flags, every entry point guarded by ClearUpperOnReturn.

#include "jolt_scale_world.hpp"
#include "jolt_internal.hpp"

#include <Jolt/Jolt.h>

#include <Jolt/Core/JobSystemThreadPool.h>
#include <Jolt/Core/TempAllocator.h>
#include <Jolt/Physics/Body/BodyCreationSettings.h>
#include <Jolt/Physics/Collision/ContactListener.h>
#include <Jolt/Physics/Collision/Shape/HeightFieldShape.h>
#include <Jolt/Physics/PhysicsSettings.h>
#include <Jolt/Physics/PhysicsSystem.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <vector>

namespace jolt_queries {

namespace {

/// Speeds no body of the benchmark reaches (its bullets fly at about 420 m/s, Jolt's default
/// limit is 500 m/s, and 47 rad/s for turning): nothing is clamped.
constexpr float kMaxLinearSpeed = 1.0e4f;
constexpr float kMaxAngularSpeed = 1.0e3f;
/// Body mutexes: 0 lets Jolt pick its default.
constexpr JPH::uint kDefaultBodyMutexes = 0;
/// Update's collision steps per frame (one, as World3D::step is one).
constexpr int kCollisionSteps = 1;
/// The temporary allocator's block: at least this (a small world's fixed costs), at most what
/// its 32-bit size holds (past it, malloc serves the rest).
constexpr std::size_t kMinTempBytes = std::size_t{32} << 20;
constexpr std::size_t kMaxTempBytes = std::size_t{3} << 30;

std::size_t temp_bytes(std::size_t bodies, const ScaleCapacity& capacity) {
  return std::clamp(bodies * capacity.temp_bytes_per_body, kMinTempBytes, kMaxTempBytes);
}

/// Counts the manifolds Update reports. Called from every job thread at once.
class ContactCounter final : public JPH::ContactListener {
 public:
  void OnContactAdded(const JPH::Body&, const JPH::Body&, const JPH::ContactManifold&, JPH::ContactSettings&) override {
    added.fetch_add(1, std::memory_order_relaxed);
  }
  void OnContactPersisted(const JPH::Body&, const JPH::Body&, const JPH::ContactManifold&,
                          JPH::ContactSettings&) override {
    persisted.fetch_add(1, std::memory_order_relaxed);
  }
  std::atomic<std::int64_t> added{0}, persisted{0};
};

}  // namespace

class ScaleWorld {
 public:
  ScaleWorld(int threads, std::size_t temp_bytes)
      : temp(static_cast<JPH::uint>(temp_bytes)), jobs(JPH::cMaxPhysicsJobs, JPH::cMaxPhysicsBarriers, threads - 1) {}

  Layers layers;
  LayerVsTree layer_vs_tree;
  LayerPairs layer_pairs;
  ContactCounter contacts;
  JPH::PhysicsSystem system;  ///< destroys its bodies; after the listener and layers it points to
  JPH::TempAllocatorImplWithMallocFallback temp;
  JPH::JobSystemThreadPool jobs;
  std::vector<JPH::BodyID> moving;  ///< the bodies, in the caller's order
};

void ScaleWorldDeleter::operator()(ScaleWorld* w) const {
  const ClearUpperOnReturn clear_upper;
  delete w;
}

MeshPtr make_height_field(int samples, std::span<const float> heights, float spacing_x, float spacing_z,
                          Vec origin) {
  const ClearUpperOnReturn clear_upper;
  init();
  const auto count = static_cast<std::size_t>(samples) * static_cast<std::size_t>(samples);
  if (samples < 2 || heights.size() != count) return nullptr;
  const JPH::HeightFieldShapeSettings settings(heights.data(), to_jolt(origin), JPH::Vec3(spacing_x, 1.0f, spacing_z),
                                               static_cast<JPH::uint32>(samples));
  const JPH::ShapeSettings::ShapeResult result = settings.Create();
  if (result.HasError()) return nullptr;
  MeshPtr mesh(new Mesh);
  mesh->shape = result.Get();
  return mesh;
}

ScaleWorldPtr make_scale_world(std::span<const ScaleStatic> statics, std::span<const ScaleBody> bodies, int threads,
                               const ScaleCapacity& capacity) {
  const ClearUpperOnReturn clear_upper;
  init();
  if (threads < 1) throw std::invalid_argument("jolt_queries::make_scale_world: threads < 1");
  const std::size_t n = bodies.size();
  ScaleWorldPtr w(new ScaleWorld(threads, temp_bytes(n, capacity)));
  const auto max_bodies = static_cast<JPH::uint>(statics.size() + n);
  const auto max_pairs = static_cast<JPH::uint>(n * static_cast<std::size_t>(capacity.body_pairs_per_body));
  const auto max_contacts = static_cast<JPH::uint>(n * static_cast<std::size_t>(capacity.contacts_per_body));
  w->system.Init(max_bodies, kDefaultBodyMutexes, max_pairs, max_contacts, w->layers, w->layer_vs_tree,
                 w->layer_pairs);
  w->system.SetGravity(JPH::Vec3::sZero());
  JPH::PhysicsSettings settings = w->system.GetPhysicsSettings();
  settings.mAllowSleeping = false;
  w->system.SetPhysicsSettings(settings);
  w->system.SetContactListener(&w->contacts);

  JPH::BodyInterface& bi = w->system.GetBodyInterfaceNoLock();
  const auto create = [&](const JPH::BodyCreationSettings& s) {
    JPH::Body* body = bi.CreateBody(s);
    if (body == nullptr) throw std::runtime_error("jolt_queries::make_scale_world: out of bodies");
    return body->GetID();
  };
  std::vector<JPH::BodyID> fixed;
  fixed.reserve(statics.size());
  for (const ScaleStatic& s : statics) {
    const JPH::Shape* shape = s.level ? s.level->shape.GetPtr() : s.convex->shape.GetPtr();
    fixed.push_back(create(JPH::BodyCreationSettings(shape, to_jolt(s.pose.p), to_jolt(s.pose.q),
                                                     JPH::EMotionType::Static, kLevelLayer)));
  }
  w->moving.reserve(n);
  for (const ScaleBody& b : bodies) {
    JPH::BodyCreationSettings s(b.shape->shape.GetPtr(), to_jolt(b.pose.p), to_jolt(b.pose.q),
                                JPH::EMotionType::Kinematic, kMovingLayer);
    s.mCollideKinematicVsNonDynamic = true;
    s.mMotionQuality = JPH::EMotionQuality::Discrete;
    s.mAllowSleeping = false;
    s.mMaxLinearVelocity = kMaxLinearSpeed;
    s.mMaxAngularVelocity = kMaxAngularSpeed;
    s.mLinearVelocity = to_jolt(b.velocity);
    s.mAngularVelocity = to_jolt(b.angular);
    w->moving.push_back(create(s));
  }
  // Added in two batches (AddBodiesPrepare may reorder its array: copies).
  std::vector<JPH::BodyID> batch = fixed;
  JPH::BodyInterface::AddState state = bi.AddBodiesPrepare(batch.data(), static_cast<int>(batch.size()));
  bi.AddBodiesFinalize(batch.data(), static_cast<int>(batch.size()), state, JPH::EActivation::DontActivate);
  batch = w->moving;
  state = bi.AddBodiesPrepare(batch.data(), static_cast<int>(batch.size()));
  bi.AddBodiesFinalize(batch.data(), static_cast<int>(batch.size()), state, JPH::EActivation::Activate);
  w->system.OptimizeBroadPhase();
  return w;
}

void set_bodies(ScaleWorld& w, std::span<const ScaleBody> bodies) {
  const ClearUpperOnReturn clear_upper;
  if (bodies.size() != w.moving.size()) throw std::invalid_argument("jolt_queries::set_bodies: body count differs");
  JPH::BodyInterface& bi = w.system.GetBodyInterfaceNoLock();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const ScaleBody& b = bodies[i];
    bi.SetPositionRotationAndVelocity(w.moving[i], to_jolt(b.pose.p), to_jolt(b.pose.q), to_jolt(b.velocity),
                                      to_jolt(b.angular));
  }
}

ScaleStepOut step(ScaleWorld& w, float dt) {
  const ClearUpperOnReturn clear_upper;
  w.contacts.added.store(0, std::memory_order_relaxed);
  w.contacts.persisted.store(0, std::memory_order_relaxed);
  ScaleStepOut out;
  out.errors = static_cast<std::uint32_t>(w.system.Update(dt, kCollisionSteps, &w.temp, &w.jobs));
  out.added = w.contacts.added.load(std::memory_order_relaxed);
  out.persisted = w.contacts.persisted.load(std::memory_order_relaxed);
  return out;
}

Pose pose(const ScaleWorld& w, int body) {
  const ClearUpperOnReturn clear_upper;
  const JPH::BodyInterface& bi = w.system.GetBodyInterfaceNoLock();
  const JPH::BodyID id = w.moving[static_cast<std::size_t>(body)];
  const JPH::Quat q = bi.GetRotation(id);
  return {from_jolt(JPH::Vec3(bi.GetPosition(id))), {q.GetX(), q.GetY(), q.GetZ(), q.GetW()}};
}

}  // namespace jolt_queries
