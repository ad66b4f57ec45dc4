#pragma once
/// @file
/// Signed distance fields and closest-point fields on grids, 2D and 3D (the lesson's "Signed
/// Distance Fields"): a look-up table of how far inside (negative) or outside (positive) the
/// solid each grid node is, so "is this point inside?" costs one memory access and a comparison,
/// and beside it the closest surface point of every node.
///
/// Grid: nodes at `origin + i * voxel` for i in [0, dims) per axis, x fastest in memory. Between
/// nodes the field is multilinear (bilinear in 2D, trilinear in 3D). World units throughout.
///
/// Build (`make_distance_field`, the same three stages for every input, Jones, Baerentzen &
/// Sramek, "3D Distance Fields: A Survey of Techniques and Applications", IEEE TVCG 2006):
///  1. exact band: every primitive (a placed convex shape, a mesh triangle) writes its exact
///     distance and closest point into the nodes within `band` voxels of it (a triangle only
///     visits the nodes of each grid row that lie within the band of its plane). On a grid
///     coarse beside a mesh's triangles, where each band node lies within the band of tens of
///     them, the nodes near the mesh instead each ask its BVH for their nearest point within the
///     band (a 2x2x2 block's nodes in one batch, one descent of the tree): the same distances,
///     chosen by an estimate of the two ways' work;
///  2. sign: 2D and convex shapes by containment (exact); a triangle mesh per region that no
///     surface crosses (the grid cut into 8^D blocks; two neighbouring nodes are joined when
///     their exact distances sum to more than the distance between them, so the surface cannot
///     pass between them), one generalised winding number per region (Jacobson, Kavan &
///     Sorkine-Hornung, "Robust Inside-Outside Segmentation using Generalized Winding Numbers",
///     SIGGRAPH 2013), evaluated fast over the mesh's BVH, far clusters by their second-order
///     expansion (Barill, Dickson, Schmidt, Levin & Jacobson, "Fast Winding Numbers for Soups
///     and Clouds", SIGGRAPH 2018; sdf/winding_tree.hpp), so open meshes
///     (real levels) get a sensible inside. A region whose winding number lies within 0.3 of 1/2
///     (unsure: under an open terrain, by a hole) takes the side of the surest region that
///     reaches it without crossing the surface;
///  3. the rest by closest-point propagation: sweeps over the grid in which each node takes a
///     neighbour's closest point when it is nearer (Danielsson, "Euclidean distance mapping",
///     CGIP 1980): for shapes 2^D sweeps in the orders of fast sweeping (Zhao, Math. Comp.
///     2005); for a mesh's dense field two passes over the planes, each plane as Danielsson's
///     4SED, with the upstream row's diagonal neighbours offered too.

#include <collide/core/aabb.hpp>
#include <collide/core/config.hpp>
#include <collide/core/ray.hpp>
#include <collide/core/transform.hpp>
#include <collide/core/transform3.hpp>
#include <collide/narrow/closest_point.hpp>
#include <collide/narrow/manifold.hpp>
#include <collide/ccd/raycast.hpp>
#include <collide/shape/shape2d.hpp>
#include <collide/shape/shape3d.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#endif

namespace collide {

/// Default width of the exact band around the surface, voxels (FieldOptions::band).
inline constexpr float kFieldDefaultBand = 3.0f;
/// Default margin of nodes around the input's bounds, voxels (FieldOptions::margin).
inline constexpr int kFieldDefaultMargin = 4;
/// Default memory limit of a build, bytes (FieldOptions::max_bytes): 2 GiB.
inline constexpr std::size_t kFieldDefaultMaxBytes = std::size_t{2} << 30;
/// Voxels per side of a brick of the sparse field (8: 512 floats, 2 KiB per 3D brick, OpenVDB's
/// leaf size).
inline constexpr int kFieldBrickSize = 8;
/// Sphere tracing stops when the field is below this fraction of a voxel (a hit).
inline constexpr float kRaymarchHitVoxels = 0.01f;
/// Halvings of the last step when sphere tracing overshoots into the solid (the interpolated
/// field can exceed the true distance by a little): 10 leave under 1/1000 of the step.
inline constexpr int kRaymarchBisections = 10;
/// Sphere tracing gives up after this many steps (reported as no hit).
inline constexpr int kRaymarchMaxSteps = 256;

/// Where a point falls in a field's grid (FieldGridN::locate): the cell whose 2^D corner nodes
/// surround it, the point's position inside that cell, and how far it lies outside the grid's
/// box (a point outside is clamped onto the box first).
template <int D>
struct FieldCellN {
  glm::vec<D, int> node{0};  ///< the cell's first corner node, each axis in [0, dims - 2]
  VecN<D> fraction{0.0f};    ///< position inside the cell per axis, [0, 1]
  VecN<D> outside{0.0f};     ///< offset from the grid's box, world units; zero inside it

