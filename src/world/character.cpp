// move_character (character.hpp): collide and slide, steps, sticking to the ground, in 2D and 3D,
// on the world's public queries (shape_cast, collide_shape).

#include <collide/world/character.hpp>

#include <collide/core/error.hpp>
#include <collide/core/tolerance.hpp>
#include <collide/narrow/support.hpp>

#include "hit_order.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

namespace collide {

namespace {

/// Most planes the slide keeps: a plane beyond them is a corner the character cannot leave
/// along any of them (in 3D three planes fix a point; in 2D two), plus one for the vertical
/// plane a steep surface adds beside its own.
template <int D>
inline constexpr int kMaxPlanes = D + 1;

/// Two slide planes whose normals' cosine exceeds 1 minus this are one plane (met again on the
/// next cast, as a surface the character rests against is).
constexpr float kSamePlaneTolerance = 1e-4f;

/// Most push-out passes at the start of a move.
constexpr int kPushOutPasses = 4;

template <int D>
class Mover {
 public:
  using Vec = VecN<D>;

  Mover(const WorldN<D>& world, const BodyShapeN<D>& shape, const CharacterSettingsN<D>& settings,
        CharacterMoveN<D>& out)
      : world_(world), shape_(shape), proxy_(shape), s_(settings), out_(out),
        cos_slope_(std::cos(settings.max_slope)) {
    filter_ = settings.filter;
    filter_.sensors = false;
  }

  [[nodiscard]] bool walkable(Vec n) const { return dot(n, s_.up) >= cos_slope_; }

  /// `v` without its part along up.
  [[nodiscard]] Vec horizontal(Vec v) const { return v - dot(v, s_.up) * s_.up; }

  /// Height along up of the shape's lowest point when placed at `xf` (its support point down).
  [[nodiscard]] float lowest(const TransformN<D>& xf) const {
    const Vec down = inv_rotate(xf.q, -s_.up);
    return dot(transform_point(xf, proxy_.point(proxy_.support_index(down))), s_.up) - proxy_.radius();
  }

  /// The vertical plane a surface of normal `n` (from the surface to the character) adds for a
  /// walking character when it faces up but is steeper than the walkable slope: the character
  /// slides along it, never up it, while its own plane still lets gravity slide it down (as
  /// Jolt's CharacterVirtual adds a vertical plane beside a steep contact's). Otherwise `n`.
  [[nodiscard]] Vec effective_normal(Vec n) const {
    const float up = dot(n, s_.up);
    if (up <= 0.0f || walkable(n)) return n;
    const Vec h = n - up * s_.up;
    const float l = length(h);
    return l > kParallelTolerance ? h / l : n;
  }

  /// Casts from `xf` by `d` and a skin further (a surface the shape would end closer to than
  /// the skin counts too: a cast reports only what it touches); moves `xf` by `d`, or to where
  /// the gap to the surface hit, along its normal, is the skin. Returns the hit when it cut the
  /// move short, and then, in `met` if given, where the shape met the surface (the skin short
  /// of it along the motion is where `xf` stops).
  WorldCastHitN<D> cast(TransformN<D>& xf, Vec d, Vec* met = nullptr) {
    const float len = length(d);
    if (!(len > 0.0f)) return {};
    ++out_.casts;
    const Vec dir = d / len;
    const float skin = (1.0f + kCharacterSkinSlack) * s_.skin;
    const WorldCastHitN<D> hit = world_.shape_cast(shape_, xf, (len + skin) * dir, filter_);
    if (!hit.hit) {
      xf.p += d;
      return {};
    }
    // Approaching the surface at cosine c (the normal's component along the motion), the gap
    // along the normal closes by c per unit of travel: stop `skin / c` before the contact.
    const float c = std::max(dot(dir, hit.normal), kParallelTolerance);
    const float reach = hit.fraction * (len + skin);
    const float travel = std::clamp(reach - skin / c, 0.0f, len);
    if (met != nullptr) *met = xf.p + dir * reach;
    xf.p += dir * travel;
    if (travel == len) return {};  // the whole move keeps the skin: not met
    record(hit.collider, hit.user_id, hit.point, -hit.normal);
    return hit;
  }

