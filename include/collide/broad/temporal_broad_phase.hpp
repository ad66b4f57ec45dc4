#pragma once
/// @file
/// A temporal broad phase (the lesson's "Temporal Broad Phase"): with a bound on how fast each
/// object moves, two objects a gap g apart cannot meet before g / (v_a + v_b), so their pair
/// need not be checked again until then.
///
/// Speed bound contract: between any two times t1 < t2, object i's box at t2 lies inside its
/// box at t1 grown by speed_bound[i] * (t2 - t1) on every side (world units per time unit; the
/// caller picks the time unit). It is checked at every update, in double precision, so the
/// bound must include the float rounding of the positions: at coordinates of magnitude M a
/// step may come out up to M * 6e-8 longer than intended (add e.g. M * 4e-7 per frame). A bound
/// that is too tight is never a missed pair, only a rebuild (see 3 below).
///
/// How it works:
///  1. Every `horizon` time units (or sooner, see below) each box is grown by v_i * horizon and
///     the pairs of grown boxes are found with a LooseGrid: the candidates. A pair not
///     among them cannot touch before the horizon ends, so it is never checked.
///  2. Each frame, a candidate is checked only when its wake time has come; a separated pair
///     (gap g, the largest per-axis separation of the boxes) sleeps until t + g / (v_a + v_b).
///     Skipped checks are counted (stats().skipped_checks). An object whose speed bound rises
///     (set_speed_bounds) is flagged, and its sleeping pairs are checked at the next frame.
///  3. Fast objects (a bullet among walkers: growth over the horizon above a few grid cells)
///     are not grown, which would make them candidates with everything they could reach; each
///     frame a grid query finds their pairs with the others directly (stats().fast_objects),
///     and their pairs among themselves come from a sort and sweep along x or, when there are
///     many, from a uniform grid of their own built each frame.
///  4. An object that breaks its bound (a bounce, a push, a teleport) or leaves its grown box
///     joins the fast objects until the next rebuild: its candidate pairs are ignored and a
///     grid query finds its pairs every frame (stats().bound_violations, demoted). Only when
///     more than one object in 16 has done so does the next find_pairs rebuild the candidates
///     from the current boxes (a crowd of bouncing bodies broke some bound every frame, and
///     rebuilt every frame). Nothing is missed either way. A different number of objects is a
///     new set, with a speed bound for each: update throws, build starts over.
///  5. The rebuild of 1 may also run ahead of the update that would make it (rebuild_due,
///     rebuild_now): from the boxes of now, grown for the frame to come as well, so it can run
///     on a worker while the game moves the objects (the world does this with several workers).
/// The result equals brute force at every frame while the contract holds, and also when it
/// does not (thanks to 4).
///
/// Memory per object: the current box and update's next one, the grown box, the speed bound and
/// set_speed_bounds' next one (3 * 8*D + 8 bytes, plus 2 flag bytes), the loose grid over the
/// grown boxes, and 16 bytes per candidate pair.

#include <collide/broad/broad_phase.hpp>
#include <collide/broad/loose_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/core/large_pages.hpp>
#include <collide/core/task_scheduler.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace collide {

/// Speed-bound broad phase over boxes in D dimensions. It offers the queries of the
/// BroadPhase concept; build and update take speed bounds and times.
/// The cell of the temporal broad phase's loose grid (LooseGridN::Options::cell_quantile): the
/// grown boxes are of nearly one size, and a box the cell is too small for is a big box every
/// query and ray tests by a search along x (world rays at 1e5 bodies: 1,244 big boxes at the
/// grid's default of 0.9, 1.1-1.2 us a ray; at this 0.98-1.0 us, as over a hierarchical grid).
inline constexpr float kTemporalCellQuantile = 0.999f;

template <int D>
class TemporalBroadPhaseN {
 public:
  /// What the constructor takes; it rejects bad values, naming the field.
  struct Options {
    /// How long a candidate set stays valid, in the caller's time unit. 0 (the default) picks
    /// the time the median object needs at its speed bound to move half the median box size:
    /// grown boxes stay small, so candidates stay few.
    double horizon = 0.0;
  };

  /// Counters since build.
  struct Stats {
    /// Box tests made: awake candidates, and the fast objects' tests against the slow ones and
    /// among themselves (each tested pair of the sweep, or each pair their own grid found).
    std::int64_t checks = 0;
    std::int64_t skipped_checks = 0;    ///< candidate pair tests skipped: gap not closable yet
    std::int64_t rebuilds = 0;          ///< candidate sets built
    std::int64_t bound_violations = 0;  ///< object updates that broke their speed bound
    std::int64_t candidate_pairs = 0;   ///< size of the current candidate set
    std::int64_t fast_objects = 0;      ///< objects handled every frame at the last rebuild
    std::int64_t demoted = 0;           ///< objects that joined the fast ones between rebuilds
  };

  TemporalBroadPhaseN() = default;
  /// Throws InvalidInput for a negative or non-finite horizon.
  explicit TemporalBroadPhaseN(Options options);

