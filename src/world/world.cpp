// The world, 2D and 3D: statics and bodies, and the step (see world.hpp for the pipeline). One
// implementation for both dimensions; the geometry that differs is in world_dim.cpp.

#include "world_impl.hpp"

#include <collide/ccd/sweep.hpp>
#include <collide/ccd/time_of_impact.hpp>
#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/decompose/convex_decomposition.hpp>
#include <collide/narrow/contact.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <type_traits>

namespace collide {

namespace detail {

namespace {

/// Bounding circles (spheres) are grown by this fraction of their radius, so that rounding can
/// never make the pretest reject a pair whose exact contact reports touching (the pretest must
/// be redundant: it may only reject pairs the exact test rejects too).
constexpr float kPretestSlack = 1e-4f;

/// A body's speed bound for the temporal broad phase is its next step's motion per second times
/// this (room for push-outs by statics, which are not known in advance).
constexpr float kSpeedBoundSlack = 1.5f;

/// Static clearance (BodyN::clearance): the distance measured reaches this many bounding radii
/// of the piece beyond its sphere (further statics do not matter for the next few dozen steps
/// of a body moving a fraction of its size per step, and a bound keeps the measure cheap).
constexpr float kClearanceReach = 1.0f;
/// A piece is clear while its centre has moved less than its gap minus this fraction of its
/// bounding radius, and minus kClearanceRounding of its coordinates: far more than the
/// contacts' own allowance for rounding (kRelativeTolerance of the size and the coordinates),
/// so a skipped piece is one whose contact query would have found nothing.
constexpr float kClearanceSlack = 1e-3f;
constexpr float kClearanceRounding = 1e-4f;
/// A fast body whose whole motion stays within its pieces' clearance skips its continuous
/// collision query; the clearance then must also hold this many bounding radii more than the
/// time of impact's target separation (a query stops that far from a static and calls it a hit).
constexpr float kClearanceToiMargin = 4.0f * kToiTargetSeparation;
/// A body still deeper than this fraction of the check's tunnelling depth after the last push-out
/// is jammed (StepStats::jammed): it goes back to its pose at the start of the step.
constexpr float kJamDepthFraction = 0.5f;

}  // namespace

}  // namespace detail

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

template <class Xf>
void check_transform(const Xf& xf, const std::string& field) {
  if (!is_valid(xf)) throw InvalidInput(field + ": not finite or rotation not unit length");
}

/// The coordinate of `box` farthest from the origin (an infinity or NaN if it has one).
template <int D>
float farthest_coordinate(const AabbN<D>& box) noexcept {
  float far = 0.0f;
  for (int k = 0; k < D; ++k) {
    for (const float c : {box.min[k], box.max[k]}) {
      if (!(std::fabs(c) <= std::fabs(far))) far = c;  // (a NaN is kept: it fails the range test)
    }
  }
  return far;
}

template <class S>
void check_shapes(const std::vector<S>& shapes, const std::string& field) {
  if (shapes.empty()) throw InvalidInput(field + ": no shapes");
  if (shapes.size() > 0xffff) throw InvalidInput(field + ": more than 65535 shapes");
}

CheckChainOptions chain_options(bool adaptive) {
  CheckChainOptions o;
  o.timing_interval = 8;  // read the clock on one pair in 8: the stopwatch must not cost more than it saves
  o.reorder_interval = 256;
  if (!adaptive) {  // never re-decide, never explore: declaration order, every pretest on
    o.reorder_interval = 0xffffffffu;
    o.explore_interval = 0xffffffffu;
  }
  return o;
}

constexpr std::array<bool, 3> kChainPretests = {false, false, true};

/// Smallest range of bodies (or body pairs) a step hands to one task: enough work to pay for
/// a task (a body's motion and static contacts take a microsecond or more, a pair's early out
/// and contact 50-100 ns on average: 64 pairs are a few microseconds, and the 150 pairs of a
/// frame at 1e3 bodies split in two took 12-13 us a frame where one range took 15, collide run
/// on two threads, builds alternating; 512 pairs a range left them on one thread). 64 bodies
/// (128 until stop 86): at 1e3 bodies a frame's motion pass is about eight ranges of 15 us, one
/// of them carrying the candidate rebuild ahead, and the pass's end waited on the last range
/// (BM_CollideSpeedup at 1e3, five alternating runs: 1.78-1.80x -> 1.81-1.82x; 32 no better;
/// the step at 1e5 and 1e6 unchanged).
constexpr int kBodiesPerTask = 64;
constexpr int kPairsPerTask = 64;
/// Bodies moved, then resolved against the statics, at a time within a task (a few tens of
/// kilobytes of bodies: still in the cache for the second half).
constexpr int kBodiesPerBlock = 64;
/// Most body proxies whose temporal candidate set is rebuilt ahead, beside the bodies' motion
/// (move_bodies). A set built ahead covers one more frame, so its boxes grow more and it has
/// more candidates: on one thread that is all it does (bench_world_scale, 1e6 bodies: 371 ->
/// 386 ns a body), so it needs a second worker; on two it paid at 1e3 and 1e4 bodies (a frame
/// 8% and 4% shorter) and not at 1e5, where the rebuild's own pair search on the workers serves.
constexpr std::size_t kRebuildAheadMaxProxies = 32768;

/// `v` shortened to at most `max_length`.
template <class V>
V clamp_length(V v, float max_length) {
  const float len2 = length_squared(v);
  if (len2 <= max_length * max_length) return v;
  return v * (max_length / std::sqrt(len2));
}

/// `v` with its component along unit `n` mirrored when it points along n.
template <class V>
V reflect_if_approaching(V v, V n) {
  const float vn = dot(v, n);
  return vn > 0.0f ? v - 2.0f * vn * n : v;
}

/// The sort key of contact `c` at `place` in its list: the events' order is by A's key, then B's.
template <int D>
detail::ContactSortKey contact_key(const ContactN<D>& c, std::uint32_t place = 0) {
  return {c.a.key(), c.b.key(), place};
}

template <int D>
bool contact_less(const ContactN<D>& x, const ContactN<D>& y) {
  return contact_key(x) < contact_key(y);
}

template <int D>
int compare_contacts(const ContactN<D>& x, const ContactN<D>& y) {
  if (contact_less(x, y)) return -1;
  if (contact_less(y, x)) return 1;
  return 0;
}

constexpr std::array<const char*, 8> kBroadPhaseNames = {
    "temporal", "hierarchical_grid", "sorted_grid", "loose_grid", "hash_grid",
    "dynamic_tree", "sweep_and_prune", "brute_force"};

}  // namespace

const char* to_string(WorldBroadPhase broad_phase) noexcept {
  return kBroadPhaseNames[static_cast<std::size_t>(broad_phase)];
}

WorldBroadPhase world_broad_phase_from_string(std::string_view name) {
  for (std::size_t i = 0; i < kBroadPhaseNames.size(); ++i) {
    if (name == kBroadPhaseNames[i]) return static_cast<WorldBroadPhase>(i);
  }
  std::string valid;
  for (const char* n : kBroadPhaseNames) valid += valid.empty() ? n : std::string(", ") + n;
  throw InvalidInput("broad phase: unknown name \"" + std::string(name) + "\" (valid: " + valid +
                     ")");
}

const char* to_string(ContactEventType type) noexcept {
  switch (type) {
    case ContactEventType::begin: return "begin";
    case ContactEventType::persist: return "persist";
    case ContactEventType::end: return "end";
  }
  return "unknown";
}

std::vector<Shape2D> convex_pieces(std::span<const Vec2> outline, std::string_view name) {
  std::vector<Shape2D> pieces;
  for (Polygon& p : decompose_convex(outline, name)) pieces.emplace_back(std::move(p));
  return pieces;
}

