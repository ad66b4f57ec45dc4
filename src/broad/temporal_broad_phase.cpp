#include <collide/broad/temporal_broad_phase.hpp>

#include <collide/core/error.hpp>

#include "x_sorted.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace collide {

namespace {

/// A sleeping pair wakes this fraction of its gap-closing time early: rounding in the wake
/// time can never make it late.
constexpr double kWakeEarly = 1e-6;

/// Growth of a box over the horizon is capped here, far inside float range (a huge speed bound
/// then just makes that object a candidate with everything).
constexpr double kMaxGrowth = 1e30;

/// An object whose box would grow by more than this many grid cells over the horizon (a bullet
/// among walkers) is "fast": kept out of the candidate set, its pairs are found every frame by
/// a grid query instead. Growing it would make it a candidate with everything it could reach.
constexpr double kFastGrowthCells = 4.0;

/// Objects that break their bound between rebuilds join the fast ones (demote), until more than
/// one in kDemotedFractionForRebuild (and more than kMinDemotionsBeforeRebuild) have: then a
/// rebuild costs less than their queries.
constexpr std::size_t kDemotedFractionForRebuild = 16;
constexpr std::size_t kMinDemotionsBeforeRebuild = 16;

/// A speed bound the temporal broad phase accepts: finite and non-negative (NaN fails).
bool is_valid_speed_bound(float v) noexcept { return v >= 0.0f && v <= std::numeric_limits<float>::max(); }

/// Throws InvalidInput unless there is one finite, non-negative bound per object.
void validate_speed_bounds(std::span<const float> speed_bounds, std::size_t objects) {
  if (speed_bounds.size() != objects) {
    throw InvalidInput("speed bounds: " + std::to_string(speed_bounds.size()) + " for " +
                       std::to_string(objects) + " boxes");
  }
  for (std::size_t i = 0; i < speed_bounds.size(); ++i) {
    if (!is_valid_speed_bound(speed_bounds[i])) {
      throw InvalidInput("speed bound " + std::to_string(i) + ": negative or not finite");
    }
  }
}

}  // namespace

template <int D>
TemporalBroadPhaseN<D>::TemporalBroadPhaseN(Options options) : options_(options) {
  if (!std::isfinite(options.horizon) || options.horizon < 0.0) {
    throw InvalidInput("TemporalBroadPhase options horizon: negative or not finite");
  }
}

template <int D>
void TemporalBroadPhaseN<D>::build(std::span<const AabbN<D>> boxes,
                                   std::span<const float> speed_bounds, double time) {
  validate_boxes(boxes);
  validate_speed_bounds(speed_bounds, boxes.size());
  if (!std::isfinite(time)) throw InvalidInput("time: not finite");
  boxes_.assign(boxes.begin(), boxes.end());
  speeds_.assign(speed_bounds.begin(), speed_bounds.end());
  time_ = time;
  stats_ = Stats{};
  needs_rebuild_ = true;
  fast_index_ = FastIndex::none;

  horizon_ = options_.horizon;
  // Half the median box size over the median positive speed bound.
  scratch_.clear();
  for (const float v : speeds_) {
    if (v > 0.0f) scratch_.push_back(v);
  }
  double speed = 0.0;
  if (!scratch_.empty()) {
    auto mid = scratch_.begin() + static_cast<std::ptrdiff_t>(scratch_.size() / 2);
    std::nth_element(scratch_.begin(), mid, scratch_.end());
    speed = *mid;
  }
  cell_ = boxes.empty() ? 0.0 : suggest_cell_size(boxes, scratch_);  // twice the median size
  if (horizon_ == 0.0) {
    horizon_ = speed > 0.0 ? 0.25 * cell_ / speed : std::numeric_limits<double>::infinity();
  }
}

template <int D>
void TemporalBroadPhaseN<D>::update(std::span<const AabbN<D>> boxes, double time) {
  update(boxes, time, nullptr);
}