  /// Pushes `xf` out of whatever the shape overlaps (a spawn or a moving obstacle inside it),
  /// each pass along the deepest contact, to the skin. True when it moved.
  bool push_out(TransformN<D>& xf) {
    bool moved = false;
    for (int pass = 0; pass < kPushOutPasses; ++pass) {
      float depth = 0.0f;
      Vec normal(0.0f);
      world_.collide_shape(shape_, xf, filter_, [&](const ColliderRef& c, const ManifoldN<D>& m) {
        if (m.max_depth() > depth) {
          depth = m.max_depth();
          normal = m.normal;  // from the shape to the collider
          record(c, world_.user_id(c), m.points[0].point, -m.normal);
        }
        return true;
      });
      if (!(depth > 0.0f) || normal == Vec(0.0f)) break;
      xf.p -= (depth + s_.skin) * normal;
      moved = true;
    }
    return moved;
  }

  /// `push_out` when no static can overlap the shape at `xf` (see move_character): a pass
  /// against the bodies alone, and only if one overlaps it the full push out.
  bool push_out_of_bodies(TransformN<D>& xf) {
    if (!filter_.bodies) return false;
    QueryFilter bodies_only = filter_;
    bodies_only.statics = false;
    bool overlapped = false;
    world_.collide_shape(shape_, xf, bodies_only, [&](const ColliderRef&, const ManifoldN<D>& m) {
      overlapped = m.max_depth() > 0.0f;
      return !overlapped;
    });
    return overlapped && push_out(xf);
  }

  /// What is under `xf` within `distance`: a cast down.
  WorldCastHitN<D> probe_below(const TransformN<D>& xf, float distance) {
    ++out_.casts;
    return world_.shape_cast(shape_, xf, -distance * s_.up, filter_);
  }
  /// `probe_below` when its part against the statics is `statics` (the same cast, kept by the
  /// last move): the bodies alone are cast against, and the first of the two hits is taken as
  /// the world's shape_cast orders them (detail::better).
  WorldCastHitN<D> probe_below(const TransformN<D>& xf, float distance, const WorldCastHitN<D>& statics) {
    if (!filter_.bodies) return statics;
    ++out_.casts;
    QueryFilter bodies_only = filter_;
    bodies_only.statics = false;
    const WorldCastHitN<D> bodies = world_.shape_cast(shape_, xf, -distance * s_.up, bodies_only);
    const bool bodies_first =
        bodies.hit && detail::better(bodies.fraction, bodies.collider, statics.hit, statics.fraction, statics.collider);
    return bodies_first ? bodies : statics;
  }
  /// The ground under `xf`: a cast down by `distance` that hits walkable ground.
  WorldCastHitN<D> probe_ground(const TransformN<D>& xf, float distance) {
    return ground_of(probe_below(xf, distance));
  }
  /// `hit` if it is walkable ground, else no hit.
  [[nodiscard]] WorldCastHitN<D> ground_of(const WorldCastHitN<D>& hit) const {
    if (hit.hit && walkable(-hit.normal)) return hit;
    return {};
  }