void StepStats::accumulate(const StepStats& o) noexcept {
  steps += o.steps;
  bodies += o.bodies;
  static_pieces += o.static_pieces;
  body_pairs += o.body_pairs;
  static_candidates += o.static_candidates;
  static_clear_skips += o.static_clear_skips;
  broad_skipped_checks += o.broad_skipped_checks;
  broad_rebuilds += o.broad_rebuilds;
  filtered += o.filtered;
  aabb_rejected += o.aabb_rejected;
  pretest_rejected += o.pretest_rejected;
  narrow_tests += o.narrow_tests;
  contacts += o.contacts;
  sensor_contacts += o.sensor_contacts;
  pushes += o.pushes;
  jammed += o.jammed;
  ccd_bodies += o.ccd_bodies;
  ccd_clear_skips += o.ccd_clear_skips;
  toi_queries += o.toi_queries;
  toi_hits += o.toi_hits;
  begin_events += o.begin_events;
  persist_events += o.persist_events;
  end_events += o.end_events;
  tunnelled += o.tunnelled;
  escaped += o.escaped;
  max_static_depth = std::max(max_static_depth, o.max_static_depth);
  time_integrate += o.time_integrate;
  time_statics += o.time_statics;
  time_broad += o.time_broad;
  time_bodies += o.time_bodies;
  time_events += o.time_events;
  time_check += o.time_check;
}

// ---- Impl helpers ---------------------------------------------------------------------------

template <int D>
WorldN<D>::Impl::Impl(const WorldOptionsN<D>& o)
    : options(o),
      body_broad(o.broad_phase),
      static_chain(kChainPretests, chain_options(o.adaptive_early_out)),
      body_chain(kChainPretests, chain_options(o.adaptive_early_out)) {}

template <int D>
auto WorldN<D>::Impl::body(BodyId id) -> Body& {
  if (id.index >= bodies.size() || !bodies[id.index].alive ||
      bodies[id.index].generation != id.generation) {
    throw InvalidInput("body " + std::to_string(id.index) + ": removed or unknown");
  }
  return bodies[id.index];
}

template <int D>
auto WorldN<D>::Impl::body(BodyId id) const -> const Body& {
  return const_cast<Impl*>(this)->body(id);
}

template <int D>
TransformN<D> WorldN<D>::Impl::transform(const ColliderRef& c) const {
  return c.is_static ? statics[c.index].transform : bodies[c.index].xf;
}

template <int D>
CollisionFilter WorldN<D>::Impl::filter(const ColliderRef& c) const {
  return c.is_static ? statics[c.index].filter : bodies[c.index].filter;
}

template <int D>
bool WorldN<D>::Impl::is_sensor(const ColliderRef& c) const {
  return c.is_static ? statics[c.index].sensor : bodies[c.index].sensor;
}

template <int D>
std::uint64_t WorldN<D>::Impl::user_id(const ColliderRef& c) const {
  return c.is_static ? statics[c.index].user_id : bodies[c.index].user_id;
}

template <int D>
auto WorldN<D>::Impl::body_box(const Body& b) const -> Box {
  Box box = piece_box(b, 0);
  for (std::size_t k = 1; k < b.shapes.size(); ++k) box = merge(box, piece_box(b, int(k)));
  return box;
}

template <int D>
void WorldN<D>::Impl::refresh_static_index() {
  if (!static_index_dirty) return;
  std::vector<Box> boxes(static_pieces.size());
  for (std::size_t i = 0; i < static_pieces.size(); ++i) boxes[i] = static_pieces[i].box;
  static_tree.build(boxes);
  static_grid.build(boxes);
  static_index_dirty = false;
}

template <int D>
auto WorldN<D>::Impl::contact_with(const ColliderRef& a, const ColliderRef& b) const -> Manifold {
  if (b.is_static) return detail::piece_contact(body_shape(a), bodies[a.index].xf, static_piece(b), transform(b));
  return contact(body_shape(a), bodies[a.index].xf, body_shape(b), bodies[b.index].xf);
}

template <int D>
bool WorldN<D>::Impl::evaluate_pair(detail::WorldCheckChain& chain, const ColliderRef& a,
                                    const ColliderRef& b, const Box& box_a, const Box& box_b,
                                    VecN<D> circle_a, float radius_a, VecN<D> circle_b,
                                    float radius_b, Manifold& out, StepStats& stats) {
  int rejected_by = -1;  // first check (or 3: the pretest) that said no
  const auto run = [&](int check, CheckStage stage) {
    bool pass = false;
    if (check == detail::kCheckFilter) {
      pass = !(a.is_static == b.is_static && a.index == b.index) &&
             should_collide(filter(a), filter(b));
    } else if (check == detail::kCheckAabb) {
      pass = overlap(box_a, box_b);
    } else if (stage == CheckStage::pretest) {
      const float r = (radius_a + radius_b) * (1.0f + detail::kPretestSlack);
      pass = distance_squared(circle_a, circle_b) <= r * r;
      if (!pass && rejected_by < 0) rejected_by = 3;
      return pass;
    } else {
      ++stats.narrow_tests;
      out = contact_with(a, b);
      pass = out.touching();
    }
    if (!pass && rejected_by < 0) rejected_by = check;
    return pass;
  };
  const bool pass = chain.evaluate(run);
  if (!pass) {
    if (rejected_by == detail::kCheckFilter) ++stats.filtered;
    if (rejected_by == detail::kCheckAabb) ++stats.aabb_rejected;
    if (rejected_by == 3) ++stats.pretest_rejected;
  }
  return pass;
}

// ---- Step -----------------------------------------------------------------------------------

template <int D>
void WorldN<D>::Impl::prepare_workers() {
  const int n = options.scheduler != nullptr ? std::max(1, options.scheduler->worker_count()) : 1;
  if (static_cast<int>(workers.size()) == n) return;
  workers.resize(static_cast<std::size_t>(n));
  for (int w = 1; w < n; ++w) {
    auto& wk = workers[static_cast<std::size_t>(w)];
    if (wk.static_chain == nullptr) {
      wk.static_chain = std::make_unique<detail::WorldCheckChain>(kChainPretests, chain_options(options.adaptive_early_out));
      wk.body_chain = std::make_unique<detail::WorldCheckChain>(kChainPretests, chain_options(options.adaptive_early_out));
    }
  }
}

template <int D>
void WorldN<D>::Impl::collect_workers(StepStats& stats, std::vector<Contact> detail::StepWorkerN<D>::*share,
                                      std::vector<Contact>* into) {
  for (detail::StepWorkerN<D>& wk : workers) {
    if (share != nullptr) {
      std::vector<Contact>& list = wk.*share;
      into->insert(into->end(), list.begin(), list.end());
      list.clear();
    }
    stats.accumulate(wk.stats);
    wk.stats = StepStats{};
  }
}