namespace {

/// Smallest range of objects or candidates per task.
constexpr int kObjectsPerTask = 2048;
/// Smallest range of fast objects per task (each a grid query of a few microseconds).
constexpr int kFastObjectsPerTask = 64;
/// find_pairs splits its work over the workers from this much on: candidates, each fast object
/// counting as kFastQueryCandidates (a grid query of a few microseconds against a few
/// nanoseconds a candidate; at 1e3 objects, 560 candidates and 11 fast objects took about 7 and
/// 5.5 us). Below it one thread does it all: a wait for the workers costs a few microseconds,
/// and each worker's share reads boxes the other cores just wrote. It was 256 until the serial
/// checks prefetched (kCandidatePrefetchAhead) in a world stepped on several workers; then, on
/// the Zen 5 VM at stop 95 (two threads, collide run's default scene), find_pairs took 7.0-7.2
/// us a frame on the stepping thread against 10.8-14.1 split at 1e3 bodies (about 1.1e3
/// units), 24-27 against 27-35 at 2e3.
constexpr int kSplitFindFrom = 4096;
constexpr int kFastQueryCandidates = 50;
/// Fewest candidates a range of find_pairs checks when it splits them.
constexpr int kMinCandidatesPerTask = 128;
/// Candidates ahead of the one being checked whose two objects' boxes, speed bounds and flags
/// are prefetched when the scheduler has several workers. A check takes 7-10 ns and reads two
/// random objects; in a stepping world with two workers about half the boxes were just written
/// by the other core's share of the motion pass, and on the Zen 5 VM (stop 95) a line from the
/// other core takes some 200-300 ns: without it a check took 15-31 ns on two threads against
/// 7-10 on one, with it 9-17. On one thread the loop is as it was (on the Intel host at stop 93
/// a prefetch there made the one-thread pair search 2-4% slower).
constexpr int kCandidatePrefetchAhead = 32;
/// From this many fast objects on, their pairs among themselves come from a grid of their own
/// instead of a sort and sweep along x.
constexpr std::size_t kFastGridFrom = 256;

/// update's verdict on an object: bound kept, bound broken, bound kept but out of its grown box
/// (it may still pair with candidates it was not grown towards), or a box update refuses.
constexpr unsigned char kKept = 0;
constexpr unsigned char kBrokeBound = 1;
constexpr unsigned char kLeftGrownBox = 2;
constexpr unsigned char kBadBox = 3;  // NaN or infinite coordinates, or min > max: validate_boxes names it

/// Bit 0: `now` is within `reach` of `before` (each min fell by at most reach, each max rose by
/// at most reach, the differences in double: exact in sign, and a float difference could round
/// a small excess away); bit 1: `now` lies inside `grown`. Both false for NaN coordinates.
/// Branch-free: whether an object keeps its bound is as good as random from one to the next.
template <int D>
inline unsigned reach_and_inside(const AabbN<D>& before, const AabbN<D>& now, const AabbN<D>& grown,
                                 double reach) noexcept {
  static_assert(sizeof(AabbN<D>) == 2 * D * sizeof(float), "a box is its 2D floats, min then max");
#if defined(__SSE2__)
  // The box's 2D floats as D pairs of doubles; on a max coordinate the difference is negated
  // (exact), so every lane asks "difference <= limit". Float differences in double have the
  // sign of the float comparison, so the grown box's test is exactly contains().
  const auto* b = reinterpret_cast<const float*>(&before);
  const auto* n = reinterpret_cast<const float*>(&now);
  const auto* g = reinterpret_cast<const float*>(&grown);
  const auto pair = [](const float* f) {
    return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(f))));
  };
  const __m128d limit = _mm_set1_pd(reach);
  const __m128d zero = _mm_setzero_pd();
  __m128d within = _mm_castsi128_pd(_mm_set1_epi32(-1));
  __m128d inside = within;
  for (int j = 0; j < D; ++j) {
    // float 2j is a min coordinate when 2j < D, float 2j + 1 when 2j + 1 < D
    const __m128d flip = _mm_set_pd(2 * j + 1 < D ? 0.0 : -0.0, 2 * j < D ? 0.0 : -0.0);
    const __m128d pn = pair(n + 2 * j);
    within = _mm_and_pd(within, _mm_cmple_pd(_mm_xor_pd(_mm_sub_pd(pair(b + 2 * j), pn), flip), limit));
    inside = _mm_and_pd(inside, _mm_cmple_pd(_mm_xor_pd(_mm_sub_pd(pair(g + 2 * j), pn), flip), zero));
  }
  return unsigned{_mm_movemask_pd(within) == 3} | unsigned{_mm_movemask_pd(inside) == 3} << 1;
#else
  unsigned within = 1, inside = 1;
  for (int k = 0; k < D; ++k) {
    within &= unsigned{static_cast<double>(before.min[k]) - static_cast<double>(now.min[k]) <= reach} &
              unsigned{static_cast<double>(now.max[k]) - static_cast<double>(before.max[k]) <= reach};
    inside &= unsigned{grown.min[k] <= now.min[k]} & unsigned{now.max[k] <= grown.max[k]};
  }
  return within | inside << 1;
