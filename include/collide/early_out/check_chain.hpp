#pragma once
/// @file
/// Early out, as the lesson analyses it ("Early Out", "Simple Checks First"): a pair collides
/// only if every check in a chain passes, so the chain stops at the first check that rejects.
///
/// Two independent checks a and b with costs t and pass rates p: running a first costs
/// t_a + p_a t_b, running b first costs t_b + p_b t_a. a goes first iff
/// t_a + p_a t_b < t_b + p_b t_a, i.e. t_a (1 - p_b) < t_b (1 - p_a), i.e.
/// t_a / (1 - p_a) < t_b / (1 - p_b). The quantity t / (1 - p) is the cost the check spends per
/// pair it rejects; sorting by it is optimal for any number of independent checks (an adjacent
/// swap never helps a sorted order: Smith 1956's ratio rule; Simon & Kadane 1975, "Optimal
/// problem-solving search"). So "fastest check first" is wrong whenever a slower check rejects
/// much more often: t_b / (1 - p_b) < t_a / (1 - p_a) puts the slow, selective b first.
///
/// A redundant pretest (a bounding-circle test before the exact test: whenever the exact test
/// passes, the pretest passes too) changes the cost of the exact test t_e into
/// t_pre + p_pre t_e. It pays only while t_pre < (1 - p_pre) t_e: a pretest that almost always
/// passes (pairs from a good broad phase) is pure overhead.
///
/// `CheckChain` measures t and p online (exponential moving averages of clock readings and
/// outcomes), reorders its checks by t / (1 - p), switches each pretest on or off by the rule
/// above, and reports the model's cost against the fixed declaration order.
///
/// The pass rate p that orders the checks must be unconditional: measured on every pair, not
/// only on the pairs earlier checks let through. Real checks are rarely independent (an AABB
/// test passes whenever the exact test does), and a pass rate measured behind the exact test
/// reads 1, which would keep the AABB test last forever. So p comes from the evaluations where
/// a check's outcome does not depend on the others: the first check of the order, and the
/// exploring evaluations that run every check on the pair. With unconditional rates the
/// two-check rule t_a + p_a t_b is exact whatever the dependence.
///
/// What the choices saved is also measured, without the model: on each exploring evaluation
/// (where every stage runs and is timed) the chain replays the pair through its current order
/// and through the declaration order with every pretest on, from the stage times and outcomes
/// measured on that very pair, and reports the mean of both.
///
/// Units: costs are in whatever unit the clock returns (nanoseconds for `SteadyClockNs`);
/// pass rates are fractions in [0, 1].
///
/// The statistics use double: costs are sums of nanosecond clock readings over millions of
/// evaluations, and 1 - p must stay meaningful when p is 0.9999.

#include <collide/core/error.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <limits>
#include <span>

namespace collide {

/// Cost and pass rate of one check: what the ordering decisions need.
struct CheckStats {
  double cost = 0.0;       ///< mean time per run, clock units, >= 0
  double pass_rate = 0.0;  ///< fraction of runs that pass (do not reject the pair), [0, 1]
};

/// t / (1 - p): the expected cost spent per rejected pair. +infinity for a check that never
/// rejects (it can only go last), 0 for a free check.
[[nodiscard]] double cost_per_rejection(const CheckStats& check) noexcept;

/// Expected cost of running `checks` in `order` (indices into `checks`), stopping at the first
/// rejection: sum over k of t_{order[k]} times the product of the pass rates before it.
/// Assumes the checks' outcomes are independent (the lesson's assumption).
[[nodiscard]] double expected_cost(std::span<const CheckStats> checks,
                                   std::span<const int> order) noexcept;

/// Writes into `order` (same size as `checks`) the order that minimises `expected_cost`:
/// ascending t / (1 - p), ties kept in index order. Throws InvalidInput if the sizes differ or
/// a cost is negative/not finite or a pass rate is outside [0, 1].
void optimal_order(std::span<const CheckStats> checks, std::span<int> order);

/// Expected cost of an exact check of cost `exact_cost` behind a redundant pretest:
/// t_pre + p_pre * t_exact.
[[nodiscard]] double cost_with_pretest(const CheckStats& pretest, double exact_cost) noexcept;

/// The lesson's rule for a redundant pretest: worth running iff t_pre < (1 - p_pre) t_exact.
[[nodiscard]] bool pretest_pays(const CheckStats& pretest, double exact_cost) noexcept;

/// Once warmed up, a cost sample above this multiple of the running estimate is clipped to it:
/// a thread preempted mid-check must not teach the chain that the check is slow (a winsorized
/// mean; a real change still moves the estimate by a factor of this per sample).
inline constexpr double kCostOutlierFactor = 16.0;

/// A moving average of a check's cost and pass rate. The first samples are averaged plainly
/// (weight 1/n) so the estimate is useful at once; after 1/alpha samples it becomes an
/// exponential moving average with weight `alpha`, which follows a changing scene. Cost samples
/// far above the estimate are clipped (kCostOutlierFactor).
class RunningStats {
 public:
  RunningStats() noexcept = default;
  explicit RunningStats(double alpha) noexcept : alpha_(alpha) {}

