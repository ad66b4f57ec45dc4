#pragma once
/// @file
/// The broad phases by name, for tools (`collide query`'s `pairs` op) and comparisons: every
/// name gives exactly the same pairs, only the speed differs.

#include <collide/broad/broad_phase.hpp>

#include <span>
#include <string_view>

namespace collide {

/// A broad phase the registry knows: its name and a one-line description for `--help`.
struct BroadPhaseInfo {
  /// The name find_pairs and `collide query`'s "broadphase" field take, e.g. "hash_grid".
  std::string_view name;
  /// One line for `--help`: what the structure is and when to pick it.
  std::string_view description;
};

/// All registered broad phases, the default first.
[[nodiscard]] std::span<const BroadPhaseInfo> broadphases() noexcept;

/// The names of broadphases(), the default first.
[[nodiscard]] std::span<const std::string_view> broadphase_names() noexcept;

/// Every overlapping pair (touching counts) of the 2D boxes, found by the named broad phase:
/// (i, j) with i < j, sorted lexicographically, each once. An empty name means the default.
/// Throws InvalidInput for an unknown name (the message lists the valid names) or a box with a
/// non-finite coordinate or min > max (the message names the box index).
[[nodiscard]] PairList find_pairs(std::string_view name, std::span<const Aabb> boxes);

/// The same for 3D boxes.
[[nodiscard]] PairList find_pairs(std::string_view name, std::span<const Aabb3> boxes);

}  // namespace collide