#endif
}

}  // namespace

template <int D>
void TemporalBroadPhaseN<D>::update(std::span<const AabbN<D>> boxes, double time, TaskScheduler* scheduler) {
  // Each object's verdict into its own slot and its box into next_boxes_ (in parallel), then
  // the demotions in id order.
  begin_update(boxes.size(), time);
  parallel_for(scheduler, size(), kObjectsPerTask, [&](int begin, int end, int) { update_range(begin, end, boxes); });
  finish_update(boxes);
}

template <int D>
void TemporalBroadPhaseN<D>::begin_update(std::size_t count, double time) {
  if (count != boxes_.size()) {
    throw InvalidInput("boxes: " + std::to_string(count) + " given, " + std::to_string(boxes_.size()) +
                       " built; call build for a new set");
  }
  if (!std::isfinite(time) || time < time_) throw InvalidInput("time: not finite or goes back");
  update_time_ = time;
  fast_index_ = FastIndex::none;  // the boxes change
  broke_.resize(boxes_.size());
  next_boxes_.resize(boxes_.size());
}

template <int D>
void TemporalBroadPhaseN<D>::update_range(int begin, int end, std::span<const AabbN<D>> boxes) noexcept {
  // Plain pointers in locals and no branch on the outcome: the verdicts are byte stores, which
  // may alias anything, so members read through `this` would be reloaded for every object
  // (update: 119 instructions an object with them, 101 now, cachegrind).
  const AabbN<D>* const before_all = boxes_.data();
  const AabbN<D>* const now_all = boxes.data();
  const float* const speeds = speeds_.data();
  const unsigned char* const flags = flags_.data();
  const AabbN<D>* const grown = grown_.data();
  unsigned char* const broke = broke_.data();
  AabbN<D>* const next = next_boxes_.data();
  // grown_ and flags_' fast bits are from a rebuild of these objects unless one is pending (only
  // finish_update's demotions change that, after every range)
  const bool check_grown = !needs_rebuild_;
  const double dt = update_time_ - time_;
  for (int i = begin; i < end; ++i) {
    const AabbN<D>& now = now_all[i];
    // (before rebuilding, grown_ may be stale or short: the object's own box stands in)
    const unsigned tests = reach_and_inside<D>(before_all[i], now, check_grown ? grown[i] : now,
                                               static_cast<double>(speeds[i]) * dt);
    // A NaN or infinite coordinate fails the reach test (the previous box is finite, the reach
    // too), so only a box that failed it needs the whole is_valid_box (a few a frame, a branch
    // that predicts well); min > max can pass it, so that comparison is made for every box.
    unsigned ordered = 1;
    for (int k = 0; k < D; ++k) ordered &= unsigned{now.min[k] <= now.max[k]};
    unsigned verdict = (tests & 1u) != 0 ? kKept : kBrokeBound;
    if (check_grown && tests == 1u && (flags[i] & kFastFlag) == 0) verdict = kLeftGrownBox;  // (rare)
    if ((tests & 1u) == 0 && !is_valid_box(now)) ordered = 0;
    broke[i] = static_cast<unsigned char>(ordered != 0 ? verdict : kBadBox);
    next[i] = now;
  }
}

template <int D>
void TemporalBroadPhaseN<D>::finish_update(std::span<const AabbN<D>> boxes) {
  // The verdicts 8 at a time: nearly all objects keep their bounds, so most words are 0. A bad
  // box makes validate_boxes name the first one before anything changes; otherwise next_boxes_
  // becomes boxes_ (a swap, no copy).
  const int n = size();
  const int whole = n - n % 8;
  const auto any_bad = [&](int from, int to) {
    for (int i = from; i < to; ++i) {
      if (broke_[std::size_t(i)] == kBadBox) return true;
    }
    return false;
  };
  bool bad = any_bad(whole, n);
  for (int i = 0; i < whole && !bad; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, broke_.data() + i, sizeof word);
    if (word != 0) bad = any_bad(i, i + 8);
  }
  if (bad) validate_boxes(boxes);
  boxes_.swap(next_boxes_);
  const auto demote_if_broke = [&](int i) {
    const unsigned char verdict = broke_[std::size_t(i)];
    if (verdict == kKept) return;
    if (verdict == kBrokeBound) ++stats_.bound_violations;
    // Broke its bound, or left its grown box: the candidate set no longer covers it. It joins
    // the fast objects until the next rebuild (its pairs found by a grid query every frame, its
    // candidate pairs ignored), unless so many do that a rebuild is cheaper. A fast object is
    // checked every frame anyway.
    if (!needs_rebuild_ && !is_fast(i)) demote(i);
  };
  for (int i = 0; i < whole; i += 8) {
    std::uint64_t word;
    std::memcpy(&word, broke_.data() + i, sizeof word);
    if (word == 0) continue;
    for (int k = i; k < i + 8; ++k) demote_if_broke(k);
  }
  for (int i = whole; i < n; ++i) demote_if_broke(i);
  time_ = update_time_;
}

