#pragma once
// What must hold for any numbers given to the shape constructors (fuzz_shapes, and the
// regression test that replays the inputs the fuzzer found): shared so both check the same.
//
// The bytes are read as a recipe: one byte picks the constructor, then its arguments follow as
// floats (FuzzFloats: small values, special ones such as NaN, infinities, the float limits and
// denormals, or any 4 raw bytes) and small counts.

#include "fuzz_check.hpp"

#include <collide/ccd/raycast.hpp>
#include <collide/ccd/shape_cast.hpp>
#include <collide/ccd/sweep.hpp>
#include <collide/ccd/time_of_impact.hpp>
#include <collide/core/error.hpp>
#include <collide/core/finite_range.hpp>
#include <collide/narrow/contact.hpp>
#include <collide/narrow/distance.hpp>
#include <collide/narrow/overlap.hpp>
#include <collide/shape/box.hpp>
#include <collide/shape/capsule.hpp>
#include <collide/shape/capsule3.hpp>
#include <collide/shape/circle.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/height_field.hpp>
#include <collide/shape/polygon.hpp>
#include <collide/shape/segment.hpp>
#include <collide/shape/segment3.hpp>
#include <collide/shape/sphere.hpp>
#include <collide/shape/triangle.hpp>
#include <collide/shape/triangle_bvh.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <glm/geometric.hpp>

#include <array>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace collide::fuzz {

/// Reads a fuzz input as numbers; past the end every read gives 0.
class FuzzFloats {
 public:
  explicit FuzzFloats(std::string_view bytes) : bytes_(bytes) {}

  std::uint8_t byte() { return pos_ < bytes_.size() ? static_cast<std::uint8_t>(bytes_[pos_++]) : 0; }

  /// A count in [lo, hi].
  int count(int lo, int hi) { return lo + byte() % (hi - lo + 1); }

  /// One float: a tag byte below 64 gives (tag - 32) / 4, below 96 a special value, else the
  /// next 4 bytes as they are (any float, NaN payloads and denormals included).
  float number() {
    const std::uint8_t tag = byte();
    if (tag < 64) return static_cast<float>(tag - 32) / 4.0f;
    if (tag < 96) {
      constexpr float kInf = std::numeric_limits<float>::infinity();
      constexpr float kSpecial[] = {0.0f, -0.0f, std::numeric_limits<float>::quiet_NaN(), kInf, -kInf,
                                    std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                                    std::numeric_limits<float>::min(), std::numeric_limits<float>::denorm_min(),
                                    -std::numeric_limits<float>::denorm_min(), 1e-30f, 1e-20f, 1e-7f, 1e7f, 1e10f,
                                    1e19f, -1e19f, 1e30f, 1e38f, -1e38f, 3e38f, 1.0f + 0x1p-23f, 0.5f, 1e-3f};
      return kSpecial[(tag - 64) % (sizeof kSpecial / sizeof kSpecial[0])];
    }
    std::uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits = bits << 8 | byte();
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }
  Vec2 vec2() { return {number(), number()}; }
  Vec3 vec3() { return {number(), number(), number()}; }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

inline bool finite(float x) { return std::isfinite(x); }

inline bool finite(Vec2 v) { return is_finite(v); }
inline bool finite(Vec3 v) { return is_finite(v); }

/// Equal floats, bit for bit, or both NaN (which NaN comes out of an operation with two may
/// differ between a scalar and a packed instruction).
inline bool same_float(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0;
}

/// "" when the batched polygon-circle contact gives every pair the single call's manifold: five
/// placements of `probe` around `polygon` (one group of four lanes, then the tail).
inline std::string check_contact_batch(const Polygon& polygon, const Circle& probe) {
  std::array<PolygonCirclePair, 5> pairs;
  const std::array<Vec2, 5> offsets{Vec2{0.0f, 0.0f}, Vec2{1.5f, 0.0f}, Vec2{-0.75f, 2.0f}, Vec2{0.0f, -1e4f},
                                    Vec2{1e-3f, 1e-3f}};
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    pairs[i] = {&polygon, Transform::from(Vec2{0.0f, 0.0f}, 0.3f * float(i)), &probe, Transform{offsets[i], Rot2{}}};
  }
  std::array<Manifold, 5> batch;
  contact(pairs, batch);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Manifold one = contact(polygon, pairs[i].polygon_xf, probe, pairs[i].circle_xf);
    const Manifold& m = batch[i];
    bool same = m.count == one.count && same_float(m.normal.x, one.normal.x) && same_float(m.normal.y, one.normal.y);
    for (int k = 0; same && k < one.count; ++k) {
      const ManifoldPoint& p = m.points[k];
      const ManifoldPoint& q = one.points[k];
      same = same_float(p.point.x, q.point.x) && same_float(p.point.y, q.point.y) && same_float(p.depth, q.depth) &&
             p.id == q.id;
    }
    if (!same) return "batched polygon-circle contact differs from the single call";
  }
  return {};
}

