// Queries on distance fields: sampling, the one-read inside test, closest points, contacts by
// surface samples, sphere tracing, soft shadows and particles (distance_field.hpp).

#include <collide/sdf/distance_field.hpp>

#include <collide/broad/broad_phase.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <variant>

namespace collide {
namespace {

template <int D>
using IVec = glm::vec<D, int>;


// ---- sparse ---------------------------------------------------------------------------------

template <int D>
constexpr std::size_t kBrickNodes = D == 2 ? kFieldBrickSize * kFieldBrickSize
                                           : kFieldBrickSize * kFieldBrickSize * kFieldBrickSize;
constexpr int kBrickShift = 3;  // log2(kFieldBrickSize)
static_assert((1 << kBrickShift) == kFieldBrickSize);

template <int D>
std::size_t region_index(const SparseDistanceFieldN<D>& field, IVec<D> r) noexcept {
  std::size_t at = static_cast<std::size_t>(r[D - 1]);
  for (int k = D - 2; k >= 0; --k) at = at * static_cast<std::size_t>(field.bricks_per_axis[k]) + static_cast<std::size_t>(r[k]);
  return at;
}

template <int D>
std::size_t local_index(IVec<D> l) noexcept {
  std::size_t at = static_cast<std::size_t>(l[D - 1]);
  for (int k = D - 2; k >= 0; --k) at = at * kFieldBrickSize + static_cast<std::size_t>(l[k]);
  return at;
}

// ---- contacts -------------------------------------------------------------------------------

/// Most surface samples a contact takes of one shape (spacing grows beyond it).
constexpr int kMaxContactSamples = 256;

/// step_particles asks for the node of the particle this many places on before it needs it
/// (about the reads a core keeps in flight, ~ memory latency / time per particle).
constexpr std::size_t kParticlePrefetchAhead = 64;

/// A hint to bring the cache line at `address` in (and its page's translation); nothing where the
/// compiler has no such hint.
inline void prefetch(const void* address) noexcept {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(address);
#else
  (void)address;
#endif
}

/// A sample of a shape's surface: a core point and the radius around it.
template <int D>
struct SurfaceSample {
  VecN<D> point{0.0f};
  float radius = 0.0f;
};

template <int D>
struct SampleList {
  std::array<SurfaceSample<D>, kMaxContactSamples> items;
  int count = 0;
  void add(VecN<D> p, float r) noexcept {
    if (count < kMaxContactSamples) items[count++] = {p, r};
  }
  /// The two ends and points between them at most `spacing` apart (the ends excluded when
  /// `ends` is false), within the samples left.
  void add_segment(VecN<D> a, VecN<D> b, float r, float spacing, bool ends) noexcept {
    const float length = glm::length(b - a);
    const int room = std::max(1, (kMaxContactSamples - count) / 2);
    const int pieces = std::clamp(static_cast<int>(std::ceil(length / spacing)), 1, room);
    for (int i = ends ? 0 : 1; i <= (ends ? pieces : pieces - 1); ++i)
      add(a + (b - a) * (float(i) / float(pieces)), r);
  }
};

SampleList<2> surface_samples(const Shape2D& shape, const Transform& xf, float spacing) noexcept {
  SampleList<2> out;
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Circle>) {
          out.add(transform_point(xf, s.center), s.radius);
        } else if constexpr (std::is_same_v<S, Capsule>) {
          out.add_segment(transform_point(xf, s.a), transform_point(xf, s.b), s.radius, spacing, true);
        } else if constexpr (std::is_same_v<S, Segment>) {
          out.add_segment(transform_point(xf, s.a), transform_point(xf, s.b), 0.0f, spacing, true);
        } else {
          for (int i = 0; i < s.count; ++i) out.add(transform_point(xf, s.vertices[i]), s.radius);
          for (int i = 0; i < s.count; ++i)
            out.add_segment(transform_point(xf, s.vertices[i]), transform_point(xf, s.vertices[(i + 1) % s.count]),
                            s.radius, spacing, false);
        }
      },
      shape);
  return out;
}