template <int D>
void TemporalBroadPhaseN<D>::demote(int i) {
  flags_[std::size_t(i)] |= kFastFlag;
  fast_.push_back(i);
  fast_index_ = FastIndex::none;
  ++stats_.demoted;
  if (++demoted_since_rebuild_ > std::max<std::size_t>(kMinDemotionsBeforeRebuild, boxes_.size() / kDemotedFractionForRebuild)) {
    needs_rebuild_ = true;
  }
}

template <int D>
void TemporalBroadPhaseN<D>::set_speed_bounds(std::span<const float> speed_bounds) {
  set_speed_bounds(speed_bounds, nullptr);
}

template <int D>
void TemporalBroadPhaseN<D>::set_speed_bounds(std::span<const float> speed_bounds, TaskScheduler* scheduler) {
  if (speed_bounds.size() != speeds_.size()) validate_speed_bounds(speed_bounds, speeds_.size());
  // One pass per object (in parallel): the new bound stored beside the old, whether any is bad
  // (named by validate_speed_bounds before anything changes), and each object whose bound rose
  // flagged; then the new bounds swapped in. A sleeping candidate pair with a raised member may
  // meet sooner than its wake time: check_candidates checks it at the next find_pairs, as it
  // reads the pair's flags anyway. (Until stop 92 a second pass over every candidate moved such
  // wake times to now here: at 1e4 bodies about 9,000 candidates, 20 us a frame.) The flags are
  // set only over a current candidate set: a pending rebuild wakes every pair, and clears them.
  next_speeds_.resize(speeds_.size());
  const bool flag = !needs_rebuild_;
  std::atomic<unsigned> found{0};  // bit 0: a bound raised, bit 1: a bad bound
  const auto n = static_cast<int>(speeds_.size());
  parallel_for(scheduler, n, kObjectsPerTask, [&](int begin, int end, int) {
    const float* const bounds = speed_bounds.data();
    const float* const speeds = speeds_.data();
    float* const next = next_speeds_.data();
    unsigned char* const flags = flags_.data();
    // Loops without branches or calls, which the compiler turns into vector code (the loop
    // with the flag inside and is_valid_speed_bound's && ran a float an iteration: 25 us a
    // frame at 1e4 bodies, now 4).
    unsigned raised = 0, valid = 1;
    for (int i = begin; i < end; ++i) {
      const float v = bounds[i];
      raised |= unsigned{v > speeds[i]};
      valid &= unsigned{v >= 0.0f} & unsigned{v <= std::numeric_limits<float>::max()};  // (NaN fails both)
      next[i] = v;
    }
    if (flag && raised != 0) {
      for (int i = begin; i < end; ++i) {
        flags[i] = static_cast<unsigned char>(flags[i] | unsigned{bounds[i] > speeds[i]} << 1);  // (kRaisedFlag)
      }
    }
    const unsigned bad = valid ^ 1u;
    if ((raised | bad) != 0) found.fetch_or(raised | bad << 1, std::memory_order_relaxed);
  });
  const unsigned any = found.load(std::memory_order_relaxed);
  if (flag && (any & 1u)) raised_pending_ = true;
  // (A bad bound changes no bound; flags it set only wake pairs a frame early, never change
  // the pairs found.)
  if (any & 2u) validate_speed_bounds(speed_bounds, speeds_.size());
  speeds_.swap(next_speeds_);  // next_speeds_ holds the old bounds now
}

template <int D>
void TemporalBroadPhaseN<D>::clear_raised_flags() noexcept {
  for (unsigned char& f : flags_) f = static_cast<unsigned char>(f & kFastFlag);
  raised_pending_ = false;
}