/// "" when a polygon and a probe box answer the pair queries consistently: the polygon's
/// distance to the box, warm-started from the cache its cold call wrote (the closest-feature
/// walk from the cached pair, or the cached triangle of an overlap), agrees with the cold call
/// (the same distance within a thousandth of the pair's size), their contact manifold is
/// finite with a unit normal, and the box's shape cast and times of impact at the polygon are
/// finite with fractions in [0, 1] (asked of polygons within kFiniteQueryRange; beyond it the
/// calls run for the sanitizers alone).
inline std::string check_polygon_against_box(const Polygon& shape) {
  const Polygon box = make_box({0.75f, 0.5f});
  const Transform xf{};
  const Transform at = Transform::from({0.5f, 0.25f}, 0.3f);
  SimplexCache cache;
  const DistanceResult cold = distance(shape, xf, box, at, &cache);
  const DistanceResult warm = distance(shape, xf, box, at, &cache);
  const Aabb bounds = compute_aabb(shape, xf);
  if (!within_finite_range(bounds)) return {};
  if (!finite(warm.distance) || !finite(warm.point_a) || !finite(warm.point_b) || !finite(warm.normal)) {
    return "warm-started polygon distance is not finite";
  }
  const Vec2 size = bounds.max - bounds.min;
  const float tolerance = 1e-3f * (2.0f + std::max(size.x, size.y));
  if (!(std::abs(warm.distance - cold.distance) <= tolerance)) {
    return "warm-started polygon distance differs from the cold call";
  }
  // The manifold against the same box: a unit normal and finite points when touching.
  const Manifold m = contact(shape, xf, box, at);
  if (m.count > 0 && !(finite(m.normal) && std::abs(length(m.normal) - 1.0f) <= 1e-3f)) {
    return "polygon-box contact normal is not a finite unit vector";
  }
  for (int i = 0; i < m.count; ++i) {
    if (!finite(m.points[i].point) || !finite(m.points[i].depth)) return "polygon-box contact point is not finite";
  }
  // The box swept at the polygon from 3 units away: a shape cast (the ray into A - B for sharp
  // polygons) and times of impact, translating (the same ray) and turning (GJK advancement).
  const Transform away = Transform::from({3.5f, 2.25f}, 0.3f);  // the box's start
  const Vec2 toward = at.p - away.p;
  const ShapeCastResult cast = shape_cast(shape, xf, Vec2{0.0f, 0.0f}, box, away, toward);
  if (!(cast.fraction >= 0.0f && cast.fraction <= 1.0f) || !finite(cast.point) || !finite(cast.normal)) {
    return "polygon-box shape cast is not finite or its fraction is outside [0, 1]";
  }
  const Sweep still = Sweep::from_motion(xf, Vec2{0.0f, 0.0f}, Vec2{0.0f, 0.0f}, 0.0f);
  for (const float turn : {0.0f, 2.0f}) {
    const Sweep sweep = Sweep::from_motion(away, Vec2{0.0f, 0.0f}, toward, turn);
    const ToiResult toi = time_of_impact(shape, still, box, sweep);
    if (!(toi.fraction >= 0.0f && toi.fraction <= 1.0f) || !finite(toi.separation) || !finite(toi.point) ||
        !finite(toi.normal)) {
      return "polygon-box time of impact is not finite or its fraction is outside [0, 1]";
    }
  }
  return {};
}

