// Queries on distance fields: sampling, the one-read inside test, closest points, contacts by
// surface samples, sphere tracing, soft shadows and particles (distance_field.hpp).

#include <collide/sdf/distance_field.hpp>

#include <collide/broad/broad_phase.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <type_traits>
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

/// step_particles works through the particles this many at a time: every node of a chunk is
/// asked for before the first is read, so the reads overlap (a core keeps about 20 misses in
/// flight; a chunk takes longer to locate than one miss takes to arrive), and the chunk's
/// scratch (about 7 KiB in 3D) stays on the stack and in L1.
constexpr std::size_t kParticleChunk = 256;

/// sample(field, points, out) on a dense 3D field locates this many points, asking for their
/// cells, before it reads the first (as step_particles' chunks): a multiple of 4.
constexpr std::size_t kSampleChunk = 64;

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

/// step_particles' scratch for one chunk of particles (see there), on the stack.
template <int D>
struct ParticleChunk {
  std::array<IVec<D>, kParticleChunk> node;         ///< nearest node (the scalar pass)
  std::array<std::uint32_t, kParticleChunk> index;  ///< its key (the lane pass; 0 when out):
                                                    ///< dense, the node's memory index;
                                                    ///< sparse, its brick region's index
  std::array<std::uint32_t, kParticleChunk> local;  ///< sparse: the node's place in its brick
  std::array<std::uint8_t, kParticleChunk> in;      ///< within half a voxel of the grid
};

/// Pass 1, one particle at a time (fields whose keys need more than 32 bits, and machines
/// without SSE2): each particle moved, its nearest node found and, for a dense field, asked for.
template <DistanceFieldType F>
void move_and_locate(const F& field, const FieldGridN<F::kDim>& grid, VecN<F::kDim>* position,
                     const VecN<F::kDim>* velocity, float dt, std::size_t first, std::size_t count,
                     ParticleChunk<F::kDim>& chunk) noexcept {
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t i = first + j;
    const VecN<F::kDim> p = position[i] + velocity[i] * dt;
    position[i] = p;
    chunk.in[j] = grid.nearest_node(p, chunk.node[j]);
    if constexpr (requires { field.distances; }) {
      if (chunk.in[j]) prefetch(field.distances.data() + grid.index(chunk.node[j]));
    }
  }
}

#if defined(__SSE2__) || defined(_M_X64)
/// `v * s` in every 32-bit lane (the low 32 bits of the product), SSE2 (which has no 32-bit
/// lane multiply): the even lanes, then the odd ones, through the 64-bit multiply.
inline __m128i mul_lanes(__m128i v, __m128i s) noexcept {
  const __m128i even = _mm_mul_epu32(v, s);
  const __m128i odd = _mm_mul_epu32(_mm_srli_epi64(v, 32), s);
  return _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                            _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
}

/// x + dims.x * (y + dims.y * z) in every lane (FieldGridN::index's order), 32 bits.
template <int D>
__m128i row_major(const __m128i (&i)[D], glm::vec<D, int> dims) noexcept {
  __m128i at = i[D - 1];
  for (int k = D - 2; k >= 0; --k) at = _mm_add_epi32(mul_lanes(at, _mm_set1_epi32(dims[k])), i[k]);
  return at;
}

