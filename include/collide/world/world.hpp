#pragma once
/// @file
/// `WorldN<D>`: what a game does with collision every frame, in one place, in 2D (`World2D`,
/// world2d.hpp) and 3D (`World3D`, world3d.hpp). Static colliders and moving bodies; `step(dt)`
/// runs the lesson's pipeline,
///
///   broad phase -> early out -> narrow phase -> continuous collision -> contact events,
///
/// and the world answers the queries a game asks between frames: ray casts with reflections
/// (lasers and mirrors), AABB and point queries (mouse picks), shape casts (is the player
/// standing on something?).
///
/// One step of `dt` seconds:
///  1. Integrate. Each body moves by velocity * dt (plus the push-out left by last step's
///     body-body contacts) and turns by angular velocity * dt. A body that would move more than
///     kCcdMotionFraction of its own size (or is flagged `bullet`) moves by continuous collision
///     against the statics: time of impact (`time_of_impact`: GJK ray cast into the Minkowski
///     difference, conservative advancement with rotation; against a level's triangles, one
///     candidate triangle at a time), stop there, reflect, go on with the rest of the step (up
///     to kMaxCcdBounces times). Slower bodies move the whole step at once, and so do fast
///     ones whose whole motion stays within their static clearance (the distance to the statics
///     measured when the body last met none: no query could hit; StepStats::ccd_clear_skips).
///  2. Statics. Each body's swept box is looked up in the statics' tree (DynamicTree); each
///     candidate goes through the early-out chain (filter, AABB, bounding-sphere pretest) and
///     the exact `contact` (a level shape: its merged manifold, active edges applied); the body
///     is pushed out by the deepest contact and its velocity reflected (a kinematic bounce), up
///     to kResolveIterations times.
///  3. Bodies. The bodies' swept boxes go to the body broad phase (the temporal broad phase by
///     default: pairs that cannot meet yet are skipped), each pair through its own early-out
///     chain and `contact`. Touching bodies exchange their velocity components along the normal
///     (equal masses, elastic) and are pushed apart by half the depth each, applied with the
///     next step's motion so that it, too, cannot tunnel.
///  4. Events. This step's touching pairs are compared with last step's: begin, persist, end;
///     contact points are matched across steps by feature id (`ContactId`).
///  5. Check. An independent brute-force pass counts bodies that end the step inside static
///     geometry, or whose centre crossed a level's surface during it (tunnelling), and bodies
///     outside the world's bounds; all must stay 0.
///
/// A static may also hold signed distance fields (`StaticDefN::fields`, dense or sparse, 2D and
/// 3D: terrain baked once, shared by pointer): the solid is where the field is at or below 0,
/// met through the field's own queries, one look-up per sample point (sdf/distance_field.hpp):
/// contacts sample the body's surface (`contact`), continuous collision and shape casts advance
/// conservatively on the sampled distance, rays sphere-trace (`raymarch`). Its answers agree with
/// the exact shapes it was built from to within the field's error, about a voxel.
///
/// Units: world units (metres or pixels, the caller's choice), seconds, radians (2D:
/// counter-clockwise in a y-up world; 3D: an angular velocity is a rotation vector, its
/// direction the axis, right-handed). Determinism: the same calls in the same order give the
/// same state bit for bit on the same build (`state_hash`), whatever broad phase is chosen and
/// whatever the early-out chains learn (they reorder checks, which never changes a result).
///
/// Not thread-safe: one thread steps and queries a world. Allocation happens when bodies or
/// statics are added; steady-state steps reuse their buffers.

#include <collide/broad/broad_phase.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/core/aabb.hpp>
#include <collide/core/debug_draw.hpp>
#include <collide/core/finite_range.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/task_scheduler.hpp>
#include <collide/core/transform3.hpp>
#include <collide/early_out/check_chain.hpp>
#include <collide/narrow/manifold.hpp>
#include <collide/sdf/distance_field.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace collide {

