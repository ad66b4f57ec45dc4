#include <collide/ccd/sweep.hpp>

#include <collide/core/config.hpp>
#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

namespace collide {
namespace {

/// Box of the proxy's core placed by `xf`, without the radius.
template <int D>
AabbN<D> core_aabb(const ConvexProxyN<D>& proxy, const TransformN<D>& xf) noexcept {
  VecN<D> lo = transform_point(xf, proxy.point(0));
  VecN<D> hi = lo;
  for (int i = 1; i < proxy.count(); ++i) {
    const VecN<D> p = transform_point(xf, proxy.point(i));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {lo, hi};
}

/// The rotating swept box of both dimensions (see sweep.hpp): `turn` is the angle turned over
/// the step (radians, >= 0). In 3D the chord bound takes each point's distance from the axis
/// (the radius of its arc), which `axis_reach2` gives squared; in 2D that is the distance from
/// the centre.
template <int D, class SweepT, class AxisReach2>
AabbN<D> rotating_swept_aabb(const ConvexProxyN<D>& proxy, const SweepT& sweep, float turn,
                             const AxisReach2& axis_reach2) noexcept {
  const AabbN<D> start = core_aabb<D>(proxy, sweep.at(0.0f));
  const AabbN<D> end = core_aabb<D>(proxy, sweep.at(1.0f));
  AabbN<D> box = merge(start, end);
  if (turn > 0.0f) {
    // Reach of the core from the centre of rotation, and the radius of the widest arc.
    float reach2 = 0.0f;
    float arc2 = 0.0f;
    for (int i = 0; i < proxy.count(); ++i) {
      reach2 = std::max(reach2, distance_squared(proxy.point(i), sweep.local_center));
      arc2 = std::max(arc2, axis_reach2(proxy.point(i) - sweep.local_center));
    }
    const float reach = std::sqrt(reach2);
    const float arc = std::sqrt(arc2);
    // Bound 1: every core point stays within arc * turn^2 / 8 of the chord between its end
    // positions, and chords stay inside merge(start, end).
    const AabbN<D> chord_box = fatten(box, arc * turn * turn * 0.125f);
    // Bound 2: the centre moves on a segment and the core stays within `reach` of it.
    const AabbN<D> centre_box =
        fatten(AabbN<D>{glm::min(sweep.c0, sweep.c1), glm::max(sweep.c0, sweep.c1)}, reach);
    box = AabbN<D>{glm::max(chord_box.min, centre_box.min),
                   glm::min(chord_box.max, centre_box.max)};
  }
  return fatten(box, proxy.radius());
}

/// check_sweep's failure: throws InvalidInput naming the first field that is not finite.
[[noreturn]] COLLIDE_COLD void throw_bad_sweep(const Sweep& sweep, const char* name) {
  const std::string n(name);
  if (!is_finite(sweep.local_center)) throw InvalidInput(n + " local_center: not finite");
  if (!is_finite(sweep.c0)) throw InvalidInput(n + " c0: not finite");
  if (!is_finite(sweep.c1)) throw InvalidInput(n + " c1: not finite");
  if (!std::isfinite(sweep.a0)) throw InvalidInput(n + " a0: not finite");
  throw InvalidInput(n + " a1: not finite");
}

/// The 3D check's failure, as throw_bad_sweep above.
[[noreturn]] COLLIDE_COLD void throw_bad_sweep(const Sweep3& sweep, const char* name) {
  const std::string n(name);
  if (!is_finite(sweep.local_center)) throw InvalidInput(n + " local_center: not finite");
  if (!is_finite(sweep.c0)) throw InvalidInput(n + " c0: not finite");
  if (!is_finite(sweep.c1)) throw InvalidInput(n + " c1: not finite");
  if (!is_valid(Transform3{Vec3(0.0f), sweep.q0})) throw InvalidInput(n + " q0: not finite or not unit length");
  throw InvalidInput(n + " rotation: not finite");
}

}  // namespace

void check_sweep(const Sweep& sweep, const char* name) {
  // Every time-of-impact query checks two sweeps: the message is built only on failure (the
  // name's string alone was 3% of a turning box-box query's instructions).
  if (is_finite(sweep.local_center) && is_finite(sweep.c0) && is_finite(sweep.c1) && std::isfinite(sweep.a0) &&
      std::isfinite(sweep.a1)) [[likely]] {
    return;
  }
  throw_bad_sweep(sweep, name);
}

Aabb swept_aabb(const Shape2D& shape, const Transform& xf, Vec2 translation) noexcept {
  return std::visit([&](const auto& s) { return swept_aabb(s, xf, translation); }, shape);
}

Aabb swept_aabb(const Shape2D& shape, const Sweep& sweep) noexcept {
  return swept_aabb(ConvexProxy(shape), sweep);
}

Aabb swept_aabb(const ConvexProxy& proxy, const Sweep& sweep) noexcept {
  // In 2D every point turns about the centre: its arc's radius is its distance from it.
  return rotating_swept_aabb<2>(proxy, sweep, std::fabs(sweep.a1 - sweep.a0),
                                [](Vec2 r) { return length_squared(r); });
}

void check_sweep(const Sweep3& sweep, const char* name) {
  // As the 2D check: the message only on failure.
  if (is_finite(sweep.local_center) && is_finite(sweep.c0) && is_finite(sweep.c1) &&
      is_valid(Transform3{Vec3(0.0f), sweep.q0}) && is_finite(sweep.rotation)) [[likely]] {
    return;
  }
  throw_bad_sweep(sweep, name);
}

Aabb3 swept_aabb(const Shape3D& shape, const Transform3& xf, Vec3 translation) noexcept {
  return std::visit([&](const auto& s) { return swept_aabb(s, xf, translation); }, shape);
}

Aabb3 swept_aabb(const Shape3D& shape, const Sweep3& sweep) noexcept {
  return swept_aabb(ConvexProxy3(shape), sweep);
}

Aabb3 swept_aabb(const ConvexProxy3& proxy, const Sweep3& sweep) noexcept {
  const float turn = length(sweep.rotation);
  // A point's arc radius is its distance from the axis (the axis is fixed in the body).
  const Vec3 axis = turn > 0.0f ? inv_rotate(sweep.q0, sweep.rotation * (1.0f / turn)) : Vec3(0.0f);
  return rotating_swept_aabb<3>(proxy, sweep, turn,
                                [axis](Vec3 r) { return length_squared(cross(axis, r)); });
}

}  // namespace collide