/// Four points' packed floats (D registers: x0 y0 x1 y1 | x2 y2 x3 y3 in 2D, x0 y0 z0 x1 |
/// y1 z1 x2 y2 | z2 x3 y3 z3 in 3D) as one register per axis, a point per lane.
template <int D>
COLLIDE_ALWAYS_INLINE void to_lanes(const __m128 (&r)[D], __m128 (&axis)[D]) noexcept {
  if constexpr (D == 2) {
    axis[0] = _mm_shuffle_ps(r[0], r[1], _MM_SHUFFLE(2, 0, 2, 0));
    axis[1] = _mm_shuffle_ps(r[0], r[1], _MM_SHUFFLE(3, 1, 3, 1));
  } else {
    const __m128 x23 = _mm_shuffle_ps(r[1], r[2], _MM_SHUFFLE(1, 1, 2, 2));  // x2 x2 x3 x3
    axis[0] = _mm_shuffle_ps(r[0], x23, _MM_SHUFFLE(2, 0, 3, 0));
    const __m128 y01 = _mm_shuffle_ps(r[0], r[1], _MM_SHUFFLE(0, 0, 1, 1));  // y0 y0 y1 y1
    const __m128 y23 = _mm_shuffle_ps(r[1], r[2], _MM_SHUFFLE(2, 2, 3, 3));  // y2 y2 y3 y3
    axis[1] = _mm_shuffle_ps(y01, y23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 z01 = _mm_shuffle_ps(r[0], r[1], _MM_SHUFFLE(1, 1, 2, 2));  // z0 z0 z1 z1
    const __m128 z23 = _mm_shuffle_ps(r[2], r[2], _MM_SHUFFLE(3, 3, 0, 0));  // z2 z2 z3 z3
    axis[2] = _mm_shuffle_ps(z01, z23, _MM_SHUFFLE(2, 0, 2, 0));
  }
}

/// Pass 1 four particles at a time in SSE2 lanes: the positions moved as packed floats (the
/// same float operations as VecN's p + v * dt), transposed to x, y (and z) lanes, and the
/// nearest nodes found with FieldGridN::nearest_node's float operations (so the same nodes);
/// then `keys(j, node, in)` stores the four particles' keys from the node lanes and the
/// inside mask. The last count % 4 particles go through the lanes from a padded copy.
template <int D, class Keys>
void move_and_locate_lanes(const FieldGridN<D>& grid, VecN<D>* position, const VecN<D>* velocity,
                           float dt, std::size_t first, std::size_t count, ParticleChunk<D>& chunk,
                           Keys&& keys) noexcept {
  // The particle arrays are read and written as packed floats (glm's vectors hold D floats and
  // nothing else, as glm::value_ptr relies on).
  static_assert(sizeof(VecN<D>) == D * sizeof(float), "particles packed as floats");
  const __m128 step = _mm_set1_ps(dt);
  const __m128 inv = _mm_set1_ps(1.0f / grid.voxel);
  const __m128 half = _mm_set1_ps(0.5f);
  const __m128 zero = _mm_setzero_ps();
  __m128 origin[D], size[D];
  for (int k = 0; k < D; ++k) {
    origin[k] = _mm_set1_ps(grid.origin[k]);
    size[k] = _mm_set1_ps(float(grid.dims[k]));
  }
  const auto four = [&](std::size_t j, float* p, const float* v) {
    __m128 r[D];  // four particles' packed floats, moved and stored back
    for (int k = 0; k < D; ++k) {
      r[k] = _mm_add_ps(_mm_loadu_ps(p + 4 * k), _mm_mul_ps(_mm_loadu_ps(v + 4 * k), step));
      _mm_storeu_ps(p + 4 * k, r[k]);
    }
    __m128 axis[D];  // x, y (, z) of the four particles
    to_lanes<D>(r, axis);
    __m128 in = _mm_castsi128_ps(_mm_set1_epi32(-1));
    __m128i node[D];
    for (int k = 0; k < D; ++k) {
      const __m128 u = _mm_add_ps(_mm_mul_ps(_mm_sub_ps(axis[k], origin[k]), inv), half);
      in = _mm_and_ps(in, _mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmplt_ps(u, size[k])));
      node[k] = _mm_cvttps_epi32(u);  // u >= 0 where it counts: the floor
    }
    const int inside = _mm_movemask_ps(in);
    for (int l = 0; l < 4; ++l) chunk.in[j + l] = static_cast<std::uint8_t>((inside >> l) & 1);
    keys(j, node, _mm_castps_si128(in));
  };
  std::size_t j = 0;
  for (; j + 4 <= count; j += 4) four(j, &position[first + j].x, &velocity[first + j].x);
  if (j < count) {  // the last one to three: padded with zeros, moved, copied back
    float p[4 * D] = {}, v[4 * D] = {};
    const std::size_t rest = count - j;
    std::copy_n(&position[first + j].x, rest * D, p);
    std::copy_n(&velocity[first + j].x, rest * D, v);
    four(j, p, v);
    std::copy_n(p, rest * D, &position[first + j].x);
  }
}
#endif

