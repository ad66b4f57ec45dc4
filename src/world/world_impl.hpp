#pragma once
// The world's state, shared by the files that implement it for both dimensions: world.cpp
// (bodies, statics, the step), world_queries.cpp (ray casts, lasers, picks, shape casts),
// world_draw.cpp (2D pictures) and world_check.cpp (the independent end-of-step check).
// Dimension-specific geometry is in world_dim.hpp; fields as static pieces in world_field.hpp.

#include "body_broad_phase.hpp"
#include "shape_pool.hpp"
#include "world_dim.hpp"
#include "world_field.hpp"

#include <collide/broad/dynamic_tree.hpp>
#include <collide/broad/hash_grid.hpp>
#include <collide/broad/sorted_grid.hpp>
#include <collide/core/large_pages.hpp>
#include <collide/early_out/check_chain.hpp>
#include <collide/world/world.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

namespace collide::detail {

/// One piece of a static, in world space.
template <int D>
struct StaticPieceN {
  std::uint32_t owner = 0;      ///< index into statics
  std::uint16_t piece = 0;      ///< index into the owner's shapes
  AabbN<D> box;                 ///< world box
  VecN<D> circle_center{0.0f};  ///< world bounding circle or sphere
  float circle_radius = 0.0f;
  float inner_size = 0.0f;
  bool level = false;           ///< a level shape (3D): met triangle by triangle
};

/// Most points of a body's path over a step: its start, up to kMaxCcdBounces + 1 legs of
/// motion, kResolveIterations push-outs.
inline constexpr int kMaxPathPoints = 2 + kMaxCcdBounces + kResolveIterations;

template <int D>
struct BodyN {
  /// Appends the centre of rotation at `xf` to the path (the last point is overwritten when
  /// the path is full: it is always the body's end).
  void mark_path(const TransformN<D>& at) noexcept {
    if constexpr (D == 3) {  // only the 3D check reads it (a centre crossing a level's surface)
      path[path_count < kMaxPathPoints ? path_count++ : kMaxPathPoints - 1] = transform_point(at, local_center);
    }
  }

  /// Moves the body to `at` and computes its pieces' boxes there: every change of `xf` goes
  /// through here, so the boxes always match it.
  void place(const TransformN<D>& at) {
    xf = at;
    for (std::size_t k = 0; k < shapes.size(); ++k) piece(k).box = compute_aabb(shapes[k], xf);
  }

  /// Each piece's static clearance: the lesson's temporal coherence applied to the statics. When
  /// a piece met no static, the step measures how far its bounding circle or sphere is from
  /// every static piece (`gap`, a lower bound) with the sphere's centre then (`anchor`). Until
  /// the centre has moved `gap` (less a slack) from the anchor, wherever its path went, the
  /// piece can touch no static, and the step skips its static contacts: most bodies of a level
  /// are in free space, and their contact query against the level found nothing 999 times in
  /// 1000. Valid while `version` is the world's statics_version (statics are only added).
  struct Clearance {
    VecN<D> anchor{0.0f};
    float gap = 0.0f;
    std::uint32_t version = 0;  ///< 0: never measured
  };
  /// What the step keeps for each piece (shape k of the body).
  struct PieceState {
    PieceInfoN<D> info;  ///< bounding circle or sphere and inner size, local space
    /// The piece's tight box at `xf`, world space. A step asks for a piece's box several times
    /// per pose (start and end of its motion, the statics' query, the early out, the broad
    /// phase): computed once per pose instead (a hull's box costs a pass over its vertices;
    /// the boxes took 30% of a step of 1000 bodies over dungeon.obj).
    AabbN<D> box;
    Clearance clearance;
  };
  /// Piece k's state, k < shapes.size().
  PieceState& piece(std::size_t k) noexcept { return k == 0 ? first_piece : more_pieces[k - 1]; }
  const PieceState& piece(std::size_t k) const noexcept { return k == 0 ? first_piece : more_pieces[k - 1]; }

