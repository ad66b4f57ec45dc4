// Jolt doing a world's per-frame collision work (see jolt_world.hpp): compiled with Jolt's own
// flags, every entry point guarded by ClearUpperOnReturn.

#include "jolt_world.hpp"
#include "jolt_internal.hpp"

#include <Jolt/Jolt.h>

#include <Jolt/Core/TempAllocator.h>
#include <Jolt/Physics/Body/Body.h>
#include <Jolt/Physics/Body/BodyCreationSettings.h>
#include <Jolt/Physics/Body/BodyManager.h>
#include <Jolt/Physics/Character/CharacterVirtual.h>
#include <Jolt/Physics/Collision/BroadPhase/BroadPhaseQuadTree.h>
#include <Jolt/Physics/Collision/CollideShape.h>
#include <Jolt/Physics/Collision/CollisionDispatch.h>
#include <Jolt/Physics/Collision/ContactListener.h>
#include <Jolt/Physics/Collision/ManifoldBetweenTwoFaces.h>
#include <Jolt/Physics/Collision/NarrowPhaseQuery.h>
#include <Jolt/Physics/Collision/CastResult.h>
#include <Jolt/Physics/Collision/RayCast.h>
#include <Jolt/Physics/Body/BodyLockInterface.h>
#include <Jolt/Physics/Collision/Shape/CapsuleShape.h>
#include <Jolt/Physics/Collision/Shape/SphereShape.h>
#include <Jolt/Physics/PhysicsSettings.h>
#include <Jolt/Physics/PhysicsSystem.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace jolt_queries {

namespace {

using JPH::Vec3;

/// The broad phase's pairs, in a buffer reused from step to step.
class PairCollector final : public JPH::BodyPairCollector {
 public:
  void AddHit(const JPH::BodyPair& pair) override { pairs.push_back(pair); }
  std::vector<JPH::BodyPair> pairs;
};

/// Most manifolds one body pair keeps (PhysicsSystem's bound too).
constexpr int kMaxManifoldsPerPair = 32;

/// The manifolds of one body pair, built as PhysicsSystem's manifold reduction builds them: each
/// collision result (one per triangle against a mesh) joins the first manifold whose first
/// normal is within `cos_max_delta` of its own (else starts one; when all slots are taken it
/// replaces the shallowest, if deeper), its contact points from ManifoldBetweenTwoFaces added to
/// that manifold's; points are pruned to 4 when the pair is done (finish). Contact points are
/// relative to the first body's centre of mass, where the query runs.
class ReducingCollector final : public JPH::CollideShapeCollector {
 public:
  struct Manifold {
    Vec3 first_normal;
    Vec3 normal_sum;
    float depth = 0.0f;
    JPH::ContactPoints on1, on2;
  };

  /// Before a step: ManifoldBetweenTwoFaces' max contact distance and the normals' merge cosine.
  void configure(float max_contact_distance, float cos_max_delta) {
    max_contact_distance_ = max_contact_distance;
    cos_max_delta_ = cos_max_delta;
  }

  void AddHit(const JPH::CollideShapeResult& r) override {
    const Vec3 normal = r.mPenetrationAxis.Normalized();
    Manifold* m = nullptr;
    for (int i = 0; i < count && m == nullptr; ++i) {
      if (normal.Dot(manifolds[i].first_normal) >= cos_max_delta_) m = &manifolds[i];
    }
    if (m != nullptr) {
      m->normal_sum += normal;
      m->depth = std::max(m->depth, r.mPenetrationDepth);
    } else {
      if (count < kMaxManifoldsPerPair) {
        m = &manifolds[count++];
      } else {
        m = &manifolds[0];
        for (int i = 1; i < count; ++i) {
          if (manifolds[i].depth < m->depth) m = &manifolds[i];
        }
        if (r.mPenetrationDepth < m->depth) return;
      }
      m->first_normal = normal;
      m->normal_sum = normal;
      m->depth = r.mPenetrationDepth;
      m->on1.clear();
      m->on2.clear();
    }
    JPH::ManifoldBetweenTwoFaces(r.mContactPointOn1, r.mContactPointOn2, r.mPenetrationAxis,
                                 max_contact_distance_, r.mShape1Face, r.mShape2Face, m->on1, m->on2);
    // Room for the next result's points (a face has at most 32 of the 64).
    if (m->on1.size() > 32) JPH::PruneContactPoints(m->first_normal, m->on1, m->on2);
  }