/// Pass 2: the particles of the chunk whose nearest node is not farther out than `clear`, or
/// that lie outside the grid, into `list` (places in the chunk); returns how many. `keyed`:
/// pass 1 left keys (the lane pass), else nodes.
template <DistanceFieldType F>
std::size_t list_near(const F& field, float clear, std::size_t count, bool keyed,
                      const ParticleChunk<F::kDim>& chunk,
                      std::array<std::uint32_t, kParticleChunk>& list) noexcept {
  constexpr int D = F::kDim;
  std::size_t near = 0;
  for (std::size_t j = 0; j < count; ++j) {
    bool far;
    if (!keyed) {
      far = chunk.in[j] && field.node_value(chunk.node[j]) > clear;
    } else if constexpr (requires { field.distances; }) {
      // An outside particle's key is 0: a read of node 0, not used.
      far = chunk.in[j] & (field.distances[chunk.index[j]] > clear);
    } else {
      // A branch on the region's kind: most particles sit in empty regions and read no brick
      // (reading one from a safe place always, the kind picked without a branch, measured
      // slower: dungeon 4.4-4.7 -> 6.5 ns a step).
      const std::uint32_t brick = field.table[chunk.index[j]];
      float value = brick == F::kNoBrick ? field.band_distance : -field.band_distance;
      if (brick < F::kNoBrickInside) value = field.bricks[brick * kBrickNodes<D> + chunk.local[j]];
      far = chunk.in[j] & (value > clear);
    }
    list[near] = static_cast<std::uint32_t>(j);
    near += far ? 0 : 1;
  }
  return near;
}