  void add_outcome(bool passed) noexcept {
    ++outcomes_;
    pass_rate_ += weight(outcomes_) * ((passed ? 1.0 : 0.0) - pass_rate_);
  }
  void add_cost(double cost) noexcept {
    ++costs_;
    const double w = weight(costs_);
    if (w <= alpha_ && cost > kCostOutlierFactor * cost_) cost = kCostOutlierFactor * cost_;
    cost_ += w * (cost - cost_);
  }
  [[nodiscard]] CheckStats stats() const noexcept { return {cost_, pass_rate_}; }
  [[nodiscard]] std::uint64_t outcomes() const noexcept { return outcomes_; }
  [[nodiscard]] std::uint64_t costs() const noexcept { return costs_; }

 private:
  [[nodiscard]] double weight(std::uint64_t n) const noexcept {
    const double plain = 1.0 / static_cast<double>(n);
    return plain > alpha_ ? plain : alpha_;
  }
  double alpha_ = 1.0 / 64.0;
  double cost_ = 0.0;
  double pass_rate_ = 0.0;
  std::uint64_t outcomes_ = 0;
  std::uint64_t costs_ = 0;
};

/// The stage of a check a `CheckChain` asks the caller to run.
enum class CheckStage : unsigned char {
  exact,    ///< the check itself
  pretest,  ///< its redundant pretest: must pass whenever the exact check passes
};

/// Options of a `CheckChain`. Intervals count evaluations and must be >= 1.
struct CheckChainOptions {
  double alpha = 1.0 / 64.0;           ///< moving-average weight of a new sample
  std::uint32_t timing_interval = 1;   ///< read the clock on every k-th evaluation only
  std::uint32_t reorder_interval = 64; ///< re-decide order and pretests every k evaluations
  /// Every k-th evaluation runs every check and every pretest, so checks that sit behind a
  /// strong rejector and switched-off pretests keep fresh statistics.
  std::uint32_t explore_interval = 97;
};

/// What a chain did and what its choices are worth, in clock units per evaluation.
struct CheckChainReport {
  std::uint64_t evaluations = 0;   ///< calls to evaluate()
  std::uint64_t rejections = 0;    ///< evaluations that returned false
  std::uint64_t reorders = 0;      ///< times the order or a pretest choice changed
  /// Moving average of the measured time of whole timed evaluations (the chain's own clock
  /// reads taken out, preemption outliers clipped as in RunningStats).
  double measured_cost = 0.0;
  double expected_cost = 0.0;      ///< model cost of the current order and pretest choices
  double fixed_order_cost = 0.0;   ///< model cost of declaration order, every pretest on
  /// Exploring evaluations replayed (every stage timed on the same pair); 0 when the chain
  /// never explores (CheckChainOptions::explore_interval larger than the evaluations).
  std::uint64_t sampled_pairs = 0;
  /// Mean measured cost of the sampled pairs through the order and pretests the chain had
  /// chosen at the time, clock units per pair.
  double sampled_cost = 0.0;
  /// Mean measured cost of the same pairs through the declaration order, every pretest on.
  double sampled_fixed_order_cost = 0.0;
  /// Fraction of the fixed order's cost the chain's choices save (model), in (-inf, 1].
  [[nodiscard]] double saved_fraction() const noexcept {
    return fixed_order_cost > 0.0 ? 1.0 - expected_cost / fixed_order_cost : 0.0;
  }
  /// Fraction of the fixed order's cost the chain's choices saved on the sampled pairs
  /// (measured), in (-inf, 1]; 0 without samples.
  [[nodiscard]] double sampled_saved_fraction() const noexcept {
    return sampled_fixed_order_cost > 0.0 ? 1.0 - sampled_cost / sampled_fixed_order_cost : 0.0;
  }
};

/// A monotonic clock in nanoseconds, the default for `CheckChain::evaluate`.
struct SteadyClockNs {
  [[nodiscard]] double operator()() const noexcept {
    return static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
  }
};

/// A chain of up to `MaxChecks` independent checks, each optionally with a redundant pretest,
/// that a pair must all pass. Checks are indices 0..count-1; the caller runs them through a
/// callable `bool run(int check, CheckStage stage)`. The chain learns costs and pass rates as it
/// goes and keeps the order that the lesson's analysis says is cheapest. Storage is inline;
/// `evaluate` allocates nothing.
template <int MaxChecks = 8>
class CheckChain {
 public:
  /// `has_pretest[i]`: check i has a redundant pretest. Throws InvalidInput if there are more
  /// than MaxChecks checks or none, or an interval or alpha is out of range.
  explicit CheckChain(std::span<const bool> has_pretest, const CheckChainOptions& options = {})
      : options_(options), count_(static_cast<int>(has_pretest.size())) {
    if (has_pretest.empty() || has_pretest.size() > static_cast<size_t>(MaxChecks)) {
      throw InvalidInput("check chain: needs 1 to MaxChecks checks");
    }
    if (options.timing_interval == 0 || options.reorder_interval == 0 ||
        options.explore_interval == 0) {
      throw InvalidInput("check chain options: intervals must be >= 1");
    }
    if (!(options.alpha > 0.0 && options.alpha <= 1.0)) {
      throw InvalidInput("check chain options alpha: must be in (0, 1]");
    }
    for (int i = 0; i < count_; ++i) {
      Unit& u = units_[i];
      u.has_pretest = has_pretest[i];
      u.pretest_on = u.has_pretest;  // the fixed order's habit: pretest first
      u.unit = u.pretest = u.exact = RunningStats(options.alpha);
      order_[i] = i;
    }
    total_ = RunningStats(options.alpha);
  }