  /// `inner` (the value interpolated at the clamped point) plus the distance to the grid's box
  /// (an upper bound of the field beyond it, exact on the box). With `gradient` (may be null):
  /// `inner_gradient` with the clamped axes' slope dropped, plus the direction away from the box.
  [[nodiscard]] float add_outside(float inner, VecN<D> inner_gradient, VecN<D>* gradient) const noexcept {
    const float out2 = glm::dot(outside, outside);
    if (out2 == 0.0f) [[likely]] {
      if (gradient) *gradient = inner_gradient;
      return inner;
    }
    const float out = std::sqrt(out2);
    if (gradient) {
      for (int k = 0; k < D; ++k)
        if (outside[k] != 0.0f) inner_gradient[k] = 0.0f;
      *gradient = inner_gradient + outside / out;
    }
    return inner + out;
  }
};

/// The grid under a field: node i (per axis, 0 <= i < dims) sits at origin + i * voxel.
template <int D>
struct FieldGridN {
  VecN<D> origin{0.0f};            ///< world position of node 0
  float voxel = 1.0f;              ///< spacing of the nodes, world units, > 0
  glm::vec<D, int> dims{0};        ///< nodes per axis, each >= 2

  /// Number of nodes.
  [[nodiscard]] std::size_t count() const noexcept {
    std::size_t n = 1;
    for (int k = 0; k < D; ++k) n *= static_cast<std::size_t>(dims[k]);
    return n;
  }
  /// Memory index of node `i` (x fastest).
  [[nodiscard]] std::size_t index(glm::vec<D, int> i) const noexcept {
    std::size_t at = static_cast<std::size_t>(i[D - 1]);
    for (int k = D - 2; k >= 0; --k) at = at * static_cast<std::size_t>(dims[k]) + static_cast<std::size_t>(i[k]);
    return at;
  }
  /// World position of node `i`.
  [[nodiscard]] VecN<D> node(glm::vec<D, int> i) const noexcept { return origin + VecN<D>(i) * voxel; }
  /// Box from the first node to the last.
  [[nodiscard]] AabbN<D> bounds() const noexcept { return {origin, origin + VecN<D>(dims - 1) * voxel}; }