/// A body that would move more than this fraction of its size in one step (its size: the radius
/// of the largest circle or sphere that fits its narrowest piece) moves by continuous collision.
inline constexpr float kCcdMotionFraction = 0.25f;
/// Most bounces a fast body makes within one step; the rest of its motion is dropped after that.
inline constexpr int kMaxCcdBounces = 4;
/// Most push-out passes of a body against the statics per step (corners need two).
inline constexpr int kResolveIterations = 4;
/// A body-body push is capped per step at this fraction of the body's bounding radius, so a
/// deep overlap comes apart over a few steps instead of throwing bodies across the world.
inline constexpr float kMaxPushFraction = 0.5f;
/// A body counts as tunnelled (inside static geometry) when it overlaps a static deeper than
/// this fraction of its size at the end of a step (the independent check).
inline constexpr float kTunnelDepthFraction = 0.05f;

/// Largest coordinate magnitude a world accepts: kFiniteQueryRange (2^30 = 1073741824 world
/// units), the range where the queries promise finite results (collide/core/finite_range.hpp
/// says why). Every static, body and the bounds must lie within [-kMaxWorldCoordinate,
/// kMaxWorldCoordinate] on every axis. Beyond, results hold only while overflows keep their
/// sign: examples/scenes scaled up ran clean to coordinates of 6e11, then bodies escaped
/// through walls (1e12) and boxes became infinite (1e14). A level in metres or pixels is far
/// inside. Enforced by the world's constructor (bounds), add_static and add_body
/// (check_world_range), and by the scene loader at load.
inline constexpr float kMaxWorldCoordinate = kFiniteQueryRange;

/// Largest speed a world accepts for a body, in world units per second (each velocity
/// component within [-kMaxWorldSpeed, kMaxWorldSpeed]): a body crosses the whole coordinate
/// range in two seconds at it, far beyond any game's speed, and a body's speed bound for the
/// temporal broad phase, |v| + |angular velocity| * radius, stays finite (below 2^62). Faster
/// velocities (a finite 1e25 from a scene file, found by fuzz_scene_json) made that bound
/// overflow and the step throw. Enforced by add_body, set_velocity and the scene loader.
inline constexpr float kMaxWorldSpeed = kMaxWorldCoordinate;
/// Largest angular speed a world accepts, in radians per second (same reason as
/// kMaxWorldSpeed; in 3D each component of the rotation vector).
inline constexpr float kMaxWorldAngularSpeed = kMaxWorldCoordinate;

/// A 3D static's piece: a convex shape, or a level shape (a triangle mesh, a height field)
/// held by a shared pointer, so a level's triangles and BVH are built once and never copied
/// into the world (which keeps the pointer: the level stays alive while the world does).
using StaticShape3D = std::variant<Sphere, Capsule3, Segment3, Box, ConvexHull,
                                   std::shared_ptr<const TriangleMesh>,
                                   std::shared_ptr<const HeightField>>;

/// A signed distance field as a piece of a static collider (StaticDefN::fields), dense or sparse,
/// held by a shared pointer: a field is baked once and never copied into the world (which keeps
/// the pointer: the field stays alive while the world does). Its grid is in the static's local
/// space, placed by the static's transform (any rigid transform: rotated fields are fine). The
/// solid is where the interpolated field is at or below 0. A sparse field holds +band beyond its
/// band, and its `contact` samples a circle, sphere or capsule along its core minus the radius,
/// skipping a sample beyond the band (its distance unknown): build it with a band
/// (FieldOptions::band * voxel) wider than the bodies' radii, or such a body's contacts are missed.
template <int D>
using StaticFieldN = std::variant<std::shared_ptr<const DistanceFieldN<D>>, std::shared_ptr<const SparseDistanceFieldN<D>>>;

/// The types a world of D dimensions works with: what its bodies and statics are made of and
/// what an angular velocity is (2D: radians per second, counter-clockwise; 3D: a rotation
/// vector in radians per second, world space).
template <int D>
struct WorldTypes;
template <>
struct WorldTypes<2> {
  using BodyShape = Shape2D;
  using StaticShape = Shape2D;
  using Angular = float;
};
template <>
struct WorldTypes<3> {
  using BodyShape = Shape3D;
  using StaticShape = StaticShape3D;
  using Angular = Vec3;
};
template <int D>
using BodyShapeN = typename WorldTypes<D>::BodyShape;
template <int D>
using StaticShapeN = typename WorldTypes<D>::StaticShape;
template <int D>
using AngularN = typename WorldTypes<D>::Angular;

/// Bounding box of a 3D static piece placed by `xf`, world space (a level shape's: its
/// triangles' box).
[[nodiscard]] Aabb3 compute_aabb(const StaticShape3D& shape, const Transform3& xf) noexcept;