template <int D>
void TemporalBroadPhaseN<D>::rebuild(double until) {
  // Each box grown by how far its bound lets it move by `until` (the horizon from now, or from
  // the next update's time when built ahead of it).
  const double window = until - time_;
  grown_.resize(boxes_.size());
  flags_.assign(boxes_.size(), 0);  // (every candidate is awake after it: no raised bound pending)
  raised_pending_ = false;
  fast_.clear();
  fast_index_ = FastIndex::none;
  slow_ids_.clear();
  slow_grown_.clear();
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    // The horizon is infinite only when every speed bound is 0.
    const double margin = speeds_[i] > 0.0f ? speeds_[i] * window : 0.0;
    if (margin > kFastGrowthCells * cell_) {
      flags_[i] = kFastFlag;
      fast_.push_back(static_cast<int>(i));
      grown_[i] = boxes_[i];
      continue;
    }
    grown_[i] = fatten(boxes_[i], static_cast<float>(std::min(margin, kMaxGrowth)));
    slow_ids_.push_back(static_cast<int>(i));
    slow_grown_.push_back(grown_[i]);
  }
  grid_.build_and_find_pairs(slow_grown_, candidates_);
  // Grid ids are positions in slow_ids_, which is ascending: mapping keeps i < j. Sorted once
  // here, the candidates give every frame's pairs in order (no sort of them per frame), and
  // their checks read the boxes in ascending order of the first object.
  for (BroadPair& pair : candidates_) {
    pair = {slow_ids_[std::size_t(pair.first)], slow_ids_[std::size_t(pair.second)]};
  }
  sort_pairs(candidates_, sort_scratch_);
  wake_.assign(candidates_.size(), time_);
  expires_at_ = until;
  needs_rebuild_ = false;
  demoted_since_rebuild_ = 0;
  ++stats_.rebuilds;
  stats_.candidate_pairs = static_cast<std::int64_t>(candidates_.size());
  stats_.fast_objects = static_cast<std::int64_t>(fast_.size());
}

template <int D>
template <bool kPrefetch>
void TemporalBroadPhaseN<D>::check_candidates(int begin, int end, PairList& out, std::int64_t& checks,
                                              std::int64_t& skipped) {
  // Without branches on the outcome: whether a candidate sleeps, overlaps or is apart is as
  // good as random from one to the next, and the mispredictions cost more than doing every
  // candidate's arithmetic (perf: 14 ns a candidate with branches, most of it after them).
  // A candidate is active unless it sleeps (skipped) or has a fast member (found by
  // find_fast_pairs: demoted since the rebuild). An active one overlaps when no separation
  // along an axis is positive, and then is emitted and stays awake; otherwise it sleeps until
  // the gap (the largest separation) could close at the pair's combined speed bound. Gaps are
  // in double: a float difference of two floats could round to 0 and hide a positive gap.
  constexpr int kChunk = 256;  // pairs kept on the stack, then appended in order
  std::array<BroadPair, kChunk> found;
  const double time = time_;
  // A select by bit masks: compilers turn a ternary of doubles back into a branch.
  const auto pick = [](bool take_a, double a, double b) {
    const std::uint64_t mask = std::uint64_t{0} - static_cast<std::uint64_t>(take_a);
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(a) & mask) |
                                 (std::bit_cast<std::uint64_t>(b) & ~mask));
  };
  std::int64_t checked = 0, slept = 0;
  for (int first = begin; first < end; first += kChunk) {
    const int last = std::min(end, first + kChunk);
    int count = 0;
    for (int c = first; c < last; ++c) {
      if (kPrefetch && c + kCandidatePrefetchAhead < end) {
        const BroadPair ahead = candidates_[std::size_t(c + kCandidatePrefetchAhead)];
        for (const int id : {ahead.first, ahead.second}) {
          __builtin_prefetch(&boxes_[std::size_t(id)]);
          __builtin_prefetch(&speeds_[std::size_t(id)]);
          __builtin_prefetch(&flags_[std::size_t(id)]);
        }
      }
      const BroadPair pair = candidates_[std::size_t(c)];
      const auto a = std::size_t(pair.first), b = std::size_t(pair.second);
      const double wake = wake_[std::size_t(c)];
      const unsigned flags = unsigned{flags_[a]} | flags_[b];
      // (a raised speed bound since the last check wakes the pair: set_speed_bounds)
      const bool asleep = (wake > time) & ((flags & kRaisedFlag) == 0);
      const bool active = !asleep & ((flags & kFastFlag) == 0);
      const AabbN<D>& box_a = boxes_[a];
      const AabbN<D>& box_b = boxes_[b];
      double gap = -std::numeric_limits<double>::infinity();
      for (int k = 0; k < D; ++k) {
        gap = std::max({gap, static_cast<double>(box_b.min[k]) - box_a.max[k],
                        static_cast<double>(box_a.min[k]) - box_b.max[k]});
      }
      const bool touching = !(gap > 0.0);  // overlap(box_a, box_b): boxes are never NaN here
      const double closing = static_cast<double>(speeds_[a]) + speeds_[b];
      const double apart = pick(closing > 0.0, time + (gap / closing) * (1.0 - kWakeEarly),
                                std::numeric_limits<double>::infinity());
      wake_[std::size_t(c)] = pick(active, pick(touching, time, apart), wake);
      found[std::size_t(count)] = pair;
      count += static_cast<int>(active & touching);
      checked += static_cast<int>(active);
      slept += static_cast<int>(asleep);
    }
    out.insert(out.end(), found.begin(), found.begin() + count);
  }
  checks += checked;
  skipped += slept;
}