  /// Runs the checks in the current order until one rejects; true if all pass. `run(i, stage)`
  /// performs stage `stage` of check i; `now()` returns the time as a double (tests pass a fake
  /// clock). Every `timing_interval`-th evaluation is timed, and so is every exploring one
  /// (every `explore_interval`-th: it runs every stage and is replayed for the report). A
  /// pretest that rejects a pair its exact check accepts breaks the contract and trips
  /// COLLIDE_ASSERT on exploring evaluations (where both run).
  template <class Run, class Clock = SteadyClockNs>
  bool evaluate(Run&& run, Clock&& now = Clock{}) {
    ++evaluations_;
    const bool explore = evaluations_ % options_.explore_interval == 0;
    const bool timed = explore || evaluations_ % options_.timing_interval == 0;
    if (timed && !calibrated_) calibrate(now);
    int reads = 0;  // clock reads in this evaluation, to take their cost out of the total
    auto read = [&] {
      ++reads;
      return now();
    };
    // A sample is the time between two clock reads minus what one read costs.
    auto elapsed = [&](double since) {
      const double t = read() - since - clock_overhead_;
      return t > 0.0 ? t : 0.0;
    };
    const double start = timed ? read() : 0.0;
    std::array<Sample, MaxChecks> sample{};  // exploring evaluations: each stage's time and outcome
    bool all_pass = true;
    for (int k = 0; k < count_; ++k) {
      const int i = order_[k];
      Unit& u = units_[i];
      bool pass = true;
      bool rejected_by_pretest = false;
      if (u.has_pretest && (u.pretest_on || explore)) {
        const double t0 = timed ? read() : 0.0;
        const bool pre = run(i, CheckStage::pretest);
        const double t = timed ? elapsed(t0) : 0.0;
        if (timed) u.pretest.add_cost(t);
        u.pretest.add_outcome(pre);
        sample[i].pretest_cost = t;
        sample[i].pretest_pass = pre;
        rejected_by_pretest = !pre;
        if (!pre && u.pretest_on && !explore) pass = false;
      }
      if (pass) {
        const double t0 = timed ? read() : 0.0;
        pass = run(i, CheckStage::exact);
        const double t = timed ? elapsed(t0) : 0.0;
        if (timed) u.exact.add_cost(t);
        u.exact.add_outcome(pass);
        sample[i].exact_cost = t;
        sample[i].exact_pass = pass;
        COLLIDE_ASSERT(!(rejected_by_pretest && pass),
                       "check chain: a pretest rejected a pair its exact check accepts");
        if (rejected_by_pretest && u.pretest_on) pass = false;
      }
      // Only unconditional outcomes teach the pass rate (see the file comment).
      if (k == 0 || explore) u.unit.add_outcome(pass);
      if (!pass) {
        all_pass = false;
        if (!explore) break;
      }
    }
    if (timed) {
      const double total = read() - start - static_cast<double>(reads - 1) * clock_overhead_;
      total_.add_cost(total > 0.0 ? total : 0.0);
    }
    if (explore) replay(sample);
    if (!all_pass) ++rejections_;
    if (evaluations_ % options_.reorder_interval == 0) decide();
    return all_pass;
  }