/// Throws InvalidInput "WHAT: ... beyond the coordinate range [-1073741824, 1073741824]
/// (kMaxWorldCoordinate)", with the box and the coordinate that is out, unless `box` is finite
/// and within the range.
template <int D>
void check_world_range(const AabbN<D>& box, std::string_view what);
/// check_world_range for the world box of each of `shapes` placed by `transform`, naming the
/// shape: "WHAT shapes[K]: ..."; a null level shape is refused too ("WHAT shapes[K]: null level
/// shape").
void check_world_range(std::span<const Shape2D> shapes, const Transform& transform, std::string_view what);
void check_world_range(std::span<const Shape3D> shapes, const Transform3& transform, std::string_view what);
void check_world_range(std::span<const StaticShape3D> shapes, const Transform3& transform,
                       std::string_view what);

/// Throws InvalidInput "WHAT velocity: ..." / "WHAT angular velocity: ..." unless `velocity`
/// is finite with each component within kMaxWorldSpeed and `angular_velocity` (radians per
/// second; in 3D each component) finite within kMaxWorldAngularSpeed.
void check_world_velocity(Vec2 velocity, float angular_velocity, std::string_view what);
void check_world_velocity(Vec3 velocity, Vec3 angular_velocity, std::string_view what);

/// Which pairs interact: A and B do iff (A.layer & B.mask) != 0 and (B.layer & A.mask) != 0.
struct CollisionFilter {
  std::uint32_t layer = 1u;            ///< the layers this collider is on (usually one bit)
  std::uint32_t mask = 0xffffffffu;    ///< the layers it interacts with
};

/// True when the two filters let their colliders interact.
[[nodiscard]] constexpr bool should_collide(CollisionFilter a, CollisionFilter b) noexcept {
  return (a.layer & b.mask) != 0u && (b.layer & a.mask) != 0u;
}

/// Handle of a static collider: an index that stays valid for the world's lifetime.
struct StaticId {
  std::uint32_t index = 0;
  friend constexpr bool operator==(StaticId, StaticId) noexcept = default;
};

/// Handle of a body: index plus generation, so a handle of a removed body is recognised as stale
/// even after its slot is reused.
struct BodyId {
  std::uint32_t index = 0;
  std::uint32_t generation = 0;
  friend constexpr bool operator==(BodyId, BodyId) noexcept = default;
};

/// One piece of a static or a body (a convex shape, or a static's level shape): what contacts
/// and queries name. A contact with a level shape names its triangle in the manifold's feature
/// ids (ContactId::index_b).
struct ColliderRef {
  bool is_static = true;    ///< a piece of a static (else of a body)
  std::uint32_t index = 0;  ///< StaticId::index or BodyId::index
  std::uint16_t piece = 0;  ///< which of the owner's shapes
  /// Packed into one integer (statics sort before bodies), for ordering and keys.
  [[nodiscard]] constexpr std::uint64_t key() const noexcept {
    return (std::uint64_t{is_static ? 0u : 1u} << 48) | (std::uint64_t{index} << 16) | piece;
  }
  friend constexpr bool operator==(ColliderRef, ColliderRef) noexcept = default;
};

/// A static collider: one or more pieces placed by one transform. Statics never move. 2D: convex
/// shapes (a concave outline goes in as the pieces of `convex_pieces`); 3D: convex shapes (a
/// decomposed concave mesh: make_compound_static, world/compound.hpp), triangle meshes (a level
/// from OBJ) and height fields (StaticShape3D). Both: signed distance fields (`fields`). Pieces
/// are numbered shapes first, then fields: field k is piece shapes.size() + k
/// (ColliderRef::piece).
template <int D>
struct StaticDefN {
  std::vector<StaticShapeN<D>> shapes;  ///< local space; at least one piece in shapes and fields
  TransformN<D> transform;              ///< local -> world
  std::uint64_t user_id = 0;            ///< the game's own id, echoed in contacts and queries
  CollisionFilter filter{};
  bool sensor = false;                  ///< reports overlaps (events), never pushes
  /// Signed distance fields, local space (their grids placed by `transform`), shared: see
  /// StaticFieldN. A contact with a field names the body's surface sample in
  /// ContactId::index_a and face 0 of the field.
  std::vector<StaticFieldN<D>> fields;
};

