#pragma once
/// @file
/// Approximate convex decomposition of 3D triangle meshes (the lesson, "Convexity": "it is
/// worth looking into (especially) approximate convex decomposition"): a concave prop becomes a
/// few convex hulls whose union stays within a concavity bound of the mesh, where an exact
/// decomposition would explode into thousands of pieces.
///
/// Method: volumetric hierarchical splitting by planes, as V-HACD (Mamou & Ghorbel, "A simple
/// and efficient approach for 3D mesh approximate convex decomposition", ICIP 2009; V-HACD 2016),
/// with CoACD's measure of quality in place of V-HACD's volume difference (Wei et al.,
/// "Approximate convex decomposition for 3D meshes with collision-aware concavity and tree
/// search", SIGGRAPH 2022): what a collision query pays for is how far a hull reaches outside
/// the mesh, a distance, not the volume it adds. Why this combination:
///  - the mesh is classified once into a signed distance field (sdf/, winding-number sign), so
///    open and self-touching meshes, which real assets are, decompose as the solid they bound;
///    CoACD's mesh cutting needs a closed manifold and remeshes the input first;
///  - a hull's concavity is read off that same field: the largest distance to the mesh of a grid
///    node inside the hull and outside the mesh (the one-sided Hausdorff distance from the hull
///    to the solid, to within a voxel), with no per-candidate mesh work;
///  - the worst piece is split first (best first), so a hull budget goes where the error is
///    and the result at any budget is the best this greedy search found for it.
/// Each split tries planes across the three axes and across the piece's principal axis of
/// largest spread (a limb at an angle), coarse then refined around the best, and keeps the one
/// whose two hulls reach least far outside the mesh (max of the two concavities; ties to the
/// smaller hull volume). Greedy alone halves a block with two limbs into two limbed halves; so
/// each direction's best plane is also judged two splits ahead (its worse side split once more,
/// CoACD's tree search at depth 2), and one that clearly wins there is taken instead: rob.obj
/// at 5 hulls goes from 13% of its diagonal to 2.2%. A piece's hull is made of its surface
/// nodes' closest surface points, the mesh vertices nearest its nodes and its cut faces (surface
/// points where a cut meets the surface), so hulls hug the mesh to within the field's exact
/// distances. Candidates are
/// evaluated in parallel on a TaskScheduler, each into its own slot, and chosen in a fixed
/// order: the result is the same for every worker count.
///
/// Runs at load time, not per frame: it allocates and takes 0.2-0.8 s at the default 1e5 nodes
/// (bench_decompose_mesh; README).

#include <collide/core/aabb.hpp>
#include <collide/core/function_ref.hpp>
#include <collide/core/task_scheduler.hpp>
#include <collide/shape/convex_hull.hpp>
#include <collide/shape/triangle_mesh.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace collide {

/// Default number of grid nodes the mesh's bounding box is divided into (V-HACD's default
/// resolution is 1e5 voxels too): voxel = cbrt(box volume / this).
inline constexpr int kDecompositionDefaultResolution = 100000;
/// Fewest and most grid nodes `ApproximateDecompositionOptions::resolution` may ask for (the most:
/// about 100 MB of field, closest points and owners, and tens of seconds).
inline constexpr int kDecompositionMinResolution = 1000;
inline constexpr int kDecompositionMaxResolution = 4000000;
/// Most surface samples the measurement may be asked for per surface (12 bytes each, 120 MB).
inline constexpr int kDecompositionMaxSamples = 10000000;
/// Most hulls a decomposition may be asked for.
inline constexpr int kDecompositionMaxHulls = 1024;
/// Plane positions tried per axis in the coarse pass of a split (then the best one's
/// neighbourhood is refined voxel by voxel).
inline constexpr int kDecompositionCoarsePlanes = 16;
/// A grid node counts as part of the solid when its signed distance is below this many voxels:
/// outside the surface too, up to half a cell's diagonal, so that every point of the surface has
/// a solid node at a corner of its cell and a feature thinner than a voxel (a plate, a rail, an
/// open mesh's single sheet) still has nodes, and its closest points a hull. (The hulls are made
/// of surface points, not of the nodes, so this does not fatten them.)
inline constexpr float kDecompositionSolidVoxels = 0.8660254f;

