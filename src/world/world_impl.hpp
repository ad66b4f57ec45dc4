#pragma once
// World2D's state, shared by the files that implement it: world2d.cpp (bodies, statics, the
// step), world_queries.cpp (ray casts, lasers, picks, shape casts), world_draw.cpp and
// world_check.cpp (the independent end-of-step check).

#include "body_broad_phase.hpp"

#include <collide/broad/dynamic_tree.hpp>
#include <collide/early_out/check_chain.hpp>
#include <collide/world/world2d.hpp>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace collide::detail {

/// Precomputed facts about one convex piece, in its owner's local frame.
struct PieceInfo {
  Vec2 circle_center{0.0f, 0.0f};  ///< bounding circle (the early-out pretest)
  float circle_radius = 0.0f;
  /// Radius of the largest circle that fits inside (0 for a segment): how far the piece can
  /// move in one step before it could pass through a thin wall.
  float inner_size = 0.0f;
};

/// Facts about a shape: bounding circle, inner size, area and area centroid (local space).
PieceInfo piece_info(const Shape2D& shape);
float shape_area(const Shape2D& shape);
Vec2 shape_centroid(const Shape2D& shape);

/// One convex piece of a static, in world space.
struct StaticPiece {
  std::uint32_t owner = 0;   ///< index into statics
  std::uint16_t piece = 0;   ///< index into the owner's shapes
  Aabb box;                  ///< world box
  Vec2 circle_center{0.0f, 0.0f};  ///< world bounding circle
  float circle_radius = 0.0f;
  float inner_size = 0.0f;
};

struct Body {
  std::vector<Shape2D> shapes;
  std::vector<PieceInfo> pieces;
  Transform xf;
  Vec2 velocity{0.0f, 0.0f};
  float angular_velocity = 0.0f;
  Vec2 push{0.0f, 0.0f};          ///< push-out from body contacts, applied with the next motion
  std::uint64_t user_id = 0;
  CollisionFilter filter{};
  bool sensor = false;
  bool bullet = false;
  bool alive = false;
  bool used_ccd = false;          ///< moved by continuous collision in the last step
  bool very_fast = false;         ///< last step's motion exceeded its own size (would tunnel)
  std::uint32_t generation = 0;
  Vec2 local_center{0.0f, 0.0f};  ///< centre of rotation: area centroid of the pieces
  float inner_size = 0.0f;        ///< smallest piece's inner size
  float bounding_radius = 0.0f;   ///< reach of the pieces from local_center
};

/// A body piece in the body broad phase.
struct Proxy {
  std::uint32_t body = 0;
  std::uint16_t piece = 0;
};

/// The early-out chain used for both kinds of pairs: check 0 the layer/mask filter, check 1
/// the tight boxes, check 2 the exact contact with the bounding circles as its pretest.
using WorldCheckChain = CheckChain<3>;
inline constexpr int kCheckFilter = 0;
inline constexpr int kCheckAabb = 1;
inline constexpr int kCheckExact = 2;

/// The independent check's own uniform grid over the static pieces: deliberately not the
/// world's tree, so a bug there cannot hide a tunnelled body.
struct CheckGrid {
  float cell = 1.0f;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  std::vector<std::uint32_t> stamp;  ///< per static piece: last query that visited it
  std::uint32_t query = 0;
};

}  // namespace collide::detail

namespace collide {

struct World2D::Impl {
  explicit Impl(const WorldOptions& o);

  WorldOptions options;

  // Statics
  std::vector<StaticDef> statics;
  std::vector<detail::StaticPiece> static_pieces;
  DynamicTree static_tree;
  bool static_tree_dirty = false;
  detail::CheckGrid check_grid;
  bool check_grid_dirty = true;

  // Bodies
  std::vector<detail::Body> bodies;
  std::vector<std::uint32_t> free_slots;
  int alive_bodies = 0;

  // Body broad phase
  detail::BodyBroadPhase body_broad;
  std::vector<detail::Proxy> proxies;
  std::vector<Aabb> proxy_boxes;        ///< swept boxes over the last step
  std::vector<Aabb> proxy_start_boxes;  ///< tight boxes at the start of the step
  std::vector<float> proxy_speeds;
  bool proxies_changed = true;          ///< bodies added or removed since the broad phase was set
  bool body_boxes_current = false;      ///< the broad phase holds every body's current box
  double time = 0.0;
  std::int64_t last_skipped = 0;

  // Early out
  detail::WorldCheckChain static_chain;
  detail::WorldCheckChain body_chain;

  // Results
  std::vector<Contact> contacts;
  /// Body-static pairs a fast body hit during this step's continuous motion (manifold at the
  /// time of impact); merged into `contacts` unless the pair touches at the end, too.
  std::vector<Contact> ccd_contacts;
  std::vector<Contact> merged_contacts;  ///< make_events' buffer, reused every step
  std::vector<Contact> previous_contacts;
  std::vector<ContactEvent> events;
  StepStats last{};
  StepStats total{};

  // Scratch, reused every step
  PairList pairs;
  std::vector<int> candidates;
  std::vector<Contact> body_contacts;

  // Helpers
  [[nodiscard]] detail::Body& body(BodyId id);
  [[nodiscard]] const detail::Body& body(BodyId id) const;
  [[nodiscard]] const Shape2D& shape(const ColliderRef& c) const;
  [[nodiscard]] Transform transform(const ColliderRef& c) const;
  [[nodiscard]] CollisionFilter filter(const ColliderRef& c) const;
  [[nodiscard]] bool is_sensor(const ColliderRef& c) const;
  [[nodiscard]] std::uint64_t user_id(const ColliderRef& c) const;
  [[nodiscard]] Aabb body_box(const detail::Body& b) const;
  [[nodiscard]] Aabb piece_box(const detail::Body& b, int piece) const;
  void refresh_static_tree();

  // Step phases
  void integrate(float dt, StepStats& stats);
  void move_with_ccd(std::uint32_t index, Vec2 translation, float rotation, StepStats& stats);
  void resolve_statics(StepStats& stats);
  void find_body_contacts(float dt, StepStats& stats);
  /// Bound on how fast body b's swept boxes move from now on, world units per second.
  [[nodiscard]] float speed_bound(const detail::Body& b, float dt) const;
  /// Records a fast body's impact on a static piece as a contact of this step.
  void record_impact(std::uint32_t index, std::size_t piece, int static_piece, Vec2 normal, Vec2 point);
  void make_events(StepStats& stats);
  void check(StepStats& stats);
  /// Runs `chain` on one pair; on pass, `out` holds the manifold. Counts rejections in `stats`.
  bool evaluate_pair(detail::WorldCheckChain& chain, const ColliderRef& a, const ColliderRef& b,
                     const Aabb& box_a, const Aabb& box_b, Vec2 circle_a, float radius_a,
                     Vec2 circle_b, float radius_b, Manifold& out, StepStats& stats);
};

}  // namespace collide