/// A moving body: one or more convex shapes moving together, with a velocity. Kinematic: it
/// keeps its velocity until it bounces (reflection about the contact normal) or the game sets it.
/// The body turns about its local origin. A concave 3D prop goes in as the hulls of its convex
/// decomposition: make_compound_body (world/compound.hpp) centres them on their volume centroid.
template <int D>
struct BodyDefN {
  std::vector<BodyShapeN<D>> shapes;    ///< local space, at least one
  TransformN<D> transform;              ///< local -> world at the start
  VecN<D> velocity{0.0f};               ///< world units per second
  AngularN<D> angular_velocity{0.0f};   ///< radians per second (see WorldTypes)
  std::uint64_t user_id = 0;
  CollisionFilter filter{};
  bool sensor = false;                  ///< passes through everything, reports overlaps
  bool bullet = false;                  ///< always use continuous collision, whatever its speed
};

/// Which broad phase finds body-body pairs (statics always live in a DynamicTree). Every choice
/// finds the same pairs; only the speed differs.
enum class WorldBroadPhase : std::uint8_t {
  temporal,           ///< speed bounds: pairs that cannot meet yet are skipped (the default)
  hierarchical_grid,  ///< grid levels for mixed sizes
  sorted_grid,        ///< counting-sorted uniform grid
  loose_grid,         ///< one cell per box (its min corner), the fastest full rebuild
  hash_grid,          ///< the lesson's hashed grid
  dynamic_tree,       ///< incremental AABB tree
  sweep_and_prune,    ///< insertion-sorted intervals
  brute_force,        ///< every pair: the reference
};

/// Lower-case name of a WorldBroadPhase ("temporal", "hash_grid", ...).
[[nodiscard]] const char* to_string(WorldBroadPhase broad_phase) noexcept;
/// The WorldBroadPhase named `name`; throws InvalidInput listing the valid names otherwise.
[[nodiscard]] WorldBroadPhase world_broad_phase_from_string(std::string_view name);

/// Options of a world.
template <int D>
struct WorldOptionsN {
  WorldBroadPhase broad_phase = WorldBroadPhase::temporal;
  /// Where bodies belong. When set, the end-of-step check counts bodies whose centre left it
  /// (`StepStats::escaped`); the world does not enforce it (give it walls as statics).
  std::optional<AabbN<D>> bounds;
  /// Learn check costs and pass rates and reorder the early-out chains (the lesson's t / (1 - p)
  /// rule). Off: the declaration order with every pretest on, for comparison.
  bool adaptive_early_out = true;
  /// Run the independent end-of-step check (tunnelling, escapes). It costs a brute-force pass
  /// per step; games turn it off, tests and `collide run` keep it on.
  bool check_each_step = true;
  /// Acceleration of every non-sensor body, world units per second squared (e.g. (0, -9.81, 0)
  /// in a y-up world); zero (the default) leaves velocities to the bounces and the game.
  VecN<D> gravity{0.0f};
  /// The game's job system (not owned; it must outlive the world's steps): the step's per-body and
  /// per-pair work is spread over its workers, with results bit for bit identical to a serial
  /// step for any worker count. Null: every phase runs on the stepping thread.
  TaskScheduler* scheduler = nullptr;
};

/// A contact between two colliders in a step: touching at the end of the step, or hit by a fast
/// body during its continuous motion (then the manifold is the one at the time of impact, and
/// the body has usually bounced away by the end of the step: a bullet's hit is still reported).
/// `a` is always a body piece; `b` a static piece or a piece of another body (a.index < b.index).
template <int D>
struct ContactN {
  ColliderRef a;          ///< a body piece
  ColliderRef b;          ///< a static piece, or a piece of another body (then a.index < b.index)
  ManifoldN<D> manifold;  ///< normal from A to B, world space; points with feature ids
  bool sensor = false;    ///< one side is a sensor: reported, no response
  std::uint64_t user_a = 0;  ///< user id of A's owner
  std::uint64_t user_b = 0;  ///< user id of B's owner
};

/// What happened to a touching pair this step.
enum class ContactEventType : std::uint8_t {
  begin,    ///< touching now, not last step
  persist,  ///< touching now and last step
  end,      ///< touching last step, not now
};