  /// The cell around `p` (world space), `p` clamped onto the grid's box first. A NaN coordinate
  /// falls on node 0 with no outside offset; an infinite one on the box with none either.
  [[nodiscard]] FieldCellN<D> locate(VecN<D> p) const noexcept {
    FieldCellN<D> at;
    const float inv = 1.0f / voxel;
    bool clamped = false;
    for (int k = 0; k < D; ++k) {
      const float u = (p[k] - origin[k]) * inv;
      // Branch-free clamp onto [0, dims - 1]; std::max(0, NaN) is 0.
      const float c = std::min(std::max(0.0f, u), float(dims[k] - 1));
      clamped |= c != u;
      const int i = std::min(static_cast<int>(c), dims[k] - 2);
      at.node[k] = i;
      at.fraction[k] = c - float(i);
    }
    if (clamped) {  // rare: the offset from the box, zero for a NaN or infinite coordinate
      for (int k = 0; k < D; ++k) {
        const float u = (p[k] - origin[k]) * inv;
        const float out = (u - (float(at.node[k]) + at.fraction[k])) * voxel;
        at.outside[k] = std::fabs(out) <= std::numeric_limits<float>::max() ? out : 0.0f;
      }
    }
    return at;
  }
  /// The node nearest to `p` (world space) into `node`; false when `p` lies more than half a
  /// voxel outside the grid's box (or is NaN), `node` then unspecified.
  [[nodiscard]] bool nearest_node(VecN<D> p, glm::vec<D, int>& node) const noexcept {
    const float inv = 1.0f / voxel;
    bool in = true;
    for (int k = 0; k < D; ++k) {
      const float u = (p[k] - origin[k]) * inv + 0.5f;
      in &= u >= 0.0f && u < float(dims[k]);
      node[k] = in ? static_cast<int>(u) : 0;
    }
    return in;
  }
};

/// Multilinear interpolation (bilinear in 2D, trilinear in 3D) of a cell's 2^D corner values
/// `v` (corner c holds the far node on axis k when bit k of c is set) at `fraction` in the cell,
/// and, when `gradient` is not null, its gradient per world unit for cells `voxel` wide.
template <int D>
[[nodiscard]] inline float interpolate_cell(const float (&v)[1 << D], VecN<D> f, float voxel,
                                            VecN<D>* gradient) noexcept {
  if constexpr (D == 2) {
    const float bottom = v[0] + (v[1] - v[0]) * f.x, top = v[2] + (v[3] - v[2]) * f.x;
    if (gradient) {
      *gradient = Vec2{(v[1] - v[0]) + ((v[3] - v[2]) - (v[1] - v[0])) * f.y, top - bottom} / voxel;
    }
    return bottom + (top - bottom) * f.y;
  } else {
    // Along z first (the cell's two z layers are the halves of the corner array: in SIMD one
    // lerp of two registers, no shuffle), then y, then x; c_xy = the edge along z at (x, y).
    const float dz00 = v[4] - v[0], dz10 = v[5] - v[1], dz01 = v[6] - v[2], dz11 = v[7] - v[3];
    const float c00 = v[0] + dz00 * f.z, c10 = v[1] + dz10 * f.z;
    const float c01 = v[2] + dz01 * f.z, c11 = v[3] + dz11 * f.z;
    const float dy0 = c01 - c00, dy1 = c11 - c10;
    const float x0 = c00 + dy0 * f.y, x1 = c10 + dy1 * f.y;
    if (gradient) {
      const float dz0 = dz00 + (dz01 - dz00) * f.y, dz1 = dz10 + (dz11 - dz10) * f.y;
      *gradient = Vec3{x1 - x0, dy0 + (dy1 - dy0) * f.x, dz0 + (dz1 - dz0) * f.x} / voxel;
    }
    return x0 + (x1 - x0) * f.x;
  }
}

using FieldGrid = FieldGridN<2>;   ///< 2D grid
using FieldGrid3 = FieldGridN<3>;  ///< 3D grid

/// How a field is built.
struct FieldOptions {
  float voxel = 0.0f;                        ///< node spacing, world units; > 0 and finite
  int margin = kFieldDefaultMargin;          ///< nodes beyond the input's bounds on each side, >= 1
  /// Width of the exact band, voxels (>= 1; values below are raised to 1). Dense fields: exact
  /// distances within it, propagated beyond. Sparse fields: nothing is stored beyond it (the
  /// value there is +-band * voxel).
  float band = kFieldDefaultBand;
  bool keep_closest_points = true;           ///< keep the closest-point field beside the distances
  std::size_t max_bytes = kFieldDefaultMaxBytes;  ///< a build that would need more is refused
};

/// What a build did.
struct FieldBuildStats {
  std::size_t nodes = 0;             ///< nodes of the grid (dense) or of its allocated bricks (sparse)
  std::size_t band_nodes = 0;        ///< nodes given an exact distance (stage 1)
  /// Nodes that asked the mesh's BVH for their nearest point (a mesh's band on a grid coarse
  /// beside its triangles; eight nodes a batch); 0 when the triangles were scattered into the band.
  std::size_t nearest_queries = 0;
  std::size_t sign_evaluations = 0;  ///< winding numbers (or containment tests) evaluated
  std::size_t bytes = 0;             ///< memory the field holds after the build
  double seconds = 0.0;              ///< wall time of the build
};

/// A convex shape placed in the world: an input of a field build (a map's statics, a scene's).
template <int D>
struct PlacedShapeN;
/// A 2D shape and its placement.
template <>
struct PlacedShapeN<2> {
  Shape2D shape;
  Transform xf{};
};
/// A 3D shape and its placement.
template <>
struct PlacedShapeN<3> {
  Shape3D shape;
  Transform3 xf{};
};
using PlacedShape = PlacedShapeN<2>;   ///< 2D placed shape
using PlacedShape3 = PlacedShapeN<3>;  ///< 3D placed shape

/// A dense signed distance field with its closest-point field. Build with `make_distance_field`.
/// Queries never allocate or throw; a query point outside the grid gets the value at the
/// nearest point of the grid's box plus its distance to that box (an upper bound).
template <int D>
struct DistanceFieldN {
  static constexpr int kDim = D;  ///< dimension
  FieldGridN<D> grid;
  std::vector<float> distances;          ///< signed distance per node, negative inside
  std::vector<VecN<D>> closest_points;   ///< closest surface point per node; empty when not kept
  FieldBuildStats stats;

  /// The signed distance at `p`, interpolated between the 2^D nodes around it.
  [[nodiscard]] float sample(VecN<D> p) const noexcept;
  /// The gradient of the interpolated field at `p` (not normalised; about unit length near the
  /// surface; points away from the solid). Zero outside the grid's box along a clamped axis.
  [[nodiscard]] VecN<D> gradient(VecN<D> p) const noexcept;
  /// `sample` and `gradient` from one read of the 2^D nodes.
  [[nodiscard]] float sample(VecN<D> p, VecN<D>& gradient_out) const noexcept;
  /// The lesson's one-memory-access test: the nearest node's distance is negative. Exact to
  /// half a voxel diagonal; false outside the grid.
  [[nodiscard]] bool is_inside(VecN<D> p) const noexcept;
  /// The stored distance of the node nearest to `p` (one read; +inf outside the grid).
  [[nodiscard]] float nearest_value(VecN<D> p) const noexcept;
  /// The stored distance of node `i` (each axis in [0, dims)).
  [[nodiscard]] float node_value(glm::vec<D, int> i) const noexcept { return distances[grid.index(i)]; }
  /// The 2^D corner values of the cell whose first node is `i` (each axis in [0, dims - 2]),
  /// ordered as interpolate_cell takes them.
  void cell_values(glm::vec<D, int> i, float (&v)[1 << D]) const noexcept;
  /// Bytes held by the field.
  [[nodiscard]] std::size_t bytes() const noexcept {
    return distances.capacity() * sizeof(float) + closest_points.capacity() * sizeof(VecN<D>);
  }
};

using DistanceField = DistanceFieldN<2>;   ///< 2D dense field
using DistanceField3 = DistanceFieldN<3>;  ///< 3D dense field

/// A sparse narrow-band signed distance field (as OpenVDB keeps a level set): bricks of
/// kFieldBrickSize^D nodes only where the band reaches, found through a coarse table of brick
/// indices; a brick-sized region without a brick holds +-band * voxel (the sign per region).
/// Same queries as the dense field, two memory accesses each (table, then brick); beyond the
/// band the value is clamped to +-band * voxel.
template <int D>
struct SparseDistanceFieldN {
  static constexpr int kDim = D;  ///< dimension
  FieldGridN<D> grid;                   ///< the grid the bricks tile (dims rounded up to whole bricks)
  glm::vec<D, int> bricks_per_axis{0};  ///< size of the brick table
  /// Per brick-sized region: index of its brick in `bricks`, or kNoBrick / kNoBrickInside.
  std::vector<std::uint32_t> table;
  std::vector<float> bricks;            ///< kFieldBrickSize^D distances per brick, x fastest
  float band_distance = 0.0f;           ///< band * voxel: the magnitude of every value beyond the band
  FieldBuildStats stats;