template <int D>
bool TemporalBroadPhaseN<D>::rebuild_due(double next_time) const noexcept {
  if (boxes_.empty() || !(next_time >= time_)) return false;
  return (needs_rebuild_ || next_time > expires_at_) && next_time - time_ <= horizon_;
}

template <int D>
void TemporalBroadPhaseN<D>::rebuild_now(double next_time) {
  if (!std::isfinite(next_time) || next_time < time_) throw InvalidInput("time: not finite or goes back");
  rebuild(next_time + horizon_);
}

template <int D>
void TemporalBroadPhaseN<D>::find_pairs(PairList& pairs) {
  find_pairs(pairs, nullptr);
}

template <int D>
void TemporalBroadPhaseN<D>::find_pairs(PairList& pairs, TaskScheduler* scheduler) {
  pairs.clear();
  if (needs_rebuild_ || time_ > expires_at_) rebuild(time_ + horizon_);
  const auto count = static_cast<int>(candidates_.size());
  const auto fast_count = static_cast<int>(fast_.size());
  const int workers = scheduler != nullptr ? scheduler->worker_count() : 1;
  std::size_t candidate_pairs = 0;  // the candidates' pairs, ahead of the fast objects' in `pairs`
  if (workers < 2 || count + kFastQueryCandidates * fast_count < kSplitFindFrom) {
    // (in a world on several workers the boxes were just written on other cores: prefetched)
    if (workers >= 2) {
      check_candidates<true>(0, count, pairs, stats_.checks, stats_.skipped_checks);
    } else {
      check_candidates<false>(0, count, pairs, stats_.checks, stats_.skipped_checks);
    }
    candidate_pairs = pairs.size();
    query_fast(0, fast_count, pairs, stats_.checks);
  } else {
    // The candidates' checks and the fast objects' grid queries as the ranges of one parallel
    // region (one wait for the workers, where two had been: at 1e3 objects on two threads they
    // took 11-16 us a frame on one). Each range writes its own share; the candidates' shares
    // are joined in range order, which is the candidates' order, ascending; the fast objects'
    // pairs after them are sorted by merge_fast_pairs below, so the result is the same for any
    // split. Small sets are cut in one range per worker, large ones in ranges of a fixed size.
    const int per_candidates = std::max(kMinCandidatesPerTask, std::min(kObjectsPerTask, (count + workers - 1) / workers));
    const int per_fast = std::max(1, std::min(kFastObjectsPerTask, (fast_count + workers - 1) / workers));
    const int candidate_ranges = (count + per_candidates - 1) / per_candidates;
    const int ranges = candidate_ranges + (fast_count + per_fast - 1) / per_fast;
    if (range_out_.size() < static_cast<std::size_t>(ranges)) range_out_.resize(static_cast<std::size_t>(ranges));
    parallel_for(scheduler, ranges, 1, [&](int begin, int end, int) {
      for (int r = begin; r < end; ++r) {
        RangeOutput& out = range_out_[static_cast<std::size_t>(r)];  // (capacity kept: no allocation)
        out.pairs.clear();
        out.checks = 0;
        out.skipped = 0;
        if (r < candidate_ranges) {
          check_candidates<true>(r * per_candidates, std::min(count, (r + 1) * per_candidates), out.pairs, out.checks,
                           out.skipped);
        } else {
          const int first = (r - candidate_ranges) * per_fast;
          query_fast(first, std::min(fast_count, first + per_fast), out.pairs, out.checks);
        }
      }
    });
    for (int r = 0; r < ranges; ++r) {
      const RangeOutput& out = range_out_[static_cast<std::size_t>(r)];
      pairs.insert(pairs.end(), out.pairs.begin(), out.pairs.end());
      stats_.checks += out.checks;
      stats_.skipped_checks += out.skipped;
      if (r + 1 == candidate_ranges) candidate_pairs = pairs.size();
    }
  }
  if (raised_pending_) clear_raised_flags();  // every candidate has been checked against them
  fast_among_themselves(pairs);
  merge_fast_pairs(pairs, candidate_pairs);
}

