#pragma once
// What the sources of `collide_jolt_queries` share behind jolt_queries.hpp's plain types: the
// Jolt objects the opaque handles hold, and the guard every entry point starts with. Included
// only by those sources (compiled with Jolt's headers and instruction set), never by a caller.

#include "jolt_queries.hpp"

#include <Jolt/Jolt.h>

#include <Jolt/Physics/Collision/Shape/ConvexShape.h>
#include <Jolt/Physics/Collision/Shape/Shape.h>

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

/// A level: a JPH::MeshShape (make_mesh).
class Mesh {
 public:
  JPH::RefConst<JPH::Shape> shape;
};

/// A convex JPH::Shape with convex radius 0 (make_box, make_capsule, make_convex, make_sphere).
class Convex {
 public:
  JPH::RefConst<JPH::ConvexShape> shape;
};

}  // namespace jolt_queries