  static constexpr std::uint32_t kNoBrick = 0xffffffffu;        ///< an outside region
  static constexpr std::uint32_t kNoBrickInside = 0xfffffffeu;  ///< an inside region

  /// As DistanceFieldN::sample (values beyond the band clamped to +-band_distance).
  [[nodiscard]] float sample(VecN<D> p) const noexcept;
  /// As DistanceFieldN::sample with the gradient.
  [[nodiscard]] float sample(VecN<D> p, VecN<D>& gradient_out) const noexcept;
  /// As DistanceFieldN::gradient (zero beyond the band).
  [[nodiscard]] VecN<D> gradient(VecN<D> p) const noexcept;
  /// As DistanceFieldN::is_inside: the nearest node's value is negative.
  [[nodiscard]] bool is_inside(VecN<D> p) const noexcept;
  /// The stored value of the node nearest to `p`; +inf outside the grid.
  [[nodiscard]] float nearest_value(VecN<D> p) const noexcept;
  /// The value of node `i` (each axis in [0, dims)): its brick's, or its empty region's
  /// +-band_distance (two reads: the table, then the brick).
  [[nodiscard]] float node_value(glm::vec<D, int> i) const noexcept;
  /// As DistanceFieldN::cell_values: one table read when the cell lies inside one brick.
  void cell_values(glm::vec<D, int> i, float (&v)[1 << D]) const noexcept;
  /// Bytes held by the field.
  [[nodiscard]] std::size_t bytes() const noexcept {
    return table.capacity() * sizeof(std::uint32_t) + bricks.capacity() * sizeof(float);
  }
};

using SparseDistanceField = SparseDistanceFieldN<2>;   ///< 2D sparse field
using SparseDistanceField3 = SparseDistanceFieldN<3>;  ///< 3D sparse field

/// The field types the queries below take.
template <class F>
concept DistanceFieldType = requires(const F& f, VecN<F::kDim> p, VecN<F::kDim>& g, glm::vec<F::kDim, int> i) {
  { f.grid } -> std::convertible_to<FieldGridN<F::kDim>>;
  { f.node_value(i) } -> std::same_as<float>;
  { f.sample(p) } -> std::same_as<float>;
  { f.sample(p, g) } -> std::same_as<float>;
  { f.is_inside(p) } -> std::same_as<bool>;
};

/// Dense field of the union of `shapes` (convex shapes; a map's statics, which overlap and abut
/// freely: the union's surface is what counts, so a seam between two pieces is not a surface).
/// The grid covers the shapes' bounds plus `options.margin` nodes. Throws InvalidInput naming
/// the problem for a voxel that is not positive and finite, no shapes, a margin below 1, and a
/// grid that would need more than `options.max_bytes` (the message gives the bytes it needs).
[[nodiscard]] DistanceField make_distance_field(std::span<const PlacedShape> shapes, const FieldOptions& options);
/// 3D version of the above.
[[nodiscard]] DistanceField3 make_distance_field(std::span<const PlacedShape3> shapes, const FieldOptions& options);
/// Dense field of a triangle mesh (mesh space), signed by the generalised winding number per
/// region (stage 2 above): a closed mesh's inside exactly; an open mesh's where its winding
/// number exceeds 1/2, an unsure region (within 0.3 of 1/2) on the side of the surest region that
/// reaches it without crossing the surface. The same errors as above, and for a mesh without
/// triangles.
[[nodiscard]] DistanceField3 make_distance_field(const TriangleMesh& mesh, const FieldOptions& options);

/// The reference build: the exact distance of every node through the mesh BVH
/// (`TriangleBvh::nearest`) and the winding number of every node (WindingTree, as the fast
/// build's regions). Slow (the benchmark's and the tests' yardstick for `make_distance_field`);
/// the same errors.
[[nodiscard]] DistanceField3 make_distance_field_exact(const TriangleMesh& mesh, const FieldOptions& options);

/// Sparse narrow-band field of the union of `shapes` (see SparseDistanceFieldN). The same
/// errors as the dense build.
[[nodiscard]] SparseDistanceField make_sparse_distance_field(std::span<const PlacedShape> shapes, const FieldOptions& options);
/// 3D version of the above.
[[nodiscard]] SparseDistanceField3 make_sparse_distance_field(std::span<const PlacedShape3> shapes, const FieldOptions& options);
/// Sparse narrow-band field of a triangle mesh, signed as the dense one.
[[nodiscard]] SparseDistanceField3 make_sparse_distance_field(const TriangleMesh& mesh, const FieldOptions& options);

/// The generalised winding number of `p` with respect to the mesh (mesh space): 1 inside a
/// closed outward-wound mesh, 0 outside, in between near an open mesh's holes. Exact solid
/// angles summed over every triangle (Van Oosterom & Strackee, IEEE Trans. Biomed. Eng. 1983).
/// O(triangles): the reference for the fast evaluation the builds use.
[[nodiscard]] float winding_number(const TriangleMesh& mesh, Vec3 p) noexcept;

/// The closest surface point to `p` from the closest-point field: the stored point of the 2^D
/// nodes around `p` that lies nearest to it (exact where the nearest surface feature of `p` is
/// one of theirs; otherwise off by at most about a voxel). `inside` and `distance` from the
/// field's sign. Requires a field built with keep_closest_points (else the answer of
/// closest_point_by_gradient).
[[nodiscard]] PointQuery closest_point(const DistanceField& field, Vec2 p) noexcept;
/// 3D version of the above.
[[nodiscard]] PointQuery3 closest_point(const DistanceField3& field, Vec3 p) noexcept;
/// The closest surface point to `p` by stepping along the field's gradient: p - d * g / |g|,
/// repeated `steps` times (the lesson's alternative to storing closest points).
[[nodiscard]] PointQuery closest_point_by_gradient(const DistanceField& field, Vec2 p, int steps = 2) noexcept;
/// 3D version of the above.
[[nodiscard]] PointQuery3 closest_point_by_gradient(const DistanceField3& field, Vec3 p, int steps = 2) noexcept;

// The templates below are instantiated in the library for the four field types (dense and
// sparse, 2D and 3D).

/// Contact of a point (shape A, no extent) with the field's solid (B): one manifold point at
/// `p` when the field there is <= 0, depth = -distance, normal from A into B (minus the field's
/// normalised gradient). Feature ids: A vertex 0, B face 0.
template <DistanceFieldType F>
[[nodiscard]] ManifoldN<F::kDim> contact(VecN<F::kDim> p, const F& field) noexcept;

/// Contact of a convex shape (A, placed by `xf`) with the field's solid (B), by sampling the
/// shape's surface (Guendelman, Bridson & Fedkiw, "Nonconvex rigid bodies with stacking",
/// SIGGRAPH 2003): a circle or sphere at its centre (one point, depth radius - distance); a
/// capsule along its core at most a voxel apart (distance minus radius); a polygon, box or hull
/// at its vertices and along its edges at most a voxel apart. The deepest samples that touch
/// (depth >= 0) become the manifold, up to kMaxManifoldPoints, spread out (the deepest, then the
/// one farthest from those kept); the normal is the deepest sample's. Points midway between
/// the surfaces, as every manifold. Agrees with the exact narrow phase to within the field's
/// error (about a voxel). A segment is sampled as a capsule of radius 0. A sparse field skips a
/// sample beyond its band (its distance there is unknown): a circle, sphere or capsule wider than
/// the band touches only where its core comes within the band.
template <DistanceFieldType F>
  requires(F::kDim == 2)
[[nodiscard]] Manifold contact(const Shape2D& shape, const Transform& xf, const F& field) noexcept;
/// 3D version of the above.
template <DistanceFieldType F>
  requires(F::kDim == 3)
[[nodiscard]] Manifold3 contact(const Shape3D& shape, const Transform3& xf, const F& field) noexcept;

/// Sphere tracing of `ray` (world space) through the field (Hart, "Sphere tracing", The Visual
/// Computer 1996): step by the sampled distance until it falls below kRaymarchHitVoxels of a
/// voxel (a step that lands inside is bisected back to the zero level). Hit: fraction, point on
/// the zero level, normal = normalised gradient. The march starts where the ray enters the
/// grid's box (beyond it the field's value is an upper bound, no safe step). No hit when the ray
/// misses the box, starts inside the solid, leaves the grid, or takes kRaymarchMaxSteps steps.
template <DistanceFieldType F>
[[nodiscard]] RayHitN<F::kDim> raymarch(const F& field, const RayN<F::kDim>& ray) noexcept;

/// Soft shadow factor of a light seen from `point` along `ray` (Quilez, "Soft shadows in
/// raymarched SDFs", 2010): 0 when the ray is blocked, up to 1 when it passes everything by
/// at least 1/sharpness of the distance travelled. `sharpness` > 0 (8 to 32 are typical).
template <DistanceFieldType F>
[[nodiscard]] float soft_shadow(const F& field, const RayN<F::kDim>& ray, float sharpness) noexcept;

/// A batch of point particles (structure of arrays), world space.
template <int D>
struct ParticlesN {
  std::vector<VecN<D>> positions;
  std::vector<VecN<D>> velocities;  ///< world units per second
};
using Particles = ParticlesN<2>;   ///< 2D particles
using Particles3 = ParticlesN<3>;  ///< 3D particles

/// What one particle step did.
struct ParticleStepStats {
  std::size_t bounced = 0;  ///< particles that met the solid and were pushed out and reflected
  std::size_t near = 0;     ///< particles whose one-read test was not enough (their cell read)
};

/// Moves every particle by velocity * dt and bounces the ones that end inside the field's solid:
/// a particle whose nearest node is farther out than a voxel diagonal is done with one read;
/// otherwise the field is sampled (unless no corner of its cell is inside: then no sample is),
/// and if it is below 0 the particle is pushed back to the surface along the gradient and its
/// velocity reflected about the surface normal, its normal part scaled by `restitution` (0:
/// stick to the surface, 1: elastic). Works through the particles in chunks of a few hundred,
/// every node read of a chunk asked for before the first is made, four particles at a time in
/// SSE2 lanes where the machine has them; the same result as one particle at a time, bit for
/// bit. No allocation.
template <DistanceFieldType F>
ParticleStepStats step_particles(const F& field, ParticlesN<F::kDim>& particles, float dt, float restitution) noexcept;

/// `field.sample` at many points (world space): out[k] = field.sample(points[k]), the same
/// values bit for bit, for k below min(points.size(), out.size()) (the rest of `out` is left
/// as it was). What a batch of queries gains over one at a time: a dense 3D field takes the
/// points four at a time in SSE2 lanes (located together, each cell's 8 corners read as four
/// pairs, interpolated for the four at once), so the reads of several points are in flight
/// together and the arithmetic is shared; a point outside the grid's box is sampled alone.
/// Other fields (2D, sparse, or more than 2^32 nodes), and machines without SSE2, sample one
/// point at a time. No allocation.
template <DistanceFieldType F>
void sample(const F& field, std::span<const VecN<F::kDim>> points, std::span<float> out) noexcept;

#if defined(__SSE2__) || defined(_M_X64)
/// The memory index x + y * nx + z * nxy of the node whose (x, y, z) are lanes 0-2 of `i` (each
/// >= 0, the grid's x-fastest order): on x86-64 the y and z terms as two 32 x 32 -> 64-bit
/// products in one register (pmuludq) when nx and nxy fit 32 bits, no round trip through memory;
/// else in scalars. The same integer either way.
COLLIDE_ALWAYS_INLINE std::size_t dense_node_index_sse(__m128i i, std::size_t nx, std::size_t nxy) noexcept {
#if defined(__x86_64__) || defined(_M_X64)
  if (nxy <= 0xffffffffu) {
    const __m128i yz = _mm_shuffle_epi32(i, _MM_SHUFFLE(3, 2, 3, 1));  // y . z .
    const __m128i scale = _mm_set_epi32(0, static_cast<int>(static_cast<std::uint32_t>(nxy)), 0,
                                        static_cast<int>(static_cast<std::uint32_t>(nx)));
    const __m128i terms = _mm_mul_epu32(yz, scale);  // y * nx, z * nxy (64 bits each)
    const __m128i sum = _mm_add_epi64(terms, _mm_unpackhi_epi64(terms, terms));
    return static_cast<std::size_t>(_mm_cvtsi128_si64(sum)) +
           static_cast<std::size_t>(static_cast<std::uint32_t>(_mm_cvtsi128_si32(i)));
  }
#endif
  alignas(16) int node[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(node), i);
  return static_cast<std::size_t>(node[0]) + static_cast<std::size_t>(node[1]) * nx +
         static_cast<std::size_t>(node[2]) * nxy;
}

/// Locates grid coordinates u (per lane, in node units from the origin, 0 <= u <= dims - 1,
/// which the caller has checked) in their cells: the cell's first node into `cell`, floor(u)
/// with the last node taking the cell below it, and the fraction u - cell returned, as
/// FieldGridN::locate does inside the box. min(floor(u), dims - 2) = floor(min(u, dims - 2)),
/// so the clamp is one float min against `top` = dims - 2 (and u >= 0 makes truncation the
/// floor).
COLLIDE_ALWAYS_INLINE __m128 cell_fraction_sse(__m128 u, __m128 top, __m128i& cell) noexcept {
  cell = _mm_cvttps_epi32(_mm_min_ps(u, top));
  return _mm_sub_ps(u, _mm_cvtepi32_ps(cell));
}

/// The 8 corner values of a dense 3D grid's cell whose first node is at `d` (rows `nx` floats
/// apart, slabs `nxy`), in two registers as DistanceFieldN::cell_values orders them:
/// lo = (v0, v1, v2, v3) at the lower z, hi = (v4, v5, v6, v7) at the upper; each pair of x
/// neighbours is one 8-byte load (4-byte aligned only: _mm_loadl_epi64 reads it unaligned).
COLLIDE_ALWAYS_INLINE void load_cell_corners_sse(const float* d, std::size_t nx, std::size_t nxy, __m128& lo,
                                                 __m128& hi) noexcept {
  const auto pair = [](const float* at) {
    return _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(at)));
  };
  lo = _mm_movelh_ps(pair(d), pair(d + nx));
  hi = _mm_movelh_ps(pair(d + nxy), pair(d + nxy + nx));
}