template <int D>
void TemporalBroadPhaseN<D>::merge_fast_pairs(PairList& pairs, std::size_t sorted_end) {
  if (pairs.size() == sorted_end) return;
  const auto middle = pairs.begin() + static_cast<std::ptrdiff_t>(sorted_end);
  fast_sorted_.assign(middle, pairs.end());
  sort_pairs(fast_sorted_, sort_scratch_);
  // (std::inplace_merge would allocate a buffer every frame; merged_ keeps its capacity)
  merged_.resize(pairs.size());
  std::merge(pairs.begin(), middle, fast_sorted_.begin(), fast_sorted_.end(), merged_.begin());
  pairs.swap(merged_);
}

template <int D>
void TemporalBroadPhaseN<D>::query_fast(int begin, int end, PairList& out, std::int64_t& checks) const {
  // Fast objects, every frame, against the slow ones through the grid (a slow object's grown box
  // contains its current box).
  for (int n = begin; n < end; ++n) {
    const int f = fast_[std::size_t(n)];
    const AabbN<D>& box_f = boxes_[std::size_t(f)];
    grid_.query(box_f, [&](int slot) {
      const int s = slow_ids_[std::size_t(slot)];
      if (is_fast(s)) return true;  // demoted since the rebuild: a fast pair below
      ++checks;
      if (overlap(box_f, boxes_[std::size_t(s)])) out.emplace_back(std::min(f, s), std::max(f, s));
      return true;
    });
  }
}

template <int D>
void TemporalBroadPhaseN<D>::fast_among_themselves(PairList& pairs) {
  // The fast objects against each other by sort and sweep along x (1% of a million bodies are
  // bullets: all pairs of them would be 5e7 checks a frame).
  if (fast_.size() >= kFastGridFrom) {
    // Many fast objects: a sweep along x checks each against every other whose box spans the
    // same x (3D bullets crossing 20 body sizes a frame: a quarter of the 3D broad phase at 1e5
    // bodies, on one thread). A grid of their own boxes finds the same pairs.
    fast_boxes_.resize(fast_.size());
    for (std::size_t k = 0; k < fast_.size(); ++k) fast_boxes_[k] = boxes_[std::size_t(fast_[k])];
    fast_grid_.build(fast_boxes_);
    fast_index_ = FastIndex::grid;  // until the boxes or the fast objects change
    fast_grid_.find_pairs(fast_pairs_);
    stats_.checks += static_cast<std::int64_t>(fast_pairs_.size());
    for (const auto& [k, m] : fast_pairs_) {
      const int f = fast_[std::size_t(k)], g = fast_[std::size_t(m)];
      pairs.emplace_back(std::min(f, g), std::max(f, g));
    }
    return;
  }
  fast_order_.assign(fast_.begin(), fast_.end());
  std::sort(fast_order_.begin(), fast_order_.end(), [&](int a, int b) {
    const float xa = boxes_[std::size_t(a)].min[0], xb = boxes_[std::size_t(b)].min[0];
    return xa < xb || (xa == xb && a < b);
  });
  float widest = 0.0f;
  for (std::size_t k = 0; k < fast_order_.size(); ++k) {
    const int f = fast_order_[k];
    const AabbN<D>& box_f = boxes_[std::size_t(f)];
    widest = std::max(widest, box_f.max[0] - box_f.min[0]);
    for (std::size_t m = k + 1; m < fast_order_.size(); ++m) {
      const int g = fast_order_[m];
      const AabbN<D>& box_g = boxes_[std::size_t(g)];
      if (box_g.min[0] > box_f.max[0]) break;
      ++stats_.checks;
      if (overlap(box_f, box_g)) pairs.emplace_back(std::min(f, g), std::max(f, g));
    }
  }
  fast_max_width_ = widest;
  fast_index_ = FastIndex::sorted;  // until the boxes or the fast objects change
}

template <int D>
template <class Visit>
bool TemporalBroadPhaseN<D>::visit_fast_in_x(float lo, float hi, Visit&& visit) const {
  if (fast_index_ != FastIndex::sorted) {
    for (const int f : fast_) {
      if (!visit(f)) return false;
    }
    return true;
  }
  return detail::visit_in_x_range(fast_order_.begin(), fast_order_.end(), lo, hi, fast_max_width_,
                                  [&](int id) { return boxes_[std::size_t(id)].min[0]; }, visit);
}

