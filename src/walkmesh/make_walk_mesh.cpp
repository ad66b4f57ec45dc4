// From a level mesh to a walk mesh: slope filter, headroom filter, then build_walk_mesh.
#include <collide/walkmesh/make_walk_mesh.hpp>

#include "local_frame.hpp"

#include <collide/core/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

namespace collide {
namespace {

/// Interval of the points' projections onto `axis`.
template <std::size_t N>
void project(const std::array<glm::dvec3, N>& points, glm::dvec3 axis, double& lo, double& hi) noexcept {
  lo = hi = glm::dot(points[0], axis);
  for (std::size_t i = 1; i < N; ++i) {
    const double d = glm::dot(points[i], axis);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
}

/// The candidate separating axes of the convex prism (triangle `base` swept by `lift`) against
/// triangle `other`: the face normals of both, and the cross products of every prism edge
/// direction (three base edges, the lift) with every edge of the other triangle (separating
/// axis theorem for convex polyhedra; Ericson 5.2.1), unnormalised, with the other triangle's
/// interval and the lift's projection on each. A refined piece of `base` has edges parallel to
/// its own (midpoint subdivision), so one set serves the base and all its pieces.
/// Stored by coordinate, padded to an even count with a copy of the first axis, so headroom()
/// can take two axes at a time in lanes (a copy decides nothing the first axis does not).
struct PrismAxes {
  static constexpr int kMax = 17;
  static constexpr int kSlots = kMax + 1;
  std::array<double, kSlots> x, y, z;  ///< the axes
  std::array<double, kSlots> other_lo, other_hi, margin;
  std::array<double, kSlots> down, up;  ///< min(0, rise) and max(0, rise): the lift's projection
  int count = 0;
  glm::dvec3 other_min, other_max;  ///< the other triangle's box
};

/// Bounding box of the prism over `piece` (the triangle swept by `lift`).
std::pair<glm::dvec3, glm::dvec3> prism_bounds(const std::array<glm::dvec3, 3>& piece, glm::dvec3 lift) noexcept {
  const glm::dvec3 lo = glm::min(glm::min(piece[0], piece[1]), piece[2]);
  const glm::dvec3 hi = glm::max(glm::max(piece[0], piece[1]), piece[2]);
  return {glm::min(lo, lo + lift), glm::max(hi, hi + lift)};
}

/// How the prism over a piece meets another triangle (headroom()).
enum class Headroom {
  clear,    ///< separated, or touching within the tolerance
  blocked,  ///< overlap by more than the tolerance on every axis
  covered,  ///< blocked, and so is the prism over every point of the piece: every refined piece too
};

/// One axis' test (axis k of `axes`, the piece projected on it to [p_lo, p_hi]): whether it
/// parts the prism from the other triangle by the margin; else `covered` drops to false unless
/// every point of the piece is blocked along it.
inline bool axis_clears(const PrismAxes& axes, int k, double p_lo, double p_hi, bool& covered) noexcept {
  // The prism's interval is the piece's and the lifted piece's; compared unnormalised.
  const double margin = axes.margin[k];
  if (p_hi + axes.up[k] - axes.other_lo[k] <= margin || axes.other_hi[k] - (p_lo + axes.down[k]) <= margin) return true;
  covered = covered && p_lo + axes.up[k] - axes.other_lo[k] > 2.0 * margin &&
            axes.other_hi[k] - (p_hi + axes.down[k]) > 2.0 * margin;
  return false;
}

/// Whether the prism over `piece` (the triangle `axes` were made for, or a refined piece of it)
/// and the other triangle overlap by more than the tolerance on every axis. In double, on world
/// coordinates: float corners are exact there, so the answer does not depend on the local
/// origin's rounding (borderline contacts decided one way for every origin).
///
/// `covered` bounds every sub-piece at once: a point of the piece projects inside the piece's
/// interval [p_lo, p_hi], so its lifted segment reaches at least p_lo + max(0, rise) and starts at
/// most at p_hi + min(0, rise). When those bounds overlap the other triangle by more than the
/// tolerance on every axis, no refinement can find headroom (with a doubled margin, so that the
/// rounding of a sub-piece's own projections cannot decide it).
Headroom headroom(const PrismAxes& axes, const std::array<glm::dvec3, 3>& piece) noexcept {
#if defined(__SSE2__) || defined(_M_X64)
  // Two axes at a time in SSE2 lanes, each lane the scalar steps of axis_clears on the same
  // doubles (the projections summed as glm::dot sums them): the same answer, half the
  // instructions (the refined pieces' tests were a sixth of a walk mesh build).
  __m128d px[3], py[3], pz[3];
  for (int i = 0; i < 3; ++i) {
    px[i] = _mm_set1_pd(piece[i].x);
    py[i] = _mm_set1_pd(piece[i].y);
    pz[i] = _mm_set1_pd(piece[i].z);
  }
  __m128d covered = _mm_castsi128_pd(_mm_set1_epi32(-1));
  for (int k = 0; k < axes.count; k += 2) {
    const __m128d ax = _mm_loadu_pd(&axes.x[k]), ay = _mm_loadu_pd(&axes.y[k]), az = _mm_loadu_pd(&axes.z[k]);
    __m128d d[3];
    for (int i = 0; i < 3; ++i) {
      d[i] = _mm_add_pd(_mm_add_pd(_mm_mul_pd(px[i], ax), _mm_mul_pd(py[i], ay)), _mm_mul_pd(pz[i], az));
    }
    const __m128d p_lo = _mm_min_pd(_mm_min_pd(d[0], d[1]), d[2]);
    const __m128d p_hi = _mm_max_pd(_mm_max_pd(d[0], d[1]), d[2]);
    const __m128d margin = _mm_loadu_pd(&axes.margin[k]), twice = _mm_add_pd(margin, margin);
    const __m128d up = _mm_loadu_pd(&axes.up[k]), down = _mm_loadu_pd(&axes.down[k]);
    const __m128d other_lo = _mm_loadu_pd(&axes.other_lo[k]), other_hi = _mm_loadu_pd(&axes.other_hi[k]);
    const __m128d clears = _mm_or_pd(_mm_cmple_pd(_mm_sub_pd(_mm_add_pd(p_hi, up), other_lo), margin),
                                     _mm_cmple_pd(_mm_sub_pd(other_hi, _mm_add_pd(p_lo, down)), margin));
    if (_mm_movemask_pd(clears) != 0) return Headroom::clear;
    covered = _mm_and_pd(covered, _mm_and_pd(_mm_cmpgt_pd(_mm_sub_pd(_mm_add_pd(p_lo, up), other_lo), twice),
                                             _mm_cmpgt_pd(_mm_sub_pd(other_hi, _mm_add_pd(p_hi, down)), twice)));
  }
  return _mm_movemask_pd(covered) == 3 ? Headroom::covered : Headroom::blocked;
#else
  bool covered = true;
  for (int k = 0; k < axes.count; ++k) {
    double p_lo, p_hi;
    project(piece, glm::dvec3(axes.x[k], axes.y[k], axes.z[k]), p_lo, p_hi);
    if (axis_clears(axes, k, p_lo, p_hi, covered)) return Headroom::clear;
  }
  return covered ? Headroom::covered : Headroom::blocked;
#endif
}

/// The candidate axes of the prism over `base` (swept by `lift`) against triangle `other`, as
/// PrismAxes describes them, with headroom(axes, base) worked out axis by axis as each is made:
/// at the first axis that parts them the answer is Headroom::clear and the rest are not made
/// (most triangles a prism's box meets are clear: on recast's dungeon.obj this halved the
/// headroom filter's cost). Otherwise `out` holds every axis and the answer is headroom's.
Headroom prism_headroom(const std::array<glm::dvec3, 3>& base, glm::dvec3 lift, const std::array<glm::dvec3, 3>& other,
                        double tolerance, PrismAxes& out) noexcept {
  const std::array<glm::dvec3, 3> e{base[1] - base[0], base[2] - base[1], base[0] - base[2]};
  const std::array<glm::dvec3, 3> f{other[1] - other[0], other[2] - other[1], other[0] - other[2]};
  std::array<glm::dvec3, PrismAxes::kMax> candidates;
  int n = 0;
  candidates[n++] = glm::cross(e[0], e[1]);
  candidates[n++] = glm::cross(f[0], f[1]);
  for (const glm::dvec3& ei : e) candidates[n++] = glm::cross(ei, lift);
  for (const glm::dvec3& fj : f) {
    for (const glm::dvec3& ei : e) candidates[n++] = glm::cross(ei, fj);
    candidates[n++] = glm::cross(lift, fj);
  }
  out.count = 0;
  bool covered = true;
  for (const glm::dvec3& axis : candidates) {
    const double len = glm::length(axis);
    if (!(len > 0.0)) continue;  // parallel edges: no axis
    const int k = out.count++;
    out.x[k] = axis.x;
    out.y[k] = axis.y;
    out.z[k] = axis.z;
    project(other, axis, out.other_lo[k], out.other_hi[k]);
    const double rise = glm::dot(lift, axis);
    out.down[k] = std::min(0.0, rise);
    out.up[k] = std::max(0.0, rise);
    out.margin[k] = tolerance * len;
    double p_lo, p_hi;
    project(base, axis, p_lo, p_hi);
    if (axis_clears(out, k, p_lo, p_hi, covered)) return Headroom::clear;
  }
  if (out.count % 2 != 0) {  // the pad: a copy of the first axis
    for (auto field : {&PrismAxes::x, &PrismAxes::y, &PrismAxes::z, &PrismAxes::other_lo, &PrismAxes::other_hi,
                       &PrismAxes::margin, &PrismAxes::down, &PrismAxes::up}) {
      (out.*field)[out.count] = (out.*field)[0];
    }
  }
  out.other_min = glm::min(glm::min(other[0], other[1]), other[2]);
  out.other_max = glm::max(glm::max(other[0], other[1]), other[2]);
  return covered ? Headroom::covered : Headroom::blocked;
}

}  // namespace

WalkMesh make_walk_mesh(const TriangleSoup& level, const WalkAgent& agent) {
  const std::string name = level.name.empty() ? "level" : level.name;
  if (!std::isfinite(agent.max_slope) || agent.max_slope < 0.0f ||
      agent.max_slope >= 0.5f * std::numbers::pi_v<float>) {
    throw InvalidInput(name + ": WalkAgent.max_slope must be in [0, pi/2) radians");
  }
  if (!std::isfinite(agent.height) || agent.height < 0.0f) {
    throw InvalidInput(name + ": WalkAgent.height must be finite and >= 0");
  }
  if (!is_finite(agent.up) || !(glm::length(agent.up) > 0.0f)) {
    throw InvalidInput(name + ": WalkAgent.up must be a finite non-zero vector");
  }
  validate_triangle_soup(level);
  const Vec3 up = glm::normalize(agent.up);

  // Work near a local origin: level coordinates may be large (undulating.obj sits at 5000). The
  // vertices' median, so that a piece far from the rest does not drag it away.
  Aabb3 box{level.positions[level.triangles[0].x], level.positions[level.triangles[0].x]};
  for (const glm::uvec3& t : level.triangles) {
    for (int k = 0; k < 3; ++k) box = merge(box, Aabb3{level.positions[t[k]], level.positions[t[k]]});
  }
  const Vec3 origin = detail::local_origin(level);
  const Vec3 extent = box.size();
  const float size = std::max({extent.x, extent.y, extent.z});
  detail::check_float_span(size, name);
  const float scale = detail::tolerance_scale(level, size, name);
  std::vector<Vec3> local(level.positions.size(), Vec3(0.0f));
  for (const glm::uvec3& t : level.triangles) {
    for (int k = 0; k < 3; ++k) local[t[k]] = level.positions[t[k]] - origin;
  }
  const TriangleBvh bvh(local, level.triangles);
  const float cos_max_slope = std::cos(agent.max_slope);
  const Vec3 lift = agent.height * up;
  const float tolerance = kHeadroomTolerance * scale;

  TriangleSoup walkable;
  walkable.name = level.name;
  walkable.positions = level.positions;
  std::size_t too_steep = 0, degenerate = 0, low_headroom = 0, refined = 0;
  const glm::dvec3 world_origin(origin);
  const glm::dvec3 world_lift = static_cast<double>(agent.height) * glm::dvec3(up);
  auto world = [&](std::uint32_t v) { return glm::dvec3(level.positions[v]); };
  // The level triangles that leave a prism (base swept by the lift) less than the tolerance of
  // headroom, each with its separating axes against the level triangle being refined. First
  // through the BVH; a refined piece then tests only its parent's blockers: a piece's prism lies
  // inside its parent's, and its edges are parallel to the parent's, so the separating axes are
  // the same and every overlap can only shrink.
  std::vector<PrismAxes> blocker_axes;  // per level triangle: its blockers
  std::vector<std::uint32_t> blockers;  // per level triangle: each piece's list (blocker_axes indices), in turn
  // Each returns true when one blocker covers the whole piece (Headroom::covered): no part of it
  // can be kept, so it is dropped without refining.
  auto collect_blockers = [&](std::uint32_t self, const std::array<glm::dvec3, 3>& base) {
    bool covered = false;
    std::array<Vec3, 3> corner;
    for (int k = 0; k < 3; ++k) corner[static_cast<std::size_t>(k)] = Vec3(base[static_cast<std::size_t>(k)] - world_origin);
    Aabb3 prism_box{glm::min(glm::min(corner[0], corner[1]), corner[2]), glm::max(glm::max(corner[0], corner[1]), corner[2])};
    prism_box = fatten(merge(prism_box, Aabb3{prism_box.min + lift, prism_box.max + lift}), tolerance);
    PrismAxes axes;
    bvh.query(prism_box, [&](std::uint32_t other) {
      if (other == self) return true;
      const glm::uvec3 o = level.triangles[other];
      const Headroom h = prism_headroom(base, world_lift, {world(o.x), world(o.y), world(o.z)}, static_cast<double>(tolerance), axes);
      if (h != Headroom::clear) {
        blockers.push_back(static_cast<std::uint32_t>(blocker_axes.size()));
        blocker_axes.push_back(axes);
        covered = h == Headroom::covered;
      }
      return !covered;  // covered: the piece is dropped whatever else blocks it
    });
    return covered;
  };
  // Most of a refined piece's children lie away from a small obstacle: disjoint bounding boxes
  // settle those before the separating axes (disjoint solids cannot overlap on every axis). A
  // piece that will not be split again (`first_only`) needs one blocker, not the list.
  auto filter_blockers = [&](std::size_t first, std::size_t count, const std::array<glm::dvec3, 3>& piece,
                             bool first_only) {
    const auto [prism_lo, prism_hi] = prism_bounds(piece, world_lift);
    for (std::size_t i = first; i < first + count; ++i) {
      const std::uint32_t b = blockers[i];
      const PrismAxes& axes = blocker_axes[b];
      if (glm::any(glm::lessThan(prism_hi, axes.other_min)) || glm::any(glm::lessThan(axes.other_max, prism_lo))) continue;
      const Headroom h = headroom(axes, piece);
      if (h == Headroom::covered) return true;
      if (h == Headroom::blocked) {
        blockers.push_back(b);
        if (first_only) return false;
      }
    }
    return false;
  };
  // A triangle partly under an obstacle is split into four at its edge midpoints, again and
  // again, keeping the pieces with headroom, until pieces are smaller than
  // kHeadroomRefineFraction of the agent's height. Neighbours that were not split meet the
  // pieces at T-junctions, which build_walk_mesh splits so they link. Pieces are kept in world
  // coordinates in double, where midpoints of float corners are exact: a midpoint shared by two
  // pieces (of one level triangle or of two) becomes the same float vertex, and corners that are
  // level vertices keep their index, whatever the local origin's rounding.
  const double min_edge = static_cast<double>(kHeadroomRefineFraction * agent.height);
  constexpr std::uint32_t kNewVertex = 0xffffffffu;
  struct Piece {
    std::array<glm::dvec3, 3> corners;          // world coordinates
    std::array<std::uint32_t, 3> level_vertex;  // level vertex index of each corner, or kNewVertex
    int depth;
    std::size_t first_blocker, blocker_count;  // the parent's blockers in `blockers`
  };
  std::vector<Piece> pieces;
  for (std::uint32_t t = 0; t < level.triangles.size(); ++t) {
    const glm::uvec3 tri = level.triangles[t];
    // In double on world coordinates, like the headroom test: the same answer whatever the origin.
    const std::array<glm::dvec3, 3> base{world(tri.x), world(tri.y), world(tri.z)};
    const glm::dvec3 n = glm::cross(base[1] - base[0], base[2] - base[0]);
    const double len = glm::length(n);
    const double longest2 = std::max({glm::dot(base[1] - base[0], base[1] - base[0]),
                                      glm::dot(base[2] - base[1], base[2] - base[1]),
                                      glm::dot(base[0] - base[2], base[0] - base[2])});
    if (!(len > static_cast<double>(kWalkDegenerateTolerance) * longest2)) {  // no plane, so no slope: build_walk_mesh's test
      ++degenerate;
      continue;
    }
    if (std::fabs(glm::dot(n, glm::dvec3(up))) < static_cast<double>(cos_max_slope) * len) {
      ++too_steep;
      continue;
    }
    blockers.clear();
    blocker_axes.clear();
    if (agent.height > 0.0f && collect_blockers(t, base)) {
      ++low_headroom;
      continue;
    }
    if (blockers.empty()) {
      walkable.triangles.push_back(tri);
      continue;
    }
    bool dropped = false, split = false, kept_part = false;
    pieces.assign(1, {{world(tri.x), world(tri.y), world(tri.z)}, {tri.x, tri.y, tri.z}, 0, 0, blockers.size()});
    while (!pieces.empty()) {
      const Piece piece = pieces.back();
      pieces.pop_back();
      const auto& c = piece.corners;
      const double piece_longest2 = std::max({glm::dot(c[1] - c[0], c[1] - c[0]), glm::dot(c[2] - c[1], c[2] - c[1]),
                                              glm::dot(c[0] - c[2], c[0] - c[2])});
      // Blocked, it is dropped rather than split: deep enough, or small enough.
      const bool last = piece.depth >= kMaxHeadroomRefineDepth || !(piece_longest2 > min_edge * min_edge);
      std::size_t first = piece.first_blocker, count = piece.blocker_count;
      if (piece.depth > 0) {
        first = blockers.size();
        const bool covered = filter_blockers(piece.first_blocker, piece.blocker_count, c, last);
        count = blockers.size() - first;
        if (covered) {
          dropped = true;
          continue;
        }
      }
      if (count == 0) {
        glm::uvec3 kept;
        for (int k = 0; k < 3; ++k) {
          kept[k] = piece.level_vertex[k];
          if (kept[k] == kNewVertex) {
            kept[k] = static_cast<unsigned>(walkable.positions.size());
            walkable.positions.push_back(Vec3(c[k]));
          }
        }
        walkable.triangles.push_back(kept);
        kept_part = true;
        continue;
      }
      if (last) {
        dropped = true;
        continue;
      }
      split = true;
      const glm::dvec3 m01 = (c[0] + c[1]) * 0.5, m12 = (c[1] + c[2]) * 0.5, m20 = (c[2] + c[0]) * 0.5;
      const auto& v = piece.level_vertex;
      const int d = piece.depth + 1;
      pieces.push_back({{c[0], m01, m20}, {v[0], kNewVertex, kNewVertex}, d, first, count});
      pieces.push_back({{m01, c[1], m12}, {kNewVertex, v[1], kNewVertex}, d, first, count});
      pieces.push_back({{m20, m12, c[2]}, {kNewVertex, kNewVertex, v[2]}, d, first, count});
      pieces.push_back({{m01, m12, m20}, {kNewVertex, kNewVertex, kNewVertex}, d, first, count});
    }
    refined += split && kept_part ? 1 : 0;
    low_headroom += dropped ? 1 : 0;
  }
  if (walkable.triangles.empty()) {
    throw InvalidInput(name + ": no walkable triangles (" + std::to_string(too_steep) + " too steep, " +
                       std::to_string(degenerate) + " degenerate, " + std::to_string(low_headroom) +
                       " without headroom for the agent)");
  }
  WalkMesh mesh = build_walk_mesh(walkable, {up, kWalkWeldTolerance, scale});
  mesh.stats_.input_triangles = level.triangles.size();
  mesh.stats_.too_steep_triangles = too_steep;
  mesh.stats_.degenerate_triangles += degenerate;
  mesh.stats_.low_headroom_triangles = low_headroom;
  mesh.stats_.headroom_refined_triangles = refined;
  return mesh;
}

}  // namespace collide