  /// Starts over at `time` with these boxes and speed bounds (one per box, >= 0, finite).
  /// Throws InvalidInput for a bad box (naming its index), a bad speed bound ("speed bound 4:
  /// negative"), a count mismatch or a non-finite time.
  void build(std::span<const AabbN<D>> boxes, std::span<const float> speed_bounds,
             double time = 0.0);
  /// The same objects at a later `time` (>= the previous one). Objects that broke their bound
  /// are detected here. Throws InvalidInput for a bad box, a different count, or a time that is
  /// not finite or goes backwards.
  void update(std::span<const AabbN<D>> boxes, double time);

  /// New speed bounds from the current time on (one per object, >= 0, finite): for objects
  /// whose speed changes (a bounce, a collision response). A raised bound wakes the object's
  /// sleeping candidate pairs (their wake times assumed the old bound); a lowered one keeps
  /// the wake times, which stay conservative. Throws InvalidInput for a bad bound or count.
  void set_speed_bounds(std::span<const float> speed_bounds);
  /// Every pair overlapping at the current time, once, i < j, in ascending order (as
  /// sort_pairs leaves them: the candidates are kept sorted, so only the fast objects' few
  /// pairs are sorted, then merged in).
  void find_pairs(PairList& pairs);

  /// update, set_speed_bounds and find_pairs with their per-object and per-candidate loops
  /// spread over a game's job system (null: the calls above). The same pairs in the same order
  /// and the same state for any worker count.
  void update(std::span<const AabbN<D>> boxes, double time, TaskScheduler* scheduler);
  void set_speed_bounds(std::span<const float> speed_bounds, TaskScheduler* scheduler);
  void find_pairs(PairList& pairs, TaskScheduler* scheduler);
  /// update() in three parts, for a caller that makes the boxes in a parallel pass of its own
  /// and checks each range of objects while their boxes are still in the cache (the world's
  /// body pass does, where a separate update re-read every box and, with few objects, ran on
  /// one thread): begin_update(boxes.size(), time); then update_range(begin, end, boxes) over
  /// ranges that cover [0, size()) once each, from any threads at once (a range writes only its
  /// own objects' slots; `boxes` is the whole span, read at [begin, end)); then
  /// finish_update(boxes). The same state as update(boxes, time). begin_update throws as update
  /// does for a count mismatch or a bad time, finish_update for a bad box (naming the first)
  /// before anything changes. Not beside rebuild_now: a range reads what a rebuild writes.
  void begin_update(std::size_t count, double time);
  void update_range(int begin, int end, std::span<const AabbN<D>> boxes) noexcept;
  void finish_update(std::span<const AabbN<D>> boxes);
  /// True when the next find_pairs, after an update to `next_time` (within one horizon of
  /// now), would build the candidate set anew: its window ends before then, or a build asked
  /// for it.
  [[nodiscard]] bool rebuild_due(double next_time) const noexcept;
  /// Builds the candidate set now, ahead of the update to `next_time`: from the current boxes
  /// and speed bounds (of the last update and set_speed_bounds), each box grown for the time
  /// from now to a horizon after `next_time`, on the calling thread. It reads and writes only
  /// this object, so a game may run it on a worker beside its own work while it moves the
  /// objects for that update (a temporal pipeline); find_pairs then has no rebuild to do for a
  /// horizon. The pairs are the same either way. Throws InvalidInput for a `next_time` that is
  /// not finite or before the current time.
  void rebuild_now(double next_time);
  /// Each id whose current box overlaps `box`, once.
  void query(const AabbN<D>& box, QueryCallback callback) const;
  /// Each id whose current box contains `point`, once.
  void query_point(const VecN<D>& point, QueryCallback callback) const;
  /// Each id whose current box the ray meets, once.
  void ray_cast(const RayN<D>& ray, RayCallback callback) const;

  /// Number of objects given to the last build or update.
  [[nodiscard]] int size() const noexcept { return static_cast<int>(boxes_.size()); }
  /// Heap bytes held (vector capacities), for the memory-per-object figures.
  [[nodiscard]] std::size_t memory_bytes() const noexcept;
  /// The counters since the last build (see Stats); candidate_pairs and fast_objects are of
  /// the last rebuild of the candidate set.
  [[nodiscard]] const Stats& stats() const noexcept { return stats_; }
  /// The horizon in use (after the automatic choice).
  [[nodiscard]] double horizon() const noexcept { return horizon_; }

 private:
  /// The grown boxes and the candidate pairs, anew, on the calling thread (a world runs it on
  /// a worker beside its motion pass: rebuild_now).
  void rebuild(double until);
  /// Object i broke its bound or left its grown box: handled with the fast objects until the
  /// next rebuild (or a rebuild is due when too many have).
  void demote(int i);
  /// Every object's kRaisedFlag cleared (find_pairs has woken their pairs).
  void clear_raised_flags() noexcept;
  [[nodiscard]] bool grid_is_current() const noexcept { return !needs_rebuild_; }