/// Lower-case name ("begin", "persist", "end").
[[nodiscard]] const char* to_string(ContactEventType type) noexcept;

/// A contact event. For `end`, `manifold` is last step's.
template <int D>
struct ContactEventN {
  ContactEventType type = ContactEventType::begin;
  ColliderRef a;             ///< as ContactN::a
  ColliderRef b;             ///< as ContactN::b
  std::uint64_t user_a = 0;  ///< user id of A's owner
  std::uint64_t user_b = 0;  ///< user id of B's owner
  ManifoldN<D> manifold;     ///< normal from A to B, world space; points with feature ids
  bool sensor = false;       ///< one side is a sensor
  /// Bit i set: point i has the same feature id as a point of last step's manifold (the same
  /// contact point, so a game can carry its data over). Always 0 for begin and end.
  std::uint8_t persisted_points = 0;
};

/// Counters and timings of a step (or, from `total_stats`, summed over all steps).
struct StepStats {
  std::int64_t steps = 0;              ///< 1 for a step; the number of steps in totals
  std::int64_t bodies = 0;             ///< alive bodies (summed per step in totals)
  std::int64_t static_pieces = 0;      ///< static pieces (summed per step in totals)
  // Broad phase
  std::int64_t body_pairs = 0;         ///< body-body pairs from the broad phase (swept boxes)
  std::int64_t static_candidates = 0;  ///< body-static pairs from the statics' tree
  /// Bodies whose static contacts were skipped: each piece still within the clearance from
  /// every static measured at an earlier step (temporal coherence; no static can touch them)
  std::int64_t static_clear_skips = 0;
  /// Pair checks the temporal broad phase skipped. With several workers and up to 32768
  /// proxies its candidate set is built a frame ahead, beside the motion, with boxes grown for
  /// one more frame: more candidates, more of them skipped. Pairs and results do not change.
  std::int64_t broad_skipped_checks = 0;
  std::int64_t broad_rebuilds = 0;  ///< candidate sets the temporal broad phase rebuilt (its horizon ended, or broken speed bounds)
  // Early out (both chains)
  std::int64_t filtered = 0;           ///< rejected by layer/mask or same body
  std::int64_t aabb_rejected = 0;      ///< rejected by the tight boxes
  std::int64_t pretest_rejected = 0;   ///< rejected by the bounding-circle (sphere) pretest
  std::int64_t narrow_tests = 0;       ///< exact contact computations
  // Narrow phase and response
  std::int64_t contacts = 0;           ///< touching pairs at the end of the step
  std::int64_t sensor_contacts = 0;    ///< of which involve a sensor
  std::int64_t pushes = 0;             ///< push-outs applied against statics
  /// Bodies still inside a static after the last push-out (wedged in a gap narrower than
  /// themselves), put back at their pose at the start of the step and turned around
  std::int64_t jammed = 0;
  // Continuous collision
  std::int64_t ccd_bodies = 0;         ///< bodies moved by continuous collision
  /// Fast bodies whose whole motion stayed within their static clearance (static_clear_skips):
  /// moved without a continuous collision query, as none could hit.
  std::int64_t ccd_clear_skips = 0;
  std::int64_t toi_queries = 0;        ///< time-of-impact queries run
  std::int64_t toi_hits = 0;           ///< of which stopped a body before the end of its motion
  // Events
  std::int64_t begin_events = 0;       ///< pairs that started touching
  std::int64_t persist_events = 0;     ///< pairs still touching
  std::int64_t end_events = 0;         ///< pairs that stopped touching (or lost a removed body)
  // Independent check
  std::int64_t tunnelled = 0;          ///< bodies ending a step inside static geometry
  std::int64_t escaped = 0;            ///< bodies ending a step outside WorldOptions::bounds
  float max_static_depth = 0.0f;       ///< deepest body-static overlap seen by the check
  // Time per phase, seconds (steady clock)
  double time_integrate = 0.0;         ///< motion and continuous collision
  double time_statics = 0.0;           ///< statics' tree, early out, narrow, push-out
  double time_broad = 0.0;             ///< body broad phase
  double time_bodies = 0.0;            ///< body pairs' early out, narrow, response
  double time_events = 0.0;            ///< event matching
  double time_check = 0.0;             ///< the independent check

  /// Adds `other`'s counters and times (max for max_static_depth).
  void accumulate(const StepStats& other) noexcept;
};

