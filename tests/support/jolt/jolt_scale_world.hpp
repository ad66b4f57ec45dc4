#pragma once
// Jolt's PhysicsSystem stepping a whole world of kinematic bodies among static level pieces,
// behind plain types (part of `collide_jolt_queries`, compiled with Jolt's headers and
// instruction set; see jolt_queries.hpp): the rival of World3D::step at 1e3 .. 1e6 bodies in
// bench_world_scale3d. Unlike jolt_world.hpp's StepWorld (Jolt's collision pieces called one by
// one, on one thread), this is PhysicsSystem::Update itself, with its job system: what a game
// running Jolt pays per frame when nothing needs solving. Each entry point clears the upper
// vector state on return (jolt_internal.hpp).
//
// Units and frames: world units (metres), seconds, radians; y up only where a height field
// says so. A Pose is a shape's own frame (the frame its make_* function took), as
// BodyCreationSettings takes a body's position and rotation; Jolt puts the centre of mass where
// the shape says.

#include "jolt_queries.hpp"

#include <cstdint>
#include <memory>
#include <span>

namespace jolt_queries {

/// JPH::HeightFieldShape of samples_x == samples_z = `samples` samples, row by row
/// (`heights[j * samples + i]`), sample (i, j) at local point
/// origin + (i * spacing_x, heights[j * samples + i], j * spacing_z): rows along +z, columns
/// along +x, cell (i, j) split along its (i, j)-(i + 1, j + 1) diagonal (collide's HeightField
/// layout and triangles). Jolt pads the sample count to a multiple of its block size (2) with
/// no-collision samples and stores heights quantised (8 bits per sample within each block's
/// range: an error of at most the block's height range / 255). Returned in a Mesh handle (a
/// level piece). nullptr if Jolt rejects it.
MeshPtr make_height_field(int samples, std::span<const float> heights, float spacing_x, float spacing_z,
                          Vec origin);

/// A static piece of the level: one shape, exactly one of `level` (a MeshShape or
/// HeightFieldShape) and `convex` set, placed by `pose`. The handle must outlive make_scale_world
/// only (Jolt keeps the shape by reference count).
struct ScaleStatic {
  const Mesh* level = nullptr;
  const Convex* convex = nullptr;
  Pose pose;
};

/// A moving body: one convex shape placed by `pose`, moving at `velocity` (world units per
/// second) and `angular` (rotation vector, radians per second, world space) about its centre of
/// mass. Handles as ScaleStatic.
struct ScaleBody {
  const Convex* shape = nullptr;
  Pose pose;
  Vec velocity;
  Vec angular;
};

/// What a PhysicsSystem is given room for: every capacity Jolt fixes at Init, per moving body
/// (so that a 1e5 world fits; Update reports an overflow in ScaleStepOut::errors).
struct ScaleCapacity {
  int body_pairs_per_body = 16;        ///< PhysicsSystem::Init's inMaxBodyPairs / bodies
  int contacts_per_body = 8;           ///< inMaxContactConstraints / bodies (cached manifolds too)
  /// The step's temporary allocator block (TempAllocatorImplWithMallocFallback: malloc serves
  /// what does not fit), per body; at least 32 MB, at most 3 GB (its size is 32-bit).
  std::size_t temp_bytes_per_body = 4096;
};

/// A JPH::PhysicsSystem (BroadPhaseQuadTree, two broad phase layers: the level and moving
/// bodies, as jolt_world.hpp's worlds) holding each static as a static body and each body as a
/// KINEMATIC body with mCollideKinematicVsNonDynamic (it collides with statics and other
/// kinematic bodies, reports contacts, and is never pushed: no contact constraint is made
/// between non-dynamic bodies), discrete motion quality (Jolt casts dynamic bodies only),
/// sleeping off, maximum speeds raised so that no velocity is clamped; gravity zero; a
/// ContactListener counting OnContactAdded / OnContactPersisted manifolds; a
/// JobSystemThreadPool of `threads` - 1 worker threads (Update's thread runs jobs too while it
/// waits: `threads` run at once; 1: Update runs every job itself) and a temporary allocator
/// (ScaleCapacity).
/// The broad phase is optimised (OptimizeBroadPhase) after the bodies are added.
class ScaleWorld;
struct ScaleWorldDeleter {
  void operator()(ScaleWorld* w) const;
};
using ScaleWorldPtr = std::unique_ptr<ScaleWorld, ScaleWorldDeleter>;
ScaleWorldPtr make_scale_world(std::span<const ScaleStatic> statics, std::span<const ScaleBody> bodies, int threads,
                               const ScaleCapacity& capacity = {});

/// Puts every body where `bodies[i]` says, with its velocities (BodyInterface::
/// SetPositionRotationAndVelocity without locking; the broad phase is told of boxes that left
/// their fattened bounds, as Jolt always does); `bodies` in make_scale_world's order, same
/// count, shapes ignored. For keeping the world in step with another simulation between
/// Updates.
void set_bodies(ScaleWorld& world, std::span<const ScaleBody> bodies);

/// What one Update did.
struct ScaleStepOut {
  std::uint32_t errors = 0;       ///< JPH::EPhysicsUpdateError bits: 0 unless a capacity overflowed
  std::int64_t added = 0;         ///< manifolds reported by OnContactAdded (pairs starting to touch)
  std::int64_t persisted = 0;     ///< manifolds reported by OnContactPersisted (still touching)
};

/// PhysicsSystem::Update(`dt`, 1 collision step): integrate (positions by velocities), broad
/// phase update and pair finding (speculative contact distance of PhysicsSettings, 0.02),
/// narrow phase on every pair not served by the body pair cache, contact callbacks, the
/// (empty) constraint solve, no sleeping.
ScaleStepOut step(ScaleWorld& world, float dt);

/// Body i's pose (its shape's own frame), as ScaleBody takes it.
Pose pose(const ScaleWorld& world, int body);

}  // namespace jolt_queries