/// raycast_fraction's promise: raycast's hit and fraction, bit for bit (NaN bits included).
template <int D>
bool same_fraction(const RayFraction& f, const RayHitN<D>& h) {
  return f.hit == h.hit && std::bit_cast<std::uint32_t>(f.fraction) == std::bit_cast<std::uint32_t>(h.fraction);
}

/// "" when the queries of a built 2D shape against the fixed probes give finite answers (asked
/// of shapes within kFiniteQueryRange; beyond it the queries run for the sanitizers alone).
template <class S>
std::string probe2(const S& shape) {
  const Circle probe = make_circle({0.5f, 0.25f}, 1.0f);
  const Transform xf{};
  if constexpr (std::is_same_v<S, Polygon>) {
    if (std::string batch = check_contact_batch(shape, probe); !batch.empty()) return batch;
    if (std::string pair = check_polygon_against_box(shape); !pair.empty()) return pair;
  }
  (void)overlap(shape, xf, probe, xf);
  const DistanceResult d = distance(shape, xf, probe, xf);
  const Ray ray{{-100.0f, 0.1f}, {200.0f, 0.0f}};
  const RayHit hit = raycast(shape, xf, ray);
  if (!same_fraction(raycast_fraction(shape, xf, ray), hit)) return "raycast_fraction differs from raycast";
  if (!within_finite_range(compute_aabb(shape, xf))) return {};
  if (!finite(d.distance) || !finite(d.point_a) || !finite(d.point_b) || !finite(d.normal)) {
    return "distance to the probe circle is not finite";
  }
  if (hit.hit && (!finite(hit.fraction) || !finite(hit.point) || !finite(hit.normal))) return "ray cast is not finite";
  return {};
}

/// "" when the queries of a built convex 3D shape against the fixed probes give finite answers
/// (within kFiniteQueryRange, as probe2).
template <class S>
std::string probe3(const S& shape) {
  const Sphere probe = make_sphere({0.5f, 0.25f, -0.125f}, 1.0f);
  const Transform3 xf{};
  (void)overlap(shape, xf, probe, xf);
  const DistanceResult3 d = distance(shape, xf, probe, xf);
  const Ray3 ray{{-100.0f, 0.1f, 0.2f}, {200.0f, 0.0f, 0.0f}};
  const RayHit3 hit = raycast(shape, xf, ray);
  if constexpr (Shape3DType<S>) {  // (a Triangle has no raycast_fraction)
    if (!same_fraction(raycast_fraction(shape, xf, ray), hit)) return "raycast_fraction differs from raycast";
  }
  if (!within_finite_range(compute_aabb(shape, xf))) return {};
  if (!finite(d.distance) || !finite(d.point_a) || !finite(d.point_b) || !finite(d.normal)) {
    return "distance to the probe sphere is not finite";
  }
  if (hit.hit && (!finite(hit.fraction) || !finite(hit.point) || !finite(hit.normal))) return "ray cast is not finite";
  return {};
}

/// make_convex_hull's planes hold what convex_hull.hpp promises: every vertex behind every face
/// plane exactly (the offsets are the vertices' maximum, rounded up to float), and every input
/// point at most the tolerance above one when the vertex cap cannot have cut the build short (no
/// more points than the cap). Heights in double, as the build's final sweep takes them: float
/// products are exact there, so only the sums round, the same way in both. The tolerance is
/// stored as float: half a float ulp of slack for its rounding.
inline std::string check_hull_planes(const ConvexHull& hull, std::span<const Vec3> points, int max_vertices) {
  const double tolerance = static_cast<double>(hull.tolerance) * (1.0 + 0.5 * FLT_EPSILON);
  const bool uncapped = points.size() <= static_cast<std::size_t>(max_vertices);
  for (const HullFace& face : hull.faces) {
    const glm::dvec3 n(face.normal);
    const double offset = face.offset;
    for (const Vec3& v : hull.vertices) {
      if (glm::dot(n, glm::dvec3(v)) > offset) return "convex hull: a vertex lies above a face plane";
    }
    if (!uncapped) continue;
    for (const Vec3& p : points) {
      if (glm::dot(n, glm::dvec3(p)) - offset > tolerance) {
        return "convex hull: an input point lies more than the tolerance above a face plane";
      }
    }
  }
  return {};
}