/// Which colliders a query sees.
struct QueryFilter {
  std::uint32_t mask = 0xffffffffu;  ///< layers to see: colliders whose filter.layer & mask
  bool statics = true;
  bool bodies = true;
  bool sensors = false;              ///< sensors are skipped unless this is set
  std::optional<BodyId> ignore;      ///< a body to skip (the caster itself)
};

/// A world ray cast hit.
template <int D>
struct WorldRayHitN {
  ColliderRef collider;       ///< the piece hit
  std::uint64_t user_id = 0;  ///< user id of its owner
  RayHitN<D> hit;  ///< fraction along the ray, point, outward normal (world space)
};

/// Most segments of a laser path.
inline constexpr int kMaxLaserBounces = 16;

/// A laser and its reflections: points[0] is the origin, points[i + 1] the end of segment i;
/// hits[i] is what segment i hit (segments - 1 hits, plus one more when the last segment ended
/// on a surface rather than running out of length).
template <int D>
struct LaserPathN {
  std::array<VecN<D>, kMaxLaserBounces + 2> points{};
  int segments = 0;
  std::array<WorldRayHitN<D>, kMaxLaserBounces + 1> hits{};
  int hit_count = 0;
};

/// A world shape cast hit. On a miss: hit false and every other field as initialised here.
template <int D>
struct WorldCastHitN {
  bool hit = false;
  ColliderRef collider;      ///< the piece touched first
  std::uint64_t user_id = 0; ///< user id of its owner
  float fraction = 1.0f;     ///< of the translation at first touch, [0, 1]
  VecN<D> point{0.0f};       ///< contact point at first touch, world space
  VecN<D> normal{0.0f};      ///< unit, from the cast shape towards what it hit, world space
};

/// Called with each collider a query finds; return false to stop. Non-owning (no allocation).
using ColliderCallback = FunctionRef<bool(const ColliderRef&)>;

/// Called with each collider a shape touches and the contact (normal from the shape to the
/// collider, world space); return false to stop. Non-owning (no allocation).
template <int D>
using ContactCallbackN = FunctionRef<bool(const ColliderRef&, const ManifoldN<D>&)>;

/// What `draw` includes.
struct WorldDrawOptions {
  bool statics = true;
  bool bodies = true;
  bool contacts = true;           ///< contact points and normals
  float normal_length = 0.0f;     ///< arrow length; 0: a fraction of the median body size
};

/// The collision world of D dimensions. See the file comment for what a step does.
template <int D>
class WorldN {
 public:
  using Vec = VecN<D>;
  using Xf = TransformN<D>;
  using Angular = AngularN<D>;
  using BodyShape = BodyShapeN<D>;
  using StaticShape = StaticShapeN<D>;

  /// Throws InvalidInput for non-finite or empty bounds, or bounds beyond kMaxWorldCoordinate.
  explicit WorldN(const WorldOptionsN<D>& options = {});
  ~WorldN();
  WorldN(WorldN&&) noexcept;
  WorldN& operator=(WorldN&&) noexcept;
  WorldN(const WorldN&) = delete;
  WorldN& operator=(const WorldN&) = delete;

  /// Adds a static collider. Throws InvalidInput, naming the field, for no shapes and no fields,
  /// more than 65535 pieces, a non-finite or non-unit transform, a null level shape or field, a
  /// field with no node at or below 0 (no solid), or a piece reaching beyond kMaxWorldCoordinate
  /// ("static 7 shapes[0]: ... beyond the coordinate range ..."). Shapes must come from the
  /// make_* functions and fields from make_distance_field / make_sparse_distance_field (they
  /// are trusted as valid).
  StaticId add_static(const StaticDefN<D>& def);
  /// Adds a body. Throws InvalidInput as add_static, and for a non-finite velocity.
  BodyId add_body(const BodyDefN<D>& def);
  /// Grows the world's storage for `bodies` bodies in all, so that adding up to that many never
  /// moves the bodies already added (a million bodies added one by one otherwise copy the body
  /// array about 20 times). Above a few MiB the array is asked onto large pages (Linux
  /// transparent huge pages, where enabled: the step reads bodies at random, and each such read
  /// on 4 KiB pages also missed the TLB). Throws InvalidInput for a negative count.
  void reserve(int bodies);
  /// Removes a body; its contacts end (reported as end events by the next step). Throws
  /// InvalidInput for a stale or unknown id.
  void remove_body(BodyId id);
  /// True when `id` names a body that is still in the world.
  [[nodiscard]] bool contains(BodyId id) const noexcept;