  /// Re-decides pretests (t_pre < (1 - p_pre) t_exact) and the order (ascending
  /// t / (1 - p) of each check with its chosen pretest) from the statistics so far. `evaluate`
  /// calls it every `reorder_interval` evaluations.
  void decide() noexcept {
    bool changed = false;
    std::array<CheckStats, MaxChecks> model{};
    for (int i = 0; i < count_; ++i) {
      Unit& u = units_[i];
      if (u.has_pretest && u.pretest.costs() > 0 && u.exact.costs() > 0) {
        const bool on = pretest_pays(u.pretest.stats(), u.exact.stats().cost);
        changed = changed || on != u.pretest_on;
        u.pretest_on = on;
      }
      model[i] = model_stats(i, u.pretest_on);
    }
    // Insertion sort by cost per rejection: n <= MaxChecks, stable, no allocation.
    for (int k = 1; k < count_; ++k) {
      const int i = order_[k];
      const double key = cost_per_rejection(model[i]);
      int j = k - 1;
      while (j >= 0 && cost_per_rejection(model[order_[j]]) > key) {
        order_[j + 1] = order_[j];
        --j;
        changed = true;
      }
      order_[j + 1] = i;
    }
    if (changed) ++reorders_;
  }

  /// The current order: order()[k] is the index of the k-th check run.
  [[nodiscard]] std::span<const int> order() const noexcept { return {order_.data(), size_t(count_)}; }
  /// Whether check i currently runs its pretest.
  [[nodiscard]] bool pretest_enabled(int i) const noexcept { return units_[i].pretest_on; }
  /// Measured statistics of check i's exact stage, pretest stage, and the two together.
  [[nodiscard]] CheckStats exact_stats(int i) const noexcept { return units_[i].exact.stats(); }
  [[nodiscard]] CheckStats pretest_stats(int i) const noexcept { return units_[i].pretest.stats(); }
  /// What the order decision sees for check i: its cost with its current pretest choice
  /// (t_pre + p_pre t_exact, or t_exact) and its unconditional pass rate.
  [[nodiscard]] CheckStats check_stats(int i) const noexcept { return model_stats(i, units_[i].pretest_on); }

  /// Counters and the model's costs of the current choices and of the fixed declaration order
  /// (every pretest on), from the current statistics.
  [[nodiscard]] CheckChainReport report() const noexcept {
    CheckChainReport r;
    r.evaluations = evaluations_;
    r.rejections = rejections_;
    r.reorders = reorders_;
    r.measured_cost = total_.stats().cost;
    std::array<CheckStats, MaxChecks> current{};
    std::array<CheckStats, MaxChecks> fixed{};
    std::array<int, MaxChecks> declared{};
    for (int i = 0; i < count_; ++i) {
      current[i] = model_stats(i, units_[i].pretest_on);
      fixed[i] = model_stats(i, units_[i].has_pretest);
      declared[i] = i;
    }
    const auto n = static_cast<size_t>(count_);
    r.expected_cost = expected_cost({current.data(), n}, {order_.data(), n});
    r.fixed_order_cost = expected_cost({fixed.data(), n}, {declared.data(), n});
    r.sampled_pairs = samples_;
    if (samples_ > 0) {
      r.sampled_cost = sampled_cost_ / static_cast<double>(samples_);
      r.sampled_fixed_order_cost = sampled_fixed_cost_ / static_cast<double>(samples_);
    }
    return r;
  }