SampleList<3> surface_samples(const Shape3D& shape, const Transform3& xf, float spacing) noexcept {
  SampleList<3> out;
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Sphere>) {
          out.add(transform_point(xf, s.center), s.radius);
        } else if constexpr (std::is_same_v<S, Capsule3>) {
          out.add_segment(transform_point(xf, s.a), transform_point(xf, s.b), s.radius, spacing, true);
        } else if constexpr (std::is_same_v<S, Segment3>) {
          out.add_segment(transform_point(xf, s.a), transform_point(xf, s.b), 0.0f, spacing, true);
        } else if constexpr (std::is_same_v<S, Box>) {
          for (int i = 0; i < 8; ++i) out.add(transform_point(xf, s.vertex(i)), s.radius);
          for (int i = 0; i < 8; ++i)
            for (int k = 0; k < 3; ++k)
              if (!(i & (1 << k)))
                out.add_segment(transform_point(xf, s.vertex(i)), transform_point(xf, s.vertex(i | (1 << k))),
                                s.radius, spacing, false);
        } else {
          for (const Vec3& v : s.vertices) out.add(transform_point(xf, v), s.radius);
          for (const HullEdge& e : s.edges)
            out.add_segment(transform_point(xf, s.vertices[e.v0]), transform_point(xf, s.vertices[e.v1]), s.radius,
                            spacing, false);
        }
      },
      shape);
  return out;
}

/// The manifold of the touching samples: deepest first, then each next the farthest from those
/// kept; the normal is the deepest sample's.
template <int D, class F>
ManifoldN<D> samples_contact(const SampleList<D>& samples, const F& field) noexcept {
  struct Touch {
    VecN<D> surface;  // A's surface point nearest the solid
    VecN<D> normal;
    float depth;
    int index;
  };
  std::array<Touch, kMaxContactSamples> touching;
  int count = 0;
  for (int i = 0; i < samples.count; ++i) {
    VecN<D> g;
    const float value = field.sample(samples.items[i].point, g);
    if constexpr (requires { field.band_distance; }) {
      if (value >= field.band_distance) continue;  // beyond a sparse field's band: how far is unknown
    }
    const float d = value - samples.items[i].radius;
    const float length = glm::length(g);
    if (!(d <= 0.0f) || !(length > 0.0f)) continue;
    const VecN<D> normal = -g / length;  // from the shape into the solid
    touching[count++] = {samples.items[i].point + samples.items[i].radius * normal, normal, -d, i};
  }
  ManifoldN<D> m;
  if (count == 0) return m;
  int deepest = 0;
  for (int i = 1; i < count; ++i)
    if (touching[i].depth > touching[deepest].depth) deepest = i;
  m.normal = touching[deepest].normal;
  std::array<int, kMaxManifoldPoints<D>> kept{};
  kept[0] = deepest;
  int kept_count = 1;
  while (kept_count < kMaxManifoldPoints<D>) {
    int best = -1;
    float best_distance = 0.0f;
    for (int i = 0; i < count; ++i) {
      float nearest = std::numeric_limits<float>::infinity();
      for (int j = 0; j < kept_count; ++j) {
        const VecN<D> d = touching[i].surface - touching[kept[j]].surface;
        nearest = std::min(nearest, glm::dot(d, d));
      }
      if (nearest > best_distance) {
        best_distance = nearest;
        best = i;
      }
    }
    if (best < 0) break;
    kept[kept_count++] = best;
  }
  for (int j = 0; j < kept_count; ++j) {
    const Touch& t = touching[kept[j]];
    ManifoldPointN<D>& point = m.points[m.count++];
    point.depth = t.depth;
    point.point = t.surface - 0.5f * t.depth * t.normal;
    point.id = {static_cast<std::uint32_t>(t.index), 0, FeatureType::vertex, FeatureType::face};
  }
  return m;
}

template <int D, class F>
PointQueryN<D> gradient_closest(const F& field, VecN<D> p, int steps) noexcept {
  PointQueryN<D> out;
  out.distance = field.sample(p);
  out.inside = out.distance < 0.0f;
  VecN<D> q = p;
  for (int i = 0; i < steps; ++i) {
    VecN<D> g;
    const float d = field.sample(q, g);
    const float length = glm::length(g);
    if (!(length > 0.0f)) break;
    q -= d * g / length;
  }
  out.closest = q;
  out.feature = {FeatureType::face, 0};
  return out;
}

