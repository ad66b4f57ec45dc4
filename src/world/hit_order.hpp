#pragma once
/// @file
/// The order of the world's query hits, shared by its queries (world_queries.cpp) and the
/// character mover (character.cpp), which merges hits of two queries as one would order them.
/// Internal to src/world.

#include <collide/world/world.hpp>

namespace collide::detail {

/// Is candidate `c` (fraction t) better than the best so far? Earlier wins; ties go to the
/// smaller collider key, so results do not depend on the order structures visit candidates.
[[nodiscard]] inline bool better(float t, const ColliderRef& c, bool have_best, float best_t,
                                 const ColliderRef& best) noexcept {
  return !have_best || t < best_t || (t == best_t && c.key() < best.key());
}

}  // namespace collide::detail