template <int D>
void WorldN<D>::Impl::move_bodies(float dt, StepStats& stats) {
  if (proxies_changed) {
    proxies.clear();
    first_proxy.assign(bodies.size(), 0);
    for (std::uint32_t i = 0; i < bodies.size(); ++i) {
      first_proxy[i] = static_cast<std::uint32_t>(proxies.size());
      if (!bodies[i].alive) continue;
      for (std::size_t k = 0; k < bodies[i].shapes.size(); ++k) {
        proxies.push_back({i, static_cast<std::uint16_t>(k)});
      }
    }
  }
  proxy_start_boxes.resize(proxies.size());  // filled by integrate_body
  proxy_boxes.resize(proxies.size());        // filled by finish_motion
  proxy_speeds.resize(proxies.size());
  const bool have_statics = !static_pieces.empty();
  // When the temporal broad phase's candidate set expires this step, it is rebuilt from the
  // boxes of the last step as item 0 of this pass: on one worker while the others move bodies,
  // rather than alone after them (the same pairs come out; its own state is all it touches).
  // Only where that hides it: with several workers and a set small enough to build on one.
  const double next_time = time + dt;  // the body broad phase's time after this step
  const bool hidden = workers.size() >= 2 && proxies.size() <= kRebuildAheadMaxProxies;
  const int ahead = hidden && !proxies_changed && body_broad.rebuild_due(next_time) ? 1 : 0;
  // In the same regime, each block's new boxes go through the temporal broad phase's update
  // as soon as they are made, on the workers (find_body_contacts' set() then only finishes it):
  // a separate update of up to 2048 objects runs on one thread (at 1e3 bodies on two threads
  // 6.5-9.5 us a frame, now 2.5-3.3 with the rebuild frames' own), and a larger one is another
  // wait for the workers. Not on one thread (the same work either way: 1e3 bodies, set() 5 us
  // less, the pass 4-6 more) nor for large sets (1e5 on one thread: the pass 0.8 ms more, set()
  // 0.4 less; the separate loop streams its arrays). Not when a rebuild runs beside the blocks
  // in this pass: it writes what the update reads.
  const bool update_in_pass =
      hidden && ahead == 0 && body_broad.begin_update(proxies.size(), next_time, !proxies_changed);
  const auto start = Clock::now();
  parallel(static_cast<int>(bodies.size()) + ahead, kBodiesPerTask, [&](int begin, int end, int w) {
    StepStats& worker_stats = workers[static_cast<std::size_t>(w)].stats;
    if (begin < ahead) {
      const auto t0 = Clock::now();
      body_broad.rebuild_now(next_time);
      worker_stats.time_broad += seconds(t0, Clock::now());
    }
    begin = std::max(begin - ahead, 0);
    end -= ahead;
    // A body's static contacts need only its own motion: each block of bodies is moved, then
    // resolved against the statics while its bodies are still in the cache (one pass over the
    // bodies' memory, one wait for the workers). The clock is read per block, not per body.
    for (int first = begin; first < end; first += kBodiesPerBlock) {
      const int block_end = std::min(end, first + kBodiesPerBlock);
      const auto t0 = Clock::now();
      for (int i = first; i < block_end; ++i) {
        // The shapes of a body a few ahead: its new boxes read them, from the world's shape pool
        // apart from the body (at 1e6 bodies a cache miss a body, most of the box computation's
        // time).
        detail::prefetch_shapes_ahead(bodies, i, end);
        integrate_body(static_cast<std::uint32_t>(i), dt, have_statics, w);
      }
      const auto t1 = Clock::now();
      for (int i = first; i < block_end; ++i) {
        if (have_statics) resolve_body(static_cast<std::uint32_t>(i), w);
        finish_motion(static_cast<std::uint32_t>(i), dt);
      }
      if (update_in_pass) {
        const auto proxy_end = static_cast<std::size_t>(block_end) < bodies.size()
                                   ? first_proxy[static_cast<std::size_t>(block_end)]
                                   : static_cast<std::uint32_t>(proxies.size());
        body_broad.update_range(static_cast<int>(first_proxy[static_cast<std::size_t>(first)]),
                                static_cast<int>(proxy_end), proxy_boxes);
      }
      worker_stats.time_integrate += seconds(t0, t1);
      worker_stats.time_statics += seconds(t1, Clock::now());
    }
  });
  const double wall = seconds(start, Clock::now());
  collect_workers(stats, &detail::StepWorkerN<D>::ccd_contacts, &ccd_contacts);
  collect_workers(stats, &detail::StepWorkerN<D>::contacts, &contacts);
  // The pass's time, split between motion, statics and the rebuild as the workers spent it.
  const double busy = stats.time_integrate + stats.time_statics + stats.time_broad;
  if (!(busy > 0.0)) {
    stats.time_integrate = wall;
    return;
  }
  const double scale = wall / busy;
  stats.time_integrate *= scale;
  stats.time_statics *= scale;
  stats.time_broad *= scale;
}

template <int D>
void WorldN<D>::Impl::integrate_body(std::uint32_t i, float dt, bool have_statics, int w) {
  Body& b = bodies[i];
  if (!b.alive) return;
  // The boxes the body starts the step with (its proxies' swept boxes begin there).
  for (std::size_t k = 0; k < b.shapes.size(); ++k) proxy_start_boxes[first_proxy[i] + k] = b.piece(k).box;
  if (options.gravity != VecN<D>(0.0f) && !b.sensor) {
    // (kept within kMaxWorldSpeed, as check_world_velocity keeps a game's velocities: a body
    // falling forever must not overflow the temporal broad phase's speed bound)
    b.velocity = glm::clamp(b.velocity + options.gravity * dt, VecN<D>(-kMaxWorldSpeed), VecN<D>(kMaxWorldSpeed));
  }
  b.path_count = 0;
  b.mark_path(b.xf);
  b.start_xf = b.xf;
  const VecN<D> d = b.velocity * dt + clamp_length(b.push, kMaxPushFraction * b.bounding_radius);
  b.push = VecN<D>(0.0f);
  const AngularN<D> rot = b.angular_velocity * dt;
  const float motion = length(d) + detail::turn_size(rot) * b.bounding_radius;
  const bool fast = b.bullet || motion > kCcdMotionFraction * b.inner_size;
  b.very_fast = motion > b.inner_size;
  if (b.sensor || !have_statics || !fast || motion == 0.0f) {
    b.place(detail::moved(b.xf, b.local_center, d, rot));
    b.mark_path(b.xf);
    return;
  }
  // A fast body whose motion stays within its static clearance can hit no static: the pose its
  // continuous motion reaches at its end, without the query, composed as a slow body's is
  // (`moved`). Not the sweep's pose at t = 1: in 2D that rebuilds the rotation from its angle
  // (an atan2, then a sine and cosine: about a tenth of a 1e4-body step's time, and up to an
  // ulp of drift a step for a body that does not turn, whose rotation `moved` keeps exactly).
  const TransformN<D> end = detail::moved(b.xf, b.local_center, d, rot);
  if (clear_of_statics(b, end, detail::turn_size(rot), detail::kClearanceToiMargin)) {
    b.place(end);
    b.mark_path(b.xf);
    ++workers[static_cast<std::size_t>(w)].stats.ccd_clear_skips;
    return;
  }
  move_with_ccd(i, d, rot, w);
}