template <int D>
PointQueryN<D> stored_closest(const DistanceFieldN<D>& field, VecN<D> p) noexcept {
  if (field.closest_points.empty()) return gradient_closest<D>(field, p, 2);
  const FieldCellN<D> at = field.grid.locate(p);
  PointQueryN<D> out;
  float best = std::numeric_limits<float>::infinity();
  for (int c = 0; c < (1 << D); ++c) {
    IVec<D> i = at.node;
    for (int k = 0; k < D; ++k) i[k] += (c >> k) & 1;
    const VecN<D> candidate = field.closest_points[field.grid.index(i)];
    const VecN<D> d = candidate - p;
    const float d2 = glm::dot(d, d);
    if (d2 < best) {
      best = d2;
      out.closest = candidate;
    }
  }
  out.inside = field.sample(p) < 0.0f;
  out.distance = out.inside ? -std::sqrt(best) : std::sqrt(best);
  out.feature = {FeatureType::face, 0};
  return out;
}

}  // namespace

// ---- members ---------------------------------------------------------------------------------

template <int D>
float SparseDistanceFieldN<D>::node_value(IVec<D> i) const noexcept {
  const std::uint32_t brick = table[region_index(*this, i >> kBrickShift)];
  if (brick == kNoBrick) return band_distance;
  if (brick == kNoBrickInside) return -band_distance;
  return bricks[brick * kBrickNodes<D> + local_index<D>(i & (kFieldBrickSize - 1))];
}
template <int D>
void SparseDistanceFieldN<D>::cell_values(IVec<D> i, float (&v)[1 << D]) const noexcept {
  const IVec<D> local = i & (kFieldBrickSize - 1);
  bool one_brick = true;
  for (int k = 0; k < D; ++k) one_brick &= local[k] < kFieldBrickSize - 1;
  if (!one_brick) {
    for (int c = 0; c < (1 << D); ++c) {
      IVec<D> corner = i;
      for (int k = 0; k < D; ++k) corner[k] += (c >> k) & 1;
      v[c] = node_value(corner);
    }
    return;
  }
  // All corners in one region: one table read, then the brick (or the region's value).
  const std::uint32_t brick = table[region_index(*this, i >> kBrickShift)];
  if (brick >= kNoBrickInside) {
    const float value = brick == kNoBrick ? band_distance : -band_distance;
    for (float& x : v) x = value;
    return;
  }
  const float* d = bricks.data() + brick * kBrickNodes<D> + local_index<D>(local);
  v[0] = d[0];
  v[1] = d[1];
  v[2] = d[kFieldBrickSize];
  v[3] = d[kFieldBrickSize + 1];
  if constexpr (D == 3) {
    constexpr int kLayer = kFieldBrickSize * kFieldBrickSize;
    v[4] = d[kLayer];
    v[5] = d[kLayer + 1];
    v[6] = d[kLayer + kFieldBrickSize];
    v[7] = d[kLayer + kFieldBrickSize + 1];
  }
}
template <int D>
float SparseDistanceFieldN<D>::sample(VecN<D> p) const noexcept { return sample_cells(*this, p, nullptr); }
template <int D>
float SparseDistanceFieldN<D>::sample(VecN<D> p, VecN<D>& gradient_out) const noexcept {
  return sample_cells(*this, p, &gradient_out);
}
template <int D>
VecN<D> SparseDistanceFieldN<D>::gradient(VecN<D> p) const noexcept {
  VecN<D> g;
  (void)sample(p, g);
  return g;
}
template <int D>
bool SparseDistanceFieldN<D>::is_inside(VecN<D> p) const noexcept {
  IVec<D> i;
  return grid.nearest_node(p, i) && node_value(i) < 0.0f;
}
template <int D>
float SparseDistanceFieldN<D>::nearest_value(VecN<D> p) const noexcept {
  IVec<D> i;
  return grid.nearest_node(p, i) ? node_value(i) : std::numeric_limits<float>::infinity();
}

template struct DistanceFieldN<2>;
template struct DistanceFieldN<3>;
template struct SparseDistanceFieldN<2>;
template struct SparseDistanceFieldN<3>;

// ---- free functions --------------------------------------------------------------------------

PointQuery closest_point(const DistanceField& field, Vec2 p) noexcept { return stored_closest<2>(field, p); }
PointQuery3 closest_point(const DistanceField3& field, Vec3 p) noexcept { return stored_closest<3>(field, p); }
PointQuery closest_point_by_gradient(const DistanceField& field, Vec2 p, int steps) noexcept {
  return gradient_closest<2>(field, p, steps);
}
PointQuery3 closest_point_by_gradient(const DistanceField3& field, Vec3 p, int steps) noexcept {
  return gradient_closest<3>(field, p, steps);
}