/// check_mesh_nearest's allowance, in float spacings (FLT_EPSILON) of the largest coordinate:
/// each of the search's float steps (a corner's offset, a dot product, the winner's point and
/// its distance) rounds by a few, and a wrong winner costs at most its lane's error.
inline constexpr double kMeshNearestRounding = 64.0;

/// check_level_cast's rounding allowance, in kShapeCastRounding of the coordinates: the cast's
/// own steps and the probe's and its nearest point's float coordinates.
inline constexpr double kCastRoundingFactor = 8.0;

/// The name a level's messages start with.
inline std::string level_name(const TriangleMesh&) { return "triangle mesh"; }
inline std::string level_name(const HeightField&) { return "height field"; }

/// "" when `body` at `xf` (world space; the level, a TriangleMesh or a HeightField, stands at
/// the identity) touches the level: its contact is not empty, and finite, with a unit normal;
/// else what went wrong, naming the body by `what`. Asked of bodies known to reach past the
/// level's nearest triangle. Bodies whose bounds leave kFiniteQueryRange are not asked.
template <class Level, class Body>
std::string check_level_touch(const Level& level, const Body& body, const Transform3& xf, std::string_view what) {
  if (!within_finite_range(compute_aabb(body, xf))) return {};
  const Manifold3 m = contact(body, xf, level, Transform3{});
  const std::string name = level_name(level) + ": a " + std::string(what);
  if (m.count == 0) return name + " reaching past the nearest triangle has no contact";
  if (!finite(m.normal) || !(std::abs(length(m.normal) - 1.0f) <= 1e-3f)) return name + "'s contact normal is not unit";
  for (int i = 0; i < m.count; ++i) {
    if (!finite(m.points[i].point) || !finite(m.points[i].depth)) return name + "'s contact is not finite";
  }
  return {};
}

/// The probe bodies of the level checks, each holding the ball of radius `r` at `centre` (world
/// space): a sphere of that radius, and turned by a fixed rotation off the level's axes a capsule
/// (core 2r long, radius r), a box (half extents r, 1.25r, 1.5r) and a convex hull (the
/// octahedron of corners 2r out, whose faces lie 1.15r from its centre). Each is handed to
/// `ask(body, placement, name, bound)`, `bound` the radius of a ball about `centre` that holds
/// it; the first non-empty answer is returned. A body whose constructor refuses its size is
/// skipped.
template <class Ask>
std::string ask_probe_bodies(Vec3 centre, float r, Ask&& ask) {
  if (std::string e = ask(make_sphere(Vec3(0.0f), r), Transform3{centre, Quat{1, 0, 0, 0}}, "sphere", double(r)); !e.empty()) {
    return e;
  }
  const Transform3 turned{centre, glm::normalize(Quat{0.8f, 0.36f, -0.24f, 0.42f})};
  const auto made = [&](auto make, std::string_view what, double bound) -> std::string {
    try {
      return ask(make(), turned, what, bound);
    } catch (const InvalidInput&) {
      return {};
    }
  };
  if (std::string e = made([&] { return make_capsule(Vec3(0.0f, -r, 0.0f), Vec3(0.0f, r, 0.0f), r); }, "capsule", 2.0 * r);
      !e.empty()) {
    return e;
  }
  const Vec3 half(r, 1.25f * r, 1.5f * r);
  if (std::string e = made([&] { return make_box(half); }, "box", double(length(half))); !e.empty()) return e;
  return made(
      [&] {
        const float c = 2.0f * r;
        const std::array<Vec3, 6> corners{Vec3(c, 0, 0), Vec3(-c, 0, 0), Vec3(0, c, 0), Vec3(0, -c, 0), Vec3(0, 0, c), Vec3(0, 0, -c)};
        return make_convex_hull(corners);
      },
      "hull", 2.0 * r);
}

