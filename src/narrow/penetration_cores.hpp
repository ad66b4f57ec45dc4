#pragma once
/// @file
/// epa_penetration's work with its route told: GJK on the cores, then EPA when they overlap.
/// `contact` asks it once where it would otherwise run GJK for the distance and again inside
/// epa_penetration. Internal to the narrow phase.

#include <collide/narrow/epa.hpp>

namespace collide::detail {

/// What penetration_of_cores found: epa_penetration's answer, and which step gave it.
struct CorePenetration {
  PenetrationResult3 result;
  /// True: the cores (the shapes without their radii) overlap or touch and EPA gave the
  /// answer. False: they are apart and the answer is GJK's closest points (the shapes may
  /// still overlap through their radii; status max_iterations when GJK did not converge).
  bool cores_overlap = false;
};

/// epa_penetration (epa.hpp) with the step that answered; same arguments, same result.
[[nodiscard]] CorePenetration penetration_of_cores(const ConvexProxy3& a, const Transform3& xa,
                                                   const ConvexProxy3& b,
                                                   const Transform3& xb) noexcept;

}  // namespace collide::detail