  /// The step over a wall of normal `n` (from the wall to the character) met at `xf`, going
  /// `along` (horizontal): up by at most step_height, forward, down onto walkable ground. Kept
  /// when it rises, goes forward and lands higher than it was, each by more than the skin, on
  /// or by walkable ground (`step_forward_test` further on: a rounded bottom perched on the
  /// step's edge goes on climbing in the next frames); the first of these to fail ends the try.
  /// Where it landed, or nothing.
  std::optional<TransformN<D>> step_over(const TransformN<D>& xf, Vec n, Vec along) {
    TransformN<D> t = xf;
    cast(t, s_.step_height * s_.up);
    const float risen = dot(t.p - xf.p, s_.up);
    if (!(risen > s_.skin)) return std::nullopt;
    const Vec raised = t.p;
    Vec ahead = along;
    const WorldCastHitN<D> block = cast(t, along);
    const auto gone = [&] { return length(horizontal(t.p - raised)); };
    if (block.hit && gone() <= s_.skin) {
      // Stopped at once by another surface than the one stepped over (a wall beside a stair,
      // the move going a little into it): along that surface, once.
      const Vec side = effective_normal(-block.normal);
      const float into_side = dot(along, side);
      if (into_side < 0.0f && dot(side, effective_normal(n)) < 1.0f - kSamePlaneTolerance) {
        ahead = along - into_side * side;
        cast(t, ahead);
      }
    }
    if (!(gone() > s_.skin)) return std::nullopt;
    bool land = probe_ground(t, risen + s_.skin).hit;
    if (!land && s_.step_forward_test > 0.0f) {
      TransformN<D> further = t;
      cast(further, s_.step_forward_test * (ahead / length(ahead)));
      land = probe_ground(further, risen + s_.skin).hit;
    }
    if (!land) return std::nullopt;
    cast(t, -(risen + s_.skin) * s_.up);
    if (!(dot(t.p - xf.p, s_.up) > s_.skin)) return std::nullopt;
    return t;
  }

  void record(const ColliderRef& c, std::uint64_t user, Vec point, Vec normal) {
    for (int i = 0; i < out_.contact_count; ++i) {
      if (out_.contacts[i].collider == c && dot(out_.contacts[i].normal, normal) > 1.0f - kRelativeTolerance) return;
    }
    if (out_.contact_count < kMaxCharacterContacts) out_.contacts[out_.contact_count++] = {c, user, point, normal};
  }