  /// Normalises each manifold's normal and prunes it to 4 points; returns the points kept.
  int finish() {
    int points = 0;
    for (int i = 0; i < count; ++i) {
      Manifold& m = manifolds[i];
      const Vec3 normal = m.normal_sum.Normalized();
      if (m.on1.size() > 4) JPH::PruneContactPoints(normal, m.on1, m.on2);
      points += static_cast<int>(m.on1.size());
    }
    return points;
  }

  void reset() {
    ResetEarlyOutFraction();
    count = 0;
  }

  std::array<Manifold, kMaxManifoldsPerPair> manifolds;
  int count = 0;

 private:
  float max_contact_distance_ = 0.0f;
  float cos_max_delta_ = 1.0f;
};

}  // namespace

// ---- the collision work of a physics step -------------------------------------------------------

class StepWorld {
 public:
  Layers layers;
  LayerVsTree layer_vs_tree;
  LayerPairs layer_pairs;
  JPH::BodyManager bodies;  ///< destroys the bodies it holds, after the broad phase goes
  JPH::BroadPhaseQuadTree broad_phase;
  std::vector<JPH::BodyID> moving;       ///< the bodies, in the caller's order
  std::vector<JPH::BodyID> find_buffer;  ///< FindCollidingPairs may reorder its input: a copy
  PairCollector pairs;
  JPH::PhysicsSettings settings;  ///< defaults: manifold tolerance, normal merge angle
  ReducingCollector collector;
  JPH::BodyLockInterfaceNoLock lock{bodies};  ///< single-threaded queries: no locking
  JPH::NarrowPhaseQuery query;                ///< ray casts over broad_phase and bodies

  JPH::BodyID level;
};

void StepWorldDeleter::operator()(StepWorld* w) const {
  const ClearUpperOnReturn clear_upper;
  delete w;
}

StepWorldPtr make_step_world(const Mesh& level, std::span<const Convex* const> shapes,
                             std::span<const Pose> poses) {
  const ClearUpperOnReturn clear_upper;
  init();
  StepWorldPtr w(new StepWorld);
  const auto body_count = static_cast<JPH::uint>(shapes.size());
  w->bodies.Init(body_count + 1, 0, w->layers);
  w->broad_phase.Init(&w->bodies, w->layers);

  const auto add = [&](const JPH::BodyCreationSettings& settings) {
    JPH::Body* body = w->bodies.AllocateBody(settings);
    w->bodies.AddBody(body);
    return body->GetID();
  };
  w->level = add(JPH::BodyCreationSettings(level.shape, JPH::RVec3::sZero(), JPH::Quat::sIdentity(),
                                           JPH::EMotionType::Static, kLevelLayer));
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    JPH::BodyCreationSettings settings(shapes[i]->shape, to_jolt(poses[i].p), to_jolt(poses[i].q),
                                       JPH::EMotionType::Kinematic, kMovingLayer);
    settings.mCollideKinematicVsNonDynamic = true;  // kinematic bodies report contacts too
    w->moving.push_back(add(settings));
  }
  std::vector<JPH::BodyID> all = w->moving;
  all.push_back(w->level);
  const JPH::BroadPhase::AddState state = w->broad_phase.AddBodiesPrepare(all.data(), static_cast<int>(all.size()));
  w->broad_phase.AddBodiesFinalize(all.data(), static_cast<int>(all.size()), state);
  w->bodies.ActivateBodies(w->moving.data(), static_cast<int>(w->moving.size()));
  w->broad_phase.Optimize();
  w->query.Init(w->lock, w->broad_phase);
  w->find_buffer.resize(w->moving.size());
  w->pairs.pairs.reserve(4 * w->moving.size());
  return w;
}