/// "" when every body of each kind that holds a ball at `centre` (world space; the level stands
/// at the identity) reaching `allowance` past the level's nearest distance `nearest` (found by
/// brute force) plus half of it touches the level (check_level_touch): ask_probe_bodies' sphere,
/// capsule, box and hull for that radius r. A contact the level query, its early out, the closed form
/// of a body against a triangle or the active-edge correction drops fails (stop 104: slivers'
/// planes made in float dropped contacts 0.05 deep; stop 105: a capsule behind a thin crease).
/// `offset` is the size of the coordinates the level rounds its own at (a mesh's origin).
template <class Level>
std::string check_level_contact(const Level& level, Vec3 centre, double nearest, double allowance, float offset) {
  if (!(max_abs(centre) <= kFiniteQueryRange)) return {};
  const auto r = static_cast<float>(1.5 * nearest + 4.0 * (allowance + FLT_EPSILON * double(offset)));
  if (!(r > 0.0f) || !finite(r)) return {};
  return ask_probe_bodies(centre, r, [&](const auto& body, const Transform3& xf, std::string_view what, double) {
    return check_level_touch(level, body, xf, what);
  });
}

/// "" when bodies cast at the level from `centre` (world space; the level at the identity),
/// `nearest` from its nearest point `target` (brute force), towards that point by twice that
/// distance, first touch it when the distance says: the distance to the level falls at most as
/// fast as the body moves, and along that line it falls exactly that fast. A sphere of radius
/// r = nearest / 4 must hit at fraction (nearest - r) / |v|; a capsule, a box and a hull each
/// holding that sphere and held in a ball of radius R (ask_probe_bodies': 2r, 2.14r, 2r)
/// between (nearest - R) / |v| and that. Within the cast's own
/// target separation (kShapeCastTolerance of the body's size) and rounding (kShapeCastRounding
/// of the coordinates, times kCastRoundingFactor) plus `allowance`; a cast that stopped short
/// of converging (max_iterations) must not have passed the latest touch. Probes nearer than 1000
/// allowances are skipped (their line is rounding).
template <class Level>
std::string check_level_cast(const Level& level, Vec3 centre, Vec3 target, double nearest, double allowance, float offset) {
  if (!(nearest > 1000.0 * allowance) || !(max_abs(centre) <= kFiniteQueryRange)) return {};
  const Vec3 v = 2.0f * (target - centre);
  const double length_v = glm::length(glm::dvec3(v));
  if (!(length_v > 0.0) || !std::isfinite(length_v)) return {};
  const auto r = static_cast<float>(0.25 * nearest);
  const double rounding = kCastRoundingFactor * double(kShapeCastRounding) *
                          (length_v + double(max_abs(centre)) + double(offset) + 3.0 * nearest);
  const std::string name = level_name(level) + ": a ";
  // Every body holds the sphere of radius r (inner) and lies within `outer` of the centre.
  const double inner = r;
  return ask_probe_bodies(centre, r, [&](const auto& body, const Transform3& xf, std::string_view what, double outer) -> std::string {
    if (!within_finite_range(compute_aabb(body, xf))) return {};
    const ShapeCastResult3 c = shape_cast(body, xf, v, level, Transform3{}, Vec3(0.0f));
    const double slack = (double(kShapeCastTolerance) * 4.0 * outer + rounding + allowance) / length_v;
    const double earliest = (nearest - outer) / length_v - slack, latest = (nearest - inner) / length_v + slack;
    // Stopped short of converging: the fraction reached, before which there is no contact (the
    // status' contract), must not pass the touch.
    if (c.status == QueryStatus::max_iterations) {
      if (!(std::isfinite(c.fraction) && c.fraction <= latest)) {
        return name + std::string(what) + " cast at the nearest triangle stopped past the touch";
      }
      return {};
    }
    if (!c.hit) return name + std::string(what) + " cast at the nearest triangle misses it";
    if (!std::isfinite(c.fraction) || !(c.fraction >= earliest && c.fraction <= latest)) {
      return name + std::string(what) + " cast at the nearest triangle touches it at the wrong time";
    }
    if (!finite(c.point) || !finite(c.normal)) return name + std::string(what) + "'s cast is not finite";
    if (!(std::abs(length(c.normal) - 1.0f) <= 1e-3f)) return name + std::string(what) + "'s cast normal is not unit";
    return {};
  });
}

