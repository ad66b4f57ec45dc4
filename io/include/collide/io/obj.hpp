#pragma once
/// @file
/// Wavefront OBJ level meshes (through tinyobjloader): as triangle soups for the walk mesh, and
/// as collision meshes (TriangleMesh) through the same reader.

#include <collide/shape/triangle_mesh.hpp>
#include <collide/walkmesh/walk_mesh.hpp>

#include <string>

namespace collide::io {

/// Loads every face of an OBJ file as triangles, positions in the file's units and axes (only
/// `v` and `f` statements are used; the others are ignored). Polygons are split into a fan of
/// triangles wound as the polygon (a quad takes whichever diagonal keeps it unfolded). The soup's
/// `name` is the file name, so errors from `build_walk_mesh` / `make_walk_mesh` name the file.
/// Throws InvalidInput naming the file, and the line and vertex or face where there is one, e.g.
/// "level.obj:12: vertex 9: coordinate x 'nan' is not finite", for: a file that is missing or
/// unreadable; a vertex with fewer than three coordinates or one that is not a finite float; a
/// face with fewer than three vertices, a vertex reference that is not a non-zero integer or is
/// out of range (as written in the file: OBJ counts from 1, negative counts back); a polygon that
/// no fan of triangles covers (not convex); no face at all.
[[nodiscard]] TriangleSoup load_obj(const std::string& path);

/// The OBJ file's faces as a collision mesh: `load_obj`, then `make_triangle_mesh` on its
/// positions and triangles (vertex i and triangle t are the file's i-th vertex and the t-th
/// triangle of its faces' fans, before degenerate ones are dropped). Throws InvalidInput for
/// what either rejects, the message starting with the file name.
[[nodiscard]] TriangleMesh load_triangle_mesh(const std::string& path, const TriangleMeshOptions& options = {});

}  // namespace collide::io