 private:
  const WorldN<D>& world_;
  const BodyShapeN<D>& shape_;
  ConvexProxyN<D> proxy_;  ///< shape_'s support map
  const CharacterSettingsN<D>& s_;
  CharacterMoveN<D>& out_;
  float cos_slope_;
  QueryFilter filter_;
};

/// `v` with its motion into the planes removed: of the motions that go into none of the planes,
/// the nearest to `v` (Quake's PM_SlideMove and Box2D v3's b2SolvePlanes solve the same small
/// problem). It is `v` itself, or `v` projected onto one plane (slide along it), or in 3D onto
/// the crease of two (slide along the crease), or nothing: the nearest motion that keeps clear of
/// a set of planes lies on as many of them as it must, so the candidates are those, each kept
/// only if it goes into no other plane. (Taking the first plane `v` goes into, then the crease
/// with the first plane that projection goes into, held a character still on a slope beside a
/// steep wall: the crease of the wall with the vertical plane beside it is level and goes into
/// the slope, while the crease of the slope with the vertical plane climbs along the wall.)
template <int D>
VecN<D> clip(VecN<D> v, const std::array<VecN<D>, kMaxPlanes<D>>& planes, int count) {
  // Into none of the planes but `skip_a` and `skip_b` (the ones `w` lies on).
  const auto clear = [&](VecN<D> w, int skip_a, int skip_b) {
    for (int k = 0; k < count; ++k) {
      if (k != skip_a && k != skip_b && dot(w, planes[k]) < 0.0f) return false;
    }
    return true;
  };
  if (clear(v, -1, -1)) return v;
  VecN<D> best(0.0f);
  float best_d2 = INFINITY;
  const auto offer = [&](VecN<D> w) {
    const float d2 = dot(v - w, v - w);
    if (d2 < best_d2) {
      best = w;
      best_d2 = d2;
    }
  };
  for (int i = 0; i < count; ++i) {
    const float into = dot(v, planes[i]);
    if (into >= 0.0f) continue;
    const VecN<D> w = v - into * planes[i];
    if (clear(w, i, -1)) offer(w);
  }
  if (best_d2 < INFINITY) return best;  // a crease is never nearer than a plane it lies on
  if constexpr (D == 3) {
    for (int i = 0; i < count; ++i) {
      for (int j = i + 1; j < count; ++j) {
        const VecN<D> crease = cross(planes[i], planes[j]);
        const float cc = dot(crease, crease);
        if (!(cc > kParallelTolerance * kParallelTolerance)) continue;
        const VecN<D> w = (dot(v, crease) / cc) * crease;
        if (clear(w, i, j)) offer(w);
      }
    }
  }
  return best_d2 < INFINITY ? best : VecN<D>(0.0f);
}

/// Bit for bit the same placement.
[[nodiscard]] bool same_transform(const Transform& a, const Transform& b) noexcept {
  return a.p == b.p && a.q.c == b.q.c && a.q.s == b.q.s;
}
[[nodiscard]] bool same_transform(const Transform3& a, const Transform3& b) noexcept {
  return a.p == b.p && a.q == b.q;
}

template <int D>
void check_settings(const CharacterSettingsN<D>& s, const TransformN<D>& start, VecN<D> displacement) {
  if (!is_valid(start)) throw InvalidInput("character start: not finite or rotation not unit length");
  if (!is_finite(displacement)) throw InvalidInput("character displacement: not finite");
  if (!is_finite(s.up) || std::fabs(length(s.up) - 1.0f) > 1e-3f) {
    throw InvalidInput("character settings up: not a unit vector");
  }
  if (!(s.max_slope >= 0.0f && s.max_slope <= 0.5f * std::numbers::pi_v<float>)) {
    throw InvalidInput("character settings max_slope: not in [0, pi/2] radians");
  }
  if (!(s.step_height >= 0.0f) || !std::isfinite(s.step_height)) {
    throw InvalidInput("character settings step_height: negative or not finite");
  }
  if (!(s.skin >= 0.0f) || !std::isfinite(s.skin)) throw InvalidInput("character settings skin: negative or not finite");
  if (s.max_iterations < 1) throw InvalidInput("character settings max_iterations: less than 1");
}

}  // namespace

template <int D>
CharacterMoveN<D> move_character(const WorldN<D>& world, const BodyShapeN<D>& shape,
                                 const TransformN<D>& start, VecN<D> displacement,
                                 const CharacterSettingsN<D>& settings, const CharacterMoveN<D>* previous) {
  check_settings(settings, start, displacement);
  using Vec = VecN<D>;
  CharacterMoveN<D> out;
  Mover<D> mover(world, shape, settings, out);
  TransformN<D> xf = start;
  // Where the last move ended, with the same statics: its ground probe is this move's first
  // cast against them. That cast reports every static the shape overlaps at the start at
  // fraction 0, so a first static hit later than that (or none) says no static overlaps it,
  // and pushing out needs to look at the bodies only.
  const bool continued = previous != nullptr && previous->probe_statics == world.static_count() &&
                         same_transform(start, previous->transform);
  const bool statics_clear =
      continued && (!previous->static_probe.hit || previous->static_probe.fraction > 0.0f);
  out.pushed_out = statics_clear ? mover.push_out_of_bodies(xf) : mover.push_out(xf);
  const Vec up = settings.up;
  // How far down the ground probe looks from `at`: twice the skin it keeps, and rounding.
  const auto probe_at = [&](const TransformN<D>& at) {
    return 2.0f * (1.0f + kCharacterSkinSlack) * settings.skin + kRelativeTolerance * (max_abs(at.p) + 1.0f);
  };
  const float probe = probe_at(xf);
  // The last move ended with this very cast when the character starts where it ended.
  const bool reuse = continued && !out.pushed_out;
  const WorldCastHitN<D> under = reuse ? mover.probe_below(xf, probe, previous->static_probe)
                                       : mover.probe_below(xf, probe);
  const bool was_grounded = under.hit && mover.walkable(-under.normal);
  // Held up by something under it, walkable or not (a rounded bottom on a step's edge): it may
  // step.
  const bool supported = under.hit && dot(-under.normal, settings.up) > 0.0f;

  // Collide and slide.
  std::array<Vec, kMaxPlanes<D>> planes{};
  int plane_count = 0;
  Vec remaining = displacement;
  // Standing on walkable ground within the skin (the gap along its normal, from the probe):
  // its plane is the slide's first, so the part of the displacement into the ground (gravity
  // while walking) is taken out before the first cast instead of by a cast that meets the
  // ground at once and moves nowhere.
  const float skin_kept = (1.0f + kCharacterSkinSlack) * settings.skin;
  if (was_grounded && under.fraction * probe * dot(-under.normal, up) <= skin_kept) {
    planes[plane_count++] = -under.normal;
    remaining = clip(displacement, planes, plane_count);
  }
  bool tried_step = false;
  for (int i = 0; i < settings.max_iterations; ++i) {
    if (!(length(remaining) > kRelativeTolerance * (max_abs(xf.p) + 1.0f))) break;
    const TransformN<D> before = xf;
    Vec met(0.0f);
    const WorldCastHitN<D> hit = mover.cast(xf, remaining, &met);
    if (!hit.hit) break;
    const Vec n = -hit.normal;  // from the surface towards the character
    Vec leftover = remaining - (xf.p - before.p);
    // A wall met on the ground: try to step over it, once per move, when what is left of
    // the move goes into it by more than the skin (not a wall walked along: the try is left
    // for a step met further on) and it is met no higher above the character's lowest point
    // than a step (rising by a step, the shape would meet that point again going forward).
    const Vec along = mover.horizontal(leftover);
    if (!tried_step && supported && settings.step_height > 0.0f && !mover.walkable(n) && dot(n, up) > -0.5f &&
        -dot(along, mover.effective_normal(n)) > settings.skin &&
        dot(hit.point, up) - mover.lowest(TransformN<D>{met, xf.q}) <= settings.step_height + settings.skin) {
      tried_step = true;
      if (const std::optional<TransformN<D>> landed = mover.step_over(xf, n, along)) {
        xf = *landed;
        out.stepped = true;
        remaining = dot(leftover, up) * up;  // the vertical part (gravity) goes on
        continue;
      }
    }
    // The surface's plane, and for a steep one the vertical plane that keeps it from being
    // climbed; a plane already kept is not added again.
    const Vec wall = mover.effective_normal(n);
    bool full = false;
    for (const Vec p : {n, wall}) {
      bool known = false;
      for (int k = 0; k < plane_count && !known; ++k) known = dot(planes[k], p) > 1.0f - kSamePlaneTolerance;
      if (known) continue;
      if (plane_count == kMaxPlanes<D>) {
        full = true;
        break;
      }
      planes[plane_count++] = p;
    }
    if (full) {
      remaining = Vec(0.0f);
      break;
    }
    remaining = clip(leftover, planes, plane_count);
  }

  // Stick to the ground going down: a character that stood on ground and did not move up is
  // pressed down onto walkable ground within a step. The last cast down is the ground probe
  // (from where the character ends, so that the next move can start from it).
  WorldCastHitN<D> end_probe = mover.probe_below(xf, probe_at(xf));
  if (!mover.ground_of(end_probe).hit && was_grounded && dot(displacement, up) <= 0.0f &&
      settings.step_height > 0.0f) {
    const WorldCastHitN<D> below = mover.probe_ground(xf, settings.step_height + settings.skin);
    if (below.hit) {
      mover.cast(xf, -(settings.step_height + settings.skin) * up);
      end_probe = mover.probe_below(xf, probe_at(xf));
    }
  }
  const WorldCastHitN<D> ground = mover.ground_of(end_probe);
  if (!end_probe.hit || end_probe.collider.is_static) {
    out.static_probe = end_probe;
    out.probe_statics = world.static_count();
  }
  out.transform = xf;
  out.moved = xf.p - start.p;
  out.grounded = ground.hit;
  if (ground.hit) {
    out.ground_normal = -ground.normal;
    out.ground = ground.collider;
    out.ground_user_id = ground.user_id;
  }
  out.blocked = length(displacement - out.moved) > 2.0f * settings.skin + kRelativeTolerance * (max_abs(xf.p) + 1.0f);
  return out;
}

template CharacterMoveN<2> move_character<2>(const WorldN<2>&, const BodyShapeN<2>&, const TransformN<2>&,
                                             VecN<2>, const CharacterSettingsN<2>&, const CharacterMoveN<2>*);
template CharacterMoveN<3> move_character<3>(const WorldN<3>&, const BodyShapeN<3>&, const TransformN<3>&,
                                             VecN<3>, const CharacterSettingsN<3>&, const CharacterMoveN<3>*);

}  // namespace collide
