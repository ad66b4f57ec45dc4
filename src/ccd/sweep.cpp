#include <collide/ccd/sweep.hpp>

#include <collide/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {
namespace {

/// Box of the proxy's core placed by `xf`, without the radius.
Aabb core_aabb(const ConvexProxy& proxy, const Transform& xf) noexcept {
  Vec2 lo = transform_point(xf, proxy.point(0));
  Vec2 hi = lo;
  for (int i = 1; i < proxy.count(); ++i) {
    const Vec2 p = transform_point(xf, proxy.point(i));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {lo, hi};
}

}  // namespace

void check_sweep(const Sweep& sweep, const char* name) {
  const std::string n(name);
  if (!is_finite(sweep.local_center)) throw InvalidInput(n + " local_center: not finite");
  if (!is_finite(sweep.c0)) throw InvalidInput(n + " c0: not finite");
  if (!is_finite(sweep.c1)) throw InvalidInput(n + " c1: not finite");
  if (!std::isfinite(sweep.a0)) throw InvalidInput(n + " a0: not finite");
  if (!std::isfinite(sweep.a1)) throw InvalidInput(n + " a1: not finite");
}

Aabb swept_aabb(const Shape2D& shape, const Transform& xf, Vec2 translation) noexcept {
  return std::visit([&](const auto& s) { return swept_aabb(s, xf, translation); }, shape);
}

Aabb swept_aabb(const Shape2D& shape, const Sweep& sweep) noexcept {
  return swept_aabb(ConvexProxy(shape), sweep);
}

Aabb swept_aabb(const ConvexProxy& proxy, const Sweep& sweep) noexcept {
  const Aabb start = core_aabb(proxy, sweep.at(0.0f));
  const Aabb end = core_aabb(proxy, sweep.at(1.0f));
  const float turn = std::fabs(sweep.a1 - sweep.a0);
  Aabb box = merge(start, end);
  if (turn > 0.0f) {
    // Reach of the core from the centre of rotation.
    float reach2 = 0.0f;
    for (int i = 0; i < proxy.count(); ++i) {
      reach2 = std::max(reach2, distance_squared(proxy.point(i), sweep.local_center));
    }
    const float reach = std::sqrt(reach2);
    // Bound 1: every core point stays within reach * turn^2 / 8 of the chord between its end
    // positions, and chords stay inside merge(start, end).
    const Aabb chord_box = fatten(box, reach * turn * turn * 0.125f);
    // Bound 2: the centre moves on a segment and the core stays within `reach` of it.
    const Aabb centre_box =
        fatten(Aabb{glm::min(sweep.c0, sweep.c1), glm::max(sweep.c0, sweep.c1)}, reach);
    box = Aabb{glm::max(chord_box.min, centre_box.min), glm::min(chord_box.max, centre_box.max)};
  }
  return fatten(box, proxy.radius());
}

}  // namespace collide
