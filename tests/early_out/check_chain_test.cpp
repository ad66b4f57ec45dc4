#include <collide/early_out/check_chain.hpp>

#include "support/test_util.hpp"

#include <algorithm>
#include <numeric>

namespace collide {
namespace {

// ---- the analysis -------------------------------------------------------------------------------

TEST(EarlyOut, LessonTwoChecksSlowSelectiveCheckGoesFirst) {
  // a: fast, rarely rejects. b: three times slower, rejects 90% of pairs.
  const std::vector<CheckStats> checks{{1.0, 0.9}, {3.0, 0.1}};
  const std::vector<int> a_first{0, 1}, b_first{1, 0};
  EXPECT_DOUBLE_EQ(expected_cost(checks, a_first), 1.0 + 0.9 * 3.0);  // t_a + p_a t_b
  EXPECT_DOUBLE_EQ(expected_cost(checks, b_first), 3.0 + 0.1 * 1.0);  // t_b + p_b t_a
  // t_b / (1 - p_b) = 3.33 < t_a / (1 - p_a) = 10: b first.
  EXPECT_LT(cost_per_rejection(checks[1]), cost_per_rejection(checks[0]));
  std::vector<int> order(2);
  optimal_order(checks, order);
  EXPECT_EQ(order, b_first);
  // And the fast check does go first when it is also the better rejector.
  const std::vector<CheckStats> other{{1.0, 0.5}, {3.0, 0.1}};
  optimal_order(other, order);
  EXPECT_EQ(order, a_first);
  EXPECT_LT(expected_cost(other, a_first), expected_cost(other, b_first));
}

TEST(EarlyOut, RankOrderIsOptimalAgainstEveryPermutation) {
  std::mt19937 rng(42);
  int strictly_better_than_fastest_first = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 6);
    std::vector<CheckStats> checks;
    for (int i = 0; i < n; ++i) {
      // Some checks never reject (p = 1) and some are free (t = 0): the edge cases of the rank.
      const double p = trial % 7 == 0 && i == 0 ? 1.0 : test::uniform(rng, 0.0f, 1.0f);
      const double t = trial % 11 == 0 && i == 1 ? 0.0 : test::uniform(rng, 0.1f, 10.0f);
      checks.push_back({t, p});
    }
    std::vector<int> order(static_cast<size_t>(n));
    optimal_order(checks, order);
    const double ours = expected_cost(checks, order);
    std::vector<int> perm(static_cast<size_t>(n));
    std::iota(perm.begin(), perm.end(), 0);
    double best = std::numeric_limits<double>::max();
    do {
      best = std::min(best, expected_cost(checks, perm));
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_NEAR(ours, best, 1e-9 * (1.0 + best));
    // The naive rule (fastest first) is beaten often enough that the rank matters.
    std::vector<int> fastest(static_cast<size_t>(n));
    std::iota(fastest.begin(), fastest.end(), 0);
    std::stable_sort(fastest.begin(), fastest.end(),
                     [&](int a, int b) { return checks[a].cost < checks[b].cost; });
    if (expected_cost(checks, fastest) > ours * (1.0 + 1e-9)) ++strictly_better_than_fastest_first;
  }
  EXPECT_GT(strictly_better_than_fastest_first, 100);
}

TEST(EarlyOut, RedundantPretestRule) {
  // Bounding circle (cost 1) before an exact test (cost 10).
  const CheckStats selective{1.0, 0.2};  // rejects 80% of pairs
  const CheckStats useless{1.0, 0.95};   // pairs from a good broad phase: almost all pass
  EXPECT_TRUE(pretest_pays(selective, 10.0));   // 1 < 0.8 * 10
  EXPECT_FALSE(pretest_pays(useless, 10.0));    // 1 > 0.05 * 10
  EXPECT_DOUBLE_EQ(cost_with_pretest(selective, 10.0), 1.0 + 0.2 * 10.0);
  // The rule is exactly "the pretest lowers the expected cost", on random cases.
  std::mt19937 rng(8);
  int pays = 0;
  for (int i = 0; i < 1000; ++i) {
    const CheckStats pre{test::uniform(rng, 0.0f, 5.0f), test::uniform(rng, 0.0f, 1.0f)};
    const double exact = test::uniform(rng, 0.0f, 20.0f);
    EXPECT_EQ(pretest_pays(pre, exact), cost_with_pretest(pre, exact) < exact);
    pays += pretest_pays(pre, exact);
  }
  EXPECT_GT(pays, 200);
  EXPECT_LT(pays, 800);
}

TEST(EarlyOut, OptimalOrderRejectsBadStatistics) {
  std::vector<int> order(2);
  const std::vector<CheckStats> bad_rate{{1.0, 1.5}, {1.0, 0.5}};
  const std::vector<CheckStats> bad_cost{{-1.0, 0.5}, {1.0, 0.5}};
  EXPECT_THROW(optimal_order(bad_rate, order), InvalidInput);
  EXPECT_THROW(optimal_order(bad_cost, order), InvalidInput);
  std::vector<int> short_order(1);
  EXPECT_THROW(optimal_order(std::vector<CheckStats>{{1, 0.5}, {1, 0.5}}, short_order), InvalidInput);
}

TEST(EarlyOut, RunningStatsAverageThenFollowChanges) {
  RunningStats s(1.0 / 16.0);
  for (int i = 0; i < 8; ++i) {
    s.add_cost(i % 2 == 0 ? 10.0 : 20.0);
    s.add_outcome(i % 4 == 0);
  }
  EXPECT_DOUBLE_EQ(s.stats().cost, 15.0);  // plain mean while n < 1/alpha
  EXPECT_DOUBLE_EQ(s.stats().pass_rate, 0.25);
  for (int i = 0; i < 400; ++i) s.add_cost(100.0);  // the scene changed
  EXPECT_NEAR(s.stats().cost, 100.0, 1e-6);
}

TEST(EarlyOut, RunningStatsClipPreemptionOutliers) {
  RunningStats s(1.0 / 16.0);
  for (int i = 0; i < 64; ++i) s.add_cost(100.0);
  s.add_cost(1e7);  // the thread was preempted for 10 ms during one measurement
  EXPECT_LE(s.stats().cost, 100.0 + (kCostOutlierFactor - 1.0) * 100.0 / 16.0 + 1e-9);
  EXPECT_GT(s.stats().cost, 100.0);  // it still counts, as a large but bounded sample
  for (int i = 0; i < 400; ++i) s.add_cost(1000.0);  // a real change is followed
  EXPECT_NEAR(s.stats().cost, 1000.0, 1e-3);
}

// ---- the online chain, on synthetic checks with a fake clock -------------------------------------

/// Synthetic checks with known costs and pass rates. Running one advances a fake clock by its
/// cost; outcomes are drawn from a fixed-seed generator. A pretest passes whenever its exact
/// check will (it is redundant) and otherwise passes with a given leak rate.
struct Synthetic {
  struct Check {
    double cost;
    double pass_rate;
    double pretest_cost = 0.0;
    double pretest_leak = 0.0;  ///< P(pretest passes | exact fails)
  };
  std::vector<Check> checks;
  std::mt19937 rng{123};
  double clock = 0.0;
  std::vector<int> outcome;  ///< this pair's exact outcome per check (drawn once per pair)
  std::vector<int> pre_outcome;