StepCounts step(StepWorld& w, std::span<const Pose> from, std::span<const Vec> velocities,
                std::span<const Vec> angular, float dt, float margin) {
  const ClearUpperOnReturn clear_upper;
  StepCounts counts;
  JPH::BodyVector& all = w.bodies.GetBodies();

  // 1. Move.
  for (std::size_t i = 0; i < w.moving.size(); ++i) {
    JPH::Body& body = *all[w.moving[i].GetIndex()];
    body.SetPositionAndRotationInternal(to_jolt(from[i].p), to_jolt(from[i].q), false);
    const Vec3 v = to_jolt(velocities[i]);
    const Vec3 omega = to_jolt(angular[i]);
    body.SetLinearVelocity(v);
    body.SetAngularVelocity(omega);
    body.AddRotationStep(omega * dt);
    body.AddPositionStep(v * dt);
    body.CalculateWorldSpaceBoundsInternal();
  }
  w.find_buffer = w.moving;
  w.broad_phase.NotifyBodiesAABBChanged(w.find_buffer.data(), static_cast<int>(w.find_buffer.size()), true);

  // 2. Broad phase.
  w.broad_phase.FrameSync();
  w.broad_phase.LockModifications();
  const JPH::BroadPhase::UpdateState update = w.broad_phase.UpdatePrepare();
  w.broad_phase.UpdateFinalize(update);
  w.broad_phase.UnlockModifications();
  w.pairs.pairs.clear();
  w.find_buffer = w.moving;
  w.broad_phase.FindCollidingPairs(w.find_buffer.data(), static_cast<int>(w.find_buffer.size()), margin,
                                   w.layer_vs_tree, w.layer_pairs, w.pairs);

  // 3. Narrow phase, in the first body's centre-of-mass frame: the body of the higher motion
  // type (a moving body against the level), else the lower id (PhysicsSystem::ProcessBodyPair).
  JPH::CollideShapeSettings settings;
  settings.mCollectFacesMode = JPH::ECollectFacesMode::CollectFaces;
  settings.mActiveEdgeMode = w.settings.mCheckActiveEdges ? JPH::EActiveEdgeMode::CollideOnlyWithActive
                                                          : JPH::EActiveEdgeMode::CollideWithAll;
  settings.mMaxSeparationDistance = margin;
  settings.mBackFaceMode = JPH::EBackFaceMode::CollideWithBackFaces;  // two-sided, as collide's
  ReducingCollector& collector = w.collector;
  collector.configure(margin + w.settings.mManifoldTolerance, w.settings.mContactNormalCosMaxDeltaRotation);
  for (const JPH::BodyPair& pair : w.pairs.pairs) {
    const JPH::Body* a = all[pair.mBodyA.GetIndex()];
    const JPH::Body* b = all[pair.mBodyB.GetIndex()];
    if (a->GetMotionType() < b->GetMotionType() ||
        (a->GetMotionType() == b->GetMotionType() && pair.mBodyB < pair.mBodyA)) {
      std::swap(a, b);
    }
    const bool with_level = b->IsStatic();
    (with_level ? counts.level_pairs : counts.body_pairs) += 1;
    settings.mActiveEdgeMovementDirection = a->GetLinearVelocity() - b->GetLinearVelocity();
    const JPH::RVec3 offset = a->GetCenterOfMassPosition();
    const JPH::Mat44 xa = JPH::Mat44::sRotation(a->GetRotation());
    const JPH::Mat44 xb = b->GetCenterOfMassTransform().PostTranslated(-offset).ToMat44();
    collector.reset();
    JPH::CollisionDispatch::sCollideShapeVsShape(a->GetShape(), b->GetShape(), Vec3::sOne(), Vec3::sOne(), xa, xb,
                                                 JPH::SubShapeIDCreator(), JPH::SubShapeIDCreator(), settings,
                                                 collector);
    if (collector.count == 0) continue;
    (with_level ? counts.touching_level : counts.touching_bodies) += 1;
    counts.manifolds += collector.count;
    counts.points += collector.finish();
  }
  return counts;
}

Pose pose(const StepWorld& w, int body) {
  const ClearUpperOnReturn clear_upper;
  const JPH::Body& b = *w.bodies.GetBodies()[w.moving[static_cast<std::size_t>(body)].GetIndex()];
  const JPH::Quat q = b.GetRotation();
  return {from_jolt(JPH::Vec3(b.GetPosition())), {q.GetX(), q.GetY(), q.GetZ(), q.GetW()}};
}

WorldRayHit cast_ray(const StepWorld& w, Vec origin, Vec translation) {
  const ClearUpperOnReturn clear_upper;
  const JPH::RRayCast ray{to_jolt(origin), to_jolt(translation)};
  JPH::RayCastResult hit;
  if (!w.query.CastRay(ray, hit)) return {};
  const JPH::Body& body = *w.bodies.GetBodies()[hit.mBodyID.GetIndex()];
  const JPH::RVec3 point = ray.GetPointOnRay(hit.mFraction);
  const Vec3 normal = body.GetWorldSpaceSurfaceNormal(hit.mSubShapeID2, point);
  return {true, hit.mFraction, from_jolt(Vec3(point)), from_jolt(normal)};
}