template <DistanceFieldType F>
ManifoldN<F::kDim> contact(VecN<F::kDim> p, const F& field) noexcept {
  SampleList<F::kDim> one;
  one.add(p, 0.0f);
  return samples_contact<F::kDim>(one, field);
}

template <DistanceFieldType F>
  requires(F::kDim == 2)
Manifold contact(const Shape2D& shape, const Transform& xf, const F& field) noexcept {
  return samples_contact<2>(surface_samples(shape, xf, field.grid.voxel), field);
}

template <DistanceFieldType F>
  requires(F::kDim == 3)
Manifold3 contact(const Shape3D& shape, const Transform3& xf, const F& field) noexcept {
  return samples_contact<3>(surface_samples(shape, xf, field.grid.voxel), field);
}

template <DistanceFieldType F>
RayHitN<F::kDim> raymarch(const F& field, const RayN<F::kDim>& ray) noexcept {
  constexpr int D = F::kDim;
  RayHitN<D> hit;
  const float length = glm::length(ray.translation);
  if (!(length > 0.0f) || !std::isfinite(length)) return hit;
  const VecN<D> direction = ray.translation / length;
  const float epsilon = kRaymarchHitVoxels * field.grid.voxel;
  // The march starts where the ray enters the grid's box: beyond it the sample is an upper
  // bound of the distance, not a safe step (it would cut past the solid's corners).
  const float enter = ray_box_fraction(ray, field.grid.bounds(), 1.0f);
  if (enter < 0.0f) return hit;
  float t = enter * length, t_before = t;
  for (int step = 0; step < kRaymarchMaxSteps && t <= length; ++step) {
    VecN<D> p = ray.origin + t * direction;
    VecN<D> g;
    float d = field.sample(p, g);
    if (!std::isfinite(d)) return hit;
    if (d < epsilon) {
      if (step == 0 && d < 0.0f) return hit;  // starts inside
      // The interpolated field is not exactly 1-Lipschitz: a step may overshoot into the solid.
      // Then bisect between the last point outside and this one for the zero crossing.
      for (int i = 0; i < kRaymarchBisections && d < -epsilon; ++i) {
        const float mid = 0.5f * (t_before + t);
        const float dm = field.sample(ray.origin + mid * direction, g);
        if (dm < 0.0f) t = mid;
        else t_before = mid;
        p = ray.origin + t * direction;
        d = field.sample(p, g);
      }
      if (t > length) return hit;
      const float gl = glm::length(g);
      hit.hit = true;
      hit.fraction = std::min(t / length, 1.0f);
      hit.point = p;
      hit.normal = gl > 0.0f ? g / gl : -direction;
      return hit;
    }
    t_before = t;
    t += d;
  }
  return hit;
}

template <DistanceFieldType F>
float soft_shadow(const F& field, const RayN<F::kDim>& ray, float sharpness) noexcept {
  constexpr int D = F::kDim;
  const float length = glm::length(ray.translation);
  if (!(length > 0.0f) || !std::isfinite(length)) return 1.0f;
  const VecN<D> direction = ray.translation / length;
  const float epsilon = kRaymarchHitVoxels * field.grid.voxel;
  float light = 1.0f;
  float t = 2.0f * epsilon;  // leave the surface the ray starts on
  for (int step = 0; step < kRaymarchMaxSteps && t < length; ++step) {
    const float d = field.sample(ray.origin + t * direction);
    if (!(d >= epsilon)) return 0.0f;
    light = std::min(light, sharpness * d / t);
    t += d;
  }
  return std::clamp(light, 0.0f, 1.0f);
}

