#pragma once
// What the sources of `collide_jolt_queries` share behind jolt_queries.hpp's plain types: the
// Jolt objects the opaque handles hold, and the guard every entry point starts with. Included
// only by those sources (compiled with Jolt's headers and instruction set), never by a caller.

#include "jolt_queries.hpp"

#include <Jolt/Jolt.h>

#include <Jolt/Physics/Collision/BroadPhase/BroadPhaseLayer.h>
#include <Jolt/Physics/Collision/ObjectLayer.h>
#include <Jolt/Physics/Collision/Shape/ConvexShape.h>
#include <Jolt/Physics/Collision/Shape/Shape.h>

#include <array>

#if defined(__AVX__)
#include <immintrin.h>
#endif

namespace jolt_queries {

/// Clears the upper halves of the vector registers when an entry point returns. Some of Jolt's
/// paths return with them in use (mesh_contact: its collide dispatch), though compiled AVX code
/// is expected to clear them (vzeroupper) before returning to code that may use SSE. The
/// baseline SSE code that runs next (collide's side of every benchmark) then pays a false
/// dependency on each vector register it writes, for as long as nothing clears them: collide's
/// capsule against a level ran 45% slower after one Jolt call on a Zen 4 host (6.6 -> 9.6 us).
/// Jolt's own (VEX) code pays nothing either way, and the instruction costs a cycle. Every
/// function of the library that runs Jolt code declares one first.
struct ClearUpperOnReturn {
  ClearUpperOnReturn() = default;
  ClearUpperOnReturn(const ClearUpperOnReturn&) = delete;
  ClearUpperOnReturn& operator=(const ClearUpperOnReturn&) = delete;
#if defined(__AVX__)
  ~ClearUpperOnReturn() { _mm256_zeroupper(); }
#endif
};

/// A level: a JPH::MeshShape (make_mesh) or a JPH::HeightFieldShape (make_height_field,
/// jolt_scale_world.hpp).
class Mesh {
 public:
  JPH::RefConst<JPH::Shape> shape;
};

/// A convex JPH::Shape with convex radius 0 (make_box, make_capsule, make_convex, make_sphere).
class Convex {
 public:
  JPH::RefConst<JPH::ConvexShape> shape;
};

inline JPH::Vec3 to_jolt(Vec v) { return JPH::Vec3(v.x, v.y, v.z); }
inline Vec from_jolt(JPH::Vec3Arg v) { return {v.GetX(), v.GetY(), v.GetZ()}; }
/// A quaternion given as (x, y, z, w).
inline JPH::Quat to_jolt(const std::array<float, 4>& q) { return JPH::Quat(q[0], q[1], q[2], q[3]); }

// ---- layers: moving bodies and the level (jolt_world.cpp, jolt_scale_world.cpp) ----------------

/// Object layers, each in a broad phase layer (tree) of its own, as Jolt's samples do: the level
/// never moves, so its tree is never rebuilt.
inline constexpr JPH::ObjectLayer kLevelLayer = 0;
inline constexpr JPH::ObjectLayer kMovingLayer = 1;
inline constexpr JPH::uint kLayerCount = 2;

class Layers final : public JPH::BroadPhaseLayerInterface {
 public:
  JPH::uint GetNumBroadPhaseLayers() const override { return kLayerCount; }
  JPH::BroadPhaseLayer GetBroadPhaseLayer(JPH::ObjectLayer layer) const override {
    return JPH::BroadPhaseLayer(static_cast<JPH::BroadPhaseLayer::Type>(layer));
  }
#if defined(JPH_EXTERNAL_PROFILE) || defined(JPH_PROFILE_ENABLED)
  const char* GetBroadPhaseLayerName(JPH::BroadPhaseLayer layer) const override {
    return layer.GetValue() == kLevelLayer ? "level" : "moving";
  }
#endif
};

/// Moving bodies meet everything; the level meets moving bodies only.
inline bool layers_meet(JPH::ObjectLayer a, JPH::ObjectLayer b) {
  return a == kMovingLayer || b == kMovingLayer;
}

class LayerVsTree final : public JPH::ObjectVsBroadPhaseLayerFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer layer, JPH::BroadPhaseLayer tree) const override {
    return layers_meet(layer, static_cast<JPH::ObjectLayer>(tree.GetValue()));
  }
};

class LayerPairs final : public JPH::ObjectLayerPairFilter {
 public:
  bool ShouldCollide(JPH::ObjectLayer a, JPH::ObjectLayer b) const override { return layers_meet(a, b); }
};

}  // namespace jolt_queries