  /// A body's current state. Throw InvalidInput for a stale id.
  [[nodiscard]] const Xf& transform(BodyId id) const;
  [[nodiscard]] Vec velocity(BodyId id) const;
  [[nodiscard]] Angular angular_velocity(BodyId id) const;
  [[nodiscard]] std::span<const BodyShape> shapes(BodyId id) const;
  [[nodiscard]] std::uint64_t user_id(BodyId id) const;
  /// Setters; throw InvalidInput for a stale id, non-finite values or a velocity beyond
  /// kMaxWorldSpeed / kMaxWorldAngularSpeed. A teleport is fine: the broad phase notices the
  /// broken speed bound and rebuilds.
  void set_transform(BodyId id, const Xf& xf);
  void set_velocity(BodyId id, Vec velocity, Angular angular_velocity = Angular(0.0f));
  /// Every alive body's id, in index order.
  [[nodiscard]] std::vector<BodyId> body_ids() const;
  [[nodiscard]] int body_count() const noexcept;
  [[nodiscard]] int static_count() const noexcept;
  /// Static `id`'s definition. Throws InvalidInput for an unknown id.
  [[nodiscard]] const StaticDefN<D>& static_def(StaticId id) const;
  /// User id of the static or body that owns `collider`.
  [[nodiscard]] std::uint64_t user_id(const ColliderRef& collider) const;
  /// The shape (local space) of a body piece or a static piece a query or a contact named, and
  /// the collider's transform (local -> world). Throw InvalidInput for a collider that is not
  /// in the world, or not a body's (body_shape) or a static's (static_shape) piece.
  [[nodiscard]] const BodyShape& body_shape(const ColliderRef& collider) const;
  [[nodiscard]] const StaticShape& static_shape(const ColliderRef& collider) const;
  /// The field of a static's field piece (StaticDefN::fields). Throws InvalidInput for a
  /// collider that is not in the world or not a static's field piece (static_shape and
  /// collider_shape throw for a field piece).
  [[nodiscard]] const StaticFieldN<D>& static_field(const ColliderRef& collider) const;
  [[nodiscard]] Xf collider_transform(const ColliderRef& collider) const;
  /// 2D: the shape of any collider (statics and bodies are both Shape2D).
  [[nodiscard]] const Shape2D& collider_shape(const ColliderRef& collider) const
    requires(D == 2);
  /// True for a sensor's collider. Throws InvalidInput as collider_transform.
  [[nodiscard]] bool is_sensor(const ColliderRef& collider) const;

  /// Advances the world by `dt` seconds (see the file comment). Throws InvalidInput if dt is
  /// not finite or negative.
  void step(float dt);

  /// Contacts of the last step (touching at its end, or hit during it), sorted by (a, b).
  [[nodiscard]] std::span<const ContactN<D>> contacts() const noexcept;
  /// Events of the last step, sorted by (a, b).
  [[nodiscard]] std::span<const ContactEventN<D>> events() const noexcept;
  /// Counters and timings of the last step, and summed over all steps.
  [[nodiscard]] const StepStats& last_step_stats() const noexcept;
  [[nodiscard]] const StepStats& total_stats() const noexcept;
  /// What the early-out chains learned: [0] body-static pairs, [1] body-body pairs.
  /// Check order: 0 filter, 1 AABB, 2 exact contact (pretest: bounding circles or spheres).
  [[nodiscard]] std::array<CheckChainReport, 2> early_out_reports() const;
  /// The current order of each chain (indices as above) and whether the pretest is on.
  [[nodiscard]] std::array<std::array<int, 3>, 2> early_out_orders() const;
  [[nodiscard]] std::array<bool, 2> early_out_pretests() const;
  /// What each chain's order decision sees per check (indices as above): mean cost in
  /// nanoseconds with the current pretest choice, and the unconditional pass rate.
  [[nodiscard]] std::array<std::array<CheckStats, 3>, 2> early_out_check_stats() const;