/// Probe points about triangles (a, b, c): up to 24 triangles' corners, centroids, and points
/// beyond their edges and off their planes, added to `probes`.
inline void add_triangle_probes(Vec3 a, Vec3 b, Vec3 c, std::vector<Vec3>& probes) {
  const Vec3 centroid = (a + b + c) / 3.0f;
  const Vec3 up = cross(b - a, c - a);
  const float up_length = length(up);
  const Vec3 off = up_length > 0.0f ? up * (0.25f * length(b - a) / up_length) : Vec3(0.0f);
  probes.insert(probes.end(), {a, centroid, centroid + off, a + 1.25f * (b - a) + 0.5f * (c - b) - off,
                               centroid + 0.6f * (c - centroid) + off});
}

/// "" when bodies reaching past a height field's nearest triangle touch it, at probe points
/// about up to 24 of its triangles (add_triangle_probes), the nearest distance by brute force
/// over every triangle of a cell that is not a hole (closest_point_on_triangle, in double), with check_mesh_nearest's
/// allowance: check_level_contact (above the field and below it: the active edges are two-sided since
/// stop 107, finding 22), and
/// bodies cast at the nearest point touch it when the distance says (check_level_cast). Asked
/// of fields within kFiniteQueryRange.
inline std::string check_height_field_contact(const HeightField& field) {
  if (!within_finite_range(compute_aabb(field, Transform3{}))) return {};
  // Every triangle of a cell that is not a hole, read from the samples (not through the field's
  // own query, whose block culling is under test).
  std::vector<std::array<Vec3, 3>> triangles;
  for (std::uint32_t t = 0; t < field.triangle_count(); ++t) {
    if (!field.is_hole(t / 2)) triangles.push_back(field.triangle(t).vertices);
  }
  if (triangles.empty()) return {};
  float magnitude = 0.0f;
  for (const auto& t : triangles) {
    for (const Vec3& v : t) magnitude = std::max(magnitude, max_abs(v));
  }
  std::vector<Vec3> probes;
  const std::size_t step = triangles.size() / 24 + 1;
  for (std::size_t i = 0; i < triangles.size(); i += step) add_triangle_probes(triangles[i][0], triangles[i][1], triangles[i][2], probes);
  for (const Vec3& p : probes) {
    if (!(max_abs(p) <= kFiniteQueryRange)) continue;
    double truth = std::numeric_limits<double>::infinity();
    Vec3 nearest_point = p;
    for (const auto& t : triangles) {
      const Vec3 q = closest_point_on_triangle(p, t[0], t[1], t[2]).point;
      const double d = glm::length(glm::dvec3(q) - glm::dvec3(p));
      if (d < truth) truth = d, nearest_point = q;
    }
    const double allowance = kMeshNearestRounding * FLT_EPSILON * static_cast<double>(std::max(magnitude, max_abs(p))) + 1e-18;
    if (std::string touch = check_level_contact(field, p, truth, allowance, magnitude); !touch.empty()) return touch;
    if (std::string cast = check_level_cast(field, p, nearest_point, truth, allowance, magnitude); !cast.empty()) return cast;
  }
  return {};
}