template <int D>
void WorldN<D>::Impl::move_with_ccd(std::uint32_t index, VecN<D> d, AngularN<D> rot, int w) {
  Body& b = bodies[index];
  detail::StepWorkerN<D>& wk = workers[static_cast<std::size_t>(w)];
  std::vector<int>& candidates = wk.candidates;
  StepStats& stats = wk.stats;
  ++stats.ccd_bodies;
  for (int bounce = 0; bounce <= kMaxCcdBounces; ++bounce) {
    const auto sweep = detail::sweep_of(b.xf, b.local_center, d, rot);
    Box box = swept_aabb(b.shapes[0], sweep);
    for (std::size_t k = 1; k < b.shapes.size(); ++k) box = merge(box, swept_aabb(b.shapes[k], sweep));
    candidates.clear();
    static_grid.query(box, [&](int id) {
      candidates.push_back(id);
      return true;
    });
    std::sort(candidates.begin(), candidates.end());
    float best_t = 1.0f;
    VecN<D> best_n(0.0f);
    VecN<D> best_point(0.0f);
    int best_id = -1;
    std::size_t best_k = 0;
    bool found = false;
    bool stop = false;  // a query failed: stop at its safe time
    for (const int id : candidates) {
      const StaticPiece& sp = static_pieces[id];
      const StaticDefN<D>& st = statics[sp.owner];
      if (st.sensor || !should_collide(b.filter, st.filter)) continue;
      // The centre's path never within the body's reach of the static's bounding ball.
      if (!detail::path_reaches<D>(sweep.c0, sweep.c1, sp.circle_center, b.bounding_radius + sp.circle_radius)) continue;
      const detail::StaticPieceRefN<D> static_shape = static_piece(sp.owner, sp.piece);  // a shape or a field
      for (std::size_t k = 0; k < b.shapes.size(); ++k) {
        const Box piece_sweep = b.shapes.size() > 1 ? swept_aabb(b.shapes[k], sweep) : box;  // one piece: the body's box
        if (b.shapes.size() > 1 && !overlap(piece_sweep, sp.box)) continue;
        const auto r = detail::piece_impact(b.shapes[k], sweep, piece_sweep, static_shape,
                                            st.transform, stats.toi_queries);
        if (r.status == QueryStatus::hit || r.status == QueryStatus::max_iterations) {
          if (r.fraction < best_t) {
            best_t = r.fraction;
            best_n = r.normal;
            best_point = r.point;
            best_id = id;
            best_k = k;
            found = true;
            stop = r.status == QueryStatus::max_iterations;
          }
        } else if (r.status == QueryStatus::overlapped) {
          // Already touching at the start: only a motion into the static is stopped; sliding
          // along it or leaving it goes on (the push-out pass settles the rest).
          VecN<D> n = r.normal;
          if (n == VecN<D>(0.0f)) {
            n = detail::piece_contact(b.shapes[k], b.xf, static_shape, st.transform).normal;
          }
          if (dot(d, n) > 0.0f && best_t > 0.0f) {
            best_t = 0.0f;
            best_n = n;
            best_point = r.point;
            best_id = id;
            best_k = k;
            found = true;
            stop = false;
          }
        }
      }
    }
    // (No hit: the whole motion, composed as integrate_body's clear path does.)
    b.place(found ? detail::pose_at(sweep, best_t) : detail::moved(b.xf, b.local_center, d, rot));
    b.mark_path(b.xf);
    if (!found) break;
    ++stats.toi_hits;
    if (best_id >= 0 && !stop && best_n != VecN<D>(0.0f)) record_impact(index, best_k, best_id, best_n, best_point, wk.ccd_contacts);
    if (stop || best_n == VecN<D>(0.0f)) break;
    b.velocity = reflect_if_approaching(b.velocity, best_n);
    d = reflect_if_approaching((1.0f - best_t) * d, best_n);
    rot = detail::scaled_turn(rot, 1.0f - best_t);
  }
}

template <int D>
void WorldN<D>::Impl::record_impact(std::uint32_t index, std::size_t piece, int static_piece,
                                    VecN<D> normal, VecN<D> point, std::vector<Contact>& out) {
  const Body& b = bodies[index];
  const StaticPiece& sp = static_pieces[static_piece];
  const StaticDefN<D>& st = statics[sp.owner];
  Contact c{ColliderRef{false, index, static_cast<std::uint16_t>(piece)},
            ColliderRef{true, sp.owner, sp.piece}, {}, false, b.user_id, st.user_id};
  // A pair hit twice in one step keeps its first impact. This body's impacts are the tail of
  // `out` (a worker moves its bodies one after another), so the scan stops at the first other body.
  for (auto it = out.rbegin(); it != out.rend() && it->a.index == index; ++it) {
    if (compare_contacts(*it, c) == 0) return;
  }
  // The exact manifold at the impact pose when the shapes already touch there (it carries
  // feature ids); else the time of impact's own point and normal at depth 0.
  c.manifold = detail::piece_contact(b.shapes[piece], b.xf, this->static_piece(sp.owner, sp.piece), st.transform);
  if (!c.manifold.touching()) {
    c.manifold.normal = normal;
    c.manifold.count = 1;
    c.manifold.points[0] = ManifoldPointN<D>{point, 0.0f, ContactId{}};
  }
  out.push_back(c);
}

template <int D>
void WorldN<D>::Impl::finish_motion(std::uint32_t i, float dt) {
  const Body& b = bodies[i];
  if (!b.alive) return;
  const std::uint32_t first = first_proxy[i];
  for (std::size_t k = 0; k < b.shapes.size(); ++k) {
    proxy_boxes[first + k] = merge(proxy_start_boxes[first + k], b.piece(k).box);
  }
  store_speed_bound(i, dt);
}

template <int D>
void WorldN<D>::Impl::store_speed_bound(std::uint32_t i, float dt) {
  const float bound = speed_bound(bodies[i], dt);
  for (std::size_t k = 0; k < bodies[i].shapes.size(); ++k) proxy_speeds[first_proxy[i] + k] = bound;
}

template <int D>
void WorldN<D>::Impl::resolve_body(std::uint32_t i, int w) {
  Body& b = bodies[i];
  if (!b.alive) return;
  detail::StepWorkerN<D>& wk = workers[static_cast<std::size_t>(w)];
  std::vector<int>& candidates = wk.candidates;
  std::vector<Contact>& body_contacts = wk.body_contacts;
  StepStats& stats = wk.stats;
  detail::WorldCheckChain& chain = static_chain_of(w);
  if (clear_of_statics(b)) {
    ++stats.static_clear_skips;
    return;
  }
  const std::size_t piece_count = b.shapes.size();
  const std::size_t first = first_proxy[i];
  Box start = proxy_start_boxes[first];
  for (std::size_t k = 1; k < piece_count; ++k) start = merge(start, proxy_start_boxes[first + k]);
  bool put_back = false;
  for (int iteration = 0;; ++iteration) {
    body_contacts.clear();
    const Box query_box = merge(start, body_box(b));
    candidates.clear();
    static_grid.query(query_box, [&](int id) {
      candidates.push_back(id);
      return true;
    });
    std::sort(candidates.begin(), candidates.end());
    stats.static_candidates += static_cast<std::int64_t>(candidates.size() * piece_count);
    for (std::size_t k = 0; k < piece_count; ++k) {
      const ColliderRef a{false, i, static_cast<std::uint16_t>(k)};
      const Box box_a = piece_box(b, int(k));
      const VecN<D> circle_a = transform_point(b.xf, b.piece(k).info.center);
      for (const int id : candidates) {
        const StaticPiece& sp = static_pieces[id];
        const ColliderRef other{true, sp.owner, sp.piece};
        Manifold m;
        if (evaluate_pair(chain, a, other, box_a, sp.box, circle_a, b.piece(k).info.radius,
                          sp.circle_center, sp.circle_radius, m, stats)) {
          const StaticDefN<D>& st = statics[sp.owner];
          body_contacts.push_back({a, other, m, b.sensor || st.sensor, b.user_id, st.user_id});
        }
      }
    }
    // The deepest solid contact pushes the body out; then look again (corners).
    const Contact* deepest = nullptr;
    float depth = kRelativeTolerance * b.inner_size;
    for (const Contact& c : body_contacts) {
      if (!c.sensor && c.manifold.max_depth() > depth) {
        depth = c.manifold.max_depth();
        deepest = &c;
      }
    }
    if (body_contacts.empty()) measure_clearance(b);
    if (deepest == nullptr || put_back) break;
    if (iteration == kResolveIterations) {
      // Pushed out of one static into another: a gap narrower than the body (a thin wall across
      // an obstacle's notch). Pushes cannot settle it; the pose it started the step at was clear,
      // so it goes back there and turns around (then its contacts are gathered once more).
      if (depth <= detail::kJamDepthFraction * kTunnelDepthFraction * b.inner_size) break;
      b.place(b.start_xf);
      b.mark_path(b.xf);
      b.velocity = -b.velocity;
      b.angular_velocity = -b.angular_velocity;
      ++stats.jammed;
      put_back = true;
      continue;
    }
    const VecN<D> n = deepest->manifold.normal;  // from the body to the static
    TransformN<D> out = b.xf;
    out.p -= depth * n;
    b.place(out);
    b.mark_path(b.xf);
    b.velocity = reflect_if_approaching(b.velocity, n);
    ++stats.pushes;
  }
  wk.contacts.insert(wk.contacts.end(), body_contacts.begin(), body_contacts.end());
}