  Options options_{};
  double horizon_ = 0.0;
  double time_ = 0.0;        // time of the current boxes
  double expires_at_ = 0.0;  // the candidate set covers the boxes' motion up to this time
  double update_time_ = 0.0;  // begin_update's time, until finish_update
  bool needs_rebuild_ = true;
  LargePageVector<AabbN<D>> boxes_;
  LargePageVector<AabbN<D>> grown_;   // boxes at the rebuild grown by v * (expires_at_ - then)
  LargePageVector<float> speeds_;
  PairList candidates_;  // ascending: checked in order, the pairs come out sorted
  LargePageVector<double> wake_;      // earliest time each candidate can overlap
  /// Over slow_grown_: the candidates at a rebuild (a loose grid's full rebuild and pair pass
  /// took a quarter of a hierarchical grid's build and pairs), the queries and rays.
  LooseGridN<D> grid_{typename LooseGridN<D>::Options{.cell_quantile = kTemporalCellQuantile}};
  std::vector<float> scratch_;
  LargePageVector<float> next_speeds_;     // set_speed_bounds' scratch: the new bounds, then the old ones
  double cell_ = 0.0;                  // suggested grid cell at build: the yardstick of "fast"
  /// Per object: kFastFlag (fast at the last rebuild, or demoted since) and kRaisedFlag (its
  /// speed bound rose since the last find_pairs: its sleeping candidates are checked anyway).
  LargePageVector<unsigned char> flags_;
  static constexpr unsigned char kFastFlag = 1;
  static constexpr unsigned char kRaisedFlag = 2;
  bool raised_pending_ = false;        // some object's kRaisedFlag is set
  [[nodiscard]] bool is_fast(int i) const noexcept { return (flags_[std::size_t(i)] & kFastFlag) != 0; }
  std::vector<int> fast_;              // ids of the fast objects (ascending, then the demoted)
  std::size_t demoted_since_rebuild_ = 0;
  std::vector<int> fast_order_;        // find_pairs' scratch: the fast objects by box min x
  std::vector<AabbN<D>> fast_boxes_;   // find_pairs' scratch: the fast objects' boxes, by place in fast_
  SortedGridN<D> fast_grid_;           // over fast_boxes_, when there are many fast objects
  /// What indexes the fast objects' current boxes for the queries, as the last find_pairs left
  /// it (any change of the boxes or of the fast objects drops it): nothing (each is tested),
  /// fast_grid_ (places in fast_), or fast_order_ by box min x with fast_max_width_ (1% bullets
  /// among 1e5 bodies were 1,100 box tests a world ray cast, 110 among 1e4).
  enum class FastIndex : unsigned char { none, grid, sorted };
  FastIndex fast_index_ = FastIndex::none;
  float fast_max_width_ = 0.0f;  // the widest fast box along x, when fast_order_ indexes them
  /// Calls visit(id) for each fast object whose box may reach [lo, hi] along x (all of them
  /// without the sorted index) until it returns false; returns false when stopped.
  template <class Visit>
  bool visit_fast_in_x(float lo, float hi, Visit&& visit) const;
  PairList fast_pairs_;                // fast_grid_'s pairs (places in fast_)
  LargePageVector<unsigned char> broke_;   // update's scratch: per object, kept / broke its bound / left its grown box / bad
  LargePageVector<AabbN<D>> next_boxes_;   // update's scratch: the new boxes, swapped with boxes_ when all are valid
  struct RangeOutput {                 // a range's share of find_pairs on the workers
    PairList pairs;
    std::int64_t checks = 0;
    std::int64_t skipped = 0;
  };
  std::vector<RangeOutput> range_out_;
  PairList fast_sorted_;                 // find_pairs' scratch: the fast objects' pairs, sorted
  PairList merged_;                      // find_pairs' scratch: candidates' and fast pairs merged
  PairList sort_scratch_;                // sort_pairs' storage (candidates at a rebuild, fast pairs)
  /// The candidate checks of candidates [begin, end) (wake time, overlap, next wake time): the
  /// overlapping pairs appended to `out` in candidate order, checks and sleepers counted.
  /// kPrefetch: ask for the objects of candidates ahead (when the scheduler has several workers).
  template <bool kPrefetch>
  void check_candidates(int begin, int end, PairList& out, std::int64_t& checks, std::int64_t& skipped);
  /// The pairs of fast objects [begin, end) of fast_ with the slow ones, by grid queries, appended
  /// to `out` (any order); the checks counted. Reads only: ranges may run on several workers.
  void query_fast(int begin, int end, PairList& out, std::int64_t& checks) const;
  /// The fast objects' pairs among themselves, appended to `pairs` (any order): by sort and
  /// sweep along x or, when many, a grid of their own.
  void fast_among_themselves(PairList& pairs);
  /// pairs[0, sorted_end) is ascending, the rest (the fast objects' pairs, none among the first
  /// part) in any order: sorts the rest and merges it in.
  void merge_fast_pairs(PairList& pairs, std::size_t sorted_end);
  LargePageVector<int> slow_ids_;          // grid slot -> object id, ascending
  LargePageVector<AabbN<D>> slow_grown_;   // grown boxes of the slow objects, by grid slot
  Stats stats_{};
};

using TemporalBroadPhase = TemporalBroadPhaseN<2>;
using TemporalBroadPhase3 = TemporalBroadPhaseN<3>;

}  // namespace collide