/// "" when a triangle mesh's BVH gives each probe point the distance of its nearest triangle:
/// the least over every triangle of closest_point_on_triangle's distance (brute force), for one
/// point at a time and in a batch, to within kMeshNearestRounding float spacings of the largest
/// coordinate (the search's lanes and the winner's float distance round) or 1e-18 (squared
/// distances below about 1e-38 lose their bits in float). Probes, in the mesh's local
/// coordinates (the BVH's): up to 24 triangles' corners, centroids and points beyond their
/// edges and off their planes, and the origin. Asked of meshes within kFiniteQueryRange. At
/// each probe, each body holding a ball reaching past that distance must touch the mesh
/// (check_level_contact), and bodies cast at the nearest point must touch it when the distance
/// says (check_level_cast).
inline std::string check_mesh_nearest(const TriangleMesh& mesh) {
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  if (count == 0) return {};
  float magnitude = 0.0f;
  for (std::uint32_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) magnitude = std::max(magnitude, max_abs(mesh.corner(t, k)));
  }
  if (!(magnitude <= kFiniteQueryRange)) return {};
  std::vector<Vec3> probes{Vec3(0.0f)};
  const std::uint32_t step = count / 24 + 1;
  for (std::uint32_t t = 0; t < count; t += step) add_triangle_probes(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2), probes);
  std::vector<BvhNearest> batch(probes.size());
  mesh.bvh.nearest(probes, std::vector<float>(probes.size(), std::numeric_limits<float>::infinity()), batch);
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Vec3 p = probes[i];
    if (!(max_abs(p) <= kFiniteQueryRange)) continue;
    double truth = std::numeric_limits<double>::infinity();
    Vec3 nearest_point = p;
    for (std::uint32_t t = 0; t < count; ++t) {
      const Vec3 q = closest_point_on_triangle(p, mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)).point;
      const double d = glm::length(glm::dvec3(q) - glm::dvec3(p));
      if (d < truth) truth = d, nearest_point = q;
    }
    const double allowance =
        kMeshNearestRounding * FLT_EPSILON * static_cast<double>(std::max(magnitude, max_abs(p))) + 1e-18;
    for (const BvhNearest& hit : {mesh.bvh.nearest(p), batch[i]}) {
      if (hit.triangle >= count) return "triangle mesh: the BVH found no nearest triangle";
      if (!(std::abs(std::sqrt(static_cast<double>(hit.distance_squared)) - truth) <= allowance)) {
        return "triangle mesh: the BVH's nearest distance differs from the nearest triangle's";
      }
    }
    if (std::string touch = check_level_contact(mesh, mesh.origin + p, truth, allowance, max_abs(mesh.origin)); !touch.empty()) {
      return touch;
    }
    if (std::string cast = check_level_cast(mesh, mesh.origin + p, mesh.origin + nearest_point, truth, allowance, max_abs(mesh.origin));
        !cast.empty()) {
      return cast;
    }
  }
  return {};
}

/// The same for a mesh or height field (the probe first, as the overloads take them); a
/// distance beyond the 1000 bound is "none within it" (+infinity by contract).
template <class S>
std::string probe_level(const S& level) {
  const Sphere probe = make_sphere({0.5f, 0.25f, -0.125f}, 1.0f);
  const Transform3 xf{};
  (void)overlap(probe, xf, level, xf);
  const DistanceResult3 d = distance(probe, xf, level, xf, 1000.0f);
  const RayHit3 hit = raycast(level, xf, Ray3{{-100.0f, 0.1f, 0.2f}, {200.0f, 0.0f, 0.0f}});
  if (!within_finite_range(compute_aabb(level, xf))) return {};
  if (d.distance <= 1000.0f && (!finite(d.distance) || !finite(d.point_a) || !finite(d.point_b))) {
    return "distance to the probe sphere is not finite";
  }
  if (hit.hit && (!finite(hit.fraction) || !finite(hit.point) || !finite(hit.normal))) return "ray cast is not finite";
  return {};
}