/// sample_cells' fast path for a 3D dense field (DistanceField3), SSE2: when the point `xyz`
/// (world space: x, y, z, z in lanes 0-3; lane 3 repeats z, so its test is z's again) lies
/// within the grid's box, its trilinear sample into `value` (and its gradient into `gradient`
/// when not null) and true, with the same float operations in the same order as locate and
/// interpolate_cell, so the same values; else false (then the general path, which adds the
/// distance to the box). The three axes are located at once and the cell's 8 corners
/// interpolated 4, then 2, then 1 at a time.
template <class F>
[[nodiscard]] COLLIDE_ALWAYS_INLINE bool sample_inside_sse(const F& field, __m128 xyz, float& value, Vec3* gradient) noexcept {
  const FieldGridN<3>& grid = field.grid;
  const __m128 inv = _mm_set1_ps(1.0f / grid.voxel);
  const __m128 u = _mm_mul_ps(_mm_sub_ps(xyz,
                                         _mm_setr_ps(grid.origin.x, grid.origin.y, grid.origin.z, grid.origin.z)),
                              inv);
  const __m128i dims = _mm_setr_epi32(grid.dims.x, grid.dims.y, grid.dims.z, grid.dims.z);
  const __m128 last = _mm_cvtepi32_ps(_mm_sub_epi32(dims, _mm_set1_epi32(1)));  // dims - 1 per axis
  const __m128 top = _mm_cvtepi32_ps(_mm_sub_epi32(dims, _mm_set1_epi32(2)));   // dims - 2
  // Inside the box: 0 <= u <= dims - 1 on every axis. On the floats' bits as signed integers
  // (dims - 1 > 0): a negative u (and -0, and a NaN with its sign set) has its sign bit set, and
  // u <= dims - 1 is bits(u) <= bits(dims - 1) (false for +inf and every other NaN); so one
  // integer compare and the sign bits. -0 takes the general path, which gives it the same value.
  const __m128i bits = _mm_castps_si128(u);
  const __m128i outside = _mm_or_si128(bits, _mm_cmpgt_epi32(bits, _mm_castps_si128(last)));
  if (_mm_movemask_ps(_mm_castsi128_ps(outside)) != 0) return false;
  __m128i i;
  const __m128 f = cell_fraction_sse(u, top, i);
  const auto nx = static_cast<std::size_t>(grid.dims.x);
  const std::size_t nxy = nx * static_cast<std::size_t>(grid.dims.y);
  // The corners: lo = (v0, v1, v2, v3) (z = 0), hi = (v4, v5, v6, v7) (z = 1), as cell_values.
  const float* d = field.distances.data() + dense_node_index_sse(i, nx, nxy);
  __m128 lo, hi;
  load_cell_corners_sse(d, nx, nxy, lo, hi);
  // Along z: (c00, c10, c01, c11) = lo + (hi - lo) * fz, the corners' z layers as loaded.
  const __m128 dz = _mm_sub_ps(hi, lo);  // dz00 dz10 dz01 dz11
  const __m128 c = _mm_add_ps(lo, _mm_mul_ps(dz, _mm_shuffle_ps(f, f, _MM_SHUFFLE(2, 2, 2, 2))));
  const __m128 fy = _mm_shuffle_ps(f, f, _MM_SHUFFLE(1, 1, 1, 1));
  if (gradient == nullptr) {
    // Along y: (x0, x1) = (c00, c10) + ((c01, c11) - (c00, c10)) * fy; then along x.
    const __m128 y = _mm_add_ps(c, _mm_mul_ps(_mm_sub_ps(_mm_movehl_ps(c, c), c), fy));
    const __m128 x1 = _mm_shuffle_ps(y, y, _MM_SHUFFLE(1, 1, 1, 1));
    value = _mm_cvtss_f32(_mm_add_ss(y, _mm_mul_ss(_mm_sub_ss(x1, y), f)));
    return true;
  }
  // With the gradient (interpolate_cell's terms): the z slopes are lerped along y beside the
  // values, (x0, x1, dz0, dz1); then value, y slope and z slope along x at once.
  const __m128 a = _mm_movelh_ps(c, dz);                              // c00 c10 dz00 dz10
  const __m128 b = _mm_movehl_ps(dz, c);                              // c01 c11 dz01 dz11
  const __m128 dy = _mm_sub_ps(b, a);                                 // dy0 dy1 . .
  const __m128 y = _mm_add_ps(a, _mm_mul_ps(dy, fy));                 // x0 x1 dz0 dz1
  const __m128 t = _mm_unpacklo_ps(y, dy);                            // x0 dy0 x1 dy1
  const __m128 near = _mm_shuffle_ps(t, y, _MM_SHUFFLE(2, 2, 1, 0));  // x0 dy0 dz0 dz0
  const __m128 far = _mm_shuffle_ps(t, y, _MM_SHUFFLE(3, 3, 3, 2));   // x1 dy1 dz1 dz1
  const __m128 z = _mm_add_ps(near, _mm_mul_ps(_mm_sub_ps(far, near), _mm_shuffle_ps(f, f, 0)));
  alignas(16) float out[4];
  _mm_store_ps(out, z);
  value = out[0];
  const float dx = _mm_cvtss_f32(_mm_sub_ss(far, near));  // x1 - x0
  *gradient = Vec3{dx, out[1], out[2]} / grid.voxel;
  return true;
}
#endif

