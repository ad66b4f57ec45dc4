#pragma once
// The determinism check both runs share (2D run_world, 3D run_world3d): the state hash is a
// function of the options that choose what happens, not of how the world finds it.

#include "run.hpp"

#include <gtest/gtest.h>

#include <initializer_list>

namespace collide::test {

using cli::RunOptions;

/// Expects `run(options).state_hash` to be the same on a second run, with each broad phase of
/// `broad_phases` and with the fixed early-out order, and to differ with another seed.
template <class Run>
void expect_hash_independent_of_choices(Run&& run, const RunOptions& options,
                                        std::initializer_list<WorldBroadPhase> broad_phases) {
  const auto hash = run(options).state_hash;
  EXPECT_EQ(run(options).state_hash, hash);
  for (const WorldBroadPhase bp : broad_phases) {
    RunOptions o = options;
    o.broad_phase = bp;
    EXPECT_EQ(run(o).state_hash, hash) << to_string(bp);
  }
  RunOptions fixed = options;
  fixed.adaptive_early_out = false;
  EXPECT_EQ(run(fixed).state_hash, hash);
  RunOptions other_seed = options;
  other_seed.seed = options.seed + 1;
  EXPECT_NE(run(other_seed).state_hash, hash);
}

}  // namespace collide::test