template <int D>
bool WorldN<D>::Impl::clear_of_statics(const Body& b, const TransformN<D>& to, float turn, float margin) const {
  for (std::size_t k = 0; k < b.shapes.size(); ++k) {
    const typename Body::Clearance& c = b.piece(k).clearance;
    if (c.version != statics_version) return false;
    const detail::PieceInfoN<D>& piece = b.piece(k).info;
    const VecN<D> c0 = transform_point(b.xf, piece.center);
    const VecN<D> c1 = transform_point(to, piece.center);
    const float slack = detail::kClearanceSlack * piece.radius +
                        detail::kClearanceRounding * (std::max(max_abs(c0), max_abs(c1)) + piece.radius) +
                        margin * piece.radius;
    // The ball around the anchor holds the segment c0 c1; the centre's path leaves the segment
    // by at most the arc its offset from the centre of rotation sweeps.
    const float reach = std::max(distance(c0, c.anchor), distance(c1, c.anchor)) +
                        turn * distance(piece.center, b.local_center);
    if (!(reach < c.gap - slack)) return false;
  }
  return true;
}

template <int D>
void WorldN<D>::Impl::measure_clearance(Body& b) {
  for (std::size_t k = 0; k < b.shapes.size(); ++k) {
    const float radius = b.piece(k).info.radius * (1.0f + detail::kPretestSlack);
    const float reach = detail::kClearanceReach * radius;
    const VecN<D> center = transform_point(b.xf, b.piece(k).info.center);
    // Statics whose boxes come within the reach of the sphere; the rest are farther.
    Box box{center - VecN<D>(radius + reach), center + VecN<D>(radius + reach)};
    float gap = reach;
    static_grid.query(box, [&](int id) {
      const StaticPiece& sp = static_pieces[static_cast<std::size_t>(id)];
      const StaticDefN<D>& st = statics[sp.owner];
      gap = std::min(gap, detail::static_distance(static_piece(sp.owner, sp.piece), st.transform, center, radius + gap) - radius);
      return gap > 0.0f;
    });
    b.piece(k).clearance = {center, gap, gap > 0.0f ? statics_version : 0u};
  }
}

template <int D>
float WorldN<D>::Impl::speed_bound(const Body& b, float dt) const {
  // Next step a swept box moves by at most the motion (velocity, bounces keep its length, plus
  // the deferred push) and the turn; kSpeedBoundSlack leaves room for static push-outs. A body
  // that breaks it costs the temporal broad phase a rebuild, never a missed pair.
  const float push = std::min(length(b.push), kMaxPushFraction * b.bounding_radius);
  // Velocities are within kMaxWorldSpeed (check_world_velocity), but a push over a tiny step
  // (dt near the smallest float) is not: the bound saturates at the largest float, which the
  // temporal broad phase takes as "grows to its cap" (an infinite bound it refuses).
  const float per_second = dt > 0.0f ? push / dt : 0.0f;
  const float bound = detail::kSpeedBoundSlack * (length(b.velocity) + per_second) +
                      detail::turn_size(b.angular_velocity) * b.bounding_radius;
  return std::min(bound, std::numeric_limits<float>::max());
}

template <int D>
void WorldN<D>::Impl::find_body_contacts(float dt, StepStats& stats) {
  const auto t0 = Clock::now();
  body_broad.set(proxy_boxes, proxy_speeds, time + dt, !proxies_changed, options.scheduler);
  proxies_changed = false;
  body_boxes_current = true;
  body_broad.find_pairs(pairs, options.scheduler);
  const std::int64_t skipped = body_broad.skipped_checks();
  stats.broad_skipped_checks = skipped >= last_skipped ? skipped - last_skipped : skipped;
  last_skipped = skipped;
  const std::int64_t rebuilds = body_broad.rebuilds();
  stats.broad_rebuilds = rebuilds >= last_rebuilds ? rebuilds - last_rebuilds : rebuilds;
  last_rebuilds = rebuilds;
  stats.body_pairs = static_cast<std::int64_t>(pairs.size());
  const auto t1 = Clock::now();
  stats.time_broad += seconds(t0, t1);  // (after any rebuild move_bodies ran ahead)

  // The narrow phase, pair by pair on the workers (each writes only its own pair's slot), then
  // the response in pair order on this thread: it changes velocities that later pairs read.
  const auto pair_count = static_cast<int>(pairs.size());
  pair_manifolds.resize(pairs.size());
  pair_passed.resize(pairs.size());
  parallel(pair_count, kPairsPerTask, [&](int begin, int end, int w) {
    detail::StepWorkerN<D>& wk = workers[static_cast<std::size_t>(w)];
    detail::WorldCheckChain& chain = body_chain_of(w);
    for (int i = begin; i < end; ++i) {
      if (i + detail::kPairPrefetchAhead < end) {
        const auto [p_ahead, q_ahead] = pairs[static_cast<std::size_t>(i + detail::kPairPrefetchAhead)];
        detail::prefetch_body(bodies[proxies[p_ahead].body]);
        detail::prefetch_body(bodies[proxies[q_ahead].body]);
      }
      const auto [p, q] = pairs[static_cast<std::size_t>(i)];
      const detail::Proxy pa = proxies[p];
      const detail::Proxy pb = proxies[q];
      const Body& ba = bodies[pa.body];
      const Body& bb = bodies[pb.body];
      pair_passed[static_cast<std::size_t>(i)] = evaluate_pair(
          chain, ColliderRef{false, pa.body, pa.piece}, ColliderRef{false, pb.body, pb.piece},
          piece_box(ba, pa.piece), piece_box(bb, pb.piece),
          transform_point(ba.xf, ba.piece(pa.piece).info.center), ba.piece(pa.piece).info.radius,
          transform_point(bb.xf, bb.piece(pb.piece).info.center), bb.piece(pb.piece).info.radius,
          pair_manifolds[static_cast<std::size_t>(i)], wk.stats);
    }
  });
  collect_workers(stats);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (pair_passed[i] == 0) continue;
    const detail::Proxy pa = proxies[pairs[i].first];
    const detail::Proxy pb = proxies[pairs[i].second];
    const ColliderRef a{false, pa.body, pa.piece};
    const ColliderRef b{false, pb.body, pb.piece};
    Body& ba = bodies[pa.body];
    Body& bb = bodies[pb.body];
    const Manifold& m = pair_manifolds[i];
    const bool sensor = ba.sensor || bb.sensor;
    contacts.push_back({a, b, m, sensor, ba.user_id, bb.user_id});
    if (sensor) continue;
    // Equal masses, elastic: swap the velocity components along the normal when approaching.
    const VecN<D> normal = m.normal;
    const float approach = dot(bb.velocity - ba.velocity, normal);
    if (approach < 0.0f) {
      ba.velocity += approach * normal;
      bb.velocity -= approach * normal;
    }
    const float half = 0.5f * m.max_depth();
    ba.push -= half * normal;
    bb.push += half * normal;
  }
  // The response changed velocities and pushes: tell the broad phase how fast the swept boxes
  // may move from now on, so its sleeping pairs stay safe without a rebuild. Only the bodies of
  // solid pairs changed (a few percent of them); the others keep the bounds finish_motion stored.
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (pair_passed[i] == 0) continue;
    const detail::Proxy pa = proxies[pairs[i].first];
    const detail::Proxy pb = proxies[pairs[i].second];
    if (bodies[pa.body].sensor || bodies[pb.body].sensor) continue;
    store_speed_bound(pa.body, dt);
    store_speed_bound(pb.body, dt);
  }
  body_broad.set_speed_bounds(proxy_speeds, options.scheduler);
  stats.time_bodies = seconds(t1, Clock::now());
}