  TransformN<D> xf;  ///< set by place()
  /// The first piece's state in the body itself, the others' on the heap: most bodies are one
  /// shape, and the passes of a step read a piece's box, clearance and circle for every body,
  /// which in heap blocks of their own cost a cache miss each per body at 1e6 bodies.
  PieceState first_piece;
  std::vector<PieceState> more_pieces;  ///< pieces 1, 2, ... (shapes.size() - 1 of them)
  std::span<BodyShapeN<D>> shapes;  ///< local space, in the world's shape_pool
  TransformN<D> start_xf;  ///< the pose at the start of the step (a jammed body goes back to it)
  VecN<D> velocity{0.0f};
  AngularN<D> angular_velocity{0.0f};
  VecN<D> push{0.0f};             ///< push-out from body contacts, applied with the next motion
  /// The centre of rotation's path over the last step, leg by leg (start, the end of each
  /// continuous-collision leg or of the motion, each push-out): the check tests whether it
  /// crossed a level's surface.
  std::array<VecN<D>, D == 3 ? kMaxPathPoints : 0> path{};  ///< 2D keeps none (only 3D reads it)
  int path_count = 0;
  std::uint64_t user_id = 0;
  CollisionFilter filter{};
  bool sensor = false;
  bool bullet = false;
  bool alive = false;
  bool very_fast = false;         ///< last step's motion exceeded its own size (would tunnel)
  std::uint32_t generation = 0;
  VecN<D> local_center{0.0f};     ///< centre of rotation: area (volume) centroid of the pieces
  float inner_size = 0.0f;        ///< smallest piece's inner size
  float bounding_radius = 0.0f;   ///< reach of the pieces from local_center
};

/// A contact's place in make_events' order: its colliders' keys (ColliderRef::key, A then B)
/// and its place in its list. Sorting these instead of the contacts (about 100 bytes each)
/// moves each contact once.
struct ContactSortKey {
  std::uint64_t a = 0;
  std::uint64_t b = 0;
  std::uint32_t place = 0;