// ---- a character walking a level ------------------------------------------------------------------

/// Temporary memory of CharacterVirtual's queries.
constexpr std::size_t kCharacterTempBytes = 4u << 20;

class CharacterWorld {
 public:
  Layers layers;
  LayerVsTree layer_vs_tree;
  LayerPairs layer_pairs;
  JPH::PhysicsSystem system;
  JPH::TempAllocatorImpl temp{kCharacterTempBytes};
};

void CharacterWorldDeleter::operator()(CharacterWorld* w) const {
  const ClearUpperOnReturn clear_upper;
  delete w;
}

CharacterWorldPtr make_character_world(const Mesh& level) {
  const ClearUpperOnReturn clear_upper;
  init();
  CharacterWorldPtr w(new CharacterWorld);
  constexpr JPH::uint kMaxBodies = 16, kMaxBodyPairs = 64, kMaxContacts = 64;
  w->system.Init(kMaxBodies, 0, kMaxBodyPairs, kMaxContacts, w->layers, w->layer_vs_tree, w->layer_pairs);
  JPH::BodyInterface& bodies = w->system.GetBodyInterfaceNoLock();
  bodies.CreateAndAddBody(JPH::BodyCreationSettings(level.shape, JPH::RVec3::sZero(), JPH::Quat::sIdentity(),
                                                    JPH::EMotionType::Static, kLevelLayer),
                          JPH::EActivation::DontActivate);
  w->system.OptimizeBroadPhase();
  return w;
}

class Character {
 public:
  CharacterWorld* world = nullptr;
  JPH::Ref<JPH::CharacterVirtual> character;
  JPH::CharacterVirtual::ExtendedUpdateSettings update;
};

void CharacterDeleter::operator()(Character* c) const {
  const ClearUpperOnReturn clear_upper;
  delete c;
}

CharacterPtr make_character(CharacterWorld& world, const CharacterSettings& s, Vec position) {
  const ClearUpperOnReturn clear_upper;
  JPH::Ref<JPH::CharacterVirtualSettings> settings = new JPH::CharacterVirtualSettings;
  settings->mShape = new JPH::CapsuleShape(s.half_height, s.radius);
  settings->mUp = Vec3::sAxisY();
  settings->mMaxSlopeAngle = s.max_slope;
  // Supporting contacts: below the plane through the bottom sphere's centre (y = -half_height).
  settings->mSupportingVolume = JPH::Plane(Vec3::sAxisY(), s.half_height);
  settings->mCharacterPadding = s.padding;
  settings->mPredictiveContactDistance = s.predictive_distance;
  CharacterPtr c(new Character);
  c->world = &world;
  c->character = new JPH::CharacterVirtual(settings, to_jolt(position), JPH::Quat::sIdentity(), 0, &world.system);
  c->update.mWalkStairsStepUp = Vec3(0.0f, s.step_height, 0.0f);
  c->update.mStickToFloorStepDown = Vec3(0.0f, -s.step_height, 0.0f);
  c->update.mWalkStairsStepForwardTest = s.step_forward_test;
  return c;
}

CharacterOut move(Character& c, Vec velocity, float dt, Vec gravity) {
  const ClearUpperOnReturn clear_upper;
  JPH::PhysicsSystem& system = c.world->system;
  c.character->SetLinearVelocity(to_jolt(velocity));
  c.character->ExtendedUpdate(dt, to_jolt(gravity), c.update, system.GetDefaultBroadPhaseLayerFilter(kMovingLayer),
                              system.GetDefaultLayerFilter(kMovingLayer), {}, {}, c.world->temp);
  CharacterOut out;
  out.position = from_jolt(JPH::Vec3(c.character->GetPosition()));
  out.grounded = c.character->GetGroundState() == JPH::CharacterBase::EGroundState::OnGround;
  return out;
}

void place(Character& c, Vec position) {
  const ClearUpperOnReturn clear_upper;
  c.character->SetPosition(to_jolt(position));
  c.character->SetLinearVelocity(Vec3::sZero());
}

}  // namespace jolt_queries
