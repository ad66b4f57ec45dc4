#pragma once
/// @file
/// Wavefront OBJ level meshes: as triangle soups for the walk mesh, and as collision meshes
/// (TriangleMesh) through the same reader; and convex hulls written out as OBJ objects (a
/// decomposition's pieces, for an engine or a modelling tool to load).

#include <collide/shape/convex_hull.hpp>
#include <collide/shape/triangle_mesh.hpp>
#include <collide/walkmesh/walk_mesh.hpp>

#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace collide::io {

/// Most vertices (`v` statements) an OBJ file may have: 2^24, 200 MB of positions and several
/// times that in a walk mesh or TriangleMesh built from them. Far beyond a game level.
inline constexpr std::size_t kMaxObjVertices = std::size_t{1} << 24;

/// Most triangles an OBJ file's faces may make (a face of n vertices makes n - 2): 2^25.
inline constexpr std::size_t kMaxObjTriangles = std::size_t{1} << 25;

/// Most vertices one face may have: 1024. Triangulating a face is O(n^2) in its vertices
/// (`triangulate_planar_polygon`), so a file of faces each 10^5 vertices long would take hours;
/// exporters write n-gons of tens of vertices (a round floor of a few hundred at most).
inline constexpr std::size_t kMaxObjFaceVertices = 1024;

/// The limits `load_obj` enforces; a caller may tighten them (larger values count as the
/// default). docs/limits.md lists them.
struct ObjLimits {
  std::size_t max_vertices = kMaxObjVertices;            ///< `v` statements
  std::size_t max_triangles = kMaxObjTriangles;          ///< triangles of all faces together
  std::size_t max_face_vertices = kMaxObjFaceVertices;   ///< vertices of one `f` statement
};

/// Loads every face of an OBJ file as triangles, positions in the file's units and axes (only
/// `v` and `f` statements are used; the others are skipped unread). A triangle is kept as it is
/// (a degenerate one too: `build_walk_mesh` drops and counts it); a face of more vertices is
/// triangulated in its plane by ear clipping (`triangulate_planar_polygon`: concave n-gons too,
/// every vertex of the face a corner of its triangles, each wound as the face). The soup's
/// `name` is the file name, so errors from `build_walk_mesh` / `make_walk_mesh` name the file.
/// Throws InvalidInput naming the file, and the line and vertex or face where there is one, e.g.
/// "level.obj:12: vertex 9: coordinate x 'nan' is not finite", for: a file that is missing, a
/// folder or unreadable; a vertex with fewer than three coordinates or one that is not a finite
/// float; a face with fewer than three vertices, a vertex reference that is not a non-zero
/// integer or is out of range (as written in the file: OBJ counts from 1, negative counts back);
/// a face of 4 or more vertices that is not a simple polygon (no area, self-intersecting) or not
/// planar within kPlanarityTolerance of its size (the message says which vertex and by how
/// much); more vertices, triangles or vertices in one face than `limits` allow (the message names
/// the limit and its value); no face at all.
[[nodiscard]] TriangleSoup load_obj(const std::string& path, const ObjLimits& limits = {});

/// The OBJ file's faces as a collision mesh: `load_obj`, then `make_triangle_mesh` on its
/// positions and triangles (vertex i and triangle t are the file's i-th vertex and the t-th
/// triangle of its faces' triangulations, before degenerate ones are dropped). Throws
/// InvalidInput for what either rejects, the message starting with the file name.
[[nodiscard]] TriangleMesh load_triangle_mesh(const std::string& path, const TriangleMeshOptions& options = {},
                                              const ObjLimits& limits = {});

/// Writes `hulls` to the OBJ file at `path` (created or replaced): one object `o hull_N` per
/// hull, N counting from 1 in the order given, with its vertices (`v x y z`, the hull's own
/// coordinates, each float written with 9 significant digits so it reads back bit for bit) and
/// its polygonal faces (`f`, counter-clockwise seen from outside as ConvexHull stores them,
/// which is OBJ's front face; 1-based indices counting over the whole file). A rounded hull's
/// core is written (OBJ has no radius). `load_obj` reads the file back (its faces triangulated).
/// Throws InvalidInput "PATH: cannot be written (WHY)" when the file cannot be opened or a write
/// fails (no folder, no permission, disk full); a partly written file is left as it is.
void write_hulls_obj(const std::string& path, std::span<const ConvexHull> hulls);

/// Reads a set of convex hulls from the OBJ file at `path`, as write_hulls_obj, V-HACD and
/// CoACD write them (each hull a closed surface with vertices of its own): `load_obj`, then one
/// hull per connected component of the faces (faces sharing a vertex index belong together;
/// `o` and `g` statements are not needed), each the convex hull (make_convex_hull) of its
/// component's vertices, in file order of their first face. Throws InvalidInput naming the file
/// for what load_obj rejects, and "NAME: hull N: ..." for a component whose points have no
/// volume (flat, or a single edge).
[[nodiscard]] std::vector<ConvexHull> load_hulls_obj(const std::string& path, const ObjLimits& limits = {});

}  // namespace collide::io