  friend bool operator<(const ContactSortKey& x, const ContactSortKey& y) noexcept {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  }
};

/// A body piece in the body broad phase.
struct Proxy {
  std::uint32_t body = 0;
  std::uint16_t piece = 0;
};

/// The early-out chain used for both kinds of pairs: check 0 the layer/mask filter, check 1
/// the tight boxes, check 2 the exact contact with the bounding circles (spheres) as its
/// pretest.
using WorldCheckChain = CheckChain<3>;
inline constexpr int kCheckFilter = 0;
inline constexpr int kCheckAabb = 1;
inline constexpr int kCheckExact = 2;

/// What one worker of a step writes (TaskScheduler): its scratch and its share of the outputs,
/// merged after each phase. Outputs are contacts with unique (a, b) keys, sorted by the events
/// pass, and integer counters: the merge order cannot change a result.
template <int D>
struct StepWorkerN {
  std::vector<int> candidates;
  std::vector<ContactN<D>> body_contacts;  ///< one body's static contacts while it is pushed out
  std::vector<ContactN<D>> contacts;       ///< body-static contacts at the end of the motion
  std::vector<ContactN<D>> ccd_contacts;   ///< impacts during the motion
  StepStats stats{};
  /// Early-out chains of workers after the first (worker 0 uses the world's own, whose reports
  /// the world gives; with several workers they describe worker 0's share of the pairs).
  std::unique_ptr<WorldCheckChain> static_chain;
  std::unique_ptr<WorldCheckChain> body_chain;
};

/// A static item of the check's grid covering more cells than this is tested against every body
/// instead (HashGridN's oversized list).
inline constexpr int kMaxCheckCellsPerItem = 4096;

/// The independent check's own grid over the static pieces and the level shapes' triangles: a
/// hashed uniform grid (broad/hash_grid.hpp), deliberately not the world's tree or the levels'
/// BVHs, so a bug there cannot hide a tunnelled body. Grid id n is `items[n]`: a static piece
/// index below static_pieces.size(), else static_pieces.size() + a triangle index.
template <int D>
struct CheckGridN {
  HashGridN<D> grid{typename HashGridN<D>::Options{.max_cells_per_box = kMaxCheckCellsPerItem}};
  LargePageVector<std::uint32_t> items;
  /// Triangles of the level shapes (world corners) and the static piece each belongs to: a big
  /// 3D level's millions, on large pages (their first build took most of the page faults of a
  /// 2e5-body `collide run --3d`).
  LargePageVector<std::array<Vec3, 3>> triangles;
  LargePageVector<std::uint32_t> triangle_piece;
};

/// Bodies ahead of the one being moved whose shapes are prefetched (a body's motion or check
/// takes about 100 ns, a miss to memory about as long).
constexpr int kShapePrefetchAhead = 4;

/// Asks the cache for the first shape of `b` (both ends of it: the variant's kind is stored
/// after its largest alternative) and for the state of its second piece, if any (the pieces
/// after the first live in a heap block of their own).
template <class Body>
void prefetch_shapes(const Body& b) noexcept {
  if (b.shapes.empty()) return;
  const auto* first = reinterpret_cast<const char*>(b.shapes.data());
  __builtin_prefetch(first);
  __builtin_prefetch(first + sizeof(b.shapes[0]) - 1);
  if (!b.more_pieces.empty()) __builtin_prefetch(b.more_pieces.data());
}

/// prefetch_shapes for the body kShapePrefetchAhead after `i`, if it is before `end`: the
/// passes over bodies in index order (motion, check) call it before working on body `i`.
template <class Bodies>
void prefetch_shapes_ahead(const Bodies& bodies, int i, int end) noexcept {
  if (i + kShapePrefetchAhead < end) prefetch_shapes(bodies[static_cast<std::size_t>(i + kShapePrefetchAhead)]);
}

/// Body pairs ahead of the one being tested whose bodies are prefetched: pairs are in proxy
/// order, so the second body of each is a random one (a miss to memory at 1e5 bodies: perf
/// gave the load of its pose 65% of the pair loop's own time).
constexpr int kPairPrefetchAhead = 4;

/// Bytes of a cache line on the x86-64 and ARM64 CPUs games run on (the step between prefetches).
constexpr std::size_t kCacheLineBytes = 64;

/// Asks the cache for every line of `b`: a pair's test reads its pose and first piece's state
/// (circle, box) at the front, its filter and its shapes' pointer further on.
template <class Body>
void prefetch_body(const Body& b) noexcept {
  const auto* at = reinterpret_cast<const char*>(&b);
  for (std::size_t offset = 0; offset < sizeof(Body); offset += kCacheLineBytes) __builtin_prefetch(at + offset);
}

}  // namespace collide::detail

namespace collide {

template <int D>
struct WorldN<D>::Impl {
  using Body = detail::BodyN<D>;
  using StaticPiece = detail::StaticPieceN<D>;
  using Box = AabbN<D>;
  using Contact = ContactN<D>;
  using Manifold = ManifoldN<D>;

  explicit Impl(const WorldOptionsN<D>& o);

  WorldOptionsN<D> options;

  // Statics
  std::vector<StaticDefN<D>> statics;
  std::vector<StaticPiece> static_pieces;
  /// The static pieces' boxes for ray casts (a dynamic tree: a ray finds its first hits
  /// without walking the cells between them), with no fat margin: statics do not move, and a
  /// margin only loosened the ray's pruning...
  DynamicTreeN<D> static_tree{typename DynamicTreeN<D>::Options{0.0f, 0.0f}};
  /// ... and for box queries: the step's (swept bodies, push-outs, clearance), which a uniform
  /// grid answers from the one to four cells a body covers instead of a descent through the
  /// tree (at 1e6 bodies over 26k static pieces the tree's descent was a fifth of the step).
  SortedGridN<D> static_grid;
  bool static_index_dirty = false;  ///< static_tree and static_grid
  /// Bumped by every add_static: a body's static clearance measured before is void.
  std::uint32_t statics_version = 1;
  detail::CheckGridN<D> check_grid;
  bool check_grid_dirty = true;

