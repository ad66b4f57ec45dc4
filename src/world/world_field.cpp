// Signed distance fields as static pieces of the world, 2D and 3D, dense and sparse
// (world_field.hpp).

#include "world_field.hpp"

#include <collide/narrow/closest_point.hpp>
#include <collide/sdf/contour.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <variant>

namespace collide::detail {

namespace {

/// Calls `fn(field)` with the dense or the sparse field behind the pointer.
template <int D, class Fn>
decltype(auto) with_field(const StaticFieldN<D>& field, Fn&& fn) {
  return std::visit([&](const auto& p) -> decltype(auto) { return fn(*p); }, field);
}

/// Calls `visit(node, value)` for every node of a dense field (x fastest).
template <int D, class Visit>
void for_each_node(const DistanceFieldN<D>& f, Visit&& visit) {
  glm::vec<D, int> i(0);
  for (const float value : f.distances) {
    visit(i, value);
    for (int k = 0; k < D; ++k) {
      if (++i[k] < f.grid.dims[k]) break;
      i[k] = 0;
    }
  }
}

/// Calls `visit(node, value)` for every node of a sparse field's bricks and inside regions (an
/// outside region holds no node at or below 0, so it is skipped).
template <int D, class Visit>
void for_each_node(const SparseDistanceFieldN<D>& f, Visit&& visit) {
  constexpr int n = kFieldBrickSize;
  std::size_t brick_nodes = 1;
  for (int k = 0; k < D; ++k) brick_nodes *= n;
  glm::vec<D, int> r(0);
  for (const std::uint32_t brick : f.table) {
    if (brick != SparseDistanceFieldN<D>::kNoBrick) {
      glm::vec<D, int> l(0);
      for (std::size_t at = 0; at < brick_nodes; ++at) {
        const glm::vec<D, int> node = r * n + l;
        bool in_grid = true;
        for (int k = 0; k < D; ++k) in_grid = in_grid && node[k] < f.grid.dims[k];
        if (in_grid) {
          visit(node, brick == SparseDistanceFieldN<D>::kNoBrickInside ? -f.band_distance
                                                                        : f.bricks[brick * brick_nodes + at]);
        }
        for (int k = 0; k < D; ++k) {
          if (++l[k] < n) break;
          l[k] = 0;
        }
      }
    }
    for (int k = 0; k < D; ++k) {
      if (++r[k] < f.bricks_per_axis[k]) break;
      r[k] = 0;
    }
  }
}

/// A lower bound of the distance from `p` (field frame) to the field's solid, negative inside.
/// In the grid: the sample over kFieldLipschitz. Beyond it the field's sample is the edge's
/// value plus the distance to the grid's box (an upper bound, which sphere tracing and
/// advancement must not step by): with q the box's point nearest p, every point x of the box
/// has |p - x| >= |p - q| and |p - x| >= |q - x| >= value(q) / kFieldLipschitz.
template <int D, class F>
float distance_bound(const F& f, VecN<D> p) noexcept {
  const AabbN<D> box = f.grid.bounds();
  const float out = distance(p, glm::clamp(p, box.min, box.max));
  const float s = f.sample(p);
  if (!(out > 0.0f)) return s / kFieldLipschitz<D>;
  return std::max(out, (s - out) / kFieldLipschitz<D>);
}

/// distance_bound at world point `p` for the field placed by `xf`.
template <int D>
float field_bound(const StaticFieldN<D>& field, const TransformN<D>& xf, VecN<D> p) noexcept {
  const VecN<D> local = inv_transform_point(xf, p);
  return with_field<D>(field, [&](const auto& f) { return distance_bound<D>(f, local); });
}

/// The transform of the piece in the field's frame.
template <int D>
TransformN<D> in_field(const TransformN<D>& xb, const TransformN<D>& xa) noexcept {
  return inv_mul(xb, xa);
}

/// `m` (field frame) in world space.
template <int D>
ManifoldN<D> to_world(ManifoldN<D> m, const TransformN<D>& xb) noexcept {
  m.normal = rotate(xb.q, m.normal);
  for (int i = 0; i < m.count; ++i) m.points[i].point = transform_point(xb, m.points[i].point);
  return m;
}

}  // namespace

template <int D>
bool is_null_field(const StaticFieldN<D>& field) noexcept {
  return std::visit([](const auto& p) { return p == nullptr; }, field);
}

template <int D>
float field_voxel(const StaticFieldN<D>& field) noexcept {
  return with_field<D>(field, [](const auto& f) { return f.grid.voxel; });
}

template <int D>
bool field_solid_box(const StaticFieldN<D>& field, AabbN<D>& box_out) {
  return with_field<D>(field, [&](const auto& f) {
    glm::vec<D, int> lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
    float deepest = 0.0f;
    bool any = false;
    for_each_node(f, [&](glm::vec<D, int> node, float value) {
      if (!(value <= 0.0f)) return;
      any = true;
      lo = glm::min(lo, node);
      hi = glm::max(hi, node);
      deepest = std::min(deepest, value);
    });
    if (!any) return false;
    // The cells around the solid nodes, within the grid.
    const FieldGridN<D>& g = f.grid;
    AabbN<D> box{g.node(glm::max(lo - 1, glm::vec<D, int>(0))), g.node(glm::min(hi + 1, g.dims - 1))};
    bool at_edge = false;
    for (int k = 0; k < D; ++k) at_edge = at_edge || lo[k] == 0 || hi[k] == g.dims[k] - 1;
    if (at_edge) {
      box.min -= VecN<D>(-deepest);
      box.max += VecN<D>(-deepest);
    }
    box_out = box;
    return true;
  });
}

template <int D>
AabbN<D> placed_box(const AabbN<D>& box, const TransformN<D>& xf) noexcept {
  AabbN<D> out{transform_point(xf, box.min), transform_point(xf, box.min)};
  for (int corner = 1; corner < (1 << D); ++corner) {
    VecN<D> c;
    for (int k = 0; k < D; ++k) c[k] = (corner >> k) & 1 ? box.max[k] : box.min[k];
    const VecN<D> p = transform_point(xf, c);
    out.min = glm::min(out.min, p);
    out.max = glm::max(out.max, p);
  }
  return out;
}

template <int D>
float field_sample(const StaticFieldN<D>& field, const TransformN<D>& xf, VecN<D> p) noexcept {
  const VecN<D> local = inv_transform_point(xf, p);
  return with_field<D>(field, [&](const auto& f) { return f.sample(local); });
}

template <int D>
ManifoldN<D> field_contact(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticFieldN<D>& field,
                           const TransformN<D>& xb) noexcept {
  const TransformN<D> local = in_field<D>(xb, xa);
  return to_world<D>(with_field<D>(field, [&](const auto& f) { return contact(a, local, f); }), xb);
}

template <int D>
bool field_overlap(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticFieldN<D>& field,
                   const TransformN<D>& xb) noexcept {
  if (field_contact<D>(a, xa, field, xb).touching()) return true;
  // No sample of A's surface touches: A overlaps only if a part of the solid lies wholly inside
  // it, and then so does one of that part's nodes (a part smaller than a cell is missed).
  const TransformN<D> local = in_field<D>(xb, xa);
  const AabbN<D> box = compute_aabb(a, local);
  return with_field<D>(field, [&](const auto& f) {
    const FieldGridN<D>& g = f.grid;
    glm::vec<D, int> lo, hi;
    for (int k = 0; k < D; ++k) {
      const float from = std::ceil((box.min[k] - g.origin[k]) / g.voxel);
      const float to = std::floor((box.max[k] - g.origin[k]) / g.voxel);
      if (!(from <= to) || to < 0.0f || from > static_cast<float>(g.dims[k] - 1)) return false;
      lo[k] = static_cast<int>(std::max(from, 0.0f));
      hi[k] = static_cast<int>(std::min(to, static_cast<float>(g.dims[k] - 1)));
    }
    glm::vec<D, int> i = lo;
    for (;;) {
      const VecN<D> p = g.node(i);
      if (f.sample(p) <= 0.0f && closest_point(a, local, p).distance <= 0.0f) return true;
      int k = 0;
      for (; k < D; ++k) {
        if (i[k] < hi[k]) {
          ++i[k];
          break;
        }
        i[k] = lo[k];
      }
      if (k == D) return false;
    }
  });
}

template <int D>
float field_depth(const BodyShapeN<D>& a, const TransformN<D>& xa, const StaticFieldN<D>& field,
                  const TransformN<D>& xb) noexcept {
  const VecN<D> center = transform_point(xa, piece_info(a).center);
  return std::max({field_contact<D>(a, xa, field, xb).max_depth(), -field_sample<D>(field, xb, center), 0.0f});
}

template <int D>
ToiResultN<D> field_impact(const BodyShapeN<D>& a, const SweepN<D>& sweep, const StaticFieldN<D>& field,
                           const TransformN<D>& xb, std::int64_t& queries) noexcept {
  const PieceInfoN<D> info = piece_info(a);
  const float voxel = field_voxel<D>(field);
  // Any point of the piece moves at most `bound` per unit fraction: its centre of rotation's
  // translation plus the turn times the point's reach from that centre.
  const float reach = distance(info.center, sweep.local_center) + info.radius;
  float turn;
  if constexpr (D == 2) {
    turn = std::fabs(sweep.a1 - sweep.a0);
  } else {
    turn = length(sweep.rotation);
  }
  const float bound = distance(sweep.c0, sweep.c1) + turn * reach;
  const float creep = kFieldToiCreepVoxels * voxel;
  ToiResultN<D> r;
  float clear = 0.0f;  // the last stop known clear of the solid
  float t = 0.0f;
  for (int step = 0; step < kFieldToiMaxSteps; ++step) {
    r.iterations = step + 1;
    const TransformN<D> pose = pose_at(sweep, t);
    const float gap = field_bound<D>(field, xb, transform_point(pose, info.center)) - info.radius;
    float advance = gap;
    if (!(gap > creep)) {  // the bounding circle or sphere may touch: ask the samples
      ++queries;
      ManifoldN<D> m = field_contact<D>(a, pose, field, xb);
      if (m.touching()) {
        r.status = t == 0.0f ? QueryStatus::overlapped : QueryStatus::hit;
        // Between the last clear stop and this touching one, halve towards the first touch.
        for (int i = 0; i < kFieldToiBisections && t > 0.0f; ++i) {
          const float mid = 0.5f * (clear + t);
          ++queries;
          const ManifoldN<D> at_mid = field_contact<D>(a, pose_at(sweep, mid), field, xb);
          if (at_mid.touching()) {
            t = mid;
            m = at_mid;
          } else {
            clear = mid;
          }
        }
        r.fraction = clear;
        r.normal = m.normal;
        r.point = m.points[0].point;
        return r;
      }
      advance = creep;
    }
    clear = t;
    if (t == 1.0f || !(bound > 0.0f)) {
      r.status = QueryStatus::separated;
      r.fraction = 1.0f;
      return r;
    }
    t = std::min(t + advance / bound, 1.0f);
  }
  r.status = QueryStatus::max_iterations;
  r.fraction = clear;
  return r;
}

template <int D>
ShapeCastResultN<D> field_shape_cast(const BodyShapeN<D>& a, const TransformN<D>& xa, VecN<D> v,
                                     const StaticFieldN<D>& field, const TransformN<D>& xb) noexcept {
  std::int64_t queries = 0;
  const ToiResultN<D> t = field_impact<D>(a, sweep_of(xa, VecN<D>(0.0f), v, AngularN<D>(0.0f)), field, xb, queries);
  ShapeCastResultN<D> r;
  r.status = t.status;
  r.iterations = t.iterations;
  r.fraction = t.fraction;
  r.hit = t.status == QueryStatus::hit || t.status == QueryStatus::overlapped;
  if (r.hit) {
    r.normal = t.normal;
    r.point = t.point;
  }
  return r;
}

template <int D>
RayHitN<D> field_raycast(const StaticFieldN<D>& field, const TransformN<D>& xb, const RayN<D>& ray) noexcept {
  const RayN<D> local{inv_transform_point(xb, ray.origin), inv_rotate(xb.q, ray.translation)};
  RayHitN<D> h = with_field<D>(field, [&](const auto& f) {
    return raymarch(f, local);  // from where the ray enters the grid's box
  });
  if (h.hit) {
    h.point = transform_point(xb, h.point);
    h.normal = rotate(xb.q, h.normal);
  }
  return h;
}

template <int D>
float field_distance(const StaticFieldN<D>& field, const TransformN<D>& xb, VecN<D> p, float cap) noexcept {
  return std::min(field_bound<D>(field, xb, p), cap);
}

template <int D>
float field_laser_offset(const StaticFieldN<D>& field) noexcept {
  return kFieldLaserOffsetVoxels * field_voxel<D>(field);
}

template <int D>
void draw_field(DebugDrawN<D>& draw, const StaticFieldN<D>& field, const TransformN<D>& xf, DrawRole role) {
  if constexpr (D == 2) {
    // The zero contour by marching squares over the field's nodes.
    with_field<2>(field, [&](const auto& f) {
      const FieldGrid& g = f.grid;
      march_squares(
          g.dims.x, g.dims.y, g.origin, g.voxel, 0.0f, [&](int x, int y) { return f.node_value({x, y}); },
          [&](Vec2 a, Vec2 b) { draw.draw_segment(transform_point(xf, a), transform_point(xf, b), role); });
    });
  } else {
    AabbN<D> box;
    if (!field_solid_box<D>(field, box)) return;
    // The twelve edges: from each corner, along each axis where it is at the minimum.
    for (int corner = 0; corner < 8; ++corner) {
      Vec3 from;
      for (int k = 0; k < 3; ++k) from[k] = (corner >> k) & 1 ? box.max[k] : box.min[k];
      for (int k = 0; k < 3; ++k) {
        if ((corner >> k) & 1) continue;
        Vec3 to = from;
        to[k] = box.max[k];
        draw.draw_segment(transform_point(xf, from), transform_point(xf, to), role);
      }
    }
  }
}

#define COLLIDE_WORLD_FIELD(D)                                                                             \
  template bool is_null_field<D>(const StaticFieldN<D>&) noexcept;                                         \
  template float field_voxel<D>(const StaticFieldN<D>&) noexcept;                                          \
  template bool field_solid_box<D>(const StaticFieldN<D>&, AabbN<D>&);                                     \
  template AabbN<D> placed_box<D>(const AabbN<D>&, const TransformN<D>&) noexcept;                         \
  template float field_sample<D>(const StaticFieldN<D>&, const TransformN<D>&, VecN<D>) noexcept;          \
  template ManifoldN<D> field_contact<D>(const BodyShapeN<D>&, const TransformN<D>&, const StaticFieldN<D>&, \
                                         const TransformN<D>&) noexcept;                                   \
  template bool field_overlap<D>(const BodyShapeN<D>&, const TransformN<D>&, const StaticFieldN<D>&,     \
                                 const TransformN<D>&) noexcept;                                           \
  template float field_depth<D>(const BodyShapeN<D>&, const TransformN<D>&, const StaticFieldN<D>&,        \
                                const TransformN<D>&) noexcept;                                            \
  template ToiResultN<D> field_impact<D>(const BodyShapeN<D>&, const SweepN<D>&, const StaticFieldN<D>&,   \
                                         const TransformN<D>&, std::int64_t&) noexcept;                    \
  template ShapeCastResultN<D> field_shape_cast<D>(const BodyShapeN<D>&, const TransformN<D>&, VecN<D>,    \
                                                   const StaticFieldN<D>&, const TransformN<D>&) noexcept; \
  template RayHitN<D> field_raycast<D>(const StaticFieldN<D>&, const TransformN<D>&, const RayN<D>&) noexcept; \
  template float field_distance<D>(const StaticFieldN<D>&, const TransformN<D>&, VecN<D>, float) noexcept; \
  template float field_laser_offset<D>(const StaticFieldN<D>&) noexcept;                                   \
  template void draw_field<D>(DebugDrawN<D>&, const StaticFieldN<D>&, const TransformN<D>&, DrawRole);
COLLIDE_WORLD_FIELD(2)
COLLIDE_WORLD_FIELD(3)
#undef COLLIDE_WORLD_FIELD

}  // namespace collide::detail