template <int D>
void WorldN<D>::Impl::make_events(StepStats& stats) {
  // Impacts during the motion count as contacts of this step unless the pair also touches at
  // the end (then the end-of-step manifold wins). Both lists hold each pair at most once, so a
  // sort of each and one merge does it (std::stable_sort of the union would allocate every step).
  // The lists' keys are sorted, not the contacts, and the merge copies each contact once (at
  // 1e4 bodies, ~300 contacts a frame, the sort of the contacts took 13 of the events' 30 us).
  const auto sort_keys = [](const std::vector<Contact>& list, std::vector<detail::ContactSortKey>& keys) {
    keys.resize(list.size());
    for (std::size_t i = 0; i < list.size(); ++i) keys[i] = contact_key(list[i], static_cast<std::uint32_t>(i));
    std::sort(keys.begin(), keys.end());
  };
  sort_keys(contacts, contact_keys);
  sort_keys(ccd_contacts, ccd_keys);
  merged_contacts.clear();
  std::size_t k = 0;
  for (const detail::ContactSortKey& key : contact_keys) {
    for (; k < ccd_keys.size() && ccd_keys[k] < key; ++k) merged_contacts.push_back(ccd_contacts[ccd_keys[k].place]);
    if (k < ccd_keys.size() && !(key < ccd_keys[k])) ++k;  // same pair: the end-of-step contact wins
    merged_contacts.push_back(contacts[key.place]);
  }
  for (; k < ccd_keys.size(); ++k) merged_contacts.push_back(ccd_contacts[ccd_keys[k].place]);
  ccd_contacts.clear();
  std::swap(contacts, merged_contacts);
  events.clear();
  std::size_t i = 0, j = 0;
  const auto emit = [&](ContactEventType type, const Contact& c, std::uint8_t persisted) {
    events.push_back({type, c.a, c.b, c.user_a, c.user_b, c.manifold, c.sensor, persisted});
  };
  while (i < contacts.size() || j < previous_contacts.size()) {
    const int order = i == contacts.size()            ? 1
                      : j == previous_contacts.size() ? -1
                                                      : compare_contacts(contacts[i], previous_contacts[j]);
    if (order < 0) {
      emit(ContactEventType::begin, contacts[i++], 0);
      ++stats.begin_events;
    } else if (order > 0) {
      emit(ContactEventType::end, previous_contacts[j++], 0);
      ++stats.end_events;
    } else {
      const Manifold& now = contacts[i].manifold;
      const Manifold& before = previous_contacts[j].manifold;
      std::uint8_t persisted = 0;
      for (int p = 0; p < now.count; ++p) {
        for (int q = 0; q < before.count; ++q) {
          if (now.points[p].id == before.points[q].id) persisted |= std::uint8_t(1u << p);
        }
      }
      emit(ContactEventType::persist, contacts[i++], persisted);
      ++j;
      ++stats.persist_events;
    }
  }
  for (const Contact& c : contacts) {
    ++stats.contacts;
    if (c.sensor) ++stats.sensor_contacts;
  }
  std::swap(previous_contacts, contacts);  // `contacts()` reads previous_contacts from here on
}

// ---- coordinate range ------------------------------------------------------------------------

template <int D>
void check_world_range(const AabbN<D>& box, std::string_view what) {
  const float far = farthest_coordinate(box);
  if (std::fabs(far) <= kMaxWorldCoordinate) return;
  std::ostringstream os;
  os << what << ": the box [";
  for (int k = 0; k < D; ++k) os << box.min[k] << ", ";
  for (int k = 0; k < D; ++k) os << box.max[k] << (k + 1 < D ? ", " : "");
  os << "] reaches " << far << ", beyond the coordinate range [-" << std::fixed << std::setprecision(0)
     << kMaxWorldCoordinate << ", " << kMaxWorldCoordinate << "] (kMaxWorldCoordinate)";
  throw InvalidInput(os.str());
}
template void check_world_range<2>(const Aabb&, std::string_view);
template void check_world_range<3>(const Aabb3&, std::string_view);

namespace {

template <int D, class S>
void check_shapes_range(std::span<const S> shapes, const TransformN<D>& transform, std::string_view what) {
  for (std::size_t k = 0; k < shapes.size(); ++k) {
    if constexpr (std::is_same_v<S, StaticShape3D>) {
      if (detail::is_null_level(shapes[k])) {
        throw InvalidInput(std::string(what) + " shapes[" + std::to_string(k) + "]: null level shape");
      }
    }
    const AabbN<D> box = detail::piece_box(shapes[k], transform);
    if (std::fabs(farthest_coordinate(box)) <= kMaxWorldCoordinate) continue;
    check_world_range(box, std::string(what) + " shapes[" + std::to_string(k) + "]");
  }
}

}  // namespace

void check_world_range(std::span<const Shape2D> shapes, const Transform& transform, std::string_view what) {
  check_shapes_range<2>(shapes, transform, what);
}
void check_world_range(std::span<const Shape3D> shapes, const Transform3& transform, std::string_view what) {
  check_shapes_range<3>(shapes, transform, what);
}
void check_world_range(std::span<const StaticShape3D> shapes, const Transform3& transform,
                       std::string_view what) {
  check_shapes_range<3>(shapes, transform, what);
}

namespace {

/// The velocity check of both dimensions: `components` of the velocity and of the angular
/// velocity (one in 2D, three in 3D), printed as "(x, y)" / "(x, y, z)".
template <class V, class W>
void check_velocity(V velocity, W angular_velocity, std::string_view what) {
  if (!is_finite(velocity)) throw InvalidInput(std::string(what) + " velocity: not finite");
  float turn_fastest;
  if constexpr (std::is_same_v<W, float>) {
    if (!std::isfinite(angular_velocity)) throw InvalidInput(std::string(what) + " angular velocity: not finite");
    turn_fastest = std::fabs(angular_velocity);
  } else {
    if (!is_finite(angular_velocity)) throw InvalidInput(std::string(what) + " angular velocity: not finite");
    turn_fastest = max_abs(angular_velocity);
  }
  const float fastest = max_abs(velocity);
  if (fastest > kMaxWorldSpeed) {
    std::ostringstream os;
    os << what << " velocity: (";
    for (int k = 0; k < V::length(); ++k) os << velocity[k] << (k + 1 < V::length() ? ", " : "");
    os << ") beyond the speed range [-" << std::fixed << std::setprecision(0) << kMaxWorldSpeed << ", "
       << kMaxWorldSpeed << "] per axis (kMaxWorldSpeed, world units per second)";
    throw InvalidInput(os.str());
  }
  if (turn_fastest > kMaxWorldAngularSpeed) {
    std::ostringstream os;
    os << what << " angular velocity: ";
    if constexpr (std::is_same_v<W, float>) {
      os << angular_velocity;
    } else {
      os << "(" << angular_velocity.x << ", " << angular_velocity.y << ", " << angular_velocity.z << ")";
    }
    os << " beyond [-" << std::fixed << std::setprecision(0) << kMaxWorldAngularSpeed << ", "
       << kMaxWorldAngularSpeed << "] (kMaxWorldAngularSpeed, radians per second)";
    throw InvalidInput(os.str());
  }
}

}  // namespace

void check_world_velocity(Vec2 velocity, float angular_velocity, std::string_view what) {
  check_velocity(velocity, angular_velocity, what);
}
void check_world_velocity(Vec3 velocity, Vec3 angular_velocity, std::string_view what) {
  check_velocity(velocity, angular_velocity, what);
}

// ---- WorldN --------------------------------------------------------------------------------

template <int D>
WorldN<D>::WorldN(const WorldOptionsN<D>& options) {
  if (options.bounds && !is_valid(*options.bounds)) {
    throw InvalidInput("world options bounds: not finite or min > max");
  }
  if (options.bounds) check_world_range(*options.bounds, "world options bounds");
  if (!is_finite(options.gravity) || max_abs(options.gravity) > kMaxWorldSpeed) {
    throw InvalidInput("world options gravity: not finite or beyond kMaxWorldSpeed per second");
  }
  impl_ = std::make_unique<Impl>(options);
}