  // Bodies. The arrays a step reads per body or per pair are on large pages once big
  // (core/large_pages.hpp): at 1e6 bodies they are read at random over hundreds of MiB.
  LargePageVector<Body> bodies;
  detail::ShapePool<BodyShapeN<D>> shape_pool;  ///< every body's shapes (Body::shapes)
  std::vector<std::uint32_t> free_slots;
  int alive_bodies = 0;

  // Body broad phase
  detail::BodyBroadPhaseN<D> body_broad;
  LargePageVector<detail::Proxy> proxies;
  LargePageVector<std::uint32_t> first_proxy;  ///< per body slot: index of its first proxy
  LargePageVector<Box> proxy_boxes;        ///< swept boxes over the last step
  LargePageVector<Box> proxy_start_boxes;  ///< tight boxes at the start of the step
  LargePageVector<float> proxy_speeds;
  bool proxies_changed = true;          ///< bodies added or removed since the broad phase was set
  bool body_boxes_current = false;      ///< the broad phase holds every body's current box
  double time = 0.0;
  std::int64_t last_skipped = 0;
  std::int64_t last_rebuilds = 0;

  // Early out
  detail::WorldCheckChain static_chain;
  detail::WorldCheckChain body_chain;

  // Results
  std::vector<Contact> contacts;
  /// Body-static pairs a fast body hit during this step's continuous motion (manifold at the
  /// time of impact); merged into `contacts` unless the pair touches at the end, too.
  std::vector<Contact> ccd_contacts;
  std::vector<Contact> merged_contacts;  ///< make_events' buffer, reused every step
  /// make_events' sort keys of `contacts` and `ccd_contacts` (their colliders' keys and places),
  /// reused every step.
  std::vector<detail::ContactSortKey> contact_keys, ccd_keys;
  std::vector<Contact> previous_contacts;
  std::vector<ContactEventN<D>> events;
  StepStats last{};
  StepStats total{};

  // Scratch, reused every step
  PairList pairs;
  LargePageVector<Manifold> pair_manifolds;  ///< per body pair: its manifold when it passed
  LargePageVector<std::uint8_t> pair_passed;
  std::vector<detail::StepWorkerN<D>> workers;  ///< one per scheduler worker

  /// collide::parallel_for on the world's scheduler (prepare_workers has sized `workers`).
  template <class F>
  void parallel(int count, int min_range, F&& f) {
    collide::parallel_for(options.scheduler, count, min_range, std::forward<F>(f));
  }
  /// Worker w's scratch and chains (the world's own chains for worker 0).
  detail::WorldCheckChain& static_chain_of(int w) { return w == 0 ? static_chain : *workers[w].static_chain; }
  detail::WorldCheckChain& body_chain_of(int w) { return w == 0 ? body_chain : *workers[w].body_chain; }
  /// Sizes `workers` to the scheduler's worker count (chains made once).
  void prepare_workers();
  /// Moves every worker's counters into `stats`, and its `share` of contacts (when given) onto
  /// the end of `into` (their order does not matter: contacts have unique keys, sorted later).
  void collect_workers(StepStats& stats, std::vector<Contact> detail::StepWorkerN<D>::*share = nullptr,
                       std::vector<Contact>* into = nullptr);