 private:
  /// One check's stages on one exploring evaluation.
  struct Sample {
    double pretest_cost = 0.0;
    double exact_cost = 0.0;
    bool pretest_pass = true;
    bool exact_pass = true;
  };

  /// Cost of the sampled pair through `order` with pretests `pretest_on(i)`: stages in order,
  /// stopping at the first rejection, each charged its measured time.
  template <class PretestOn>
  [[nodiscard]] double replay_cost(const std::array<Sample, MaxChecks>& sample, const int* order,
                                   PretestOn&& pretest_on) const noexcept {
    double cost = 0.0;
    for (int k = 0; k < count_; ++k) {
      const int i = order[k];
      const Sample& s = sample[i];
      if (units_[i].has_pretest && pretest_on(i)) {
        cost += s.pretest_cost;
        if (!s.pretest_pass) return cost;
      }
      cost += s.exact_cost;
      if (!s.exact_pass) return cost;
    }
    return cost;
  }

  /// Adds an exploring evaluation to the measured comparison of the chosen and the fixed order.
  void replay(const std::array<Sample, MaxChecks>& sample) noexcept {
    std::array<int, MaxChecks> declared{};
    for (int i = 0; i < count_; ++i) declared[i] = i;
    sampled_cost_ += replay_cost(sample, order_.data(), [&](int i) { return units_[i].pretest_on; });
    sampled_fixed_cost_ += replay_cost(sample, declared.data(), [](int) { return true; });
    ++samples_;
  }

  struct Unit {
    bool has_pretest = false;
    bool pretest_on = false;
    RunningStats unit;     ///< outcome of the check with its pretest, unconditional runs only
    RunningStats pretest;  ///< the pretest alone
    RunningStats exact;    ///< the exact check alone (on pairs its pretest let through)
  };

  /// Model of check i with or without its pretest: cost t_pre + p_pre t_e or t_e, and the
  /// exact check's unconditional pass rate (the pretest is redundant, so it does not change it).
  [[nodiscard]] CheckStats model_stats(int i, bool with_pretest) const noexcept {
    const Unit& u = units_[i];
    const CheckStats exact = u.exact.stats();
    const double pass = u.unit.outcomes() > 0 ? u.unit.stats().pass_rate : exact.pass_rate;
    if (!u.has_pretest || u.pretest.outcomes() == 0) return {exact.cost, pass};
    const double cost = with_pretest ? cost_with_pretest(u.pretest.stats(), exact.cost) : exact.cost;
    return {cost, pass};
  }

  /// The cost of one clock read, measured once as the least of a few back-to-back pairs (0 for
  /// a fake clock that does not move), so cheap checks are not charged for the stopwatch.
  template <class Clock>
  void calibrate(Clock& now) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 16; ++i) {
      const double a = now();
      const double b = now();
      best = b - a < best ? b - a : best;
    }
    clock_overhead_ = best > 0.0 ? best : 0.0;
    calibrated_ = true;
  }

  CheckChainOptions options_;
  bool calibrated_ = false;
  double clock_overhead_ = 0.0;
  int count_ = 0;
  std::array<Unit, MaxChecks> units_{};
  std::array<int, MaxChecks> order_{};
  std::uint64_t evaluations_ = 0;
  std::uint64_t rejections_ = 0;
  std::uint64_t reorders_ = 0;
  RunningStats total_{};  ///< time of whole timed evaluations (outliers clipped)
  std::uint64_t samples_ = 0;        ///< exploring evaluations replayed
  double sampled_cost_ = 0.0;        ///< their summed cost through the chosen order
  double sampled_fixed_cost_ = 0.0;  ///< and through the declaration order
};

}  // namespace collide