template <DistanceFieldType F>
ParticleStepStats step_particles(const F& field, ParticlesN<F::kDim>& particles, float dt, float restitution) noexcept {
  constexpr int D = F::kDim;
  ParticleStepStats stats;
  // The field changes by at most about a voxel diagonal between a point and its nearest node.
  const float clear = field.grid.voxel * std::sqrt(float(D));
  const std::size_t n = std::min(particles.positions.size(), particles.velocities.size());
  VecN<D>* position = particles.positions.data();
  VecN<D>* velocity = particles.velocities.data();
  // A copy of the grid: the stores to the particles (floats) could alias the field's own, so the
  // loop would reload it (and divide by the voxel) at every particle.
  const FieldGridN<D> grid = field.grid;
  // Each particle's next position and node are worked out kParticlePrefetchAhead particles
  // before its turn, and its node asked for then; half way there, the node (arrived by then)
  // tells whether the particle is near the solid, and a near particle's cell is asked for.
  // Particles sit anywhere, so each read misses the caches (and the TLB) and would otherwise
  // wait alone.
  struct Ahead {
    VecN<D> p;
    glm::vec<D, int> node;
    bool in;   ///< p within half a voxel of the grid: `node` is its nearest node
    bool far;  ///< the nearest node is farther out than `clear`: nothing to do
  };
  constexpr std::size_t kAhead = kParticlePrefetchAhead, kHalf = kAhead / 2, kMask = kAhead - 1;
  static_assert((kAhead & kMask) == 0, "a power of two");
  Ahead ring[kAhead];
  const auto plan = [&](std::size_t j) noexcept {
    Ahead& a = ring[j & kMask];
    a.p = position[j] + velocity[j] * dt;
    a.in = grid.nearest_node(a.p, a.node);
    if constexpr (requires { field.distances; }) {
      if (a.in) prefetch(field.distances.data() + grid.index(a.node));
    }
  };
  const auto check = [&](std::size_t j) noexcept {
    Ahead& a = ring[j & kMask];
    a.far = a.in && field.node_value(a.node) > clear;
    if constexpr (requires { field.distances; }) {
      if (a.far || !a.in) return;
      const float* d = field.distances.data() + grid.index(grid.locate(a.p).node);
      const auto nx = static_cast<std::size_t>(grid.dims[0]);
      prefetch(d);
      prefetch(d + nx + 1);
      if constexpr (D == 3) {
        const std::size_t nxy = nx * static_cast<std::size_t>(grid.dims[1]);
        prefetch(d + nxy);
        prefetch(d + nxy + nx + 1);
      }
    }
  };
  for (std::size_t j = 0; j < std::min(n, kAhead); ++j) plan(j);
  for (std::size_t j = 0; j < std::min(n, kHalf); ++j) check(j);
  for (std::size_t i = 0; i < n; ++i) {
    const Ahead a = ring[i & kMask];
    if (i + kAhead < n) plan(i + kAhead);
    if (i + kHalf < n) check(i + kHalf);
    const VecN<D> p = a.p;
    position[i] = p;
    if (a.far) continue;  // the one read: far from the solid
    ++stats.near;
    VecN<D> g;
    const float d = field.sample(p, g);
    const float gl = glm::length(g);
    if (!(d < 0.0f) || !(gl > 0.0f)) continue;
    const VecN<D> normal = g / gl;
    position[i] = p - d * normal;
    const float vn = glm::dot(velocity[i], normal);
    if (vn < 0.0f) velocity[i] -= (1.0f + restitution) * vn * normal;
    ++stats.bounced;
  }
  return stats;
}

#define COLLIDE_FIELD_QUERIES(F)                                                                  \
  template ManifoldN<F::kDim> contact<F>(VecN<F::kDim>, const F&) noexcept;                       \
  template RayHitN<F::kDim> raymarch<F>(const F&, const RayN<F::kDim>&) noexcept;                 \
  template float soft_shadow<F>(const F&, const RayN<F::kDim>&, float) noexcept;                  \
  template ParticleStepStats step_particles<F>(const F&, ParticlesN<F::kDim>&, float, float) noexcept;
COLLIDE_FIELD_QUERIES(DistanceField)
COLLIDE_FIELD_QUERIES(DistanceField3)
COLLIDE_FIELD_QUERIES(SparseDistanceField)
COLLIDE_FIELD_QUERIES(SparseDistanceField3)
#undef COLLIDE_FIELD_QUERIES
template Manifold contact<DistanceField>(const Shape2D&, const Transform&, const DistanceField&) noexcept;
template Manifold contact<SparseDistanceField>(const Shape2D&, const Transform&, const SparseDistanceField&) noexcept;
template Manifold3 contact<DistanceField3>(const Shape3D&, const Transform3&, const DistanceField3&) noexcept;
template Manifold3 contact<SparseDistanceField3>(const Shape3D&, const Transform3&, const SparseDistanceField3&) noexcept;

}  // namespace collide