  void new_pair() {
    outcome.assign(checks.size(), 0);
    pre_outcome.assign(checks.size(), 0);
    for (size_t i = 0; i < checks.size(); ++i) {
      outcome[i] = test::uniform(rng, 0.0f, 1.0f) < checks[i].pass_rate;
      pre_outcome[i] = outcome[i] || test::uniform(rng, 0.0f, 1.0f) < checks[i].pretest_leak;
    }
  }
  bool run(int i, CheckStage stage) {
    const Check& c = checks[static_cast<size_t>(i)];
    clock += stage == CheckStage::exact ? c.cost : c.pretest_cost;
    return stage == CheckStage::exact ? outcome[i] : pre_outcome[i];
  }
};

TEST(EarlyOut, ChainLearnsTheOptimalOrderFromMeasurements) {
  Synthetic s;
  s.checks = {{1.0, 0.99}, {2.0, 0.95}, {10.0, 0.02}, {5.0, 0.9}};
  std::vector<CheckStats> truth;
  for (const auto& c : s.checks) truth.push_back({c.cost, c.pass_rate});
  std::vector<int> best(truth.size());
  optimal_order(truth, best);
  ASSERT_NE(best, (std::vector<int>{0, 1, 2, 3}));  // declaration order is not already optimal

  const std::array<bool, 4> no_pretests{};
  CheckChainOptions options;
  options.alpha = 1.0 / 1024.0;  // long memory: the synthetic scene does not change
  CheckChain<8> chain(no_pretests, options);
  int hits = 0;
  const int n = 20000;
  for (int e = 0; e < n; ++e) {
    s.new_pair();
    const bool expected = std::all_of(s.outcome.begin(), s.outcome.end(), [](int o) { return o; });
    const bool got = chain.evaluate([&](int i, CheckStage st) { return s.run(i, st); },
                                    [&] { return s.clock; });
    EXPECT_EQ(got, expected);  // reordering never changes the answer
    hits += got;
  }
  EXPECT_GT(hits, 0);  // both outcomes occur
  EXPECT_LT(hits, n);
  EXPECT_EQ(std::vector<int>(chain.order().begin(), chain.order().end()), best);
  const CheckChainReport r = chain.report();
  EXPECT_EQ(r.evaluations, static_cast<std::uint64_t>(n));
  EXPECT_EQ(r.rejections, static_cast<std::uint64_t>(n - hits));
  // Model cost of the learned order matches the true optimum; the fixed order is worse, and the
  // clock agrees (exploring evaluations run everything, so measured sits a little above).
  const std::vector<int> declared{0, 1, 2, 3};
  EXPECT_NEAR(r.expected_cost, expected_cost(truth, best), 0.1 * expected_cost(truth, best));
  EXPECT_NEAR(r.fixed_order_cost, expected_cost(truth, declared), 0.1 * expected_cost(truth, declared));
  const double saved = 1.0 - expected_cost(truth, best) / expected_cost(truth, declared);
  EXPECT_GT(saved, 0.15);
  EXPECT_NEAR(r.saved_fraction(), saved, 0.05);
  EXPECT_NEAR(r.measured_cost, expected_cost(truth, best), 0.2 * expected_cost(truth, best));
}

TEST(EarlyOut, ChainSwitchesPretestsByTheLessonRule) {
  Synthetic s;
  // Check 0: pretest cost 1 in front of exact cost 10; exact passes 10%; the pretest leaks 10%
  // of the failures: p_pre = 0.1 + 0.9 * 0.1 = 0.19, 1 < 0.81 * 10: keep it.
  // Check 1: exact passes 95%: p_pre >= 0.95, 1 > 0.05 * 10: drop it.
  s.checks = {{10.0, 0.1, 1.0, 0.1}, {10.0, 0.95, 1.0, 0.0}};
  const std::array<bool, 2> pretests{true, true};
  CheckChainOptions options;
  options.reorder_interval = 32;
  options.alpha = 1.0 / 1024.0;
  CheckChain<4> chain(pretests, options);
  for (int e = 0; e < 20000; ++e) {
    s.new_pair();
    const bool expected = s.outcome[0] && s.outcome[1];
    EXPECT_EQ(chain.evaluate([&](int i, CheckStage st) { return s.run(i, st); },
                             [&] { return s.clock; }),
              expected);
  }
  EXPECT_TRUE(chain.pretest_enabled(0));
  EXPECT_FALSE(chain.pretest_enabled(1));
  EXPECT_NEAR(chain.pretest_stats(0).pass_rate, 0.19, 0.03);
  EXPECT_NEAR(chain.pretest_stats(1).pass_rate, 0.95, 0.05);
  // Model: check 0 costs 1 + 0.19 * 10 = 2.9 and passes 10%; check 1 costs 10 without pretest.
  const CheckChainReport r = chain.report();
  EXPECT_NEAR(r.expected_cost, 2.9 + 0.1 * 10.0, 0.3);
  // Fixed order, both pretests on: 2.9 + 0.1 * (1 + 0.95 * 10).
  EXPECT_NEAR(r.fixed_order_cost, 2.9 + 0.1 * 10.5, 0.3);
  EXPECT_GT(r.saved_fraction(), 0.0);
}

// Regression: pass rates were learned from every run of a check, also behind other checks. A
// box test placed behind the exact test only sees pairs the exact test accepted, which it
// always accepts too: its pass rate read 1, its cost per rejection infinity, and the chain kept
// the slow exact test first forever (the world's body-static chain learned "exact, aabb").
TEST(EarlyOut, DependentChecksAreOrderedByUnconditionalPassRates) {
  // Check 0: exact, cost 10, passes 20%. Check 1: box, cost 1, passes whenever the exact test
  // does and 3/8 of the rest: 0.2 + 0.8 * 0.375 = 0.5. Declared order: exact first.
  // Box first costs 1 + 0.5 * 10 = 6; exact first 10 + 0.2 * 1 = 10.2.
  std::mt19937 rng(5);
  double clock = 0.0;
  bool exact_passes = false, box_passes = false;
  const auto new_pair = [&] {
    exact_passes = test::uniform(rng, 0.0f, 1.0f) < 0.2f;
    box_passes = exact_passes || test::uniform(rng, 0.0f, 1.0f) < 0.375f;
  };
  const auto run = [&](int i, CheckStage) {
    clock += i == 0 ? 10.0 : 1.0;
    return i == 0 ? exact_passes : box_passes;
  };
  const std::array<bool, 2> none{};
  CheckChainOptions options;
  options.alpha = 1.0 / 256.0;
  CheckChain<2> chain(none, options);
  const int n = 40000;
  for (int e = 0; e < n; ++e) {
    new_pair();
    EXPECT_EQ(chain.evaluate(run, [&] { return clock; }), exact_passes);
  }
  EXPECT_EQ(chain.order()[0], 1) << "the box test must go first";
  const CheckChainReport r = chain.report();
  EXPECT_NEAR(r.expected_cost, 6.0, 0.5);
  EXPECT_NEAR(r.fixed_order_cost, 10.2, 0.3);
  // Measured on the replayed pairs, without the model: every 97th evaluation.
  EXPECT_EQ(r.sampled_pairs, static_cast<std::uint64_t>(n / 97));
  EXPECT_NEAR(r.sampled_cost, 6.0, 1.0);               // 1 or 11 per pair: standard error 0.25
  EXPECT_NEAR(r.sampled_fixed_order_cost, 10.2, 0.2);  // 10 or 11 per pair
  EXPECT_NEAR(r.sampled_saved_fraction(), 1.0 - 6.0 / 10.2, 0.1);
}

// The replayed cost of a sampled pair is exactly what each order would have spent on it.
TEST(EarlyOut, ReplayChargesEachOrderItsOwnStagesOnTheSamePair) {
  // Check 0 (cost 4, pretest cost 1) and check 1 (cost 2), with a pair on which check 0's
  // pretest passes, its exact test rejects, and check 1 rejects. Explore on every evaluation,
  // never reorder: both orders are the declaration order with the pretest on, so both replays
  // cost 1 + 4 = 5 per pair.
  double clock = 0.0;
  const auto run = [&](int i, CheckStage stage) {
    clock += i == 1 ? 2.0 : stage == CheckStage::pretest ? 1.0 : 4.0;
    return stage == CheckStage::pretest;
  };
  const std::array<bool, 2> pretests{true, false};
  CheckChainOptions options;
  options.explore_interval = 1;
  options.reorder_interval = 1000000;
  CheckChain<2> fixed(pretests, options);
  for (int e = 0; e < 50; ++e) EXPECT_FALSE(fixed.evaluate(run, [&] { return clock; }));
  CheckChainReport r = fixed.report();
  EXPECT_EQ(r.sampled_pairs, 50u);
  EXPECT_DOUBLE_EQ(r.sampled_cost, 5.0);
  EXPECT_DOUBLE_EQ(r.sampled_fixed_order_cost, 5.0);
  // Let it decide once: check 1 goes first (2 / 1 < 5 / 1) and the pretest is dropped
  // (1 > (1 - 1) * 4). The replay now charges the chosen order 2 and the fixed order still 5.
  options.reorder_interval = 10;
  CheckChain<2> learning(pretests, options);
  for (int e = 0; e < 10; ++e) (void)learning.evaluate(run, [&] { return clock; });
  ASSERT_EQ(learning.order()[0], 1);
  ASSERT_FALSE(learning.pretest_enabled(0));
  const CheckChainReport before = learning.report();
  for (int e = 0; e < 40; ++e) (void)learning.evaluate(run, [&] { return clock; });
  r = learning.report();
  EXPECT_DOUBLE_EQ(r.sampled_cost * 50.0 - before.sampled_cost * 10.0, 40 * 2.0);
  EXPECT_DOUBLE_EQ(r.sampled_fixed_order_cost, 5.0);
  EXPECT_NEAR(r.sampled_saved_fraction(), 1.0 - (10 * 5.0 + 40 * 2.0) / 50.0 / 5.0, 1e-12);
}

TEST(EarlyOut, ChainFollowsAChangingScene) {
  Synthetic s;
  s.checks = {{1.0, 0.9}, {3.0, 0.1}};
  const std::array<bool, 2> none{};
  CheckChain<2> chain(none);
  auto run_pairs = [&](int n) {
    for (int e = 0; e < n; ++e) {
      s.new_pair();
      (void)chain.evaluate([&](int i, CheckStage st) { return s.run(i, st); }, [&] { return s.clock; });
    }
  };
  run_pairs(5000);
  EXPECT_EQ(chain.order()[0], 1);  // 3 / 0.9 < 1 / 0.1
  s.checks[1].pass_rate = 0.95;      // the scene changes: b stops rejecting
  run_pairs(5000);
  EXPECT_EQ(chain.order()[0], 0);
  EXPECT_GE(chain.report().reorders, 2u);
}

TEST(EarlyOut, ChainTimingIntervalSkipsClockReads) {
  Synthetic s;
  s.checks = {{1.0, 0.5}, {2.0, 0.5}};
  const std::array<bool, 2> none{};
  CheckChainOptions options;
  options.timing_interval = 10;
  CheckChain<2> chain(none, options);
  int clock_reads = 0;
  for (int e = 0; e < 1000; ++e) {
    s.new_pair();
    (void)chain.evaluate([&](int i, CheckStage st) { return s.run(i, st); },
                         [&] { ++clock_reads; return s.clock; });
  }
  // Only 1 in 10 evaluations reads the clock (6 reads at most each), plus the exploring ones
  // (every 97th: 10 of them) and the calibration of the clock's own cost (16 pairs of reads).
  EXPECT_LE(clock_reads, (100 + 10) * 6 + 32);
  EXPECT_GT(clock_reads, 0);
  EXPECT_GT(chain.report().measured_cost, 0.0);
}

TEST(EarlyOut, ChainTakesTheClockReadsOutOfItsMeasurements) {
  // A fake clock whose every read costs 5 units: the stopwatch must not be charged to checks.
  Synthetic s;
  s.checks = {{2.0, 0.5}, {30.0, 0.5}};
  const std::array<bool, 2> none{};
  CheckChain<2> chain(none);
  auto reading_clock = [&] {
    s.clock += 5.0;
    return s.clock;
  };
  for (int e = 0; e < 2000; ++e) {
    s.new_pair();
    (void)chain.evaluate([&](int i, CheckStage st) { return s.run(i, st); }, reading_clock);
  }
  EXPECT_NEAR(chain.exact_stats(0).cost, 2.0, 1e-9);
  EXPECT_NEAR(chain.exact_stats(1).cost, 30.0, 1e-9);
  // Order: 2 / 0.5 < 30 / 0.5, and the whole-evaluation cost is 2 + 0.5 * 30 = 17 on average.
  EXPECT_EQ(chain.order()[0], 0);
  EXPECT_NEAR(chain.report().measured_cost, 17.0, 4.0);
}

TEST(EarlyOut, ChainRejectsBadConfiguration) {
  const std::array<bool, 3> three{};
  EXPECT_THROW(CheckChain<2>{three}, InvalidInput);
  EXPECT_THROW(CheckChain<4>(std::span<const bool>{}), InvalidInput);
  CheckChainOptions zero;
  zero.reorder_interval = 0;
  EXPECT_THROW(CheckChain<4>(three, zero), InvalidInput);
  CheckChainOptions alpha;
  alpha.alpha = 0.0;
  EXPECT_THROW(CheckChain<4>(three, alpha), InvalidInput);
}

}  // namespace
}  // namespace collide