/// Pass 1 for particles [first, first + count) into `chunk`; returns whether it left keys.
template <DistanceFieldType F>
bool move_and_locate_chunk(const F& field, const FieldGridN<F::kDim>& grid, VecN<F::kDim>* position,
                           const VecN<F::kDim>* velocity, float dt, std::size_t first,
                           std::size_t count, ParticleChunk<F::kDim>& chunk) noexcept {
  constexpr int D = F::kDim;
#if defined(__SSE2__) || defined(_M_X64)
  if constexpr (requires { field.distances; }) {
    if (grid.count() <= std::size_t{std::numeric_limits<std::uint32_t>::max()}) {
      const float* distances = field.distances.data();
      move_and_locate_lanes(grid, position, velocity, dt, first, count, chunk,
                            [&](std::size_t j, const __m128i (&node)[D], __m128i in) {
                              const __m128i at = _mm_and_si128(row_major<D>(node, grid.dims), in);
                              _mm_storeu_si128(reinterpret_cast<__m128i*>(&chunk.index[j]), at);
                              for (int l = 0; l < 4; ++l) prefetch(distances + chunk.index[j + l]);
                            });
      return true;
    }
  } else {
    // The brick table is a word per brick region: small and cached; the bricks are read in
    // pass 2 without being asked for first (asking for every listed brick node after this pass
    // measured slower, stop 50, AMD EPYC: dungeon 4.5 -> 5.9 ns a step, torus 8.6 -> 11.8).
    if (field.table.size() <= std::size_t{std::numeric_limits<std::uint32_t>::max()}) {
      move_and_locate_lanes(grid, position, velocity, dt, first, count, chunk,
                            [&](std::size_t j, const __m128i (&node)[D], __m128i in) {
                              __m128i region[D], local[D];
                              for (int k = 0; k < D; ++k) {
                                region[k] = _mm_srai_epi32(node[k], kBrickShift);
                                local[k] = _mm_and_si128(node[k], _mm_set1_epi32(kFieldBrickSize - 1));
                              }
                              const __m128i at = _mm_and_si128(row_major<D>(region, field.bricks_per_axis), in);
                              __m128i place = local[D - 1];
                              for (int k = D - 2; k >= 0; --k)
                                place = _mm_or_si128(_mm_slli_epi32(place, kBrickShift), local[k]);
                              _mm_storeu_si128(reinterpret_cast<__m128i*>(&chunk.index[j]), at);
                              _mm_storeu_si128(reinterpret_cast<__m128i*>(&chunk.local[j]), place);
                            });
      return true;
    }
  }
#endif
  move_and_locate(field, grid, position, velocity, dt, first, count, chunk);
  return false;
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
  // loops would reload it (and divide by the voxel) at every particle.
  const FieldGridN<D> grid = field.grid;
  // Particles sit anywhere, so each node read misses the caches (and the TLB) and would wait
  // alone: a chunk's reads are all asked for in pass 1 and made in pass 2, hundreds in flight.
  ParticleChunk<D> chunk;
  std::array<std::uint32_t, kParticleChunk> near_list;
  std::array<IVec<D>, kParticleChunk> near_cell;
  for (std::size_t first = 0; first < n; first += kParticleChunk) {
    const std::size_t count = std::min(kParticleChunk, n - first);
    // 1: move, find the nearest node, ask for it.
    const bool keyed = move_and_locate_chunk(field, grid, position, velocity, dt, first, count, chunk);
    // 2: read the nodes (arrived by now), list the particles near the solid, find their cells
    // and ask for them.
    const std::size_t near = list_near(field, clear, count, keyed, chunk, near_list);
    stats.near += near;
    for (std::size_t k = 0; k < near; ++k) {
      near_cell[k] = grid.locate(position[first + near_list[k]]).node;
      if constexpr (requires { field.distances; }) {
        const float* d = field.distances.data() + grid.index(near_cell[k]);
        const auto row = static_cast<std::size_t>(grid.dims[0]);
        prefetch(d);
        prefetch(d + row + 1);
        if constexpr (D == 3) {
          const std::size_t slab = row * static_cast<std::size_t>(grid.dims[1]);
          prefetch(d + slab);
          prefetch(d + slab + row + 1);
        }
      }
    }
    // 3: the near ones whose cell has a corner inside are sampled; those inside are pushed back
    // to the surface and their velocity reflected. A cell whose corners are all >= 0 samples
    // >= 0 everywhere (each interpolation step a + (b - a) f, f in [0, 1], of non-negative
    // values rounds to a non-negative value, and outside the box a non-negative distance is
    // added), so its particle is not inside: the sample is skipped, the result the same.
    for (std::size_t k = 0; k < near; ++k) {
      float corner[1 << D];
      field.cell_values(near_cell[k], corner);
      float lowest = corner[0];
      for (int c = 1; c < (1 << D); ++c) lowest = std::min(lowest, corner[c]);
      if (lowest >= 0.0f) continue;
      const std::size_t i = first + near_list[k];
      const VecN<D> p = position[i];
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
  }
  return stats;
}

// ---- many samples ---------------------------------------------------------------------------

#if defined(__SSE2__) || defined(_M_X64)
namespace {

/// sample() of a dense 3D field at `count` points (a multiple of 4), four at a time in SSE2
/// lanes with sample_inside_sse's float operations in its order (so its values), in chunks of
/// kSampleChunk points: pass 1 locates a chunk's points (transposed to x, y, z lanes, each
/// located in its cell, the cells' memory indices in 32 bits, which the caller checked they
/// fit) and asks for the four cache lines of each cell; pass 2 reads each cell's 8 corners as
/// four pairs, by then arriving, transposes them to a corner per register and interpolates
/// along x, y and z for four points at once. (In one pass a group of four points is about 170
/// instructions, so the CPU's window held the reads of one or two groups at a time.) A point
/// outside the grid's box (or with a NaN) is sampled alone afterwards.
void sample_lanes(const DistanceField3& field, const Vec3* points, std::size_t count, float* out) noexcept {
  const FieldGridN<3> grid = field.grid;  // in registers: the stores to `out` could alias it
  const float* distances = field.distances.data();
  const auto nx = static_cast<std::size_t>(grid.dims.x);
  const std::size_t nxy = nx * static_cast<std::size_t>(grid.dims.y);
  const __m128 inv = _mm_set1_ps(1.0f / grid.voxel);
  __m128 origin[3], last[3], top[3];
  for (int k = 0; k < 3; ++k) {
    origin[k] = _mm_set1_ps(grid.origin[k]);
    last[k] = _mm_set1_ps(static_cast<float>(grid.dims[k] - 1));
    top[k] = _mm_set1_ps(static_cast<float>(grid.dims[k] - 2));
  }
  const auto lerp = [](__m128 a, __m128 b, __m128 t) { return _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), t)); };
  constexpr std::size_t kGroups = kSampleChunk / 4;
  alignas(16) std::uint32_t at[kSampleChunk];  // each point's cell, memory index (0 when outside)
  __m128 fraction[kGroups][3];                   // per group of four: the fractions along x, y, z
  int inside[kGroups];                           // per group: the lanes inside the grid's box
  for (std::size_t first = 0; first < count; first += kSampleChunk) {
    const std::size_t groups = std::min(kSampleChunk, count - first) / 4;
    for (std::size_t g = 0; g < groups; ++g) {  // 1: locate, ask for the cells
      const float* p = &points[first + 4 * g].x;
      const __m128 r[3] = {_mm_loadu_ps(p), _mm_loadu_ps(p + 4), _mm_loadu_ps(p + 8)};
      __m128 axis[3];
      to_lanes<3>(r, axis);
      __m128 in = _mm_castsi128_ps(_mm_set1_epi32(-1));
      __m128i node[3];
      for (int k = 0; k < 3; ++k) {
        const __m128 u = _mm_mul_ps(_mm_sub_ps(axis[k], origin[k]), inv);
        in = _mm_and_ps(in, _mm_and_ps(_mm_cmpge_ps(u, _mm_setzero_ps()), _mm_cmple_ps(u, last[k])));
        // (A lane outside the box gets some cell; its index is masked to 0 below.)
        fraction[g][k] = cell_fraction_sse(u, top[k], node[k]);
      }
      inside[g] = _mm_movemask_ps(in);
      // An outside lane reads node 0's cell (the grid has at least 2 nodes an axis) and is
      // sampled again below.
      _mm_store_si128(reinterpret_cast<__m128i*>(at + 4 * g),
                      _mm_and_si128(row_major<3>(node, grid.dims), _mm_castps_si128(in)));
      for (int l = 0; l < 4; ++l) {
        const float* d = distances + at[4 * g + l];
        prefetch(d);
        prefetch(d + nx + 1);
        prefetch(d + nxy);
        prefetch(d + nxy + nx + 1);
      }
    }
    for (std::size_t g = 0; g < groups; ++g) {  // 2: read the corners, interpolate
      __m128 lo[4], hi[4];  // per point: corners 0-3 (z = 0) and 4-7 (z = 1), as cell_values
      for (int l = 0; l < 4; ++l) {
        load_cell_corners_sse(distances + at[4 * g + l], nx, nxy, lo[l], hi[l]);
      }
      _MM_TRANSPOSE4_PS(lo[0], lo[1], lo[2], lo[3]);  // lo[c]: corner c of the four points
      _MM_TRANSPOSE4_PS(hi[0], hi[1], hi[2], hi[3]);
      const __m128* f = fraction[g];
      // interpolate_cell's order: along z, then y, then x.
      const __m128 c00 = lerp(lo[0], hi[0], f[2]), c10 = lerp(lo[1], hi[1], f[2]);
      const __m128 c01 = lerp(lo[2], hi[2], f[2]), c11 = lerp(lo[3], hi[3], f[2]);
      const __m128 x0 = lerp(c00, c01, f[1]), x1 = lerp(c10, c11, f[1]);
      const std::size_t j = first + 4 * g;
      _mm_storeu_ps(out + j, lerp(x0, x1, f[0]));
      if (inside[g] != 0xf) {
        for (int l = 0; l < 4; ++l) {
          if (((inside[g] >> l) & 1) == 0) out[j + l] = field.sample(points[j + l]);
        }
      }
    }
  }
}

}  // namespace
#endif