template <int D>
void TemporalBroadPhaseN<D>::query(const AabbN<D>& box, QueryCallback callback) const {
  if (!grid_is_current()) {
    for (int i = 0; i < size(); ++i) {
      if (overlap(box, boxes_[i]) && !callback(i)) return;
    }
    return;
  }
  bool go_on = true;
  grid_.query(box, [&](int slot) {
    const int id = slow_ids_[std::size_t(slot)];
    go_on = is_fast(id) || !overlap(box, boxes_[std::size_t(id)]) || callback(id);
    return go_on;
  });
  if (!go_on) return;
  if (fast_index_ == FastIndex::grid) {
    fast_grid_.query(box, [&](int k) { return callback(fast_[std::size_t(k)]); });
    return;
  }
  visit_fast_in_x(box.min[0], box.max[0], [&](int f) { return !overlap(box, boxes_[std::size_t(f)]) || callback(f); });
}

template <int D>
void TemporalBroadPhaseN<D>::query_point(const VecN<D>& point, QueryCallback callback) const {
  if (!grid_is_current()) {
    for (int i = 0; i < size(); ++i) {
      if (contains(boxes_[i], point) && !callback(i)) return;
    }
    return;
  }
  bool go_on = true;
  grid_.query_point(point, [&](int slot) {
    const int id = slow_ids_[std::size_t(slot)];
    go_on = is_fast(id) || !contains(boxes_[std::size_t(id)], point) || callback(id);
    return go_on;
  });
  if (!go_on) return;
  if (fast_index_ == FastIndex::grid) {
    fast_grid_.query_point(point, [&](int k) { return callback(fast_[std::size_t(k)]); });
    return;
  }
  visit_fast_in_x(point[0], point[0], [&](int f) { return !contains(boxes_[std::size_t(f)], point) || callback(f); });
}

template <int D>
void TemporalBroadPhaseN<D>::ray_cast(const RayN<D>& ray, RayCallback callback) const {
  float limit = 1.0f;
  const SlabRayN<D> slab(ray);
  const auto visit = [&](int id) {
    if (slab.fraction(boxes_[id], limit) < 0.0f) return limit;
    const float r = callback(id, limit);
    if (r < limit) limit = r;
    return limit;
  };
  if (!grid_is_current()) {
    for (int i = 0; i < size() && limit > 0.0f; ++i) visit(i);
    return;
  }
  grid_.ray_cast(ray, slab, [&](int slot, float) {
    const int id = slow_ids_[std::size_t(slot)];
    return is_fast(id) ? limit : visit(id);  // demoted: visited with the fast ones
  });
  if (limit <= 0.0f) return;
  if (fast_index_ == FastIndex::grid) {
    // (visit tests the box again: the fast grid's walk starts at fraction 1, not at the clip
    // the slow objects left.)
    fast_grid_.ray_cast(ray, slab, [&](int k, float) { return visit(fast_[std::size_t(k)]); });
    return;
  }
  // Along x the ray reaches [x0, x1] within the clip so far (which only shrinks).
  const float x_end = ray.origin[0] + limit * ray.translation[0];
  visit_fast_in_x(std::min(ray.origin[0], x_end), std::max(ray.origin[0], x_end), [&](int f) {
    visit(f);
    return limit > 0.0f;
  });
}

template <int D>
std::size_t TemporalBroadPhaseN<D>::memory_bytes() const noexcept {
  std::size_t range_pairs = 0;
  for (const RangeOutput& out : range_out_) range_pairs += out.pairs.capacity();
  return (boxes_.capacity() + next_boxes_.capacity() + grown_.capacity()) * sizeof(AabbN<D>) +
         (range_pairs + fast_sorted_.capacity() + merged_.capacity() + sort_scratch_.capacity()) *
             sizeof(BroadPair) +
         broke_.capacity() +
         (speeds_.capacity() + scratch_.capacity()) * sizeof(float) +
         candidates_.capacity() * sizeof(BroadPair) + wake_.capacity() * sizeof(double) +
         (slow_grown_.capacity() + fast_boxes_.capacity()) * sizeof(AabbN<D>) +
         fast_pairs_.capacity() * sizeof(BroadPair) + fast_grid_.memory_bytes() +
         (slow_ids_.capacity() + fast_.capacity() + fast_order_.capacity()) * sizeof(int) + flags_.capacity() +
         next_speeds_.capacity() * sizeof(float) + grid_.memory_bytes();
}

template class TemporalBroadPhaseN<2>;
template class TemporalBroadPhaseN<3>;

}  // namespace collide