/// sample_cells' general path: locate, the cell's corners, interpolate_cell, the distance to
/// the grid's box added beyond it.
template <class F>
[[nodiscard]] COLLIDE_ALWAYS_INLINE float sample_cells_located(const F& field, VecN<F::kDim> p,
                                                             VecN<F::kDim>* gradient) noexcept {
  constexpr int D = F::kDim;
  const FieldCellN<D> at = field.grid.locate(p);
  float v[1 << D];
  field.cell_values(at.node, v);
  VecN<D> g{0.0f};
  const float inner = interpolate_cell<D>(v, at.fraction, field.grid.voxel, gradient ? &g : nullptr);
  return at.add_outside(inner, g, gradient);
}

/// sample_cells' path for a point outside the grid's box (or NaN) when the fast path handles the
/// rest: rare in a caller's loop, so out of line, its code and registers apart from the loop's.
/// The point comes as lanes 0-2 of `xyz`, which stays in a register; a Vec3 argument made GCC 12
/// keep a copy of every point in memory for the call that seldom happens.
template <class F>
[[nodiscard]] COLLIDE_COLD float sample_cells_outside(const F& field, __m128 xyz, Vec3* gradient) noexcept {
  alignas(16) float p[4];
  _mm_store_ps(p, xyz);
  return sample_cells_located(field, Vec3(p[0], p[1], p[2]), gradient);
}