  // Helpers
  [[nodiscard]] Body& body(BodyId id);
  [[nodiscard]] const Body& body(BodyId id) const;
  /// Static piece `piece` of static `owner`: a shape (pieces below shapes.size()) or a field.
  [[nodiscard]] detail::StaticPieceRefN<D> static_piece(std::uint32_t owner, std::uint16_t piece) const {
    const StaticDefN<D>& st = statics[owner];
    if (piece < st.shapes.size()) return {&st.shapes[piece], nullptr};
    return {nullptr, &st.fields[piece - st.shapes.size()]};
  }
  [[nodiscard]] detail::StaticPieceRefN<D> static_piece(const ColliderRef& c) const {
    return static_piece(c.index, c.piece);
  }
  [[nodiscard]] const BodyShapeN<D>& body_shape(const ColliderRef& c) const {
    return bodies[c.index].shapes[c.piece];
  }
  [[nodiscard]] TransformN<D> transform(const ColliderRef& c) const;
  [[nodiscard]] CollisionFilter filter(const ColliderRef& c) const;
  [[nodiscard]] bool is_sensor(const ColliderRef& c) const;
  [[nodiscard]] std::uint64_t user_id(const ColliderRef& c) const;
  [[nodiscard]] Box body_box(const Body& b) const;
  /// Piece `piece` of `b`'s tight box at its pose (world space).
  [[nodiscard]] Box piece_box(const Body& b, int piece) const noexcept {
    return b.piece(static_cast<std::size_t>(piece)).box;
  }
  /// Rebuilds static_tree and static_grid when a static was added since the last build.
  void refresh_static_index();
  /// The contact of a body piece `a` with the collider `b` (a static piece or a body piece).
  [[nodiscard]] Manifold contact_with(const ColliderRef& a, const ColliderRef& b) const;

  // Step phases
  /// Every body's motion (integrate_body), then its contacts with statics and push-outs
  /// (resolve_body) and its proxies' swept boxes and speed bounds for the body broad phase
  /// (finish_motion), block by block in one pass over the bodies on the workers; with them, as
  /// one more item, the temporal broad phase's rebuild when it falls due this step. Sets the
  /// step's time_integrate, time_statics and time_broad (the pass's wall time, split as the
  /// workers spent it).
  void move_bodies(float dt, StepStats& stats);
  /// One body's motion (worker w): gravity, then free or continuous motion against statics.
  void integrate_body(std::uint32_t index, float dt, bool have_statics, int w);
  void move_with_ccd(std::uint32_t index, VecN<D> translation, AngularN<D> rotation, int w);
  /// One body's contacts with statics and its push-outs (worker w).
  void resolve_body(std::uint32_t index, int w);
  /// True when every piece of `b` stays within its static clearance (BodyN::clearance) over a
  /// motion from its pose to `to` turning by `turn` radians, with `margin` bounding radii to
  /// spare (the ball about the anchor holds the straight path of each piece's centre; the turn
  /// adds the arc of its offset from the centre of rotation).
  bool clear_of_statics(const Body& b, const TransformN<D>& to, float turn, float margin) const;
  /// True when every piece of `b` is within its static clearance where it is.
  bool clear_of_statics(const Body& b) const { return clear_of_statics(b, b.xf, 0.0f, 0.0f); }
  /// Measures the static clearance of every piece of `b` at its pose.
  void measure_clearance(Body& b);
  /// Body i's proxies' boxes over the step (from its start to its end pose) and speed bound.
  void finish_motion(std::uint32_t index, float dt);
  /// Body i's speed bound (speed_bound) stored for each of its proxies.
  void store_speed_bound(std::uint32_t index, float dt);
  void find_body_contacts(float dt, StepStats& stats);
  /// Bound on how fast body b's swept boxes move from now on, world units per second.
  [[nodiscard]] float speed_bound(const Body& b, float dt) const;
  /// Records a fast body's impact on a static piece as a contact of this step.
  void record_impact(std::uint32_t index, std::size_t piece, int static_piece, VecN<D> normal,
                     VecN<D> point, std::vector<Contact>& out);
  void make_events(StepStats& stats);
  void check(StepStats& stats);
  /// The check of body i (worker w): escaped, tunnelled, deepest overlap into the worker's stats.
  void check_body(std::uint32_t i, int w);
  /// Runs `chain` on one pair; on pass, `out` holds the manifold. Counts rejections in `stats`.
  bool evaluate_pair(detail::WorldCheckChain& chain, const ColliderRef& a, const ColliderRef& b,
                     const Box& box_a, const Box& box_b, VecN<D> circle_a, float radius_a,
                     VecN<D> circle_b, float radius_b, Manifold& out, StepStats& stats);
};

}  // namespace collide