template <int D>
WorldN<D>::~WorldN() = default;
template <int D>
WorldN<D>::WorldN(WorldN&&) noexcept = default;
template <int D>
WorldN<D>& WorldN<D>::operator=(WorldN&&) noexcept = default;

template <int D>
StaticId WorldN<D>::add_static(const StaticDefN<D>& def) {
  const std::string name = "static " + std::to_string(impl_->statics.size());
  if (!def.fields.empty()) {
    if (def.shapes.size() + def.fields.size() > 0xffff) throw InvalidInput(name + " shapes: more than 65535 pieces");
  } else {
    check_shapes(def.shapes, name + " shapes");
  }
  check_transform(def.transform, name + " transform");
  check_world_range(std::span<const StaticShape>(def.shapes), def.transform, name);
  const Xf xf = detail::unit_pose(def.transform);
  // Each field's solid box (field frame), once: the broad phase's box and the pretest's sphere.
  std::vector<AabbN<D>> field_boxes(def.fields.size());
  for (std::size_t k = 0; k < def.fields.size(); ++k) {
    const std::string field = name + " fields[" + std::to_string(k) + "]";
    if (detail::is_null_field<D>(def.fields[k])) throw InvalidInput(field + ": null field");
    if (!detail::field_solid_box<D>(def.fields[k], field_boxes[k])) {
      throw InvalidInput(field + ": no solid (no node at or below 0)");
    }
    check_world_range<D>(detail::placed_box<D>(field_boxes[k], xf), field);
  }
  const auto owner = static_cast<std::uint32_t>(impl_->statics.size());
  impl_->statics.push_back(def);
  impl_->statics.back().transform = xf;
  for (std::size_t k = 0; k < def.shapes.size(); ++k) {
    const detail::PieceInfoN<D> info = detail::piece_info(def.shapes[k]);
    impl_->static_pieces.push_back({owner, static_cast<std::uint16_t>(k),
                                    detail::piece_box(def.shapes[k], xf),
                                    transform_point(xf, info.center), info.radius,
                                    info.inner_size, detail::is_level(def.shapes[k])});
  }
  for (std::size_t k = 0; k < def.fields.size(); ++k) {
    const AabbN<D>& box = field_boxes[k];
    // The broad phase's box and the pretest's sphere around the solid's box; no inner size (as
    // a level's).
    impl_->static_pieces.push_back({owner, static_cast<std::uint16_t>(def.shapes.size() + k),
                                    detail::placed_box<D>(box, xf), transform_point(xf, 0.5f * (box.min + box.max)),
                                    0.5f * length(box.max - box.min), 0.0f, false});
  }
  impl_->static_index_dirty = true;
  impl_->check_grid_dirty = true;
  ++impl_->statics_version;
  return StaticId{owner};
}

template <int D>
BodyId WorldN<D>::add_body(const BodyDefN<D>& def) {
  const std::string name = "body " + std::to_string(impl_->bodies.size());
  check_shapes(def.shapes, name + " shapes");
  check_transform(def.transform, name + " transform");
  check_world_range(std::span<const BodyShape>(def.shapes), def.transform, name);
  check_world_velocity(def.velocity, def.angular_velocity, name);
  std::uint32_t index;
  if (!impl_->free_slots.empty()) {
    index = impl_->free_slots.back();
    impl_->free_slots.pop_back();
  } else {
    index = static_cast<std::uint32_t>(impl_->bodies.size());
    impl_->bodies.emplace_back();
  }
  detail::BodyN<D>& b = impl_->bodies[index];
  const std::uint32_t generation = b.generation;
  b = detail::BodyN<D>{};
  b.generation = generation;
  b.shapes = impl_->shape_pool.allocate(def.shapes);
  b.more_pieces.resize(b.shapes.size() - 1);  // check_shapes: at least one
  b.place(detail::unit_pose(def.transform));
  b.velocity = def.velocity;
  b.angular_velocity = def.angular_velocity;
  b.user_id = def.user_id;
  b.filter = def.filter;
  b.sensor = def.sensor;
  b.bullet = def.bullet;
  b.alive = true;
  // Centre of rotation: the area (volume) centroid of the pieces (their plain average if none
  // has any: segments).
  float measure = 0.0f;
  Vec weighted(0.0f), plain(0.0f);
  for (std::size_t k = 0; k < b.shapes.size(); ++k) {
    const detail::PieceInfoN<D>& info = b.piece(k).info = detail::piece_info(b.shapes[k]);
    const float a = detail::shape_measure(b.shapes[k]);
    measure += a;
    weighted += a * info.center;
    plain += info.center;
  }
  b.local_center = measure > 0.0f ? weighted / measure : plain / static_cast<float>(b.shapes.size());
  b.inner_size = std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k < b.shapes.size(); ++k) {
    const detail::PieceInfoN<D>& p = b.piece(k).info;
    b.inner_size = std::min(b.inner_size, p.inner_size);
    b.bounding_radius = std::max(b.bounding_radius, distance(p.center, b.local_center) + p.radius);
  }
  b.mark_path(b.xf);
  ++impl_->alive_bodies;
  impl_->proxies_changed = true;
  impl_->body_boxes_current = false;
  return BodyId{index, generation};
}

template <int D>
void WorldN<D>::reserve(int bodies) {
  if (bodies < 0) throw InvalidInput("World reserve bodies: negative (" + std::to_string(bodies) + ")");
  impl_->bodies.reserve(static_cast<std::size_t>(bodies));
}

template <int D>
void WorldN<D>::remove_body(BodyId id) {
  detail::BodyN<D>& b = impl_->body(id);
  b.alive = false;
  impl_->shape_pool.release(b.shapes);
  b.shapes = {};
  b.more_pieces.clear();
  ++b.generation;
  impl_->free_slots.push_back(id.index);
  --impl_->alive_bodies;
  impl_->proxies_changed = true;
  impl_->body_boxes_current = false;
}

template <int D>
bool WorldN<D>::contains(BodyId id) const noexcept {
  return id.index < impl_->bodies.size() && impl_->bodies[id.index].alive &&
         impl_->bodies[id.index].generation == id.generation;
}

template <int D>
auto WorldN<D>::transform(BodyId id) const -> const Xf& { return impl_->body(id).xf; }
template <int D>
auto WorldN<D>::velocity(BodyId id) const -> Vec { return impl_->body(id).velocity; }
template <int D>
auto WorldN<D>::angular_velocity(BodyId id) const -> Angular { return impl_->body(id).angular_velocity; }
template <int D>
auto WorldN<D>::shapes(BodyId id) const -> std::span<const BodyShape> { return impl_->body(id).shapes; }
template <int D>
std::uint64_t WorldN<D>::user_id(BodyId id) const { return impl_->body(id).user_id; }

namespace {
template <int D>
void check_collider(const typename WorldN<D>::Impl& w, const ColliderRef& c) {
  if (c.is_static) {
    if (c.index >= w.statics.size() ||
        c.piece >= w.statics[c.index].shapes.size() + w.statics[c.index].fields.size()) {
      throw InvalidInput("collider: unknown static or piece");
    }
  } else if (c.index >= w.bodies.size() || !w.bodies[c.index].alive ||
             c.piece >= w.bodies[c.index].shapes.size()) {
    throw InvalidInput("collider: unknown or removed body, or unknown piece");
  }
}
}  // namespace

template <int D>
std::uint64_t WorldN<D>::user_id(const ColliderRef& collider) const {
  check_collider<D>(*impl_, collider);
  return impl_->user_id(collider);
}