  /// The first collider `ray` (world space, point = origin + fraction * translation) enters;
  /// nullopt when it enters none. Statics through their tree, bodies through the body broad
  /// phase (both boxes, then the exact `raycast`); equal fractions go to the smaller collider
  /// key. A ray starting inside a collider does not hit it (see `raycast`). Throws InvalidInput
  /// for a non-finite ray.
  [[nodiscard]] std::optional<WorldRayHitN<D>> raycast(const RayN<D>& ray,
                                                       const QueryFilter& filter = {}) const;
  /// Casts each ray of `rays` as `raycast` does (the same filter) into the same slot of `hits`,
  /// spread over the world's scheduler (WorldOptionsN::scheduler): a frame's lasers, line of
  /// sight checks, a batch of picks. The same hits for any worker count. Throws InvalidInput,
  /// before casting any, for sizes that differ or a non-finite ray (naming its index).
  void raycast_batch(std::span<const RayN<D>> rays, std::span<std::optional<WorldRayHitN<D>>> hits,
                     const QueryFilter& filter = {}) const;
  /// The lesson's laser and mirrors: casts `ray`, reflects at each hit about the surface normal
  /// (keeping the remaining length), up to `max_bounces` reflections (<= kMaxLaserBounces).
  /// Throws InvalidInput for a non-finite ray or max_bounces out of range.
  [[nodiscard]] LaserPathN<D> cast_laser(const RayN<D>& ray, int max_bounces,
                                         const QueryFilter& filter = {}) const;
  /// Each collider whose shape overlaps the box (exact, not just the bounding boxes; touching
  /// counts), world space. Throws InvalidInput for a non-finite box or min > max.
  void query_aabb(const AabbN<D>& box, const QueryFilter& filter,
                  const ColliderCallback& callback) const;
  /// Each collider whose shape contains `point` (a mouse pick; boundary counts; a level shape's
  /// surface within rounding), world space. Throws InvalidInput for a non-finite point.
  void query_point(Vec point, const QueryFilter& filter, const ColliderCallback& callback) const;
  /// Each collider that `shape` placed by `xf` touches or overlaps, with their contact (the
  /// exact `contact`; a level shape's merged manifold): the overlap of a shape, and what a
  /// character mover pushes itself out of. Throws InvalidInput for a non-finite transform.
  void collide_shape(const BodyShape& shape, const Xf& xf, const QueryFilter& filter,
                     const ContactCallbackN<D>& callback) const;
  /// Earliest collider that `shape` placed by `xf` touches while translating by `translation`
  /// (GJK shape cast against each candidate). Colliders it overlaps at the start are reported
  /// at fraction 0. Throws InvalidInput for non-finite input.
  [[nodiscard]] WorldCastHitN<D> shape_cast(const BodyShape& shape, const Xf& xf, Vec translation,
                                            const QueryFilter& filter = {}) const;
  /// Is body `id` standing on something? Casts each of its shapes by `down` (e.g. (0, -0.05) in
  /// a y-up world) against everything its mask sees but itself; the earliest hit, if any, is
  /// the ground (normal from the body towards it). Throws InvalidInput for a stale id or a
  /// non-finite `down`.
  [[nodiscard]] WorldCastHitN<D> ground_check(BodyId id, Vec down) const;

  /// Draws statics, bodies (bullets, and bodies whose last step was longer than their own size,
  /// as DrawRole::fast_body) and the last step's contacts (points, and a normal arrow from each
  /// manifold's centre). 3D: every shape as triangles (draw_shape), levels too. A field: 2D its
  /// zero contour as segments (marching squares over its nodes), 3D the edges of its solid's box.
  void draw(DebugDrawN<D>& draw, const WorldDrawOptions& options = {}) const;
  /// Draws a laser path (segments as DrawRole::laser, hit points as DrawRole::laser_hit).
  static void draw_laser(DebugDrawN<D>& draw, const LaserPathN<D>& path);

  /// A hash of every body's transform and velocities (bit patterns, in index order): equal
  /// hashes mean equal states. FNV-1a, 64 bits.
  [[nodiscard]] std::uint64_t state_hash() const noexcept;
  /// Box around every static and body, world space (empty box at the origin for an empty world).
  [[nodiscard]] AabbN<D> bounds() const noexcept;

  /// The implementation (opaque outside src/world; named here so the sources can share it).
  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

extern template class WorldN<2>;
extern template class WorldN<3>;

}  // namespace collide
