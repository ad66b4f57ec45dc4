#pragma once
// Jolt Physics doing a game world's per-frame collision work, behind plain types (part of
// `collide_jolt_queries`, compiled with Jolt's headers and instruction set; see
// jolt_queries.hpp): the collision half of a physics step over a level (bench_world3d's rival
// of World3D::step) and CharacterVirtual walking a level (the rival of move_character). Each
// entry point clears the upper vector state on return (jolt_internal.hpp), so the collide code a
// benchmark runs next is not slowed by Jolt's AVX code.

#include "jolt_queries.hpp"

#include <memory>
#include <span>

namespace jolt_queries {

// ---- the collision work of a physics step (bench_world3d) --------------------------------------

/// Jolt's own pieces of a PhysicsSystem that find contacts, used without the rest (no solver, no
/// constraints, no contact cache): a BodyManager holding the level (a static body of `level`'s
/// MeshShape) and one kinematic body per convex shape, and a BroadPhaseQuadTree over them (two
/// broad phase layers: moving bodies and the level, as Jolt's samples set them up).
class StepWorld;
struct StepWorldDeleter {
  void operator()(StepWorld* w) const;
};
using StepWorldPtr = std::unique_ptr<StepWorld, StepWorldDeleter>;

/// The world with body i of shape `shapes[i]` (kept by reference count, the caller's handle may
/// go) placed by `poses[i]` (the shape's own frame, as make_box/make_convex... took it; Jolt puts
/// its centre of mass where the shape says). Bodies collide with each other and the level
/// (kinematic bodies with mCollideKinematicVsNonDynamic).
StepWorldPtr make_step_world(const Mesh& level, std::span<const Convex* const> shapes,
                             std::span<const Pose> poses);

/// What one step found (the pairs and contacts the work produced, for the benchmark's counters).
struct StepCounts {
  int body_pairs = 0;      ///< body-body pairs from the broad phase (FindCollidingPairs)
  int level_pairs = 0;     ///< body-level pairs from the broad phase
  int touching_bodies = 0; ///< body-body pairs with at least one manifold
  int touching_level = 0;  ///< body-level pairs with at least one manifold
  int manifolds = 0;       ///< manifolds after reduction, over all pairs
  int points = 0;          ///< contact points over all manifolds (at most 4 each)
};

/// One step's collision work, as PhysicsSystem::Update does it minus the solver:
///  1. Move: each body placed at `from[i]` (the pose the caller's recording had before this
///     step), then moved as the step's integration moves a body (JobIntegrateVelocity:
///     AddRotationStep by `angular[i]` * dt about its centre of mass, AddPositionStep by
///     `velocities[i]` * dt, angular in radians per second, world space), its world bounds
///     recomputed (CalculateWorldSpaceBoundsInternal) and the broad phase told
///     (NotifyBodiesAABBChanged). The linear velocity also steers active edges.
///  2. Broad phase: UpdatePrepare / UpdateFinalize (the quad tree rebuilt where bodies moved),
///     then FindCollidingPairs for every body (speculative distance `margin`).
///  3. Narrow phase, each pair: CollisionDispatch::sCollideShapeVsShape in the first body's
///     centre-of-mass frame (faces collected, active edges on, mMaxSeparationDistance `margin`,
///     back faces collided with: collide's triangles are two-sided), each result made a manifold
///     (ManifoldBetweenTwoFaces), results with normals within PhysicsSettings'
///     mContactNormalCosMaxDeltaRotation merged into one manifold and pruned to 4 points
///     (PruneContactPoints), as PhysicsSystem's manifold reduction does.
StepCounts step(StepWorld& world, std::span<const Pose> from, std::span<const Vec> velocities,
                std::span<const Vec> angular, float dt, float margin);

/// Where body i is: the pose of its shape's own frame (as `from` takes it).
Pose pose(const StepWorld& world, int body);

/// The closest hit of a ray cast into the world (bench_world3d's rival of World3D::raycast).
struct WorldRayHit {
  bool hit = false;
  float fraction = 0.0f;  ///< along the translation
  Vec point;              ///< world space
  Vec normal;             ///< world space, unit
};

/// NarrowPhaseQuery::CastRay over the world's bodies and level (the broad phase's quad tree, then
/// each body's shape, the closest hit; convex shapes solid: a ray starting inside one hits it at
/// fraction 0), and the hit body's GetWorldSpaceSurfaceNormal at the hit: the closest hit with
/// point and normal, as a game's laser or line of sight asks. The bodies where the last `step`
/// left them.
WorldRayHit cast_ray(const StepWorld& world, Vec origin, Vec translation);

// ---- a character walking a level (bench_world3d) -----------------------------------------------

/// A PhysicsSystem holding the level (a static body of `level`'s MeshShape), where
/// CharacterVirtual walks; single-threaded.
class CharacterWorld;
struct CharacterWorldDeleter {
  void operator()(CharacterWorld* w) const;
};
using CharacterWorldPtr = std::unique_ptr<CharacterWorld, CharacterWorldDeleter>;
CharacterWorldPtr make_character_world(const Mesh& level);

/// A character as CharacterVirtualSettings and ExtendedUpdateSettings take it, y up.
struct CharacterSettings {
  float radius = 0.3f;           ///< capsule radius
  float half_height = 0.6f;      ///< half length of the capsule's core segment (along y)
  float max_slope = 0.872664626f;  ///< mMaxSlopeAngle, radians
  float step_height = 0.4f;      ///< mWalkStairsStepUp and -mStickToFloorStepDown, along y
  float step_forward_test = 0.15f;  ///< mWalkStairsStepForwardTest
  float padding = 0.02f;         ///< mCharacterPadding
  float predictive_distance = 0.1f;  ///< mPredictiveContactDistance
};

/// A JPH::CharacterVirtual: a capsule whose centre is at `position`, supporting volume the
/// plane through the bottom sphere's centre (Jolt samples' choice: only contacts below it hold
/// the character up).
class Character;
struct CharacterDeleter {
  void operator()(Character* c) const;
};
using CharacterPtr = std::unique_ptr<Character, CharacterDeleter>;
CharacterPtr make_character(CharacterWorld& world, const CharacterSettings& settings, Vec position);

struct CharacterOut {
  Vec position;           ///< the capsule's centre after the move
  bool grounded = false;  ///< GetGroundState() == OnGround (walkable ground)
};
/// One frame: SetLinearVelocity(`velocity`), then ExtendedUpdate(`dt`, `gravity`) with the
/// settings' stick to floor and stair walking (TempAllocatorImpl of the world, default filters).
CharacterOut move(Character& character, Vec velocity, float dt, Vec gravity);
/// Puts the character at `position` (SetPosition), its velocity zero.
void place(Character& character, Vec position);

}  // namespace jolt_queries