template <int D>
auto WorldN<D>::body_shape(const ColliderRef& collider) const -> const BodyShape& {
  check_collider<D>(*impl_, collider);
  if (collider.is_static) throw InvalidInput("collider: a static's piece, not a body's");
  return impl_->body_shape(collider);
}

template <int D>
auto WorldN<D>::static_shape(const ColliderRef& collider) const -> const StaticShape& {
  check_collider<D>(*impl_, collider);
  if (!collider.is_static) throw InvalidInput("collider: a body's piece, not a static's");
  const detail::StaticPieceRefN<D> piece = impl_->static_piece(collider);
  if (piece.shape == nullptr) throw InvalidInput("collider: a static's field, not a shape (static_field)");
  return *piece.shape;
}

template <int D>
const StaticFieldN<D>& WorldN<D>::static_field(const ColliderRef& collider) const {
  check_collider<D>(*impl_, collider);
  if (!collider.is_static) throw InvalidInput("collider: a body's piece, not a static's field");
  const detail::StaticPieceRefN<D> piece = impl_->static_piece(collider);
  if (piece.field == nullptr) throw InvalidInput("collider: a static's shape, not a field (static_shape)");
  return *piece.field;
}

template <int D>
const Shape2D& WorldN<D>::collider_shape(const ColliderRef& collider) const
  requires(D == 2)
{
  check_collider<D>(*impl_, collider);
  // (Clang 14 instantiates this for WorldN<3> in `template class WorldN<3>` despite the
  // constraint, where the two shapes have different types: only D == 2 has a body here.)
  if constexpr (D == 2) {
    return collider.is_static ? static_shape(collider) : impl_->body_shape(collider);
  } else {
    throw InvalidInput("collider_shape: a 2D query");
  }
}

template <int D>
auto WorldN<D>::collider_transform(const ColliderRef& collider) const -> Xf {
  check_collider<D>(*impl_, collider);
  return impl_->transform(collider);
}

template <int D>
bool WorldN<D>::is_sensor(const ColliderRef& collider) const {
  check_collider<D>(*impl_, collider);
  return impl_->is_sensor(collider);
}

template <int D>
void WorldN<D>::set_transform(BodyId id, const Xf& xf) {
  detail::BodyN<D>& b = impl_->body(id);
  check_transform(xf, "body " + std::to_string(id.index) + " transform");
  b.place(detail::unit_pose(xf));
  impl_->body_boxes_current = false;
}

template <int D>
void WorldN<D>::set_velocity(BodyId id, Vec velocity, Angular angular_velocity) {
  detail::BodyN<D>& b = impl_->body(id);
  check_world_velocity(velocity, angular_velocity, "body " + std::to_string(id.index));
  b.velocity = velocity;
  b.angular_velocity = angular_velocity;
}

template <int D>
std::vector<BodyId> WorldN<D>::body_ids() const {
  std::vector<BodyId> ids;
  for (std::uint32_t i = 0; i < impl_->bodies.size(); ++i) {
    if (impl_->bodies[i].alive) ids.push_back({i, impl_->bodies[i].generation});
  }
  return ids;
}

template <int D>
int WorldN<D>::body_count() const noexcept { return impl_->alive_bodies; }
template <int D>
int WorldN<D>::static_count() const noexcept { return static_cast<int>(impl_->statics.size()); }

template <int D>
const StaticDefN<D>& WorldN<D>::static_def(StaticId id) const {
  if (id.index >= impl_->statics.size()) {
    throw InvalidInput("static " + std::to_string(id.index) + ": unknown");
  }
  return impl_->statics[id.index];
}

template <int D>
void WorldN<D>::step(float dt) {
  if (!std::isfinite(dt) || dt < 0.0f) throw InvalidInput("dt: negative or not finite");
  Impl& w = *impl_;
  w.refresh_static_index();
  StepStats s;
  s.steps = 1;
  s.bodies = w.alive_bodies;
  s.static_pieces = static_cast<std::int64_t>(w.static_pieces.size());
  w.contacts.clear();
  w.prepare_workers();
  w.move_bodies(dt, s);
  w.find_body_contacts(dt, s);
  const auto t3 = Clock::now();
  w.make_events(s);
  const auto t4 = Clock::now();
  if (w.options.check_each_step) w.check(s);
  s.time_events = seconds(t3, t4);
  s.time_check = seconds(t4, Clock::now());
  w.time += dt;
  w.last = s;
  w.total.accumulate(s);
}

template <int D>
std::span<const ContactN<D>> WorldN<D>::contacts() const noexcept { return impl_->previous_contacts; }
template <int D>
std::span<const ContactEventN<D>> WorldN<D>::events() const noexcept { return impl_->events; }
template <int D>
const StepStats& WorldN<D>::last_step_stats() const noexcept { return impl_->last; }
template <int D>
const StepStats& WorldN<D>::total_stats() const noexcept { return impl_->total; }

template <int D>
std::array<CheckChainReport, 2> WorldN<D>::early_out_reports() const {
  return {impl_->static_chain.report(), impl_->body_chain.report()};
}

template <int D>
std::array<std::array<int, 3>, 2> WorldN<D>::early_out_orders() const {
  std::array<std::array<int, 3>, 2> orders{};
  const std::array<const detail::WorldCheckChain*, 2> chains = {&impl_->static_chain, &impl_->body_chain};
  for (int c = 0; c < 2; ++c) {
    const auto order = chains[c]->order();
    for (int k = 0; k < 3; ++k) orders[c][k] = order[k];
  }
  return orders;
}

template <int D>
std::array<std::array<CheckStats, 3>, 2> WorldN<D>::early_out_check_stats() const {
  std::array<std::array<CheckStats, 3>, 2> stats{};
  const std::array<const detail::WorldCheckChain*, 2> chains = {&impl_->static_chain, &impl_->body_chain};
  for (int c = 0; c < 2; ++c) {
    for (int k = 0; k < 3; ++k) stats[c][k] = chains[c]->check_stats(k);
  }
  return stats;
}

template <int D>
std::array<bool, 2> WorldN<D>::early_out_pretests() const {
  return {impl_->static_chain.pretest_enabled(detail::kCheckExact),
          impl_->body_chain.pretest_enabled(detail::kCheckExact)};
}

template <int D>
std::uint64_t WorldN<D>::state_hash() const noexcept {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a offset basis
  const auto mix = [&](const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      h ^= bytes[i];
      h *= 1099511628211ull;  // FNV prime
    }
  };
  for (std::uint32_t i = 0; i < impl_->bodies.size(); ++i) {
    const detail::BodyN<D>& b = impl_->bodies[i];
    if (!b.alive) continue;
    mix(&i, sizeof i);
    if constexpr (D == 2) {
      const float values[] = {b.xf.p.x, b.xf.p.y, b.xf.q.c, b.xf.q.s,
                              b.velocity.x, b.velocity.y, b.angular_velocity};
      mix(values, sizeof values);
    } else {
      const float values[] = {b.xf.p.x, b.xf.p.y, b.xf.p.z, b.xf.q.w, b.xf.q.x, b.xf.q.y, b.xf.q.z,
                              b.velocity.x, b.velocity.y, b.velocity.z, b.angular_velocity.x,
                              b.angular_velocity.y, b.angular_velocity.z};
      mix(values, sizeof values);
    }
  }
  return h;
}

template <int D>
AabbN<D> WorldN<D>::bounds() const noexcept {
  bool any = false;
  AabbN<D> box{};
  const auto add = [&](const AabbN<D>& b) {
    box = any ? merge(box, b) : b;
    any = true;
  };
  for (const detail::StaticPieceN<D>& sp : impl_->static_pieces) add(sp.box);
  for (const detail::BodyN<D>& b : impl_->bodies) {
    if (b.alive) add(impl_->body_box(b));
  }
  return box;
}

template class WorldN<2>;
template class WorldN<3>;

}  // namespace collide
