#pragma once
// collide's vectors and placements in jolt_queries' plain types and back, for the benchmarks
// and tests that race or check collide against Jolt. Header only: compiled with the includer's
// flags (collide's), never with Jolt's.

#include <collide/core/transform3.hpp>

#include "jolt_queries.hpp"

namespace collide::test {

/// `v` as jolt_queries::Vec.
[[nodiscard]] inline jolt_queries::Vec jolt_vec(Vec3 v) { return {v.x, v.y, v.z}; }

/// A jolt_queries::Vec back as collide's Vec3.
[[nodiscard]] inline Vec3 from_jolt(const jolt_queries::Vec& v) { return {v.x, v.y, v.z}; }

/// `xf` as a jolt_queries::Pose (the quaternion as x, y, z, w).
[[nodiscard]] inline jolt_queries::Pose jolt_pose(const Transform3& xf) {
  return {jolt_vec(xf.p), {xf.q.x, xf.q.y, xf.q.z, xf.q.w}};
}

}  // namespace collide::test