/// How `decompose_approximate` runs.
struct ApproximateDecompositionOptions {
  /// Most hulls, in [1, kDecompositionMaxHulls].
  int max_hulls = 16;
  /// Pieces are split until every hull reaches at most this far outside the mesh, as a fraction
  /// of the mesh's bounding-box diagonal (CoACD's threshold is expressed the same way), or until
  /// `max_hulls`. >= 0 and finite; 0 spends the whole hull budget.
  float concavity = 0.01f;
  /// Most vertices per hull, in [4, kMaxHullVertices]: the hull keeps the farthest points first
  /// (make_convex_hull's cap), so a capped hull may leave a little of its piece outside (the
  /// report's `mesh_to_hull` measures it).
  int max_vertices = 64;
  /// Grid nodes over the mesh's bounding box, in [kDecompositionMinResolution,
  /// kDecompositionMaxResolution]: voxel = cbrt(box volume / resolution), except that an axis
  /// thinner than that voxel (a plate, a sheet) counts as one node and the voxel is chosen over
  /// the other axes, so a thin mesh's grid stays within a few times `resolution` (with the
  /// margin nodes) instead of growing with its flatness. More nodes: finer splits and a finer
  /// concavity, slower.
  int resolution = kDecompositionDefaultResolution;
  /// Seeds the surface samples of the report's measurement (the split itself has no randomness).
  std::uint64_t seed = 1;
  /// Surface samples of the report's measurement per unit of budget: this many on the mesh and
  /// this many over all hulls (in [0, kDecompositionMaxSamples]; 0 skips the measurement,
  /// leaving the report's distances unset).
  int measure_samples = 20000;
  /// Runs the candidate planes of each split in parallel; null: the calling thread. The result
  /// does not depend on it.
  TaskScheduler* scheduler = nullptr;
};

/// Called after each split with the hulls made so far and the worst concavity left (mesh
/// units). Must not throw.
using DecompositionProgress = FunctionRef<void(int hulls, float worst_concavity)>;

/// How far a set of hulls is from the mesh it approximates, measured by sampling both surfaces
/// (`measure_decomposition`). Distances in mesh units.
struct DecompositionError {
  /// One-sided Hausdorff distance from the hulls to the solid: the largest distance of a point on
  /// a hull's surface to the mesh's solid (0 for points inside the mesh). How far a collision
  /// against the hulls may fire before the mesh is touched.
  float hull_to_mesh = 0.0f;
  /// One-sided Hausdorff distance from the mesh's surface to the union of the hulls: the largest
  /// distance of a point on the mesh to the nearest hull (0 inside one). What the hulls miss.
  float mesh_to_hull = 0.0f;
  /// Sum of the hulls' volumes over the mesh's volume (overlaps count twice; the mesh's volume by
  /// the divergence theorem: exact for a geometrically closed surface however it is triangulated,
  /// holes' caps left out; 0 when the mesh bounds no volume).
  float volume_ratio = 0.0f;
  int hull_samples = 0;  ///< points sampled on the hulls
  int mesh_samples = 0;  ///< points sampled on the mesh
};

/// What `decompose_approximate` made and what it took.
struct ApproximateDecomposition {
  /// The hulls, mesh space (the input's coordinates, `TriangleMesh::origin` added back), each
  /// with at most `max_vertices` vertices, in the order the pieces were made.
  std::vector<ConvexHull> hulls;
  float diagonal = 0.0f;          ///< the mesh's bounding-box diagonal, mesh units
  float voxel = 0.0f;             ///< grid spacing used, mesh units
  int grid_nodes = 0;             ///< nodes of the grid
  int solid_nodes = 0;            ///< nodes classified as solid
  /// The worst concavity of the pieces as the split saw it (field distance of a node inside a
  /// hull and outside the mesh; about a voxel resolution), mesh units.
  float grid_concavity = 0.0f;
  int splits = 0;                 ///< planes cut
  int candidates = 0;             ///< candidate planes evaluated (two hulls each)
  std::optional<DecompositionError> error;  ///< measured when measure_samples > 0
  double seconds = 0.0;           ///< wall time of the whole call, measurement included
  double field_seconds = 0.0;     ///< of which building the distance field
  double measure_seconds = 0.0;   ///< of which measuring the result
};

/// Splits `mesh` (mesh space; closed or nearly closed: holes, self-touching parts and
/// inconsistent winding are handled through the winding-number sign of the field) into at most
/// `options.max_hulls` convex hulls (see the file comment for the method). Deterministic: the
/// same mesh and options give the same hulls, bit for bit, for every scheduler. `progress`
/// (optional) is called after each split.
///
/// Throws InvalidInput naming the problem for: a mesh without triangles; a mesh whose bounding
/// box is flat on an axis or whose solid has no grid node ("no volume"); options out of range
/// (names the field).
[[nodiscard]] ApproximateDecomposition decompose_approximate(
    const TriangleMesh& mesh, const ApproximateDecompositionOptions& options = {},
    std::optional<DecompositionProgress> progress = std::nullopt);

/// Measures how well `hulls` (mesh space) approximate `mesh` (see DecompositionError):
/// `samples` points spread by area over the mesh's triangles and as many over the hulls' faces
/// (seeded by `seed`, deterministic), plus every hull and mesh vertex; the inside of the mesh by
/// its generalised winding number (WindingTree, sdf/winding_tree.hpp), distances by the
/// mesh BVH and `closest_point`. Independent of how the hulls were made (the benchmark measures
/// peers' hulls with it). Throws InvalidInput for a mesh without triangles, no hulls or
/// samples outside [1, kDecompositionMaxSamples].
[[nodiscard]] DecompositionError measure_decomposition(const TriangleMesh& mesh,
                                                       std::span<const ConvexHull> hulls, int samples,
                                                       std::uint64_t seed);

}  // namespace collide