/// "" when the constructor the recipe `input` names either throws InvalidInput with a non-empty
/// message or builds a shape whose queries against fixed probes (overlap, distance, ray cast)
/// give finite answers when its bounds lie within kFiniteQueryRange; else what went wrong. Shapes: 2D circle, capsule, segment, polygon
/// (hull of points and convex), box; 3D sphere, capsule, segment, box, triangle, convex hull of a
/// point cloud, triangle mesh, height field. Crashes and undefined behaviour are the sanitizers'.
inline std::string check_shapes(std::string_view input) {
  FuzzFloats in(input);
  const int kind = in.byte() % 14;
  try {
    switch (kind) {
      case 0: return probe2(make_circle(in.vec2(), in.number()));
      case 1: return probe2(make_capsule(in.vec2(), in.vec2(), in.number()));
      case 2: return probe2(make_segment(in.vec2(), in.vec2()));
      case 3:
      case 4: {
        std::vector<Vec2> points(static_cast<std::size_t>(in.count(0, kind == 3 ? 80 : kMaxPolygonVertices + 2)));
        for (Vec2& p : points) p = in.vec2();
        const float radius = in.number();
        return probe2(kind == 3 ? make_polygon(points, radius) : make_convex_polygon(points, radius));
      }
      case 5: {
        const Vec2 half = in.vec2(), centre = in.vec2();
        const float angle = in.number();
        return probe2(make_box(half, centre, angle, in.number()));
      }
      case 6: return probe3(make_sphere(in.vec3(), in.number()));
      case 7: return probe3(make_capsule(in.vec3(), in.vec3(), in.number()));
      case 8: return probe3(make_segment(in.vec3(), in.vec3()));
      case 9: return probe3(make_box(in.vec3(), in.number()));
      case 10: return probe3(make_triangle(in.vec3(), in.vec3(), in.vec3()));
      case 11: {
        std::vector<Vec3> points(static_cast<std::size_t>(in.count(0, 300)));
        for (Vec3& p : points) p = in.vec3();
        HullOptions options;
        options.radius = in.number();
        options.max_vertices = in.count(2, kMaxHullVertices + 2);
        const ConvexHull hull = make_convex_hull(points, options);
        if (std::string planes = check_hull_planes(hull, points, options.max_vertices); !planes.empty()) return planes;
        return probe3(hull);
      }
      case 12: {
        std::vector<Vec3> vertices(static_cast<std::size_t>(in.count(0, 40)));
        for (Vec3& v : vertices) v = in.vec3();
        std::vector<glm::uvec3> triangles(static_cast<std::size_t>(in.count(0, 60)));
        for (glm::uvec3& t : triangles) t = {in.byte() % 48u, in.byte() % 48u, in.byte() % 48u};
        const TriangleMesh mesh = make_triangle_mesh(vertices, triangles);
        if (std::string nearest = check_mesh_nearest(mesh); !nearest.empty()) return nearest;
        return probe_level(mesh);
      }
      default: {
        const int sx = in.count(0, 10), sz = in.count(0, 10);
        std::vector<float> heights(static_cast<std::size_t>(in.count(0, 1) == 0 ? sx * sz : in.count(0, 120)));
        for (float& h : heights) h = in.number();
        const Vec2 spacing = in.vec2();
        const Vec3 origin = in.vec3();
        std::vector<std::uint8_t> holes;
        if (in.count(0, 1) == 1 && sx > 1 && sz > 1) {
          holes.resize(static_cast<std::size_t>((sx - 1) * (sz - 1)));
          for (std::uint8_t& h : holes) h = in.byte() % 2;
        }
        const HeightField field = make_height_field(sx, sz, heights, spacing, origin, holes);
        if (std::string touch = check_height_field_contact(field); !touch.empty()) return touch;
        return probe_level(field);
      }
    }
  } catch (const InvalidInput& e) {
    if (std::string(e.what()).empty()) return "InvalidInput with an empty message (constructor " + std::to_string(kind) + ")";
    return {};
  } catch (const std::exception& e) {
    return "constructor " + std::to_string(kind) + " threw other than InvalidInput: " + e.what();
  }
}

}  // namespace collide::fuzz