template <DistanceFieldType F>
void sample(const F& field, std::span<const VecN<F::kDim>> points, std::span<float> out) noexcept {
  const std::size_t n = std::min(points.size(), out.size());
  std::size_t j = 0;
#if defined(__SSE2__) || defined(_M_X64)
  if constexpr (std::is_same_v<F, DistanceField3>) {
    if (field.grid.count() <= std::size_t{std::numeric_limits<std::uint32_t>::max()}) {
      j = n & ~std::size_t{3};
      sample_lanes(field, points.data(), j, out.data());
    }
  }
#endif
  for (; j < n; ++j) out[j] = field.sample(points[j]);
}

#define COLLIDE_FIELD_QUERIES(F)                                                                  \
  template ManifoldN<F::kDim> contact<F>(VecN<F::kDim>, const F&) noexcept;                       \
  template RayHitN<F::kDim> raymarch<F>(const F&, const RayN<F::kDim>&) noexcept;                 \
  template float soft_shadow<F>(const F&, const RayN<F::kDim>&, float) noexcept;                  \
  template ParticleStepStats step_particles<F>(const F&, ParticlesN<F::kDim>&, float, float) noexcept; \
  template void sample<F>(const F&, std::span<const VecN<F::kDim>>, std::span<float>) noexcept;
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