/// The multilinear sample of `field` at `p` (world space; any field with a `grid` and
/// `cell_values`, as DistanceFieldN): the cell's corners interpolated, plus the distance to the
/// grid's box beyond it; the gradient per world unit into `gradient` when not null. What the
/// fields' `sample` members call.
template <class F>
[[nodiscard]] COLLIDE_ALWAYS_INLINE float sample_cells(const F& field, VecN<F::kDim> p, VecN<F::kDim>* gradient) noexcept {
#if defined(__SSE2__) || defined(_M_X64)
  if constexpr (F::kDim == 3 && requires { field.distances; }) {
    float value;
    const __m128 xyz = _mm_movelh_ps(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&p.x))),
                                     _mm_set1_ps(p.z));
    if (sample_inside_sse(field, xyz, value, gradient)) return value;
    return sample_cells_outside(field, xyz, gradient);
  }
#endif
  return sample_cells_located(field, p, gradient);
}

// ---- the dense field's queries, inline: a caller's loop keeps the grid in registers ----------

template <int D>
COLLIDE_ALWAYS_INLINE void DistanceFieldN<D>::cell_values(glm::vec<D, int> i, float (&v)[1 << D]) const noexcept {
  const float* d = distances.data() + grid.index(i);
  const auto nx = static_cast<std::size_t>(grid.dims[0]);
  v[0] = d[0];
  v[1] = d[1];
  v[2] = d[nx];
  v[3] = d[nx + 1];
  if constexpr (D == 3) {
    const std::size_t nxy = nx * static_cast<std::size_t>(grid.dims[1]);
    v[4] = d[nxy];
    v[5] = d[nxy + 1];
    v[6] = d[nxy + nx];
    v[7] = d[nxy + nx + 1];
  }
}
template <int D>
COLLIDE_ALWAYS_INLINE float DistanceFieldN<D>::sample(VecN<D> p) const noexcept { return sample_cells(*this, p, nullptr); }
template <int D>
inline float DistanceFieldN<D>::sample(VecN<D> p, VecN<D>& gradient_out) const noexcept {
  return sample_cells(*this, p, &gradient_out);
}
template <int D>
inline VecN<D> DistanceFieldN<D>::gradient(VecN<D> p) const noexcept {
  VecN<D> g;
  (void)sample(p, g);
  return g;
}
template <int D>
inline bool DistanceFieldN<D>::is_inside(VecN<D> p) const noexcept {
  glm::vec<D, int> i;
  return grid.nearest_node(p, i) && distances[grid.index(i)] < 0.0f;
}
template <int D>
inline float DistanceFieldN<D>::nearest_value(VecN<D> p) const noexcept {
  glm::vec<D, int> i;
  return grid.nearest_node(p, i) ? distances[grid.index(i)] : std::numeric_limits<float>::infinity();
}

}  // namespace collide
