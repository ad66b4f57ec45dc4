#pragma once
/// @file
/// `move_character`: the piece every game writes for itself. A character's shape (usually a
/// capsule) moves through a world's colliders by a displacement per frame: it slides along
/// walls, walks up slopes up to a maximum angle and steps up to a maximum height, stays on the
/// ground going down slopes and steps, never enters the geometry, and reports where it ended,
/// whether it stands on ground (with the ground's normal and collider) and the surfaces it met.
/// The same in 2D and 3D (`WorldN<D>`).
///
/// Method (collide and slide). The shape is cast along what is left of the displacement
/// (`WorldN::shape_cast`: the ray into the Minkowski difference) and stops `skin` short of the
/// first surface; the rest of the displacement is projected onto the planes met so far, as
/// Box2D v3's mover (`b2SolvePlanes`) and Jolt's `CharacterVirtual` do: the nearest motion that
/// goes into none of them, which slides along one plane, along the crease of two (3D), or stops.
/// A character that starts on walkable ground within its skin has that ground as its first plane
/// (the part of the displacement into it, gravity, is taken out before the first cast). A
/// surface steeper than `max_slope` counts as a vertical wall, so it can be slid along but not
/// climbed; a ceiling blocks upward motion. Met by a wall while on the ground, the mover tries a
/// step (once a move): up by at most `step_height`, forward (along another wall it meets at
/// once, as beside a stair), down onto walkable ground, kept only if it lands there or finds
/// walkable ground a little further on (`step_forward_test`: a rounded bottom perched on the
/// step's edge goes on climbing in the next frames). No step is tried at a wall the rest of the
/// move goes into by no more than the skin (one walked along) or met higher above the shape's
/// lowest point than `step_height` (rising by a step, the shape meets it again going forward).
/// After the move a character that stood on ground and did not move up is pressed down by up to
/// `step_height` onto walkable ground (stairs and slopes down). A start inside geometry (a
/// spawn, a moving obstacle) is first pushed out along the deepest contacts. The ground is what
/// a short cast down finds.

#include <collide/world/world.hpp>

#include <array>
#include <cstdint>

namespace collide {

/// Most contacts a character move reports.
inline constexpr int kMaxCharacterContacts = 16;
/// A cast stops where the gap to the surface, along its normal, is the skin times (1 + this),
/// and does not move towards a surface already within that: a shape cast's fraction is exact
/// only to about 1e-4 of the cast, and a character stopped at exactly the skin crept into a
/// wall by that much a frame (2.4 mm in 240 frames of walking into it).
inline constexpr float kCharacterSkinSlack = 0.1f;

/// How a character moves.
template <int D>
struct CharacterSettingsN {
  /// Unit up direction, world space (y up by default).
  VecN<D> up = [] {
    VecN<D> y(0.0f);
    y[1] = 1.0f;
    return y;
  }();
  /// Steepest walkable slope, radians from the horizontal (50 degrees).
  float max_slope = 0.872664626f;
  /// Highest step the character climbs, world units; 0 climbs none.
  float step_height = 0.3f;
  /// How far ahead, past a step's edge, a step looks for walkable ground when the frame's own
  /// motion lands the shape's rounded bottom on the edge itself (as Jolt's stair walking's
  /// forward test), world units.
  float step_forward_test = 0.15f;
  /// Gap kept between the shape and every surface, world units: casts stop this short of the
  /// surface (aiming at kCharacterSkinSlack more, so that the casts' rounding never creeps it
  /// closer frame after frame), so the shape never touches or enters it.
  float skin = 0.01f;
  /// Most casts per move (slides along new planes).
  int max_iterations = 6;
  /// What the character collides with (statics and bodies by default; sensors never).
  QueryFilter filter{};
};

/// A surface a character met during a move.
template <int D>
struct CharacterContactN {
  ColliderRef collider;
  std::uint64_t user_id = 0;  ///< user id of its owner
  VecN<D> point{0.0f};        ///< world space
  VecN<D> normal{0.0f};       ///< unit, from the surface towards the character
};

/// What a character move did.
template <int D>
struct CharacterMoveN {
  TransformN<D> transform;     ///< where the shape ended
  VecN<D> moved{0.0f};         ///< the displacement made: transform.p - start.p
  bool grounded = false;       ///< stands on walkable ground at the end
  VecN<D> ground_normal{0.0f}; ///< unit, from the ground towards the character; zero when airborne
  ColliderRef ground;          ///< what it stands on (when grounded)
  std::uint64_t ground_user_id = 0;
  /// The move was cut short: the displacement made is shorter, by more than the skin, than the
  /// one asked (a wall, a too steep slope, a ceiling, a corridor too narrow).
  bool blocked = false;
  bool stepped = false;        ///< climbed a step on the way
  bool pushed_out = false;     ///< started inside geometry and was pushed out first
  int casts = 0;               ///< shape casts made
  std::array<CharacterContactN<D>, kMaxCharacterContacts> contacts{};  ///< surfaces met
  int contact_count = 0;
  /// What the cast down under the shape at the end met first among the world's statics (no
  /// hit: nothing within the probe), kept for this character's next move (`previous` of
  /// move_character), which starts with the same cast. Kept when `probe_statics` >= 0: the
  /// world's static_count() then; -1 when that cast met a body first (the statics' own first
  /// hit is then unknown).
  WorldCastHitN<D> static_probe{};
  int probe_statics = -1;
};

using CharacterSettings = CharacterSettingsN<2>;    ///< 2D character settings
using CharacterSettings3 = CharacterSettingsN<3>;   ///< 3D character settings
using CharacterContact = CharacterContactN<2>;      ///< 2D surface met
using CharacterContact3 = CharacterContactN<3>;     ///< 3D surface met
using CharacterMove = CharacterMoveN<2>;            ///< 2D character move
using CharacterMove3 = CharacterMoveN<3>;           ///< 3D character move

/// Moves `shape` (local space, usually a capsule along `up`) from `start` by `displacement`
/// (world units, e.g. velocity * dt, gravity included) through `world`'s colliders that
/// `settings.filter` sees, as the file comment says. The shape keeps its orientation.
///
/// `previous`, optional: this character's last move (same shape and settings), as a game keeps
/// it. A move starts with a push out and a cast down (what is under the shape); the last move
/// ended with that same cast when the character starts where it ended. Then that cast's part
/// against the statics, which never move, is taken from `previous`, and so is the push out's:
/// the cast reports a static the shape overlaps at fraction 0, so a later first hit means none
/// does. Only the bodies are queried again (a shape cast and a contact query against the level
/// fewer per move). The result is the same as without it: it is used only when `start` is
/// `previous->transform` exactly and no static was added since.
///
/// Throws InvalidInput for a non-finite transform or displacement, a non-unit `up`, a negative
/// skin or step height, or a max_slope outside [0, pi/2].
template <int D>
[[nodiscard]] CharacterMoveN<D> move_character(const WorldN<D>& world, const BodyShapeN<D>& shape,
                                               const TransformN<D>& start, VecN<D> displacement,
                                               const CharacterSettingsN<D>& settings = {},
                                               const CharacterMoveN<D>* previous = nullptr);

}  // namespace collide
